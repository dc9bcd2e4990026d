//! Atmospheric refraction, safe for every altitude.
//!
//! The Saemundsson and Bennett formulas diverge a few degrees below the
//! horizon (their argument h + 10.3/(h + 5.11) passes through zero). Both
//! functions here evaluate the formula at max(h, [`REFRACTION_FLOOR_DEG`]) and,
//! below that floor, multiply by a smoothstep that falls from 1 at the floor
//! to 0 at [`REFRACTION_FLOOR_DEG`] − [`REFRACTION_FADE_DEG`]. The result is
//! continuous, finite and non-negative from −90° to +90°, and the apparent
//! altitude h + R(h) stays monotonic in h (the fade's steepest slope,
//! 1.5 × 0.83°/2°, is below 1). Refraction below −1° has no physical meaning
//! for a ground observer; the fade only keeps callers (rise/set searches,
//! plots) free of NaN and jumps.

use crate::units::{Radians, DEG};

/// Standard pressure for refraction, hPa (Meeus ch. 16).
pub const STANDARD_PRESSURE_HPA: f64 = 1010.0;
/// Standard temperature for refraction, °C (Meeus ch. 16).
pub const STANDARD_TEMPERATURE_C: f64 = 10.0;

/// Altitude (degrees) below which the formulas are no longer evaluated.
pub const REFRACTION_FLOOR_DEG: f64 = -1.0;
/// Width (degrees) of the smooth fade to zero below the floor.
pub const REFRACTION_FADE_DEG: f64 = 2.0;

/// Pressure and temperature factor (P/1010)·(283/(273 + T)) of Meeus ch. 16,
/// with the pressure clamped to ≥ 0 and the temperature to ≥ −200 °C.
#[inline]
fn weather_factor(pressure_hpa: f64, temperature_c: f64) -> f64 {
    (pressure_hpa.max(0.0) / 1010.0) * (283.0 / (273.0 + temperature_c.max(-200.0)))
}

