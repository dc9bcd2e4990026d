//! The diffuse night sky outside the atmosphere, in cd/m²: the Milky Way
//! (a brightness map), the integrated light of faint stars, zodiacal light
//! and airglow. The atmosphere's extinction is applied by the renderer
//! (the same per-direction factors as for stars, `crate::stars::Extinction`).
//!
//! Units: S10 = the surface brightness of one V = 10 star per square degree,
//! 2.54 × 10⁻¹⁰ lx / (π/180)² sr = 8.34 × 10⁻⁷ cd/m² ([`S10_CD_M2`]).
//!
//! * **Milky Way map**: Axel Mellinger's all-sky panorama (Mellinger 2009,
//!   PASP 121, 1180) as shipped by Stellarium 0.22.2 (`textures/milkyway.png`,
//!   stars removed and the high-latitude background subtracted), box-filtered
//!   to 512 × 256 by `tools/gen_milkyway.py`. Frame: plate carrée in ICRS
//!   (J2000), α = 90° − 360° u (mod 360°), δ = 90° − 180° v; the tool checks
//!   it against M42, the LMC, the SMC, M31, the Pleiades and η Car (all within
//!   0.3°). The sky is rotated into the horizon frame of date by the catalogue
//!   stars' ICRS → ENU matrix (precession, nutation, sidereal time, latitude)
//!   after refraction is taken off the altitude below 10° ([`unrefracted`],
//!   tabulated in the apparent zenith cosine: [`Unrefraction`]).
//!   Calibration (in the file header): the integrated starlight of stars
//!   of all magnitudes, averaged over galactic longitude, is ≈ 250 S10 on the
//!   galactic equator and ≈ 25 S10 at the galactic poles (Roach & Megill
//!   1961 as tabulated by Leinert et al. 1998, A&AS 127, 1, §8). No double
//!   counting: the renderer draws the catalogue stars (V ≤ 6.5) as points,
//!   and they carry 40.8 S10 at |b| < 5° and 15.9 S10 at |b| > 60°
//!   (computed by `tools/gen_milkyway.py` from the embedded catalogue), so
//!   the diffuse part is 250 − 40.8 S10 on the equator and 25 − 15.9 = 9.1
//!   S10 at the poles. The map (stars already removed by Stellarium) is
//!   scaled so that its mean over |b| < 5° is the difference, 200.2 S10.
//!   (Drawing fainter stars with `stars.limit_mag` > 6.5 adds their light
//!   again, about 10 S10 more: left as is.)
//! * **Faint-star floor**: 9.1 S10 everywhere (the diffuse galactic-pole
//!   level above); the map adds the excess towards the plane.
//! * **Zodiacal light**: I(β) = 60 + 140 cos⁴ β S10 at ecliptic latitude β,
//!   a fit to Leinert et al. 1998, Table 17, at 90° elongation from the Sun
//!   (≈ 60 S10 at the ecliptic pole, ≈ 200 S10 on the ecliptic); its
//!   dependence on elongation (the brighter cone near the Sun, the
//!   gegenschein) is not modelled. Colour: sunlight (B−V = 0.65).
//! * **Airglow**: 120 S10 at the zenith (≈ 22.6 V mag/arcsec², Leinert et al.
//!   1998 §11 for solar minimum), emitted in a thin layer at 90 km and
//!   brightened towards the horizon by the van Rhijn (1921) factor
//!   1/√(1 − (R/(R + h))² sin² z). Colour: a green tint for the OI 557.7 nm
//!   line that dominates the V band.
//!
//! A dark site with the galactic pole near the zenith adds up to about
//! 120 (airglow) + 60–140 (zodiacal light) + 9 + 15 (the drawn stars,
//! averaged) ≈ 200–280 S10 ≈ 1.7–2.4 × 10⁻⁴ cd/m² outside the atmosphere
//! (21.7–22.0 V mag/arcsec², the natural dark-sky zenith brightness; Benn &
//! Ellison 1998, La Palma), 10–20 % less after extinction.

use std::sync::OnceLock;

use glam::{DMat3, Mat3, Vec3};

use crate::stars::colour_from_bv;

mod block;
pub use block::{Unrefraction, REFRACTION_BELOW_Z};

/// One S10 unit (one V = 10 star per square degree), cd/m².
pub const S10_CD_M2: f64 =
    2.54e-10 / (std::f64::consts::PI / 180.0) / (std::f64::consts::PI / 180.0);
