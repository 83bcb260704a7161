//! Files as other tools write them (session 16, the second hostile round; scripts/hostile.py
//! `other_tools` generates the same cases): Excel's UTF-16 "Unicode text" and Windows-1252 CSV,
//! classic-Mac line ends, headers with units, pandas' index column, a slice column, a time-frame
//! column, no header line (session 19), GPFiles saved with commas or spaces, a SliceInfoFile of
//! another acquisition, and stdout closed by `| head`. Each either gives the canonical file's mesh
//! byte for byte, or one line that says what to do.

mod common;
use common::{bin, data, mesh_lines, run, scratch};
use std::io::Read;
use std::path::Path;
use std::process::Stdio;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `reconstruct FILE -o DIR/out.obj [extra]`: (status, stderr, the mesh's vertex and face lines).
fn reconstruct(dir: &Path, file: &Path, extra: &[&str]) -> (i32, String, Vec<String>) {
    let out = dir.join("out.obj");
    let _ = std::fs::remove_file(&out);
    let (code, _, err) = run(bin()
        .args(["reconstruct", s(file), "-o", s(&out), "--quiet"])
        .args(extra));
    let body = mesh_lines(&out);
    (code, err, body)
}

fn surfco() -> String {
    std::fs::read_to_string(data("contours/surfco-example.csv")).unwrap()
}

/// Each data row of the canonical SurFCo file through `f` (the header through `head`).
fn rows(head: &str, f: impl Fn(&str) -> String) -> String {
    let text = surfco();
    let mut out = format!("{head}\n");
    for l in text.lines().skip(1).filter(|l| !l.is_empty()) {
        out.push_str(&f(l));
        out.push('\n');
    }
    out
}

#[test]
fn encodings_line_ends_and_layouts_of_other_tools_give_the_canonical_mesh() {
    let dir = scratch("other-tools");
    let canonical = dir.join("canonical.csv");
    std::fs::write(&canonical, surfco()).unwrap();
    let (code, err, want) = reconstruct(&dir, &canonical, &[]);
    assert_eq!(code, 0, "{err}");
    assert!(want.len() > 1000);
    let tabbed = surfco().replace(',', "\t").replace('\n', "\r\n");
    let utf16le: Vec<u8> = [0xFF, 0xFE]
        .into_iter()
        .chain(tabbed.encode_utf16().flat_map(u16::to_le_bytes))
        .collect();
    let utf16be: Vec<u8> = [0xFE, 0xFF]
        .into_iter()
        .chain(tabbed.encode_utf16().flat_map(u16::to_be_bytes))
        .collect();
    let bare16: Vec<u8> = tabbed.encode_utf16().flat_map(u16::to_le_bytes).collect();
    // "Région" in Windows-1252 (0xE9), as Excel's plain "CSV" writes it on Windows.
    let ansi: Vec<u8> = rows("contour,x,y,z", |l| format!("R\u{e9}gion {l}"))
        .chars()
        .map(|c| c as u32 as u8)
        .collect();
    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("Excel Unicode text (UTF-16 LE, tabs, CRLF)", utf16le),
        ("UTF-16 BE", utf16be),
        ("UTF-16 LE without BOM", bare16),
        ("Windows-1252 id", ansi),
        ("classic Mac CR", surfco().replace('\n', "\r").into_bytes()),
        ("CR CR LF", surfco().replace('\n', "\r\r\n").into_bytes()),
        (
            "Unicode minus sign",
            surfco().replace(",-", ",\u{2212}").into_bytes(),
        ),
        (
            "units in the header",
            surfco()
                .replacen("contour,x,y,z", "Contour,X (mm),Y [mm],z_mm", 1)
                .into_bytes(),
        ),
        (
            "pandas index column",
            rows(",contour,x,y,z", |l| format!("7,{l}")).into_bytes(),
        ),
        (
            "slice column",
            surfco()
                .replacen("contour,x,y,z", "slice,x,y,z", 1)
                .into_bytes(),
        ),
        (
            "separator at the end of every row",
            rows("contour,x,y,z,", |l| format!("{l},")).into_bytes(),
        ),
        (
            "no header line (session 19)",
            surfco()
                .split_once('\n')
                .map(|(_, body)| body.to_string())
                .unwrap()
                .into_bytes(),
        ),
        (
            "no header line, semicolons and decimal commas",
            rows("", |l| l.replace(',', ";").replace('.', ","))
                .trim_start()
                .to_string()
                .into_bytes(),
        ),
        (
            "every field quoted",
            rows("\"contour\",\"x\",\"y\",\"z\"", |l| {
                l.split(',')
                    .map(|f| format!("\"{f}\""))
                    .collect::<Vec<_>>()
                    .join(",")
            })
            .into_bytes(),
        ),
    ];
    for (name, bytes) in cases {
        let f = dir.join("variant.csv");
        std::fs::write(&f, bytes).unwrap();
        let (code, err, got) = reconstruct(&dir, &f, &[]);
        assert_eq!(code, 0, "{name}: {err}");
        assert!(
            got == want,
            "{name}: another mesh than the canonical file's"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn decimal_commas_pixels_and_centimetres_in_the_header_are_told() {
    let dir = scratch("other-tools-units");
    let f = dir.join("decimal-comma.csv");
    std::fs::write(&f, rows("contour,x,y,z", |l| l.replace('.', ","))).unwrap();
    let (code, err, body) = reconstruct(&dir, &f, &[]);
    assert_eq!((code, err.lines().count(), body.len()), (2, 1, 0), "{err}");
    assert_eq!(
        err.trim_end(),
        format!(
            "heartmesh: {}:2: row has 7 fields but the header names 4 columns; decimal commas \
             with \",\" between the fields? Then separate the fields with \";\"",
            s(&f)
        )
    );
    std::fs::write(
        &f,
        surfco().replacen("contour,x,y,z", "contour,x (px),y,z", 1),
    )
    .unwrap();
    let (code, err, _) = reconstruct(&dir, &f, &[]);
    assert_eq!((code, err.lines().count()), (2, 1), "{err}");
    assert!(
        err.contains(":1: column \"x (px)\" is in pixels; heartmesh works in millimetres"),
        "{err}"
    );
    // Centimetres the header declares: converted, said once, and no "centimetres?" guess.
    let cm = rows("contour,x (cm),y (cm),z (cm)", |l| {
        let f: Vec<&str> = l.split(',').collect();
        let v: Vec<String> = f[1..]
            .iter()
            .map(|v| format!("{}", v.parse::<f64>().unwrap() / 10.0))
            .collect();
        format!("{},{}", f[0], v.join(","))
    });
    std::fs::write(&f, cm).unwrap();
    let (code, _, err) = run(bin().args([
        "reconstruct",
        s(&f),
        "-o",
        s(&dir.join("cm.obj")),
        "--report",
        s(&dir.join("cm.json")),
    ]));
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        err.lines().collect::<Vec<_>>(),
        [format!(
            "heartmesh: warning: {}: coordinates in cm (as the header says) converted to mm",
            s(&f)
        )]
    );
    let rep: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("cm.json")).unwrap()).unwrap();
    let c2m = rep["contour_to_mesh"]["mean"].as_f64().unwrap();
    assert!((c2m - 0.060).abs() < 0.001, "{c2m} mm, as in mm");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_csv_with_several_time_frames_reads_one_and_says_so() {
    let dir = scratch("other-tools-frames");
    let text = surfco();
    let data_rows: Vec<&str> = text.lines().skip(1).filter(|l| !l.is_empty()).collect();
    let mut csv = String::from("contour,x,y,z,frame\n");
    for (frame, grow) in [(0, 1.0), (1, 1.1)] {
        for l in &data_rows {
            let f: Vec<&str> = l.split(',').collect();
            let v: Vec<String> = f[1..]
                .iter()
                .map(|v| format!("{}", v.parse::<f64>().unwrap() * grow))
                .collect();
            csv.push_str(&format!("{},{},{frame}\n", f[0], v.join(",")));
        }
    }
    let f = dir.join("cine.csv");
    std::fs::write(&f, csv).unwrap();
    let canonical = dir.join("canonical.csv");
    std::fs::write(&canonical, &text).unwrap();
    let (_, _, want) = reconstruct(&dir, &canonical, &[]);
    let out = dir.join("out.obj");
    let (code, _, err) = run(bin().args(["reconstruct", s(&f), "-o", s(&out)]));
    assert_eq!(code, 0, "{err}");
    let warn = format!(
        "heartmesh: warning: {}: the file holds 2 time frames (0, 1): frame 0 read, {} points of \
         other frames left out; save one frame per file, or choose one with the command line's \
         --frame (e.g. --frame 1)",
        s(&f),
        data_rows.len()
    );
    assert_eq!(err.lines().next(), Some(warn.as_str()), "{err}");
    let (code, err, got) = reconstruct(&dir, &f, &[]);
    assert_eq!(code, 0, "{err}");
    assert!(got == want, "frame 0 alone is the canonical file");
    let (code, err, one) = reconstruct(&dir, &f, &["--frame", "1"]);
    assert_eq!(code, 0, "{err}");
    assert!(one != want, "frame 1 is another shape");
    let (code, err, _) = reconstruct(&dir, &f, &["--frame", "3"]);
    assert_eq!((code, err.lines().count()), (2, 1), "{err}");
    assert!(
        err.contains("no contour points in frame 3 (frames in the file: 0, 1)"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A `contour` column that names only the surface (`one` for every curve of it, short- and
/// long-axis alike, as some exports do): each slice's curve is read as a contour of its own
/// (`contours::plane_split`), and the mesh is the file's own to the byte. Biv-me patient 1 ED's
/// LV endocardium and epicardium and its RV epicardium; the RV endocardium's free wall and septum
/// of one slice share a plane, so under one name they read as one curve of that slice, as any
/// file naming both alike does (not asserted here).
#[test]
fn one_name_for_every_slice_of_a_surface_gives_the_files_mesh() {
    let dir = scratch("other-tools-one-name");
    let src = data("contours/bivme-example-patient1/patient1-ED.csv");
    let text = std::fs::read_to_string(&src).unwrap();
    for surface in ["LV_ENDO", "LV_EPI", "RV_EPI"] {
        let (code, err, want) = reconstruct(&dir, &src, &["--surface", surface]);
        assert_eq!(code, 0, "{err}");
        let mut one = String::from("contour,x,y,z,surface\n");
        let mut rows = 0;
        for l in text.lines().skip(1).map(str::trim_end) {
            if let Some((_, rest)) = l.split_once(',').filter(|_| l.ends_with(surface)) {
                one.push_str(&format!("one,{rest}\n"));
                rows += 1;
            }
        }
        assert!(rows > 300, "{surface}: {rows} rows");
        let f = dir.join(format!("{surface}.csv"));
        std::fs::write(&f, one).unwrap();
        let out = dir.join("out.obj");
        let (code, _, err) = run(bin().args(["reconstruct", s(&f), "-o", s(&out)]));
        assert_eq!(code, 0, "{surface}: {err}");
        assert!(
            err.contains("contour \"one\" (line 2, 8 image planes, read as \"one\", \"one (2)\""),
            "{surface}: {err}"
        );
        assert!(
            mesh_lines(&out) == want,
            "{surface}: another mesh than the file's"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gpfiles_saved_with_commas_spaces_or_cr_and_another_slice_info() {
    let dir = scratch("other-tools-gp");
    let src = data("contours/bivme-example-patient1");
    let gp = std::fs::read_to_string(src.join("GPFile_000.txt")).unwrap();
    let info = std::fs::read(src.join("SliceInfoFile.txt")).unwrap();
    let f = dir.join("GPFile_000.txt");
    std::fs::write(dir.join("SliceInfoFile.txt"), &info).unwrap();
    std::fs::write(&f, &gp).unwrap();
    let lv = ["--surface", "LV_ENDO"];
    let (code, err, want) = reconstruct(&dir, &f, &lv);
    assert_eq!(code, 0, "{err}");
    let utf16: Vec<u8> = [0xFF, 0xFE]
        .into_iter()
        .chain(gp.encode_utf16().flat_map(u16::to_le_bytes))
        .collect();
    for (name, bytes) in [
        ("commas", gp.replace('\t', ",").into_bytes()),
        ("spaces", gp.replace('\t', " ").into_bytes()),
        ("CR only", gp.replace('\n', "\r").into_bytes()),
        ("UTF-16", utf16),
    ] {
        std::fs::write(&f, bytes).unwrap();
        let (code, err, got) = reconstruct(&dir, &f, &lv);
        assert_eq!(code, 0, "{name}: {err}");
        assert!(got == want, "{name}: another mesh");
    }
    // Patient 2's SliceInfoFile beside patient 1's GPFile: two warning lines, not forty.
    std::fs::write(&f, &gp).unwrap();
    std::fs::copy(
        data("contours/bivme-test-patient2/SliceInfoFile.txt"),
        dir.join("SliceInfoFile.txt"),
    )
    .unwrap();
    let (code, _, err) = run(bin()
        .args(["reconstruct", s(&f), "-o", s(&dir.join("o.obj"))])
        .args(lv));
    assert_eq!(code, 0, "{err}");
    let warnings: Vec<&str> = err.lines().filter(|l| l.contains("warning")).collect();
    assert_eq!(warnings.len(), 2, "{err}");
    assert!(warnings[0].ends_with("is the slice info file from another acquisition?"));
    assert!(warnings[1].ends_with("slice 11 (3 contours) is not in the slice info file"));
    // A damaged one is only a check not made: the GPFile reconstructs as without it, said once.
    std::fs::write(
        dir.join("SliceInfoFile.txt"),
        "x sliceID: 1 ImagePositionPatient 1 2\n",
    )
    .unwrap();
    let (code, _, err) = run(bin()
        .args(["reconstruct", s(&f), "-o", s(&dir.join("out.obj"))])
        .args(lv));
    assert_eq!(code, 0, "{err}");
    let warnings: Vec<&str> = err.lines().filter(|l| l.contains("warning")).collect();
    assert_eq!(warnings.len(), 1, "{err}");
    assert!(
        warnings[0].ends_with(
            "slice info file not read (line 1: ImagePositionPatient needs 3 numbers): the \
             contours are not checked against their image planes"
        ),
        "{err}"
    );
    assert!(mesh_lines(&dir.join("out.obj")) == want, "another mesh");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `heartmesh compare ... --json | head -1`: the reader leaves, the command ends quietly (it
/// panicked with exit 101 and a backtrace).
#[test]
fn stdout_closed_early_is_not_a_panic() {
    let truth = data("meshes/cap-atlas-mean-ED-LV_ENDO-open.obj");
    let mut child = bin()
        .args(["compare", s(&truth), s(&truth), "--json"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        e.read_to_string(&mut err).unwrap();
    }
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(0), "{err}");
    assert!(err.is_empty(), "{err}");
}

/// A biv-me GPFile to VTP / VTK polylines (the files ParaView opens) and back keeps its 23
/// landmarks (apex, valves, RV inserts as named one-point vertex cells), which were dropped.
#[test]
fn gpfile_landmarks_survive_vtp_and_vtk() {
    let dir = scratch("gpfile-landmarks");
    let gp = data("contours/bivme-example-patient1/GPFile_000.txt");
    let counts = "40 contours, 1791 points, 23 landmarks";
    for ext in ["vtp", "vtk"] {
        let lines = dir.join(format!("x.{ext}"));
        let (code, out, err) = run(bin().args(["convert", s(&gp), s(&lines)]));
        assert_eq!(code, 0, "{ext}: {err}");
        assert_eq!(out, format!("{}: {counts}\n", s(&lines)), "{ext}");
        let csv = dir.join(format!("y-{ext}.csv"));
        let (code, out, err) = run(bin().args(["convert", s(&lines), s(&csv)]));
        assert_eq!(code, 0, "{ext}: {err}");
        assert_eq!(out, format!("{}: {counts}\n", s(&csv)), "{ext}");
        let text = std::fs::read_to_string(&csv).unwrap();
        let apex = text
            .lines()
            .filter(|l| l.starts_with("# landmark APEX_POINT "));
        assert_eq!(apex.count(), 1, "{ext}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A VTP saved by VTK / ParaView with their default settings (appended raw data, zlib): made
/// from patient1-ED.csv by `convert`, read and written back by vtkXMLPolyDataWriter 9.7 (see
/// heartmesh-core/tests/data/vtk9/README.md). It converts to the CSV's contours again, joined by
/// their binary `contour_id` strings (refused as "compressed VTP is not supported" before).
#[test]
fn a_vtp_saved_by_vtk_with_default_settings_converts() {
    let dir = scratch("vtk-default-vtp");
    let vtp = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../heartmesh-core/tests/data/vtk9/patient1-ED-vtk-default.vtp");
    let counts = |input: &Path, name: &str| {
        let out = dir.join(name);
        let (code, text, err) = run(bin().args(["convert", s(input), s(&out)]));
        assert_eq!(code, 0, "{}: {err}", s(input));
        text.strip_prefix(&format!("{}: ", s(&out)))
            .unwrap_or_else(|| panic!("{text}"))
            .to_string()
    };
    let csv = counts(
        &data("contours/bivme-example-patient1/patient1-ED.csv"),
        "a.csv",
    );
    assert_eq!(csv, "40 contours, 1791 points, 0 landmarks\n");
    assert_eq!(counts(&vtp, "b.csv"), csv);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A contour file handed out in a ZIP archive (with a macOS resource fork beside it): read from
/// inside it, the mesh of the file itself.
#[test]
fn a_zipped_contour_file_gives_the_files_mesh() {
    let dir = scratch("other_tools_zip");
    let zip = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/patient1-ED.zip");
    let csv = data("contours/bivme-example-patient1/patient1-ED.csv");
    let args = ["--surface", "LV_ENDO", "--iterations", "40"];
    let (code, err, zipped) = reconstruct(&dir, &zip, &args);
    assert_eq!(code, 0, "{err}");
    let (_, _, plain) = reconstruct(&dir, &csv, &args);
    assert!(zipped.len() > 1000, "{}", zipped.len());
    assert_eq!(zipped, plain);
}
