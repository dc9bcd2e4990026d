//! No silent loss of output: every file `himmel render` writes (the image,
//! `--stats`, the LUT cache) is written through a synced temporary renamed
//! into place, or directly (and checked) onto a device; every failure exits
//! 1 with one line `error: FLAG FILE: …` and leaves neither a half-written
//! file under the target name nor a temporary.

use std::path::{Path, PathBuf};
use std::process::Command;

const BASE: [&str; 8] = [
    "render",
    "--time",
    "2024-06-21T19:00:00Z",
    "--lat",
    "10",
    "--lon",
    "10",
    "--exposure=0",
];

fn run(cmd: Command) -> (i32, String) {
    let mut cmd = cmd;
    let out = cmd.output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn himmel(size: u32, extra: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_himmel"));
    let s = size.to_string();
    c.args(BASE)
        .args(["--width", &s, "--height", &s])
        .args(extra)
        .env("HIMMEL_CACHE_DIR", "");
    if !extra.contains(&"--effects") {
        // The Sun alone renders in milliseconds.
        c.args(["--effects", "sun"]);
    }
    c
}

fn render(size: u32, extra: &[&str]) -> (i32, String) {
    run(himmel(size, extra))
}

/// A fresh, empty scratch directory for one test.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("himmel-out-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Exit 1 with one line `error: FLAG FILE: …`.
fn assert_write_error(what: &str, (code, err): (i32, String), flag: &str, file: &str) {
    assert_eq!(code, 1, "{what}: {err}");
    assert_eq!(err.trim().lines().count(), 1, "{what}: {err}");
    assert!(
        err.starts_with(&format!("error: {flag} {file}: ")),
        "{what}: {err}"
    );
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[cfg(unix)]
#[test]
fn images_and_stats_onto_a_full_device_exit_1_naming_the_file() {
    if !Path::new("/dev/full").exists() {
        eprintln!("no /dev/full here; skipped");
        return;
    }
    let d = scratch("full");
    for size in [8, 256] {
        for ext in ["png", "exr"] {
            let link = d.join(format!("full-{size}.{ext}"));
            std::os::unix::fs::symlink("/dev/full", &link).unwrap();
            let r = render(size, &["--output", s(&link)]);
            assert_write_error(&format!("{size} px {ext}"), r.clone(), "--output", s(&link));
            assert!(r.1.contains("No space left on device"), "{}", r.1);
        }
        let png = d.join(format!("ok-{size}.png"));
        // --stats directly onto the device, and through a link.
        let r = render(size, &["--output", s(&png), "--stats", "/dev/full"]);
        assert_write_error("--stats /dev/full", r, "--stats", "/dev/full");
        let link = d.join(format!("full-{size}.json"));
        std::os::unix::fs::symlink("/dev/full", &link).unwrap();
        let r = render(size, &["--output", s(&png), "--stats", s(&link)]);
        assert_write_error("--stats link", r, "--stats", s(&link));
    }
    // The links are still links, and nothing else was left behind.
    for n in names(&d) {
        let m = std::fs::symlink_metadata(d.join(&n)).unwrap();
        assert!(
            m.file_type().is_symlink() || n.starts_with("ok-"),
            "left behind: {n}"
        );
    }
    std::fs::remove_dir_all(d).unwrap();
}

#[test]
fn a_successful_render_leaves_no_temporary_files() {
    let d = scratch("clean");
    let cache = d.join("cache");
    let scene = d.join("scene.json");
    // Small LUTs so that the atmosphere's cache file is written quickly.
    std::fs::write(
        &scene,
        r#"{"lut": {"transmittance_w": 32, "transmittance_h": 16, "multiscatter_n": 8,
                     "multiscatter_dirs": 16, "sky_view_w": 32, "sky_view_h": 16}}"#,
    )
    .unwrap();
    for out in ["a.png", "a.exr"] {
        for _ in 0..2 {
            // The second run replaces the files.
            let mut c = himmel(
                32,
                &[
                    "--scene",
                    s(&scene),
                    "--effects",
                    "atmosphere,sun",
                    "--stats",
                    s(&d.join("stats.json")),
                    "--output",
                    s(&d.join(out)),
                ],
            );
            c.env("HIMMEL_CACHE_DIR", &cache);
            let (code, err) = run(c);
            assert_eq!(code, 0, "{err}");
        }
    }
    assert_eq!(
        names(&d),
        ["a.exr", "a.png", "cache", "scene.json", "stats.json"]
    );
    let cached = names(&cache);
    assert_eq!(cached.len(), 1, "{cached:?}");
    assert!(
        cached[0].starts_with("atmosphere-") && cached[0].ends_with(".bin"),
        "{cached:?}"
    );
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("stats.json")).unwrap()).unwrap();
    assert_eq!(stats["width"], 32);
    assert!(std::fs::read(d.join("a.png"))
        .unwrap()
        .starts_with(b"\x89PNG"));
    std::fs::remove_dir_all(d).unwrap();
}

