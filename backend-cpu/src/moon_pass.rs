//! The Moon pass: the opaque lunar disk (Hapke–Lommel–Seeliger BRDF on the
//! albedo map, earthshine, lunar-eclipse shading and extinction, all from
//! [`himmel_skymodel::moon::MoonShader`]), composited over what the earlier
//! passes drew (the Milky Way, stars, planets) by its coverage: the Moon
//! replaces what lies behind it; the limb is anti-aliased analytically.
//!
//! Only the rows and columns of the disk's bounding box are visited (found
//! by projecting the disk's centre and radius for the perspective camera;
//! other projections test every pixel with one dot product).

use glam::Vec3;
use himmel_skymodel::atmosphere::AtmosphereLuts;
use himmel_skymodel::moon::MoonShader;
use himmel_skymodel::{Camera, Projection, Scene, SkyState};
use rayon::prelude::*;

/// Draws the Moon into `pixels` (row-major, width `w`) for the pixel
/// directions `dirs`; `luts` (with the observer's radius `r0`, km) apply the
/// extinction along the line of sight.
pub fn render(
    pixels: &mut [[f32; 3]],
    dirs: &[Option<Vec3>],
    w: usize,
    scene: &Scene,
    state: &SkyState,
    luts: Option<&AtmosphereLuts>,
    r0: f32,
) {
    let shader = MoonShader::for_frame(scene, state, luts, r0);
    let cam: &Camera = &scene.camera;
    let pixel = local_pixel_angle(cam, shader.centre.as_dvec3()) as f32;
    let cos_bound = shader.cos_bound(limb_margin(pixel));
    let h = pixels.len() / w.max(1);
    let (x0, x1, y0, y1) = bounding_box(cam, &shader, w, h);
    if x0 >= x1 || y0 >= y1 {
        return;
    }
    let n = supersampling(shader.radius / pixel);
    pixels
        .par_chunks_mut(w)
        .zip(dirs.par_chunks(w))
        .enumerate()
        .skip(y0)
        .take(y1 - y0)
        .for_each(|(y, (row, drow))| {
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
                    supersample(cam, &shader, x, y, n)
                };
                if let Some((l, cov)) = shaded {
                    let p = &mut row[x];
                    for k in 0..3 {
                        p[k] = p[k] * (1.0 - cov) + l[k] * cov;
                    }
                }
            }
        });
}

/// The margin (radians) around the disk within which pixel centres are
/// shaded, for pixels of `pixel` radians: two pixels, and at least 10⁻³
/// rad (f32 dot products resolve ~0.02° near 1: the margin stays above that).
pub fn limb_margin(pixel: f32) -> f32 {
    (2.0 * pixel).max(1e-3)
}

/// Sub-samples per axis for a disk of `r_px` pixels in radius: small disks
/// (a few pixels across, e.g. all-sky images) are supersampled 8 × 8 or
/// 4 × 4 so that the light and the shape stay right; large ones (0) use
/// the analytic edge coverage.
pub fn supersampling(r_px: f32) -> usize {
    if r_px < 4.0 {
        8
    } else if r_px < 16.0 {
        4
    } else {
        0
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

/// The angular size of a pixel at direction `c` (geometric mean of its
/// two sides, so that the anti-aliased edge keeps the disk's area); the
/// camera's largest pixel angle where `c` is not in the image.
pub fn local_pixel_angle(cam: &Camera, c: glam::DVec3) -> f64 {
    let fallback = cam.max_pixel_angle();
    let Some((x, y)) = cam.dir_to_pixel(c) else {
        return fallback;
    };
    let at = |x: f64, y: f64| cam.pixel_to_dir(x, y);
    match (
        at(x - 0.5, y),
        at(x + 0.5, y),
        at(x, y - 0.5),
        at(x, y + 0.5),
    ) {
        (Some(a), Some(b), Some(u), Some(v)) => {
            let s = (a.angle_between(b) * u.angle_between(v)).sqrt();
            if s.is_finite() && s > 0.0 {
                s
            } else {
                fallback
            }
        }
        _ => fallback,
    }
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

/// The inner corona around an eclipsed Sun (run by the Sun pass when the
/// Moon hides part of the disk; against the uneclipsed daylight sky the
/// corona, ~10⁻⁶ of the disk's radiance, is invisible): Baumbach's profile
/// ([`himmel_skymodel::sun::corona_relative`], less its value at 6 solar
/// radii, where the drawing ends) times
/// the disk's mean radiance and the transmittance along the line of sight,
/// hidden by the Moon's disk (anti-aliased).
pub fn render_corona(
    pixels: &mut [[f32; 3]],
    dirs: &[Option<Vec3>],
    scene: &Scene,
    state: &SkyState,
    luts: Option<&AtmosphereLuts>,
    r0: f32,
) {
    use himmel_skymodel::spectrum::{BandWeights, Spectrum};
    if state.sun.visible_fraction >= 1.0 {
        return;
    }
    let sun = state.sun.dir().as_vec3();
    let rs = (state.sun.angular_radius * scene.sun_scale) as f32;
    let moon = state.moon.dir().as_vec3();
    let rm = (state.moon.angular_radius * scene.moon_scale) as f32;
    let pixel = scene.camera.max_pixel_angle() as f32;
    let cos_out = (6.0 * rs).cos();
    let w = BandWeights::solar();
    let mean =
        (state.sun.irradiance_scale / (std::f64::consts::PI * (rs as f64).sin().powi(2))) as f32;
    pixels
        .par_iter_mut()
        .zip(dirs.par_iter())
        .for_each(|(p, d)| {
            let Some(d) = *d else { return };
            if d.z < 0.0 || d.dot(sun) < cos_out {
                return;
            }
            let r = d.cross(sun).length().atan2(d.dot(sun)) / rs;
            // Minus the value at 6 R☉ so that the drawn corona ends without a step.
            let rel = (himmel_skymodel::sun::corona_relative(r as f64)
                - himmel_skymodel::sun::corona_relative(6.0)) as f32;
            if rel <= 0.0 {
                return;
            }
            let gm = d.cross(moon).length().atan2(d.dot(moon));
            let visible = 1.0 - ((rm - gm) / pixel + 0.5).clamp(0.0, 1.0);
            if visible <= 0.0 {
                return;
            }
            let t = luts.map_or(Spectrum::ONE, |l| l.sun_transmittance(r0, d.z));
            let c = w.to_rgb(&(t * (mean * rel * visible)));
            for k in 0..3 {
                p[k] += c[k];
            }
        });
}
