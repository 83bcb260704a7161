//! The heartmesh command-line tool: reconstruct cardiac surface meshes from contours
//! (Villard, Grau & Zacur, J. Imaging 2018) and convert contour and mesh files.
//!
//! Exit status: 0 success, 2 bad input or usage (one line on stderr: `heartmesh: FILE:LINE:
//! problem`; outputs that cannot be written, or would overwrite an input, are refused so before
//! any work), 1 the reconstruction or writing failed.

// No unwrap/expect outside tests: a panic on user data would kill the CLI run or the app's
// worker, so every fallible step returns a typed error (`clippy -D warnings` in CI enforces this;
// tests may unwrap).
#![cfg_attr(not(test), deny(clippy::unwrap_used, clippy::expect_used))]

#[macro_use]
mod stdout;
mod anatomical_out;
mod anatomical_study_out;
mod args;
mod cmd_align;
mod cmd_compare;
mod cmd_convert;
mod cmd_experiment;
mod cmd_experiment_plot;
mod cmd_info;
mod cmd_leave_one_out;
mod cmd_myocardium;
mod cmd_reconstruct;
mod cmd_segment;
mod cmd_simulate;
mod cmd_volumes;
mod contours;
mod each_surface;
mod error;
mod files;
mod hex_out;
mod hex_study_out;
mod info_volume;
mod report;
mod svg;
mod svg_plot;
mod volume_plot;

use error::CliError;

fn usage() -> String {
    format!(
        "heartmesh {} - surface meshes from cardiac MRI contours (Villard, Grau & Zacur 2018)\n\n\
         usage:\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  {}\n\n  heartmesh --version | --help | help COMMAND\n\n\
         exit status: 0 ok, 2 bad input or usage (an output that cannot be written or would\n\
         overwrite an input is found before any work), 1 reconstruction or writing failed",
        heartmesh_core::VERSION,
        cmd_reconstruct::USAGE,
        cmd_info::USAGE,
        cmd_volumes::USAGE,
        cmd_myocardium::USAGE,
        cmd_convert::USAGE,
        cmd_simulate::USAGE,
        cmd_segment::USAGE,
        cmd_compare::USAGE,
        cmd_leave_one_out::USAGE,
        cmd_experiment::USAGE,
        cmd_align::USAGE
    )
}

/// The usage of one command (`heartmesh help COMMAND`, `heartmesh COMMAND --help`).
fn command_usage(cmd: &str) -> Option<&'static str> {
    Some(match cmd {
        "reconstruct" => cmd_reconstruct::USAGE,
        "info" => cmd_info::USAGE,
        "volumes" => cmd_volumes::USAGE,
        "myocardium" => cmd_myocardium::USAGE,
        "convert" => cmd_convert::USAGE,
        "simulate" => cmd_simulate::USAGE,
        "segment" => cmd_segment::USAGE,
        "compare" => cmd_compare::USAGE,
        "leave-one-out" => cmd_leave_one_out::USAGE,
        "experiment" => cmd_experiment::USAGE,
        "align" => cmd_align::USAGE,
        _ => return None,
    })
}

fn run(argv: &[String]) -> Result<(), CliError> {
    let Some((cmd, rest)) = argv.split_first() else {
        return Err(CliError::usage("no command given"));
    };
    let wants_help = rest.iter().any(|a| a == "--help" || a == "-h");
    match cmd.as_str() {
        // `heartmesh help reconstruct`, as git and cargo take it.
        "help" if !rest.is_empty() => {
            let [topic] = rest else {
                return Err(CliError::usage("help takes one command name"));
            };
            let text = command_usage(topic)
                .ok_or_else(|| CliError::usage(format!("unknown command {topic:?}")))?;
            outln!("usage: {text}");
        }
        "--help" | "-h" | "help" => outln!("{}", usage()),
        "--version" | "-V" | "version" => outln!("heartmesh {}", heartmesh_core::VERSION),
        other if wants_help && command_usage(other).is_some() => {
            outln!("usage: {}", command_usage(other).unwrap_or_default())
        }
        "reconstruct" => cmd_reconstruct::run(rest)?,
        "convert" => cmd_convert::run(rest)?,
        "simulate" => cmd_simulate::run(rest)?,
        "segment" => cmd_segment::run(rest)?,
        "compare" => cmd_compare::run(rest)?,
        "leave-one-out" => cmd_leave_one_out::run(rest)?,
        "experiment" => cmd_experiment::run(rest)?,
        "align" => cmd_align::run(rest)?,
        "volumes" => cmd_volumes::run(rest)?,
        "myocardium" => cmd_myocardium::run(rest)?,
        "info" => cmd_info::run(rest)?,
        // `heartmesh --iterations 5 reconstruct ...`: an option where the command goes.
        other if other.starts_with('-') => {
            return Err(CliError::usage(format!(
                "{other} before the command: the command comes first, its options after it \
                 (heartmesh reconstruct CONTOURS -o MESH.obj {other} ...)"
            )))
        }
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
