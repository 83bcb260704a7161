//! Region labels (named triangle groups) through every mesh writer: what each file holds, in
//! triangle order, that our readers still read the mesh, that files without regions are the
//! bytes they always were, and that bad regions are errors, not panics.
//!
//! The same files were opened in the real tools when the feature was written (VTK 9.7
//! vtkPolyDataReader / vtkXMLPolyDataReader: `region` = 1 1 2 3 as the active cell scalars and
//! `region_name` as a string array; trimesh: OBJ groups and the PLY face property; meshio: OBJ
//! `obj:group_ids`).

use heartmesh_core::error::CoreError;
use heartmesh_core::io::{read_mesh, write_mesh, write_mesh_with, MeshFormat, Regions};
use heartmesh_core::mesh::shapes::unit_tetrahedron;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::VERSION;

const IDS: [u32; 4] = [0, 0, 1, 2];
const NAMES: [&str; 3] = ["a", "b", "c"];
const DIST: [f64; 4] = [0.5, 1.5, 2.5, 3.5];

fn regions() -> Regions<'static> {
    Regions {
        array: "region",
        ids: &IDS,
        names: &NAMES,
    }
}

fn write(format: MeshFormat, point_data: bool) -> Vec<u8> {
    let pd = point_data.then_some(("distance", &DIST[..]));
    write_mesh_with(&unit_tetrahedron(), format, pd, Some(&regions()), "regions").unwrap()
}

fn text(format: MeshFormat, point_data: bool) -> String {
    String::from_utf8(write(format, point_data)).unwrap()
}

