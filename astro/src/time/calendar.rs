//! Calendar dates ↔ Julian days (Meeus, *Astronomical Algorithms* 2nd ed.,
//! ch. 7). Dates before 1582 October 15 are in the Julian calendar, later
//! ones in the Gregorian calendar; years use astronomical numbering
//! (year 0 = 1 BC, −1 = 2 BC).

use crate::units::JulianDay;

/// First Julian day number (at noon) of the Gregorian calendar,
/// 1582 October 15 (Meeus ch. 7, the "2 299 161" switch).
const GREGORIAN_START_JDN: f64 = 2_299_161.0;

/// Length of the Julian calendar's 4-year cycle, days.
const JULIAN_CYCLE_DAYS: f64 = 1_461.0;

/// Whether (year, month, day) falls on or after the Gregorian reform,
/// 1582 October 15.
#[inline]
pub(crate) fn is_gregorian(year: i32, month: u8, day: f64) -> bool {
    (year, month) > (1582, 10) || ((year, month) == (1582, 10) && day >= 15.0)
}

/// Whether `year` is a leap year of the calendar in force in that year
/// (Julian before 1582, Gregorian from 1583; 1582 itself is not a leap year
/// in either).
pub fn is_leap_year(year: i32) -> bool {
    if year < 1583 {
        year.rem_euclid(4) == 0
    } else {
        (year % 4 == 0 && year % 100 != 0) || year % 400 == 0
    }
}

/// Number of days in `month` (1–12) of `year`, in the calendar in force.
/// October 1582 is reported as 31 days long; its ten missing days
/// (5–14) are rejected separately by [`crate::time::UtcDateTime::new`].
pub fn days_in_month(year: i32, month: u8) -> u8 {
    match month {
        1 | 3 | 5 | 7 | 8 | 10 | 12 => 31,
        4 | 6 | 9 | 11 => 30,
        2 => {
            if is_leap_year(year) {
                29
            } else {
                28
            }
        }
        _ => 0,
    }
}

/// Julian day of a calendar date; `day` may carry a fraction of a day
/// (e.g. 4.81 = day 4 at 19h26m24s). The Julian calendar is used before
/// 1582 October 15, the Gregorian from then on; years are astronomical
/// (0 = 1 BC). Valid for any year, negative Julian days included.
///
/// The time scale of the result is that of the input.
/// Source: Meeus, *Astronomical Algorithms* 2nd ed., eq. 7.1, with `INT`
/// taken as `floor` so that negative years work.
pub fn julian_day(year: i32, month: u8, day: JulianDay) -> JulianDay {
    let (y, m) = if month <= 2 {
        (year as f64 - 1.0, month as f64 + 12.0)
    } else {
        (year as f64, month as f64)
    };
    let b = if is_gregorian(year, month, day) {
        let a = libm::floor(y / 100.0);
        2.0 - a + libm::floor(a / 4.0)
    } else {
        0.0
    };
    // The integer part is exact in f64; the day (with its fraction) is added
    // last so that only one rounding touches it.
    (libm::floor(365.25 * (y + 4716.0)) + libm::floor(30.6001 * (m + 1.0)) + b - 1524.5) + day
}

