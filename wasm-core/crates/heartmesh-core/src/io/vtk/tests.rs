use super::*;

const LINES: &str = "# vtk DataFile Version 3.0\ncontours\nASCII\nDATASET POLYDATA\n\
    POINTS 5 float\n0 0 0 1 0 0 1 1 0\n0 0 5 0 1 5\nLINES 2 7\n3 0 1 2\n2 3 4\n";

#[test]
fn lines_become_contours() {
    let set = read_vtk_contours(LINES.as_bytes()).unwrap();
    assert_eq!(set.contours.len(), 2);
    assert_eq!(set.contours[0].point_count(), 3);
    assert_eq!(set.contours[1].pieces[0].points[1], v3(0.0, 1.0, 5.0));
}

#[test]
fn polygons_are_closed_contours_and_triangles_a_mesh() {
    // Two 8-point rings as POLYGONS (DICOM-RT's closed planar contours), no LINES.
    let mut s = String::from(
        "# vtk DataFile Version 3.0\nrings\nASCII\nDATASET POLYDATA\nPOINTS 16 float\n",
    );
    for z in [0.0, 10.0] {
        for i in 0..8 {
            let t = i as f64 * std::f64::consts::TAU / 8.0;
            s.push_str(&format!("{} {} {z}\n", 20.0 * t.cos(), 20.0 * t.sin()));
        }
    }
    s.push_str("POLYGONS 2 18\n8 0 1 2 3 4 5 6 7\n8 8 9 10 11 12 13 14 15\n");
    let set = read_vtk_contours(s.as_bytes()).unwrap();
    let rings: Vec<(&str, usize, bool)> = set
        .contours
        .iter()
        .map(|c| (c.id.as_str(), c.point_count(), c.pieces[0].closed))
        .collect();
    assert_eq!(rings, [("polygon1", 8, true), ("polygon2", 8, true)]);
    // The same in VTP: one ring as Polys.
    let pts: Vec<String> = (0..8)
        .map(|i| {
            let t = i as f64 * std::f64::consts::TAU / 8.0;
            format!("{} {} 0", 20.0 * t.cos(), 20.0 * t.sin())
        })
        .collect();
    let vtp = format!(
        "<VTKFile type=\"PolyData\" version=\"0.1\"><PolyData><Piece NumberOfPoints=\"8\" \
         NumberOfPolys=\"1\"><Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" \
         format=\"ascii\">{}</DataArray></Points><Polys><DataArray type=\"Int32\" \
         Name=\"connectivity\" format=\"ascii\">0 1 2 3 4 5 6 7</DataArray><DataArray \
         type=\"Int32\" Name=\"offsets\" format=\"ascii\">8</DataArray></Polys></Piece>\
         </PolyData></VTKFile>",
        pts.join(" ")
    );
    let ring = crate::io::read_contours("r.vtp", vtp.as_bytes()).unwrap();
    assert_eq!(
        (ring.point_count(), ring.contours[0].pieces[0].closed),
        (8, true)
    );
    let tri = "# vtk DataFile Version 3.0\nm\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n\
               0 0 0 1 0 0 1 1 0 0 1 0\nPOLYGONS 2 8\n3 0 1 2\n3 0 2 3\n";
    let e = read_vtk_contours(tri.as_bytes()).unwrap_err().to_string();
    assert_eq!(
        e,
        "no LINES (polylines) found: the file holds a surface of 2 polygons (a mesh), not contours"
    );
}

#[test]
fn version_51_layout() {
    let s = "# vtk DataFile Version 5.1\nx\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n\
             0 0 0 1 0 0 1 1 0 0 1 0\nPOLYGONS 2 4\nOFFSETS vtktypeint64\n0 4\n\
             CONNECTIVITY vtktypeint64\n0 1 2 3\n";
    let m = read_vtk_mesh(s.as_bytes()).unwrap().mesh;
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
}

/// `head` (a binary legacy file up to its POINTS) followed by three points and one line through
/// them, big-endian as VTK writes binary files.
fn with_binary_line(mut b: Vec<u8>) -> Vec<u8> {
    b.extend_from_slice(b"POINTS 3 float\n");
    for x in [0f32, 0., 0., 10., 0., 0., 10., 10., 0.] {
        b.extend_from_slice(&x.to_be_bytes());
    }
    b.extend_from_slice(b"\nLINES 1 4\n");
    for i in [3i32, 0, 1, 2] {
        b.extend_from_slice(&i.to_be_bytes());
    }
    b.push(b'\n');
    b
}

#[test]
fn binary_lines() {
    let b = with_binary_line(b"# vtk DataFile Version 3.0\nb\nBINARY\nDATASET POLYDATA\n".to_vec());
    let set = read_vtk_contours(&b).unwrap();
    assert_eq!(set.point_count(), 3);
    assert_eq!(set.contours[0].pieces[0].points[2], v3(10.0, 10.0, 0.0));
    // Truncated binary data is an error, not a panic.
    assert!(read_vtk_contours(&b[..b.len() - 6]).is_err());
}

