//! The temporal filter (`lighting.temporal`, issue 16) on the plane with
//! boxes (`himmel_world::procedural::plane_and_boxes`) at the high Sun of
//! Munich (2024-04-15 11:45 UTC), 160 × 90, with the sky, the Sun, shadows
//! and `gtao` ambient occlusion (whose per-pixel noise the filter is to
//! average away) — the three acceptance figures:
//!
//! * **static view** (`a_static_view_converges_to_the_jittered_average`):
//!   64 filtered frames of a still camera against the mean of 64 frames
//!   drawn with the same jitter offsets and noise turns but no history
//!   (`max_frames: 1`, each frame as rendered): Σ|ΔY| / ΣY over the world
//!   pixels ≤ 1 %, closer than a single unfiltered frame; the sky pixels
//!   are exactly the unfiltered frame's (the filter never writes them);
//!   the same with `ssr` on a polished floor (`ssr_noise_averages_out`);
//! * **ghosting** (`a_moved_box_leaves_no_ghost`): after 16 frames a box
//!   moves 1.5 m; over the pixels it left (the floor now, eroded by a
//!   pixel), Σ|ΔY| / ΣY of each filtered frame against the new state's
//!   reference (the mean of 16 unfiltered jittered frames of it) must be
//!   below 2 % by the 8th frame after the move; likewise, seen from the
//!   north (`a_moved_shadow_leaves_no_ghost`), over the floor the box's
//!   shadow left or reached (the same surface, its light changed: only
//!   the clip box can take the old light out);
//! * **moving camera** (`a_moving_camera_does_not_flicker`): 24 frames of a
//!   camera sliding 5 cm a frame sideways (looking at a fixed point); on
//!   the static floor, each pixel's luminance Y_t(x) against the previous
//!   frame's at the floor point's place there (projected through the
//!   previous camera, bilinear), |Y_t(x) − Y_{t−1}(x')| / Y_t(x), averaged
//!   over the floor pixels seen in both frames (both frames' G-buffer
//!   distance within 3 % of the floor's, x eroded by a pixel): ≤ 2 % for
//!   every pair of frames, and less on average than without the filter
//!   (`max_frames: 1`). The reprojection is the test's own (the camera
//!   model and the plane y = 0), not the pass's velocity.
//!
//! `cargo test -p himmel-tests --test world_temporal -- --nocapture`
//! prints the figures the README quotes and the pass's `--stats` ms.

mod wgpu_common;
mod world_common;

use glam::DVec3;
use himmel_skymodel::projection::enu_from_scene;
use himmel_skymodel::{Effect, Scene, SkyRenderer, SkyState, TemporalSettings, WorldSpec};
use himmel_wgpu::WgpuRenderer;
use world_common::metrics::{mean_relative_error, RgbImage};
use world_common::view::{ground_point, munich_view};

const SIZE: (u32, u32) = (160, 90);
const AT: [f64; 3] = [0.0, 0.5, -2.0];

/// The scene seen from `eye`, with the temporal pass when `temporal` is
/// `Some`.
fn scene(eye: [f64; 3], temporal: Option<TemporalSettings>) -> Scene {
    let mut s = munich_view("2024-04-15T11:45:00Z", eye, AT, [0.0, 1.0, 0.0], SIZE, 60.0);
    s.effects = vec![
        Effect::Atmosphere,
        Effect::Sun,
        Effect::World,
        Effect::Shadows,
        Effect::Ao,
    ];
    s.world = Some(WorldSpec {
        gltf: "plane_and_boxes (procedural)".into(),
        ground: false,
    });
    // A lighter sky light than the default 64 directions per set keeps
    // lavapipe at ~0.3 s a frame; the filter does not depend on it.
    s.lighting.sky.directions = 16;
    if let Some(t) = temporal {
        s.effects.push(Effect::Temporal);
        s.lighting.temporal = t;
    }
    s
}