#[cfg(unix)]
#[test]
fn a_link_to_a_regular_file_is_followed_and_kept() {
    let d = scratch("link");
    std::fs::write(d.join("real.png"), b"old").unwrap();
    std::os::unix::fs::symlink("real.png", d.join("link.png")).unwrap();
    let (code, err) = render(8, &["--output", s(&d.join("link.png"))]);
    assert_eq!(code, 0, "{err}");
    let m = std::fs::symlink_metadata(d.join("link.png")).unwrap();
    assert!(m.file_type().is_symlink());
    assert!(std::fs::read(d.join("real.png"))
        .unwrap()
        .starts_with(b"\x89PNG"));
    assert_eq!(names(&d), ["link.png", "real.png"]);
    std::fs::remove_dir_all(d).unwrap();
}

/// A write that fails half-way into a regular file (the file-size limit:
/// `write` fails with EFBIG) leaves the old file and no temporary.
#[cfg(target_os = "linux")]
#[test]
fn a_write_failing_half_way_keeps_the_old_file() {
    let d = scratch("efbig");
    for (flag, file) in [("--output", "a.exr"), ("--stats", "stats.json")] {
        let target = d.join(file);
        std::fs::write(&target, b"old").unwrap();
        let ok_png = d.join("ok.png");
        // Ignore SIGXFSZ so that the write fails instead of killing; limit
        // files to 1 KiB: a 256² EXR is 786 KiB, the stats about 2 KiB
        // (beside an 8² PNG of 139 bytes).
        let args = if flag == "--output" {
            vec!["--width", "256", "--height", "256", "--output", s(&target)]
        } else {
            vec![
                "--width",
                "8",
                "--height",
                "8",
                "--output",
                s(&ok_png),
                "--stats",
                s(&target),
            ]
        };
        let mut c = Command::new("sh");
        c.arg("-c")
            .arg(r#"trap "" XFSZ; ulimit -f 1; exec "$@""#)
            .arg("sh")
            .arg(env!("CARGO_BIN_EXE_himmel"))
            .args(BASE)
            .args(["--effects", "sun"])
            .args(&args)
            .env("HIMMEL_CACHE_DIR", "");
        let r = run(c);
        assert_write_error(flag, r.clone(), flag, s(&target));
        assert!(r.1.contains("too large"), "{}", r.1);
        let now = std::fs::read(&target).unwrap();
        assert!(
            now == b"old",
            "{flag}: the target changed ({} bytes)",
            now.len()
        );
        let left: Vec<String> = names(&d)
            .into_iter()
            .filter(|n| n.ends_with(".tmp"))
            .collect();
        assert!(left.is_empty(), "temporaries left: {left:?}");
    }
    std::fs::remove_dir_all(d).unwrap();
}

#[test]
fn an_unwritable_directory_exits_1() {
    let d = scratch("unwritable");
    let missing = d.join("missing/a.png");
    let r = render(8, &["--output", s(&missing)]);
    assert_write_error("missing directory", r, "--output", s(&missing));
    // A "directory" that is a regular file.
    std::fs::write(d.join("file"), b"x").unwrap();
    let under_file = d.join("file/a.exr");
    let r = render(8, &["--output", s(&under_file)]);
    assert_write_error("under a file", r, "--output", s(&under_file));
    let stats = d.join("missing/s.json");
    let png = d.join("ok.png");
    let r = render(8, &["--output", s(&png), "--stats", s(&stats)]);
    assert_write_error("--stats in a missing directory", r, "--stats", s(&stats));
    // The target is a directory.
    std::fs::create_dir(d.join("dir.png")).unwrap();
    let r = render(8, &["--output", s(&d.join("dir.png"))]);
    assert_write_error("a directory", r, "--output", s(&d.join("dir.png")));
    #[cfg(target_os = "linux")]
    {
        // No one may create files in /proc.
        let r = render(8, &["--output", "/proc/himmel-test.png"]);
        assert_write_error("/proc", r, "--output", "/proc/himmel-test.png");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let ro = d.join("ro");
        std::fs::create_dir(&ro).unwrap();
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
        // Root writes anyway: then there is nothing to test here.
        let probe = ro.join("probe");
        if std::fs::write(&probe, b"x").is_ok() {
            std::fs::remove_file(&probe).unwrap();
            eprintln!("a read-only directory is writable here (root); that case skipped");
        } else {
            let target = ro.join("a.png");
            let r = render(8, &["--output", s(&target)]);
            assert_write_error("read-only directory", r, "--output", s(&target));
            assert!(names(&ro).is_empty());
        }
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    std::fs::remove_dir_all(d).unwrap();
}
