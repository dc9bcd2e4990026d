//! Atmosphere parameters (serde, part of the [`Scene`](crate::Scene)) and
//! LUT settings.
//!
//! Defaults describe a clear mid-latitude atmosphere as in Bruneton (2017,
//! "precomputed_atmospheric_scattering" demo) and Hillaire (2020, "A
//! scalable and production ready sky and atmosphere rendering technique",
//! table 1): Rayleigh scattering 5.802 / 13.558 / 33.1 ×10⁻⁶ m⁻¹ at
//! 680 / 550 / 440 nm with an 8 km scale height; 300 Dobson units of ozone
//! in a tent profile 10–40 km peaking at 25 km; aerosols with
//! single-scattering albedo 0.9, 1.2 km scale height and a Cornette–Shanks
//! phase function with g = 0.8. The aerosol *amount* departs from those
//! demos (whose 3.996 ×10⁻⁶ m⁻¹ is an aerosol optical depth of only 0.005):
//! the default is 7.992 ×10⁻⁵ m⁻¹ at 550 nm, an aerosol optical depth of
//! 0.107, with Ångström exponent 1.3 (Ångström 1929) — a clear continental
//! sky, which is what the CIE "clear, low turbidity" sky (type 12) and
//! measured clear-sky zenith luminances describe.

use serde::{Deserialize, Serialize};

use crate::units::show;

/// Physical parameters of the atmosphere (documented defaults and ranges,
/// checked by [`AtmosphereParams::validate`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AtmosphereParams {
    /// Radius of the ground sphere, km, in [100, 100000] (default 6360).
    pub ground_radius_km: f64,
    /// Thickness of the atmosphere, km, in [1, 1000] (default 100).
    pub thickness_km: f64,
    /// Rayleigh coefficient at 1 µm, m⁻¹ µm⁴: β_R(λ) = k / λ⁴
    /// in [0, 1e-3] (default 1.24062e-6, Bruneton 2017 demo; 13.3e-6 m⁻¹ at 550 nm).
    pub rayleigh_k: f64,
    /// Rayleigh (air) density scale height, km, in [0.1, 100] (default 8).
    pub rayleigh_scale_height_km: f64,
    /// Aerosol scattering coefficient at sea level and 550 nm, m⁻¹, in
    /// [0, 1e-2] (default 7.992e-5).
    pub aerosol_scattering: f64,
    /// Multiplier on the aerosol density, in [0, 1000] (1 = default; 0 = pure Rayleigh).
    pub aerosol_density: f64,
    /// Aerosol single-scattering albedo, in [0, 1] (default 0.9).
    pub aerosol_albedo: f64,
    /// Aerosol Ångström exponent α: β_M(λ) ∝ (λ / 550 nm)^(−α), in [−4, 4] (default 1.3).
    pub aerosol_angstrom: f64,
    /// Aerosol density scale height, km, in [0.01, 100] (default 1.2).
    pub aerosol_scale_height_km: f64,
    /// Asymmetry g of the Cornette–Shanks aerosol phase function, in
    /// [−0.99, 0.99] (default 0.8).
    pub aerosol_g: f64,
    /// Ozone column, Dobson units, in [0, 2000] (default 300).
    pub ozone_du: f64,
    /// Altitude of the ozone density peak, km, in [0, `thickness_km`] (default 25).
    pub ozone_peak_km: f64,
    /// Half-width of the ozone tent profile, km, in [0.1, `thickness_km`] (default 15).
    pub ozone_half_width_km: f64,
    /// Lambertian ground albedo, in [0, 1] (default 0.2).
    pub ground_albedo: f64,
}

impl Default for AtmosphereParams {
    fn default() -> Self {
        AtmosphereParams {
            ground_radius_km: 6360.0,
            thickness_km: 100.0,
            rayleigh_k: 1.240_62e-6,
            rayleigh_scale_height_km: 8.0,
            aerosol_scattering: 7.992e-5,
            aerosol_density: 1.0,
            aerosol_albedo: 0.9,
            aerosol_angstrom: 1.3,
            aerosol_scale_height_km: 1.2,
            aerosol_g: 0.8,
            ozone_du: 300.0,
            ozone_peak_km: 25.0,
            ozone_half_width_km: 15.0,
            ground_albedo: 0.2,
        }
    }
}

/// A parameter outside its physical range.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamError {
    /// The offending field (e.g. `atmosphere.aerosol_g`).
    pub field: String,
    /// What is accepted.
    pub expected: String,
}

impl std::fmt::Display for ParamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: expected {}", self.field, self.expected)
    }
}

impl std::error::Error for ParamError {}

fn range(field: &str, v: f64, lo: f64, hi: f64) -> Result<(), ParamError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(ParamError {
            field: format!("atmosphere.{field}"),
            expected: format!("a number in [{}, {}], got {}", show(lo), show(hi), show(v)),
        })
    }
}