/// Airglow at the zenith, S10.
pub const AIRGLOW_ZENITH_S10: f64 = 120.0;
/// Height of the airglow layer, km.
pub const AIRGLOW_HEIGHT_KM: f64 = 90.0;
/// Integrated starlight at the galactic poles without the drawn catalogue
/// stars, S10 (the floor under the map): 25 − 15.9.
pub const STARLIGHT_FLOOR_S10: f64 = 9.1;
/// Mean obliquity of the ecliptic at J2000.0 (IAU 1976), radians.
pub const OBLIQUITY_J2000: f32 = 0.409_092_8;
/// Earth radius of the van Rhijn factor, km.
pub const EARTH_RADIUS_KM: f64 = 6371.0;

/// Zodiacal light at ecliptic latitude β given as sin β, S10.
pub fn zodiacal_s10(sin_beta: f32) -> f32 {
    let c2 = (1.0 - sin_beta * sin_beta).max(0.0);
    60.0 + 140.0 * c2 * c2
}

/// The van Rhijn factor of a thin emitting layer at `AIRGLOW_HEIGHT_KM`
/// for a line of sight with zenith cosine `cos_z` (1 at the zenith, ≈ 5.6 at
/// the horizon).
pub fn van_rhijn(cos_z: f32) -> f32 {
    let k = (EARTH_RADIUS_KM / (EARTH_RADIUS_KM + AIRGLOW_HEIGHT_KM)) as f32;
    let s2 = (1.0 - cos_z * cos_z).max(0.0);
    1.0 / (1.0 - k * k * s2).max(1e-6).sqrt()
}

pub use crate::refraction::unrefracted;

/// The Milky Way brightness map (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct MilkyWayMap {
    w: usize,
    h: usize,
    /// Linear sRGB per texel, cd/m².
    data: Vec<[f32; 3]>,
}

const MAP_BYTES: &[u8] = include_bytes!("../data/milkyway.bin");

fn srgb_decode(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

impl MilkyWayMap {
    /// Decodes a map in the `milkyway.bin` format (`tools/gen_milkyway.py`).
    pub fn from_bytes(b: &[u8]) -> Result<Self, String> {
        if b.len() < 16 || &b[..4] != b"HMMW" {
            return Err("milkyway.bin: bad magic".into());
        }
        let u16_at = |i: usize| u16::from_le_bytes([b[i], b[i + 1]]) as usize;
        if u16_at(4) != 1 {
            return Err("milkyway.bin: unsupported version".into());
        }
        let (w, h) = (u16_at(6), u16_at(8));
        let scale = f32::from_le_bytes([b[12], b[13], b[14], b[15]]);
        if w < 2 || h < 2 || b.len() != 16 + w * h * 3 || !(scale.is_finite() && scale > 0.0) {
            return Err("milkyway.bin: size does not match its header".into());
        }
        let lut: Vec<f32> = (0..=255u8).map(srgb_decode).collect();
        let data = b[16..]
            .chunks_exact(3)
            .map(|c| {
                [
                    lut[c[0] as usize] * scale,
                    lut[c[1] as usize] * scale,
                    lut[c[2] as usize] * scale,
                ]
            })
            .collect();
        Ok(MilkyWayMap { w, h, data })
    }

    /// The embedded map, decoded on first use.
    pub fn embedded() -> Result<&'static MilkyWayMap, String> {
        static CELL: OnceLock<Result<MilkyWayMap, String>> = OnceLock::new();
        CELL.get_or_init(|| MilkyWayMap::from_bytes(MAP_BYTES))
            .as_ref()
            .map_err(Clone::clone)
    }

    /// Width and height of the map, texels (plate carrée, see the module
    /// documentation).
    pub fn size(&self) -> (usize, usize) {
        (self.w, self.h)
    }

    /// The texels, row-major from δ = +90° and α = 90° (linear sRGB, cd/m²),
    /// for renderers that upload the map (e.g. `himmel-wgpu`).
    pub fn texels(&self) -> &[[f32; 3]] {
        &self.data
    }

    /// Luminance (linear sRGB, cd/m²) towards the ICRS unit vector `u`,
    /// bilinear, wrapping in right ascension.
    pub fn radiance(&self, u: Vec3) -> [f32; 3] {
        self.bilinear(self.taps(u.x, u.y, u.z))
    }

    /// The bilinear taps of [`Self::radiance`] towards ICRS (x, y, z): the
    /// first texel's column and row and the weights of the next ones.
    /// Without branches (selects), so that a loop over pixels vectorises.
    #[inline(always)]
    pub(crate) fn taps(&self, ux: f32, uy: f32, uz: f32) -> (i32, i32, f32, f32) {
        let ra = crate::angle::atan2(uy, ux);
        let dec = crate::angle::asin(uz);
        // u = 0.25 − α/2π in [−0.25, 0.75] for α in [−π, π]; no divisions
        // or remainders on this hot path.
        let mut fu = 0.25 - ra * (0.5 / std::f32::consts::PI);
        if fu < 0.0 {
            fu += 1.0;
        }
        let fv = 0.5 - dec * (1.0 / std::f32::consts::PI);
        let x = fu * self.w as f32 - 0.5;
        let y = (fv * self.h as f32 - 0.5).clamp(0.0, (self.h - 1) as f32);
        // floor(x) for x ≥ −1 (x ≥ −0.5 here) and floor(y) for y ≥ 0 by
        // truncation: exact, without a call to the C library's `floorf`
        // (no SSE4.1 rounding instruction in the baseline target).
        // (x and y are below the map's size: `i32` holds them.)
        let x0 = if x < 0.0 { -1.0 } else { (x as i32) as f32 };
        let y0 = (y as i32) as f32;
        let (tx, ty) = (x - x0, y - y0);
        let last = self.w as i32 - 1;
        let xi0 = if x0 < 0.0 {
            last
        } else {
            (x0 as i32).min(last)
        };
        (xi0, y0 as i32, tx, ty)
    }

    /// The bilinear interpolation of the [`Self::taps`].
    #[inline(always)]
    pub(crate) fn bilinear(&self, (xi0, yi0, tx, ty): (i32, i32, f32, f32)) -> [f32; 3] {
        let (xi0, yi0) = (xi0.max(0) as usize, yi0.max(0) as usize);
        let xi1 = if xi0 + 1 >= self.w { 0 } else { xi0 + 1 };
        let yi1 = (yi0 + 1).min(self.h - 1);
        let t = |xi: usize, yi: usize| self.data[yi * self.w + xi];
        let (a, b, c, d) = (t(xi0, yi0), t(xi1, yi0), t(xi0, yi1), t(xi1, yi1));
        let mut out = [0.0; 3];
        for k in 0..3 {
            let top = a[k] + (b[k] - a[k]) * tx;
            let bot = c[k] + (d[k] - c[k]) * tx;
            out[k] = top + (bot - top) * ty;
        }
        out
    }
}

