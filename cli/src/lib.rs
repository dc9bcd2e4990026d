//! The library part of the `himmel` command line: the parsers of its text
//! inputs (times and dates, `--batch` lines, observer ranges), free of
//! `clap` so that the fuzz harness (`fuzz/`) and the tests call them as the
//! binary does.

pub mod inputs;
pub mod timearg;