impl AtmosphereParams {
    /// Checks every field against its physical range.
    pub fn validate(&self) -> Result<(), ParamError> {
        range("ground_radius_km", self.ground_radius_km, 100.0, 100_000.0)?;
        range("thickness_km", self.thickness_km, 1.0, 1000.0)?;
        range("rayleigh_k", self.rayleigh_k, 0.0, 1e-3)?;
        range(
            "rayleigh_scale_height_km",
            self.rayleigh_scale_height_km,
            0.1,
            100.0,
        )?;
        range("aerosol_scattering", self.aerosol_scattering, 0.0, 1e-2)?;
        range("aerosol_density", self.aerosol_density, 0.0, 1000.0)?;
        range("aerosol_albedo", self.aerosol_albedo, 0.0, 1.0)?;
        range("aerosol_angstrom", self.aerosol_angstrom, -4.0, 4.0)?;
        range(
            "aerosol_scale_height_km",
            self.aerosol_scale_height_km,
            0.01,
            100.0,
        )?;
        range("aerosol_g", self.aerosol_g, -0.99, 0.99)?;
        range("ozone_du", self.ozone_du, 0.0, 2000.0)?;
        range("ozone_peak_km", self.ozone_peak_km, 0.0, self.thickness_km)?;
        range(
            "ozone_half_width_km",
            self.ozone_half_width_km,
            0.1,
            self.thickness_km,
        )?;
        range("ground_albedo", self.ground_albedo, 0.0, 1.0)?;
        Ok(())
    }
}

/// LUT resolutions and sample counts (the accuracy/cost dial).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LutConfig {
    /// Transmittance LUT width (view zenith, Bruneton 2017 mapping), in
    /// [2, 1024] like every size and step count here, default 256.
    pub transmittance_w: usize,
    /// Transmittance LUT height (altitude), in [2, 1024], default 64.
    pub transmittance_h: usize,
    /// Ray-march steps per transmittance texel, in [2, 1024], default 40.
    pub transmittance_steps: usize,
    /// Multiple-scattering LUT size (Sun zenith × altitude), in [2, 1024], default 48.
    pub multiscatter_n: usize,
    /// Directions per multiple-scattering texel (a square number), in
    /// [2, 1024], default 64.
    pub multiscatter_dirs: usize,
    /// Ray-march steps per multiple-scattering direction, in [2, 1024], default 20.
    pub multiscatter_steps: usize,
    /// Sky-view LUT width (azimuth from the Sun, 0–180°), in [2, 1024], default 192.
    pub sky_view_w: usize,
    /// Sky-view LUT height (elevation 0–90°, square-root mapping), in
    /// [2, 1024], default 108.
    pub sky_view_h: usize,
    /// Ray-march steps per sky-view texel, in [2, 1024], default 30.
    pub sky_view_steps: usize,
    /// Scattering orders: 1 = single scattering only, n ≥ 2 = the first
    /// n orders of Hillaire's geometric series, 0 = all orders (default);
    /// in [0, 1000].
    pub orders: u32,
    /// Half-angle of the aerosol forward peak, degrees, that the LUT path
    /// treats as unscattered light (δ-scaling; see
    /// `lut::forward_scattering`), in [0, 90] (a forward peak lies in the
    /// forward hemisphere); 0 turns it off (default 15).
    pub forward_peak_deg: f32,
}

impl Default for LutConfig {
    fn default() -> Self {
        LutConfig {
            transmittance_w: 256,
            transmittance_h: 64,
            transmittance_steps: 40,
            multiscatter_n: 48,
            multiscatter_dirs: 64,
            multiscatter_steps: 20,
            sky_view_w: 192,
            sky_view_h: 108,
            sky_view_steps: 30,
            orders: 0,
            forward_peak_deg: 15.0,
        }
    }
}

impl LutConfig {
    /// Whether `self` and `other` describe the same precomputed tables
    /// (transmittance, multiple scattering): they may differ only in the
    /// per-frame sky view (`sky_view_w`, `sky_view_h`, `sky_view_steps`),
    /// which no precomputed table reads.
    pub fn same_tables(&self, other: &LutConfig) -> bool {
        let tables = |c: &LutConfig| LutConfig {
            sky_view_w: 0,
            sky_view_h: 0,
            sky_view_steps: 0,
            ..*c
        };
        tables(self) == tables(other)
    }

    /// A small configuration for fast tests.
    pub fn small() -> Self {
        LutConfig {
            transmittance_w: 128,
            transmittance_h: 32,
            transmittance_steps: 30,
            multiscatter_n: 16,
            multiscatter_dirs: 36,
            multiscatter_steps: 16,
            sky_view_w: 96,
            sky_view_h: 64,
            sky_view_steps: 30,
            orders: 0,
            forward_peak_deg: 15.0,
        }
    }
}
