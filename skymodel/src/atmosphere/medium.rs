//! The participating medium: density profiles, spectral coefficients,
//! phase functions and the spherical geometry shared by the LUT path
//! ([`super::lut`]) and the brute-force reference ([`super::reference`]).
//!
//! Positions are described by the distance r from the planet's centre (km)
//! and cosines of zenith angles μ measured at that point.

use super::params::AtmosphereParams;
use crate::spectrum::{Spectrum, BANDS};
use crate::units::Nanometres;

/// Ozone absorption cross-section at 293 K, m² per molecule, every 10 nm
/// from 360 nm to 830 nm (Serdyuchenko et al. 2014, "High spectral
/// resolution ozone absorption cross-sections", AMT 7; values as tabulated
/// in Bruneton's 2017 demo). This is the Chappuis band that keeps the
/// twilight zenith blue.
const OZONE_CROSS_SECTION_M2: [f64; 48] = [
    1.18e-27, 2.182e-28, 2.818e-28, 6.636e-28, 1.527e-27, 2.763e-27, 5.52e-27, 8.451e-27,
    1.582e-26, 2.316e-26, 3.669e-26, 4.924e-26, 7.752e-26, 9.016e-26, 1.48e-25, 1.602e-25,
    2.139e-25, 2.755e-25, 3.091e-25, 3.5e-25, 4.266e-25, 4.672e-25, 4.398e-25, 4.701e-25,
    5.019e-25, 4.305e-25, 3.74e-25, 3.215e-25, 2.662e-25, 2.238e-25, 1.852e-25, 1.473e-25,
    1.209e-25, 9.423e-26, 7.455e-26, 6.566e-26, 5.105e-26, 4.15e-26, 4.228e-26, 3.237e-26,
    2.451e-26, 2.801e-26, 2.534e-26, 1.624e-26, 1.465e-26, 2.078e-26, 1.383e-26, 7.105e-27,
];

/// Ozone cross-section at `nm` (linear interpolation of the 10 nm table), m².
pub fn ozone_cross_section_m2(nm: Nanometres) -> f64 {
    let x = ((nm - 360.0) / 10.0).clamp(0.0, 46.999);
    let i = x as usize;
    let f = x - i as f64;
    OZONE_CROSS_SECTION_M2[i] * (1.0 - f) + OZONE_CROSS_SECTION_M2[i + 1] * f
}

/// Molecules per m² in one Dobson unit.
pub const DOBSON_UNIT_M2: f64 = 2.686_7e20;

/// The atmosphere as the integrators see it (coefficients in km⁻¹).
#[derive(Debug, Clone)]
pub struct Medium {
    /// Ground radius, km.
    pub bottom: f32,
    /// Top-of-atmosphere radius, km.
    pub top: f32,
    /// Rayleigh scattering at sea level, km⁻¹ (no absorption).
    pub rayleigh: Spectrum,
    /// Aerosol scattering at sea level, km⁻¹.
    pub mie_scattering: Spectrum,
    /// Aerosol extinction at sea level, km⁻¹.
    pub mie_extinction: Spectrum,
    /// Ozone absorption at the peak density, km⁻¹.
    pub ozone: Spectrum,
    /// 1 / Rayleigh scale height, km⁻¹.
    pub inv_h_r: f32,
    /// 1 / aerosol scale height, km⁻¹.
    pub inv_h_m: f32,
    /// Ozone peak altitude, km.
    pub ozone_peak: f32,
    /// 1 / ozone half-width, km⁻¹.
    pub inv_ozone_w: f32,
    /// Cornette–Shanks asymmetry.
    pub g: f32,
    /// Ground albedo.
    pub albedo: f32,
    /// Angular radius of the Sun used for the soft Earth-shadow edge, radians.
    pub sun_angular_radius: f32,
}

/// Densities (relative to their reference) of the three constituents.
#[derive(Debug, Clone, Copy, Default)]
pub struct Densities {
    /// Air (Rayleigh), relative to sea level.
    pub rayleigh: f32,
    /// Aerosols, relative to sea level.
    pub mie: f32,
    /// Ozone, relative to its peak.
    pub ozone: f32,
}

