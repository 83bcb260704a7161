//! Mutation smoke test of every reader: 2,000 deterministic random mutations of small samples
//! each, in the normal test suite (the cargo-fuzz targets in wasm-core/fuzz go much further). A
//! panic anywhere fails the test; errors are the expected outcome.

use super::*;
use crate::geometry::Vec3;
use crate::params::Params;

/// xorshift64*: deterministic, no dependency.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
}

/// Tokens that tend to reach edge cases of number and structure parsing.
const TOKENS: &[&[u8]] = &[
    b"nan",
    b"-inf",
    b"1e308",
    b"-1",
    b"0",
    b"4294967295",
    b"18446744073709551616",
    b"\n",
    b"\r\n",
    b",",
    b";",
    b"\t",
    b" ",
    b"#",
    b"\"",
    b"\xEF\xBB\xBF",
    b"\x00",
    b"\xff",
    b"3 0 1 2",
    b"end_header\n",
    b"POINTS 99999999 float\n",
    b"LINES 5 5\n",
    b"]",
    b"[",
    b"{",
    b"</DataArray>",
    b"SAX_LV_ENDOCARDIAL",
    b"APEX_POINT",
    b"f 1 2 -9\n",
    b"v 1 2 3\n",
    b"solid",
    b"facet",
];

fn mutate(seed: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut d = seed.to_vec();
    for _ in 0..1 + rng.below(4) {
        let at = rng.below(d.len() + 1);
        match rng.below(8) {
            0 if !d.is_empty() => {
                let i = rng.below(d.len());
                d[i] ^= 1 << rng.below(8);
            }
            1 if !d.is_empty() => {
                let i = rng.below(d.len());
                d[i] = rng.next() as u8;
            }
            2 => {
                let t = TOKENS[rng.below(TOKENS.len())];
                d.splice(at..at, t.iter().copied());
            }
            3 => {
                let end = (at + 1 + rng.below(64)).min(d.len());
                if at < end {
                    d.drain(at..end);
                }
            }
            4 => d.truncate(at),
            5 => {
                let end = (at + 1 + rng.below(256)).min(d.len());
                let chunk: Vec<u8> = d[at.min(end)..end].to_vec();
                let to = rng.below(d.len() + 1);
                d.splice(to..to, chunk);
            }
            6 => {
                let n = rng.below(8);
                let bytes: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
                d.splice(at..at, bytes);
            }
            _ => {
                // Overwrite a 4-byte little-endian field with an extreme value (binary headers).
                if d.len() >= 4 {
                    let i = rng.below(d.len() - 3);
                    let v = [0u32, 1, 0x7fff_ffff, u32::MAX, 3, 14, 15][rng.below(7)];
                    d[i..i + 4].copy_from_slice(&v.to_le_bytes());
                }
            }
        }
    }
    d
}

/// First `n` lines of a sample: small seeds keep 2,000 runs fast in debug builds.
fn head(rel: &str, n: usize) -> Vec<u8> {
    let b = sample(rel);
    let end = b
        .iter()
        .enumerate()
        .filter(|(_, &c)| c == b'\n')
        .nth(n)
        .map(|(i, _)| i + 1)
        .unwrap_or(b.len());
    b[..end].to_vec()
}

fn small_mesh() -> TriMesh {
    crate::mesh::shapes::octahedron(10.0, Vec3::zeros())
}

fn lines_vtk() -> Vec<u8> {
    b"# vtk DataFile Version 3.0\nc\nASCII\nDATASET POLYDATA\nPOINTS 6 float\n\
      0 0 0 10 0 0 10 10 0 0 0 5 10 0 5 10 10 5\nLINES 2 8\n3 0 1 2\n3 3 4 5\n"
        .to_vec()
}

