//! Regressions of a user audit of the command line (session 24): outputs that cannot be written,
//! or that would overwrite an input, are refused before any work with status 2 and one line (they
//! were written after the whole run, exit 1, or silently overwrote the input); `help COMMAND`;
//! messages that read wrong; the report's `converged`; the README's volumes example.

mod common;
use common::{bin, data, run, scratch};
use std::path::Path;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Status 2, nothing on stdout, exactly `want` (one line) on stderr.
fn refused(args: &[&str], want: &str) {
    let (code, out, err) = run(bin().args(args));
    assert_eq!(code, 2, "{args:?}: {err}");
    assert!(out.is_empty(), "{args:?}: {out}");
    assert_eq!(err, format!("heartmesh: {want}\n"), "{args:?}");
}

#[test]
fn an_output_that_cannot_be_written_is_refused_before_the_run() {
    let dir = scratch("unwritable");
    let surfco = data("contours/surfco-example.csv");
    let patient = data("contours/bivme-example-patient1/patient1-ED.csv");
    let es = data("contours/bivme-example-patient1/patient1-ES.csv");
    let lv = data("meshes/bivme-patient1-ED-LV_ENDO-closed.obj");
    let nodir = dir.join("nodir");
    let missing = |name: &str| nodir.join(name).to_str().unwrap().to_string();
    let no_dir = |name: &str| {
        format!(
            "{}: cannot write: no directory {}",
            missing(name),
            s(&nodir)
        )
    };
    let mesh = dir.join("m.obj");
    // Each was exit 1 after the whole run (volumes: after every phase and surface; --surface all
    // wrote the four meshes, then failed four times on their reports).
    refused(
        &["reconstruct", s(&surfco), "-o", &missing("m.obj")],
        &no_dir("m.obj"),
    );
    refused(
        &[
            "reconstruct",
            s(&patient),
            "--surface",
            "all",
            "-o",
            s(&mesh),
            "--report",
            &missing("r.json"),
        ],
        &no_dir("r.json"),
    );
    refused(
        &[
            "reconstruct",
            s(&surfco),
            "-o",
            s(&mesh),
            "--contour-distances",
            &missing("d.csv"),
        ],
        &no_dir("d.csv"),
    );
    refused(
        &["volumes", s(&patient), s(&es), "--csv", &missing("v.csv")],
        &no_dir("v.csv"),
    );
    refused(
        &["volumes", s(&patient), s(&es), "--json", &missing("v.json")],
        &no_dir("v.json"),
    );
    refused(
        &["align", s(&patient), "-o", &missing("a.csv")],
        &no_dir("a.csv"),
    );
    refused(
        &["convert", s(&surfco), &missing("c.csv")],
        &no_dir("c.csv"),
    );
    refused(
        &["simulate", s(&lv), "-o", &missing("sim.csv")],
        &no_dir("sim.csv"),
    );
    refused(
        &["segment", "--lv-endo", s(&lv), "-o", &missing("seg.nii.gz")],
        &no_dir("seg.nii.gz"),
    );
    // Every refusal comes before any work: nothing was written (--surface all wrote its four
    // meshes before).
    assert!(!nodir.exists());
    assert!(
        std::fs::read_dir(&dir).unwrap().next().is_none(),
        "nothing written"
    );

    // A directory where a file is wanted, and a file where a directory is.
    let a_dir = dir.join("d.obj");
    std::fs::create_dir(&a_dir).unwrap();
    refused(
        &["reconstruct", s(&surfco), "-o", s(&a_dir)],
        &format!(
            "{}: cannot write: is a directory; give a file name in it",
            s(&a_dir)
        ),
    );
    let a_file = dir.join("f.csv");
    std::fs::write(&a_file, "x").unwrap();
    let inside = a_file.join("m.obj");
    refused(
        &["reconstruct", s(&surfco), "-o", s(&inside)],
        &format!(
            "{}: cannot write: {} is not a directory",
            s(&inside),
            s(&a_file)
        ),
    );
    // Was exit 1 with "cannot create directory: File exists (os error 17)".
    refused(
        &[
            "experiment",
            "sax-count",
            s(&lv),
            "-o",
            s(&a_file),
            "--from",
            "3",
            "--to",
            "3",
            "--iterations",
            "5",
        ],
        &format!("{}: is a file, not a directory", s(&a_file)),
    );
    refused(
        &["volumes", s(&patient), s(&es), "--meshes", s(&a_file)],
        &format!("{}: is a file, not a directory", s(&a_file)),
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_output_that_would_overwrite_an_input_or_another_output_is_refused() {
    let dir = scratch("same-file");
    let original = std::fs::read(data("contours/surfco-example.csv")).unwrap();
    let input = dir.join("s.csv");
    std::fs::write(&input, &original).unwrap();
    let dotted = dir.join(".").join("s.csv");
    let mesh = dir.join("m.obj");
    let overwrite = |option: &str, out: &Path| {
        format!(
            "{}: {option} would overwrite the input file {}; give another output name",
            s(out),
            s(&input)
        )
    };
    // align and convert rewrote the file in canonical form; --contour-distances replaced the
    // contours with distances; --report overwrote the mesh just written.
    refused(
        &["align", s(&input), "-o", s(&input)],
        &overwrite("-o", &input),
    );
    refused(
        &["convert", s(&input), s(&dotted)],
        &overwrite("OUT", &dotted),
    );
    refused(
        &[
            "reconstruct",
            s(&input),
            "-o",
            s(&mesh),
            "--contour-distances",
            s(&input),
        ],
        &overwrite("--contour-distances", &input),
    );
    refused(
        &[
            "reconstruct",
            s(&input),
            "-o",
            s(&mesh),
            "--report",
            s(&mesh),
        ],
        &format!(
            "{}: given as both -o and --report; give each output its own file",
            s(&mesh)
        ),
    );
    let v = dir.join("v.csv");
    refused(
        &["volumes", s(&input), "--csv", s(&v), "--json", s(&v)],
        &format!(
            "{}: given as both --csv and --json; give each output its own file",
            s(&v)
        ),
    );
    assert_eq!(std::fs::read(&input).unwrap(), original, "input untouched");
    assert!(!mesh.exists() && !v.exists());
    // A mesh converted onto itself, through a link of its directory.
    let obj = dir.join("a.obj");
    std::fs::write(
        &obj,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n",
    )
    .unwrap();
    #[cfg(unix)]
    {
        let link = dir.join("link");
        std::os::unix::fs::symlink(&dir, &link).unwrap();
        let via = link.join("a.obj");
        let (code, _, err) = run(bin().args(["convert", s(&obj), s(&via)]));
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("OUT would overwrite the input file"), "{err}");
    }
    // Distinct names still work.
    let (code, out, err) = run(bin().args(["convert", s(&obj), s(&dir.join("b.stl"))]));
    assert_eq!((code, err.as_str()), (0, ""));
    assert!(out.contains("4 vertices, 4 triangles"), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn help_command_prints_that_commands_usage() {
    for cmd in [
        "reconstruct",
        "volumes",
        "convert",
        "simulate",
        "segment",
        "compare",
        "leave-one-out",
        "experiment",
        "align",
    ] {
        let (code, out, err) = run(bin().args(["help", cmd]));
        assert_eq!((code, err.as_str()), (0, ""), "{cmd}");
        assert!(
            out.starts_with(&format!("usage: heartmesh {cmd} ")),
            "{cmd}: {out}"
        );
        let (_, same, _) = run(bin().args([cmd, "--help"]));
        assert_eq!(out, same, "{cmd}");
    }
    let (_, all, _) = run(bin().arg("--help"));
    assert!(
        all.contains("heartmesh --version | --help | help COMMAND"),
        "{all}"
    );
    refused(
        &["help", "reconstrut"],
        "unknown command \"reconstrut\" (see heartmesh --help)",
    );
}

#[test]
fn messages_name_the_problem_in_plain_words() {
    let surfco = data("contours/surfco-example.csv");
    let lv = data("meshes/bivme-patient1-ED-LV_ENDO-closed.obj");
    let folder = data("contours/bivme-example-patient1");
    // Was "surface RV_ENDO not found; available: " (an empty list).
    refused(
        &[
            "reconstruct",
            s(&surfco),
            "-o",
            "never.obj",
            "--surface",
            "RV_ENDO",
        ],
        &format!(
            "{}: surface \"RV_ENDO\" not found: the file names no surfaces (no surface column: \
             it is one surface; leave out --surface)",
            s(&surfco)
        ),
    );
    // A biv-me patient folder: the files to give instead.
    let g = |n: &str| folder.join(n).to_str().unwrap().to_string();
    refused(
        &["volumes", s(&folder)],
        &format!(
            "{}: is a directory, not a file (give the contour files in it, e.g. {} {} {}, ...)",
            s(&folder),
            g("GPFile_000.txt"),
            g("GPFile_009.txt"),
            g("patient1-ED.csv")
        ),
    );
    refused(
        &["reconstruct", "", "-o", "never.obj"],
        "\"\": empty file name",
    );
    // Was "got 1 file names"; "population" was missing from the kinds.
    refused(
        &["compare", s(&lv)],
        "compare needs TRUTH and MESH, got 1 file name (see heartmesh --help)",
    );
    refused(
        &["experiment"],
        "experiment needs a kind: sax-count, lax-count, misalignment, sweep or population \
         (see heartmesh --help)",
    );
    // Was "unknown command \"--iterations\"".
    refused(
        &[
            "--iterations",
            "5",
            "reconstruct",
            s(&surfco),
            "-o",
            "never.obj",
        ],
        "--iterations before the command: the command comes first, its options after it \
         (heartmesh reconstruct CONTOURS -o MESH.obj --iterations ...) (see heartmesh --help)",
    );
    // simulate wrote CSV into x.obj.
    refused(
        &["simulate", s(&lv), "-o", "x.obj"],
        "simulate writes canonical CSV: x.obj should end in .csv (see heartmesh --help)",
    );
    assert!(!Path::new("x.obj").exists());
}

#[test]
fn the_report_says_when_the_stop_rule_ended_the_run() {
    let dir = scratch("converged");
    let surfco = data("contours/surfco-example.csv");
    let report = dir.join("r.json");
    let mesh = dir.join("m.obj");
    let reconstruct = |more: &[&str]| -> serde_json::Value {
        let (code, _, err) = run(bin()
            .args([
                "reconstruct",
                s(&surfco),
                "-o",
                s(&mesh),
                "--report",
                s(&report),
            ])
            .args(more));
        assert_eq!(code, 0, "{more:?}: {err}");
        serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap()
    };
    let r = reconstruct(&[]);
    // SurFCo meets the stop threshold at iteration 240 of 250 and settles until 244 (44 steps
    // after its last remesh, at 200).
    assert_eq!(r["converged"], true, "{r}");
    let it = r["iterations"].as_u64().unwrap();
    assert_eq!(it, 244, "{r}");
    assert_eq!(r["parameters"]["iterations"], 250.0);
    let r = reconstruct(&["--iterations", "30"]);
    assert_eq!(
        (r["iterations"].as_u64(), &r["converged"]),
        (Some(30), &serde_json::json!(false))
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The README's `heartmesh volumes patient1-ED.csv patient1-ES.csv`, run as written from the
/// patient's folder, prints what the README shows.
#[test]
fn the_readme_volumes_example_prints_as_shown() {
    let folder = data("contours/bivme-example-patient1");
    let (code, out, err) =
        run(bin()
            .current_dir(&folder)
            .args(["volumes", "patient1-ED.csv", "patient1-ES.csv"]));
    assert_eq!(code, 0, "{err}");
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../README.md"))
            .unwrap();
    let shown = readme
        .split("$ heartmesh volumes patient1-ED.csv patient1-ES.csv\n")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .expect("the README's volumes example");
    assert_eq!(out, shown);
}