/// The settings under test: the defaults, or `HIMMEL_TEMPORAL` (a
/// `lighting.temporal` object) to measure others.
fn settings() -> TemporalSettings {
    std::env::var("HIMMEL_TEMPORAL")
        .map(|v| serde_json::from_str(&v).expect("a lighting.temporal object"))
        .unwrap_or_default()
}

/// Each frame as rendered: the same jitter and noise, no history.
fn unfiltered() -> TemporalSettings {
    TemporalSettings {
        max_frames: 1,
        ..TemporalSettings::default()
    }
}

struct Frame {
    image: RgbImage,
    /// The G-buffer's distance per pixel (0: sky).
    distance: Vec<f32>,
    ms: f64,
    reason: String,
}

fn render(r: &mut WgpuRenderer, s: &Scene) -> Frame {
    let state = SkyState::at(s).unwrap();
    let out = r.render(s, &state).unwrap();
    let stat = out.passes.iter().find(|p| p.name == "temporal").unwrap();
    let on = s.wants(Effect::Temporal);
    assert_eq!(stat.ran, on, "{:?}", stat.reason);
    let t = r.temporal_image().unwrap();
    Frame {
        image: RgbImage {
            width: out.image.width,
            height: out.image.height,
            pixels: out.image.pixels,
        },
        distance: t.map(|t| t.distance).unwrap_or_default(),
        ms: stat.ms.unwrap_or(0.0),
        reason: stat.reason.clone().unwrap_or_default(),
    }
}

/// Ends the renderer's run of filtered frames (a frame without the pass):
/// the next run starts unjittered, at jitter index 0.
fn end_run(r: &mut WgpuRenderer) {
    let f = render(r, &scene([0.0, 1.5, 6.0], None));
    assert!(f.reason.contains("not requested"), "{}", f.reason);
}

fn mean(images: &[RgbImage]) -> RgbImage {
    let (w, h) = (images[0].width, images[0].height);
    let n = images.len() as f64;
    RgbImage::from_fn(w, h, |x, y| {
        let mut acc = [0.0f64; 3];
        for img in images {
            for (a, v) in acc.iter_mut().zip(img.pixels[y * w + x]) {
                *a += v as f64;
            }
        }
        acc.map(|v| (v / n) as f32)
    })
}

/// Pixels of `mask` whose 8 neighbours are in it too.
fn eroded(mask: &[bool], w: usize, h: usize) -> Vec<bool> {
    (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as i64, (i / w) as i64);
            (-1..=1).all(|dy| {
                (-1..=1).all(|dx| {
                    let (a, b) = (x + dx, y + dy);
                    a >= 0
                        && b >= 0
                        && a < w as i64
                        && b < h as i64
                        && mask[(b * w as i64 + a) as usize]
                })
            })
        })
        .collect()
}

fn y(p: [f32; 3]) -> f64 {
    0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64
}

/// A still camera's frame 64, filtered with `settings()`, against the mean
/// of 64 unfiltered frames (the same jitter and noise turns) of `world`,
/// with the ssr pass when `ssr`: (error, one unfiltered frame's error).
/// Also checks that the sky pixels are untouched.
fn static_view(r: &mut WgpuRenderer, world: &himmel_world::World, ssr: bool) -> (f64, f64) {
    r.set_world(world);
    let eye = [0.0, 1.5, 6.0];
    let scene_with = |q| {
        let mut s = scene(eye, Some(q));
        if ssr {
            s.effects.push(Effect::Ssr);
        }
        s
    };
    end_run(r);
    let plain: Vec<RgbImage> = (0..64)
        .map(|_| render(r, &scene_with(unfiltered())).image)
        .collect();
    let reference = mean(&plain);
    end_run(r);
    let s = scene_with(settings());
    let mut last = None;
    let mut ms = Vec::new();
    for k in 0..64 {
        let f = render(r, &s);
        if k == 0 {
            assert!(f.reason.starts_with("first frame"), "{}", f.reason);
        }
        ms.push(f.ms);
        last = Some(f);
    }
    let last = last.unwrap();
    let world: Vec<bool> = last.distance.iter().map(|d| *d > 0.0).collect();
    assert!(world.iter().filter(|w| **w).count() > 5000);
    let err = mean_relative_error(&last.image, &reference, &world);
    let single = mean_relative_error(&plain[63], &reference, &world);
    ms.sort_by(f64::total_cmp);
    println!(
        "static view (ssr {ssr}): filtered frame 64 vs the 64-frame jittered mean {:.4} (one unfiltered frame: {:.4}); pass {:.1} ms (median)",
        err, single, ms[32]
    );
    // The sky is never touched: frame 63 of both runs has the same jitter,
    // so the same sky pixels, and they hold exactly what the sky passes drew.
    let sky: Vec<usize> = (0..world.len()).filter(|&i| !world[i]).collect();
    assert!(sky.len() > 1000, "{}", sky.len());
    assert!(sky
        .iter()
        .all(|&i| last.image.pixels[i] == plain[63].pixels[i]));
    (err, single)
}

