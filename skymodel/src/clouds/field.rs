//! The cloud density fields: the low layer's extinction coefficient in 3D
//! ([`LowField`]) and the high layer's vertical optical depth in 2D
//! ([`HighField`]). Both are plain functions of position (km, observer
//! frame: x East, y North, altitude above the observer's ground) so that
//! the CPU pass, the WGSL shader and the Mitsuba export
//! (`tools/cloud_reference.py`) evaluate the same field.
//!
//! The low layer follows Schneider & Vos (2015): a base shape noise (here
//! fBm of value noise, [`super::noise::fbm`]) multiplied by a height
//! profile of the cloud type, then remapped by the coverage so that only
//! the densest columns survive a small coverage:
//!
//! ```text
//! d = clamp((n · profile(h) − (1 − c)) / c, 0, 1),   σ_t = σ_max · d
//! ```
//!
//! With c = 1 every point is cloud (d = n · profile, the noise lifted to
//! n ≥ ½ by [`close`] from c = 0.85 on: an overcast deck has no gap); as c
//! falls the cells
//! shrink to their cores and the profile rounds their tops. The wind moves
//! the noise; the offset is wrapped by the noise's spatial period, so an
//! instant decades from J2000 keeps full f32 precision.

use glam::{Vec2, Vec3};

use super::noise::fbm;
use crate::atmosphere::medium::smoothstep;
use crate::cloud_spec::{HighCloudSpec, LowCloudKind, LowCloudSpec};
use crate::units::PerKm;

/// Lattice cells per noise period (each axis, base octave).
pub const NOISE_PERIOD_CELLS: u32 = 256;
/// Octaves of the low layer's shape noise.
pub const LOW_OCTAVES: u32 = 4;
/// Octaves of the high layer's noise.
pub const HIGH_OCTAVES: u32 = 5;
/// Contrast applied to the fBm around its mean 0.5 before the coverage
/// remap (fBm of value noise rarely leaves [0.25, 0.75]).
pub const NOISE_CONTRAST: f32 = 2.0;

/// The vertical density profile of a cloud kind at height fraction `hf`
/// (0 at the base, 1 at the top), in [0, 1] (Schneider & Vos 2015's
/// height gradients: a fast rise above the base, a slower fall below the
/// kind's top).
pub fn profile(kind: LowCloudKind, hf: f32) -> f32 {
    let ProfileShape { rise, fall0, fall1 } = ProfileShape::of(kind);
    smoothstep(0.0, rise, hf) * (1.0 - smoothstep(fall0, fall1, hf))
}

/// The height fractions that shape a kind's [`profile`]: the density rises
/// over [0, `rise`] and falls over [`fall0`, `fall1`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProfileShape {
    /// End of the rise above the base.
    pub rise: f32,
    /// Start of the fall towards the top.
    pub fall0: f32,
    /// End of the fall (no cloud above).
    pub fall1: f32,
}

impl ProfileShape {
    /// The shape of `kind` (Schneider & Vos 2015's gradients).
    pub fn of(kind: LowCloudKind) -> Self {
        let (rise, fall0, fall1) = match kind {
            LowCloudKind::Cumulus => (0.1, 0.6, 1.0),
            LowCloudKind::Stratocumulus => (0.15, 0.35, 0.7),
            LowCloudKind::Stratus => (0.05, 0.1, 0.2),
        };
        ProfileShape { rise, fall0, fall1 }
    }
}

/// The fBm's contrast stretch around 0.5, clamped to [0, 1].
#[inline]
fn contrast(n: f32) -> f32 {
    ((n - 0.5) * NOISE_CONTRAST + 0.5).clamp(0.0, 1.0)
}

/// From this coverage on the deck closes ([`close`]).
pub const CLOSE_FROM: f32 = 0.85;
/// How far towards 1 the noise is lifted at coverage 1 ([`close`]).
pub const CLOSE_DECK: f32 = 0.5;

/// Closes the deck as the coverage approaches 1: the noise `n` is lifted
/// towards 1 by [`CLOSE_DECK`] × smoothstep([`CLOSE_FROM`], 1, coverage),
/// so that at coverage 1 no column is empty (n ≥ ½: an overcast sky with
/// texture) while every coverage up to 0.85 keeps its field unchanged.
#[inline]
pub fn close(n: f32, coverage: f32) -> f32 {
    n + (1.0 - n) * CLOSE_DECK * smoothstep(CLOSE_FROM, 1.0, coverage)
}

/// Coverage remap: the part of `v` above 1 − `coverage`, rescaled to [0, 1].
#[inline]
fn cover(v: f32, coverage: f32) -> f32 {
    ((v - (1.0 - coverage)) / coverage.max(1e-3)).clamp(0.0, 1.0)
}

/// Wind offset of a layer at `seconds` since J2000 (TT), km, wrapped by
/// the noise's period `period_km` (exact in f64, then f32).
pub fn wind_offset_km(wind_m_s: [f64; 2], seconds: f64, period_km: f64) -> Vec2 {
    let w = |v: f64| ((v * seconds / 1000.0).rem_euclid(period_km)) as f32;
    Vec2::new(w(wind_m_s[0]), w(wind_m_s[1]))
}

