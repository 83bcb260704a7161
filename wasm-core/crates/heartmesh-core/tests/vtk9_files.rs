//! VTK XML PolyData as the real VTK (9.7) writes it, in each of its modes (tests/data/vtk9, see
//! its README): every mode reads to what the ascii file gives, and damaged copies of the default
//! mode (appended raw, zlib) are errors, never panics.

use heartmesh_core::io::{read_contours, read_mesh};

const MODES: [&str; 9] = [
    "default",
    "default-u64",
    "big-endian",
    "appended-raw",
    "appended-base64",
    "appended-base64-zlib",
    "binary",
    "binary-zlib",
    "binary-zlib-u64",
];

fn fixture(name: &str) -> Vec<u8> {
    let path = format!("{}/tests/data/vtk9/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn contours_in_every_vtk_mode_read_as_the_ascii_file() {
    let ascii = read_contours("c.vtp", &fixture("contours-ascii.vtp")).unwrap();
    let named: Vec<(&str, Option<&str>, usize)> = ascii
        .contours
        .iter()
        .map(|c| {
            (
                c.id.as_str(),
                c.surface.as_deref(),
                c.pieces[0].points.len(),
            )
        })
        .collect();
    assert_eq!(
        named,
        [("endo 1", Some("LV_ENDO"), 4), ("epi µ", Some("LV_EPI"), 3)]
    );
    let p = &ascii.contours[1].pieces[0].points;
    assert_eq!((p[1].x, p[1].y, p[1].z), (12345.678901234, 0.5, 17.25));
    assert_eq!(ascii.contours[0].pieces[0].points[1].x, 10.0 / 3.0);
    for mode in MODES {
        let name = format!("contours-{mode}.vtp");
        let set = read_contours(&name, &fixture(&name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(set.contours.len(), ascii.contours.len(), "{name}");
        for (c, a) in set.contours.iter().zip(&ascii.contours) {
            // Everything but `first_line`, the line of the cells in each file.
            assert_eq!(
                (&c.id, &c.surface, &c.pieces),
                (&a.id, &a.surface, &a.pieces),
                "{name}"
            );
        }
        assert_eq!(
            (&set.landmarks, &set.warnings),
            (&ascii.landmarks, &ascii.warnings),
            "{name}"
        );
    }
}

#[test]
fn meshes_in_every_vtk_mode_read_as_the_ascii_file() {
    let ascii = read_mesh("t.vtp", &fixture("tetra-ascii.vtp")).unwrap();
    assert_eq!(
        ascii.mesh.triangles,
        [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]
    );
    let p = ascii.mesh.positions[3];
    assert_eq!(
        (p.x, p.y, p.z),
        (0.3f32 as f64, 0.4f32 as f64, -3.7f32 as f64)
    );
    let (name, values) = ascii.point_data.clone().unwrap();
    assert_eq!(
        (name.as_str(), values),
        ("distance", vec![0.0, -1.25, 1.0 / 3.0, 1e-9])
    );
    for mode in MODES {
        let name = format!("tetra-{mode}.vtp");
        let mesh = read_mesh(&name, &fixture(&name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(mesh, ascii, "{name}");
    }
}

#[test]
fn lz4_is_refused_by_name() {
    for name in ["contours-lz4.vtp", "tetra-lz4.vtp"] {
        let e = read_contours(name, &fixture(name)).unwrap_err().to_string();
        assert!(
            e.contains("vtkLZ4DataCompressor") && e.contains("uncompressed") && e.contains("zlib"),
            "{name}: {e}"
        );
        assert!(!e.contains('\n'), "{e}");
    }
}

/// Where the appended data starts (the byte after the `_` marker) in a default-mode file.
fn data_start(bytes: &[u8]) -> usize {
    let tag = bytes
        .windows(13)
        .position(|w| w == b"<AppendedData")
        .unwrap();
    tag + bytes[tag..].iter().position(|&b| b == b'_').unwrap() + 1
}

fn put_u32(bytes: &mut [u8], at: usize, v: u32) {
    bytes[at..at + 4].copy_from_slice(&v.to_le_bytes());
}

#[test]
fn damaged_appended_data_gives_errors() {
    for stem in ["contours", "tetra"] {
        let good = fixture(&format!("{stem}-default.vtp"));
        let start = data_start(&good);
        let read = |b: &[u8]| match stem {
            "contours" => read_contours("x.vtp", b).map(|_| ()),
            _ => read_mesh("x.vtp", b).map(|_| ()),
        };
        read(&good).unwrap();
        // The first array's header: blocks, block size, last block size, compressed sizes.
        let mut blocks = good.clone();
        put_u32(&mut blocks, start, u32::MAX);
        let mut size = good.clone();
        put_u32(&mut size, start + 12, 0x7fff_ffff);
        let mut inflated = good.clone();
        put_u32(&mut inflated, start + 4, 0x7fff_ffff);
        put_u32(&mut inflated, start + 8, 0x7fff_0000);
        // The points' offset, with digits put before it.
        let points = good.windows(8).position(|w| w == b"<Points>").unwrap();
        let at = points
            + good[points..]
                .windows(8)
                .position(|w| w == b"offset=\"")
                .unwrap();
        let offset = [&good[..at + 8], b"999999", &good[at + 8..]].concat();
        // Truncated with its closing tags put back (a repaired download), and plainly cut.
        let mut short = good[..start + 120].to_vec();
        short.extend_from_slice(b"\n  </AppendedData>\n</VTKFile>\n");
        let cut = good[..good.len() - 40].to_vec();
        for (what, bad) in [
            ("2^32-1 blocks", blocks),
            ("compressed size past the end", size),
            ("block size past the limit", inflated),
            ("offset past the end", offset),
            ("truncated data", short),
            ("cut file", cut),
        ] {
            let e = read(&bad).unwrap_err();
            assert!(e.line().is_some_and(|l| l > 0), "{stem} {what}: {e}");
        }
        // Every prefix, and every byte of the data flipped: errors or data, no panic.
        for n in 0..good.len() {
            let _ = read(&good[..n]);
        }
        for k in start..good.len() {
            let mut b = good.clone();
            b[k] ^= 0xff;
            let _ = read(&b);
        }
    }
}

/// Corners as a sorted list of coordinate triples: the same surface whatever the numbering.
fn corner_set(mesh: &heartmesh_core::mesh::TriMesh) -> Vec<[[u64; 3]; 3]> {
    let mut out: Vec<[[u64; 3]; 3]> = (0..mesh.triangles.len())
        .map(|t| {
            let c = mesh
                .corners(t)
                .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]);
            // Rotate so the smallest corner leads, keeping the winding.
            let k = (0..3).min_by_key(|&k| c[k]).unwrap();
            [c[k], c[(k + 1) % 3], c[(k + 2) % 3]]
        })
        .collect();
    out.sort_unstable();
    out
}

#[test]
fn a_file_in_several_pieces_reads_whole() {
    // vtkXMLPolyDataWriter with SetNumberOfPieces: each <Piece> numbers its own points from 0,
    // and a surface cut into pieces repeats the corners along the cut.
    let one = read_mesh("t.vtp", &fixture("tetra-ascii.vtp")).unwrap();
    let two = read_mesh("t.vtp", &fixture("tetra-two-pieces-default.vtp")).unwrap();
    assert_eq!(two.mesh.positions.len(), 4, "shared corners merged");
    assert_eq!(corner_set(&two.mesh), corner_set(&one.mesh));
    assert!((two.mesh.volume_ml() - one.mesh.volume_ml()).abs() < 1e-12);
    let value = |m: &heartmesh_core::io::MeshData, p: heartmesh_core::geometry::Vec3| {
        let i = m.mesh.positions.iter().position(|q| *q == p).unwrap();
        m.point_data.as_ref().unwrap().1[i]
    };
    for &p in &one.mesh.positions {
        assert_eq!(value(&two, p), value(&one, p), "distance at {p:?}");
    }

    let ascii = read_contours("c.vtp", &fixture("contours-ascii.vtp")).unwrap();
    let pieces = read_contours("c.vtp", &fixture("contours-two-pieces-default.vtp")).unwrap();
    let names = |s: &heartmesh_core::contours::ContourSet| -> Vec<(String, Option<String>, usize)> {
        s.contours
            .iter()
            .map(|c| (c.id.clone(), c.surface.clone(), c.pieces[0].points.len()))
            .collect()
    };
    assert_eq!(names(&pieces), names(&ascii));

    // A real file: biv-me patient 1 ED (40 contours, 1791 points) written by VTK in 3 pieces
    // (vtkExtractPolyDataPiece stores the points as Float32).
    let whole = read_contours("p.vtp", &fixture("patient1-ED-vtk-default.vtp")).unwrap();
    let three = read_contours("p.vtp", &fixture("patient1-ED-three-pieces.vtp")).unwrap();
    assert_eq!(names(&three), names(&whole));
    assert_eq!(whole.contours.len(), 40);
    let mut worst = 0.0f64;
    for (a, b) in three.contours.iter().zip(&whole.contours) {
        for (pa, pb) in a.pieces.iter().zip(&b.pieces) {
            assert_eq!(pa.points.len(), pb.points.len(), "{}", a.id);
            for (p, q) in pa.points.iter().zip(&pb.points) {
                worst = worst.max((p - q).norm());
            }
        }
    }
    assert!(worst < 1e-4, "points moved {worst} mm");
}

/// VTK's legacy writer puts CELL_DATA (here region scalars and a string field, as a myocardium
/// wall has them) before POINT_DATA: the point data after them is read, in ASCII and binary.
#[test]
fn legacy_files_with_cell_data_first_keep_their_point_data() {
    for name in [
        "tetra-cell-data-legacy-ascii.vtk",
        "tetra-cell-data-legacy-binary.vtk",
    ] {
        let m = read_mesh(name, &fixture(name)).unwrap();
        assert_eq!(m.mesh.triangles.len(), 4, "{name}");
        // The region labels and their names, as VTK wrote them (`region` 1 1 2 3 and the
        // string array `region_name`).
        let r = m
            .regions
            .as_ref()
            .unwrap_or_else(|| panic!("{name}: no regions"));
        assert_eq!(
            (r.array.as_str(), r.labels.as_slice()),
            ("region", &[1, 1, 2, 3][..])
        );
        let names: Vec<&str> = r.names.values().map(String::as_str).collect();
        assert_eq!(names, ["epicardium", "endocardium", "base"], "{name}");
        let (array, values) = m
            .point_data
            .unwrap_or_else(|| panic!("{name}: no point data"));
        assert_eq!(array, "distance", "{name}");
        assert_eq!(values.len(), 4, "{name}");
        let want = [0.0, -1.25, 1.0 / 3.0, 1e-9];
        for (v, w) in values.iter().zip(want) {
            // The ASCII file prints 11 significant digits.
            assert!((v - w).abs() <= 1e-11, "{name}: {values:?}");
        }
    }
}