#[test]
fn a_static_view_converges_to_the_jittered_average() {
    let mut r = wgpu_common::gpu();
    let world = himmel_world::procedural::plane_and_boxes();
    let (err, single) = static_view(&mut r, &world, false);
    assert!(err <= 0.01, "{err}");
    // The filter does something: a single frame is farther from the mean.
    assert!(single > err, "{single} vs {err}");
}

/// The same on a polished metal floor (roughness 0.3) with `ssr`, whose 8
/// GGX samples a pixel are far noisier than AO: a frame's 5.7 % from the
/// mean, 0.57 % filtered. (Before the clip box was widened by the pixel's
/// own spread over its frames it was 1.26 %: a box from the 3 × 3
/// neighbourhood of one noisy frame kept pulling the history towards it.)
#[test]
fn ssr_noise_averages_out() {
    let mut r = wgpu_common::gpu();
    let world = himmel_world::procedural::glossy_plane_and_boxes(0.3);
    let (err, single) = static_view(&mut r, &world, true);
    assert!(err <= 0.01, "{err}");
    assert!(err < single / 3.0, "{single} vs {err}");
}

/// The plane with boxes with the box at x 3…4, z −2…−1 moved by `dx` m.
fn moved_world(dx: f32) -> himmel_world::World {
    let mut w = himmel_world::procedural::plane_and_boxes();
    for m in &mut w.meshes {
        for p in &mut m.positions {
            if (3.0..=4.0).contains(&p[0]) && (-2.0..=-1.0).contains(&p[2]) && p[1] <= 1.0 {
                p[0] += dx;
            }
        }
    }
    w
}

/// Frames 1–8 after the box moves by −1.5 m in x, seen from `eye`
/// (16 frames of the old state before): Σ|ΔY| / ΣY against the new
/// state's reference (16 unfiltered jittered frames) over the pixels the
/// box left (the floor now) and over the floor whose light the move
/// changed (a shadow left it or fell on it: the same surface, its
/// luminance ≥ 20 % apart), each mask eroded by a pixel, with its size.
fn moved_box(eye: [f64; 3]) -> [(usize, Vec<f64>); 2] {
    let mut r = wgpu_common::gpu();
    let (before, after) = (moved_world(0.0), moved_world(-1.5));
    r.set_world(&after);
    end_run(&mut r);
    let plain: Vec<Frame> = (0..16)
        .map(|_| render(&mut r, &scene(eye, Some(unfiltered()))))
        .collect();
    let reference = mean(&plain.iter().map(|f| f.image.clone()).collect::<Vec<_>>());
    let d_after = plain[0].distance.clone();
    end_run(&mut r);
    r.set_world(&before);
    let s = scene(eye, Some(settings()));
    let old = (0..16).map(|_| render(&mut r, &s)).last().unwrap();
    let (w, h) = (SIZE.0 as usize, SIZE.1 as usize);
    let (left, relit): (Vec<bool>, Vec<bool>) = (0..w * h)
        .map(|i| {
            let (b, a) = (old.distance[i], d_after[i]);
            let (yb, ya) = (y(old.image.pixels[i]), y(reference.pixels[i]));
            let both = b > 0.0 && a > 0.0;
            let relit = (b - a).abs() < 0.01 * a && (yb - ya).abs() > 0.2 * ya.max(yb);
            (both && b < 0.95 * a, both && relit)
        })
        .unzip();
    let masks = [eroded(&left, w, h), eroded(&relit, w, h)];
    r.set_world(&after);
    let mut errors = [Vec::new(), Vec::new()];
    for _ in 0..8 {
        let image = render(&mut r, &s).image;
        for (e, m) in errors.iter_mut().zip(&masks) {
            e.push(mean_relative_error(&image, &reference, m));
        }
    }
    let count = |m: &Vec<bool>| m.iter().filter(|m| **m).count();
    let [e0, e1] = errors;
    [(count(&masks[0]), e0), (count(&masks[1]), e1)]
}

