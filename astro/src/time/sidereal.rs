//! Greenwich sidereal time.

use crate::units::{wrap_tau, JulianDay, Radians, DAYS_PER_CENTURY, DEG, J2000};

/// Greenwich mean sidereal time at the UT1 Julian day `jd_ut1`, radians in
/// [0, 2π) (the hour angle of the mean equinox of date).
///
/// Source: IAU 1982 expression as given by Meeus, *Astronomical Algorithms*
/// 2nd ed., eq. 12.4. The day count is split into its whole and fractional
/// parts so that the 360° × days term, which would swamp f64 precision, is
/// dropped exactly: the result keeps ~1e-11 rad (2 µs of time) over the
/// whole 5-digit JD range.
pub fn gmst(jd_ut1: JulianDay) -> Radians {
    // d = JD − J2000 as whole days plus a fraction; both parts are exact.
    let whole = libm::floor(jd_ut1);
    let frac = jd_ut1 - whole;
    let d_whole = whole - J2000; // an integer, exact
    let t = (jd_ut1 - J2000) / DAYS_PER_CENTURY;
    // 360.98564736629 d = 360 d + 0.98564736629 d, and 360° × whole days is
    // a whole number of turns.
    let deg = 280.460_618_37
        + crate::units::reduce_deg(0.985_647_366_29 * d_whole)
        + 360.985_647_366_29 * frac
        + t * t * (0.000_387_933 - t / 38_710_000.0);
    wrap_tau(crate::units::reduce_deg(deg) * DEG)
}

/// Greenwich apparent sidereal time at `jd_ut1`, radians in [0, 2π): the mean
/// sidereal time plus the equation of the equinoxes Δψ cos ε, where `dpsi` is
/// the nutation in longitude and `true_obliquity` ε = ε₀ + Δε.
///
/// Source: Meeus, *Astronomical Algorithms* 2nd ed., ch. 12 (IAU 1982 with
/// the classical equation of the equinoxes, no complementary terms).
pub fn gast(jd_ut1: JulianDay, dpsi: Radians, true_obliquity: Radians) -> Radians {
    wrap_tau(gmst(jd_ut1) + dpsi * libm::cos(true_obliquity))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::ARCSEC;

    fn hms(h: f64, m: f64, s: f64) -> Radians {
        (h + m / 60.0 + s / 3600.0) * 15.0 * DEG
    }

    #[test]
    fn meeus_example_12a() {
        // 1987 April 10, 0h UT: θ0 = 13h10m46.3668s (mean), 13h10m46.1351s
        // (apparent, with Δψ = −3.788″, ε = 23°26′36.850″).
        let jd = 2_446_895.5;
        let mean = gmst(jd);
        assert!((mean - hms(13.0, 10.0, 46.3668)).abs() < 1e-4 * 15.0 * ARCSEC);
        let eps = (23.0 + 26.0 / 60.0 + 36.850 / 3600.0) * DEG;
        let app = gast(jd, -3.788 * ARCSEC, eps);
        assert!((app - hms(13.0, 10.0, 46.1351)).abs() < 1e-3 * 15.0 * ARCSEC);
    }

    #[test]
    fn meeus_example_12b() {
        // 1987 April 10, 19h21m00s UT: θ0 = 128.7378734°.
        let jd = 2_446_896.306_25;
        assert!((gmst(jd) - 128.737_873_4 * DEG).abs() < 2e-7 * DEG);
    }

    #[test]
    fn matches_sofa_gmst82() {
        // SOFA/ERFA eraGmst82(jd_ut1, 0) (tools/gen_frames_refs.py): the same
        // IAU 1982 expression written in seconds of time. Meeus' rounded
        // degree coefficients differ by 2.4e-9 rad (0.5 mas) a century away.
        let refs = [
            (2415020.5, 1.7485367552330615),
            (2446895.5, 3.45039716350869),
            (2451545.0, 4.894961212823059),
            (2460000.25, 1.123215941958044),
            (2488069.75, 3.333310929129567),
        ];
        for (jd, g) in refs {
            assert!((gmst(jd) - g).abs() < 4e-9, "{jd}: {}", gmst(jd) - g);
        }
    }

    #[test]
    fn split_evaluation_matches_long_double_style_reference() {
        // Compare with a direct evaluation done in two steps of reduced size
        // (days since J2000 small): at J2000 + 0.25 d the direct formula is
        // exact enough to serve as reference.
        let jd = J2000 + 0.25;
        let d: f64 = 0.25;
        let t = d / 36525.0;
        let direct =
            280.46061837 + 360.98564736629 * d + 0.000387933 * t * t - t * t * t / 38710000.0;
        assert!((gmst(jd) - wrap_tau(direct * DEG)).abs() < 1e-12);
        // And it advances by one sidereal rotation per sidereal day everywhere.
        for jd0 in [0.5, 1_000_000.3, 2_451_545.0, 2_816_787.7, 5_000_000.1] {
            let dd = 0.1;
            let adv = wrap_tau(gmst(jd0 + dd) - gmst(jd0));
            let expected = wrap_tau(360.985_647_366_29 * dd * DEG);
            assert!((adv - expected).abs() < 1e-8, "{jd0}");
        }
    }
}