/// The low, volumetric layer's field of one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LowField {
    /// Cloud kind (height profile).
    pub kind: LowCloudKind,
    /// Coverage in (0, 1].
    pub coverage: f32,
    /// Base and top altitude above the ground, km.
    pub base_km: f32,
    /// Top altitude, km.
    pub top_km: f32,
    /// Extinction of the densest cloud, km⁻¹.
    pub extinction_per_km: PerKm,
    /// 1 / noise cell size, km⁻¹.
    pub inv_scale: f32,
    /// How far the wind has carried the field, km (subtracted from the
    /// position).
    pub offset_km: Vec2,
    /// Noise seed.
    pub seed: u32,
    /// Half-width of the cloud patch, km (`f32::INFINITY`: unbounded).
    pub half_extent_km: f32,
}

impl LowField {
    /// The field of `spec` at `seconds` since J2000 (TT).
    pub fn new(spec: &LowCloudSpec, seconds: f64) -> Self {
        let period_km = spec.scale_km * NOISE_PERIOD_CELLS as f64;
        LowField {
            kind: spec.kind,
            coverage: spec.coverage as f32,
            base_km: spec.base_km as f32,
            top_km: spec.top_km as f32,
            extinction_per_km: spec.extinction_per_km as f32,
            inv_scale: (1.0 / spec.scale_km) as f32,
            offset_km: wind_offset_km(spec.wind_m_s, seconds, period_km),
            seed: spec.seed,
            half_extent_km: if spec.extent_km > 0.0 {
                spec.extent_km as f32
            } else {
                f32::INFINITY
            },
        }
    }

    /// Thickness of the slab, km.
    pub fn thickness_km(&self) -> f32 {
        self.top_km - self.base_km
    }

    /// Normalised density in [0, 1] at horizontal position `xy` (km East,
    /// North of the observer) and altitude `h_km`.
    pub fn density(&self, xy: Vec2, h_km: f32) -> f32 {
        let hf = (h_km - self.base_km) / self.thickness_km();
        if !(0.0..=1.0).contains(&hf)
            || xy.x.abs() > self.half_extent_km
            || xy.y.abs() > self.half_extent_km
        {
            return 0.0;
        }
        let prof = profile(self.kind, hf);
        if prof <= 0.0 {
            return 0.0;
        }
        let q = (xy - self.offset_km) * self.inv_scale;
        let p = Vec3::new(q.x, q.y, h_km * self.inv_scale);
        let n = contrast(fbm(p, LOW_OCTAVES, NOISE_PERIOD_CELLS, self.seed));
        cover(close(n, self.coverage) * prof, self.coverage)
    }

    /// Extinction coefficient σ_t, km⁻¹ (the single-scattering albedo of
    /// cloud droplets in the visible is 1: σ_s = σ_t).
    #[inline]
    pub fn extinction(&self, xy: Vec2, h_km: f32) -> PerKm {
        self.extinction_per_km * self.density(xy, h_km)
    }

    /// The extinction (km⁻¹) at the voxel centres of a `[nx, ny, nz]`
    /// grid over the patch [−e, e]² × [base, top] (e = the patch's
    /// half-width), x fastest, then y, then z: the field exported to
    /// Mitsuba's `gridvolume` (`skymodel/examples/cloud_grid.rs`). Empty
    /// for an unbounded layer.
    pub fn voxel_grid(&self, [nx, ny, nz]: [usize; 3]) -> Vec<f32> {
        let e = self.half_extent_km;
        if !e.is_finite() {
            return Vec::new();
        }
        let (b, t) = (self.base_km, self.top_km);
        let centre = |i: usize, n: usize| (i as f32 + 0.5) / n as f32;
        let mut v = Vec::with_capacity(nx * ny * nz);
        for k in 0..nz {
            let h = b + (t - b) * centre(k, nz);
            for j in 0..ny {
                let y = -e + 2.0 * e * centre(j, ny);
                for i in 0..nx {
                    let x = -e + 2.0 * e * centre(i, nx);
                    v.push(self.extinction(Vec2::new(x, y), h));
                }
            }
        }
        v
    }
}

/// The high, thin layer's field of one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HighField {
    /// Coverage in (0, 1].
    pub coverage: f32,
    /// Altitude above the ground, km.
    pub altitude_km: f32,
    /// Vertical optical depth of the densest cloud.
    pub optical_depth: f32,
    /// Unit vector along the wind (East, North); East without wind.
    pub along: Vec2,
    /// 1 / cell size along the wind, km⁻¹.
    pub inv_scale_along: f32,
    /// 1 / cell size across the wind, km⁻¹.
    pub inv_scale_across: f32,
    /// Wind offset, km.
    pub offset_km: Vec2,
    /// Noise seed.
    pub seed: u32,
}

