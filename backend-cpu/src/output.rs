//! Image files: `.exr` holds linear sRGB in absolute cd/m²
//! (conventions.md, Photometry); `.png` is the camera model's 8-bit sRGB.

use std::path::Path;

use himmel_skymodel::camera::{develop_pixel, exposure_ev100, exposure_scale, CameraSettings};
use himmel_skymodel::HdrImage;
use rayon::prelude::*;

/// Output format chosen by the file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// OpenEXR, 32-bit float RGB, absolute.
    Exr,
    /// PNG, 8-bit sRGB after the camera model.
    Png,
}

impl Format {
    /// The format of `path` (by extension), if supported.
    pub fn of(path: &Path) -> Option<Format> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "exr" => Some(Format::Exr),
            "png" => Some(Format::Png),
            _ => None,
        }
    }
}

/// Writes a linear absolute EXR.
pub fn write_exr(path: &Path, img: &HdrImage) -> Result<(), String> {
    let data: Vec<f32> = img.pixels.iter().flat_map(|p| p.iter().copied()).collect();
    let buf = image::Rgb32FImage::from_raw(img.width as u32, img.height as u32, data)
        .ok_or("image buffer size mismatch")?;
    image::DynamicImage::ImageRgb32F(buf)
        .save_with_format(path, image::ImageFormat::OpenExr)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Reads an RGB EXR back (tests, tools): width, height, pixels.
pub fn read_exr(path: &Path) -> Result<(usize, usize, Vec<[f32; 3]>), String> {
    let img = image::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let rgb = img.to_rgb32f();
    let (w, h) = (rgb.width() as usize, rgb.height() as usize);
    let px = rgb.pixels().map(|p| p.0).collect();
    Ok((w, h, px))
}

/// Develops with the camera model and writes a PNG; returns the EV100 used.
pub fn write_png(path: &Path, img: &HdrImage, settings: &CameraSettings) -> Result<f64, String> {
    // The camera model of himmel_skymodel::camera::develop, rows in parallel.
    let ev = exposure_ev100(&img.pixels, &img.valid, settings);
    let k = exposure_scale(ev);
    let w = img.width.max(1);
    let mut rgb8 = vec![0u8; img.pixels.len() * 3];
    rgb8.par_chunks_mut(w * 3).enumerate().for_each(|(y, row)| {
        for x in 0..w {
            let i = y * w + x;
            if i < img.pixels.len() && img.valid[i] {
                row[x * 3..x * 3 + 3].copy_from_slice(&develop_pixel(
                    img.pixels[i],
                    x,
                    y,
                    k,
                    settings,
                ));
            }
        }
    });
    let buf = image::RgbImage::from_raw(img.width as u32, img.height as u32, rgb8)
        .ok_or("image buffer size mismatch")?;
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let enc = image::codecs::png::PngEncoder::new_with_quality(
        std::io::BufWriter::new(file),
        image::codecs::png::CompressionType::Fast,
        image::codecs::png::FilterType::Adaptive,
    );
    buf.write_with_encoder(enc)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(ev)
}
