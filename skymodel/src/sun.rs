//! The Sun's disk: true angular size (× `sun_scale`), wavelength-dependent
//! limb darkening, and a radiance normalised so that the disk's integrated
//! illuminance equals the extraterrestrial solar illuminance at the Sun's
//! distance (times the atmospheric transmittance when the atmosphere is on).
//!
//! Limb darkening: I(μ)/I(1) = μ^α(λ) with α(λ) = −0.023 + 0.292 / (λ in µm)
//! (Hestroffer & Magnan 1998, A&A 333, 338, eq. 4, fitted to Neckel & Labs
//! 1994), μ = cos of the angle between the line of sight and the solar
//! surface normal. A larger `sun_scale` enlarges the disk and lowers its
//! radiance so that the illuminance stays the physical one.

use glam::{DVec3, Vec3};
use serde::Serialize;

use crate::spectrum::{band_centre_nm, BandWeights, Spectrum, BANDS};
use crate::units::{Degrees, Lux, Radians};

/// Radiance of the inner (K + F) corona relative to the mean radiance of
/// the solar disk at `r` solar radii from the Sun's centre (r ≥ 1):
/// 10⁻⁶ (0.0532 r^−2.5 + 1.425 r^−7 + 2.565 r^−17) (Baumbach 1937, as given
/// in Allen's Astrophysical Quantities, 4th ed., the solar corona). 0 inside the disk.
pub fn corona_relative(r: f64) -> f64 {
    if r < 1.0 {
        return 0.0;
    }
    1e-6 * (0.0532 * r.powf(-2.5) + 1.425 * r.powi(-7) + 2.565 * r.powi(-17))
}

/// The corona's total light relative to the solar disk's: ∫ 2πr B(r) dr / π
/// over r ≥ 1 for [`corona_relative`] = 2 × 10⁻⁶ (0.0532/0.5 + 1.425/5 +
/// 2.565/15) ≈ 1.12 × 10⁻⁶.
pub const CORONA_FRACTION: f64 = 2e-6 * (0.0532 / 0.5 + 1.425 / 5.0 + 2.565 / 15.0);

/// Limb-darkening exponent α(λ) of Hestroffer & Magnan (1998).
pub fn limb_darkening_alpha(nm: f64) -> f64 {
    -0.023 + 0.292 / (nm / 1000.0)
}

/// A Sun disk ready to shade.
#[derive(Debug, Clone)]
pub struct SunDisk {
    /// Centre direction (ENU, unit, apparent/refracted).
    pub centre: Vec3,
    /// Drawn angular radius, radians.
    pub radius: f32,
    cos_radius: f32,
    sin_radius: f32,
    /// Centre radiance per band, per unit solar irradiance at 1 AU (sr⁻¹),
    /// already scaled by (1 AU / distance)².
    centre_radiance: Spectrum,
    alpha: [f32; BANDS],
    weights: BandWeights,
}

impl SunDisk {
    /// A disk at `centre` (ENU unit vector) with angular radius `radius`
    /// (drawn), carrying the solar irradiance × `irradiance_scale` (relative to 1 AU).
    pub fn new(centre: Vec3, radius: Radians, irradiance_scale: f64) -> Self {
        let radius = radius.clamp(1e-6, 0.5);
        let mut alpha = [0.0f32; BANDS];
        let mut centre_radiance = Spectrum::ZERO;
        // ∫ I dΩ over the cap with I = I0 μ^α, μ = sqrt(1 − (sin γ / sin R)²).
        let n = 2000;
        let sr = radius.sin();
        for b in 0..BANDS {
            let a = limb_darkening_alpha(band_centre_nm(b));
            alpha[b] = a as f32;
            let mut integral = 0.0;
            for i in 0..n {
                let g0 = radius * i as f64 / n as f64;
                let g1 = radius * (i + 1) as f64 / n as f64;
                let g = 0.5 * (g0 + g1);
                let rho = (g.sin() / sr).min(1.0);
                let mu = (1.0 - rho * rho).max(0.0).sqrt();
                integral += mu.powf(a) * std::f64::consts::TAU * (g0.cos() - g1.cos());
            }
            centre_radiance.0[b] = (irradiance_scale / integral) as f32;
        }
        SunDisk {
            centre: centre.normalize(),
            radius: radius as f32,
            cos_radius: radius.cos() as f32,
            sin_radius: sr as f32,
            centre_radiance,
            alpha,
            weights: BandWeights::solar(),
        }
    }

    /// Whether `dir` (unit) may fall on the disk.
    #[inline]
    pub fn covers(&self, dir: Vec3) -> bool {
        dir.dot(self.centre) >= self.cos_radius
    }

    /// Band radiance transfer factor (sr⁻¹, relative to the 1 AU solar
    /// irradiance) of the disk in direction `dir`; zero off the disk.
    pub fn transfer(&self, dir: Vec3) -> Spectrum {
        let c = dir.dot(self.centre);
        if c < self.cos_radius {
            return Spectrum::ZERO;
        }
        let s = dir.cross(self.centre).length();
        let rho = (s / self.sin_radius).min(1.0);
        let mu = (1.0 - rho * rho).max(0.0).sqrt();
        let mut out = self.centre_radiance;
        for b in 0..BANDS {
            out.0[b] *= mu.powf(self.alpha[b]);
        }
        out
    }

