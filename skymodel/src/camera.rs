//! The camera model that turns absolute linear radiance (cd/m²) into a
//! display image: night vision → exposure → tone curve → sRGB → dither.
//!
//! * **Metering** (`exposure: "auto"`): the geometric mean luminance L̄ of
//!   the image pixels that show sky or ground (black outside-of-projection
//!   pixels excluded), EV100 = log2(L̄ · S / K) with S = 100, K = 12.5
//!   (ISO 2720 reflected-light calibration), clamped to [−6, 18] so that a
//!   moonless night stays dark instead of being lifted to grey.
//! * **Exposure**: H = L / (1.2 · 2^EV100) (saturation-based sensitivity,
//!   ISO 12232; Lagarde & de Rousiers 2014, "Moving Frostbite to PBR", §4.4).
//! * **Night vision** (only here, never in the physics): scotopic luminance
//!   V = Y (1.33 (1 + (Y + Z)/X) − 1.68) (Larson, Rushmeier & Piatko 1997,
//!   eq. 2); a mesopic weight s = smoothstep(log10 Y; −2, 0.5) blends the
//!   photopic colour (s = 1, above ≈ 3 cd/m²) with a desaturated, blue-shifted
//!   rod image V · (0.85, 0.97, 1.35) (s = 0, below 0.01 cd/m²), following
//!   Jensen et al. 2000, "Night rendering", §4.
//! * **Tone curve**: the ACES filmic fit of Narkowicz (2015),
//!   f(x) = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1].
//! * **Encoding**: sRGB transfer function (IEC 61966-2-1), then 8-bit
//!   quantisation with an 8×8 ordered (Bayer) dither against banding.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::spectrum::{linear_srgb_to_xyz, luminance};

mod rows;

/// Exposure: automatic metering or a fixed EV100.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Exposure {
    /// Metered from the image (see the module documentation).
    #[default]
    Auto,
    /// Fixed exposure value at ISO 100.
    Ev100(f64),
}

impl Exposure {
    /// Parses `auto` or a number.
    pub fn parse(s: &str) -> Option<Self> {
        let t = s.trim();
        if t.eq_ignore_ascii_case("auto") {
            return Some(Exposure::Auto);
        }
        t.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && (-30.0..=40.0).contains(v))
            .map(Exposure::Ev100)
    }
}

impl Serialize for Exposure {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Exposure::Auto => s.serialize_str("auto"),
            Exposure::Ev100(v) => s.serialize_f64(*v),
        }
    }
}

impl<'de> Deserialize<'de> for Exposure {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = Exposure;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"auto\" or an EV100 number in [-30, 40]")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Exposure, E> {
                if v.eq_ignore_ascii_case("auto") {
                    Ok(Exposure::Auto)
                } else {
                    Err(E::invalid_value(serde::de::Unexpected::Str(v), &self))
                }
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Exposure, E> {
                if v.is_finite() && (-30.0..=40.0).contains(&v) {
                    Ok(Exposure::Ev100(v))
                } else {
                    Err(E::invalid_value(serde::de::Unexpected::Float(v), &self))
                }
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Exposure, E> {
                self.visit_f64(v as f64)
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Exposure, E> {
                self.visit_f64(v as f64)
            }
        }
        d.deserialize_any(V)
    }
}

/// Lowest and highest EV100 that auto exposure chooses.
pub const AUTO_EV_RANGE: (f64, f64) = (-6.0, 18.0);

/// EV100 metered from linear sRGB pixels (cd/m²); `valid` marks pixels
/// that show the scene.
pub fn meter_ev100(pixels: &[[f32; 3]], valid: &[bool]) -> f64 {
    use rayon::prelude::*;
    // Fixed chunks on all cores, their sums added in order: the same
    // result on any number of threads.
    const CHUNK: usize = 1 << 14;
    let parts: Vec<(f64, usize)> = pixels
        .par_chunks(CHUNK)
        .zip(valid.par_chunks(CHUNK))
        .map(|(pixels, valid)| {
            let mut sum = 0.0f64;
            let mut n = 0usize;
            // Runs of one luminance (the ground, a black sky) take the
            // logarithm once: the same terms, in the same order.
            let mut last = (f32::NAN.to_bits(), 0.0f64);
            for (p, &v) in pixels.iter().zip(valid) {
                if v {
                    let y = luminance(*p).max(1e-9);
                    if y.to_bits() != last.0 {
                        last = (y.to_bits(), (y as f64).ln());
                    }
                    sum += last.1;
                    n += 1;
                }
            }
            (sum, n)
        })
        .collect();
    let (sum, n) = parts
        .iter()
        .fold((0.0f64, 0usize), |(s, n), &(a, b)| (s + a, n + b));
    let mean = if n > 0 { (sum / n as f64).exp() } else { 1e-9 };
    (mean * 100.0 / 12.5)
        .log2()
        .clamp(AUTO_EV_RANGE.0, AUTO_EV_RANGE.1)
}

