//! Image files: `.exr` holds linear sRGB in absolute cd/m²
//! (conventions.md, Photometry); `.png` is the camera model's 8-bit sRGB.

use std::io::Write;
use std::path::Path;

use himmel_skymodel::camera::{develop_row, exposure_ev100, exposure_scale, CameraSettings};
use himmel_skymodel::file::write_file;
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

/// Writes a linear absolute EXR through [`write_file`] (a synced temporary
/// renamed into place; every error names the file).
pub fn write_exr(path: &Path, img: &HdrImage) -> Result<(), String> {
    let data: Vec<f32> = img.pixels.iter().flat_map(|p| p.iter().copied()).collect();
    let buf = image::Rgb32FImage::from_raw(img.width as u32, img.height as u32, data)
        .ok_or_else(|| format!("{}: image buffer size mismatch", path.display()))?;
    let img = image::DynamicImage::ImageRgb32F(buf);
    write_file(path, |w| {
        // The EXR encoder reports a failed write as a "format error
        // decoding OpenExr": name the write error itself.
        let mut w = FirstIoError {
            inner: w,
            error: None,
        };
        img.write_to(&mut w, image::ImageFormat::OpenExr)
            .map_err(|e| {
                w.error
                    .take()
                    .map_or_else(|| e.to_string(), |io| io.to_string())
            })
    })
    .map_err(|e| e.to_string())
}

/// A writer that keeps the first I/O error it passed on.
struct FirstIoError<W> {
    inner: W,
    error: Option<std::io::Error>,
}

impl<W> FirstIoError<W> {
    fn keep<T>(&mut self, r: std::io::Result<T>) -> std::io::Result<T> {
        if let Err(e) = &r {
            if self.error.is_none() {
                self.error = Some(std::io::Error::new(e.kind(), e.to_string()));
            }
        }
        r
    }
}

impl<W: Write> Write for FirstIoError<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let r = self.inner.write(buf);
        self.keep(r)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        let r = self.inner.flush();
        self.keep(r)
    }
}

impl<W: std::io::Seek> std::io::Seek for FirstIoError<W> {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        let r = self.inner.seek(pos);
        self.keep(r)
    }
}

/// Reads an RGB EXR back (tests, tools): width, height, pixels.
pub fn read_exr(path: &Path) -> Result<(usize, usize, Vec<[f32; 3]>), String> {
    let img = image::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let rgb = img.to_rgb32f();
    let (w, h) = (rgb.width() as usize, rgb.height() as usize);
    let px = rgb.pixels().map(|p| p.0).collect();
    Ok((w, h, px))
}

/// Develops with the camera model and writes a PNG through [`write_file`];
/// returns the EV100 used. Bands of [`PIPELINE_ROWS`] rows are developed
/// on all cores while the encoder compresses the band before (the same
/// pixels as [`write_png_overlaid`], which develops the whole image first).
pub fn write_png(path: &Path, img: &HdrImage, settings: &CameraSettings) -> Result<f64, String> {
    let ev = exposure_ev100(&img.pixels, &img.valid, settings);
    let k = exposure_scale(ev);
    if img.pixels.len() != img.width * img.height || img.valid.len() != img.pixels.len() {
        return Err(format!("{}: image buffer size mismatch", path.display()));
    }
    write_file(path, |w| develop_and_encode(w, img, k, settings)).map_err(|e| e.to_string())?;
    Ok(ev)
}

/// Rows per band of [`write_png`]'s pipeline (a 1920-pixel image: 34
/// bands of 184 kB).
const PIPELINE_ROWS: usize = 32;

/// Develops `img` at exposure scale `k` band by band and encodes each band
/// ([`png_encoder`]) while the next is developed.
fn develop_and_encode(
    w: impl Write + Send,
    img: &HdrImage,
    k: f32,
    settings: &CameraSettings,
) -> Result<(), png::EncodingError> {
    let (width, height) = (img.width, img.height);
    if width == 0 || height == 0 {
        // Nothing to develop: the encoder reports the empty image.
        return encode_png(w, width as u32, height as u32, &[]);
    }
    let mut writer = png_encoder(w, width as u32, height as u32).write_header()?;
    let mut stream = writer.stream_writer_with_size(1 << 18)?;
    let bands = height.div_ceil(PIPELINE_ROWS);
    let rows = |b: usize| b * PIPELINE_ROWS..height.min((b + 1) * PIPELINE_ROWS);
    // Develops band b into `out` (its rows' RGB bytes; black where not valid).
    let develop = |b: usize, out: &mut Vec<u8>| {
        let r = rows(b);
        out.clear();
        out.resize(r.len() * width * 3, 0);
        out.par_chunks_mut(width * 3).zip(r).for_each(|(row, y)| {
            let px = y * width..(y + 1) * width;
            develop_row(&img.pixels[px.clone()], &img.valid[px], y, k, settings, row)
        });
    };
    let (mut current, mut next) = (Vec::new(), Vec::new());
    develop(0, &mut current);
    for b in 0..bands {
        let (written, ()) = rayon::join(
            || stream.write_all(&current),
            || {
                if b + 1 < bands {
                    develop(b + 1, &mut next)
                }
            },
        );
        written?;
        std::mem::swap(&mut current, &mut next);
    }
    stream.finish()?;
    writer.finish()
}

/// [`write_png`] with `overlay` drawing into the developed 8-bit image
/// (RGB rows, top to bottom) before it is encoded ([`crate::overlay`]).
pub fn write_png_overlaid(
    path: &Path,
    img: &HdrImage,
    settings: &CameraSettings,
    overlay: impl FnOnce(&mut [u8]) -> Result<(), String>,
) -> Result<f64, String> {
    // The camera model of himmel_skymodel::camera::develop, rows in parallel.
    let ev = exposure_ev100(&img.pixels, &img.valid, settings);
    let k = exposure_scale(ev);
    let w = img.width.max(1);
    let mut rgb8 = vec![0u8; img.pixels.len() * 3];
    rgb8.par_chunks_mut(w * 3)
        .zip(img.pixels.par_chunks(w).zip(img.valid.par_chunks(w)))
        .enumerate()
        .for_each(|(y, (row, (px, valid)))| develop_row(px, valid, y, k, settings, row));
    let rgb8 = rgb8
        .get_mut(..img.width * img.height * 3)
        .ok_or_else(|| format!("{}: image buffer size mismatch", path.display()))?;
    overlay(rgb8)?;
    write_file(path, |w| {
        encode_png(w, img.width as u32, img.height as u32, rgb8)
    })
    .map_err(|e| e.to_string())?;
    Ok(ev)
}

/// The PNG encoder of the images: 8-bit RGB, fdeflate's fast compression,
/// the Up filter (a fifth of the adaptive filter's row work for a sky's
/// smooth rows).
fn png_encoder<W: Write>(w: W, width: u32, height: u32) -> png::Encoder<'static, W> {
    let mut enc = png::Encoder::new(w, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    enc.set_filter(png::Filter::Up);
    enc
}

/// Encodes 8-bit RGB as PNG ([`png_encoder`]) and finishes the stream, so
/// that no error is lost in a drop.
fn encode_png(
    w: impl Write,
    width: u32,
    height: u32,
    rgb8: &[u8],
) -> Result<(), png::EncodingError> {
    let mut writer = png_encoder(w, width, height).write_header()?;
    writer.write_image_data(rgb8)?;
    writer.finish()
}
