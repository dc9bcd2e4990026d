//! `himmel render --frames N --time-step S [--camera-path FILE]
//! [--day-fraction F]`: numbered files, one renderer, per-frame `--stats`,
//! the exposure curve of a time-lapse, apparent solar time, and errors.

use std::path::PathBuf;

use serde_json::Value;

mod common;

use common::run as himmel;

/// A fresh directory for one test's files.
fn dir(name: &str) -> PathBuf {
    common::fresh_dir("himmel-seq", name)
}

fn s(p: &std::path::Path) -> String {
    p.to_string_lossy().into_owned()
}

fn stats(p: &std::path::Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// Seconds between two RFC 3339 times of the stats (no leap second here).
fn seconds(a: &Value, b: &Value) -> f64 {
    let t = |v: &Value| {
        chrono::DateTime::parse_from_rfc3339(v.as_str().unwrap())
            .unwrap()
            .timestamp_millis() as f64
            / 1e3
    };
    t(b) - t(a)
}

const MUNICH: [&str; 4] = ["--lat", "48.14", "--lon", "11.58"];

#[test]
fn three_frames_one_renderer_luts_reused() {
    let d = dir("three");
    let (out, st) = (d.join("sky.png"), d.join("stats.json"));
    let (out_s, st_s) = (s(&out), s(&st));
    let mut a = vec!["render", "--time", "2024-06-21T18:00:00Z"];
    a.extend_from_slice(&MUNICH);
    a.extend_from_slice(&[
        "--width",
        "32",
        "--height",
        "32",
        "--frames",
        "3",
        "--time-step",
        "1800",
        "--output",
        &out_s,
        "--stats",
        &st_s,
    ]);
    let (code, _, err) = himmel(&a);
    assert_eq!(code, 0, "{err}");
    for k in 0..3 {
        assert!(d.join(format!("sky_{k:04}.png")).is_file(), "frame {k}");
    }
    assert!(!out.exists());
    let v = stats(&st);
    // The first frame's single-frame fields at the top level.
    assert_eq!(v["backend"], "cpu");
    assert_eq!(v["width"], 32);
    assert!(v["passes"].as_array().unwrap().len() >= 6);
    assert!(v["sun"]["alt_deg"].is_number());
    let seq = &v["sequence"];
    assert_eq!(seq["frames"], 3);
    assert_eq!(seq["renderers_built"], 1);
    let avg = seq["average_frame_ms"].as_f64().unwrap();
    assert!(avg > 0.0 && avg <= seq["frames_ms"].as_f64().unwrap());
    let frames = v["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 3);
    for w in frames.windows(2) {
        assert_eq!(seconds(&w[0]["time_utc"], &w[1]["time_utc"]), 1800.0);
    }
    // The LUTs were built once (by the metering pass, frame 0) and every
    // frame found them in memory.
    assert_eq!(seq["metering_lut_source"], "computed");
    for f in frames {
        assert_eq!(f["lut_source"], "memory", "{f}");
        assert!(f["passes"]
            .as_array()
            .unwrap()
            .iter()
            .any(|p| p["ms"].is_number()));
    }
    assert_eq!(v["time_utc"], frames[0]["time_utc"]);
}

/// A 24 h time-lapse, 48 frames × 1800 s, sunny summer day at 48° N: the
/// metered sky spans more than 10 EV, the exposure steps at most 0.3 EV
/// between frames, and no frame is far from its meter for long.
#[test]
fn day_long_time_lapse_has_no_exposure_jumps() {
    let d = dir("lapse");
    let (out, st) = (d.join("lapse.png"), d.join("stats.json"));
    let (out_s, st_s) = (s(&out), s(&st));
    let mut a = vec!["render", "--time", "2024-06-21T00:00:00Z"];
    a.extend_from_slice(&MUNICH);
    a.extend_from_slice(&[
        "--width",
        "16",
        "--height",
        "16",
        "--frames",
        "48",
        "--time-step",
        "1800",
        "--output",
        &out_s,
        "--stats",
        &st_s,
    ]);
    let (code, _, err) = himmel(&a);
    assert_eq!(code, 0, "{err}");
    let v = stats(&st);
    let frames = v["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 48);
    let ev: Vec<f64> = frames
        .iter()
        .map(|f| f["ev100"].as_f64().unwrap())
        .collect();
    let metered: Vec<f64> = frames
        .iter()
        .map(|f| f["ev100_metered"].as_f64().unwrap())
        .collect();
    let range = metered.iter().cloned().fold(f64::MIN, f64::max)
        - metered.iter().cloned().fold(f64::MAX, f64::min);
    assert!(range > 10.0, "metered range {range} EV");
    let raw_jump = metered
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .fold(0.0, f64::max);
    assert!(
        raw_jump > 1.0,
        "per-frame metering would jump {raw_jump} EV"
    );
    for w in ev.windows(2) {
        assert!((w[1] - w[0]).abs() <= 0.3, "{} → {}", w[0], w[1]);
    }
    // Every frame's radiance is finite (night, twilight and day alike).
    for f in frames {
        assert_eq!(f["non_finite_pixels"], 0, "{}", f["time_utc"]);
    }
    // At noon (frame 24) the exposure has reached the day's meter.
    assert!(
        (ev[24] - metered[24]).abs() < 1.0,
        "{} {}",
        ev[24],
        metered[24]
    );
}

#[test]
fn negative_speed_renders_the_same_frames_in_reverse() {
    let d = dir("reverse");
    let run = |name: &str, time: &str, speed: f64| {
        let scene = d.join(format!("{name}.json"));
        std::fs::write(
            &scene,
            format!(
                r#"{{"time": {{"utc": "{time}", "speed": {speed}}},
                    "observer": {{"lat_deg": 48.14, "lon_deg": 11.58}},
                    "camera": {{"width": 24, "height": 24}}}}"#
            ),
        )
        .unwrap();
        let out = d.join(format!("{name}.png"));
        let (code, _, err) = himmel(&[
            "render",
            "--scene",
            &s(&scene),
            "--frames",
            "4",
            "--time-step",
            "1200",
            "--output",
            &s(&out),
        ]);
        assert_eq!(code, 0, "{err}");
        (0..4)
            .map(|k| std::fs::read(d.join(format!("{name}_{k:04}.png"))).unwrap())
            .collect::<Vec<_>>()
    };
    let fwd = run("fwd", "2024-03-20T17:00:00Z", 1.0);
    let back = run("back", "2024-03-20T18:00:00Z", -1.0);
    for k in 0..4 {
        assert!(fwd[k] == back[3 - k], "frame {k}");
    }
    assert!(fwd[0] != fwd[3]);
}

#[test]
fn camera_path_moves_the_camera() {
    let d = dir("path");
    let path = d.join("path.json");
    std::fs::write(
        &path,
        r#"{"keyframes": [
            {"frame": 0, "position_m": [0, 2, 0], "look_at_m": [0, 12, -10]},
            {"frame": 2, "position_m": [4, 2, 0], "look_at_m": [4, 12, -10]}
        ]}"#,
    )
    .unwrap();
    let (out, st) = (d.join("p.png"), d.join("s.json"));
    let (out_s, st_s, path_s) = (s(&out), s(&st), s(&path));
    let mut a = vec!["render", "--time", "2024-06-21T10:00:00Z"];
    a.extend_from_slice(&MUNICH);
    a.extend_from_slice(&[
        "--width",
        "24",
        "--height",
        "16",
        "--frames",
        "3",
        "--camera-path",
        &path_s,
        "--output",
        &out_s,
        "--stats",
        &st_s,
    ]);
    let (code, _, err) = himmel(&a);
    assert_eq!(code, 0, "{err}");
    let v = stats(&st);
    let f = v["frames"].as_array().unwrap();
    assert_eq!(
        f[1]["camera"]["position_m"],
        serde_json::json!([2.0, 2.0, 0.0])
    );
    assert_eq!(
        f[2]["camera"]["look_at_m"],
        serde_json::json!([4.0, 12.0, -10.0])
    );
    // No --time-step: the sky holds still.
    assert_eq!(f[0]["time_utc"], f[2]["time_utc"]);
}