/// Our reader gives back the mesh as written: 4 vertices, the same 4 triangles in order, the
/// point data when there was some, and the regions: labels 1 1 2 3 named a, b, c (OBJ keeps
/// them as groups, numbered in order of appearance, which is the same here).
fn assert_reads_back(name: &str, bytes: &[u8], point_data: bool) {
    let back = read_mesh(name, bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
    let r = back
        .regions
        .as_ref()
        .unwrap_or_else(|| panic!("{name}: no regions read back"));
    let array = if name.ends_with(".obj") {
        "group"
    } else {
        "region"
    };
    assert_eq!(r.array, array, "{name}");
    assert_eq!(r.labels, [1, 1, 2, 3], "{name}");
    let names: Vec<(i32, &str)> = r.names.iter().map(|(l, n)| (*l, n.as_str())).collect();
    assert_eq!(names, [(1, "a"), (2, "b"), (3, "c")], "{name}");
    let m = unit_tetrahedron();
    assert_eq!(back.mesh.positions.len(), 4, "{name}");
    assert_eq!(back.mesh.triangles, m.triangles, "{name}");
    if point_data {
        let (n, v) = back
            .point_data
            .unwrap_or_else(|| panic!("{name}: no point data"));
        assert_eq!((n.as_str(), v), ("distance", DIST.to_vec()), "{name}");
    }
}

#[test]
fn obj_has_a_group_line_before_each_run() {
    let s = text(MeshFormat::Obj, false);
    let body = &s[s.find("f ").unwrap() - "g a\n".len()..];
    assert_eq!(body, "g a\nf 1 3 2\nf 1 2 4\ng b\nf 1 4 3\ng c\nf 2 3 4\n");
    assert_eq!(s.matches("\nv ").count(), 4);
    assert_reads_back("m.obj", s.as_bytes(), false);
    // A region that comes back after another starts a new group of the same name.
    let m = unit_tetrahedron();
    let r = Regions {
        array: "region",
        ids: &[0, 1, 0, 0],
        names: &NAMES,
    };
    let s = String::from_utf8(write_mesh_with(&m, MeshFormat::Obj, None, Some(&r), "").unwrap())
        .unwrap();
    let groups: Vec<&str> = s.lines().filter(|l| l.starts_with("g ")).collect();
    assert_eq!(groups, ["g a", "g b", "g a"]);
    assert_eq!(s.lines().filter(|l| l.starts_with("f ")).count(), 4);
}

/// The face records of a binary PLY written by us: count byte, three i32 indices, the i32 region.
fn ply_faces(bytes: &[u8], header_end: usize, vertex_size: usize) -> Vec<([i32; 3], i32)> {
    let int = |at: usize| i32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    let start = header_end + 4 * vertex_size;
    (0..4)
        .map(|k| {
            let at = start + 17 * k;
            assert_eq!(bytes[at], 3, "face {k} corner count");
            ([int(at + 1), int(at + 5), int(at + 9)], int(at + 13))
        })
        .collect()
}

#[test]
fn ply_has_an_int_face_property_and_the_names_in_comments() {
    for point_data in [false, true] {
        let bytes = write(MeshFormat::Ply, point_data);
        let end = bytes
            .windows(11)
            .position(|w| w == b"end_header\n")
            .unwrap()
            + 11;
        let header = std::str::from_utf8(&bytes[..end]).unwrap();
        assert!(
            header.contains(
                "comment regions\ncomment region 1 a\ncomment region 2 b\ncomment region 3 c\n\
                 element vertex 4\n"
            ),
            "{header}"
        );
        assert!(header.ends_with(
            "element face 4\nproperty list uchar int vertex_indices\nproperty int region\n\
             end_header\n"
        ));
        let vertex_size = if point_data { 16 } else { 12 };
        assert_eq!(bytes.len(), end + 4 * vertex_size + 4 * 17);
        let faces = ply_faces(&bytes, end, vertex_size);
        assert_eq!(
            faces,
            [
                ([0, 2, 1], 1),
                ([0, 1, 3], 1),
                ([0, 3, 2], 2),
                ([1, 2, 3], 3)
            ]
        );
        assert_reads_back("m.ply", &bytes, point_data);
    }
}

#[test]
fn ply_reader_skips_face_properties_in_ascii_too() {
    let s = "ply\nformat ascii 1.0\ncomment region 1 a\ncomment region 2 b\n\
             comment region 3 c\nelement vertex 4\nproperty float x\nproperty float y\n\
             property float z\nelement face 4\nproperty list uchar int vertex_indices\n\
             property int region\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n\
             3 0 2 1 1\n3 0 1 3 1\n3 0 3 2 2\n3 1 2 3 3\n";
    assert_reads_back("m.ply", s.as_bytes(), false);
}

const VTK_CELLS: &str = "CELL_DATA 4\nSCALARS region int 1\nLOOKUP_TABLE default\n1\n1\n2\n3\n\
    FIELD FieldData 1\nregion_name 1 4 string\na\na\nb\nc\n";

#[test]
fn vtk_has_cell_scalars_and_names_after_the_point_data() {
    let plain = text(MeshFormat::Vtk, false);
    assert!(plain.ends_with(&format!("3 1 2 3\n{VTK_CELLS}")), "{plain}");
    assert_reads_back("m.vtk", plain.as_bytes(), false);
    let with_data = text(MeshFormat::Vtk, true);
    assert!(
        with_data.ends_with(&format!(
            "3 1 2 3\nPOINT_DATA 4\nSCALARS distance double 1\nLOOKUP_TABLE default\n\
             0.5\n1.5\n2.5\n3.5\n{VTK_CELLS}"
        )),
        "{with_data}"
    );
    assert_reads_back("m.vtk", with_data.as_bytes(), true);
}

#[test]
fn vtp_has_cell_data_between_point_data_and_points() {
    let cells = "<CellData Scalars=\"region\">\n\
                 <DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n1\n1\n2\n3\n\
                 </DataArray>\n\
                 <DataArray type=\"String\" Name=\"region_name\" format=\"ascii\">\n\
                 97 0\n97 0\n98 0\n99 0\n</DataArray>\n</CellData>\n<Points>\n";
    for point_data in [false, true] {
        let s = text(MeshFormat::Vtp, point_data);
        let at = s.find(cells).unwrap_or_else(|| panic!("{s}"));
        if point_data {
            let pd = s.find("</PointData>\n").unwrap();
            assert_eq!(pd + "</PointData>\n".len(), at);
        } else {
            assert!(s[..at].ends_with("NumberOfPolys=\"4\">\n"), "{s}");
        }
        assert_reads_back("m.vtp", s.as_bytes(), point_data);
    }
}

#[test]
fn stl_has_no_place_for_regions() {
    let m = unit_tetrahedron();
    for f in [MeshFormat::StlBinary, MeshFormat::StlAscii] {
        let plain = write_mesh(&m, f, None, "regions").unwrap();
        assert_eq!(write(f, false), plain, "{f:?}");
    }
}

/// Files without regions are the very bytes the writers produced before regions existed
/// (pinned from that version for the unit tetrahedron).
#[test]
fn without_regions_the_files_are_unchanged() {
    let m = unit_tetrahedron();
    let w = |f| write_mesh(&m, f, None, "").unwrap();
    let same = |f| write_mesh_with(&m, f, None, None, "").unwrap();
    for f in [
        MeshFormat::Obj,
        MeshFormat::StlBinary,
        MeshFormat::StlAscii,
        MeshFormat::Ply,
        MeshFormat::Vtk,
        MeshFormat::Vtp,
    ] {
        assert_eq!(w(f), same(f), "{f:?}");
    }
    let faces = ["0 2 1", "0 1 3", "0 3 2", "1 2 3"];
    let obj = format!(
        "# heartmesh {VERSION}\n# 4 vertices, 4 triangles, mm\nv 0 0 0\nv 1 0 0\nv 0 1 0\n\
         v 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
    );
    assert_eq!(String::from_utf8(w(MeshFormat::Obj)).unwrap(), obj);
    let vtk = format!(
        "# vtk DataFile Version 3.0\nheartmesh {VERSION}\nASCII\nDATASET POLYDATA\n\
         POINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\nPOLYGONS 4 16\n3 {}\n",
        faces.join("\n3 ")
    );
    assert_eq!(String::from_utf8(w(MeshFormat::Vtk)).unwrap(), vtk);
    let vtp = format!(
        "<?xml version=\"1.0\"?>\n<!-- heartmesh {VERSION} -->\n\
         <VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\">\n<PolyData>\n\
         <Piece NumberOfPoints=\"4\" NumberOfVerts=\"0\" NumberOfLines=\"0\" \
         NumberOfStrips=\"0\" NumberOfPolys=\"4\">\n<Points>\n\
         <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n\
         0 0 0\n1 0 0\n0 1 0\n0 0 1\n</DataArray>\n</Points>\n<Polys>\n\
         <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n{}\n</DataArray>\n\
         <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n3\n6\n9\n12\n\
         </DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n",
        faces.join("\n")
    );
    assert_eq!(String::from_utf8(w(MeshFormat::Vtp)).unwrap(), vtp);
    let ply = w(MeshFormat::Ply);
    let header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment heartmesh {VERSION}\nelement vertex 4\n\
         property float x\nproperty float y\nproperty float z\nelement face 4\n\
         property list uchar int vertex_indices\nend_header\n"
    );
    assert!(ply.starts_with(header.as_bytes()));
    assert_eq!(ply.len(), header.len() + 4 * 12 + 4 * 13);
}

