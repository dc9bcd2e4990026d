//! The Moon's photometry: the Hapke–Lommel–Seeliger law's opposition
//! surge and phase law with their fitted constants, the observed phase
//! curve, earthshine and the lunar reflectance spectrum (derivations in the
//! [module documentation](crate::moon)).

use crate::spectrum::{BandWeights, Spectrum};
use crate::units::Lux;

/// Hapke's (1963) compaction parameter h′ of the lunar regolith (his "g"),
/// for [`hapke_1963_b`].
pub const HAPKE_H: f64 = 0.6;
/// Amplitude B0 of the opposition surge (fitted, see the
/// [module documentation](crate::moon)).
pub const SURGE_B0: f64 = 0.9;
/// Angular width h of the opposition surge (fitted).
pub const SURGE_H: f64 = 0.08;
/// Coefficient of the (1 − cos g)² term of Hapke's S(g) (fitted; Hapke 1963: 0.1).
pub const HAPKE_S_COEFF: f64 = 0.065;
/// The Moon's geometric albedo in V (fitted; Allen's Astrophysical
/// Quantities, 4th ed., gives 0.12).
pub const GEOMETRIC_ALBEDO: f64 = 0.125;
/// The Earth's visual geometric albedo (NASA Earth fact sheet, 0.367).
pub const EARTH_GEOMETRIC_ALBEDO: f64 = 0.367;
/// Mean radius of the Earth, km.
pub const EARTH_RADIUS_KM: f64 = 6371.0;
/// Mean Earth–Moon distance of the Allen phase curve, km.
pub const MEAN_MOON_DISTANCE_KM: f64 = 384_400.0;
/// Illuminance of a magnitude-0 source outside the atmosphere, lux
/// (conventions.md).
pub const LUX_MAG0: f64 = 2.54e-6;

/// The opposition surge B(g) = 1 + B0/(1 + tan(g/2)/h) (Hapke 1986, Icarus
/// 67, 264); `g` the phase angle in radians; 1 + B0 at g = 0.
pub fn surge_b(g: f64) -> f64 {
    let g = g.abs().min(std::f64::consts::PI * 0.999_999);
    1.0 + SURGE_B0 / (1.0 + (g / 2.0).tan() / SURGE_H)
}

/// The opposition surge B(g) of Hapke (1963, JGR 68, 4571; the seed
/// thesis) with compaction `h`; `g` the phase angle in radians; 2
/// at g = 0, 1 for g ≥ 90°. Kept for comparison (see the
/// [module documentation](crate::moon)).
pub fn hapke_1963_b(g: f64, h: f64) -> f64 {
    let g = g.abs();
    if g >= std::f64::consts::FRAC_PI_2 {
        return 1.0;
    }
    if g < 1e-9 {
        return 2.0;
    }
    let t = g.tan();
    let e = (-h / t).exp();
    2.0 - t / (2.0 * h) * (1.0 - e) * (3.0 - e)
}

/// Hapke's (1963) phase law S(g) = [sin g + (π − g) cos g]/π + 0.1 (1 − cos g)².
pub fn hapke_s(g: f64) -> f64 {
    let g = g.abs().min(std::f64::consts::PI);
    (g.sin() + (std::f64::consts::PI - g) * g.cos()) / std::f64::consts::PI
        + HAPKE_S_COEFF * (1.0 - g.cos()).powi(2)
}

/// The Lambert-sphere phase law Φ(α) = [sin α + (π − α) cos α]/π (Russell 1916).
pub fn lambert_sphere_phase(alpha: f64) -> f64 {
    let a = alpha.abs().min(std::f64::consts::PI);
    (a.sin() + (std::f64::consts::PI - a) * a.cos()) / std::f64::consts::PI
}

