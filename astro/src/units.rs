//! Units and constants. Type aliases carry the unit in the name so that a
//! signature reads like the astronomy: `fn gmst(jd_ut1: JulianDay) -> Radians`.

/// An angle in radians.
pub type Radians = f64;
/// An angle in degrees.
pub type Degrees = f64;
/// An angle in arcseconds.
pub type Arcsec = f64;
/// A length in kilometres.
pub type Km = f64;
/// A length in astronomical units.
pub type Au = f64;
/// A duration in SI seconds.
pub type Seconds = f64;
/// A Julian day number (days since −4712-01-01 12:00 in the named time scale).
pub type JulianDay = f64;
/// Julian centuries of 36 525 days since J2000.0 (TT unless stated).
pub type JulianCenturies = f64;

/// The astronomical unit, km (IAU 2012 Resolution B2).
pub const KM_PER_AU: Km = 149_597_870.700;
/// The speed of light, km/s.
pub const SPEED_OF_LIGHT_KM_S: f64 = 299_792.458;
/// Light time for one astronomical unit, days (KM_PER_AU / c / 86400).
pub const LIGHT_DAYS_PER_AU: f64 = KM_PER_AU / SPEED_OF_LIGHT_KM_S / 86_400.0;
/// J2000.0 as a Julian day (TT).
pub const J2000: JulianDay = 2_451_545.0;
/// Days per Julian century.
pub const DAYS_PER_CENTURY: f64 = 36_525.0;
/// Seconds per day.
pub const SECONDS_PER_DAY: f64 = 86_400.0;
/// WGS84 equatorial radius, km.
pub const WGS84_A_KM: Km = 6_378.137;
/// WGS84 flattening.
pub const WGS84_F: f64 = 1.0 / 298.257_223_563;
/// Mean radius of the Moon, km (IAU).
pub const MOON_RADIUS_KM: Km = 1_737.4;
/// Nominal solar radius, km (IAU 2015 Resolution B3).
pub const SUN_RADIUS_KM: Km = 695_700.0;

/// Degrees → radians.
pub const DEG: f64 = core::f64::consts::PI / 180.0;
/// Arcseconds → radians.
pub const ARCSEC: f64 = DEG / 3600.0;
/// Two pi.
pub const TAU: f64 = core::f64::consts::TAU;

/// Reduce an angle to [0, 2π).
#[inline]
pub fn wrap_tau(a: Radians) -> Radians {
    // Whole turns off by floor (a libm `fmod` costs several times more).
    let r = a - TAU * libm::floor(a * (1.0 / TAU));
    let r = if r < 0.0 { r + TAU } else { r };
    // A tiny negative input rounds up to exactly TAU.
    if r >= TAU {
        0.0
    } else {
        r
    }
}

/// Reduce an angle to [−π, π).
#[inline]
pub fn wrap_pi(a: Radians) -> Radians {
    wrap_tau(a + core::f64::consts::PI) - core::f64::consts::PI
}

/// Reduce degrees to [0, 360) by subtracting whole turns; cheaper than
/// `fmod` and exact enough for polynomial arguments (|x| < 1e9°).
#[inline]
pub fn reduce_deg(x: Degrees) -> Degrees {
    let r = x - 360.0 * libm::floor(x * (1.0 / 360.0));
    if r >= 360.0 {
        0.0
    } else {
        r
    }
}

/// Reduce degrees to [0, 360).
#[inline]
pub fn wrap_360(a: Degrees) -> Degrees {
    let r = a % 360.0;
    let r = if r < 0.0 { r + 360.0 } else { r };
    if r >= 360.0 {
        0.0
    } else {
        r
    }
}

/// `asin` with its argument clamped to [−1, 1], so that a rounding error just
/// outside the domain cannot produce NaN.
#[inline]
pub fn safe_asin(x: f64) -> Radians {
    libm::asin(x.clamp(-1.0, 1.0))
}

/// `acos` with its argument clamped to [−1, 1].
#[inline]
pub fn safe_acos(x: f64) -> Radians {
    libm::acos(x.clamp(-1.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapping_stays_in_range() {
        for a in [-1e6, -TAU, -1e-300, 0.0, 1e-300, TAU, 1e6, 7.0 * TAU + 0.5] {
            let w = wrap_tau(a);
            assert!((0.0..TAU).contains(&w), "{a} -> {w}");
            let p = wrap_pi(a);
            assert!((-core::f64::consts::PI..core::f64::consts::PI).contains(&p));
        }
        assert_eq!(wrap_360(-10.0), 350.0);
        assert!(safe_asin(1.0 + 1e-12).is_finite());
    }
}
