//! Sky texture files through the `image` crate ([`ImageLoader`]): PNG and
//! JPEG decoded from sRGB to linear 0 … 1 (8 or 16 bits), OpenEXR and
//! Radiance HDR read as linear values in their own units; every error
//! names the file. [`write_texture`] writes a converted texture as EXR.

use std::path::Path;

use himmel_skymodel::camera::srgb_decode;
use himmel_skymodel::renderer::HdrImage;
use himmel_skymodel::texture_sky::store::Decoded;
use himmel_skymodel::texture_sky::{LinearImage, TextureError, TextureLoader};

/// Decodes PNG, JPEG, EXR and Radiance HDR files.
#[derive(Debug, Default, Clone, Copy)]
pub struct ImageLoader;

impl TextureLoader for ImageLoader {
    fn load(&self, path: &Path) -> Result<Decoded, TextureError> {
        read_texture(path)
    }
}

/// Reads an image file as a linear texture (module docs).
pub fn read_texture(path: &Path) -> Result<Decoded, TextureError> {
    let err = |reason: String| TextureError::File {
        path: path.display().to_string(),
        reason,
    };
    let reader = image::ImageReader::open(path)
        .map_err(|e| err(e.to_string()))?
        .with_guessed_format()
        .map_err(|e| err(e.to_string()))?;
    let format = reader.format().ok_or_else(|| {
        err("not an image file this version reads (PNG, JPEG, EXR, Radiance HDR)".into())
    })?;
    let hdr = match format {
        image::ImageFormat::OpenExr | image::ImageFormat::Hdr => true,
        image::ImageFormat::Png | image::ImageFormat::Jpeg => false,
        other => {
            return Err(err(format!(
                "{other:?} images are not read; expected PNG, JPEG, EXR or Radiance HDR"
            )))
        }
    };
    let img = reader.decode().map_err(|e| err(e.to_string()))?;
    let rgb = img.to_rgb32f();
    let (width, height) = (rgb.width(), rgb.height());
    let texels: Vec<[f32; 3]> = rgb
        .pixels()
        .map(|p| {
            if hdr {
                p.0.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 })
            } else {
                p.0.map(srgb_decode)
            }
        })
        .collect();
    if width < 2 || height < 2 {
        return Err(err(format!(
            "{width} × {height} is too small for a sky texture"
        )));
    }
    Ok(Decoded {
        image: LinearImage {
            width,
            height,
            texels,
        },
        hdr,
    })
}

/// Writes a linear texture as an EXR (linear values, through
/// [`crate::output::write_exr`]).
pub fn write_texture(path: &Path, image: &LinearImage) -> Result<(), String> {
    let hdr = HdrImage {
        width: image.width as usize,
        height: image.height as usize,
        pixels: image.texels.clone(),
        valid: vec![true; image.texels.len()],
    };
    crate::output::write_exr(path, &hdr)
}
