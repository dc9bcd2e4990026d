//! `himmel render` with the Moon: `--stats` reports the Moon, the eclipse
//! shading and the culling reason.

#[allow(dead_code)] // `json` is for the other CLI tests.
mod common;

use common::himmel;

fn render_stats(time: &str, lat: &str, lon: &str, extra: &[&str]) -> serde_json::Value {
    let dir = std::env::temp_dir().join(format!(
        "himmel-moon-cli-{}-{}",
        std::process::id(),
        time.replace(':', "")
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let stats = dir.join("s.json");
    let img = dir.join("m.exr");
    let mut args = vec![
        "render",
        "--time",
        time,
        "--lat",
        lat,
        "--lon",
        lon,
        "--width",
        "48",
        "--height",
        "48",
        "--stats",
        stats.to_str().unwrap(),
        "--output",
        img.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let out = himmel(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    v
}

fn pass<'a>(v: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    v["passes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == name)
        .unwrap()
}

#[test]
fn lunar_eclipse_stats() {
    // 2025-03-14 greatest eclipse; NASA (Espenak) umbral magnitude 1.178.
    let v = render_stats(
        "2025-03-14T06:58:43Z",
        "19.43",
        "-99.13",
        &[
            "--projection",
            "perspective",
            "--fov",
            "1",
            "--yaw",
            "190.657",
            "--pitch",
            "72.716",
            "--effects",
            "moon",
        ],
    );
    assert_eq!(pass(&v, "moon")["ran"], true);
    assert_eq!(pass(&v, "moon-eclipse")["ran"], true);
    let u = v["moon"]["umbral_magnitude"].as_f64().unwrap();
    assert!((u - 1.178).abs() < 0.01, "{u}");
    assert!((v["moon"]["alt_deg"].as_f64().unwrap() - 72.71).abs() < 0.1);
}

#[test]
fn moon_below_the_horizon_is_not_rendered() {
    // Munich, Moon at −9.6°.
    let v = render_stats(
        "2024-01-20T03:35:00Z",
        "48.14",
        "11.58",
        &["--effects", "moon,atmosphere"],
    );
    let m = pass(&v, "moon");
    assert_eq!(m["ran"], false);
    assert!(
        m["reason"].as_str().unwrap().contains("below the horizon"),
        "{m}"
    );
    assert!(v["moon"]["alt_deg"].as_f64().unwrap() < -9.0);
}
