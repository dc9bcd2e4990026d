//! The texture pass: the frame plan's [`TextureFrame`] over what the
//! earlier passes drew (`TextureFrame::over`: the textures' bilinear
//! lookups through the rotation, cross-fade weights and gain, the horizon
//! band, the blend), per pixel on all cores.

use glam::Vec3;
use himmel_skymodel::frame::TextureFrame;
use rayon::prelude::*;

/// Draws the sky texture into `pixels` for the pixel directions `dirs`.
pub fn render(pixels: &mut [[f32; 3]], dirs: &[Option<Vec3>], texture: &TextureFrame) {
    pixels
        .par_iter_mut()
        .zip(dirs.par_iter())
        .for_each(|(p, d)| {
            if let Some(d) = d {
                *p = texture.over(*p, *d);
            }
        });
}