/// 2,000 mutations per reader; HEARTMESH_SMOKE_ITERS and HEARTMESH_SMOKE_SEED allow longer
/// local explorations with other streams (the default run is always the same 2,000).
fn run(name: &str, seeds: &[Vec<u8>], reader: impl Fn(&[u8])) {
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<u64>().ok());
    let iters = env("HEARTMESH_SMOKE_ITERS").unwrap_or(2000);
    let salt = env("HEARTMESH_SMOKE_SEED").unwrap_or(0);
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ (name.len() as u64) ^ salt.wrapping_mul(0x1234_5677));
    for seed in seeds {
        reader(seed); // the seed itself must be fine too
    }
    for _ in 0..iters {
        let seed = &seeds[rng.below(seeds.len())];
        let m = mutate(seed, &mut rng);
        reader(&m);
    }
}

#[test]
fn contour_readers_survive_mutations() {
    let csv = vec![
        head("contours/surfco-example.csv", 40),
        head("contours/bivme-example-patient1/patient1-ED.csv", 40),
    ];
    run("csv", &csv, |b| {
        let _ = csv::read_csv(b);
    });
    let gp = vec![
        head("contours/bivme-example-patient1/GPFile_000.txt", 40),
        head("contours/bivme-test-patient2/GPFile_012.txt", 40),
    ];
    run("gpfile", &gp, |b| {
        let _ = gpfile::read_gpfile(&String::from_utf8_lossy(b), None);
        let _ = gpfile::read_gpfile(&String::from_utf8_lossy(b), Some(&0.into()));
    });
    let info = vec![head("contours/bivme-example-patient1/SliceInfoFile.txt", 4)];
    run("sliceinfo", &info, |b| {
        let _ = gpfile::read_slice_info(&String::from_utf8_lossy(b));
    });
    let xyz = vec![b"# x\n0 0 0\n1 0 0\n1 1 0\n\n0 0 5\n1 0 5\n".to_vec()];
    run("xyz", &xyz, |b| {
        let _ = xyz::read_xyz(b);
    });
    // Polylines with contour_id / surface cell data (as heartmesh writes them) and without.
    let labelled =
        csv::read_csv(&head("contours/bivme-example-patient1/patient1-ED.csv", 30)).unwrap();
    let vtk = vec![lines_vtk(), write_contour_lines(&labelled, false, "smoke")];
    run("vtk-lines", &vtk, |b| {
        let _ = vtk::read_vtk_contours(b);
    });
    let vtp_lines = vec![write_contour_lines(&labelled, true, "smoke")];
    run("vtp-lines", &vtp_lines, |b| {
        let _ = vtp::read_vtp_contours(b);
    });
    let set = csv::read_csv(&head("contours/surfco-example.csv", 30)).unwrap();
    let session = vec![session::write_session(&set, &Params::default(), "0").unwrap()];
    run("session", &session, |b| {
        if let Ok(s) = session::read_session(b) {
            let _ = s.params();
        }
    });
    // The MAT sample is compressed: mutations mostly exercise the inflater's error paths, so
    // also mutate its uncompressed content (re-wrapped as an uncompressed file).
    let mat = sample("contours/surfco-example.mat");
    let inflated = miniz_oxide::inflate::decompress_to_vec_zlib(&mat[136..]).unwrap();
    let mut plain = mat[..128].to_vec();
    plain.extend_from_slice(&inflated[..inflated.len().min(4096)]);
    run("mat", &[mat[..4096].to_vec(), plain], |b| {
        let _ = mat::read_mat(b);
    });
    // DICOM RTSTRUCT: a few biv-me contours and a landmark, with and without the preamble.
    let mut few =
        csv::read_csv(&head("contours/bivme-example-patient1/patient1-ED.csv", 40)).unwrap();
    few.landmarks
        .push(("APEX_POINT".into(), Vec3::new(1.0, 2.0, 3.0)));
    let dcm = rtstruct::write_rtstruct(&few, "smoke").unwrap();
    let rt = vec![dcm.clone(), dcm[128..].to_vec()];
    run("rtstruct", &rt, |b| {
        let _ = rtstruct::read_rtstruct(b);
    });
    // NIfTI label maps: a small segmented stack, plain (mutations reach every header field) and
    // gzip-compressed (the inflater's error paths and the size bound).
    let labels: Vec<u16> = (0..6 * 5 * 3).map(|n| [0, 1, 2, 3][n % 7 % 4]).collect();
    let volume = nifti::LabelVolume::new(
        [6, 5, 3],
        Vec3::new(1.0, 2.0, 3.0),
        [
            Vec3::new(1.25, 0.0, 0.0),
            Vec3::new(0.0, 1.25, 0.0),
            Vec3::new(0.0, 0.0, 10.0),
        ],
        labels,
    );
    let nii = vec![
        nifti::write_nifti(&volume, false),
        nifti::write_nifti(&volume, true),
    ];
    run("nifti", &nii, |b| {
        let _ = nifti::read_nifti(b, None);
    });
    // Slicer markups: one curve as Slicer saves it, alone and read with a copy of itself.
    let markups_seed = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/slicer-markups-patient1/s06_SAX_RV_SEPTUM.mrk.json"
    ))
    .unwrap();
    run("markups", std::slice::from_ref(&markups_seed), |b| {
        let _ = markups::read_markups("m.mrk.json", b, &[]);
        let _ = markups::read_markups("a.mrk.json", b, &[("b.mrk.json", b)]);
    });
    // A Slicer scene: its scene file, the curve and a label map read together, any one mutated
    // (`read_study` picks what to read by their contents).
    let scene_file = b"<?xml version=\"1.0\"?>\n<MRML version=\"Slicer4.4.0\">\n</MRML>\n".to_vec();
    let scene = [scene_file, markups_seed.clone(), nii[0].clone()];
    run("scene", &scene, |b| {
        for k in 0..scene.len() {
            let mut files: Vec<(&str, &[u8])> = vec![
                ("s.mrml", &scene[0]),
                ("m.mrk.json", &scene[1]),
                ("l.nii", &scene[2]),
            ];
            files[k].1 = b;
            let _ = super::read_study(&files, &super::ContourOptions::default());
        }
    });
    // And the detecting entry point over all of them.
    let mut all: Vec<Vec<u8>> = csv.into_iter().chain(gp).chain(xyz).chain(vtk).collect();
    all.extend(session);
    all.extend(rt);
    all.extend(nii);
    all.push(markups_seed);
    run("detect", &all, |b| {
        let _ = read_contours("x.txt", b);
    });
}

