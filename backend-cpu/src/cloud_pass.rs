//! The clouds pass: every pixel above the horizon seen through the high
//! and the low cloud layer ([`CloudFrame::composite`]: the cloud's
//! radiance with the aerial perspective in front of it, what lies behind
//! dimmed by the layer's transmittance), on all cores.

use glam::Vec3;
use himmel_skymodel::frame::CloudFrame;
use rayon::prelude::*;

/// Composes the cloud layers of `clouds` over `pixels` (row-major, the
/// camera's image, holding the sky behind the clouds) for the pixel
/// directions `dirs`.
pub fn render(pixels: &mut [[f32; 3]], dirs: &[Option<Vec3>], clouds: &CloudFrame) {
    pixels
        .par_iter_mut()
        .zip(dirs.par_iter())
        .with_min_len(64)
        .for_each(|(p, d)| {
            if let Some(d) = d {
                *p = clouds.composite(*d, *p);
            }
        });
}
