//! The atmosphere accuracy-vs-cost table of the README.
//!
//! `cargo run --release -p himmel-skymodel --example accuracy_table`
//!
//! For each LUT configuration: precompute time (single thread), sky-view
//! time per frame (single thread), and the median / 95th-percentile
//! relative luminance error against the brute-force reference over 48
//! directions of the upper sky (6 elevations 2–85° × 8 azimuths) for the
//! Sun at +60, +10, 0, −4 and −8°.
//!
//! Environment: `SUNS=60,10` (Sun altitudes), `PATHS=10000` (reference
//! Monte-Carlo paths per direction), `AEROSOL=1` (aerosol density factor),
//! `VERBOSE=1` (signed error per direction on stderr), `REF_CACHE=FILE`
//! (keep the reference values between runs), `ONLY=default` (configurations
//! whose name contains this).

use std::time::Instant;

use glam::Vec3;
use himmel_skymodel::atmosphere::reference::{self, ReferenceConfig};
use himmel_skymodel::atmosphere::{
    AtmosphereLuts, AtmosphereParams, LutConfig, SkyView, SkyViewInput,
};
use himmel_skymodel::spectrum::{luminance, BandWeights};

fn main() {
    // AEROSOL scales the aerosol density (0.05 = the Bruneton/Hillaire demo
    // atmosphere, aerosol optical depth 0.005); AEROSOL_G sets the aerosol
    // asymmetry parameter.
    let params = AtmosphereParams {
        aerosol_density: env_list("AEROSOL").map_or(1.0, |v| v[0]),
        aerosol_g: env_list("AEROSOL_G").map_or(AtmosphereParams::default().aerosol_g, |v| v[0]),
        ..AtmosphereParams::default()
    };
    let w = BandWeights::solar();
    let suns: Vec<f32> = env_list("SUNS").unwrap_or(vec![60.0, 10.0, 0.0, -4.0, -8.0]);
    let elevations = [2.0f32, 8.0, 20.0, 40.0, 60.0, 85.0];
    let rc = ReferenceConfig {
        paths: env_list("PATHS").map_or(10_000, |v| v[0]),
        ..Default::default()
    };
    let medium = himmel_skymodel::atmosphere::Medium::new(&params);
    // Reference luminances (cd/m² at 1 AU); REF_CACHE=FILE keeps them
    // between runs (one line per Sun altitude, tagged with the settings).
    let cache = std::env::var("REF_CACHE").ok();
    let tag = format!(
        "{} {} {} {}",
        params.aerosol_density,
        params.aerosol_g,
        rc.paths,
        elevations.len()
    );
    let cached: Vec<String> = cache
        .as_ref()
        .and_then(|c| std::fs::read_to_string(c).ok())
        .map(|t| t.lines().map(str::to_string).collect())
        .unwrap_or_default();
    let mut refs = Vec::new();
    let mut lines = Vec::new();
    let t = Instant::now();
    for &s in &suns {
        let sun = SkyView::sun_local(s.to_radians().sin());
        let key = format!("{tag} {s}:");
        // A cache line that does not parse (or is short) is recomputed.
        let hit = cached
            .iter()
            .find_map(|l| l.strip_prefix(&key))
            .and_then(|l| {
                l.split_whitespace()
                    .map(|x| x.parse::<f32>().ok())
                    .collect::<Option<Vec<_>>>()
            })
            .filter(|v| v.len() == elevations.len() * 8);
        let mut v = Vec::new();
        let mut k_all = 0;
        for &e in &elevations {
            for k in 0..8 {
                let az = (k as f32 * 22.5 + 5.0).to_radians();
                let er = e.to_radians();
                let d = Vec3::new(er.cos() * az.cos(), er.cos() * az.sin(), er.sin());
                let y = match &hit {
                    Some(h) => h[k_all],
                    None => w.to_y(&reference::radiance(&medium, medium.bottom, d, sun, &rc)),
                };
                k_all += 1;
                v.push((d, y));
            }
        }
        lines.push(format!(
            "{key} {}",
            v.iter()
                .map(|x| x.1.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        ));
        refs.push(v);
    }
    if let Some(c) = &cache {
        let mut all: Vec<String> = cached
            .into_iter()
            .filter(|l| {
                !lines
                    .iter()
                    .any(|n| n.split(':').next() == l.split(':').next())
            })
            .collect();
        all.extend(lines);
        let _ = std::fs::write(c, all.join("\n") + "\n");
    }
    eprintln!("reference: {:.1} s", t.elapsed().as_secs_f64());
    let fwd: Option<f32> = env_list("FWD").map(|v| v[0]);
    let mut configs: Vec<(&str, LutConfig)> = vec![
        (
            "single scattering (orders 1)",
            LutConfig {
                orders: 1,
                ..LutConfig::default()
            },
        ),
        (
            "orders 2",
            LutConfig {
                orders: 2,
                ..LutConfig::default()
            },
        ),
        ("small (16² MS, 36 dirs, 96×64 view)", LutConfig::small()),
        (
            "32² MS (Hillaire's size), 64 dirs, 192×108 view",
            LutConfig {
                multiscatter_n: 32,
                ..LutConfig::default()
            },
        ),
        (
            "default (48² MS, 64 dirs, 192×108 view, 30 steps)",
            LutConfig::default(),
        ),
        (
            "large (64² MS, 256 dirs, 256×192 view)",
            LutConfig {
                multiscatter_n: 64,
                multiscatter_dirs: 256,
                multiscatter_steps: 40,
                sky_view_w: 256,
                sky_view_h: 192,
                sky_view_steps: 60,
                ..LutConfig::default()
            },
        ),
    ];
    // Trial overrides of the multiple-scattering LUT (MS=n,dirs,steps).
    if let Some(v) = env_list::<usize>("MS") {
        if v.len() != 3 {
            fail("MS", "expected n,dirs,steps");
        }
        for c in configs.iter_mut() {
            c.1.multiscatter_n = v[0];
            c.1.multiscatter_dirs = v[1];
            c.1.multiscatter_steps = v[2];
        }
    }
    if let Ok(only) = std::env::var("ONLY") {
        configs.retain(|c| c.0.contains(only.as_str()));
    }
    if let Some(f) = fwd {
        for c in configs.iter_mut() {
            c.1.forward_peak_deg = f;
        }
    }
    println!("| LUT configuration | precompute (ms, 1 thread) | sky view per frame (ms, 1 thread) | {} |",
        suns.iter().map(|s| format!("Sun {s:+}°: median / p95")).collect::<Vec<_>>().join(" | "));
    println!("|---|---|---|{}", "---|".repeat(suns.len()));
    for (name, cfg) in configs {
        let t0 = Instant::now();
        let luts = AtmosphereLuts::compute(&params, &cfg);
        let pre = t0.elapsed().as_secs_f64() * 1e3;
        let mut frame = 0.0;
        let mut cells = Vec::new();
        for (i, &s) in suns.iter().enumerate() {
            let input = SkyViewInput {
                observer_altitude_km: 0.0,
                sun_sin_elevation: s.to_radians().sin(),
                irradiance_scale: 1.0,
            };
            let t1 = Instant::now();
            let sv = SkyView::compute(&luts, &input);
            frame += t1.elapsed().as_secs_f64() * 1e3 / suns.len() as f64;
            let sun_enu = Vec3::new(
                0.0,
                SkyView::sun_local(input.sun_sin_elevation).x,
                input.sun_sin_elevation,
            );
            let mut errs: Vec<f32> = refs[i]
                .iter()
                .map(|(d, r)| {
                    // Local frame (x towards the Sun) → ENU with the Sun in the North.
                    let enu = Vec3::new(d.y, d.x, d.z);
                    let l = luminance(sv.radiance(enu, sun_enu));
                    if std::env::var("VERBOSE").is_ok() {
                        eprintln!(
                            "{name} sun {s} e {:.0} az {:.0}: {:+.1} %",
                            d.z.asin().to_degrees(),
                            d.y.atan2(d.x).to_degrees(),
                            (l / r - 1.0) * 100.0
                        );
                    }
                    (l / r - 1.0).abs()
                })
                .collect();
            errs.sort_by(f32::total_cmp);
            let med = errs[errs.len() / 2];
            let p95 = errs[(errs.len() * 95 / 100).min(errs.len() - 1)];
            cells.push(format!("{:.1} % / {:.1} %", med * 100.0, p95 * 100.0));
        }
        println!("| {name} | {pre:.0} | {frame:.0} | {} |", cells.join(" | "));
    }
}

/// A comma-separated list of numbers from environment variable `name`
/// (None when unset); a malformed one ends the program with a one-line
/// error and exit code 2.
fn env_list<T: std::str::FromStr>(name: &str) -> Option<Vec<T>> {
    let s = std::env::var(name).ok()?;
    let v: Option<Vec<T>> = s.split(',').map(|x| x.trim().parse().ok()).collect();
    match v {
        Some(v) if !v.is_empty() => Some(v),
        _ => fail(
            name,
            &format!("'{s}' is not a comma-separated list of numbers"),
        ),
    }
}

fn fail(name: &str, why: &str) -> ! {
    eprintln!("error: {name}: {why}");
    std::process::exit(2)
}