/// `--day-fraction 0.5` is the Sun's transit of `himmel riseset` (an
/// independent root search) within 1 s.
#[test]
fn half_day_fraction_is_the_transit() {
    let d = dir("noon");
    for (date, lat, lon) in [
        ("2024-11-03", "-33.9", "151.2"),
        ("2024-02-11", "32.8", "-96.8"),
    ] {
        let (code, text, err) = himmel(&[
            "riseset", "--body", "sun", "--date", date, "--lat", lat, "--lon", lon, "--format",
            "json",
        ]);
        assert_eq!(code, 0, "{err}");
        let events: Value = serde_json::from_str(&text).unwrap();
        let transit = events["events"]
            .as_array()
            .unwrap()
            .iter()
            .find(|e| e["event"] == "transit")
            .unwrap()["utc"]
            .clone();
        let st = d.join("s.json");
        let (code, _, err) = himmel(&[
            "render",
            "--time",
            &format!("{date}T12:00:00Z"),
            "--lat",
            lat,
            "--lon",
            lon,
            "--day-fraction",
            "0.5",
            "--width",
            "8",
            "--height",
            "8",
            "--effects",
            "sun",
            "--output",
            &s(&d.join("n.png")),
            "--stats",
            &s(&st),
        ]);
        assert_eq!(code, 0, "{err}");
        let dt = seconds(&stats(&st)["time_utc"], &transit);
        assert!(dt.abs() < 1.0, "{date}: {dt} s");
    }
}