#[test]
fn long_comment_keeps_ascii_keyword_early() {
    let m = TriMesh::new(
        vec![v3(0., 0., 0.), v3(1., 0., 0.), v3(0., 1., 0.)],
        vec![[0, 1, 2]],
    );
    let out = write_vtk(&m, None, &"x".repeat(1000));
    let head = String::from_utf8_lossy(&out[..250]).into_owned();
    assert_eq!(head.split('\n').nth(2), Some("ASCII"));
}

#[test]
fn a_long_title_ends_after_a_whole_clause() {
    let comment =
        "biventricular myocardium of patient1-ED.csv (LV_ENDO + BIV_EPI + RV_ENDO); units \
                   mm, the contour file's coordinates; region 1 epicardium, 2 lv_endocardium, 3 \
                   rv_endocardium, 4 base";
    let t = super::write::title(comment);
    assert!(t.len() <= 160, "{t}");
    assert!(
        t.ends_with("units mm, the contour file's coordinates ..."),
        "{t}"
    );
    // One that fits is kept whole; one clause longer than the limit after its last word
    // (or at the limit).
    assert!(super::write::title("LV wall; 3 regions").ends_with("LV wall; 3 regions"));
    assert_eq!(super::write::title(&"x".repeat(1000)).len(), 160);
    let words = super::write::title(&"word ".repeat(100));
    assert!(words.ends_with("word ...") && words.len() <= 160, "{words}");
}

#[test]
fn bad_index_has_line() {
    let s = LINES.replace("2 3 4", "2 3 9");
    let e = read_vtk_contours(s.as_bytes()).unwrap_err();
    assert_eq!(e.line(), Some(10), "{e}");
}

/// Two LV_ENDO rings and an open RV curve in two pieces, with three landmarks, as heartmesh's CSV.
fn csv_with_landmarks() -> String {
    let mut s = String::from("contour,surface,x,y,z\n");
    for (id, surface, z, n) in [("s1", "LV_ENDO", 0.0, 12), ("s2", "LV_ENDO", 10.0, 10)] {
        for i in 0..n {
            let t = i as f64 * std::f64::consts::TAU / n as f64;
            s.push_str(&format!(
                "{id},{surface},{},{},{z}\n",
                20.0 * t.cos(),
                20.0 * t.sin()
            ));
        }
    }
    s.push_str("rv,RV_FW,30,0,0\nrv,RV_FW,35,5,0\nrv,RV_FW,36,12,0\n# piece\n");
    s.push_str("rv,RV_FW,34,20,0\nrv,RV_FW,30,25,0\n");
    s.push_str("# landmark APEX_POINT 1.5 -2.25 -40.125\n");
    s.push_str("# landmark MITRAL_VALVE 0.1 0.2 12.000000001\n");
    s.push_str("# landmark RV_INSERT 25 -3 5\n");
    s
}

/// Landmarks survive CSV -> VTK legacy -> read: one-point VERTICES cells written before the
/// lines, labelled in the same `contour_id` / `surface` arrays, and the contours are unchanged.
#[test]
fn landmarks_round_trip_as_vertex_cells() {
    let mut set = crate::io::read_contours("l.csv", csv_with_landmarks().as_bytes()).unwrap();
    assert_eq!(set.landmarks.len(), 3);
    // A name that only the cell arrays can carry (CSV comments split at spaces).
    set.landmarks
        .push(("odd name % µ".into(), v3(-1e-3, 2.0, 3e4)));
    let bytes = crate::io::write_contour_lines(&set, false, "landmarks");
    let text = String::from_utf8(bytes.clone()).unwrap();
    let points = set.point_count() + 4;
    assert!(
        text.contains(&format!("POINTS {points} double\n")),
        "{text}"
    );
    let verts = format!("VERTICES 4 8\n1 {}\n", points - 4);
    let (v, l) = (text.find(&verts).unwrap(), text.find("\nLINES 4 ").unwrap());
    assert!(v < l, "verts come first, as in VTK's cell order");
    assert!(text.contains("CELL_DATA 8\n"), "{text}");
    assert!(
        text.contains("contour_id 1 8 string\nAPEX_POINT\n"),
        "{text}"
    );
    let back = read_vtk_contours(&bytes).unwrap();
    assert_eq!(back.landmarks, set.landmarks);
    assert_eq!(back.contours.len(), set.contours.len());
    for (b, c) in back.contours.iter().zip(&set.contours) {
        assert_eq!(
            (&b.id, &b.surface, &b.pieces),
            (&c.id, &c.surface, &c.pieces)
        );
    }
    // Without landmarks the file is as before: no VERTICES.
    set.landmarks.clear();
    let plain = crate::io::write_contour_lines(&set, false, "");
    let plain = String::from_utf8(plain).unwrap();
    assert!(!plain.contains("VERTICES") && plain.contains("CELL_DATA 4\n"));
}

