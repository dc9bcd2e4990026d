//! Image metrics for comparing a world render with its Mitsuba 3 reference.
//!
//! * Images are linear RGB radiance in cd/m² (linear sRGB primaries), read
//!   from OpenEXR (RGB or RGBA, half or float, any compression the `exr`
//!   crate reads; alpha is dropped). Luminance Y = 0.2126 R + 0.7152 G +
//!   0.0722 B.
//! * Masks come from `<case>_mask.exr` (`tools/world_reference.py`): channel
//!   R ([`SUNLIT`]) = directly lit by the Sun (the Moon at night), G
//!   ([`SKYLIT`]) = geometry present but not directly lit (lit by the sky
//!   alone), B ([`GEOMETRY`]) = geometry present; each 0 or 1 and already
//!   eroded by one pixel at geometry and shadow edges.
//! * [`mean_relative_error`] is the luminance-weighted relative error
//!   mean|ΔY| / mean Y_ref over the mask (why: see there);
//!   [`pixel_relative_error`] is the plain mean of per-pixel |ΔY| / Y_ref.
//! * [`flip`] is NVIDIA's FLIP (LDR, `nv-flip`) between the two images after
//!   the same fixed tone map ([`tone_map`]): exposure from the *reference's*
//!   median luminance, then the sRGB transfer curve.

use std::path::Path;

/// Mask channel: directly lit by the Sun (or the Moon at night).
pub const SUNLIT: usize = 0;
/// Mask channel: geometry present but not directly lit (sky light alone).
pub const SKYLIT: usize = 1;
/// Mask channel: geometry present.
pub const GEOMETRY: usize = 2;

/// Luminance weights of linear sRGB (Rec. 709) primaries.
pub const Y_WEIGHTS: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// A linear RGB image, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct RgbImage {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Linear RGB per pixel.
    pub pixels: Vec<[f32; 3]>,
}

/// A render's RGB pixels (its validity mask dropped: the references cover
/// every pixel).
impl From<himmel_skymodel::HdrImage> for RgbImage {
    fn from(image: himmel_skymodel::HdrImage) -> Self {
        RgbImage {
            width: image.width,
            height: image.height,
            pixels: image.pixels,
        }
    }
}

impl RgbImage {
    /// An image of `width` × `height` pixels from a function of (x, y).
    pub fn from_fn(width: usize, height: usize, f: impl Fn(usize, usize) -> [f32; 3]) -> Self {
        let pixels = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect();
        RgbImage {
            width,
            height,
            pixels,
        }
    }

    /// Each pixel's luminance Y.
    pub fn luminance(&self) -> Vec<f64> {
        self.pixels.iter().map(|p| luminance(*p)).collect()
    }

    /// The image with every pixel mapped by `f`.
    pub fn map(&self, f: impl Fn([f32; 3]) -> [f32; 3]) -> Self {
        RgbImage {
            pixels: self.pixels.iter().map(|p| f(*p)).collect(),
            ..*self
        }
    }
}

/// Luminance Y of a linear sRGB pixel.
pub fn luminance(p: [f32; 3]) -> f64 {
    Y_WEIGHTS.iter().zip(p).map(|(w, c)| w * f64::from(c)).sum()
}

/// Reads an RGB(A) OpenEXR file as linear RGB (alpha dropped).
pub fn read_exr(path: impl AsRef<Path>) -> Result<RgbImage, String> {
    let path = path.as_ref();
    let img = image::ImageReader::open(path)
        .map_err(|e| format!("{}: {e}", path.display()))?
        .with_guessed_format()
        .map_err(|e| format!("{}: {e}", path.display()))?
        .decode()
        .map_err(|e| format!("{}: {e}", path.display()))?
        .into_rgb32f();
    let (width, height) = (img.width() as usize, img.height() as usize);
    let pixels = img.pixels().map(|p| p.0).collect();
    Ok(RgbImage {
        width,
        height,
        pixels,
    })
}

/// One channel ([`SUNLIT`], [`SKYLIT`] or [`GEOMETRY`]) of a mask image as
/// booleans (value > 0.5).
pub fn mask_channel(mask: &RgbImage, channel: usize) -> Vec<bool> {
    mask.pixels.iter().map(|p| p[channel] > 0.5).collect()
}

/// Reads channel `channel` of `<case>_mask.exr`.
pub fn read_mask(path: impl AsRef<Path>, channel: usize) -> Result<Vec<bool>, String> {
    Ok(mask_channel(&read_exr(path)?, channel))
}

fn check_sizes(test: &RgbImage, reference: &RgbImage, mask: Option<&[bool]>) {
    assert_eq!(
        (test.width, test.height),
        (reference.width, reference.height),
        "test and reference differ in size"
    );
    if let Some(m) = mask {
        assert_eq!(m.len(), reference.pixels.len(), "mask size");
    }
}

