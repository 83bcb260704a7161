//! Region labels read from files other tools write: polygons with several triangles, strips,
//! cell data over lines and polygons, float properties that are not labels, OBJ groups around
//! ungrouped faces. Each asserts the label of every triangle, so a label shifted by one cell
//! fails.

use heartmesh_core::io::{read_mesh, write_mesh_with, MeshFormat, Regions};
use heartmesh_core::mesh::shapes::unit_tetrahedron;

/// The array name, the label of each triangle and the named labels.
type Read = (String, Vec<i32>, Vec<(i32, String)>);

fn labels(name: &str, text: &str) -> Option<Read> {
    let m = read_mesh(name, text.as_bytes()).unwrap_or_else(|e| panic!("{name}: {e}"));
    m.regions.map(|r| {
        assert_eq!(r.labels.len(), m.mesh.triangles.len(), "{name}");
        (r.array, r.labels, r.names.into_iter().collect())
    })
}

/// A quad is two triangles with the quad's label; faces before the first `g` are OBJ's
/// `default` group; a group named again continues with its first number.
#[test]
fn obj_groups_number_in_order_of_appearance() {
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n\
               f 1 2 5\ng lid\nf 1 2 3 4\ng wall side\nf 2 3 5\ng lid\nf 3 4 5\n";
    let (array, l, names) = labels("m.obj", obj).unwrap();
    assert_eq!(array, "group");
    assert_eq!(l, [1, 2, 2, 3, 2]);
    assert_eq!(
        names,
        [
            (1, "default".into()),
            (2, "lid".into()),
            (3, "wall side".into())
        ]
    );
    // Without any `g` line there are no regions.
    assert_eq!(
        labels("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        None
    );
}

/// A PLY from another tool: `uchar material` on a quad and a triangle, no names.
#[test]
fn ply_face_property_of_other_tools() {
    let ply = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n\
               property float z\nelement face 2\nproperty list uchar int vertex_indices\n\
               property uchar material\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n\
               4 0 1 2 3 7\n3 0 1 4 9\n";
    let (array, l, names) = labels("m.ply", ply).unwrap();
    assert_eq!((array.as_str(), l.as_slice()), ("material", &[7, 7, 9][..]));
    assert!(names.is_empty());
    // A float property before the list (a quality value, not a label) gives no regions.
    let float = ply
        .replace(
            "property list uchar int vertex_indices\nproperty uchar material",
            "property float q\nproperty list uchar int vertex_indices",
        )
        .replace("4 0 1 2 3 7\n3 0 1 4 9\n", "0.5 4 0 1 2 3\n0.25 3 0 1 4\n");
    assert_eq!(labels("m.ply", &float), None);
}

/// Legacy VTK numbers cells VERTICES, LINES, POLYGONS, TRIANGLE_STRIPS whatever order the file
/// lists them in: here the strip comes first in the file and a line precedes the polygons, so
/// the polygon's label is the 2nd value and the strip's (two triangles) the 3rd.
#[test]
fn vtk_cell_order_over_lines_polygons_and_strips() {
    let vtk = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 5 float\n\
               0 0 0 1 0 0 1 1 0 0 1 0 0 0 1\n\
               TRIANGLE_STRIPS 1 5\n4 0 1 3 2\nLINES 1 3\n2 0 4\nPOLYGONS 1 5\n4 0 1 2 3\n\
               CELL_DATA 3\nSCALARS part int 1\nLOOKUP_TABLE default\n5 6 8\n\
               FIELD FieldData 1\npart_name 1 3 string\ncurve\nquad\nstrip%20part\n";
    let (array, l, names) = labels("m.vtk", vtk).unwrap();
    assert_eq!(array, "part");
    // The polygon's two fan triangles first (polys are read in file order, strips expanded
    // where they stand: here the strip's triangles come first in the mesh).
    let m = read_mesh("m.vtk", vtk.as_bytes()).unwrap();
    assert_eq!(m.mesh.triangles.len(), 4);
    assert_eq!(l, [8, 8, 6, 6]);
    assert_eq!(names, [(6, "quad".into()), (8, "strip part".into())]);
    // Too few values for the cells: no regions, the mesh still reads.
    let short = vtk
        .replace("CELL_DATA 3", "CELL_DATA 2")
        .replace("5 6 8", "5 6");
    assert_eq!(labels("m.vtk", &short), None);
}

/// VTP cell data runs over verts, lines, strips, polys: a line before the polygons shifts them.
#[test]
fn vtp_cell_data_skips_the_lines() {
    let vtp = r#"<?xml version="1.0"?>
<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian">
<PolyData><Piece NumberOfPoints="4" NumberOfVerts="0" NumberOfLines="1" NumberOfStrips="0" NumberOfPolys="2">
<CellData Scalars="tag"><DataArray type="Int32" Name="tag" format="ascii">99 4 5</DataArray></CellData>
<Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>
<Lines><DataArray type="Int32" Name="connectivity" format="ascii">0 3</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">2</DataArray></Lines>
<Polys><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 0 1 3</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">3 6</DataArray></Polys>
</Piece></PolyData></VTKFile>"#;
    let (array, l, names) = labels("m.vtp", vtp).unwrap();
    assert_eq!((array.as_str(), l.as_slice()), ("tag", &[4, 5][..]));
    assert!(names.is_empty());
    // Fractional values are not labels.
    assert_eq!(labels("m.vtp", &vtp.replace("99 4 5", "99 4.5 5")), None);
}

/// A file with regions read and written again keeps every label and name, in every format that
/// has a place for them (the round trip `heartmesh convert` makes).
#[test]
fn regions_survive_a_round_trip_through_every_format() {
    let m = unit_tetrahedron();
    let names = ["epicardium", "endocardium", "base"];
    let r = Regions {
        array: "region",
        ids: &[2, 0, 1, 0],
        names: &names,
    };
    for format in [
        MeshFormat::Obj,
        MeshFormat::Ply,
        MeshFormat::Vtk,
        MeshFormat::Vtp,
    ] {
        let name = format!("m.{}", format.extension());
        let bytes = write_mesh_with(&m, format, None, Some(&r), "").unwrap();
        let back = read_mesh(&name, &bytes).unwrap().regions.unwrap();
        let (ids, written) = back.for_writing();
        let again: Vec<&str> = ids.iter().map(|&i| written[i as usize].as_str()).collect();
        assert_eq!(
            again,
            ["base", "epicardium", "endocardium", "epicardium"],
            "{name}"
        );
        let facts = back.facts(&m);
        let counts: Vec<(&str, usize)> = facts
            .iter()
            .map(|f| (f.name.as_str(), f.triangles))
            .collect();
        let area: f64 = facts.iter().map(|f| f.area_mm2).sum();
        assert!((area - m.area()).abs() < 1e-12, "{name}");
        if format == MeshFormat::Obj {
            // OBJ numbers groups by first appearance: base came first.
            assert_eq!(counts, [("base", 1), ("epicardium", 2), ("endocardium", 1)]);
        } else {
            assert_eq!(
                counts,
                [("epicardium", 2), ("endocardium", 1), ("base", 1)],
                "{name}"
            );
        }
    }
}