/// Vertex cells of other tools stay out of the contours and landmarks, as they always were: not
/// labelled, labelled without the landmark marker, or of several points.
#[test]
fn other_vertex_cells_are_not_landmarks() {
    let with_verts = LINES.replace("LINES", "VERTICES 2 5\n1 0\n2 3 4\nLINES");
    let set = read_vtk_contours(with_verts.as_bytes()).unwrap();
    assert_eq!((set.contours.len(), set.landmarks.len()), (2, 0));
    assert_eq!(set.contours[0].id, "line1");
    let labelled = format!(
        "{with_verts}CELL_DATA 4\nFIELD FieldData 2\ncontour_id 1 4 string\nAPEX\nPTS\na\nb\n\
         surface 1 4 string\nLV_ENDO\nlandmark\nLV_ENDO\nLV_EPI\n"
    );
    let set = read_vtk_contours(labelled.as_bytes()).unwrap();
    assert_eq!(set.landmarks.len(), 0);
    let ids: Vec<&str> = set.contours.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(ids, ["a", "b"]);
    assert_eq!(set.contours[1].surface.as_deref(), Some("LV_EPI"));
}

/// Dataset field data sits after `DATASET POLYDATA`, before POINTS (where VTK's writer and the
/// app's VTK export put it); it is read past, not taken as the end of the file.
#[test]
fn dataset_field_data_before_points_is_skipped() {
    // The app's layout: parameters as FIELD data, then the tetrahedron and its distance scalars.
    let app = "# vtk DataFile Version 3.0\nheartmesh 0.1.0\nASCII\nDATASET POLYDATA\n\
               FIELD heartmesh_params 3\niterations 1 1 double\n250\nlambda 1 1 double\n100000\n\
               label 1 2 string\nLV ENDO\nmm\nPOINTS 4 float\n0 0 0\n10 0 0\n0 10 0\n0 0 10\n\
               POLYGONS 4 16\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n\
               POINT_DATA 4\nSCALARS distance_mm float 1\nLOOKUP_TABLE default\n0.1\n0.2\n0.3\n0.45\n";
    let m = read_vtk_mesh(app.as_bytes()).unwrap();
    assert_eq!((m.mesh.positions.len(), m.mesh.triangles.len()), (4, 4));
    assert_eq!(m.mesh.positions[3], v3(0.0, 0.0, 10.0));
    assert!((m.mesh.signed_volume() - 1000.0 / 6.0).abs() < 1e-9);
    let (name, d) = m.point_data.unwrap();
    assert_eq!(
        (name.as_str(), d),
        ("distance_mm", vec![0.1, 0.2, 0.3, 0.45])
    );
    // The same for contour lines, and in a binary file (big-endian doubles, then a newline).
    let lines = LINES.replace(
        "POINTS",
        "FIELD FieldData 1\nTimeValue 1 1 double\n0.5\nPOINTS",
    );
    assert_eq!(
        read_vtk_contours(lines.as_bytes()).unwrap().point_count(),
        5
    );
    let mut b = b"# vtk DataFile Version 3.0\nb\nBINARY\nDATASET POLYDATA\nFIELD FieldData 1\n\
                  TimeValue 1 2 double\n"
        .to_vec();
    for t in [0.5f64, 10.0] {
        b.extend_from_slice(&t.to_be_bytes());
    }
    b.push(b'\n');
    let b = with_binary_line(b);
    let set = read_vtk_contours(&b).unwrap();
    assert_eq!(set.contours[0].pieces[0].points[2], v3(10.0, 10.0, 0.0));
}

/// Region names are written as VTK writes string arrays (percent-encoded: VTK 9.7 read these
/// very lines back as `µ-wall`, `50%`, `x&<y>"z`), the array name as one printable-ASCII token,
/// and the file still reads as the mesh it holds, with or without point data before the cells.
#[test]
fn region_names_are_vtk_strings_and_the_mesh_still_reads() {
    let m = crate::mesh::shapes::unit_tetrahedron();
    let r = crate::io::Regions {
        array: "région",
        ids: &[2, 0, 1, 2],
        names: &["µ-wall", "50%", "x&<y>\"z"],
    };
    let d = [1.0, 2.0, 3.0, 4.0];
    for point_data in [None, Some(("d", &d[..]))] {
        let bytes =
            crate::io::write_mesh_with(&m, crate::io::MeshFormat::Vtk, point_data, Some(&r), "")
                .unwrap();
        let text = String::from_utf8(bytes.clone()).unwrap();
        assert!(text.ends_with(
            "CELL_DATA 4\nSCALARS r_gion int 1\nLOOKUP_TABLE default\n3\n1\n2\n3\n\
             FIELD FieldData 1\nr_gion_name 1 4 string\nx&<y>\"z\n%C2%B5-wall\n50%25\nx&<y>\"z\n"
        ));
        let pd = read_polydata(&bytes).unwrap();
        assert_eq!((pd.points.len(), pd.polys.len()), (4, 4));
        assert_eq!(pd.point_scalars.is_some(), point_data.is_some());
        let back = read_vtk_mesh(&bytes).unwrap();
        assert_eq!(back.mesh.triangles, m.triangles);
    }
}