/// Every format refuses the same bad regions with a message that says what is wrong.
#[test]
fn bad_regions_are_errors() {
    let m = unit_tetrahedron();
    let cases: [(&[u32], &[&str], &str, &str); 9] = [
        (&[0, 0, 1], &NAMES, "region", "3 ids for 4 triangles"),
        (&[0, 0, 1, 2, 0], &NAMES, "region", "5 ids for 4 triangles"),
        (&[0, 0, 1, 3], &NAMES, "region", "triangle 3 has region 3"),
        (&[0, 0, 0, 0], &[], "region", "0 names"),
        (&IDS, &["a", "b c", "d"], "region", "\"b c\""),
        (&IDS, &["a", "b", "c\n"], "region", "\"c\\n\""),
        (&IDS, &["a", "", "c"], "region", "\"\""),
        (&IDS, &NAMES, "my region", "region array name \"my region\""),
        (&IDS, &NAMES, "", "region array name \"\""),
    ];
    for (ids, names, array, expected) in cases {
        let r = Regions { array, ids, names };
        for f in [
            MeshFormat::Obj,
            MeshFormat::Ply,
            MeshFormat::Vtk,
            MeshFormat::StlBinary,
        ] {
            match write_mesh_with(&m, f, None, Some(&r), "") {
                Err(CoreError::Io(msg)) => assert!(msg.contains(expected), "{msg}"),
                other => panic!("{f:?} {ids:?} {names:?} {array:?}: {other:?}"),
            }
        }
    }
}

/// Regions on a larger mesh: every triangle's value and name, in order, in VTK and VTP.
#[test]
fn values_follow_the_triangle_order_on_a_larger_mesh() {
    let m: TriMesh =
        heartmesh_core::mesh::shapes::octahedron(10.0, heartmesh_core::geometry::v3(0., 0., 0.));
    let ids: Vec<u32> = (0..8).map(|t| (t * 5 % 3) as u32).collect();
    let names = ["epicardium", "endocardium", "base"];
    let r = Regions {
        array: "tag",
        ids: &ids,
        names: &names,
    };
    let vtk = String::from_utf8(write_mesh_with(&m, MeshFormat::Vtk, None, Some(&r), "").unwrap())
        .unwrap();
    let cells = &vtk[vtk
        .find("CELL_DATA 8\nSCALARS tag int 1\nLOOKUP_TABLE default\n")
        .unwrap()..];
    let lines: Vec<&str> = cells.lines().collect();
    let values: Vec<u32> = lines[3..11].iter().map(|l| l.parse().unwrap()).collect();
    assert_eq!(values, ids.iter().map(|i| i + 1).collect::<Vec<_>>());
    assert_eq!(lines[11..13], ["FIELD FieldData 1", "tag_name 1 8 string"]);
    let spelled: Vec<&str> = ids.iter().map(|&i| names[i as usize]).collect();
    assert_eq!(lines[13..], spelled[..]);
    let back = read_mesh("m.vtk", vtk.as_bytes()).unwrap();
    assert_eq!(back.mesh.triangles, m.triangles);
}
