//! Printing that never panics: `std`'s `println!` panics when its stream is
//! gone (a pager or `head` that quit, a closed terminal), which cost a run
//! its results. These macros print the same and ignore a stream that is
//! gone, so the run goes on quietly and writes its files.

use std::io::Write as _;

/// Writes to stdout, ignoring a closed stream.
pub(super) fn stdout(args: std::fmt::Arguments<'_>) {
    let mut out = std::io::stdout().lock();
    let _ = out.write_fmt(args).and_then(|()| out.flush());
}

/// Writes to stderr, ignoring a closed stream.
pub(super) fn stderr(args: std::fmt::Arguments<'_>) {
    let _ = std::io::stderr().lock().write_fmt(args);
}

/// `print!` that ignores a closed stdout.
macro_rules! out {
    ($($arg:tt)*) => { $crate::cli::say::stdout(format_args!($($arg)*)) };
}

/// `println!` that ignores a closed stdout.
macro_rules! outln {
    () => { $crate::cli::say::stdout(format_args!("\n")) };
    ($($arg:tt)*) => { $crate::cli::say::stdout(format_args!("{}\n", format_args!($($arg)*))) };
}

/// `eprintln!` that ignores a closed stderr.
macro_rules! errln {
    ($($arg:tt)*) => { $crate::cli::say::stderr(format_args!("{}\n", format_args!($($arg)*))) };
}
