//! The texture pass: the frame plan's [`TextureFrame`] over what the
//! earlier passes drew (`TextureFrame::over`: the textures' bilinear
//! lookups through the rotation, cross-fade weights and gain, the horizon
//! band, the blend), per pixel on all cores.

use glam::Vec3;
use himmel_skymodel::frame::TextureFrame;

/// Draws the sky texture into `pixels` for the pixel directions `dirs`.
pub fn render(pixels: &mut [[f32; 3]], dirs: &[Option<Vec3>], texture: &TextureFrame) {
    crate::bands::par_chunks(pixels, dirs, 4096, |_, p, d| band(p, d, texture));
}

/// [`render`] over a band of pixels and their directions.
pub fn band(pixels: &mut [[f32; 3]], dirs: &[Option<Vec3>], texture: &TextureFrame) {
    for (p, d) in pixels.iter_mut().zip(dirs) {
        if let Some(d) = d {
            *p = texture.over(*p, *d);
        }
    }
}