/// Calendar date of a Julian day: (year, month, day with fraction), in the
/// Julian calendar before 1582 October 15 and the Gregorian from then on.
/// Astronomical year numbering; any finite Julian day (negative too).
///
/// Source: Meeus, *Astronomical Algorithms* 2nd ed., ch. 7 ("Calculation of
/// the calendar date from the JD"). Meeus restricts the method to JD ≥ 0; for
/// negative days this shifts by whole 4-year Julian cycles first.
pub fn calendar_date(jd: JulianDay) -> (i32, u8, f64) {
    let mut z = libm::floor(jd + 0.5);
    let f = (jd + 0.5) - z;
    // Bring negative day numbers into range by whole Julian 4-year cycles
    // (1461 days each), which leave month and day unchanged.
    let mut cycles = 0.0;
    if z < 0.0 {
        cycles = libm::ceil(-z / JULIAN_CYCLE_DAYS);
        z += cycles * JULIAN_CYCLE_DAYS;
    }
    let a = if z < GREGORIAN_START_JDN {
        z
    } else {
        let alpha = libm::floor((z - 1_867_216.25) / 36_524.25);
        z + 1.0 + alpha - libm::floor(alpha / 4.0)
    };
    let b = a + 1524.0;
    let c = libm::floor((b - 122.1) / 365.25);
    let d = libm::floor(365.25 * c);
    let e = libm::floor((b - d) / 30.6001);
    let day = b - d - libm::floor(30.6001 * e) + f;
    let month = if e < 14.0 { e - 1.0 } else { e - 13.0 };
    let year = if month > 2.0 { c - 4716.0 } else { c - 4715.0 };
    let year = year - 4.0 * cycles;
    (year as i32, month as u8, day)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meeus_example_7a_sputnik() {
        // Meeus Example 7.a: 1957 October 4.81 → JD 2436116.31.
        assert!((julian_day(1957, 10, 4.81) - 2_436_116.31).abs() < 1e-9);
    }

    #[test]
    fn meeus_example_7b_julian_calendar() {
        // Meeus Example 7.b: 333 January 27.5 → JD 1842713.0.
        assert_eq!(julian_day(333, 1, 27.5), 1_842_713.0);
    }

    #[test]
    fn meeus_table_dates() {
        // Test values listed by Meeus after Example 7.b.
        let cases: [(i32, u8, f64, f64); 14] = [
            (2000, 1, 1.5, 2_451_545.0),
            (1999, 1, 1.0, 2_451_179.5),
            (1987, 1, 27.0, 2_446_822.5),
            (1987, 6, 19.5, 2_446_966.0),
            (1988, 1, 27.0, 2_447_187.5),
            (1988, 6, 19.5, 2_447_332.0),
            (1900, 1, 1.0, 2_415_020.5),
            (1600, 1, 1.0, 2_305_447.5),
            (1600, 12, 31.0, 2_305_812.5),
            (837, 4, 10.3, 2_026_871.8),
            (-123, 12, 31.0, 1_676_496.5),
            (-122, 1, 1.0, 1_676_497.5),
            (-1000, 7, 12.5, 1_356_001.0),
            (-4712, 1, 1.5, 0.0),
        ];
        for (y, m, d, jd) in cases {
            assert!((julian_day(y, m, d) - jd).abs() < 1e-9, "{y}-{m}-{d}");
            let (y2, m2, d2) = calendar_date(jd);
            assert_eq!((y2, m2), (y, m), "{jd}");
            assert!((d2 - d).abs() < 1e-9, "{jd}: {d2}");
        }
        // Meeus Example 7.c: JD 2436116.31 → 1957 October 4.81.
        let (y, m, d) = calendar_date(2_436_116.31);
        assert_eq!((y, m), (1957, 10));
        assert!((d - 4.81).abs() < 1e-9);
        // Meeus Example 7.c (second part): 1842713.0 → 333 January 27.5.
        assert_eq!(calendar_date(1_842_713.0), (333, 1, 27.5));
    }

    #[test]
    fn gregorian_reform_has_no_gap_in_julian_days() {
        // 1582 October 4 (Julian) is followed by October 15 (Gregorian).
        assert_eq!(julian_day(1582, 10, 15.0) - julian_day(1582, 10, 4.0), 1.0);
    }

    #[test]
    fn round_trip_over_twenty_millennia() {
        // Every 97th day from −9999 to +9999, both directions.
        let start = julian_day(-9999, 1, 1.0);
        let end = julian_day(9999, 12, 31.0);
        let mut jd = start;
        let mut previous = calendar_date(jd - 1.0);
        while jd <= end {
            let (y, m, d) = calendar_date(jd);
            assert!((1..=12).contains(&m));
            assert!(d >= 1.0 && d < days_in_month(y, m) as f64 + 1.0, "{jd}");
            assert_eq!(julian_day(y, m, d), jd, "{y}-{m}-{d}");
            assert!((y, m, d) > previous);
            previous = (y, m, d);
            jd += 97.0;
        }
    }

    #[test]
    fn leap_years_follow_the_calendar_in_force() {
        assert!(is_leap_year(1500)); // Julian
        assert!(!is_leap_year(1700)); // Gregorian
        assert!(is_leap_year(2000));
        assert!(is_leap_year(0));
        assert!(is_leap_year(-4));
        assert!(!is_leap_year(-1));
        // Julian 1500 February has 29 days: March 1 is 29 days after Feb 1.
        assert_eq!(julian_day(1500, 3, 1.0) - julian_day(1500, 2, 1.0), 29.0);
        assert_eq!(julian_day(1700, 3, 1.0) - julian_day(1700, 2, 1.0), 28.0);
    }
}
