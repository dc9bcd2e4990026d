//! Pixel-centre view directions in f32, the way the CPU renderer walks
//! the image: fisheye and equirect through closed forms with the per-row
//! and per-column work shared (equal to [`Camera::pixel_to_dir`] within
//! 10⁻⁶), the other projections through `pixel_to_dir` itself.
//!
//! [`PixelDirections::dir`] gives one pixel's direction with exactly the
//! arithmetic of [`PixelDirections::row`], so that the frame plan's
//! sparse metering samples ([`crate::frame::NightFrame`]) see the same
//! directions as the CPU backend's full buffer without building it.

use std::cell::Cell;

use glam::Vec3;

use crate::projection::{Camera, Projection};

thread_local! {
    static DIRECTION_BUFFERS: Cell<usize> = const { Cell::new(0) };
}

/// How many times this thread has had every pixel's direction computed
/// on the CPU: full buffers ([`PixelDirections::buffer`]) and band-by-band
/// walks over the image ([`count_direction_walk`], the CPU backend). A GPU
/// backend computes none (its shaders derive each pixel's direction),
/// which tests assert through this count.
pub fn direction_buffers_built() -> usize {
    DIRECTION_BUFFERS.with(Cell::get)
}

/// Counts one walk over every pixel's direction that keeps no buffer (a
/// CPU frame's bands of rows; see [`direction_buffers_built`]).
pub fn count_direction_walk() {
    DIRECTION_BUFFERS.with(|c| c.set(c.get() + 1));
}

/// A camera's pixel-centre directions (ENU, unit; `None` outside the
/// projection).
#[derive(Debug, Clone)]
pub struct PixelDirections<'a> {
    cam: &'a Camera,
    w: usize,
    h: usize,
    /// Equirect: (sin az, cos az) of each column.
    columns: Vec<(f32, f32)>,
    /// Perspective: the camera's basis (forward, right, up) and
    /// tan(fov / 2), computed once instead of per pixel.
    basis: Option<(glam::DVec3, glam::DVec3, glam::DVec3, f64)>,
}

impl<'a> PixelDirections<'a> {
    /// The directions of `cam`'s image.
    pub fn new(cam: &'a Camera) -> Self {
        let (w, h) = cam.image_size();
        let (w, h) = (w as usize, h as usize);
        let columns = if cam.projection == Projection::Equirect {
            (0..w).map(|x| equirect_column(x, w)).collect()
        } else {
            Vec::new()
        };
        let basis = (cam.projection == Projection::Perspective).then(|| {
            let (f, r, u) = cam.basis();
            (f, r, u, (cam.fov_deg.to_radians() / 2.0).tan())
        });
        PixelDirections {
            cam,
            w,
            h,
            columns,
            basis,
        }
    }

    /// The image width and height, pixels.
    pub fn size(&self) -> (usize, usize) {
        (self.w, self.h)
    }

    /// The direction of pixel (x, y)'s centre.
    #[inline]
    pub fn dir(&self, x: usize, y: usize) -> Option<Vec3> {
        match self.cam.projection {
            Projection::Fisheye => {
                let (r, dy) = fisheye_row(y, self.w, self.h);
                fisheye(x, self.w, r, dy)
            }
            Projection::Equirect => {
                let (sa, ca) = equirect_row(y, self.h);
                let (s, c) = self.columns[x];
                Some(Vec3::new(ca * s, ca * c, sa))
            }
            // The arithmetic of `Camera::pixel_to_dir` with the basis
            // computed once: the same directions, bit for bit.
            Projection::Perspective => self.basis.map(|(f, r, u, t)| {
                let (w, h) = (self.w as f64, self.h as f64);
                let nx = (x as f64 + 0.5 - w / 2.0) / (h / 2.0) * t;
                let ny = -(y as f64 + 0.5 - h / 2.0) / (h / 2.0) * t;
                (f + r * nx + u * ny).normalize().as_vec3()
            }),
            _ => self
                .cam
                .pixel_to_dir(x as f64 + 0.5, y as f64 + 0.5)
                .map(|d| d.as_vec3()),
        }
    }

