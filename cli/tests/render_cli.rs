//! `himmel render` / `himmel scene-template` from the outside: exit codes
//! and one-line errors that name the flag or field.

use std::process::Command;

fn himmel(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_himmel"))
        .args(args)
        .env("HIMMEL_CACHE_DIR", "")
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn tmp(name: &str) -> String {
    std::env::temp_dir()
        .join(format!("himmel-cli-{}-{name}", std::process::id()))
        .to_string_lossy()
        .into_owned()
}

const BASE: [&str; 6] = [
    "--time",
    "2024-06-21T19:00:00Z",
    "--lat",
    "-33.9",
    "--lon",
    "-70.6",
];

fn render(extra: &[&str]) -> (i32, String, String) {
    let mut a = vec!["render"];
    a.extend_from_slice(&BASE);
    a.extend_from_slice(extra);
    himmel(&a)
}

#[test]
fn bad_input_exits_2_naming_the_flag() {
    let out = tmp("bad.png");
    let cases: [(&[&str], &str); 6] = [
        (&["--fov", "0"], "--fov"),
        (&["--fov", "200"], "--fov"),
        (&["--width", "0"], "--width"),
        (&["--width", "100000", "--height", "100000"], "--width"),
        (&["--effects", "atmosphere,rainbow"], "rainbow"),
        (&["--exposure", "bright"], "--exposure"),
    ];
    for (extra, needle) in cases {
        let mut a: Vec<&str> = extra.to_vec();
        a.extend_from_slice(&["--output", &out]);
        let (code, _, err) = render(&a);
        assert_eq!(code, 2, "{extra:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(
            err.starts_with("error:") && err.contains(needle),
            "{extra:?}: {err}"
        );
    }
}

#[test]
fn scene_file_errors_name_the_field() {
    let out = tmp("scene.png");
    let f = tmp("unknown.json");
    std::fs::write(&f, r#"{"camera": {"fvo": 50}}"#).unwrap();
    let (code, _, err) = render(&["--scene", &f, "--output", &out]);
    assert_eq!(code, 2);
    assert!(err.contains("fvo") && err.contains("--scene"), "{err}");
    std::fs::write(&f, r#"{"camera": {"width": "wide"}}"#).unwrap();
    let (code, _, err) = render(&["--scene", &f, "--output", &out]);
    assert_eq!(code, 2);
    assert!(err.contains("invalid type"), "{err}");
    let _ = std::fs::remove_file(&f);
}

#[test]
fn template_is_a_complete_scene_and_renders_with_stats() {
    let (code, tpl, _) = himmel(&["scene-template"]);
    assert_eq!(code, 0);
    let f = tmp("tpl.json");
    // Small image via the scene file; negative numbers in separated form.
    let mut v: serde_json::Value = serde_json::from_str(&tpl).unwrap();
    v["camera"]["width"] = 96.into();
    v["camera"]["height"] = 64.into();
    v["lut"]["multiscatter_n"] = 8.into();
    std::fs::write(&f, v.to_string()).unwrap();
    let png = tmp("t.png");
    let stats = tmp("t.json");
    let (code, _, err) = render(&[
        "--scene",
        &f,
        "--effects",
        "atmosphere",
        "--projection",
        "perspective",
        "--yaw",
        "-10",
        "--pitch",
        "5",
        "--exposure",
        "-4",
        "--stats",
        &stats,
        "--output",
        &png,
    ]);
    assert_eq!(code, 0, "{err}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    assert_eq!(s["backend"], "cpu");
    assert_eq!(s["width"], 96);
    let passes = s["passes"].as_array().unwrap();
    assert_eq!(passes.len(), 7);
    for p in passes {
        let ran = p["ran"].as_bool().unwrap();
        assert_eq!(ran, p["name"] == "atmosphere");
        if !ran {
            assert!(p["reason"].as_str().is_some());
        }
    }
    assert!(std::fs::metadata(&png).unwrap().len() > 100);
    for p in [f, png, stats] {
        let _ = std::fs::remove_file(p);
    }
}

#[test]
fn wgpu_backend_is_unavailable_exit_3() {
    let (code, _, err) = render(&["--backend", "wgpu", "--output", &tmp("g.png")]);
    assert_eq!(code, 3);
    assert!(err.contains("--backend cpu"), "{err}");
}
