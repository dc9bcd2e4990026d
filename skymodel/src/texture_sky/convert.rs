//! Conversion between mappings (e.g. an equirect photograph to a
//! uniform-density cube map) and the integrals a texture is judged by:
//! its solid-angle-weighted mean radiance and its horizontal illuminance.

use glam::DVec3;
use rayon::prelude::*;

use super::{LinearImage, Mapping, SkyTexture};
use crate::projection::enu_from_alt_az;
use crate::spectrum::luminance;

/// Sub-samples per texel side of [`convert`].
pub const CONVERT_SUBSAMPLES: u32 = 3;

/// `source` resampled into mapping `to` with `size` texels per tile side
/// (a cube's face size; a polar image's side; a paraboloid's half; a
/// sphere's height, twice as wide): each target texel is the mean of 3 × 3
/// bilinear lookups of the source at its sub-texel directions, so the
/// solid-angle-weighted mean radiance is kept (the test
/// `conversion_keeps_the_mean_radiance`). Texels outside the target's
/// domain (polar corners, outside the paraboloid disks) take the values
/// their refill would give them.
pub fn convert(source: &SkyTexture, to: Mapping, size: u32) -> LinearImage {
    let size = size.max(2);
    let (w, h) = match to {
        Mapping::Polar => (size, size),
        Mapping::Sphere => (2 * size, size),
        Mapping::Paraboloid => (2 * size, size),
        Mapping::Cube | Mapping::CubeUniform => (6 * size, size),
    };
    let n = CONVERT_SUBSAMPLES;
    let tile_w = to.tiles(w, h).1;
    let texels = (0..w * h)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % w, k / w);
            let tile = Some(i / tile_w);
            let mut acc = [0.0f64; 3];
            let mut count = 0.0;
            for a in 0..n {
                for b in 0..n {
                    let x = f64::from(i) + (f64::from(a) + 0.5) / f64::from(n);
                    let y = f64::from(j) + (f64::from(b) + 0.5) / f64::from(n);
                    let Some(mut d) = to.pixel_to_dir_in(tile, x, y, w, h) else {
                        continue;
                    };
                    if to == Mapping::Polar {
                        d.z = d.z.abs();
                    }
                    let c = source.sample(d);
                    for (s, v) in acc.iter_mut().zip(c) {
                        *s += f64::from(v);
                    }
                    count += 1.0;
                }
            }
            let count: f64 = if count > 0.0 { count } else { 1.0 };
            acc.map(|s| (s / count) as f32)
        })
        .collect();
    LinearImage {
        width: w,
        height: h,
        texels,
    }
}

/// The solid-angle-weighted mean radiance (linear RGB) of `image` under
/// `mapping` over the texels in its domain ([`Mapping::texel_in_domain`]),
/// and the solid angle they cover (sr).
pub fn mean_radiance(mapping: Mapping, image: &LinearImage) -> ([f64; 3], f64) {
    let (w, h) = (image.width, image.height);
    let (sum, omega) = (0..w * h)
        .into_par_iter()
        .filter(|k| mapping.texel_in_domain(k % w, k / w, w, h))
        .map(|k| {
            let o = mapping.texel_solid_angle(k % w, k / w, w, h);
            let t = image.texels.get(k as usize).copied().unwrap_or_default();
            (t.map(|v| f64::from(v) * o), o)
        })
        .reduce(
            || ([0.0; 3], 0.0),
            |(a, oa), (b, ob)| ([a[0] + b[0], a[1] + b[1], a[2] + b[2]], oa + ob),
        );
    let o = if omega > 0.0 { omega } else { 1.0 };
    (sum.map(|s| s / o), omega)
}

/// Altitude rows and azimuth columns of [`horizontal_illuminance`].
pub const ILLUMINANCE_GRID: (u32, u32) = (90, 360);

/// The horizontal illuminance (lx) of the radiance `radiance(d)` (cd/m²,
/// linear RGB → luminance) of the upper hemisphere: ∫ L(d) sin h dΩ over
/// altitudes h > 0, by the midpoint rule on a 90 × 360 grid of 1° cells
/// (each cell's exact solid angle times sin h at its centre).
pub fn horizontal_illuminance(radiance: impl Fn(DVec3) -> [f32; 3] + Sync) -> f64 {
    let (rows, cols) = ILLUMINANCE_GRID;
    let dh = std::f64::consts::FRAC_PI_2 / f64::from(rows);
    let da = std::f64::consts::TAU / f64::from(cols);
    (0..rows)
        .into_par_iter()
        .map(|r| {
            let (h0, h1) = (f64::from(r) * dh, f64::from(r + 1) * dh);
            let h = 0.5 * (h0 + h1);
            let omega = da * (h1.sin() - h0.sin());
            let row: f64 = (0..cols)
                .map(|c| {
                    let az = (f64::from(c) + 0.5) * da;
                    f64::from(luminance(radiance(enu_from_alt_az(h, az))))
                })
                .sum();
            row * omega * h.sin()
        })
        .sum()
}