#[test]
fn bad_sequence_input_exits_2_naming_the_flag_or_field() {
    let d = dir("bad");
    let out = s(&d.join("x.png"));
    let missing = s(&d.join("missing.json"));
    let bad_path = d.join("bad.json");
    std::fs::write(
        &bad_path,
        r#"{"keyframes": [{"frame": 0, "position_m": [0, 1], "look_at_m": [0, 0, 1]}]}"#,
    )
    .unwrap();
    let bad = s(&bad_path);
    let cases: [(&[&str], &[&str]); 7] = [
        (&["--frames", "0"], &["--frames"]),
        (&["--time-step", "60"], &["--time-step", "--frames"]),
        (&["--frames", "2", "--time-step", "nan"], &["--time-step"]),
        (
            &["--frames", "2", "--camera-path", &missing],
            &["--camera-path", "missing.json"],
        ),
        (
            &["--frames", "2", "--camera-path", &bad],
            &["bad.json", "keyframes[0].position_m"],
        ),
        (&["--day-fraction", "1.5"], &["--day-fraction"]),
        (
            &[
                "--frames",
                "2",
                "--camera-path",
                &bad,
                "--projection",
                "fisheye",
            ],
            &["bad.json"],
        ),
    ];
    for (extra, needles) in cases {
        let mut a = vec!["render", "--time", "2024-06-21T10:00:00Z"];
        a.extend_from_slice(&MUNICH);
        a.extend_from_slice(&["--width", "8", "--height", "8", "--output", &out]);
        a.extend_from_slice(extra);
        let (code, _, err) = himmel(&a);
        assert_eq!(code, 2, "{extra:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        for n in needles {
            assert!(
                err.starts_with("error:") && err.contains(n),
                "{extra:?}: {err}"
            );
        }
    }
}

/// The low clouds' temporal reprojection in a sequence (`clouds.low.
/// march_stride` 4, wind): `--stats` says per frame whether the coarse
/// grid came from the last frame, why not on the first, and how many
/// nodes were reused.
#[test]
fn cloud_history_is_reported_per_frame() {
    cloud_history_per_frame("cpu");
}

/// The same on the wgpu backend (its lattices kept on the GPU, the node
/// counts read back).
#[test]
fn cloud_history_is_reported_per_frame_on_wgpu() {
    cloud_history_per_frame("wgpu");
}

fn cloud_history_per_frame(backend: &str) {
    let d = dir(&format!("cloud_history_{backend}"));
    let (out, st, scene) = (
        d.join("sky.exr"),
        d.join("stats.json"),
        d.join("scene.json"),
    );
    std::fs::write(
        &scene,
        r#"{"effects": ["atmosphere", "sun", "clouds"],
            "camera": {"projection": "fisheye", "width": 48, "height": 48},
            "clouds": {"low": {"coverage": 0.5, "march_stride": 4, "wind_m_s": [15.0, 0.0]}}}"#,
    )
    .unwrap();
    let (out_s, st_s, scene_s) = (s(&out), s(&st), s(&scene));
    let mut a = vec![
        "render",
        "--backend",
        backend,
        "--time",
        "2024-06-21T08:00:00Z",
    ];
    a.extend_from_slice(&MUNICH);
    a.extend_from_slice(&[
        "--scene",
        &scene_s,
        "--frames",
        "3",
        "--time-step",
        "4",
        "--output",
        &out_s,
        "--stats",
        &st_s,
    ]);
    let (code, _, err) = himmel(&a);
    assert_eq!(code, 0, "{err}");
    let v = stats(&st);
    assert_eq!(v["backend"], backend, "{v}");
    let frames = v["frames"].as_array().unwrap();
    let h0 = &frames[0]["cloud_history"];
    assert_eq!(h0["used"], false, "{h0}");
    assert_eq!(h0["why_not"], "first frame");
    assert_eq!(h0["nodes_reused"], 0);
    for f in &frames[1..] {
        let h = &f["cloud_history"];
        assert_eq!(h["used"], true, "{h}");
        assert!(h["why_not"].is_null(), "{h}");
        assert!(h["nodes_reused"].as_u64().unwrap() > 0, "{h}");
        assert!(h["nodes_marched"].as_u64().unwrap() > 0, "{h}");
    }
    assert_eq!(v["cloud_history"], *h0);
}