    /// Linear sRGB radiance (cd/m²) in direction `dir`, after the band
    /// transmittance `t` along the line of sight.
    pub fn radiance_rgb(&self, dir: Vec3, t: &Spectrum) -> [f32; 3] {
        let f = self.transfer(dir) * *t;
        crate::spectrum::clip_to_gamut(self.weights.to_rgb(&f))
    }
}

/// The Sun for one instant and observer.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SunState {
    /// Unit vector towards the Sun's refracted apparent place (ENU: x East, y North, z Zenith).
    pub enu: [f64; 3],
    /// Topocentric apparent altitude without refraction, degrees.
    pub alt_deg: Degrees,
    /// Altitude with standard refraction (1010 hPa, 10 °C), degrees.
    pub alt_refracted_deg: Degrees,
    /// Azimuth from North through East, degrees.
    pub az_deg: Degrees,
    /// Topocentric distance, km.
    pub distance_km: f64,
    /// True angular radius, radians.
    pub angular_radius: Radians,
    /// Extraterrestrial solar illuminance at this distance, lux.
    pub illuminance_lux: Lux,
    /// (1 AU / distance)².
    pub irradiance_scale: f64,
    /// Fraction of the solar disk not hidden by the Moon (1 outside solar
    /// eclipses; uniform-disk overlap of the topocentric disks,
    /// [`himmel_astro::events::solar_eclipse::disk_overlap_fraction`]).
    pub visible_fraction: f64,
}

impl SunState {
    /// The direction as a glam vector.
    pub fn dir(&self) -> DVec3 {
        DVec3::from_array(self.enu)
    }

    /// The irradiance scale of the sunlight that lights the sky and the
    /// ground: (1 AU / distance)² × (the visible fraction of the disk + the
    /// corona's [`CORONA_FRACTION`]); a solar eclipse dims the
    /// sky in proportion. (The light scattered into the umbra from the
    /// sunlit atmosphere outside it, which makes the real sky at totality
    /// ~10⁻⁴ of daylight, is not modelled: totality is darker here.)
    pub fn sky_irradiance_scale(&self) -> f64 {
        self.irradiance_scale * (self.visible_fraction + CORONA_FRACTION).min(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Integrates the disk luminance over a fine grid of directions.
    fn integrated_lux(d: &SunDisk) -> f64 {
        let w = BandWeights::solar();
        let n = 600;
        let r = d.radius as f64 * 1.2;
        let (t, b) = (Vec3::X, Vec3::Y);
        let mut s = 0.0;
        for i in 0..n {
            for j in 0..n {
                let x = -r + 2.0 * r * (i as f64 + 0.5) / n as f64;
                let y = -r + 2.0 * r * (j as f64 + 0.5) / n as f64;
                let dir = (Vec3::Z + t * x as f32 + b * y as f32).normalize();
                let da = (2.0 * r / n as f64).powi(2) / (1.0 + x * x + y * y).powf(1.5);
                s += w.to_y(&d.transfer(dir)) as f64 * da;
            }
        }
        s
    }

    #[test]
    fn disk_illuminance_is_the_solar_illuminance() {
        let w = BandWeights::solar();
        for &(radius, scale) in &[(0.004_65f64, 1.0f64), (0.0465, 0.967)] {
            let d = SunDisk::new(Vec3::Z, radius, scale);
            let e = integrated_lux(&d);
            let want = w.solar_illuminance_lux() * scale;
            assert!((e / want - 1.0).abs() < 0.01, "{e} vs {want}");
        }
    }

    #[test]
    fn corona_integral_matches_its_fraction() {
        let (mut s, n) = (0.0, 200_000);
        let r_max = 200.0f64;
        for i in 0..n {
            let r = 1.0 + (r_max - 1.0) * (i as f64 + 0.5) / n as f64;
            s += 2.0 * r * corona_relative(r) * (r_max - 1.0) / n as f64;
        }
        assert!((s / CORONA_FRACTION - 1.0).abs() < 0.03, "{s}");
        assert_eq!(corona_relative(0.5), 0.0);
    }

    #[test]
    fn limb_is_darker_and_redder() {
        let d = SunDisk::new(Vec3::Z, 0.004_65, 1.0);
        let centre = d.radiance_rgb(Vec3::Z, &Spectrum::ONE);
        let edge_dir = (Vec3::Z + Vec3::X * 0.0046).normalize();
        let edge = d.radiance_rgb(edge_dir, &Spectrum::ONE);
        assert!(edge[1] < 0.6 * centre[1]);
        assert!(edge[0] / edge[2] > centre[0] / centre[2]);
        // Centre luminance ≈ 2.0e9 cd/m² (measured: ~1.6e9 cd/m² at sea level at noon).
        let y = crate::spectrum::luminance(centre);
        assert!((1.5e9..2.6e9).contains(&y), "{y}");
        assert!(!d.covers((Vec3::Z + Vec3::X * 0.01).normalize()));
    }
}
