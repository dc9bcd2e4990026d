//! The Sun pass: the limb-darkened disk ([`SunFrame`]), each pixel within
//! the frame's margin supersampled, extinguished along each sub-sample's
//! line of sight (the atmosphere pass comes later, but its extinction
//! applies to the disk behind it), hidden by the ground below the horizon
//! and by the Moon's disk during a solar eclipse; and the inner corona of
//! an eclipsed Sun ([`CoronaFrame`]).

use glam::Vec3;
use himmel_skymodel::atmosphere::AtmosphereLuts;
use himmel_skymodel::frame::{CoronaFrame, SunFrame};
use himmel_skymodel::spectrum::Spectrum;
use himmel_skymodel::Camera;

/// Adds the Sun's disk to `pixels` (row-major, the camera's image) for the
/// pixel directions `dirs`; `luts` (from radius `r0`, km) extinguish it.
pub fn render(
    pixels: &mut [[f32; 3]],
    dirs: &[Option<Vec3>],
    cam: &Camera,
    sun: &SunFrame,
    luts: Option<&AtmosphereLuts>,
    r0: f32,
) {
    let disk = SunDraw { cam, sun, luts, r0 };
    let w = cam.image_size().0 as usize;
    let chunk = crate::bands::BAND_ROWS * w;
    crate::bands::par_chunks(pixels, dirs, chunk, |i0, p, d| disk.band(i0, p, d));
}

/// The Sun pass of one frame, drawn band by band ([`SunDraw::band`]).
#[derive(Debug, Clone, Copy)]
pub struct SunDraw<'a> {
    /// The camera whose image is drawn.
    pub cam: &'a Camera,
    /// The frame plan's Sun.
    pub sun: &'a SunFrame,
    /// The atmosphere LUTs that extinguish the disk, if any.
    pub luts: Option<&'a AtmosphereLuts>,
    /// The observer's radius, km.
    pub r0: f32,
}

impl SunDraw<'_> {
    /// Adds the disk to `pixels`, the image's pixels from index `i0` on
    /// (whole rows or a part of one), with their directions `dirs`.
    pub fn band(&self, i0: usize, pixels: &mut [[f32; 3]], dirs: &[Option<Vec3>]) {
        let (cam, sun) = (self.cam, self.sun);
        let w = cam.image_size().0.max(1) as usize;
        let n = sun.supersampling;
        let (centre, cos_margin) = (sun.disk.centre, sun.cos_margin);
        for (j, (p, d)) in pixels.iter_mut().zip(dirs).enumerate() {
            let Some(d) = d else { continue };
            if d.dot(centre) < cos_margin {
                continue;
            }
            let i = i0 + j;
            let (x, y) = ((i % w) as f64, (i / w) as f64);
            let mut acc = [0.0f32; 3];
            for sj in 0..n {
                for si in 0..n {
                    let sx = x + (si as f64 + 0.5) / n as f64;
                    let sy = y + (sj as f64 + 0.5) / n as f64;
                    let Some(sd) = cam.pixel_to_dir(sx, sy) else {
                        continue;
                    };
                    let sd = sd.as_vec3();
                    let behind_moon = sd.dot(sun.moon_centre) > 0.0
                        && sd.cross(sun.moon_centre).length() < sun.moon_sin_radius;
                    if sd.z < 0.0 || !sun.disk.covers(sd) || behind_moon {
                        continue;
                    }
                    let luts = self.luts;
                    let t = luts.map_or(Spectrum::ONE, |l| l.sun_transmittance(self.r0, sd.z));
                    let l = sun.disk.radiance_rgb(sd, &t);
                    for k in 0..3 {
                        acc[k] += l[k];
                    }
                }
            }
            let k = 1.0 / (n * n) as f32;
            for c in 0..3 {
                p[c] += acc[c] * k;
            }
        }
    }
}

/// Adds the inner corona of an eclipsed Sun to `pixels`.
pub fn render_corona(
    pixels: &mut [[f32; 3]],
    dirs: &[Option<Vec3>],
    corona: &CoronaFrame,
    luts: Option<&AtmosphereLuts>,
    r0: f32,
) {
    crate::bands::par_chunks(pixels, dirs, 4096, |_, p, d| {
        corona_band(p, d, corona, luts, r0)
    });
}

/// [`render_corona`] over a band of pixels and their directions.
pub fn corona_band(
    pixels: &mut [[f32; 3]],
    dirs: &[Option<Vec3>],
    corona: &CoronaFrame,
    luts: Option<&AtmosphereLuts>,
    r0: f32,
) {
    for (p, d) in pixels.iter_mut().zip(dirs) {
        let Some(d) = *d else { continue };
        if let Some(c) = corona.radiance(d, luts, r0) {
            for k in 0..3 {
                p[k] += c[k];
            }
        }
    }
}
