//! The observer on the WGS84 ellipsoid.

use crate::units::{Radians, WGS84_A_KM, WGS84_F};

/// Geocentric position of an observer at geodetic latitude `lat_geodetic`
/// and height `elevation_m` (metres above the WGS84 ellipsoid):
/// (ρ sin φ′, ρ cos φ′) in **km**, where φ′ is the geocentric latitude and ρ
/// the distance from the Earth's centre (multiply Meeus' values, which are
/// in Earth radii, by 6378.137 km to compare).
///
/// Source: Meeus, *Astronomical Algorithms* 2nd ed., ch. 11 (tan u =
/// (b/a) tan φ), on the WGS84 ellipsoid; u is computed with `atan2`, so the
/// poles are exact.
pub fn geocentric_observer(lat_geodetic: Radians, elevation_m: f64) -> (f64, f64) {
    let b_over_a = 1.0 - WGS84_F;
    let (sp, cp) = (libm::sin(lat_geodetic), libm::cos(lat_geodetic));
    let u = libm::atan2(b_over_a * sp, cp);
    let h_km = elevation_m / 1000.0;
    let rho_sin = WGS84_A_KM * b_over_a * libm::sin(u) + h_km * sp;
    let rho_cos = WGS84_A_KM * libm::cos(u) + h_km * cp;
    (rho_sin, rho_cos)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::DEG;

    #[test]
    fn meeus_example_11a_palomar() {
        // φ = +33°21′22″, H = 1706 m → ρ sin φ′ = +0.546861,
        // ρ cos φ′ = +0.836339 (Earth radii).
        let lat = (33.0 + 21.0 / 60.0 + 22.0 / 3600.0) * DEG;
        let (s, c) = geocentric_observer(lat, 1706.0);
        assert!(
            (s / WGS84_A_KM - 0.546_861).abs() < 1e-6,
            "{}",
            s / WGS84_A_KM
        );
        assert!(
            (c / WGS84_A_KM - 0.836_339).abs() < 1e-6,
            "{}",
            c / WGS84_A_KM
        );
    }

    #[test]
    fn poles_and_equator() {
        let b = WGS84_A_KM * (1.0 - WGS84_F);
        let (s, c) = geocentric_observer(90.0 * DEG, 0.0);
        assert!((s - b).abs() < 1e-9 && c.abs() < 1e-9);
        let (s, c) = geocentric_observer(-90.0 * DEG, 1000.0);
        assert!((s + b + 1.0).abs() < 1e-9 && c.abs() < 1e-9);
        let (s, c) = geocentric_observer(0.0, 0.0);
        assert!(s.abs() < 1e-12 && (c - WGS84_A_KM).abs() < 1e-12);
    }
}
