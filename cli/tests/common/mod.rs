//! Helpers shared by the command-line integration tests.

use std::process::{Command, Output};

/// Runs the `himmel` binary with `args`.
pub fn himmel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_himmel"))
        .args(args)
        .output()
        .expect("run himmel")
}

/// The JSON document on stdout of a successful run.
pub fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}
