//! TAI − UTC since 1972: the leap-second table of IERS Bulletin C.

use crate::units::{JulianDay, Seconds};

/// Julian day (UTC) of 1972 January 1, 0h: the start of the integer-second
/// UTC that this module describes.
pub const JD_UTC_1972: JulianDay = 2_441_317.5;

/// Offset between MJD and JD.
const MJD_ZERO: f64 = 2_400_000.5;

/// (MJD (UTC) from which the offset holds, TAI − UTC in seconds).
/// Source: IERS Bulletin C (file `Leap_Second.dat`); the last leap second was
/// inserted at the end of 2016 December 31. `tools/gen_delta_t.py` checks
/// this table against the jumps of UT1 − UTC in IERS `finals2000A.all`.
pub(crate) const LEAP_SECONDS: [(i32, i32); 28] = [
    (41317, 10), // 1972 Jan 1
    (41499, 11), // 1972 Jul 1
    (41683, 12), // 1973 Jan 1
    (42048, 13), // 1974 Jan 1
    (42413, 14), // 1975 Jan 1
    (42778, 15), // 1976 Jan 1
    (43144, 16), // 1977 Jan 1
    (43509, 17), // 1978 Jan 1
    (43874, 18), // 1979 Jan 1
    (44239, 19), // 1980 Jan 1
    (44786, 20), // 1981 Jul 1
    (45151, 21), // 1982 Jul 1
    (45516, 22), // 1983 Jul 1
    (46247, 23), // 1985 Jul 1
    (47161, 24), // 1988 Jan 1
    (47892, 25), // 1990 Jan 1
    (48257, 26), // 1991 Jan 1
    (48804, 27), // 1992 Jul 1
    (49169, 28), // 1993 Jul 1
    (49534, 29), // 1994 Jul 1
    (50083, 30), // 1996 Jan 1
    (50630, 31), // 1997 Jul 1
    (51179, 32), // 1999 Jan 1
    (53736, 33), // 2006 Jan 1
    (54832, 34), // 2009 Jan 1
    (56109, 35), // 2012 Jul 1
    (57204, 36), // 2015 Jul 1
    (57754, 37), // 2017 Jan 1
];

/// TAI − UTC in seconds at the UTC instant `jd_utc`, or `None` before
/// 1972 January 1 (the earlier "rubber-second" UTC is not modelled).
/// After the last entry (2017 January 1, 37 s) the last value is kept: no
/// future leap second is known.
///
/// During a leap second (23:59:60 UTC) a Julian day cannot name the instant;
/// pass the day's 0h to get the offset that applies through its end.
/// Source: IERS Bulletin C.
pub fn tai_minus_utc(jd_utc: JulianDay) -> Option<Seconds> {
    if jd_utc.is_nan() || jd_utc < JD_UTC_1972 {
        return None;
    }
    let mjd = jd_utc - MJD_ZERO;
    let mut offset = LEAP_SECONDS[0].1;
    for &(start, value) in LEAP_SECONDS.iter() {
        if mjd >= start as f64 {
            offset = value;
        } else {
            break;
        }
    }
    Some(offset as Seconds)
}

/// TAI − UTC for the UTC day that starts at `jd_day0` (a JD ending in .5),
/// zero before 1972 (callers check the era first).
#[inline]
pub(crate) fn day_offset(jd_day0: JulianDay) -> Seconds {
    tai_minus_utc(jd_day0).unwrap_or(0.0)
}

/// Whether the UTC day starting at `jd_day0` ends with a positive leap second.
#[inline]
pub(crate) fn has_leap_second(jd_day0: JulianDay) -> bool {
    match (tai_minus_utc(jd_day0), tai_minus_utc(jd_day0 + 1.0)) {
        (Some(a), Some(b)) => b > a,
        (None, Some(_)) => false,
        _ => false,
    }
}

/// Length in SI seconds of the UTC day starting at `jd_day0`.
#[inline]
pub(crate) fn utc_day_length(jd_day0: JulianDay) -> Seconds {
    if has_leap_second(jd_day0) {
        86_401.0
    } else {
        86_400.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boundaries() {
        assert_eq!(tai_minus_utc(JD_UTC_1972 - 1e-6), None);
        assert_eq!(tai_minus_utc(f64::NAN), None);
        assert_eq!(tai_minus_utc(JD_UTC_1972), Some(10.0));
        // 2017-01-01 0h UTC = JD 2457754.5.
        assert_eq!(tai_minus_utc(2_457_754.5 - 1e-6), Some(36.0));
        assert_eq!(tai_minus_utc(2_457_754.5), Some(37.0));
        assert_eq!(tai_minus_utc(2_470_000.0), Some(37.0));
        assert!(has_leap_second(2_457_753.5)); // 2016-12-31
        assert!(!has_leap_second(2_457_754.5));
        assert!(has_leap_second(2_441_498.5)); // 1972-06-30
        assert!(!has_leap_second(JD_UTC_1972 - 1.0)); // 1971-12-31: UTC began with 10 s
    }

    #[test]
    fn table_is_increasing_by_one_second() {
        for w in LEAP_SECONDS.windows(2) {
            assert!(w[1].0 > w[0].0);
            assert_eq!(w[1].1 - w[0].1, 1);
        }
    }
}