impl Medium {
    /// The medium of `p`, with coefficients at the band centres.
    pub fn new(p: &AtmosphereParams) -> Self {
        let rayleigh = Spectrum::from_fn(|nm| {
            let um = nm / 1000.0;
            p.rayleigh_k / um.powi(4) * 1000.0
        });
        let mie_ext550 = p.aerosol_scattering / p.aerosol_albedo.max(1e-6) * p.aerosol_density;
        let mie_extinction =
            Spectrum::from_fn(|nm| mie_ext550 * (nm / 550.0).powf(-p.aerosol_angstrom) * 1000.0);
        let mie_scattering = mie_extinction * p.aerosol_albedo as f32;
        // Tent profile: column = n_peak × half-width.
        let n_peak = p.ozone_du * DOBSON_UNIT_M2 / (p.ozone_half_width_km * 1000.0);
        let ozone = Spectrum::from_fn(|nm| n_peak * ozone_cross_section_m2(nm) * 1000.0);
        Medium {
            bottom: p.ground_radius_km as f32,
            top: (p.ground_radius_km + p.thickness_km) as f32,
            rayleigh,
            mie_scattering,
            mie_extinction,
            ozone,
            inv_h_r: (1.0 / p.rayleigh_scale_height_km) as f32,
            inv_h_m: (1.0 / p.aerosol_scale_height_km) as f32,
            ozone_peak: p.ozone_peak_km as f32,
            inv_ozone_w: (1.0 / p.ozone_half_width_km) as f32,
            g: p.aerosol_g as f32,
            albedo: p.ground_albedo as f32,
            sun_angular_radius: 0.004_65,
        }
    }

    /// Relative densities at radius `r` (km).
    #[inline]
    pub fn densities(&self, r: f32) -> Densities {
        let h = (r - self.bottom).max(0.0);
        Densities {
            rayleigh: (-h * self.inv_h_r).exp(),
            mie: (-h * self.inv_h_m).exp(),
            ozone: (1.0 - (h - self.ozone_peak).abs() * self.inv_ozone_w).max(0.0),
        }
    }

    /// Extinction coefficient for given densities, km⁻¹.
    #[inline]
    pub fn extinction(&self, d: Densities) -> Spectrum {
        self.rayleigh * d.rayleigh + self.mie_extinction * d.mie + self.ozone * d.ozone
    }

    /// Extinction from integrated densities (column amounts, km).
    #[inline]
    pub fn optical_depth(&self, col: Densities) -> Spectrum {
        self.extinction(col)
    }

    /// Scattering coefficients (Rayleigh, aerosol), km⁻¹.
    #[inline]
    pub fn scattering(&self, d: Densities) -> (Spectrum, Spectrum) {
        (self.rayleigh * d.rayleigh, self.mie_scattering * d.mie)
    }

    /// Distance from radius `r` along a ray of zenith cosine `mu` to the top
    /// of the atmosphere, km (Bruneton 2017, DistanceToTopAtmosphereBoundary).
    #[inline]
    pub fn distance_to_top(&self, r: f32, mu: f32) -> Km32 {
        let disc = r * r * (mu * mu - 1.0) + self.top * self.top;
        (-r * mu + safe_sqrt(disc)).max(0.0)
    }

    /// Distance to the ground, km (meaningful when [`Self::hits_ground`]).
    #[inline]
    pub fn distance_to_bottom(&self, r: f32, mu: f32) -> Km32 {
        let disc = r * r * (mu * mu - 1.0) + self.bottom * self.bottom;
        (-r * mu - safe_sqrt(disc)).max(0.0)
    }

    /// Whether a ray from `r` with zenith cosine `mu` hits the ground.
    #[inline]
    pub fn hits_ground(&self, r: f32, mu: f32) -> bool {
        mu < 0.0 && r * r * (mu * mu - 1.0) + self.bottom * self.bottom >= 0.0
    }

    /// Where a ray from radius `r` with zenith cosine `mu` leaves the
    /// atmosphere: (distance, km; whether it ends on the ground rather than
    /// at the top).
    #[inline]
    pub fn ray_end(&self, r: f32, mu: f32) -> (f32, bool) {
        if self.hits_ground(r, mu) {
            (self.distance_to_bottom(r, mu), true)
        } else {
            (self.distance_to_top(r, mu), false)
        }
    }

    /// Fraction of the Sun's disk above the horizon of a point at radius
    /// `r` when the Sun's zenith cosine there is `mu_s`: the Earth's shadow
    /// with a soft edge one solar diameter wide (Bruneton 2017 uses the
    /// same smoothstep over the Sun's angular size).
    #[inline]
    pub fn sun_visibility(&self, r: f32, mu_s: f32) -> f32 {
        let sin_h = (self.bottom / r).min(1.0);
        let cos_h = -safe_sqrt(1.0 - sin_h * sin_h);
        let a = self.sun_angular_radius * sin_h;
        smoothstep(-a, a, mu_s - cos_h)
    }
}

/// Kilometres in single precision (render math, observer-relative).
pub type Km32 = f32;

/// √max(x, 0) (Bruneton 2017 SafeSqrt).
#[inline]
pub fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

/// Clamps a cosine to [−1, 1] (Bruneton 2017 ClampCosine).
#[inline]
pub fn clamp_cosine(x: f32) -> f32 {
    x.clamp(-1.0, 1.0)
}

