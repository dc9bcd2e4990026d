//! Helpers shared by the wgpu test binaries: one renderer per binary, and
//! the image comparisons of the parity tests (relative luminance
//! differences, percentiles, PSNR of the tone-mapped images, star peaks).
#![allow(dead_code)]

use std::sync::{Mutex, OnceLock};

use himmel_skymodel::camera::{develop, CameraSettings, Exposure};
use himmel_skymodel::spectrum::luminance;
use himmel_skymodel::HdrImage;
use himmel_wgpu::WgpuRenderer;

pub fn gpu() -> std::sync::MutexGuard<'static, WgpuRenderer> {
    static R: OnceLock<Mutex<WgpuRenderer>> = OnceLock::new();
    R.get_or_init(|| Mutex::new(WgpuRenderer::new(None).expect("a wgpu adapter (lavapipe in CI)")))
        .lock()
        .unwrap_or_else(|e| e.into_inner())
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
