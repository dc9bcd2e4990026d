//! Light shafts against Mitsuba 3 (issue 15, item 4): each case of
//! `tools/godrays_cases.json` — the sun room with the low Sun through its
//! window and the atrium's colonnade in the afternoon, both in light fog —
//! rendered on the adapter at hand (lavapipe in CI) with every surface
//! black, and compared with the single-scattering reference of
//! `tests/fixtures/godrays_ref/` (`tools/godrays_reference.py`, checked
//! against Mitsuba's `volpath`).
//!
//! The fog's *added radiance* is isolated on both sides: here, the render
//! with the godrays pass minus the same render without it (the same fog's
//! extinction, the same air); in the reference, black surfaces, so that a
//! geometry pixel shows nothing but the fog's in-scattering. Measured over
//! the reference's geometry mask (B; sky pixels are left out: neither the
//! fog's extinction nor its light touches them here):
//!
//! * the luminance-weighted mean relative error Σ|ΔY| / ΣY_ref;
//! * FLIP of the tone-mapped images (both masked to the geometry);
//! * the godrays pass's time from `--stats` (lavapipe).
//!
//! `cargo test -p himmel-tests --test godrays_mitsuba -- --nocapture`
//! prints the table the README quotes, for the default quality and a
//! full-resolution 128-step march. `HIMMEL_GODRAYS='{"steps": 16}'` measures
//! other settings (the `lighting.godrays` object) instead of both.
//! `screen_space_shafts_against_mitsuba` prints the `mitchell` and `sousa`
//! rows, `sousa_against_mitchell_at_equal_taps` their time ratio;
//! `godrays_froxel` the `froxel` rows (its own binary: its frames do not
//! run beside this one's timings).

mod wgpu_common;
mod world_common;

use himmel_skymodel::{
    Effect, GodraysMethod, GodraysSettings, RenderOutput, Scene, SkyRenderer, SkyState,
};
use serde_json::Value;
use world_common::shafts::{black_world, case_scene, measure_output, root, Measured};

fn render(s: &Scene, world: &himmel_world::World) -> RenderOutput {
    let state = SkyState::at(s).unwrap();
    let mut r = wgpu_common::gpu();
    r.set_world(world);
    r.render(s, &state).unwrap()
}

/// The added radiance of `quality` against the reference.
fn measure(
    c: &Value,
    world: &himmel_world::World,
    off: &RenderOutput,
    quality: GodraysSettings,
) -> Measured {
    let on = render(&case_scene(c, Some(quality)), world);
    measure_output(c, &on, off)
}

