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
use rayon::prelude::*;

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
    let w = cam.image_size().0 as usize;
    let n = sun.supersampling;
    let (centre, cos_margin) = (sun.disk.centre, sun.cos_margin);
    pixels
        .par_iter_mut()
        .zip(dirs.par_iter())
        .enumerate()
        .for_each(|(i, (p, d))| {
            let Some(d) = d else { return };
            if d.dot(centre) < cos_margin {
                return;
            }
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
                    let t = luts.map_or(Spectrum::ONE, |l| l.sun_transmittance(r0, sd.z));
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
        });
}

/// Adds the inner corona of an eclipsed Sun to `pixels`.
pub fn render_corona(
    pixels: &mut [[f32; 3]],
    dirs: &[Option<Vec3>],
    corona: &CoronaFrame,
    luts: Option<&AtmosphereLuts>,
    r0: f32,
) {
    pixels
        .par_iter_mut()
        .zip(dirs.par_iter())
        .for_each(|(p, d)| {
            let Some(d) = *d else { return };
            if let Some(c) = corona.radiance(d, luts, r0) {
                for k in 0..3 {
                    p[k] += c[k];
                }
            }
        });
}