    /// Fills `out` (one image row) with the directions of row `y`.
    pub fn row(&self, y: usize, out: &mut [Option<Vec3>]) {
        match self.cam.projection {
            Projection::Fisheye => {
                // Columns x and w − 1 − x lie at offsets ±dx (exact in
                // f64 and f32): the same ρ and zenith angle, so the same
                // sine and cosine; the mirror's East component is the
                // negated one, bit for bit. One `sin_cos` per pair.
                let (r, dy) = fisheye_row(y, self.w, self.h);
                let half = self.w.div_ceil(2).min(out.len());
                let (left, right) = out.split_at_mut(half);
                for (x, o) in left.iter_mut().enumerate() {
                    *o = fisheye(x, self.w, r, dy);
                }
                for (k, o) in right.iter_mut().enumerate() {
                    let mirror = self.w - half - 1 - k;
                    *o = left[mirror].map(|d| Vec3::new(-d.x, d.y, d.z));
                }
            }
            Projection::Equirect => {
                let (sa, ca) = equirect_row(y, self.h);
                for (o, &(s, c)) in out.iter_mut().zip(&self.columns) {
                    *o = Some(Vec3::new(ca * s, ca * c, sa));
                }
            }
            _ => {
                for (x, o) in out.iter_mut().enumerate() {
                    *o = self.dir(x, y);
                }
            }
        }
    }

    /// Every pixel's direction, row-major, computed on all cores (the CPU
    /// backend's per-pixel geometry).
    pub fn buffer(&self) -> Vec<Option<Vec3>> {
        use rayon::prelude::*;
        DIRECTION_BUFFERS.with(|c| c.set(c.get() + 1));
        let mut out = vec![None; self.w * self.h];
        out.par_chunks_mut(self.w.max(1))
            .enumerate()
            .for_each(|(y, row)| self.row(y, row));
        out
    }
}

/// Fisheye: the image circle's radius and row `y`'s offset from the
/// centre (px) of a `w` × `h` image.
#[inline]
fn fisheye_row(y: usize, w: usize, h: usize) -> (f32, f32) {
    let r = (w.min(h) as f64 / 2.0) as f32;
    (r, (y as f64 + 0.5 - h as f64 / 2.0) as f32)
}

/// Fisheye (azimuthal equidistant, zenith at the centre, North up, East
/// left): the direction of pixel `x` of a `w`-wide image's row with
/// offset `dy` ([`fisheye_row`]).
#[inline]
fn fisheye(x: usize, w: usize, r: f32, dy: f32) -> Option<Vec3> {
    let dx = (x as f64 + 0.5 - w as f64 / 2.0) as f32;
    let rho = (dx * dx + dy * dy).sqrt();
    let zenith = std::f32::consts::FRAC_PI_2 * rho / r;
    if zenith > std::f32::consts::PI {
        return None;
    }
    let (s, c) = zenith.sin_cos();
    Some(if rho > 0.0 {
        Vec3::new(-dx / rho * s, -dy / rho * s, c)
    } else {
        Vec3::Z
    })
}

/// Equirect: (sin az, cos az) of column `x` of `w`.
fn equirect_column(x: usize, w: usize) -> (f32, f32) {
    let a = std::f64::consts::TAU * (x as f64 + 0.5) / w as f64;
    (a.sin() as f32, a.cos() as f32)
}

/// Equirect: (sin alt, cos alt) of row `y` of `h`.
#[inline]
fn equirect_row(y: usize, h: usize) -> (f32, f32) {
    let alt = std::f64::consts::FRAC_PI_2 - std::f64::consts::PI * (y as f64 + 0.5) / h as f64;
    (alt.sin() as f32, alt.cos() as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_equal_the_buffer_and_the_camera() {
        // Odd and even widths: the fisheye rows mirror their left half.
        let projections = [
            Projection::Fisheye,
            Projection::Equirect,
            Projection::Perspective,
            Projection::Cubemap,
        ];
        for (p, (width, height)) in projections
            .into_iter()
            .flat_map(|p| [(p, (37, 23)), (p, (36, 22))])
        {
            let cam = Camera {
                projection: p,
                width,
                height,
                yaw_deg: 33.0,
                pitch_deg: 12.0,
                ..Camera::default()
            };
            let pd = PixelDirections::new(&cam);
            let before = direction_buffers_built();
            let buf = pd.buffer();
            assert_eq!(direction_buffers_built(), before + 1);
            let (w, h) = pd.size();
            for y in 0..h {
                for x in 0..w {
                    // Bit-identical to the buffer.
                    assert_eq!(pd.dir(x, y), buf[y * w + x], "{p:?} {x} {y}");
                    let exact = cam.pixel_to_dir(x as f64 + 0.5, y as f64 + 0.5);
                    match (pd.dir(x, y), exact) {
                        (Some(a), Some(b)) => {
                            assert!((a.as_dvec3() - b).length() < 2e-6, "{p:?} {x} {y}");
                            if p == Projection::Perspective {
                                // The per-frame basis changes no bit.
                                assert_eq!(a, b.as_vec3(), "{x} {y}");
                            }
                        }
                        (a, b) => assert_eq!(a.is_some(), b.is_some(), "{p:?} {x} {y}"),
                    }
                }
            }
        }
    }
}
