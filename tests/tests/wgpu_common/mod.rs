//! Helpers shared by the wgpu test binaries: one renderer per binary, and
//! the image comparisons of the parity tests (relative luminance
//! differences, percentiles, PSNR of the tone-mapped images, star peaks).
#![allow(dead_code)]

use std::sync::{Mutex, OnceLock};

use himmel_skymodel::camera::{develop, CameraSettings, Exposure};
use himmel_skymodel::spectrum::luminance;
use himmel_skymodel::HdrImage;
use himmel_wgpu::WgpuRenderer;

use glam::DVec3;
use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::LutConfig;
use himmel_skymodel::{Effect, Projection, Scene, SkyRenderer, SkyState};

/// The binary's renderer, its low clouds' history forgotten: each
/// `gpu().render(..)` draws a frame of its own (a test of the history
/// holds the guard over its sequence).
pub fn gpu() -> std::sync::MutexGuard<'static, WgpuRenderer> {
    static R: OnceLock<Mutex<WgpuRenderer>> = OnceLock::new();
    let mut r = R
        .get_or_init(|| {
            Mutex::new(WgpuRenderer::new(None).expect("a wgpu adapter (lavapipe in CI)"))
        })
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    r.clear_cloud_history();
    r
}

/// Relative luminance differences over the pixels valid in both images.
pub fn rel_diffs(cpu: &HdrImage, gpu: &HdrImage) -> Vec<f64> {
    let mut d: Vec<f64> = cpu
        .pixels
        .iter()
        .zip(&gpu.pixels)
        .zip(cpu.valid.iter().zip(&gpu.valid))
        .filter(|(_, (a, b))| **a && **b)
        .map(|((c, g), _)| {
            let (yc, yg) = (luminance(*c) as f64, luminance(*g) as f64);
            if yc > 0.0 {
                (yg - yc).abs() / yc
            } else if yg == 0.0 {
                0.0
            } else {
                1.0
            }
        })
        .collect();
    d.sort_by(|a, b| a.total_cmp(b));
    d
}

pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// PSNR (dB) of the developed 8-bit images over the valid pixels.
pub fn psnr(cpu: &HdrImage, gpu: &HdrImage) -> f64 {
    let settings = CameraSettings {
        exposure: Exposure::Auto,
        night_vision: false,
        dither: false,
    };
    let (a, _) = develop(cpu.width, &cpu.pixels, &cpu.valid, &settings);
    let (b, _) = develop(gpu.width, &gpu.pixels, &gpu.valid, &settings);
    let (mut se, mut n) = (0.0f64, 0usize);
    for (i, v) in cpu.valid.iter().enumerate() {
        if *v {
            for c in 0..3 {
                let d = a[3 * i + c] as f64 - b[3 * i + c] as f64;
                se += d * d;
                n += 1;
            }
        }
    }
    if se == 0.0 {
        return f64::INFINITY;
    }
    10.0 * (255.0f64 * 255.0 / (se / n as f64)).log10()
}

/// Pixels that are strict local maxima of luminance (3 × 3) at least
/// `k` × the image's median luminance, brightest first.
pub fn peaks(img: &HdrImage, k: f32) -> Vec<(usize, usize, f32)> {
    let (w, h) = (img.width, img.height);
    let y: Vec<f32> = img.pixels.iter().map(|p| luminance(*p)).collect();
    let mut sorted = y.clone();
    sorted.sort_by(|a, b| a.total_cmp(b));
    let floor = sorted[sorted.len() / 2] * k;
    let mut out = Vec::new();
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            let v = y[j * w + i];
            if v <= floor || !img.valid[j * w + i] {
                continue;
            }
            let local_max = (-1i64..=1).all(|dj| {
                (-1i64..=1).all(|di| {
                    (di == 0 && dj == 0)
                        || y[((j as i64 + dj) as usize) * w + (i as i64 + di) as usize] < v
                })
            });
            if local_max {
                out.push((i, j, v));
            }
        }
    }
    out.sort_by(|a, b| b.2.total_cmp(&a.2));
    out
}

/// Issue 7's parity thresholds on a CPU image `c` and a GPU image `g`: the
/// same valid pixels, median relative luminance difference ≤ 2 %, 99th
/// percentile ≤ 10 %, PSNR of the tone-mapped images ≥ 35 dB. Prints the
/// figures (`-- --nocapture`) under `label` and returns (median, p99, PSNR).
pub fn assert_parity(label: &str, c: &HdrImage, g: &HdrImage) -> (f64, f64, f64) {
    assert_eq!((c.width, c.height), (g.width, g.height), "{label}");
    assert_eq!(c.valid, g.valid, "{label}: valid masks differ");
    let d = rel_diffs(c, g);
    let (med, p99) = (percentile(&d, 0.5), percentile(&d, 0.99));
    let db = psnr(c, g);
    eprintln!(
        "{label}: median |ΔY|/Y {:.4} %, p99 {:.4} %, max {:.3} %, PSNR {db:.1} dB",
        med * 100.0,
        p99 * 100.0,
        d[d.len() - 1] * 100.0
    );
    assert!(med <= 0.02, "{label}: median {med}");
    assert!(p99 <= 0.10, "{label}: p99 {p99}");
    assert!(db >= 35.0, "{label}: PSNR {db} dB");
    (med, p99, db)
}

