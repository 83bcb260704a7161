//! `heartmesh align CONTOURS -o ALIGNED.csv [--report R.json]`: breath-hold slice alignment on
//! its own (`heartmesh_core::contours::align`), writing the shifted contours in the canonical CSV
//! so that they can be inspected or reconstructed by any tool.

use heartmesh_core::contours::align::align_slices;
use heartmesh_core::io;

use crate::args::{parse, Spec};
use crate::contours;
use crate::error::CliError;
use crate::files;

pub const USAGE: &str =
    "heartmesh align CONTOURS [VIEWS...] -o ALIGNED.csv [--report REPORT.json] [--frame N|LABEL] [--quiet]
  Shifts every short-axis slice and long-axis view (all surfaces of an image together) in its
  own plane until the curves meet where the planes cross (breath-hold misalignment), and writes
  the shifted contours as canonical CSV (same columns). REPORT.json: the shifts per slice/view
  (mm), the rounds and the mean crossing residual before and after.";

pub fn run(args: &[String]) -> Result<(), CliError> {
    let p = parse(
        args,
        &Spec {
            with_value: &["output", "report", "frame"],
            switches: &["quiet"],
            aliases: &[("-o", "output"), ("-q", "quiet")],
        },
    )?;
    if p.positional.is_empty() {
        return Err(CliError::usage("align needs a contour file"));
    }
    let output = p
        .value("output")
        .ok_or_else(|| CliError::usage("align needs -o ALIGNED.csv"))?;
    if io::extension(output) != "csv" {
        return Err(CliError::usage(format!(
            "align writes canonical CSV: {output} should end in .csv"
        )));
    }
    let frame = contours::frame_flag(p.value("frame"))?;
    files::check_output(output)?;
    let mut outputs = vec![("-o", output)];
    if let Some(report) = p.value("report") {
        files::check_output(report)?;
        outputs.push(("--report", report));
    }
    let inputs: Vec<&str> = p.positional.iter().map(String::as_str).collect();
    files::check_distinct(&inputs, &outputs)?;
    let (input, loaded) = contours::load_all(&p.positional, frame)?;
    let (aligned, alignment) = align_slices(&loaded.set);
    let csv = io::csv::write_csv(&aligned, None)
        .map_err(|e| CliError::Failed(format!("{output}: {e}")))?;
    files::write(output, &csv)?;
    if let Some(path) = p.value("report") {
        // The frame read, as in reconstruct's report: an alignment of one phase names it.
        let mut value = serde_json::to_value(&alignment)
            .map_err(|e| CliError::Failed(format!("{path}: {e}")))?;
        if let Some(m) = value.as_object_mut() {
            m.insert(
                "frame".into(),
                crate::report::frame_read(loaded.set.time_frames.as_ref()),
            );
        }
        let text = serde_json::to_string_pretty(&value)
            .map_err(|e| CliError::Failed(format!("{path}: {e}")))?;
        files::write(path, format!("{text}\n").as_bytes())?;
    }
    if !p.switch("quiet") {
        for w in &loaded.set.warnings {
            eprintln!("{}", contours::warning_line(input, w));
        }
        let moved = alignment
            .groups
            .iter()
            .filter(|g| g.shift_mm.iter().any(|c| *c != 0.0))
            .count();
        let mut line = format!(
            "{output}: {moved} of {} slices/views shifted (largest {:.2} mm), crossing residual {:.3} -> {:.3} mm in {} rounds",
            alignment.groups.len(),
            alignment.max_shift_mm(),
            alignment.residual_before_mm,
            alignment.residual_after_mm,
            alignment.rounds
        );
        if let Some(note) = &alignment.note {
            line.push_str(&format!(" ({note})"));
        }
        outln!("{line}");
    }
    Ok(())
}