/// The luminance-weighted mean relative error over the masked pixels:
/// Σ |Y_test − Y_ref| / Σ Y_ref (= mean |ΔY| / mean Y_ref).
///
/// Chosen over the mean of per-pixel ratios ([`pixel_relative_error`])
/// because that one is dominated by the darkest pixels (deep shadow corners,
/// moonlit interiors), where the reference's own Monte Carlo noise and any
/// small absolute offset blow up |ΔY| / Y_ref, and it is unbounded when
/// Y_ref → 0. This form is bounded by the relative error of the brightest
/// pixels, still exactly |k| for a uniform scale error 1 + k, and its
/// reference noise is the mask's mean noise divided by √N.
///
/// NaN when the mask selects no pixel or the reference is black there.
pub fn mean_relative_error(test: &RgbImage, reference: &RgbImage, mask: &[bool]) -> f64 {
    check_sizes(test, reference, Some(mask));
    let (mut num, mut den) = (0.0, 0.0);
    for ((t, r), _) in test
        .pixels
        .iter()
        .zip(&reference.pixels)
        .zip(mask)
        .filter(|(_, m)| **m)
    {
        let (yt, yr) = (luminance(*t), luminance(*r));
        num += (yt - yr).abs();
        den += yr;
    }
    if den > 0.0 {
        num / den
    } else {
        f64::NAN
    }
}

/// The plain mean over the masked pixels with Y_ref > 0 of
/// |Y_test − Y_ref| / Y_ref (see [`mean_relative_error`] for why that one is
/// preferred). NaN when no pixel qualifies.
pub fn pixel_relative_error(test: &RgbImage, reference: &RgbImage, mask: &[bool]) -> f64 {
    check_sizes(test, reference, Some(mask));
    let (mut sum, mut n) = (0.0, 0usize);
    for ((t, r), _) in test
        .pixels
        .iter()
        .zip(&reference.pixels)
        .zip(mask)
        .filter(|(_, m)| **m)
    {
        let yr = luminance(*r);
        if yr > 0.0 {
            sum += (luminance(*t) - yr).abs() / yr;
            n += 1;
        }
    }
    if n > 0 {
        sum / n as f64
    } else {
        f64::NAN
    }
}

/// The median luminance of the image's pixels with Y > 0 (0 when none).
pub fn median_luminance(img: &RgbImage) -> f64 {
    let mut y: Vec<f64> = img.luminance().into_iter().filter(|y| *y > 0.0).collect();
    if y.is_empty() {
        return 0.0;
    }
    y.sort_by(f64::total_cmp);
    y[y.len() / 2]
}

/// The exposure (a factor on radiance) that maps the reference's median
/// luminance to 0.18 (middle grey); 1 for a black reference.
pub fn exposure_for(reference: &RgbImage) -> f64 {
    let m = median_luminance(reference);
    if m > 0.0 {
        0.18 / m
    } else {
        1.0
    }
}

/// The sRGB transfer curve (IEC 61966-2-1) of a linear value in [0, 1].
pub fn srgb_encode(v: f64) -> f64 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// The display image FLIP compares: radiance × `exposure`, clipped to
/// [0, 1] per channel, sRGB-encoded, 8 bits, RGB interleaved. With
/// `exposure` = [`exposure_for`]`(reference)` the reference's median maps
/// to middle grey, so about 2.5 stops above the median (sunlit patches in
/// shade-dominated views) clip to white: FLIP then judges the shaded and
/// sky-lit parts and the edges, and [`mean_relative_error`] on the
/// [`SUNLIT`] mask judges the sunlit ones.
pub fn tone_map(img: &RgbImage, exposure: f64) -> Vec<u8> {
    img.pixels
        .iter()
        .flat_map(|p| p.map(|c| (srgb_encode(f64::from(c) * exposure) * 255.0).round() as u8))
        .collect()
}

/// FLIP (`nv-flip`, LDR, default pixels per degree: a 24" 4K display at
/// 0.7 m) between `test` and `reference`, both tone-mapped with
/// [`tone_map`] at the reference's exposure: (the per-pixel error map in
/// [0, 1], row-major).
pub fn flip_map(test: &RgbImage, reference: &RgbImage) -> Vec<f32> {
    check_sizes(test, reference, None);
    let k = exposure_for(reference);
    let (w, h) = (reference.width as u32, reference.height as u32);
    let r = nv_flip::FlipImageRgb8::with_data(w, h, &tone_map(reference, k));
    let t = nv_flip::FlipImageRgb8::with_data(w, h, &tone_map(test, k));
    nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec()
}

/// The mean FLIP error (see [`flip_map`]) over the masked pixels, or over
/// the whole image with `mask` = `None`.
pub fn flip(test: &RgbImage, reference: &RgbImage, mask: Option<&[bool]>) -> f64 {
    check_sizes(test, reference, mask);
    let map = flip_map(test, reference);
    let (sum, n) = map
        .iter()
        .enumerate()
        .filter(|(i, _)| match mask {
            Some(m) => m[*i],
            None => true,
        })
        .fold((0.0, 0usize), |(s, n), (_, e)| (s + f64::from(*e), n + 1));
    if n > 0 {
        sum / n as f64
    } else {
        f64::NAN
    }
}