impl HighField {
    /// The field of `spec` at `seconds` since J2000 (TT).
    pub fn new(spec: &HighCloudSpec, seconds: f64) -> Self {
        let w = Vec2::new(spec.wind_m_s[0] as f32, spec.wind_m_s[1] as f32);
        let along = if w.length() > 1e-6 {
            w.normalize()
        } else {
            Vec2::X
        };
        // The wind offset lies along the wind, where the noise's period is
        // 256 cells × the along-wind cell size: wrap the distance by it.
        let speed = (spec.wind_m_s[0].powi(2) + spec.wind_m_s[1].powi(2)).sqrt();
        let period_km = spec.scale_km * spec.stretch * NOISE_PERIOD_CELLS as f64;
        let s = (speed * seconds / 1000.0).rem_euclid(period_km) as f32;
        HighField {
            coverage: spec.coverage as f32,
            altitude_km: spec.altitude_km as f32,
            optical_depth: spec.optical_depth as f32,
            along,
            inv_scale_along: (1.0 / (spec.scale_km * spec.stretch)) as f32,
            inv_scale_across: (1.0 / spec.scale_km) as f32,
            offset_km: along * s,
            seed: spec.seed,
        }
    }

    /// Vertical optical depth at horizontal position `xy` (km).
    pub fn optical_depth(&self, xy: Vec2) -> f32 {
        let p = xy - self.offset_km;
        let a = p.dot(self.along) * self.inv_scale_along;
        let b = p.perp_dot(self.along) * self.inv_scale_across;
        let n = contrast(fbm(
            Vec3::new(a, b, 0.5),
            HIGH_OCTAVES,
            NOISE_PERIOD_CELLS,
            self.seed,
        ));
        self.optical_depth * cover(close(n, self.coverage), self.coverage)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn low(coverage: f64) -> LowField {
        LowField::new(
            &LowCloudSpec {
                coverage,
                ..LowCloudSpec::default()
            },
            0.0,
        )
    }

    /// The fraction of a horizontal plane at the profile's peak that is
    /// cloud grows with the coverage, from none to all.
    #[test]
    fn coverage_controls_the_cloud_fraction() {
        let frac = |c: f64| {
            let f = low(c);
            let h = f.base_km + 0.3 * f.thickness_km();
            let n = 80;
            let mut k = 0;
            for i in 0..n {
                for j in 0..n {
                    let xy = Vec2::new(i as f32 * 0.37, j as f32 * 0.41);
                    if f.density(xy, h) > 0.0 {
                        k += 1;
                    }
                }
            }
            k as f32 / (n * n) as f32
        };
        let fs: Vec<f32> = [0.05, 0.3, 0.5, 0.7, 1.0].map(frac).to_vec();
        assert!(fs.windows(2).all(|w| w[0] <= w[1]), "{fs:?}");
        assert!(
            fs[0] < 0.05 && fs[2] > 0.2 && fs[2] < 0.8 && fs[4] > 0.95,
            "{fs:?}"
        );
    }

    #[test]
    fn nothing_outside_the_slab_or_the_patch() {
        let mut f = low(1.0);
        assert_eq!(f.density(Vec2::ZERO, f.base_km - 0.01), 0.0);
        assert_eq!(f.density(Vec2::ZERO, f.top_km + 0.01), 0.0);
        f.half_extent_km = 2.0;
        assert_eq!(f.density(Vec2::new(2.5, 0.0), 2.0), 0.0);
        assert!(f.density(Vec2::new(1.0, 0.0), 2.0) > 0.0);
    }

    #[test]
    fn profiles_vanish_at_base_and_top() {
        for k in [
            LowCloudKind::Cumulus,
            LowCloudKind::Stratocumulus,
            LowCloudKind::Stratus,
        ] {
            assert_eq!(profile(k, 0.0), 0.0);
            assert_eq!(profile(k, 1.0), 0.0);
            assert!((0..=20).any(|i| profile(k, i as f32 / 20.0) == 1.0));
        }
    }

    /// The wind carries the field downwind: the field at x + w·t then
    /// equals the field at x now.
    #[test]
    fn wind_moves_the_field_and_wraps_exactly() {
        let spec = LowCloudSpec {
            coverage: 0.8,
            wind_m_s: [10.0, 0.0],
            ..LowCloudSpec::default()
        };
        let a = LowField::new(&spec, 0.0);
        let b = LowField::new(&spec, 100.0);
        let h = 2.0;
        let p = Vec2::new(0.3, 0.7);
        assert!((b.density(p + Vec2::new(1.0, 0.0), h) - a.density(p, h)).abs() < 1e-5);
        // Decades later the offset stays below one period.
        let c = LowField::new(&spec, 8e8);
        assert!(c.offset_km.x >= 0.0 && c.offset_km.x < 3.0 * 256.0 + 1e-3);
    }

    #[test]
    fn high_layer_depth_within_range() {
        let f = HighField::new(
            &HighCloudSpec {
                coverage: 0.6,
                ..HighCloudSpec::default()
            },
            0.0,
        );
        let mut any = false;
        for i in 0..200 {
            let t = f.optical_depth(Vec2::new(i as f32 * 1.3, i as f32 * 0.7));
            assert!((0.0..=f.optical_depth).contains(&t));
            any |= t > 0.0;
        }
        assert!(any);
    }
}
