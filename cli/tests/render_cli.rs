//! `himmel render` / `himmel scene-template` from the outside: exit codes
//! and one-line errors that name the flag or field.

use std::process::Command;

mod common;

use common::run as himmel;

fn tmp(name: &str) -> String {
    common::tmp_path("himmel-cli", name)
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
    assert!(
        err.starts_with(&format!(
            "error: --scene {f}: camera.width: expected a whole number"
        )) && err.contains("found a string"),
        "{err}"
    );
    // A wrong type deep in the file, an overflow, a negative size, a
    // value out of range, a document that is no object: exit 2, one line
    // naming the field path.
    for (text, needle) in [
        (
            r#"{"observer": {"lat_deg": "not-a-number"}}"#,
            "observer.lat_deg: expected a number, found a string",
        ),
        (
            r#"{"atmosphere": {"ozone_du": 1e999}}"#,
            "atmosphere.ozone_du: ",
        ),
        (r#"{"lut": {"sky_view_w": -1}}"#, "lut.sky_view_w: "),
        (
            r#"{"lut": {"forward_peak_deg": -50}}"#,
            "lut.forward_peak_deg: ",
        ),
        (r#"{"effects": ["sun", 3]}"#, "effects[1]: "),
        ("[]", "a scene must be a JSON object"),
    ] {
        std::fs::write(&f, text).unwrap();
        let (code, _, err) = render(&["--scene", &f, "--output", &out]);
        assert_eq!(code, 2, "{text}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(
            err.starts_with("error:") && err.contains(needle),
            "{text}: {err}"
        );
    }
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
    assert_eq!(passes.len(), himmel_skymodel::Effect::ALL.len());
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

/// `render` with `WGPU_BACKEND` set (an absent backend: no adapter).
fn render_env(backend_env: &str, extra: &[&str]) -> (i32, String, String) {
    let mut a = vec!["render"];
    a.extend_from_slice(&BASE);
    a.extend_from_slice(extra);
    let out = Command::new(env!("CARGO_BIN_EXE_himmel"))
        .args(&a)
        .env("HIMMEL_CACHE_DIR", "")
        .env("WGPU_BACKEND", backend_env)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// DX12 exists only on Windows, Metal only on Apple systems.
const ABSENT: &str = if cfg!(windows) { "metal" } else { "dx12" };

#[test]
fn wgpu_without_adapter_exits_3_and_auto_falls_back() {
    let png = tmp("g.png");
    let small = ["--width", "32", "--height", "32", "--output", &png];
    let mut a = vec!["--backend", "wgpu"];
    a.extend_from_slice(&small);
    let (code, _, err) = render_env(ABSENT, &a);
    assert_eq!(code, 3, "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: --backend wgpu: no wgpu adapter"),
        "{err}"
    );
    assert!(err.contains("--backend cpu"), "{err}");
    let stats = tmp("auto.json");
    let mut a = vec!["--backend", "auto", "--stats", &stats];
    a.extend_from_slice(&small);
    let (code, _, err) = render_env(ABSENT, &a);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("note:") && err.contains("--backend cpu"),
        "{err}"
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    assert_eq!(s["backend"], "cpu");
    for p in [png, stats] {
        let _ = std::fs::remove_file(p);
    }
}

/// A frame wider than any adapter's textures (40 000 px): `wgpu` exits 3,
/// `auto` falls back to the CPU with a note.
#[test]
fn frame_beyond_the_adapter_limits_exits_3_or_falls_back() {
    let png = tmp("wide.png");
    let wide = [
        "--width",
        "40000",
        "--height",
        "8",
        "--effects",
        "atmosphere",
    ];
    let mut a = vec!["--backend", "wgpu", "--output", &png];
    a.extend_from_slice(&wide);
    let (code, _, err) = render(&a);
    assert_eq!(code, 3, "{err}");
    assert!(
        err.starts_with("error: --backend wgpu:") && err.contains("limits"),
        "{err}"
    );
    assert!(err.contains("--backend cpu"), "{err}");
    let mut a = vec!["--backend", "auto", "--output", &png];
    a.extend_from_slice(&wide);
    let (code, _, err) = render(&a);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("note:") && err.contains("limits"), "{err}");
    let _ = std::fs::remove_file(png);
}

#[test]
fn wgpu_backend_renders_with_per_pass_times() {
    let png = tmp("w.png");
    let stats = tmp("w.json");
    let (code, _, err) = render(&[
        "--backend",
        "wgpu",
        "--width",
        "64",
        "--height",
        "64",
        "--effects",
        "atmosphere,sun",
        "--stats",
        &stats,
        "--output",
        &png,
    ]);
    assert_eq!(code, 0, "{err}");
    // Nothing on stderr (no driver noise either).
    assert!(err.trim().is_empty(), "{err}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    assert_eq!(s["backend"], "wgpu");
    let timing = s["timing"].as_str().unwrap();
    assert!(timing == "gpu-timestamps" || timing == "cpu", "{timing}");
    let passes = s["passes"].as_array().unwrap();
    assert_eq!(passes.len(), himmel_skymodel::Effect::ALL.len());
    for p in passes {
        if p["ran"].as_bool().unwrap() {
            assert!(p["ms"].as_f64().unwrap() >= 0.0, "{p}");
        }
    }
    assert!(passes
        .iter()
        .any(|p| p["name"] == "atmosphere" && p["ran"] == true));
    // The process's time splits into the renderer's creation (device and
    // shaders), the frame (with read-back) and the image write.
    let part = |k: &str| s[k].as_f64().unwrap_or_else(|| panic!("{k}: {s}"));
    let (init, render, write) = (part("init_ms"), part("render_ms"), part("write_ms"));
    assert!(init > 0.0 && render > 0.0, "{s}");
    assert!(init + render + write <= part("total_ms"), "{s}");
    assert!(std::fs::metadata(&png).unwrap().len() > 100);
    for p in [png, stats] {
        let _ = std::fs::remove_file(p);
    }
}

#[test]
fn sun_disk_in_equirect_exr_matches_ephemeris_and_solar_illuminance() {
    let exr = tmp("sun.exr");
    let t = "2024-03-20T15:00:00Z";
    let (code, _, err) = himmel(&[
        "render",
        "--time",
        t,
        "--lat",
        "-33.9",
        "--lon",
        "-70.6",
        "--projection",
        "equirect",
        "--width",
        "2048",
        "--height",
        "1024",
        "--effects",
        "sun",
        "--output",
        &exr,
    ]);
    assert_eq!(code, 0, "{err}");
    let (w, h, px) = himmel_cpu::output::read_exr(std::path::Path::new(&exr)).unwrap();
    let _ = std::fs::remove_file(&exr);
    let (wf, hf) = (w as f64, h as f64);
    let (mut e, mut cx, mut cy) = (0.0f64, 0.0f64, 0.0f64);
    for (i, p) in px.iter().enumerate() {
        let y = (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) as f64;
        if y <= 0.0 {
            continue;
        }
        let (x, row) = ((i % w) as f64, (i / w) as f64);
        let top = std::f64::consts::FRAC_PI_2 - std::f64::consts::PI * row / hf;
        let bot = std::f64::consts::FRAC_PI_2 - std::f64::consts::PI * (row + 1.0) / hf;
        let omega = std::f64::consts::TAU / wf * (top.sin() - bot.sin());
        e += y * omega;
        cx += y * omega * (x + 0.5);
        cy += y * omega * (row + 0.5);
    }
    let (cx, cy) = (cx / e, cy / e);
    // The refracted apparent place from `himmel ephemeris`.
    let (code, json, err) = himmel(&[
        "ephemeris",
        "--time",
        t,
        "--lat",
        "-33.9",
        "--lon",
        "-70.6",
        "--body",
        "sun",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let sun = &v["bodies"]["sun"];
    let alt = sun["alt_refracted_deg"].as_f64().unwrap();
    let az = sun["az_deg"].as_f64().unwrap();
    let (sx, sy) = (az / 360.0 * wf, (90.0 - alt) / 180.0 * hf);
    assert!(
        (cx - sx).hypot(cy - sy) < 1.0,
        "disk at {cx},{cy}, ephemeris {sx},{sy}"
    );
    // Solar illuminance at the Sun's distance, within 2 % of the model's;
    // the disk's, brought to 1 AU, within 1 % of the luminous solar constant
    // (Darula, Kittler & Gueymard 2005: 133.8 klx at 1366.1 W/m², scaled to
    // the 1361 W/m² used here; the ASTM G173 spectrum gives 132.65 klx).
    let d_au = sun["distance_km"].as_f64().unwrap() / 149_597_870.7;
    let want =
        himmel_skymodel::spectrum::BandWeights::solar().solar_illuminance_lux() / (d_au * d_au);
    assert!((e / want - 1.0).abs() < 0.02, "{e} lx vs {want} lx");
    let disk_1au = e * d_au * d_au;
    let darula = 133_800.0 * 1361.0 / 1366.1;
    eprintln!("Sun disk: {e:.0} lx, {disk_1au:.0} lx at 1 AU; Darula et al. {darula:.0} lx");
    assert!(
        (disk_1au / darula - 1.0).abs() < 0.01,
        "{disk_1au} lx at 1 AU"
    );
}

#[test]
fn stars_pass_does_not_run_at_local_noon_and_stats_say_why() {
    // Munich, local noon on a clear summer day; automatic exposure.
    let f = tmp("noon.json");
    std::fs::write(
        &f,
        r#"{"camera": {"width": 64, "height": 64}, "lut": {"multiscatter_n": 8, "sky_view_w": 32, "sky_view_h": 32}}"#,
    )
    .unwrap();
    let (png, stats) = (tmp("noon.png"), tmp("noon-stats.json"));
    let (code, _, err) = himmel(&[
        "render",
        "--scene",
        &f,
        "--time",
        "2024-06-21T11:10:00Z",
        "--lat",
        "48.14",
        "--lon",
        "11.58",
        "--stats",
        &stats,
        "--output",
        &png,
    ]);
    assert_eq!(code, 0, "{err}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    let stars = s["passes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "stars")
        .unwrap();
    assert_eq!(stars["ran"], false);
    assert!(stars.get("ms").is_none());
    let reason = stars["reason"].as_str().unwrap();
    assert!(
        reason.starts_with("sky background brighter than the brightest visible star"),
        "{reason}"
    );
    for p in [f, png, stats] {
        let _ = std::fs::remove_file(p);
    }
}

#[test]
fn night_exr_star_peaks_and_illuminance_match_himmel_stars() {
    // Acceptance as measured from the outside: an EXR fisheye at a fixed
    // exposure, reference places from `himmel stars` (the exact reduction,
    // unrefracted) plus standard refraction.
    let (t, lat, lon) = ("2024-01-15T21:00:00Z", "48.14", "11.58");
    let exr = tmp("night.exr");
    let (code, _, err) = himmel(&[
        "render",
        "--time",
        t,
        "--lat",
        lat,
        "--lon",
        lon,
        "--effects",
        "stars",
        "--exposure",
        "-6",
        "--output",
        &exr,
    ]);
    assert_eq!(code, 0, "{err}");
    let (w, h, px) = himmel_cpu::output::read_exr(std::path::Path::new(&exr)).unwrap();
    let _ = std::fs::remove_file(&exr);
    assert_eq!((w, h), (1024, 1024));
    let (code, json, err) = himmel(&[
        "stars",
        "--time",
        t,
        "--lat",
        lat,
        "--lon",
        lon,
        "--above-horizon",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let stars: Vec<serde_json::Value> = serde_json::from_str(&json).unwrap();
    let lum = |i: i64, j: i64| {
        let p = px[j as usize * w + i as usize];
        (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) as f64
    };
    // Pixel of a star: refracted altitude, then the fisheye of conventions.md.
    let place = |s: &serde_json::Value| {
        let alt = s["alt_deg"].as_f64().unwrap();
        let az = s["az_deg"].as_f64().unwrap().to_radians();
        let r = himmel_astro::frames::refraction_true_to_apparent(alt.to_radians(), 1010.0, 10.0);
        let rho = (90.0 - alt - r.to_degrees()) / 90.0 * 512.0;
        (512.0 - rho * az.sin(), 512.0 - rho * az.cos())
    };
    let mut n = 0;
    for s in stars
        .iter()
        .filter(|s| s["alt_deg"].as_f64().unwrap() > 20.0)
        .take(15)
    {
        let (x, y) = place(s);
        let (ci, cj) = (x.floor() as i64, y.floor() as i64);
        let mut best = (f64::MIN, 0.0, 0.0);
        for j in cj - 4..=cj + 4 {
            for i in ci - 4..=ci + 4 {
                if lum(i, j) > best.0 {
                    best = (lum(i, j), i as f64 + 0.5, j as f64 + 0.5);
                }
            }
        }
        let d = (best.1 - x).hypot(best.2 - y);
        assert!(d <= 1.0, "{}: {d} px", s["name"]);
        n += 1;
    }
    assert_eq!(n, 15);
    // Sirius: Σ L·Ω over a 25×25 window, less the other stars inside it.
    let a = std::f64::consts::FRAC_PI_2 / 512.0;
    let sirius = stars.iter().find(|s| s["name"] == "Sirius").unwrap();
    let (x, y) = place(sirius);
    let (ci, cj) = (x.floor() as i64, y.floor() as i64);
    let mut e = 0.0;
    for j in cj - 12..=cj + 12 {
        for i in ci - 12..=ci + 12 {
            let z = a * ((i as f64 + 0.5 - 512.0).hypot(j as f64 + 0.5 - 512.0));
            e += lum(i, j) * a * a * z.sin() / z;
        }
    }
    let flux = |s: &serde_json::Value| 2.54e-6 * 10f64.powf(-0.4 * s["vmag"].as_f64().unwrap());
    let others: f64 = stars
        .iter()
        .filter(|s| s["hip"] != sirius["hip"])
        .filter(|s| {
            let (ox, oy) = place(s);
            (ox.floor() - ci as f64).abs() <= 12.0 && (oy.floor() - cj as f64).abs() <= 12.0
        })
        .map(flux)
        .sum();
    let want = flux(sirius);
    assert!(
        ((e - others) / want - 1.0).abs() < 0.10,
        "{e} − {others} vs {want}"
    );
}

/// At noon the night passes are culled as on the CPU; at night (Moon up,
/// first quarter) every planned pass renders on wgpu — the Moon included —
/// with per-pass times, and `--stats` lists the same passes as the CPU's
/// (`moon-eclipse` too).
#[test]
fn wgpu_culls_night_passes_at_noon_and_renders_the_night_with_the_moon() {
    let png = tmp("wn.png");
    let stats = tmp("wn.json");
    let noon = [
        "render",
        "--time",
        "2024-06-21T11:15:00Z",
        "--lat",
        "48.14",
        "--lon",
        "11.58",
        "--width",
        "64",
        "--height",
        "64",
        "--backend",
        "wgpu",
        "--stats",
        &stats,
        "--output",
        &png,
    ];
    let (code, _, err) = himmel(&noon);
    assert_eq!(code, 0, "{err}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    assert_eq!(s["backend"], "wgpu");
    let pass = |n: &str| {
        s["passes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["name"] == n)
            .cloned()
            .unwrap()
    };
    for n in ["stars", "milkyway", "planets"] {
        let p = pass(n);
        assert_eq!(p["ran"], false, "{p}");
        assert!(
            p["reason"].as_str().unwrap().contains("sky background"),
            "{p}"
        );
    }
    let night = [
        "render",
        "--time",
        "2024-01-15T21:00:00Z",
        "--lat",
        "48.14",
        "--lon",
        "11.58",
        "--width",
        "64",
        "--height",
        "64",
        "--stats",
        &stats,
        "--output",
        &png,
    ];
    let mut names = Vec::new();
    for backend in ["wgpu", "cpu"] {
        let mut a = night.to_vec();
        a.extend(["--backend", backend]);
        let (code, _, err) = himmel(&a);
        assert_eq!(code, 0, "{backend}: {err}");
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
        assert_eq!(s["backend"], backend);
        let passes = s["passes"].as_array().unwrap().clone();
        let moon = passes.iter().find(|p| p["name"] == "moon").unwrap();
        assert_eq!(moon["ran"], true, "{backend}: {moon}");
        assert!(moon["ms"].as_f64().is_some_and(|t| t >= 0.0), "{moon}");
        let e = passes.iter().find(|p| p["name"] == "moon-eclipse").unwrap();
        assert_eq!(e["ran"], false, "{e}");
        assert!(e["reason"].as_str().unwrap().contains("no lunar eclipse"));
        names.push(
            passes
                .iter()
                .map(|p| (p["name"].clone(), p["ran"].clone()))
                .collect::<Vec<_>>(),
        );
    }
    assert_eq!(names[0], names[1]);
    for p in [png, stats] {
        let _ = std::fs::remove_file(p);
    }
}

/// The cloud flags: a bad type or coverage exits 2 naming the flag; a
/// good one runs the clouds pass on either backend (`--stats`: ran, with
/// its time); the template shows the keys.
#[test]
fn cloud_flags_and_keys() {
    let out = tmp("clouds.exr");
    let (code, _, err) = render(&["--clouds-type", "nimbus", "--output", &out]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.starts_with("error: --clouds-type") && err.contains("cumulus"),
        "{err}"
    );
    let (code, _, err) = render(&["--clouds-tier", "sprites", "--output", &out]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.starts_with("error: --clouds-tier") && err.contains("heightfield"),
        "{err}"
    );
    let (code, _, err) = render(&["--clouds-coverage", "1.5", "--output", &out]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--clouds-coverage (clouds.low.coverage)"),
        "{err}"
    );
    let stats = tmp("clouds_stats.json");
    for (backend, tier) in [
        ("cpu", "volumetric"),
        ("wgpu", "volumetric"),
        ("cpu", "heightfield"),
        ("wgpu", "heightfield"),
    ] {
        let (code, _, err) = render(&[
            "--backend",
            backend,
            "--clouds-tier",
            tier,
            "--clouds-type",
            "stratocumulus",
            "--cirrus-coverage",
            "0.4",
            "--effects",
            "atmosphere,clouds",
            "--width",
            "24",
            "--height",
            "24",
            "--stats",
            &stats,
            "--output",
            &out,
        ]);
        assert_eq!(code, 0, "{backend}: {err}");
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
        assert_eq!(s["backend"], backend);
        let maps = s["cloud_maps_ms"].as_f64().unwrap();
        assert_eq!(
            maps > 0.0,
            tier == "heightfield",
            "{backend} {tier}: {maps}"
        );
        let grid = s["cloud_grid_ms"].as_f64().unwrap();
        assert_eq!(grid > 0.0, tier == "volumetric", "{backend} {tier}: {grid}");
        let clouds = s["passes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["name"] == "clouds")
            .unwrap()
            .clone();
        assert_eq!(clouds["ran"], true, "{backend}: {clouds}");
        assert!(
            clouds["ms"].as_f64().is_some_and(|t| t >= 0.0),
            "{backend}: {clouds}"
        );
    }
    let (code, t, _) = himmel(&["scene-template"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&t).unwrap();
    assert_eq!(v["clouds"]["low"]["coverage"], 0.0);
    assert_eq!(v["clouds"]["low"]["kind"], "cumulus");
    assert_eq!(v["clouds"]["low"]["tier"], "volumetric");
    assert_eq!(v["clouds"]["high"]["altitude_km"], 9.0);
}

/// Under an overcast sky (a stratocumulus deck at coverage 1) the night
/// passes do not run and `--stats` says why; broken cloud keeps them.
#[test]
fn overcast_night_runs_no_star_pass() {
    let out = tmp("overcast.exr");
    let stats = tmp("overcast_stats.json");
    for (coverage, hidden) in [("1", true), ("0.4", false)] {
        let (code, _, err) = himmel(&[
            "render",
            "--time",
            "2024-01-25T22:00:00Z",
            "--lat",
            "48.14",
            "--lon",
            "11.58",
            "--clouds-type",
            "stratocumulus",
            "--clouds-coverage",
            coverage,
            "--effects",
            "atmosphere,stars,planets,milkyway,clouds",
            "--width",
            "32",
            "--height",
            "32",
            "--stats",
            &stats,
            "--output",
            &out,
        ]);
        assert_eq!(code, 0, "{err}");
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
        for name in ["stars", "milkyway"] {
            let p = s["passes"]
                .as_array()
                .unwrap()
                .iter()
                .find(|p| p["name"] == name)
                .unwrap();
            let overcast = p["reason"]
                .as_str()
                .is_some_and(|r| r.starts_with("hidden by an overcast sky"));
            assert_eq!(overcast, hidden, "coverage {coverage}: {p}");
            if hidden {
                assert_eq!(p["ran"], false, "{p}");
            }
        }
    }
}
