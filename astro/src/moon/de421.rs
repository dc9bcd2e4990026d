//! The Moon from an embedded Chebyshev fit to JPL DE421.
//!
//! Provenance: JPL Development Ephemeris DE421 (W. M. Folkner, J. G. Williams,
//! D. H. Boggs, *The Planetary and Lunar Ephemeris DE 421*, IPN Progress
//! Report 42-178, 2009), produced by NASA/JPL and in the public domain, read
//! from `de421.bsp` as shipped by the PyPI package `skyfield-data`. The
//! geocentric Moon is SPK segment 3→301 (Earth–Moon barycentre → Moon) minus
//! 3→399 (Earth–Moon barycentre → Earth), km, ICRF axes, argument TDB.
//!
//! `tools/gen_moon_de421.py` refits it with 30 Chebyshev coefficients per
//! coordinate on 32-day intervals over the whole DE421 span, stores the
//! coefficients as little-endian f32 in `astro/data/moon_de421.bin`
//! (633 632 bytes) and measures the fit against DE421 on 64 points per
//! interval: max 0.038 km (0.021″), median 0.009 km.

use crate::units::JulianDay;
use glam::DVec3;

/// The coefficient file: header (magic, start JD, interval days, coefficient
/// count, interval count), then f32 coefficients, interval-major, then x, y, z.
static DATA: &[u8] = include_bytes!("../../data/moon_de421.bin");

const HEADER_BYTES: usize = 32;
/// First Julian day (TDB) of the fit, equal to the file header's start.
const START_JD: JulianDay = 2_414_864.5;
/// Interval length, days, equal to the file header's.
const INTERVAL_DAYS: f64 = 32.0;
/// Chebyshev coefficients per coordinate and interval (degree 29).
const NCOEF: usize = 30;
/// Number of intervals in the file.
const COUNT: usize = 1760;

/// Julian day range (TDB) covered by [`de421`]: the whole of DE421,
/// 1899-07-29 0h .. 2053-10-09 0h.
pub const DE421_SPAN: (JulianDay, JulianDay) = (START_JD, START_JD + INTERVAL_DAYS * COUNT as f64);

#[inline(always)]
fn coef(index: usize) -> f64 {
    let at = HEADER_BYTES + 4 * index;
    let bytes = [DATA[at], DATA[at + 1], DATA[at + 2], DATA[at + 3]];
    f64::from(f32::from_le_bytes(bytes))
}

/// Geometric geocentric position of the Moon (centre of mass), km, in the
/// ICRF/GCRS axes (J2000 mean equator and equinox to ~0.02″), at `jd_tdb`
/// (Julian day TDB; TT may be used, the difference is < 2 ms, < 2 m).
///
/// No light time, aberration, precession or nutation is applied. Returns
/// `None` outside [`DE421_SPAN`] (and for NaN). Source: JPL DE421 through
/// this crate's Chebyshev refit (module docs); fit error ≤ 0.04 km.
pub fn de421(jd_tdb: JulianDay) -> Option<DVec3> {
    let (first, last) = DE421_SPAN;
    if !(jd_tdb >= first && jd_tdb <= last) {
        return None;
    }
    let offset = (jd_tdb - first) / INTERVAL_DAYS;
    let index = (offset as usize).min(COUNT - 1);
    // Normalised time in [−1, 1] within the interval.
    let x = 2.0 * (offset - index as f64) - 1.0;
    Some(position(index, x))
}

/// The fitted position in interval `index` at normalised time `x` ∈ [−1, 1].
#[inline]
fn position(index: usize, x: f64) -> DVec3 {
    let base = index * 3 * NCOEF;
    DVec3::new(
        clenshaw(x, base),
        clenshaw(x, base + NCOEF),
        clenshaw(x, base + 2 * NCOEF),
    )
}

/// Σ c_k T_k(x) for the NCOEF coefficients starting at `first` (Clenshaw's
/// recurrence, which is stable on [−1, 1]).
#[inline]
fn clenshaw(x: f64, first: usize) -> f64 {
    let two_x = 2.0 * x;
    let (mut b1, mut b2) = (0.0, 0.0);
    for k in (1..NCOEF).rev() {
        let b0 = coef(first + k) + two_x * b1 - b2;
        b2 = b1;
        b1 = b0;
    }
    coef(first) + x * b1 - b2
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::vec::Vec;

    fn read_u32(at: usize) -> u32 {
        u32::from_le_bytes(DATA[at..at + 4].try_into().unwrap())
    }
    fn read_f64(at: usize) -> f64 {
        f64::from_le_bytes(DATA[at..at + 8].try_into().unwrap())
    }

    #[test]
    fn header_matches_constants() {
        assert_eq!(&DATA[..8], b"MOONCHEB");
        assert_eq!(read_f64(8), START_JD);
        assert_eq!(read_f64(16), INTERVAL_DAYS);
        assert_eq!(read_u32(24) as usize, NCOEF);
        assert_eq!(read_u32(28) as usize, COUNT);
        assert_eq!(DATA.len(), HEADER_BYTES + 4 * 3 * NCOEF * COUNT);
    }

    /// Rows of numbers from a fixture written by `tools/*.py` (JSON with one
    /// row per line).
    pub(crate) fn fixture_rows(text: &str) -> Vec<Vec<f64>> {
        let body = &text[text.find("\"rows\"").expect("rows")..];
        body.lines()
            .filter(|l| l.starts_with('['))
            .map(|l| {
                l.trim_matches(|c| c == '[' || c == ']' || c == ',')
                    .split(',')
                    .map(|v| v.trim().parse::<f64>().expect("number"))
                    .collect()
            })
            .collect()
    }

    /// 50 positions computed with jplephem from de421.bsp by
    /// tools/gen_moon_de421.py, off the fit nodes, including both ends.
    #[test]
    fn matches_de421_positions() {
        let rows = fixture_rows(include_str!("../../data/moon_de421_check.json"));
        assert_eq!(rows.len(), 50);
        let mut worst: f64 = 0.0;
        for r in &rows {
            let p = de421(r[0]).expect("inside span");
            let err = (p - DVec3::new(r[1], r[2], r[3])).length();
            worst = worst.max(err);
        }
        assert!(worst < 0.2, "max error {worst} km");
    }

    #[test]
    fn outside_span_is_none() {
        let (a, b) = DE421_SPAN;
        assert!(de421(a - 1e-6).is_none());
        assert!(de421(b + 1e-6).is_none());
        assert!(de421(f64::NAN).is_none());
        assert!(de421(a).is_some());
        assert!(de421(b).is_some());
    }

    /// Adjacent intervals are separate fits; they must meet within twice the
    /// fit error, and the distance must stay within the lunar orbit's range.
    #[test]
    fn continuous_across_interval_boundaries() {
        for i in 1..COUNT {
            let before = position(i - 1, 1.0);
            let after = position(i, -1.0);
            assert!((before - after).length() < 0.1, "jump at interval {i}");
            let r = after.length();
            assert!((356_000.0..407_000.0).contains(&r), "distance {r}");
        }
    }
}