/// Scotopic luminance of linear sRGB (Larson et al. 1997, eq. 2).
pub fn scotopic_luminance(rgb: [f32; 3]) -> f32 {
    let [x, y, z] = linear_srgb_to_xyz([rgb[0] as f64, rgb[1] as f64, rgb[2] as f64]);
    if x <= 0.0 || y <= 0.0 {
        return y.max(0.0) as f32;
    }
    (y * (1.33 * (1.0 + (y + z) / x) - 1.68)).max(0.0) as f32
}

/// The mesopic blend weight of photopic vision at luminance `y` (cd/m²):
/// the smoothstep of t = clamp((log10 Y + 2) / 2.5, 0, 1), without the
/// logarithm where the clamp decides (log10 3.17 = 0.501, log10 0.0099 =
/// −2.004).
#[inline]
fn photopic_weight(y: f32, log10: impl Fn(f32) -> f32) -> f32 {
    let t = if y >= 3.17 {
        1.0
    } else if y <= 0.0099 {
        0.0
    } else {
        ((log10(y) + 2.0) / 2.5).clamp(0.0, 1.0)
    };
    t * t * (3.0 - 2.0 * t)
}

/// Blue-shifted rod tint (linear sRGB; divided by its luminance below).
const ROD_TINT: [f32; 3] = [0.85, 0.97, 1.35];

/// Night vision: the mesopic blend of photopic colour and the rod image
/// (the reference: scotopic luminance in `f64`, the library's `log10`).
pub fn night_vision_reference(rgb: [f32; 3]) -> [f32; 3] {
    let s = photopic_weight(luminance(rgb), |y| y.max(1e-12).log10());
    if s >= 1.0 {
        return rgb;
    }
    let v = scotopic_luminance(rgb);
    let tl = luminance(ROD_TINT);
    let mut out = [0.0; 3];
    for k in 0..3 {
        out[k] = s * rgb[k] + (1.0 - s) * v * ROD_TINT[k] / tl;
    }
    out
}

/// [`night_vision_reference`] in `f32` for the camera stage: the scotopic
/// luminance (Larson et al. 1997, eq. 2) from the same XYZ matrix in `f32`,
/// the logarithm of [`log10_mesopic`]; within 2 × 10⁻⁶ of the reference
/// relative to the pixel's largest channel (test
/// `night_vision_matches_its_reference`), far below an 8-bit level.
#[inline]
pub fn night_vision(rgb: [f32; 3]) -> [f32; 3] {
    let s = photopic_weight(luminance(rgb), log10_mesopic);
    if s >= 1.0 {
        return rgb;
    }
    let [r, g, b] = rgb;
    let x = 0.412_456_4 * r + 0.357_576_1 * g + 0.180_437_5 * b;
    let y = 0.212_672_9 * r + 0.715_152_2 * g + 0.072_175_0 * b;
    let z = 0.019_333_9 * r + 0.119_192 * g + 0.950_304_1 * b;
    let v = if x <= 0.0 || y <= 0.0 {
        y.max(0.0)
    } else {
        (y * (1.33 * (1.0 + (y + z) / x) - 1.68)).max(0.0)
    };
    let tl = luminance(ROD_TINT);
    let k = (1.0 - s) * v;
    [
        s * r + k * (ROD_TINT[0] / tl),
        s * g + k * (ROD_TINT[1] / tl),
        s * b + k * (ROD_TINT[2] / tl),
    ]
}

