//! Temporal reprojection of the low layer's coarse grid over frame
//! sequences (issue 18; `skymodel/src/frame/cloud_history.rs`, CPU
//! backend): one renderer draws the frames in turn, each marching a
//! rotating quarter of the coarse nodes and taking the others from the
//! last frame, moved with the wind.
//!
//! * static clouds under a Sun moving 0.025° per frame (within the 0.1°
//!   tolerance, so the history serves): the frame-to-frame change on
//!   cloud pixels is the full march's within 2 % (p99);
//! * clouds moving with a 15 m/s wind: each frame made with the history
//!   is within FLIP 0.05 of the full march of the same instant, with at
//!   least 40 % of the coarse nodes reused;
//! * the history is not used on the first frame, after a resize, a camera
//!   change or a change of the layer, and not for nodes whose lights
//!   moved more than the tolerance; the counts of reused and marched nodes
//!   are reported.
//!
//! `cargo test -p himmel-tests --test cloud_temporal -- --nocapture`
//! prints the figures.

mod world_common;

use himmel_cpu::CpuRenderer;
use himmel_skymodel::frame::{HistoryMiss, HistoryUse};
use himmel_skymodel::{HdrImage, Projection, Scene, SkyRenderer, SkyState};
use world_common::changes::assert_flicker_at_most;
use world_common::cloud_sequence::{clear, scene, utc};
use world_common::metrics::{flip, RgbImage};

/// The frame of `s` from renderer `r` and what its history gave.
fn render(r: &mut CpuRenderer, s: &Scene) -> (HdrImage, Option<HistoryUse>) {
    let state = SkyState::at(s).expect("state");
    let out = r.render(s, &state).expect("render");
    (out.image, out.cloud_history)
}

/// The frame of `s` from a renderer of its own (no history).
fn alone(s: &Scene) -> HdrImage {
    render(&mut CpuRenderer::new(None), s).0
}

fn rgb(img: &HdrImage) -> RgbImage {
    let (w, h) = (img.width, img.height);
    RgbImage::from_fn(w, h, |x, y| img.pixels[y * w + x])
}

/// A Sun moving 6 s (0.025°) per frame over static clouds: with the
/// history serving (three quarters of the nodes reused from the second
/// frame on, within the light tolerance), the frames change
/// from one to the next as the full march's do, within 2 % (p99 over the
/// cloud pixels).
#[test]
fn moving_sun_over_static_clouds_reuses_the_history_without_flicker() {
    let (n, frames, step) = (160, 6, 6);
    let mut r = CpuRenderer::new(None);
    let mut amortised = Vec::new();
    let mut full = Vec::new();
    for k in 0..frames {
        let (img, used) = render(&mut r, &scene(n, 4, &utc(k, step), 0.0));
        let used = used.expect("an amortised frame reports its history");
        eprintln!("frame {k}: {used:?}");
        if k == 0 {
            assert_eq!(used.miss, Some(HistoryMiss::First));
        } else {
            assert_eq!((used.miss, used.light_moved), (None, 0), "frame {k}");
            assert!(used.reused >= 2 * used.marched, "frame {k}: {used:?}");
        }
        amortised.push(img);
        full.push(alone(&scene(n, 1, &utc(k, step), 0.0)));
    }
    let clear = alone(&clear(n, &utc(0, step)));
    assert_flicker_at_most(
        "Sun moving 6 s per frame, static clouds, history",
        &full,
        &amortised,
        &clear,
        0.02,
    );
}

