//! The Milky Way pass over a band of pixels ([`NightBackground::add_band`])
//! and the refraction it takes off low altitudes ([`Unrefraction`]).
//!
//! A band goes in blocks of [`BLOCK`] pixels: each direction is rotated
//! into ICRS (unrefracted below [`REFRACTION_BELOW_Z`]), then the map
//! coordinates, the zodiacal light and the airglow of the whole block are
//! computed without branches over channel arrays (several pixels per
//! instruction), then each pixel fetches its four texels and its
//! extinction. Every pixel gets the operations of
//! [`NightBackground::radiance`] × [`Extinction::rgb`] in the same order
//! (the branches become selects), so the band equals the per-pixel sum
//! bit for bit (test `bands_equal_the_pixel_functions`).

use std::sync::OnceLock;

use glam::Vec3;

use super::{van_rhijn, zodiacal_s10, NightBackground};
use crate::stars::Extinction;

/// Pixels per block.
const BLOCK: usize = 64;

/// Apparent zenith cosines below which the map is looked up where
/// refraction brings the sky from (altitudes below 10.4°).
pub const REFRACTION_BELOW_Z: f32 = 0.18;

/// Nodes of the [`Unrefraction`] table over z ∈ [0, [`REFRACTION_BELOW_Z`]].
const NODES: usize = 257;

/// [`crate::refraction::unrefracted`] as a function of the apparent zenith
/// cosine z, tabulated: the true direction of the apparent unit direction
/// (x, y, z) is (q x, q y, z′) with z′ = sin(a − R(a)) and q = cos(a −
/// R(a)) / cos a for the apparent altitude a = asin z and Bennett's
/// refraction R at 1010 hPa and 10 °C, both interpolated linearly between
/// nodes computed in `f64` (no arcsine, sine or square root per pixel). The
/// direction is within 5 × 10⁻⁷ rad (0.1″) of the exact one (test
/// `unrefraction_table_matches_the_formula`), four orders of magnitude
/// below the map's 0.7° texels.
#[derive(Debug)]
pub struct Unrefraction {
    /// (z′, q) at z = i / (NODES − 1) · REFRACTION_BELOW_Z.
    nodes: Vec<[f32; 2]>,
}

impl Unrefraction {
    /// The table, computed on first use.
    pub fn get() -> &'static Unrefraction {
        static CELL: OnceLock<Unrefraction> = OnceLock::new();
        CELL.get_or_init(|| {
            use himmel_astro::frames::{
                refraction_apparent_to_true, STANDARD_PRESSURE_HPA, STANDARD_TEMPERATURE_C,
            };
            let nodes = (0..NODES)
                .map(|i| {
                    let z = i as f64 / (NODES - 1) as f64 * REFRACTION_BELOW_Z as f64;
                    let a = z.asin();
                    let r = refraction_apparent_to_true(
                        a,
                        STANDARD_PRESSURE_HPA,
                        STANDARD_TEMPERATURE_C,
                    );
                    let (s, c) = (a - r).sin_cos();
                    [s as f32, (c / a.cos()) as f32]
                })
                .collect();
            Unrefraction { nodes }
        })
    }

    /// The true (airless) direction of the apparent unit direction `d`
    /// with 0 ≤ d.z ≤ [`REFRACTION_BELOW_Z`] (clamped into the table).
    #[inline]
    pub fn apply(&self, d: Vec3) -> Vec3 {
        let s = d.z.clamp(0.0, REFRACTION_BELOW_Z) * ((NODES - 1) as f32 / REFRACTION_BELOW_Z);
        let i = (s as usize).min(NODES - 2);
        let f = s - i as f32;
        let (a, b) = (self.nodes[i], self.nodes[i + 1]);
        let z = a[0] + (b[0] - a[0]) * f;
        let q = a[1] + (b[1] - a[1]) * f;
        Vec3::new(d.x * q, d.y * q, z)
    }
}

impl NightBackground {
    /// The ICRS direction whose light reaches the apparent ENU direction
    /// `d` (unit, above the horizon): unrefracted low down, rotated.
    #[inline]
    pub(super) fn icrs(&self, d: Vec3) -> Vec3 {
        let d_true = if d.z < REFRACTION_BELOW_Z {
            self.unrefraction.apply(d)
        } else {
            d
        };
        self.enu_to_icrs * d_true
    }

