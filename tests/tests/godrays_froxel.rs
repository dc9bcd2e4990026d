//! `froxel` (issue 15): against the Mitsuba references of the light-shaft
//! cases (`froxel_against_mitsuba`; `godrays_mitsuba` has the other
//! methods), and its temporal reprojection: a static view of the sun
//! room (`tools/godrays_cases.json`, every surface black) over 24 frames
//! on one renderer, the Sun moving one minute of time (≈ 0.2°) per frame.
//! The fog's added radiance A_n (the frame with the godrays pass minus
//! the same frame without it) is compared frame to frame over the
//! reference's geometry mask as Σ|A_n − A_(n−1)| / Σ A_(n−1) (luminance):
//!
//! * with the history (`temporal` 0.9) the change stays ≤ 2 % per frame
//!   (the flicker bound) — the largest over the 23 pairs;
//! * without it (`temporal` 0: each frame its own jittered slices alone)
//!   the mean change over the pairs is more than twice as large: the
//!   history is what steadies the frames (measured: worst 1.59 % with it,
//!   3.96 % without; means 1.1 % and 3.3 %; the Sun's own motion changes
//!   the shafts by ~1.5 % a minute here, which the history's change
//!   approaches as it catches up);
//! * printed, not bounded: the 24th frame with the history against the
//!   same frame on a fresh renderer (no history) — the jitter's noise and
//!   the history's lag behind the moving Sun (an exponential average of
//!   weight 0.9 trails by ~9 frames). That the history converges is
//!   `godrays_mitsuba`'s `froxel_against_mitsuba` (the 16th frame of a
//!   static sequence nearer the reference than a single frame).

mod wgpu_common;
mod world_common;

use himmel_skymodel::{GodraysMethod, GodraysSettings, RenderOutput, Scene, SkyRenderer, SkyState};
use serde_json::Value;
use world_common::metrics::{luminance, mask_channel, read_exr, GEOMETRY};
use world_common::shafts::{black_world, case_scene, cases, measure_output, root};

const FRAMES: usize = 24;

/// A renderer of this test's own: the froxel history lives in the
/// renderer, and the binary's shared one serves the other test's frames
/// in between.
fn own_renderer(world: &himmel_world::World) -> himmel_wgpu::WgpuRenderer {
    let mut r = himmel_wgpu::WgpuRenderer::new(None).expect("a wgpu adapter (lavapipe in CI)");
    r.set_world(world);
    r
}

/// Frame n: the case's scene at 11:30 + n minutes (UTC), with `godrays`.
fn frame_scene(c: &Value, n: usize, godrays: Option<GodraysSettings>) -> Scene {
    let mut s = case_scene(c, godrays);
    s.time.utc = format!("2024-12-21T11:{:02}:00Z", 30 + n);
    s
}

fn render(s: &Scene, world: &himmel_world::World) -> RenderOutput {
    let state = SkyState::at(s).unwrap();
    let mut r = wgpu_common::gpu();
    r.set_world(world);
    r.render(s, &state).unwrap()
}

/// The luminance of `on` − `off` per pixel of the mask.
fn added(on: &RenderOutput, off: &RenderOutput, mask: &[bool]) -> Vec<f64> {
    on.image
        .pixels
        .iter()
        .zip(&off.image.pixels)
        .zip(mask)
        .filter(|(_, m)| **m)
        .map(|((a, b), _)| luminance([0, 1, 2].map(|k| a[k] - b[k])))
        .collect()
}

/// Σ|a − b| / Σ b.
fn change(a: &[f64], b: &[f64]) -> f64 {
    let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum();
    d / b.iter().sum::<f64>().max(1e-30)
}

/// The added radiance of each frame of the sequence on one renderer.
fn sequence(
    c: &Value,
    world: &himmel_world::World,
    offs: &[RenderOutput],
    mask: &[bool],
    q: GodraysSettings,
) -> Vec<Vec<f64>> {
    let mut r = own_renderer(world);
    (0..FRAMES)
        .map(|n| {
            let s = frame_scene(c, n, Some(q));
            let on = r.render(&s, &SkyState::at(&s).unwrap()).unwrap();
            assert!(on.passes.iter().any(|p| p.name == "godrays" && p.ran));
            added(&on, &offs[n], mask)
        })
        .collect()
}

fn mean_change(frames: &[Vec<f64>]) -> f64 {
    let c: Vec<f64> = frames.windows(2).map(|w| change(&w[1], &w[0])).collect();
    c.iter().sum::<f64>() / c.len().max(1) as f64
}

fn worst_change(frames: &[Vec<f64>]) -> f64 {
    frames
        .windows(2)
        .map(|w| change(&w[1], &w[0]))
        .fold(0.0, f64::max)
}