/// Hermite smoothstep.
#[inline]
pub fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Rayleigh phase function, sr⁻¹: 3/(16π) (1 + cos²θ).
#[inline]
pub fn rayleigh_phase(cos_theta: f32) -> f32 {
    3.0 / (16.0 * std::f32::consts::PI) * (1.0 + cos_theta * cos_theta)
}

/// Cornette–Shanks (1992) phase function, sr⁻¹:
/// 3/(8π) (1 − g²)(1 + cos²θ) / ((2 + g²)(1 + g² − 2g cosθ)^{3/2}).
/// Normalised to 1 over the sphere for |g| < 1 (within 0.5 % for g = 0.8,
/// where the (1 + cos²θ) factor makes it only approximately normalised;
/// the reference integrator uses the same function).
#[inline]
pub fn cornette_shanks_phase(g: f32, cos_theta: f32) -> f32 {
    let k = 3.0 / (8.0 * std::f32::consts::PI) * (1.0 - g * g) / (2.0 + g * g);
    let d = (1.0 + g * g - 2.0 * g * cos_theta).max(1e-6);
    k * (1.0 + cos_theta * cos_theta) / (d * d.sqrt())
}

/// Henyey–Greenstein phase function, sr⁻¹ (used to sample the
/// Cornette–Shanks function in the reference integrator).
#[inline]
pub fn henyey_greenstein_phase(g: f32, cos_theta: f32) -> f32 {
    let d = (1.0 + g * g - 2.0 * g * cos_theta).max(1e-6);
    (1.0 - g * g) / (4.0 * std::f32::consts::PI * d * d.sqrt())
}

/// Band count (re-exported for the LUT code).
pub const N: usize = BANDS;

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere_integral(f: impl Fn(f32) -> f32) -> f64 {
        let n = 20_000;
        let mut s = 0.0f64;
        for i in 0..n {
            let mu = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
            s += f(mu as f32) as f64;
        }
        s * 2.0 / n as f64 * 2.0 * std::f64::consts::PI
    }

    #[test]
    fn phase_functions_are_normalised() {
        assert!((sphere_integral(rayleigh_phase) - 1.0).abs() < 1e-3);
        assert!((sphere_integral(|m| henyey_greenstein_phase(0.8, m)) - 1.0).abs() < 5e-3);
        assert!((sphere_integral(|m| cornette_shanks_phase(0.8, m)) - 1.0).abs() < 0.02);
        assert!((sphere_integral(|m| cornette_shanks_phase(0.0, m)) - 1.0).abs() < 1e-3);
    }

    #[test]
    fn default_coefficients_match_hillaire_table() {
        let m = Medium::new(&AtmosphereParams::default());
        // Band 4 is centred on 560 nm: Rayleigh ≈ 12.7e-3 km⁻¹ (13.56e-3 at 550 nm).
        let r560 = m.rayleigh.0[4];
        assert!((r560 - 0.01265).abs() < 3e-4, "{r560}");
        // Ozone at 560 nm ≈ 1.9e-3 km⁻¹ at the peak (Hillaire: 1.881e-3 at 550).
        let o = m.ozone.0[4];
        assert!((o - 2.0e-3).abs() < 4e-4, "{o}");
        // Vertical optical depths at 560 nm: Rayleigh ≈ 0.09 (Bucholtz 1995:
        // 0.0973 at 550 nm), aerosol ≈ 0.1 (the default AOD 0.107 at 550 nm),
        // ozone ≈ 0.03 (300 DU).
        let tau_r = r560 * 8.0;
        assert!((tau_r - 0.093).abs() < 0.01, "{tau_r}");
        let tau_m = m.mie_extinction.0[4] * 1.2;
        assert!((tau_m - 0.105).abs() < 0.01, "{tau_m}");
        let tau_o = o * 15.0;
        assert!((tau_o - 0.033).abs() < 0.005, "{tau_o}");
    }

    #[test]
    fn geometry_edges_are_finite() {
        let m = Medium::new(&AtmosphereParams::default());
        for &r in &[m.bottom, m.bottom + 0.001, m.top - 0.001, m.top] {
            for &mu in &[-1.0f32, -0.5, -1e-6, 0.0, 1e-6, 0.5, 1.0] {
                assert!(m.distance_to_top(r, mu).is_finite());
                assert!(m.distance_to_bottom(r, mu).is_finite());
                assert!(m.sun_visibility(r, mu).is_finite());
            }
        }
        assert_eq!(m.sun_visibility(m.bottom, 0.5), 1.0);
        assert_eq!(m.sun_visibility(m.bottom, -0.5), 0.0);
    }
}