#[test]
fn a_moved_box_leaves_no_ghost() {
    let [(n, errors), _] = moved_box([0.0, 1.5, 6.0]);
    assert!(n >= 40, "the box left {n} pixels");
    println!("ghost over the {n} pixels the box left, frames 1-8 after the move: {errors:.4?}");
    assert!(errors[7] < 0.02, "{errors:?}");
}

/// The same seen from the north, where the box's shadow lies in view: the
/// floor it left and the floor it now darkens keep their surface, so only
/// the clip box (not the disocclusion test) takes the old light out.
#[test]
fn a_moved_shadow_leaves_no_ghost() {
    let [(n, left), (m, relit)] = moved_box([3.0, 4.0, -5.5]);
    assert!(n >= 40 && m >= 40, "the box left {n} pixels, relit {m}");
    println!("seen from the north: ghost over the {n} pixels the box left {left:.4?}; over the {m} floor pixels its shadow left or reached {relit:.4?}");
    assert!(left[7] < 0.02, "{left:?}");
    assert!(relit[7] < 0.02, "{relit:?}");
}

/// Per frame pair: the mean relative change of the static floor's
/// luminance between the frame and the previous one reprojected (see the
/// file's doc), and the 99th percentile.
fn flicker(frames: &[(Scene, Frame)]) -> Vec<(f64, f64, usize)> {
    let (w, h) = (SIZE.0 as usize, SIZE.1 as usize);
    let floor = |s: &Scene, f: &Frame| -> Vec<bool> {
        let eye = s.camera.eye_m();
        let m: Vec<bool> = (0..w * h)
            .map(|i| {
                ground_point(s, i % w, i / w).is_some_and(|p| {
                    let d = (p - eye).length();
                    (f.distance[i] as f64 - d).abs() <= 0.03 * d
                })
            })
            .collect();
        eroded(&m, w, h)
    };
    let mut out = Vec::new();
    for pair in frames.windows(2) {
        let ((s0, f0), (s1, f1)) = (&pair[0], &pair[1]);
        let (m0, m1) = (floor(s0, f0), floor(s1, f1));
        let mut rel = Vec::new();
        for (i, _) in m1.iter().enumerate().filter(|(_, m)| **m) {
            let Some(p) = ground_point(s1, i % w, i / w) else {
                continue;
            };
            let d: DVec3 = enu_from_scene(p - s0.camera.eye_m());
            let Some((px, py)) = s0.camera.dir_to_pixel(d.normalize()) else {
                continue;
            };
            let (fx, fy) = (px - 0.5, py - 0.5);
            let (x0, y0) = (fx.floor() as i64, fy.floor() as i64);
            if x0 < 0 || y0 < 0 || x0 + 1 >= w as i64 || y0 + 1 >= h as i64 {
                continue;
            }
            let (tx, ty) = (fx - x0 as f64, fy - y0 as f64);
            let at = |x: i64, yy: i64| (yy as usize) * w + x as usize;
            let texels = [(x0, y0), (x0 + 1, y0), (x0, y0 + 1), (x0 + 1, y0 + 1)];
            if !texels.iter().all(|&(x, yy)| m0[at(x, yy)]) {
                continue;
            }
            let l = |x, yy| y(f0.image.pixels[at(x, yy)]);
            let prev = (1.0 - ty) * ((1.0 - tx) * l(x0, y0) + tx * l(x0 + 1, y0))
                + ty * ((1.0 - tx) * l(x0, y0 + 1) + tx * l(x0 + 1, y0 + 1));
            let now = y(f1.image.pixels[i]);
            rel.push((now - prev).abs() / now.max(1e-9));
        }
        rel.sort_by(f64::total_cmp);
        let n = rel.len();
        let m = rel.iter().sum::<f64>() / n.max(1) as f64;
        out.push((m, rel[(n * 99 / 100).min(n.saturating_sub(1))], n));
    }
    out
}