/// Clouds moving with a 15 m/s wind, 4 s per frame (60 m, about a
/// coarse cell overhead at 320²): every frame made with the history
/// (reprojected with the wind) is within FLIP 0.05 of the full march of
/// its instant; the amortised frame without history is printed beside.
#[test]
fn wind_reprojection_stays_within_flip_005_of_the_full_march() {
    let (n, frames, step, wind) = (320, 5, 4, 15.0);
    let mut r = CpuRenderer::new(None);
    let mut worst: f64 = 0.0;
    let (mut reused, mut marched) = (0, 0);
    for k in 0..frames {
        let s = scene(n, 4, &utc(k, step), wind);
        let (img, used) = render(&mut r, &s);
        let used = used.expect("history use");
        if k == 0 {
            assert_eq!(used.miss, Some(HistoryMiss::First));
            continue;
        }
        assert_eq!((used.miss, used.light_moved), (None, 0));
        assert!(used.reused > 0, "frame {k}: {used:?}");
        reused += used.reused;
        marched += used.marched;
        let full = alone(&scene(n, 1, &utc(k, step), wind));
        let fresh = alone(&scene(n, 4, &utc(k, step), wind));
        let f = flip(&rgb(&img), &rgb(&full), None);
        let f_fresh = flip(&rgb(&fresh), &rgb(&full), None);
        eprintln!(
            "wind 15 m/s, 4 s per frame, fisheye 320², frame {k}: {} nodes reused, {} marched; \
             FLIP against the full march {f:.4} with the history, {f_fresh:.4} amortised without it",
            used.reused, used.marched
        );
        worst = worst.max(f);
    }
    let share = reused as f64 / (reused + marched) as f64;
    eprintln!(
        "frames 1–{}: {:.0} % of the coarse nodes reused; largest FLIP {worst:.4}",
        frames - 1,
        share * 100.0
    );
    assert!(worst <= 0.05, "FLIP {worst:.4}");
    assert!(share >= 0.4, "only {:.0} % reused", share * 100.0);
}

/// The history is used only when the frame can use it, and says why not.
#[test]
fn the_history_is_dropped_when_the_frame_changes() {
    let n = 48;
    let mut r = CpuRenderer::new(None);
    let base = scene(n, 4, &utc(0, 10), 0.0);
    let miss = |r: &mut CpuRenderer, s: &Scene| render(r, s).1.expect("history use").miss;
    assert_eq!(miss(&mut r, &base), Some(HistoryMiss::First));
    assert_eq!(miss(&mut r, &base), None);
    let mut bigger = base.clone();
    bigger.camera.width = n + 8;
    bigger.camera.height = n + 8;
    assert_eq!(miss(&mut r, &bigger), Some(HistoryMiss::Resized));
    assert_eq!(miss(&mut r, &bigger), None);
    let mut turned = bigger.clone();
    turned.camera.projection = Projection::Equirect;
    assert_eq!(miss(&mut r, &turned), Some(HistoryMiss::CameraMoved));
    let mut denser = turned.clone();
    denser.clouds.low.coverage = 0.7;
    assert_eq!(miss(&mut r, &denser), Some(HistoryMiss::LayerChanged));
    // A Sun an hour later: the history serves, but the nodes that would
    // come from it were marched under a Sun 10° away; only rays that never
    // meet the layer (below the horizon) keep their (clear) value, so a
    // camera looking up reuses nothing.
    let mut later = denser.clone();
    later.time.utc = "2024-06-21T09:00:00Z".into();
    let used = render(&mut r, &later).1.expect("history use");
    assert_eq!(used.miss, None, "{used:?}");
    assert!(used.light_moved > 0, "{used:?}");
    let mut sky = later.clone();
    sky.time.utc = "2024-06-21T10:00:00Z".into();
    sky.camera.projection = Projection::Perspective;
    sky.camera.pitch_deg = 60.0;
    sky.camera.fov_deg = 50.0;
    assert_eq!(miss(&mut r, &sky), Some(HistoryMiss::CameraMoved));
    sky.time.utc = "2024-06-21T11:00:00Z".into();
    let used = render(&mut r, &sky).1.expect("history use");
    assert_eq!((used.miss, used.reused), (None, 0), "{used:?}");
    // A frame without the amortised march reports no history and ends
    // the sequence: the next starts afresh; so does one after
    // `clear_cloud_history`.
    let mut full = sky.clone();
    full.clouds.low.march_stride = 1;
    assert_eq!(render(&mut r, &full).1, None);
    assert_eq!(miss(&mut r, &sky), Some(HistoryMiss::First));
    assert_eq!(miss(&mut r, &sky), None);
    r.clear_cloud_history();
    assert_eq!(miss(&mut r, &sky), Some(HistoryMiss::First));
    // `clouds.low.reproject` false: no history, each frame the same image
    // as a renderer of its own draws; turned on again, it starts afresh.
    let mut off = sky.clone();
    off.clouds.low.reproject = false;
    for _ in 0..2 {
        let (img, used) = render(&mut r, &off);
        assert_eq!(used, None);
        assert_eq!(img.pixels, alone(&off).pixels);
    }
    assert_eq!(miss(&mut r, &sky), Some(HistoryMiss::First));
}