/// Fade applied below the floor: smoothstep from 0 (floor − fade) to 1 (floor).
#[inline]
fn fade(alt_deg: f64) -> f64 {
    let x = ((alt_deg - (REFRACTION_FLOOR_DEG - REFRACTION_FADE_DEG)) / REFRACTION_FADE_DEG)
        .clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Refraction R (radians, ≥ 0) to **add** to a true (airless) altitude
/// `alt_true` to get the apparent altitude, for the given pressure (hPa) and
/// temperature (°C).
///
/// Source: Saemundsson (1986), Meeus, *Astronomical Algorithms* 2nd ed.,
/// eq. 16.4: R = 1.02′ / tan(h + 10.3°/(h + 5.11°)), plus Meeus' +0.0019279′
/// so that R = 0 at the zenith, times (P/1010)(283/(273 + T)). Continuous and
/// finite for every altitude: below [`REFRACTION_FLOOR_DEG`] (−1°) the formula
/// is evaluated at the floor and faded to 0 by a smoothstep over
/// [`REFRACTION_FADE_DEG`] (2°), so R = 0 below −3°; the apparent altitude
/// stays monotonic in the true one. Altitudes are clamped to ±90°; pressure
/// to ≥ 0 hPa and temperature to ≥ −200 °C.
pub fn refraction_true_to_apparent(
    alt_true: Radians,
    pressure_hpa: f64,
    temperature_c: f64,
) -> Radians {
    let h = (alt_true / DEG).clamp(-90.0, 90.0);
    let he = h.max(REFRACTION_FLOOR_DEG);
    let arcmin = 1.02 / libm::tan((he + 10.3 / (he + 5.11)) * DEG) + 0.001_927_9;
    let r = arcmin.max(0.0) / 60.0 * DEG * fade(h);
    r * weather_factor(pressure_hpa, temperature_c)
}

/// Refraction R (radians, ≥ 0) to **subtract** from an apparent altitude
/// `alt_apparent` to get the true altitude, for the given pressure (hPa) and
/// temperature (°C).
///
/// Source: Bennett (1982), Meeus, *Astronomical Algorithms* 2nd ed.,
/// eq. 16.3: R = 1′ / tan(h₀ + 7.31°/(h₀ + 4.4°)), plus Meeus' +0.0013515′
/// so that R = 0 at the zenith, times (P/1010)(283/(273 + T)); 0.07′ accuracy
/// above the horizon. Same floor and fade as
/// [`refraction_true_to_apparent`].
pub fn refraction_apparent_to_true(
    alt_apparent: Radians,
    pressure_hpa: f64,
    temperature_c: f64,
) -> Radians {
    let h = (alt_apparent / DEG).clamp(-90.0, 90.0);
    let he = h.max(REFRACTION_FLOOR_DEG);
    let arcmin = 1.0 / libm::tan((he + 7.31 / (he + 4.4)) * DEG) + 0.001_351_5;
    let r = arcmin.max(0.0) / 60.0 * DEG * fade(h);
    r * weather_factor(pressure_hpa, temperature_c)
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: f64 = STANDARD_PRESSURE_HPA;
    const T: f64 = STANDARD_TEMPERATURE_C;
    const ARCMIN: f64 = DEG / 60.0;

    #[test]
    fn meeus_example_16a() {
        // Apparent altitude 0°30′ → R = 28.754′ by Bennett's formula (Meeus
        // Example 16.a; the +0.0013515′ zenith term adds 0.0014′).
        let r = refraction_apparent_to_true(0.5 * DEG, P, T) / ARCMIN;
        assert!((r - 28.754).abs() < 0.003, "{r}");
        // Saemundsson's formula, at the corresponding true altitude, gives the
        // same refraction within Meeus' stated 4″ consistency of the two.
        let h_true = 0.5 * DEG - r * ARCMIN;
        let r2 = refraction_true_to_apparent(h_true, P, T) / ARCMIN;
        assert!((r2 - r).abs() < 4.0 / 60.0, "{r2} vs {r}");
    }

    #[test]
    fn zenith_is_zero_and_horizon_is_34_arcmin() {
        assert_eq!(refraction_true_to_apparent(90.0 * DEG, P, T), 0.0);
        assert_eq!(refraction_apparent_to_true(90.0 * DEG, P, T), 0.0);
        let r = refraction_apparent_to_true(0.0, P, T) / ARCMIN;
        assert!((r - 34.5).abs() < 0.1, "{r}");
        // Meeus: 1.02/tan(10.3/5.11°) = 28.97′ (true altitude 0).
        let r = refraction_true_to_apparent(0.0, P, T) / ARCMIN;
        assert!((r - 28.97).abs() < 0.02, "{r}");
        // Pressure and temperature scale it.
        let low = refraction_true_to_apparent(0.0, 505.0, 10.0) / ARCMIN;
        assert!((low - 28.97 / 2.0).abs() < 0.02);
    }

    #[test]
    fn sweep_minus_90_to_90_is_continuous_finite_and_monotonic() {
        // Steps of 0.001°: no jump above 0.05′ (the steepest slopes, in the
        // fade below −1°, are 29′/° and 37′/°), and the corrected altitude
        // (true + R for Saemundsson, apparent − R for Bennett) is increasing.
        let n = 180_000;
        let alt = |i: i32| (-90.0 + 180.0 * i as f64 / n as f64) * DEG;
        for (f, sign) in [
            (refraction_true_to_apparent as fn(f64, f64, f64) -> f64, 1.0),
            (refraction_apparent_to_true, -1.0),
        ] {
            let mut prev = f(alt(0), P, T);
            for i in 1..=n {
                let r = f(alt(i), P, T);
                assert!(r.is_finite() && r >= 0.0, "{}", alt(i) / DEG);
                assert!((r - prev).abs() < 0.05 * ARCMIN, "jump at {}", alt(i) / DEG);
                assert!(
                    alt(i) + sign * r > alt(i - 1) + sign * prev,
                    "{}",
                    alt(i) / DEG
                );
                prev = r;
            }
        }
        assert_eq!(refraction_true_to_apparent(-90.0 * DEG, P, T), 0.0);
        assert_eq!(refraction_true_to_apparent(-5.0 * DEG, P, T), 0.0);
        assert!(refraction_true_to_apparent(-2.0 * DEG, P, T) > 0.0);
        // Silly weather stays finite.
        for (p, t) in [(0.0, 10.0), (-5.0, 10.0), (1010.0, -273.15), (1e5, 1e5)] {
            assert!(refraction_true_to_apparent(0.0, p, t).is_finite());
            assert!(refraction_apparent_to_true(0.0, p, t).is_finite());
        }
    }
}