#[test]
fn a_moving_camera_does_not_flicker() {
    let mut r = wgpu_common::gpu();
    r.set_world(&himmel_world::procedural::plane_and_boxes());
    let path = |t: usize| [-0.6 + 0.05 * t as f64, 1.5, 6.0];
    let mut run = |q: TemporalSettings| -> Vec<(Scene, Frame)> {
        end_run(&mut r);
        (0..24)
            .map(|t| {
                let s = scene(path(t), Some(q));
                let f = render(&mut r, &s);
                (s, f)
            })
            .collect()
    };
    let filtered = flicker(&run(settings()));
    let plain = flicker(&run(unfiltered()));
    let worst = |v: &[(f64, f64, usize)]| v.iter().map(|p| p.0).fold(0.0, f64::max);
    let mean = |v: &[(f64, f64, usize)]| v.iter().map(|p| p.0).sum::<f64>() / v.len() as f64;
    let p99 = |v: &[(f64, f64, usize)]| v.iter().map(|p| p.1).fold(0.0, f64::max);
    println!(
        "moving camera, static floor ({}..{} px a pair): frame-to-frame change mean {:.4}, worst pair {:.4}, worst p99 {:.4}; unfiltered: mean {:.4}, worst pair {:.4}, worst p99 {:.4}",
        filtered.iter().map(|p| p.2).min().unwrap_or(0),
        filtered.iter().map(|p| p.2).max().unwrap_or(0),
        mean(&filtered),
        worst(&filtered),
        p99(&filtered),
        mean(&plain),
        worst(&plain),
        p99(&plain)
    );
    assert!(filtered.iter().all(|p| p.2 > 2000), "{filtered:?}");
    assert!(worst(&filtered) <= 0.02, "{filtered:?}");
    assert!(mean(&filtered) < mean(&plain), "{filtered:?} vs {plain:?}");
}

/// A frame of another size ends the run: it starts unjittered, without
/// history, and the history images follow the new size.
#[test]
fn a_new_size_starts_a_new_run() {
    let mut r = wgpu_common::gpu();
    r.set_world(&himmel_world::procedural::plane_and_boxes());
    end_run(&mut r);
    let mut s = scene([0.0, 1.5, 6.0], Some(TemporalSettings::default()));
    let mut reasons = Vec::new();
    for size in [(160, 90), (160, 90), (80, 45), (80, 45)] {
        (s.camera.width, s.camera.height) = size;
        reasons.push(render(&mut r, &s).reason);
        let t = r.temporal_image().unwrap().unwrap();
        assert_eq!((t.width, t.height), size);
    }
    assert!(reasons[0].starts_with("first frame"), "{reasons:?}");
    assert!(
        reasons[1].starts_with("frame 1: jitter (+0.000, -0.167) px"),
        "{reasons:?}"
    );
    assert!(reasons[2].starts_with("first frame"), "{reasons:?}");
    assert!(reasons[3].starts_with("frame 1:"), "{reasons:?}");
}
