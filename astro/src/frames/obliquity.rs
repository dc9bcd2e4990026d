//! Obliquity of the ecliptic.

use crate::units::{JulianCenturies, Radians, ARCSEC};

/// Mean obliquity of the ecliptic ε₀ at `t` Julian centuries of TT from
/// J2000.0, radians (angle between the mean equator and the ecliptic of date).
///
/// Source: IAU 1980 (Lieske et al. 1977) as in Meeus, *Astronomical
/// Algorithms* 2nd ed., eq. 22.2: 23°26′21.448″ − 46.8150″T − 0.00059″T² +
/// 0.001813″T³. Good to 0.01″ within ±20 centuries; further out it degrades
/// (1″ after 2000 years, 10″ after 4000, per Meeus).
pub fn mean_obliquity(t: JulianCenturies) -> Radians {
    let arcsec = 84_381.448 + t * (-46.815_0 + t * (-0.000_59 + t * 0.001_813));
    arcsec * ARCSEC
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meeus_example_22a() {
        // 1987 April 10, 0h TD: ε₀ = 23°26′27.407″.
        let t = -0.127_296_372_348;
        let expected = 23.0 * 3600.0 + 26.0 * 60.0 + 27.407;
        assert!((mean_obliquity(t) / ARCSEC - expected).abs() < 1e-3);
    }

    #[test]
    fn j2000_value() {
        assert!((mean_obliquity(0.0) / ARCSEC - 84_381.448).abs() < 1e-9);
    }
}
