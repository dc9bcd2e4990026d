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

/// Over a sequence of `full` frames and the same frames drawn another way
/// (`other`), p99 over the cloud pixels of: the difference of the two
/// frame-to-frame changes (the flicker of its own), the full frames'
/// change and the other frames' change.
pub fn flicker(full: &[HdrImage], other: &[HdrImage], clear: &HdrImage) -> (f64, f64, f64) {
    let (mut flicker, mut change_full, mut change_other) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..full.len().min(other.len()).saturating_sub(1) {
        let f = changes(&full[k], &full[k + 1], clear);
        let a = changes(&other[k], &other[k + 1], clear);
        for (f, a) in f.into_iter().zip(a) {
            if let (Some(f), Some(a)) = (f, a) {
                flicker.push((a - f).abs());
                change_full.push(f.abs());
                change_other.push(a.abs());
            }
        }
    }
    (p99(flicker), p99(change_full), p99(change_other))
}

/// Prints the [`flicker`] figures of `other` against `full` (`what`
/// names the sequence) and asserts the flicker's p99 is at most `bound`
/// (a fraction).
pub fn assert_flicker_at_most(
    what: &str,
    full: &[HdrImage],
    other: &[HdrImage],
    clear: &HdrImage,
    bound: f64,
) {
    let (fl, cf, ca) = flicker(full, other, clear);
    eprintln!(
        "{what}: frame-to-frame change p99 {:.2} % drawn so, {:.2} % full march; \
         flicker (their difference) p99 {:.3} %",
        ca * 100.0,
        cf * 100.0,
        fl * 100.0
    );
    assert!(fl <= bound, "{what}: flicker p99 {:.2} %", fl * 100.0);
}
