//! Helpers shared by the command-line integration tests.

use std::path::PathBuf;
use std::process::{Command, Output};

/// Runs the `himmel` binary with `args`.
#[allow(dead_code)]
pub fn himmel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_himmel"))
        .args(args)
        .output()
        .expect("run himmel")
}

/// The JSON document on stdout of a successful run.
#[allow(dead_code)]
pub fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

/// Runs `himmel` with `args`, without the LUT disk cache and with the
/// device-selection layer off (lavapipe): exit code, stdout, stderr.
#[allow(dead_code)]
pub fn run(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_himmel"))
        .args(args)
        .env("HIMMEL_CACHE_DIR", "")
        .env("NODEVICE_SELECT", "1")
        .output()
        .expect("run himmel");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A fresh, empty folder for one test's files (`prefix`, the process and
/// `name` make it unique).
#[allow(dead_code)]
pub fn fresh_dir(prefix: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("{prefix}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create a test folder");
    d
}

/// A file path in the temporary folder, unique to this process.
#[allow(dead_code)]
pub fn tmp_path(prefix: &str, name: &str) -> String {
    std::env::temp_dir()
        .join(format!("{prefix}-{}-{name}", std::process::id()))
        .to_string_lossy()
        .into_owned()
}
