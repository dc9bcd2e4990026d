//! Frame-to-frame change of a sequence over clouds (the flicker checks of
//! `cloud_amortised` and `cloud_temporal`).

use himmel_skymodel::spectrum::luminance;
use himmel_skymodel::HdrImage;

/// The relative luminance change from `a` to `b` at each pixel the
/// clouds change (where `a` differs from `clear` by more than 1 %).
pub fn changes(a: &HdrImage, b: &HdrImage, clear: &HdrImage) -> Vec<Option<f64>> {
    let y = |p: [f32; 3]| f64::from(luminance(p));
    a.pixels
        .iter()
        .zip(&b.pixels)
        .zip(&clear.pixels)
        .map(|((p, q), c)| {
            ((y(*p) - y(*c)).abs() > 0.01 * y(*c).max(1e-9))
                .then(|| (y(*q) - y(*p)) / y(*p).max(1e-9))
        })
        .collect()
}

/// The 99th percentile of `v` (NaN when empty).
pub fn p99(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() * 99 / 100).copied().unwrap_or(f64::NAN)
}
