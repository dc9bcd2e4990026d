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
    let pole = glam::DVec3::from_array(state.celestial_pole).as_vec3();
    let shader = MoonShader::new(&state.moon, scene.moon_scale, luts, r0, pole);
    let cam: &Camera = &scene.camera;
    let pixel = cam.max_pixel_angle() as f32;
    // f32 dot products resolve ~0.02° near 1: keep the margin above that.
    let cos_bound = shader.cos_bound((2.0 * pixel).max(1e-3));
    let h = pixels.len() / w.max(1);
    let (x0, x1, y0, y1) = bounding_box(cam, &shader, w, h);
    if x0 >= x1 || y0 >= y1 {
        return;
    }
    pixels
        .par_chunks_mut(w)
        .zip(dirs.par_chunks(w))
        .enumerate()
        .skip(y0)
        .take(y1 - y0)
        .for_each(|(_, (row, drow))| {
            for x in x0..x1 {
                let Some(d) = drow[x] else { continue };
                // The ground hides the Moon below the horizon.
                if d.z < 0.0 || d.dot(shader.centre) < cos_bound {
                    continue;
                }
                if let Some((l, cov)) = shader.shade(d, pixel) {
                    let p = &mut row[x];
                    for k in 0..3 {
                        p[k] = p[k] * (1.0 - cov) + l[k] * cov;
                    }
                }
            }
        });
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