#[test]
fn light_shafts_against_mitsuba() {
    let cases: Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("tools/godrays_cases.json")).unwrap(),
    )
    .unwrap();
    let full = GodraysSettings {
        steps: 128,
        interleave: 1,
        resolution_divisor: 1,
        ..GodraysSettings::default()
    };
    let qualities: Vec<(String, GodraysSettings)> = match std::env::var("HIMMEL_GODRAYS") {
        Ok(json) => vec![(
            json.clone(),
            serde_json::from_str(&json).expect("HIMMEL_GODRAYS: a `lighting.godrays` object"),
        )],
        Err(_) => vec![
            ("default".into(), GodraysSettings::default()),
            ("full resolution, 128 steps".into(), full),
        ],
    };
    // What this version achieves (lavapipe), with a margin: (error, FLIP)
    // per case and quality; the goal for `toth` at its default
    // quality is an error ≤ 10 % (measured 6.50 % and 1.69 %). Other
    // settings (HIMMEL_GODRAYS) are held to the default's bounds.
    let bounds = |name: &str, q: &str| -> (f64, f64) {
        match (name, q) {
            ("sun_room_fog", "full resolution, 128 steps") => (0.10, 0.09),
            ("sun_room_fog", _) => (0.085, 0.16),
            ("atrium_fog", "full resolution, 128 steps") => (0.014, 0.025),
            ("atrium_fog", _) => (0.022, 0.036),
            (other, _) => panic!("no bounds for case {other}"),
        }
    };
    println!("| case | quality | mean relative error | FLIP | godrays ms (lavapipe) |");
    println!("|---|---|---|---|---|");
    let mut failures = Vec::new();
    for c in cases["cases"].as_array().unwrap() {
        let name = c["name"].as_str().unwrap();
        let world = black_world(c);
        let off = render(&case_scene(c, None), &world);
        let mut runs = Vec::new();
        // The times: the least of 4 frames each, the qualities alternating
        // (one frame's time on lavapipe swings with whatever else the CPU
        // runs; alternating, both see the same).
        let scenes: Vec<Scene> = qualities
            .iter()
            .map(|(_, q)| case_scene(c, Some(*q)))
            .collect();
        let times = wgpu_common::alternating_least_ms(&scenes, &world, 4);
        for ((q, settings), ms) in qualities.iter().zip(times) {
            let m = measure(c, &world, &off, *settings);
            println!(
                "| {name} | {q} | {:.2} % | {:.3} | {ms:.1} |",
                m.error * 100.0,
                m.flip,
            );
            runs.push((ms, m.error));
            let (be, bf) = bounds(name, q);
            if !(m.error <= be && m.flip <= bf) {
                failures.push(format!(
                    "{name} {q}: error {:.4} (≤ {be}), FLIP {:.3} (≤ {bf})",
                    m.error, m.flip
                ));
            }
        }
        if let [(t_opt, e_opt), (t_full, e_full)] = runs[..] {
            // Printed, not bounded: issue 15's speed-up and error ratio are
            // measured by `godrays_toth_speed` (its own binary, at twice
            // this resolution). Here, at 160 × 90 and one ray per pixel
            // centre, the full march errs by its pixels' edges against the
            // reference's means over each pixel's area as much as by its
            // march (sun room), and lavapipe's fixed cost per dispatch
            // weighs on the optimised march's three.
            println!(
                "{name}: the default quality is {:.1}× faster than the full march, error × {:.2}",
                t_full / t_opt,
                e_opt / e_full
            );
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The screen-space methods' qualities: `mitchell` and `sousa` at 63 taps
/// in total (`sousa`: 3 × 21), on the half-resolution image (the default
/// divisor) and at full resolution (`sousa` blurs at half of each:
/// `image_divisor`).
fn screen_qualities() -> Vec<(&'static str, GodraysSettings)> {
    let q = |method, resolution_divisor| GodraysSettings {
        method,
        samples: 63,
        resolution_divisor,
        ..GodraysSettings::default()
    };
    vec![
        ("mitchell, 63 taps, ½ res", q(GodraysMethod::Mitchell, 2)),
        ("mitchell, 63 taps, full res", q(GodraysMethod::Mitchell, 1)),
        (
            "sousa, 3 × 21 taps, ½ res (blurred at ¼)",
            q(GodraysMethod::Sousa, 2),
        ),
        (
            "sousa, 3 × 21 taps, full res (blurred at ½)",
            q(GodraysMethod::Sousa, 1),
        ),
    ]
}

/// Issue 15: the screen-space methods' error against the same references
/// (published, no goal): bounded at what this version measures (lavapipe)
/// plus a margin, so that a change that makes them worse shows. Their
/// error is large: the mask is the light's visibility at the surfaces and
/// the sky beyond them, not along the view ray, and the sky's light in the
/// fog is left out (`toth` without it, `{"sky_cells": 0}`, errs 39.8 % in
/// the sun room and 14.8 % in the atrium).
#[test]
fn screen_space_shafts_against_mitsuba() {
    let cases: Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("tools/godrays_cases.json")).unwrap(),
    )
    .unwrap();
    // Measured (error, FLIP) per case and quality, in the order of
    // `screen_qualities`.
    let measured = |name: &str| -> [(f64, f64); 4] {
        match name {
            "sun_room_fog" => [
                (0.535, 0.643),
                (0.495, 0.630),
                (0.458, 0.618),
                (0.530, 0.641),
            ],
            "atrium_fog" => [
                (0.812, 0.668),
                (0.783, 0.633),
                (0.804, 0.657),
                (0.830, 0.678),
            ],
            other => panic!("no bounds for case {other}"),
        }
    };
    println!(
        "| case | method, quality | mean relative error | FLIP | godrays ms (lavapipe, least of 3 frames) |"
    );
    println!("|---|---|---|---|---|");
    let mut failures = Vec::new();
    for c in cases["cases"].as_array().unwrap() {
        let name = c["name"].as_str().unwrap();
        let world = black_world(c);
        let off = render(&case_scene(c, None), &world);
        for ((q, settings), (e, f)) in screen_qualities().into_iter().zip(measured(name)) {
            let m = measure(c, &world, &off, settings);
            let ms = least_ms(&case_scene(c, Some(settings)), &world, 3);
            println!(
                "| {name} | {q} | {:.2} % | {:.3} | {ms:.1} |",
                m.error * 100.0,
                m.flip,
            );
            if !(m.error <= e + 0.03 && m.flip <= f + 0.03) {
                failures.push(format!(
                    "{name} {q}: error {:.4} (≤ {e} + 0.03), FLIP {:.3} (≤ {f} + 0.03)",
                    m.error, m.flip
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The godrays pass's least time over `frames` frames of `s` on one
/// renderer (after a first frame that builds the pipelines).
fn least_ms(s: &Scene, world: &himmel_world::World, frames: usize) -> f64 {
    let state = SkyState::at(s).unwrap();
    let mut r = wgpu_common::gpu();
    r.set_world(world);
    (0..=frames)
        .map(|_| {
            let out = r.render(s, &state).unwrap();
            let p = out.passes.iter().find(|p| p.name == "godrays").unwrap();
            assert!(p.ran, "{p:?}");
            p.ms.unwrap_or(f64::NAN)
        })
        .skip(1)
        .fold(f64::INFINITY, f64::min)
}

/// Issue 15: `sousa`'s time against `mitchell`'s at equal total taps (63
/// per texel; `sousa` 3 × 21) and equal requested quality (full
/// resolution), from `--stats`' godrays ms (the least of 8 frames each,
/// alternating, after a first; a renderer each), in the sun room at 640 × 360 (its
/// case's camera × 4, so that the passes' work rather than lavapipe's
/// per-dispatch overhead is timed). `sousa` blurs a quarter-resolution
/// image (`image_divisor`), as in Crysis; at equal texels it measured
/// 1.2–2.1× `mitchell` (two passes more, each with its own set-up per
/// texel). The goal: ≤ 0.6×.
#[test]
fn sousa_against_mitchell_at_equal_taps() {
    let cases: Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("tools/godrays_cases.json")).unwrap(),
    )
    .unwrap();
    let c = &cases["cases"][0];
    let world = black_world(c);
    let [_, (_, mitchell), _, (_, sousa)] = screen_qualities()[..] else {
        panic!("four qualities")
    };
    let scene = |q| {
        let mut s = case_scene(c, Some(q));
        s.camera.width *= 4;
        s.camera.height *= 4;
        // Only what the screen-space shafts need (the Sun, its shadow
        // maps): the sky passes and the sky light would dominate the
        // frames' time on lavapipe.
        s.effects = vec![Effect::Sun, Effect::World, Effect::Shadows, Effect::Godrays];
        s
    };
    let [tm, ts] =
        wgpu_common::alternating_least_ms(&[scene(mitchell), scene(sousa)], &world, 8)[..]
    else {
        panic!("two times")
    };
    let ratio = ts / tm;
    println!("sousa {ts:.2} ms, mitchell {tm:.2} ms: sousa / mitchell = {ratio:.2}");
    assert!(ratio <= 0.6, "sousa {ts} ms vs mitchell {tm} ms");
}

/// "Simulate only what the scene calls for": the screen-space methods do
/// not run when the Sun is behind the camera (looking north in the sun
/// room, the Sun low in the south), and `--stats` says why; `toth` runs.
#[test]
fn screen_space_shafts_skip_a_light_behind_the_camera() {
    let cases: Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("tools/godrays_cases.json")).unwrap(),
    )
    .unwrap();
    let c = &cases["cases"][0];
    let world = black_world(c);
    for (_, q) in screen_qualities()
        .into_iter()
        .chain([("toth", GodraysSettings::default())])
    {
        let mut s = case_scene(c, Some(q));
        s.camera.look_at_m = Some([-2.0, 1.4, -6.0]);
        let out = render(&s, &world);
        let p = out.passes.iter().find(|p| p.name == "godrays").unwrap();
        if q.method == GodraysMethod::Toth {
            assert!(p.ran, "{p:?}");
            continue;
        }
        let why = p.reason.clone().unwrap_or_default();
        assert!(!p.ran && p.ms.is_none(), "{p:?}");
        assert!(why.starts_with("the Sun is far off screen"), "{why}");
        // Facing the Sun again, it runs.
        let out = render(&case_scene(c, Some(q)), &world);
        assert!(out.passes.iter().any(|p| p.name == "godrays" && p.ran));
    }
}
