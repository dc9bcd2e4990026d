//! The atmosphere pass over a band of pixels ([`SkyLight::add_band`]).
//!
//! A band goes in blocks of [`BLOCK`] pixels: the sky-view coordinates of
//! the whole block (the elevation's row, shared by the sunlit and the
//! moonlit view, and each view's azimuth column) are computed without
//! branches over channel arrays, so that the compiler evaluates them for
//! several pixels per instruction; then each pixel reads its texels. The
//! operations are those of [`SkyLight::radiance`] in the same order (its
//! branches become selects), so a band adds exactly what the per-pixel
//! lookups add (test `bands_equal_the_pixel_lookups`).

use std::f32::consts::PI;

use glam::Vec3;

use super::{azimuth_between, SkyLight};
use crate::atmosphere::lut::tex_from_unit;
use crate::atmosphere::Lut2;

/// Pixels per block.
const BLOCK: usize = 64;

/// One axis of a bilinear lookup (`Lut2::corners`): the first texel of
/// texture coordinate `u` on an axis of `n` texels and the next one's
/// weight. (The clamped coordinate is below `n`: `i32` holds it.)
#[inline(always)]
fn axis(u: f32, n: usize) -> (i32, f32) {
    let x = (u * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
    let x0 = x as i32;
    (x0, x - x0 as f32)
}

/// `Lut2::sample_rgb` from the taps of its two axes.
#[inline(always)]
fn sample(lut: &Lut2<[f32; 3]>, (y0, fy): (i32, f32), (x0, fx): (i32, f32)) -> [f32; 3] {
    let (x0, y0) = (x0.max(0) as usize, y0.max(0) as usize);
    let (x1, y1) = ((x0 + 1).min(lut.w - 1), (y0 + 1).min(lut.h - 1));
    let c = [
        y0 * lut.w + x0,
        y0 * lut.w + x1,
        y1 * lut.w + x0,
        y1 * lut.w + x1,
    ];
    let mut out = [0.0; 3];
    for (k, o) in out.iter_mut().enumerate() {
        let a = lut.data[c[0]][k] * (1.0 - fx) + lut.data[c[1]][k] * fx;
        let b = lut.data[c[2]][k] * (1.0 - fx) + lut.data[c[3]][k] * fx;
        *o = a * (1.0 - fy) + b * fy;
    }
    out
}

impl SkyLight {
    /// Adds the sky radiance ([`Self::radiance`]) to each pixel of
    /// `pixels` that has a direction in `dirs`.
    pub fn add_band(&self, pixels: &mut [[f32; 3]], dirs: &[Option<Vec3>]) {
        let sun = &self.sun;
        let moon = match &self.moon {
            Some((sv, _)) if sv.lut.h == sun.lut.h => Some(sv),
            Some(_) => {
                // Views of different sizes share no row: pixel by pixel.
                for (p, d) in pixels.iter_mut().zip(dirs) {
                    if let Some(d) = d {
                        let l = self.radiance(*d);
                        for k in 0..3 {
                            p[k] += l[k];
                        }
                    }
                }
                return;
            }
            None => None,
        };
        let ground = match moon {
            Some(sv) => {
                let (a, b) = (sun.ground_rgb, sv.ground_rgb);
                [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
            }
            None => sun.ground_rgb,
        };
        let (sun_az, moon_az) = self.azimuths;
        let s = self.sun_dir;
        let (h, ws, wm) = (sun.lut.h, sun.lut.w, moon.map_or(2, |m| m.lut.w));
        let mut xyz = [[0.0f32; BLOCK]; 3];
        let mut taps = [[(0i32, 0.0f32); 3]; BLOCK];
        for (px, ds) in pixels.chunks_mut(BLOCK).zip(dirs.chunks(BLOCK)) {
            if !ds.iter().flatten().any(|d| d.z >= 0.0) {
                // All below the horizon (or outside the image): the ground.
                for (p, _) in px.iter_mut().zip(ds).filter(|(_, d)| d.is_some()) {
                    for k in 0..3 {
                        p[k] += ground[k];
                    }
                }
                continue;
            }
            for (i, d) in ds.iter().enumerate() {
                let d = d.filter(|d| d.z >= 0.0).unwrap_or(Vec3::Z);
                (xyz[0][i], xyz[1][i], xyz[2][i]) = (d.x, d.y, d.z);
            }
            if moon.is_some() {
                for (i, t) in taps.iter_mut().enumerate() {
                    let d = Vec3::new(xyz[0][i], xyz[1][i], xyz[2][i]);
                    let v = sun.row_coordinate(d);
                    let phi = crate::angle::atan2(d.y, d.x);
                    let us = tex_from_unit(azimuth_between(phi, sun_az) / PI, ws);
                    let um = tex_from_unit(azimuth_between(phi, moon_az) / PI, wm);
                    *t = [axis(v, h), axis(us, ws), axis(um, wm)];
                }
            } else {
                for (i, t) in taps.iter_mut().enumerate() {
                    let d = Vec3::new(xyz[0][i], xyz[1][i], xyz[2][i]);
                    let v = sun.row_coordinate(d);
                    // SkyView::radiance_at_row
                    let cross = d.x * s.y - d.y * s.x;
                    let dot = d.x * s.x + d.y * s.y;
                    let az = crate::angle::atan2(cross.abs(), dot);
                    t[0] = axis(v, h);
                    t[1] = axis(tex_from_unit(az / PI, ws), ws);
                }
            }
            for (i, (p, d)) in px.iter_mut().zip(ds).enumerate() {
                let Some(d) = d else { continue };
                let l = if d.z < 0.0 {
                    ground
                } else {
                    let [row, su, mo] = taps[i];
                    let mut l = sample(&sun.lut, row, su);
                    if let Some(sv) = moon {
                        let k = sample(&sv.lut, row, mo);
                        for c in 0..3 {
                            l[c] += k[c];
                        }
                    }
                    l
                };
                for k in 0..3 {
                    p[k] += l[k];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atmosphere::SkyView;
    use crate::spectrum::Spectrum;

    /// A sky view of `w` × `h` texels with distinct values.
    fn view(w: usize, h: usize, seed: f32) -> SkyView {
        let data = (0..w * h)
            .map(|i| {
                let x = i as f32 * 0.37 + seed;
                [
                    x.sin().abs(),
                    (1.3 * x).cos().abs(),
                    (0.1 * x + seed).fract(),
                ]
            })
            .collect();
        SkyView {
            lut: Lut2 { w, h, data },
            ground_rgb: [0.1 * seed, 0.2, 0.3],
            sun_transmittance: Spectrum::ONE,
            sky_illuminance_lux: 1.0,
        }
    }

    #[test]
    fn bands_equal_the_pixel_lookups() {
        let sun_dir = Vec3::new(0.3, -0.8, -0.52).normalize();
        let moon_dir = Vec3::new(-0.6, 0.2, 0.77).normalize();
        let az = |d: Vec3| crate::angle::atan2(d.y, d.x);
        let dirs: Vec<Option<Vec3>> = (0..333 * 30)
            .map(|i| {
                let (a, b) = (i as f32 * 0.013, i as f32 * 0.0071);
                let d = Vec3::new(a.cos() * b.cos(), a.sin() * b.cos(), b.sin().abs() - 0.3);
                (i % 13 != 0).then(|| d.normalize())
            })
            .chain([Some(Vec3::Z), Some(Vec3::X), Some(Vec3::NEG_Z)])
            .collect();
        let lights = [
            (view(192, 108, 1.0), None),
            (view(192, 108, 1.0), Some(view(192, 108, 2.0))),
            (view(192, 108, 1.0), Some(view(96, 108, 2.0))),
            (view(64, 40, 1.0), Some(view(64, 30, 2.0))),
        ];
        for (sun, moon) in lights {
            let light = SkyLight {
                sun,
                sun_dir,
                moon: moon.map(|m| (m, moon_dir)),
                azimuths: (az(sun_dir), az(moon_dir)),
            };
            for ds in dirs.chunks(333) {
                let start: Vec<[f32; 3]> = (0..ds.len()).map(|i| [i as f32 * 1e-3; 3]).collect();
                let mut band = start.clone();
                light.add_band(&mut band, ds);
                for ((got, d), p) in band.iter().zip(ds).zip(&start) {
                    let mut want = *p;
                    if let Some(d) = d {
                        let l = light.radiance(*d);
                        for k in 0..3 {
                            want[k] += l[k];
                        }
                    }
                    assert_eq!(got.map(f32::to_bits), want.map(f32::to_bits), "{d:?}");
                }
            }
        }
    }
}