#[test]
fn mesh_readers_survive_mutations() {
    let m = small_mesh();
    let d: Vec<f64> = (0..6).map(|i| i as f64).collect();
    let seeds: Vec<(MeshFormat, Vec<u8>)> = [
        MeshFormat::Obj,
        MeshFormat::StlBinary,
        MeshFormat::StlAscii,
        MeshFormat::Ply,
        MeshFormat::Vtk,
        MeshFormat::Vtp,
    ]
    .iter()
    .map(|&f| {
        (
            f,
            write_mesh(&m, f, Some(("distance", &d)), "smoke").unwrap(),
        )
    })
    .collect();
    for (f, seed) in &seeds {
        let name = format!("m.{}", f.extension());
        run(&name, std::slice::from_ref(seed), |b| {
            if let Ok(md) = read_mesh(&name, b) {
                // Whatever a reader accepts must be a consistent mesh.
                let n = md.mesh.positions.len();
                assert!(md
                    .mesh
                    .triangles
                    .iter()
                    .flatten()
                    .all(|&i| (i as usize) < n));
                if let Some((_, v)) = &md.point_data {
                    assert_eq!(v.len(), n);
                }
            }
        });
    }
    let ascii_ply =
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
        property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
        0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
            .to_vec();
    run("ascii-ply", &[ascii_ply], |b| {
        let _ = ply::read_ply(b);
    });
}