/// log10 of a positive normal `f32` (the mesopic range 0.0099–3.17 and
/// beyond), within 4 × 10⁻⁷ of the exact value (2 ulp at 10⁻³): y = 2ᵉ · m with
/// m ∈ [√½, √2), ln m = 2 atanh z with z = (m − 1)/(m + 1), |z| ≤ 0.172,
/// by its series to z⁷ (the next term, 2z⁹/9, is below 3 × 10⁻⁸).
#[inline]
pub fn log10_mesopic(y: f32) -> f32 {
    let bits = y.to_bits();
    let mut e = ((bits >> 23) & 0xff) as i32 - 127;
    let mut m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    if m > std::f32::consts::SQRT_2 {
        m *= 0.5;
        e += 1;
    }
    let z = (m - 1.0) / (m + 1.0);
    let z2 = z * z;
    let ln_m = 2.0 * z * (1.0 + z2 * (1.0 / 3.0 + z2 * (0.2 + z2 * (1.0 / 7.0))));
    (e as f32 * std::f32::consts::LN_2 + ln_m) * std::f32::consts::LOG10_E
}

/// The ACES filmic tone curve fit of Narkowicz (2015).
#[inline]
pub fn aces_filmic(x: f32) -> f32 {
    // The curve tends to 1.033 and is clamped; large inputs are capped
    // before squaring so that they cannot overflow.
    let x = x.clamp(0.0, 1e4);
    (x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// The sRGB transfer function (IEC 61966-2-1).
#[inline]
pub fn srgb_encode(x: f32) -> f32 {
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// The sRGB transfer function's inverse (IEC 61966-2-1): an encoded value
/// in [0, 1] → linear.
pub fn srgb_decode(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// 8×8 Bayer matrix.
const BAYER8: [[u8; 8]; 8] = [
    [0, 32, 8, 40, 2, 34, 10, 42],
    [48, 16, 56, 24, 50, 18, 58, 26],
    [12, 44, 4, 36, 14, 46, 6, 38],
    [60, 28, 52, 20, 62, 30, 54, 22],
    [3, 35, 11, 43, 1, 33, 9, 41],
    [51, 19, 59, 27, 49, 17, 57, 25],
    [15, 47, 7, 39, 13, 45, 5, 37],
    [63, 31, 55, 23, 61, 29, 53, 21],
];

/// Camera settings applied by [`develop`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSettings {
    /// Exposure.
    pub exposure: Exposure,
    /// Night vision on/off.
    pub night_vision: bool,
    /// Ordered dithering on/off.
    pub dither: bool,
}

/// The EV100 the settings choose for an image (metered or fixed).
pub fn exposure_ev100(pixels: &[[f32; 3]], valid: &[bool], settings: &CameraSettings) -> f64 {
    match settings.exposure {
        Exposure::Auto => meter_ev100(pixels, valid),
        Exposure::Ev100(v) => v,
    }
}

/// Exposure scale of an EV100: H = L / (1.2 · 2^EV100).
pub fn exposure_scale(ev100: f64) -> f32 {
    (1.0 / (1.2 * 2f64.powf(ev100))) as f32
}

/// Develops one pixel (linear sRGB, cd/m²) at image position (x, y) with
/// exposure scale `k` into 8-bit sRGB.
#[inline]
pub fn develop_pixel(
    rgb: [f32; 3],
    x: usize,
    y: usize,
    k: f32,
    settings: &CameraSettings,
) -> [u8; 3] {
    develop_with(ToneTable::get(), rgb, x, y, k, settings)
}

/// [`develop_pixel`] with the tone table given.
#[inline]
fn develop_with(
    table: &ToneTable,
    rgb: [f32; 3],
    x: usize,
    y: usize,
    k: f32,
    settings: &CameraSettings,
) -> [u8; 3] {
    let rgb = if settings.night_vision {
        night_vision(rgb)
    } else {
        rgb
    };
    let d = if settings.dither {
        BAYER8[y & 7][x & 7] as usize
    } else {
        UNDITHERED
    };
    [
        table.quantize(rgb[0] * k, d),
        table.quantize(rgb[1] * k, d),
        table.quantize(rgb[2] * k, d),
    ]
}

/// Develops image row `y` ([`develop_pixel`] of each pixel) into `out`
/// (RGB, 3 bytes a pixel); pixels not `valid` stay as they are. With night
/// vision a block of pixels at a time ([`rows`]: the same bytes).
pub fn develop_row(
    pixels: &[[f32; 3]],
    valid: &[bool],
    y: usize,
    k: f32,
    settings: &CameraSettings,
    out: &mut [u8],
) {
    if settings.night_vision {
        return rows::develop_row_night(pixels, valid, y, k, settings.dither, out);
    }
    let table = ToneTable::get();
    for (x, ((p, &v), o)) in pixels
        .iter()
        .zip(valid)
        .zip(out.chunks_exact_mut(3))
        .enumerate()
    {
        if v {
            o.copy_from_slice(&develop_with(table, *p, x, y, k, settings));
        }
    }
}

/// The dither offset of Bayer level `d` (0–63), or ½ for [`UNDITHERED`].
fn dither_offset(d: usize) -> f32 {
    if d < 64 {
        (d as f32 + 0.5) / 64.0
    } else {
        0.5
    }
}

/// The dither index of an undithered pixel.
const UNDITHERED: usize = 64;

/// One exposed channel value `x` through the tone curve, the sRGB
/// encoding and the 8-bit quantisation with dither offset `d`.
#[inline]
pub fn tone_quantize(x: f32, d: f32) -> u8 {
    let v = srgb_encode(aces_filmic(x));
    (v * 255.0 + d).floor().clamp(0.0, 255.0) as u8
}

/// [`tone_quantize`] as a table: for each dither level, the smallest
/// exposed value that reaches each 8-bit level; counting the thresholds at
/// or below x costs eight comparisons instead of a power function per
/// channel. The function is non-decreasing in x except for f32 rounding:
/// within a few ulps of some thresholds its evaluation steps back and forth
/// between two levels (110 such steps over all of 10⁻⁶ … 10⁴ for one
/// dither level, the widest zone 94 ulps). The table is its monotone form:
/// the same level everywhere else, one level apart inside those zones (NaN
/// and negative values give 0, as the function does). The test
/// `tone_table_equals_the_function` checks it around every threshold.
#[derive(Debug)]
pub struct ToneTable {
    /// Per dither index (64 Bayer levels, then [`UNDITHERED`]): the
    /// threshold of level q at index q − 1; from index 255 on NaN (never
    /// reached).
    thresholds: Vec<[f32; LEVELS_PADDED]>,
    /// The bucket index ([`BUCKET_SHIFT`]) of the first bucket.
    bucket0: u32,
    /// Per bucket of exposed values: a level at or below the level of
    /// every value in the bucket, for every dither index.
    start: Vec<u8>,
    /// Whether [`BUCKET_STEPS`] comparisons above `start` decide every
    /// bucket for every dither index (and the thresholds are sorted);
    /// otherwise the binary search decides.
    bucketed: bool,
}

/// Buckets of exposed values by their `f32` bit pattern (ordered as the
/// values for x ≥ 0): 2²³⁻¹⁷ = 64 buckets per octave, about one 8-bit
/// level per bucket where the levels are densest.
const BUCKET_SHIFT: u32 = 17;

/// Thresholds per dither index: levels 1–255, then NaN up to
/// [`BUCKET_STEPS`] past the last.
const LEVELS_PADDED: usize = 256 + BUCKET_STEPS;

/// Thresholds compared above a bucket's first level: the most levels any
/// bucket spans for some dither index (3 with the curve and buckets here;
/// the table falls back to the binary search if it ever needs more).
const BUCKET_STEPS: usize = 3;

impl ToneTable {
    /// The table, computed on first use (a few milliseconds, one thread).
    pub fn get() -> &'static ToneTable {
        static CELL: std::sync::OnceLock<ToneTable> = std::sync::OnceLock::new();
        CELL.get_or_init(ToneTable::new)
    }

    /// Serial on purpose: the first caller may be a rayon task (the PNG
    /// rows), and a parallel initialiser could then steal another row's
    /// task on the same thread and re-enter the initialisation.
    fn new() -> ToneTable {
        let thresholds: Vec<[f32; LEVELS_PADDED]> = (0..=UNDITHERED)
            .map(|di| {
                let d = dither_offset(di);
                let mut t = [f32::NAN; LEVELS_PADDED];
                for q in 1..=255u8 {
                    t[q as usize - 1] = threshold(q, d);
                }
                t
            })
            .collect();
        let sorted = thresholds.iter().all(|t| {
            let n = t.iter().take_while(|v| !v.is_nan()).count();
            t[..n].windows(2).all(|p| p[0] <= p[1]) && t[n..].iter().all(|v| v.is_nan())
        });
        let lowest = thresholds
            .iter()
            .flat_map(|t| t.iter())
            .filter(|v| **v > 0.0)
            .fold(f32::INFINITY, |m, &v| m.min(v));
        let bucket0 = lowest.min(1e4).to_bits() >> BUCKET_SHIFT;
        let buckets = ((1e4f32.to_bits() >> BUCKET_SHIFT) - bucket0 + 1) as usize;
        let mut start = vec![0u8; buckets];
        let mut steps = 0usize;
        for (k, s) in start.iter_mut().enumerate() {
            let edge = |k: u32| f32::from_bits((bucket0 + k) << BUCKET_SHIFT);
            let lo = if k == 0 { 0.0 } else { edge(k as u32) };
            let hi = if k + 1 == buckets {
                f32::INFINITY
            } else {
                f32::from_bits(edge(k as u32 + 1).to_bits() - 1)
            };
            let count = |x: f32| thresholds.iter().map(move |t| search(t, x));
            let first = count(lo).min().unwrap_or(0);
            *s = first;
            let most = count(hi).max().unwrap_or(0);
            steps = steps.max((most - first) as usize);
        }
        ToneTable {
            thresholds,
            bucket0,
            start,
            bucketed: sorted && steps <= BUCKET_STEPS,
        }
    }

    /// [`tone_quantize`]`(x, d)` for dither index `d` (Bayer level 0–63,
    /// or 64 for no dither): the number of thresholds at or below x, from
    /// its bucket's first level and a few comparisons (equal to the binary
    /// search [`Self::quantize_search`]; test `tone_buckets_equal_the_search`).
    #[inline(always)]
    pub fn quantize(&self, x: f32, d: usize) -> u8 {
        let t = &self.thresholds[d.min(UNDITHERED)];
        if !self.bucketed {
            return search(t, x);
        }
        // Negative values and NaN are below every threshold; −0 is 0.
        let bits = if x > 0.0 {
            x.to_bits()
        } else if x == 0.0 {
            0
        } else {
            return 0;
        };
        let k = ((bits >> BUCKET_SHIFT).saturating_sub(self.bucket0) as usize)
            .min(self.start.len() - 1);
        // The next BUCKET_STEPS thresholds are sorted: the count of those
        // at or below x is the scan's count, from loads that do not wait
        // on each other (t[255..] is NaN: the level stops at 255).
        let i = self.start[k] as usize;
        let mut q = i;
        for j in 0..BUCKET_STEPS {
            q += usize::from(t[i + j] <= x);
        }
        q as u8
    }

    /// [`Self::quantize`] by a binary search of the thresholds (the
    /// reference of the bucketed form).
    pub fn quantize_search(&self, x: f32, d: usize) -> u8 {
        search(&self.thresholds[d.min(UNDITHERED)], x)
    }
}

/// The number of thresholds at or below x (NaN thresholds, at the end,
/// count as above): a branch-free binary search, t[..i] ≤ x after each
/// step.
#[inline]
fn search(t: &[f32; LEVELS_PADDED], x: f32) -> u8 {
    let mut i = 0usize;
    for step in [128, 64, 32, 16, 8, 4, 2, 1] {
        if t[i + step - 1] <= x {
            i += step;
        }
    }
    i as u8
}

/// The smallest f32 x ≥ 0 with [`tone_quantize`]`(x, d) ≥ q` (NaN if none
/// up to the tone curve's cap): from the curves' inverses in f64, then
/// bracketed and bisected on the f32 bit patterns (ordered as the values
/// for x ≥ 0).
fn threshold(q: u8, d: f32) -> f32 {
    let reaches = |b: u32| tone_quantize(f32::from_bits(b), d) >= q;
    let cap = 1e4f32.to_bits();
    if !reaches(cap) {
        return f32::NAN;
    }
    if reaches(0) {
        return 0.0;
    }
    // The encoded value g·255 + d ≥ q, decoded (sRGB, then the ACES fit's
    // quadratic for x).
    let g = ((q as f64 - d as f64) / 255.0).clamp(0.0, 1.0);
    let l = if g <= 0.040_45 {
        g / 12.92
    } else {
        ((g + 0.055) / 1.055).powf(2.4)
    };
    let (a, b, c) = (2.51 - 2.43 * l, 0.03 - 0.59 * l, -0.14 * l);
    let guess = if a > 0.0 {
        (-b + (b * b - 4.0 * a * c).max(0.0).sqrt()) / (2.0 * a)
    } else {
        1e4
    };
    let start = (guess.clamp(0.0, 1e4) as f32).to_bits();
    // (lo, hi) with !reaches(lo) and reaches(hi), by doubling steps.
    let (mut lo, mut hi) = (start, start);
    let mut step = 1u32;
    if reaches(start) {
        while reaches(lo) {
            hi = lo;
            lo = start.saturating_sub(step);
            step = step.saturating_mul(2);
        }
    } else {
        while !reaches(hi) {
            lo = hi;
            hi = start.saturating_add(step).min(cap);
            step = step.saturating_mul(2);
        }
    }
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if reaches(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    f32::from_bits(hi)
}

/// Develops an HDR image (linear sRGB, cd/m²) into 8-bit sRGB; returns the
/// pixels (RGB, row-major; black where not `valid`) and the EV100 used.
pub fn develop(
    width: usize,
    pixels: &[[f32; 3]],
    valid: &[bool],
    settings: &CameraSettings,
) -> (Vec<u8>, f64) {
    let ev = exposure_ev100(pixels, valid, settings);
    let k = exposure_scale(ev);
    let mut out = vec![0u8; pixels.len() * 3];
    for (i, p) in pixels.iter().enumerate() {
        if valid[i] {
            let (x, y) = (i % width.max(1), i / width.max(1));
            out[i * 3..i * 3 + 3].copy_from_slice(&develop_pixel(*p, x, y, k, settings));
        }
    }
    (out, ev)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exposure_serde_and_parse() {
        assert_eq!(Exposure::parse("auto"), Some(Exposure::Auto));
        assert_eq!(Exposure::parse("-4"), Some(Exposure::Ev100(-4.0)));
        assert_eq!(Exposure::parse("x"), None);
        let j = serde_json::to_string(&Exposure::Ev100(12.5)).unwrap();
        assert_eq!(
            serde_json::from_str::<Exposure>(&j).unwrap(),
            Exposure::Ev100(12.5)
        );
        assert_eq!(
            serde_json::from_str::<Exposure>("\"auto\"").unwrap(),
            Exposure::Auto
        );
        assert!(serde_json::from_str::<Exposure>("\"bright\"").is_err());
        assert!(serde_json::from_str::<Exposure>("true").is_err());
    }

    #[test]
    fn metering_maps_average_to_its_ev() {
        // A uniform 1000 cd/m² field meters at log2(1000 · 8) ≈ 12.97.
        let px = vec![[1000.0f32; 3]; 16];
        let ev = meter_ev100(&px, &[true; 16]);
        assert!((ev - (8000f64).log2()).abs() < 1e-3, "{ev}");
        // Darkness is clamped.
        let px = vec![[1e-6f32; 3]; 4];
        assert_eq!(meter_ev100(&px, &[true; 4]), AUTO_EV_RANGE.0);
    }

    #[test]
    fn tone_curve_and_encoding_are_monotonic_and_bounded() {
        let mut prev = -1.0;
        for i in 0..1000 {
            let x = i as f32 * 0.01;
            let y = srgb_encode(aces_filmic(x));
            assert!((0.0..=1.0).contains(&y) && y >= prev);
            prev = y;
        }
        assert_eq!(aces_filmic(f32::INFINITY.min(1e30)), 1.0);
    }

    #[test]
    fn night_vision_desaturates_only_in_the_dark() {
        let day = [800.0, 900.0, 1200.0];
        assert_eq!(night_vision(day), day);
        let dark = [0.002f32, 0.001, 0.0005];
        let n = night_vision(dark);
        // Blue shift: the rod image is bluer than the input.
        assert!(n[2] > n[0]);
    }

    #[test]
    fn night_vision_matches_its_reference() {
        // The logarithm against f64 over the mesopic range and beyond.
        for i in 0..=200_000 {
            let y = 10f64.powf(-3.0 + 4.0 * i as f64 / 200_000.0) as f32;
            let e = (log10_mesopic(y) as f64 - (y as f64).log10()).abs();
            assert!(e <= 4e-7, "log10({y}): {e}");
        }
        // The blend, over colours and luminances from starlight to dusk.
        let mut worst = 0.0f32;
        for i in 0..400 {
            let y = 10f32.powf(-3.5 + 5.0 * i as f32 / 400.0);
            for (r, g, b) in [
                (1.0, 1.0, 1.0),
                (0.3, 0.6, 1.4),
                (1.5, 0.8, 0.2),
                (0.0, 1.0, 0.5),
            ] {
                let rgb = [r * y, g * y, b * y];
                let (a, b) = (night_vision(rgb), night_vision_reference(rgb));
                let m = a.iter().chain(&b).fold(0.0f32, |m, v| m.max(v.abs()));
                for k in 0..3 {
                    worst = worst.max((a[k] - b[k]).abs() / m);
                }
            }
        }
        assert!(worst <= 2e-6, "{worst}");
    }

    #[test]
    fn tone_buckets_equal_the_search() {
        // Around every threshold of every dither index (±64 ulps), on a
        // log-spaced sweep and at the odd values: the bucketed lookup is
        // the binary search's level, in at most four comparisons.
        let table = ToneTable::get();
        assert!(
            table.bucketed,
            "more than {BUCKET_STEPS} levels in a bucket"
        );
        let mut xs = vec![f32::NAN, -1.0, -0.0, 0.0, f32::INFINITY, 1e4, 1e30];
        xs.push(f32::MIN_POSITIVE);
        xs.extend((0..200_000).map(|i| 10f32.powf(-9.0 + 14.0 * i as f32 / 200_000.0)));
        for (d, t) in table.thresholds.iter().enumerate() {
            let near = t
                .iter()
                .filter(|v| v.is_finite() && **v > 0.0)
                .flat_map(|v| (0..129).map(move |k| f32::from_bits(v.to_bits() + k - 64)));
            for x in xs.iter().copied().chain(near) {
                assert_eq!(table.quantize(x, d), table.quantize_search(x, d), "{x} {d}");
            }
        }
    }

    #[test]
    fn tone_table_equals_the_function() {
        // Around every threshold (±256 ulps) and on a log-spaced sweep of
        // 10⁻⁹ … 10⁵ plus the odd values, for every dither index: the
        // table gives the function's level, except inside the function's
        // rounding zones (within 128 ulps of the threshold of the higher
        // level), where they may be one level apart.
        let table = ToneTable::get();
        let mut odd = vec![
            f32::NAN,
            -1.0,
            -0.0,
            0.0,
            f32::INFINITY,
            1e4,
            1e30,
            f32::MIN_POSITIVE,
        ];
        odd.extend((0..100_000).map(|i| 10f32.powf(-9.0 + 14.0 * i as f32 / 100_000.0)));
        let (mut tried, mut apart) = (0usize, 0usize);
        for di in 0..=UNDITHERED {
            let d = dither_offset(di);
            let t = &table.thresholds[di][..255];
            // Every level is reached, in order.
            assert!(
                t[0] > 0.0 && t.windows(2).all(|w| w[0] < w[1]),
                "dither {di}"
            );
            let mut xs = odd.clone();
            for &t in t {
                let b = t.to_bits();
                xs.extend((b - 256..=b + 256).map(f32::from_bits));
            }
            for x in xs {
                let (a, b) = (table.quantize(x, di), tone_quantize(x, d));
                tried += 1;
                if a != b {
                    apart += 1;
                    let near = t[a.max(b) as usize - 1].to_bits().abs_diff(x.to_bits());
                    assert!(
                        a.abs_diff(b) == 1 && near <= 128,
                        "x {x:e}, dither {di}: {a} vs {b}, {near} ulps from the threshold"
                    );
                }
            }
        }
        // The zones are rare even right at the thresholds.
        assert!(apart * 200 < tried, "{apart} of {tried}");
    }

    #[test]
    fn dither_spreads_quantisation() {
        // A flat field between two 8-bit levels produces both levels.
        let px = vec![[0.2f32; 3]; 64];
        let s = CameraSettings {
            exposure: Exposure::Ev100(-2.0),
            night_vision: false,
            dither: true,
        };
        let (out, _) = develop(8, &px, &[true; 64], &s);
        let min = out.iter().min().unwrap();
        let max = out.iter().max().unwrap();
        assert_eq!(max - min, 1);
    }
}
