//! The heartmesh command-line tool: reconstruct cardiac surface meshes from contours
//! (Villard, Grau & Zacur, J. Imaging 2018) and convert contour and mesh files.
//!
//! Exit status: 0 success, 2 bad input or usage (one line on stderr: `heartmesh: FILE:LINE:
//! problem`), 1 the reconstruction or writing failed.

#[macro_use]
mod stdout;
mod args;
mod cmd_align;
mod cmd_compare;
mod cmd_convert;
mod cmd_experiment;
mod cmd_experiment_plot;
mod cmd_leave_one_out;
mod cmd_reconstruct;
mod cmd_segment;
mod cmd_simulate;
mod cmd_volumes;
mod contours;
mod each_surface;
mod error;
mod files;
mod report;
mod svg;
mod svg_plot;

use error::CliError;

fn usage() -> String {
    format!(
        "heartmesh {} - surface meshes from cardiac MRI contours (Villard, Grau & Zacur 2018)\n\n\
         usage:\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  heartmesh --version | --help\n\n\
         exit status: 0 ok, 2 bad input or usage, 1 reconstruction failed",
        heartmesh_core::VERSION,
        cmd_reconstruct::USAGE,
        cmd_volumes::USAGE,
        cmd_convert::USAGE,
        cmd_simulate::USAGE,
        cmd_segment::USAGE,
        cmd_compare::USAGE,
        cmd_leave_one_out::USAGE,
        cmd_experiment::USAGE,
        cmd_align::USAGE
    )
}

fn run(argv: &[String]) -> Result<(), CliError> {
    let Some((cmd, rest)) = argv.split_first() else {
        return Err(CliError::usage("no command given"));
    };
    let wants_help = rest.iter().any(|a| a == "--help" || a == "-h");
    match cmd.as_str() {
        "--help" | "-h" | "help" => outln!("{}", usage()),
        "--version" | "-V" | "version" => outln!("heartmesh {}", heartmesh_core::VERSION),
        "reconstruct" if wants_help => outln!("usage: {}", cmd_reconstruct::USAGE),
        "convert" if wants_help => outln!("usage: {}", cmd_convert::USAGE),
        "reconstruct" => cmd_reconstruct::run(rest)?,
        "convert" => cmd_convert::run(rest)?,
        "simulate" if wants_help => outln!("usage: {}", cmd_simulate::USAGE),
        "compare" if wants_help => outln!("usage: {}", cmd_compare::USAGE),
        "leave-one-out" if wants_help => outln!("usage: {}", cmd_leave_one_out::USAGE),
        "simulate" => cmd_simulate::run(rest)?,
        "segment" if wants_help => outln!("usage: {}", cmd_segment::USAGE),
        "segment" => cmd_segment::run(rest)?,
        "compare" => cmd_compare::run(rest)?,
        "leave-one-out" => cmd_leave_one_out::run(rest)?,
        "experiment" if wants_help => outln!("usage: {}", cmd_experiment::USAGE),
        "experiment" => cmd_experiment::run(rest)?,
        "align" if wants_help => outln!("usage: {}", cmd_align::USAGE),
        "align" => cmd_align::run(rest)?,
        "volumes" if wants_help => outln!("usage: {}", cmd_volumes::USAGE),
        "volumes" => cmd_volumes::run(rest)?,
        other => return Err(CliError::usage(format!("unknown command {other:?}"))),
    }
    Ok(())
}

fn main() {
    // HEARTMESH_THREADS=1 forces one thread (same results either way; for timing and shared hosts).
    heartmesh_core::parallel::configure_from_env();
    let mut argv = Vec::new();
    for a in std::env::args_os().skip(1) {
        match a.into_string() {
            Ok(s) => argv.push(s),
            Err(raw) => {
                eprintln!("heartmesh: argument {raw:?} is not valid UTF-8 (see heartmesh --help)");
                std::process::exit(2);
            }
        }
    }
    if let Err(e) = run(&argv) {
        eprintln!("heartmesh: {}", e.message());
        std::process::exit(e.exit_code());
    }
}