/// The whole diffuse night sky for one frame.
#[derive(Debug, Clone)]
pub struct NightBackground {
    enu_to_icrs: Mat3,
    map: Option<&'static MilkyWayMap>,
    airglow: [f32; 3],
    zodiacal: [f32; 3],
    floor: [f32; 3],
    /// sin and cos of [`OBLIQUITY_J2000`], once per frame.
    obliquity_sin_cos: (f32, f32),
    /// The refraction taken off low altitudes.
    unrefraction: &'static Unrefraction,
}

fn scaled(rgb: [f32; 3], s10: f64) -> [f32; 3] {
    let l = (s10 * S10_CD_M2) as f32;
    [rgb[0] * l, rgb[1] * l, rgb[2] * l]
}

impl NightBackground {
    /// The background for the ICRS → ENU rotation of the frame.
    pub fn new(icrs_to_enu: DMat3) -> Self {
        // OI 557.7 nm tint, luminance 1.
        let green = [0.75f32, 1.1, 0.55];
        let y = crate::spectrum::luminance(green);
        NightBackground {
            enu_to_icrs: icrs_to_enu.transpose().as_mat3(),
            map: MilkyWayMap::embedded().ok(),
            airglow: scaled(
                [green[0] / y, green[1] / y, green[2] / y],
                AIRGLOW_ZENITH_S10,
            ),
            zodiacal: scaled(colour_from_bv(0.65), 1.0),
            floor: scaled(colour_from_bv(0.8), STARLIGHT_FLOOR_S10),
            obliquity_sin_cos: OBLIQUITY_J2000.sin_cos(),
            unrefraction: Unrefraction::get(),
        }
    }

    /// The ENU → ICRS rotation of the frame (the transpose of the
    /// catalogue stars' ICRS → ENU matrix).
    pub fn enu_to_icrs(&self) -> Mat3 {
        self.enu_to_icrs
    }