pub fn scene(utc: &str, p: Projection, w: u32, h: u32) -> Scene {
    let mut s = Scene::default();
    s.time.utc = utc.into();
    s.observer.lat_deg = 48.14;
    s.observer.lon_deg = 11.58;
    s.effects = vec![Effect::Atmosphere, Effect::Sun];
    s.camera.projection = p;
    s.camera.width = w;
    s.camera.height = h;
    s.lut = LutConfig::small();
    s
}

/// Renders `s` through both backends (the wgpu one with its sky view on
/// the GPU and, uploaded, from the CPU), checks the parity figures and
/// returns the CPU image and the GPU-sky-view image.
pub fn parity(name: &str, s: &Scene) -> (HdrImage, HdrImage) {
    let state = SkyState::at(s).unwrap();
    let cpu = CpuRenderer::new(None).render(s, &state).unwrap();
    let c = cpu.image;
    let mut first = None;
    for on_gpu in [false, true] {
        let gpu_out = {
            let mut r = gpu();
            r.set_sky_view_on_gpu(on_gpu);
            let out = r.render(s, &state);
            r.set_sky_view_on_gpu(true);
            out.unwrap()
        };
        let g = gpu_out.image;
        let mode = if on_gpu {
            "GPU sky view"
        } else {
            "CPU sky view"
        };
        let label = format!(
            "{name} ({mode}), Sun alt {:.2}°",
            state.sun.alt_refracted_deg
        );
        assert_parity(&label, &c, &g);
        // The passes that ran have times.
        // (`moon-eclipse` is part of the Moon pass and has no time of its own.)
        for p in gpu_out
            .passes
            .iter()
            .filter(|p| p.ran && p.name != "moon-eclipse")
        {
            assert!(p.ms.is_some_and(|t| t >= 0.0), "{name}: {}", p.name);
        }
        first = Some(g);
    }
    (c, first.unwrap())
}

/// Σ luminance over the pixels within `r` px of the Sun's place.
pub fn sun_sum(img: &HdrImage, s: &Scene, state: &SkyState, r: f64) -> f64 {
    let (sx, sy) = s
        .camera
        .dir_to_pixel(DVec3::from_array(state.sun.enu))
        .unwrap();
    let mut sum = 0.0;
    for (i, p) in img.pixels.iter().enumerate() {
        let (x, y) = ((i % img.width) as f64 + 0.5, (i / img.width) as f64 + 0.5);
        if (x - sx).hypot(y - sy) <= r {
            sum += luminance(*p) as f64;
        }
    }
    sum
}

/// The 200 brightest star peaks of the CPU image (at least 50) are peaks
/// of the GPU image at the same pixel (0 px offset; the acceptance allows
/// 0.5 px).
pub fn same_peaks(name: &str, c: &HdrImage, g: &HdrImage) {
    same_peaks_above(name, c, g, 20.0, 50);
}

/// [`same_peaks`] for the peaks at least `k` × the median luminance, of
/// which there must be `min`.
pub fn same_peaks_above(name: &str, c: &HdrImage, g: &HdrImage, k: f32, min: usize) {
    let pc = peaks(c, k);
    let pg = peaks(g, k);
    assert!(pc.len() >= min, "{name}: {} star peaks", pc.len());
    let mut same = 0;
    for &(i, j, _) in pc.iter().take(200) {
        if pg.iter().any(|q| q.0 == i && q.1 == j) {
            same += 1;
        }
    }
    let n = pc.len().min(200);
    eprintln!(
        "{name}: {} CPU peaks, {} GPU peaks, {same}/{n} brightest at the same pixel",
        pc.len(),
        pg.len()
    );
    assert_eq!(same, n, "{name}");
}

/// The godrays pass's least time over `frames` frames of each scene, the
/// scenes alternating frame by frame, each on a renderer of its own (a
/// device each, so that each keeps its images; the shared renderer's lock
/// keeps the binary's other tests off the device meanwhile), after a
/// first frame each that builds pipelines and light maps; with each
/// scene's last frame.
pub fn alternating_godrays(
    scenes: &[Scene],
    world: &himmel_world::World,
    frames: usize,
) -> Vec<(f64, himmel_skymodel::RenderOutput)> {
    let _device = gpu();
    let state = SkyState::at(&scenes[0]).unwrap();
    let mut renderers: Vec<_> = scenes
        .iter()
        .map(|_| {
            let mut r = WgpuRenderer::new(None).unwrap();
            r.set_world(world);
            r
        })
        .collect();
    let mut least = vec![f64::INFINITY; scenes.len()];
    let mut last = Vec::new();
    for frame in 0..=frames {
        last.clear();
        for ((r, s), t) in renderers.iter_mut().zip(scenes).zip(&mut least) {
            let out = r.render(s, &state).unwrap();
            let p = out.passes.iter().find(|p| p.name == "godrays").unwrap();
            assert!(p.ran, "{p:?}");
            if frame > 0 {
                *t = t.min(p.ms.unwrap_or(f64::NAN));
            }
            last.push(out);
        }
    }
    least.into_iter().zip(last).collect()
}

/// The times alone of `alternating_godrays`.
pub fn alternating_least_ms(
    scenes: &[Scene],
    world: &himmel_world::World,
    frames: usize,
) -> Vec<f64> {
    alternating_godrays(scenes, world, frames)
        .into_iter()
        .map(|(t, _)| t)
        .collect()
}