/// The observed lunar phase curve (Allen's Astrophysical Quantities, 4th ed.,
/// Cox 2000): V = −12.73 + 0.026 φ + 4 × 10⁻⁹ φ⁴ at the mean distances (φ in
/// degrees), moved to the Moon's distance `moon_km` from the observer and
/// the Sun's distance `sun_au` from the Moon by the inverse-square law.
pub fn allen_magnitude(phase_deg: f64, moon_km: f64, sun_au: f64) -> f64 {
    let p = phase_deg.abs();
    -12.73 + 0.026 * p + 4e-9 * p.powi(4) + 5.0 * (moon_km / MEAN_MOON_DISTANCE_KM * sun_au).log10()
}

/// Earthshine illuminance on the Moon, lux: p⊕ E☉ (R⊕/d)² Φ(α⊕), with the
/// solar illuminance `sun_lux` at the Moon, the Earth–Moon distance `d_km`
/// and the Earth's phase angle `earth_phase` (radians) seen from the Moon.
pub fn earthshine_lux(sun_lux: f64, d_km: f64, earth_phase: f64) -> Lux {
    EARTH_GEOMETRIC_ALBEDO
        * sun_lux
        * (EARTH_RADIUS_KM / d_km).powi(2)
        * lambert_sphere_phase(earth_phase)
}

/// Relative spectral reflectance of the lunar surface (1 + 0.0017 (λ − 550))
/// normalised so that its luminance under the solar spectrum is 1.
pub fn lunar_reflectance_spectrum() -> Spectrum {
    let w = BandWeights::solar();
    let raw = Spectrum::from_fn(|nm| (1.0 + 0.0017 * (nm - 550.0)).max(0.1));
    let k = w.solar_illuminance_lux() as f32 / w.to_y(&raw);
    raw * k
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::{band_centre_nm, BANDS};

    #[test]
    fn hapke_limits() {
        assert_eq!(hapke_1963_b(0.0, HAPKE_H), 2.0);
        assert!((hapke_s(0.0) - 1.0).abs() < 1e-12);
        assert_eq!(hapke_1963_b(2.0, HAPKE_H), 1.0);
        // Continuous near 0 and 90°.
        assert!((hapke_1963_b(1e-6, HAPKE_H) - 2.0).abs() < 1e-3);
        assert!((hapke_1963_b(std::f64::consts::FRAC_PI_2 - 1e-4, HAPKE_H) - 1.0).abs() < 0.01);
        assert!(hapke_s(std::f64::consts::PI).is_finite());
        assert!((surge_b(0.0) - 1.0 - SURGE_B0).abs() < 1e-12);
        assert!(surge_b(std::f64::consts::PI).is_finite());
        // Monotonic decrease of both surges; the new one halves within ~9°.
        let (mut p1, mut p2) = (2.0, surge_b(0.0));
        for k in 1..180 {
            let g = (k as f64).to_radians();
            let (b1, b2) = (hapke_1963_b(g, HAPKE_H), surge_b(g));
            assert!(b1 <= p1 + 1e-12 && b2 <= p2 + 1e-12);
            (p1, p2) = (b1, b2);
        }
        // Half the surge at tan(g/2) = h (g ≈ 9.1°).
        let half = 1.0 + SURGE_B0 / 2.0;
        assert!((surge_b(2.0 * SURGE_H.atan()) - half).abs() < 1e-12);
    }

    #[test]
    fn earthshine_magnitude() {
        // Full Earth from the Moon: ~12 lx.
        let e = earthshine_lux(127_000.0, 384_400.0, 0.0);
        assert!((10.0..14.0).contains(&e), "{e}");
        assert!(earthshine_lux(127_000.0, 384_400.0, std::f64::consts::PI) < 1e-6);
    }

    #[test]
    fn reflectance_is_reddish_and_normalised() {
        let r = lunar_reflectance_spectrum();
        assert!(r.0[BANDS - 1] > r.0[0] * 1.5);
        assert!(band_centre_nm(BANDS - 1) > 700.0);
        let w = BandWeights::solar();
        assert!((w.to_y(&r) as f64 / w.solar_illuminance_lux() - 1.0).abs() < 1e-4);
    }
}