    /// The Milky Way map, if it decoded.
    pub fn map(&self) -> Option<&'static MilkyWayMap> {
        self.map
    }

    /// The linear sRGB colours (cd/m²) of [`Self::radiance`]: the airglow
    /// at the zenith (× the van Rhijn factor), the zodiacal light per S10
    /// (× [`zodiacal_s10`]) and the faint-star floor.
    pub fn colours(&self) -> [[f32; 3]; 3] {
        [self.airglow, self.zodiacal, self.floor]
    }

    /// Luminance (linear sRGB, cd/m², before extinction) towards ENU
    /// direction `d` (unit); zero below the horizon.
    #[inline]
    pub fn radiance(&self, d: Vec3) -> [f32; 3] {
        if d.z < 0.0 {
            return [0.0; 3];
        }
        // Low down, look up the sky where refraction brings it from (Bennett,
        // Meeus eq. 16.3; 5′ at 10°, 29′ at the horizon), as for the stars
        // ([`Unrefraction`]).
        let u = self.icrs(d);
        let mw = self.map.map_or([0.0; 3], |m| m.radiance(u));
        let (se, ce) = self.obliquity_sin_cos;
        let zl = zodiacal_s10((-se * u.y + ce * u.z).clamp(-1.0, 1.0));
        self.combine(mw, zl, van_rhijn(d.z))
    }

    /// The map's light `mw` plus the floor, the zodiacal light of `zl` S10
    /// and the airglow × the van Rhijn factor `ag`.
    #[inline(always)]
    fn combine(&self, mw: [f32; 3], zl: f32, ag: f32) -> [f32; 3] {
        let mut out = [0.0; 3];
        for k in 0..3 {
            out[k] = mw[k] + self.floor[k] + self.zodiacal[k] * zl + self.airglow[k] * ag;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::luminance;

    fn icrs(ra_deg: f32, dec_deg: f32) -> Vec3 {
        let (ra, dec) = (ra_deg.to_radians(), dec_deg.to_radians());
        Vec3::new(dec.cos() * ra.cos(), dec.cos() * ra.sin(), dec.sin())
    }

    #[test]
    fn map_decodes_and_is_oriented() {
        let m = MilkyWayMap::embedded().unwrap();
        // The Carina/η Car region and the Scutum star cloud are far brighter
        // than the galactic poles (NGP 192.86°, +27.13°; SGP 12.86°, −27.13°).
        let y = |ra, dec| luminance(m.radiance(icrs(ra, dec)));
        let ngp = y(192.86, 27.13);
        let sgp = y(12.86, -27.13);
        for (ra, dec) in [(161.3, -59.7), (280.0, -8.0), (83.8, -5.4), (80.9, -69.8)] {
            let v = y(ra, dec);
            assert!(
                v > 20.0 * (ngp + sgp + 1e-9),
                "({ra}, {dec}): {v} vs {ngp}, {sgp}"
            );
        }
        assert!(MilkyWayMap::from_bytes(b"HMMW").is_err());
        assert!(MilkyWayMap::from_bytes(&MAP_BYTES[..1000]).is_err());
    }

    #[test]
    fn band_mean_matches_its_calibration() {
        // Mean over |b| < 5° of the map = 200.2 S10 (by construction of the
        // header scale; checks the decoding and the frame together).
        let m = MilkyWayMap::embedded().unwrap();
        let gal_to_icrs = glam::Mat3::from_cols_array(&[
            -0.054_875_56,
            -0.873_437_1,
            -0.483_835,
            0.494_109_43,
            -0.444_829_63,
            0.746_982_2,
            -0.867_666_1,
            -0.198_076_37,
            0.455_983_8,
        ]);
        let (mut s, mut n) = (0.0f64, 0.0f64);
        for i in 0..720 {
            for j in -10..=10 {
                let (l, b) = (
                    (i as f32 * 0.5).to_radians(),
                    (j as f32 * 0.45).to_radians(),
                );
                let g = Vec3::new(b.cos() * l.cos(), b.cos() * l.sin(), b.sin());
                s += luminance(m.radiance(gal_to_icrs * g)) as f64 * b.cos() as f64;
                n += b.cos() as f64;
            }
        }
        let band = s / n / S10_CD_M2;
        assert!((band / 200.2 - 1.0).abs() < 0.1, "{band} S10");
    }

    #[test]
    fn airglow_and_zodiacal_light_shapes() {
        assert!((van_rhijn(1.0) - 1.0).abs() < 1e-6);
        let h = van_rhijn(0.0);
        assert!((5.0..6.5).contains(&h), "{h}");
        assert!((zodiacal_s10(0.0) - 200.0).abs() < 1e-3);
        assert!((zodiacal_s10(1.0) - 60.0).abs() < 1e-3);
        // Unrefracting undoes the stars' refraction (within the two formulas'
        // 0.1′ mutual consistency, Meeus ch. 16).
        for alt in [0.0f64, 2.0, 9.0] {
            let d = glam::DVec3::new(0.0, alt.to_radians().cos(), alt.to_radians().sin());
            let back = unrefracted(crate::stars::refracted(d).as_vec3());
            let err = (back.z.asin() as f64 - alt.to_radians()).abs().to_degrees() * 60.0;
            assert!(err < 0.2, "{alt}°: {err}′");
        }
    }
}