#[test]
fn froxel_shafts_hold_still_under_a_slowly_moving_sun() {
    let c = cases()["cases"][0].clone();
    let world = black_world(&c);
    let name = c["name"].as_str().unwrap();
    let mask = mask_channel(
        &read_exr(root().join(format!("tests/fixtures/godrays_ref/{name}_mask.exr"))).unwrap(),
        GEOMETRY,
    );
    let offs: Vec<RenderOutput> = {
        let mut r = wgpu_common::gpu();
        r.set_world(&world);
        (0..FRAMES)
            .map(|n| {
                let s = frame_scene(&c, n, None);
                r.render(&s, &SkyState::at(&s).unwrap()).unwrap()
            })
            .collect()
    };
    let q = GodraysSettings::of(GodraysMethod::Froxel);
    let with = sequence(&c, &world, &offs, &mask, q);
    let without = sequence(
        &c,
        &world,
        &offs,
        &mask,
        GodraysSettings { temporal: 0.0, ..q },
    );
    let pairs = |f: &[Vec<f64>]| -> Vec<String> {
        f.windows(2)
            .map(|w| format!("{:.2}", change(&w[1], &w[0]) * 100.0))
            .collect()
    };
    println!("with the history, % per frame: {}", pairs(&with).join(" "));
    println!("without, % per frame: {}", pairs(&without).join(" "));
    let (w, wo) = (worst_change(&with), worst_change(&without));
    // The last frame on a fresh renderer: no history.
    let last = frame_scene(&c, FRAMES - 1, Some(q));
    let mut r = own_renderer(&world);
    let fresh = r.render(&last, &SkyState::at(&last).unwrap()).unwrap();
    let fresh = added(&fresh, &offs[FRAMES - 1], &mask);
    let lag = change(&with[FRAMES - 1], &fresh);
    let noise = change(&without[FRAMES - 1], &without[FRAMES - 2]);
    println!(
        "froxel, {FRAMES} frames: worst frame-to-frame change {:.2} % with the history (temporal {}), {:.2} % without; \
         the last frame against a history-less render {:.2} %, two history-less frames {:.2} %",
        w * 100.0,
        q.temporal,
        wo * 100.0,
        lag * 100.0,
        noise * 100.0
    );
    assert!(w <= 0.02, "flicker {w} with the history");
    let (mw, mwo) = (mean_change(&with), mean_change(&without));
    println!(
        "mean frame-to-frame change {:.2} % with the history, {:.2} % without",
        mw * 100.0,
        mwo * 100.0
    );
    assert!(
        mw < 0.5 * mwo,
        "the history steadies nothing: {mw} vs {mwo}"
    );
}

/// `froxel` (issue 15's goal: ≤ 15 % mean relative error) at its default
/// quality (2 × 2-pixel froxels, 32 slices, 4 samples of the Sun per
/// froxel, 8 sky cells, `temporal` 0.9): the first frame of a renderer (no
/// history)
/// and the 16th frame of a static sequence on one renderer (the history
/// averaging the jittered slices). Bounded at what this version measures
/// (lavapipe) plus a margin.
#[test]
fn froxel_against_mitsuba() {
    let cases = cases();
    // `HIMMEL_GODRAYS='{"method": "froxel", "sky_cells": 64}'` measures
    // other settings, held to the default's bounds.
    let q = std::env::var("HIMMEL_GODRAYS")
        .ok()
        .and_then(|j| serde_json::from_str::<GodraysSettings>(&j).ok())
        .filter(|g| g.method == GodraysMethod::Froxel)
        .unwrap_or(GodraysSettings::of(GodraysMethod::Froxel));
    let measured = |name: &str| -> [(f64, f64); 2] {
        match name {
            "sun_room_fog" => [(0.1376, 0.235), (0.1353, 0.234)],
            "atrium_fog" => [(0.0281, 0.055), (0.0262, 0.053)],
            other => panic!("no bounds for case {other}"),
        }
    };
    println!(
        "| case | method, quality | mean relative error | FLIP | godrays ms (lavapipe, least of 16 frames) |"
    );
    println!("|---|---|---|---|---|");
    let mut failures = Vec::new();
    for c in cases["cases"].as_array().unwrap() {
        let name = c["name"].as_str().unwrap();
        let world = black_world(c);
        let off = render(&case_scene(c, None), &world);
        let s = case_scene(c, Some(q));
        let state = SkyState::at(&s).unwrap();
        let mut r = own_renderer(&world);
        let mut frames = Vec::new();
        let mut ms = f64::INFINITY;
        for _ in 0..16 {
            let out = r.render(&s, &state).unwrap();
            let p = out.passes.iter().find(|p| p.name == "godrays").unwrap();
            ms = ms.min(p.ms.unwrap_or(f64::NAN));
            frames.push(out);
        }
        let single = measure_output(c, &frames[0], &off);
        let seq = measure_output(c, &frames[15], &off);
        if seq.error >= single.error {
            failures.push(format!(
                "{name}: the history does not converge: {} after 16 frames, {} after 1",
                seq.error, single.error
            ));
        }
        for ((label, m), (e, f)) in [("froxel, 1 frame", single), ("froxel, frame 16", seq)]
            .into_iter()
            .zip(measured(name))
        {
            println!(
                "| {name} | {label} | {:.2} % | {:.3} | {ms:.1} |",
                m.error * 100.0,
                m.flip,
            );
            let be = (e + 0.02).min(0.15);
            if !(m.error <= be && m.flip <= f + 0.03) {
                failures.push(format!(
                    "{name} {label}: error {:.4} (≤ {be}), FLIP {:.3} (≤ {f} + 0.03)",
                    m.error, m.flip
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
