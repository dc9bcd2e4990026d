//! The Moon pass: the opaque lunar disk (Hapke–Lommel–Seeliger BRDF on the
//! albedo map, earthshine, lunar-eclipse shading and extinction, all from
//! the frame plan's [`MoonFrame`] and its [`MoonShader`]), composited over what the earlier
//! passes drew (the Milky Way, stars, planets) by its coverage: the Moon
//! replaces what lies behind it; the limb is anti-aliased analytically.
//!
//! Only the rows and columns of the disk's bounding box are visited (found
//! by projecting the disk's centre and radius for the perspective camera;
//! other projections test every pixel with one dot product).

use glam::Vec3;
use himmel_skymodel::frame::MoonFrame;
use himmel_skymodel::moon::MoonShader;
use himmel_skymodel::{Camera, Projection};

/// Draws the Moon of the frame plan into `pixels` (row-major, width `w`)
/// for the pixel directions `dirs`.
pub fn render(
    pixels: &mut [[f32; 3]],
    dirs: &[Option<Vec3>],
    w: usize,
    cam: &Camera,
    moon: &MoonFrame,
) {
    let w = w.max(1);
    let draw = MoonDraw::new(cam, moon, w, pixels.len() / w);
    let chunk = crate::bands::BAND_ROWS * w;
    crate::bands::par_chunks(pixels, dirs, chunk, |i0, p, d| draw.band(i0 / w, p, d));
}

/// The Moon pass of one frame with its pixel bounding box, drawn band by
/// band ([`MoonDraw::band`]).
#[derive(Debug, Clone, Copy)]
pub struct MoonDraw<'a> {
    cam: &'a Camera,
    moon: &'a MoonFrame,
    w: usize,
    /// [x0, x1) × [y0, y1): the pixels that may show the disk.
    bbox: (usize, usize, usize, usize),
}

impl<'a> MoonDraw<'a> {
    /// The Moon of `moon` in `cam`'s `w` × `h` image.
    pub fn new(cam: &'a Camera, moon: &'a MoonFrame, w: usize, h: usize) -> Self {
        let bbox = bounding_box(cam, &moon.shader, w, h);
        MoonDraw { cam, moon, w, bbox }
    }

    /// Draws the disk into whole rows from row `y0` on: `pixels` and their
    /// directions `dirs`.
    pub fn band(&self, y0: usize, pixels: &mut [[f32; 3]], dirs: &[Option<Vec3>]) {
        let (x0, x1, by0, by1) = self.bbox;
        let (shader, w) = (&self.moon.shader, self.w);
        let (pixel, cos_bound, n) = (
            self.moon.pixel,
            self.moon.cos_bound,
            self.moon.supersampling,
        );
        if x0 >= x1 {
            return;
        }
        for (r, (row, drow)) in pixels.chunks_mut(w).zip(dirs.chunks(w)).enumerate() {
            let y = y0 + r;
            if y < by0 || y >= by1 || row.len() < x1 || drow.len() < x1 {
                continue;
            }
            for x in x0..x1 {
                let Some(d) = drow[x] else { continue };
                if d.dot(shader.centre) < cos_bound {
                    continue;
                }
                let shaded = if n == 0 {
                    // The ground hides the Moon below the horizon.
                    if d.z < 0.0 {
                        continue;
                    }
                    shader.shade(d, pixel)
                } else {
                    supersample(self.cam, shader, x, y, n)
                };
                if let Some((l, cov)) = shaded {
                    let p = &mut row[x];
                    for k in 0..3 {
                        p[k] = p[k] * (1.0 - cov) + l[k] * cov;
                    }
                }
            }
        }
    }
}

/// Mean radiance of the disk's part of pixel (x, y) and its coverage, from
/// n × n sub-samples (those below the horizon are hidden by the ground).
fn supersample(
    cam: &Camera,
    shader: &MoonShader,
    x: usize,
    y: usize,
    n: usize,
) -> Option<([f32; 3], f32)> {
    let mut acc = [0.0f32; 3];
    let mut hits = 0usize;
    for j in 0..n {
        for i in 0..n {
            let sx = x as f64 + (i as f64 + 0.5) / n as f64;
            let sy = y as f64 + (j as f64 + 0.5) / n as f64;
            let Some(sd) = cam.pixel_to_dir(sx, sy) else {
                continue;
            };
            let sd = sd.as_vec3();
            if sd.z < 0.0 || !shader.covers_exact(sd) {
                continue;
            }
            let l = shader.radiance(shader.surface_point(sd), sd.z);
            for k in 0..3 {
                acc[k] += l[k];
            }
            hits += 1;
        }
    }
    if hits == 0 {
        return None;
    }
    let inv = 1.0 / hits as f32;
    Some((acc.map(|v| v * inv), hits as f32 / (n * n) as f32))
}

/// Pixel bounding box [x0, x1) × [y0, y1) of the disk plus two pixels.
fn bounding_box(
    cam: &Camera,
    shader: &MoonShader,
    w: usize,
    h: usize,
) -> (usize, usize, usize, usize) {
    if cam.projection != Projection::Perspective {
        return (0, w, 0, h);
    }
    let c = shader.centre.as_dvec3();
    // The disk's edge points in four directions around the centre.
    let a = c.any_orthonormal_vector();
    let b = c.cross(a);
    let r = shader.radius as f64;
    let (mut xmin, mut xmax, mut ymin, mut ymax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for k in 0..16 {
        let t = std::f64::consts::TAU * k as f64 / 16.0;
        // Points slightly outside the circle (1/cos(π/16) covers the polygon gap).
        let e = (c * r.cos() + (a * t.cos() + b * t.sin()) * r.sin() * 1.02).normalize();
        match cam.dir_to_pixel(e) {
            Some((x, y)) => {
                xmin = xmin.min(x);
                xmax = xmax.max(x);
                ymin = ymin.min(y);
                ymax = ymax.max(y);
            }
            // Behind the camera: fall back to the whole image.
            None => return (0, w, 0, h),
        }
    }
    let clamp = |v: f64, n: usize| v.clamp(0.0, n as f64) as usize;
    (
        clamp(xmin.floor() - 2.0, w),
        clamp(xmax.ceil() + 2.0, w),
        clamp(ymin.floor() - 2.0, h),
        clamp(ymax.ceil() + 2.0, h),
    )
}
