//! Standard output that a closed pipe does not turn into a panic.
//!
//! `println!` panics when stdout is gone (`heartmesh compare A B --json | head -3`: exit 101 and
//! a backtrace, after the work was done). Rust ignores SIGPIPE, so the write fails instead of
//! the process being stopped as a C tool would be; here a closed pipe ends the process quietly
//! with status 0 (the reader took what it wanted), and any other write failure (a full disk
//! under a redirect) is one line on stderr and status 1.

use std::fmt;
use std::io::{ErrorKind, Write};

/// Writes `args` to stdout (the `out!` and `outln!` macros).
pub fn write(args: fmt::Arguments) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.flush()) {
        if e.kind() == ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("heartmesh: cannot write to standard output: {e}");
        std::process::exit(1);
    }
}

/// `print!` through [`write`].
macro_rules! out {
    ($($t:tt)*) => { $crate::stdout::write(format_args!($($t)*)) };
}

/// `println!` through [`write`].
macro_rules! outln {
    () => { $crate::stdout::write(format_args!("\n")) };
    ($($t:tt)*) => { $crate::stdout::write(format_args!("{}\n", format_args!($($t)*))) };
}