    /// Adds the diffuse night sky extinguished by `extinction`
    /// ([`Self::radiance`] × [`Extinction::rgb`]) to each pixel of `pixels`
    /// whose direction in `dirs` lies above the horizon.
    pub fn add_band(
        &self,
        extinction: &Extinction,
        pixels: &mut [[f32; 3]],
        dirs: &[Option<Vec3>],
    ) {
        let Some(map) = self.map else {
            for (p, d) in pixels.iter_mut().zip(dirs) {
                match d {
                    Some(d) if d.z >= 0.0 => add(p, self.radiance(*d), extinction.rgb(*d)),
                    _ => {}
                }
            }
            return;
        };
        let (se, ce) = self.obliquity_sin_cos;
        let mut u = [[0.0f32; BLOCK]; 3];
        let mut cz = [0.0f32; BLOCK];
        let mut taps = [(0i32, 0i32, 0.0f32, 0.0f32); BLOCK];
        let (mut zl, mut ag) = ([0.0f32; BLOCK], [0.0f32; BLOCK]);
        for (px, ds) in pixels.chunks_mut(BLOCK).zip(dirs.chunks(BLOCK)) {
            if !ds.iter().flatten().any(|d| d.z >= 0.0) {
                // All below the horizon (or outside the image): nothing.
                continue;
            }
            for (i, d) in ds.iter().enumerate() {
                let d = d.filter(|d| d.z >= 0.0).unwrap_or(Vec3::Z);
                let v = self.icrs(d);
                (u[0][i], u[1][i], u[2][i], cz[i]) = (v.x, v.y, v.z, d.z);
            }
            for i in 0..BLOCK {
                taps[i] = map.taps(u[0][i], u[1][i], u[2][i]);
                zl[i] = zodiacal_s10((-se * u[1][i] + ce * u[2][i]).clamp(-1.0, 1.0));
                ag[i] = van_rhijn(cz[i]);
            }
            for (i, (p, d)) in px.iter_mut().zip(ds).enumerate() {
                let Some(d) = d.filter(|d| d.z >= 0.0) else {
                    continue;
                };
                let mw = map.bilinear(taps[i]);
                let l = self.combine(mw, zl[i], ag[i]);
                add(p, l, extinction.rgb(d));
            }
        }
    }
}

/// p += l × t per channel.
#[inline(always)]
fn add(p: &mut [f32; 3], l: [f32; 3], t: [f32; 3]) {
    for k in 0..3 {
        p[k] += l[k] * t[k];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::refraction::refraction_of_apparent;

    #[test]
    fn unrefraction_table_matches_the_formula() {
        // Against the refraction in f64 over a dense sweep of altitudes
        // and azimuths: the angle between the directions.
        let table = Unrefraction::get();
        let mut worst = 0.0f64;
        for i in 0..=20_000 {
            let z = REFRACTION_BELOW_Z as f64 * i as f64 / 20_000.0;
            for az in [0.3f64, 2.0, 4.4] {
                let a = z.asin();
                let d = Vec3::new(
                    (a.cos() * az.sin()) as f32,
                    (a.cos() * az.cos()) as f32,
                    z as f32,
                );
                let got = table.apply(d).as_dvec3();
                let t = a - refraction_of_apparent(a as f32) as f64;
                let want = glam::DVec3::new(t.cos() * az.sin(), t.cos() * az.cos(), t.sin());
                worst = worst.max(got.normalize().angle_between(want));
                assert!(
                    (got.length() - 1.0).abs() < 1e-6,
                    "{z} {az}: |d| = {}",
                    got.length()
                );
            }
        }
        assert!(worst < 5e-7, "{worst} rad");
    }

    #[test]
    fn bands_equal_the_pixel_functions() {
        // Directions over the whole sphere (some missing, some below the
        // horizon), a band of 333 pixels (five full blocks and a partial
        // one): the band adds exactly radiance × extinction.
        let frame = glam::DMat3::from_euler(glam::EulerRot::ZXZ, 0.7, 0.9, 2.1);
        let bg = NightBackground::new(frame);
        let ext = Extinction::from_transmittance(|mu| {
            crate::spectrum::Spectrum::splat((-0.2 / mu.max(0.05)).exp())
        });
        let dirs: Vec<Option<Vec3>> = (0..333 * 40)
            .map(|i| {
                let (a, b) = (i as f32 * 0.013, i as f32 * 0.0071);
                let d = Vec3::new(a.cos() * b.cos(), a.sin() * b.cos(), b.sin().abs() - 0.3);
                (i % 17 != 0).then(|| d.normalize())
            })
            .collect();
        let start: Vec<[f32; 3]> = (0..dirs.len()).map(|i| [i as f32 * 1e-9; 3]).collect();
        for (ds, p0) in dirs.chunks(333).zip(start.chunks(333)) {
            let mut band = p0.to_vec();
            bg.add_band(&ext, &mut band, ds);
            for ((got, d), p) in band.iter().zip(ds).zip(p0) {
                let mut want = *p;
                if let Some(d) = d.filter(|d| d.z >= 0.0) {
                    add(&mut want, bg.radiance(d), ext.rgb(d));
                }
                assert_eq!(got.map(f32::to_bits), want.map(f32::to_bits), "{d:?}");
            }
        }
    }
}
