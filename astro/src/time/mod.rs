//! Time scales: calendar dates, UTC with leap seconds, TT, UT1, ΔT and
//! sidereal time.
//!
//! Rules for turning a UTC clock reading into an [`Instant`] (TT for the
//! dynamics, UT1 for the Earth's rotation):
//!
//! | UTC | TT | UT1 |
//! |---|---|---|
//! | before 1972-01-01 | UT1 + ΔT (model) | = UTC |
//! | 1972-01-01 … 1973-01-01 | TAI + 32.184 s (leap seconds) | = UTC (no table) |
//! | 1973-01-02 … last day of the IERS table | TAI + 32.184 s | UTC + (UT1 − UTC) from the table |
//! | the year after the table | UT1 + ΔT (model) | UTC + (UT1 − UTC)ₑₙ𝒹 · fade |
//! | later | UT1 + ΔT (model) | = UTC |
//!
//! The last IERS value of UT1 − UTC (up to ±0.9 s) is faded out linearly
//! over [`POST_TABLE_FADE_DAYS`] after the table end instead of dropped at
//! once, so that UT1 and TT stay continuous functions of UTC there; ΔT(model)
//! itself is continuous with the table (see [`delta_t`]). The jump of up to
//! ~0.1 s at 1972-01-01 is inherent: UTC before 1972 ran on "rubber seconds"
//! and is treated as UT1.

mod calendar;
mod delta_t;
#[rustfmt::skip]
#[allow(clippy::approx_constant)] // ΔT = 6.28 s in 1768 is data, not 2π
mod delta_t_data;
mod leap_seconds;
mod rfc3339;
mod sidereal;

pub use calendar::{calendar_date, days_in_month, is_leap_year, julian_day};
pub use delta_t::{
    delta_t, espenak_meeus_2006, first_predicted_jd_utc, jd_tt_of_decimal_year,
    morrison_stephenson_2004, ut1_minus_utc, JOIN_FADE_YEARS, SEAM_RAMP_YEARS,
};
pub use leap_seconds::{tai_minus_utc, JD_UTC_1972};
pub use rfc3339::{parse_date, parse_date_or_rfc3339, parse_rfc3339, Rfc3339Error};
pub use sidereal::{gast, gmst};

use crate::error::AstroError;
use crate::units::{JulianCenturies, JulianDay, Seconds, DAYS_PER_CENTURY, J2000, SECONDS_PER_DAY};
use leap_seconds::{day_offset, has_leap_second, utc_day_length};

/// TT − TAI, seconds (IAU 1991 Resolution A4).
pub const TT_MINUS_TAI: Seconds = 32.184;

/// Days after the last row of the IERS table over which its last UT1 − UTC
/// fades to zero (after which UT1 = UTC is assumed).
pub const POST_TABLE_FADE_DAYS: f64 = 365.25;

/// A civil date and clock time in UTC. Years use astronomical numbering
/// (0 = 1 BC); the calendar is Julian before 1582 October 15 and Gregorian
/// from then on. Construct with [`UtcDateTime::new`], which validates.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct UtcDateTime {
    /// Year (astronomical numbering).
    pub year: i32,
    /// Month, 1–12.
    pub month: u8,
    /// Day of month, 1–31.
    pub day: u8,
    /// Hour, 0–23.
    pub hour: u8,
    /// Minute, 0–59.
    pub minute: u8,
    /// Second with fraction, [0, 60), or [60, 61) during a leap second.
    pub second: f64,
}

/// Civil UTC from a `chrono` UTC time (feature `chrono`); chrono's leap
/// second (nanoseconds ≥ 10⁹) becomes second 60. Errors where the date is
/// invalid for [`UtcDateTime::new`].
#[cfg(feature = "chrono")]
impl TryFrom<chrono::DateTime<chrono::Utc>> for UtcDateTime {
    type Error = AstroError;

    fn try_from(t: chrono::DateTime<chrono::Utc>) -> Result<Self, AstroError> {
        use chrono::{Datelike, Timelike};
        let second = f64::from(t.second()) + f64::from(t.nanosecond()) * 1e-9;
        UtcDateTime::new(
            t.year(),
            t.month() as u8,
            t.day() as u8,
            t.hour() as u8,
            t.minute() as u8,
            second,
        )
    }
}

impl UtcDateTime {
    /// A validated UTC date and time.
    ///
    /// Checks month 1–12, the day against the month (Julian leap years before
    /// 1582, Gregorian after; 1582 October 5–14 do not exist), hour < 24,
    /// minute < 60, 0 ≤ second < 60 — or 60 ≤ second < 61 only at 23:59 of a
    /// UTC day that ends with a positive leap second (IERS Bulletin C).
    /// Errors: [`AstroError::InvalidDate`] for impossible fields,
    /// [`AstroError::OutOfRange`] for a non-finite or negative second.
    pub fn new(
        year: i32,
        month: u8,
        day: u8,
        hour: u8,
        minute: u8,
        second: f64,
    ) -> Result<Self, AstroError> {
        if !(1..=12).contains(&month) {
            return Err(AstroError::InvalidDate {
                what: "month",
                reason: "month must be 1-12",
            });
        }
        if day == 0 || day > calendar::days_in_month(year, month) {
            return Err(AstroError::InvalidDate {
                what: "day",
                reason: "no such day in this month",
            });
        }
        if year == 1582 && month == 10 && (5..=14).contains(&day) {
            return Err(AstroError::InvalidDate {
                what: "day",
                reason: "1582 October 5-14 were skipped by the Gregorian reform",
            });
        }
        if hour >= 24 {
            return Err(AstroError::InvalidDate {
                what: "hour",
                reason: "hour must be 0-23",
            });
        }
        if minute >= 60 {
            return Err(AstroError::InvalidDate {
                what: "minute",
                reason: "minute must be 0-59",
            });
        }
        AstroError::check_range("second", second, 0.0, 61.0)?;
        if second >= 61.0 {
            return Err(AstroError::InvalidDate {
                what: "second",
                reason: "second must be below 61",
            });
        }
        if second >= 60.0 {
            let day0 = calendar::julian_day(year, month, day as f64);
            if !(hour == 23 && minute == 59 && has_leap_second(day0)) {
                return Err(AstroError::InvalidDate {
                    what: "second",
                    reason: "second 60 exists only in a positive leap second",
                });
            }
        }
        Ok(UtcDateTime {
            year,
            month,
            day,
            hour,
            minute,
            second,
        })
    }

    /// Julian day of this date's 0h, and the seconds since then (which reach
    /// 86 400–86 401 during a leap second).
    fn day0_and_seconds(&self) -> (JulianDay, Seconds) {
        let day0 = calendar::julian_day(self.year, self.month, self.day as f64);
        let sod = self.hour as f64 * 3600.0 + self.minute as f64 * 60.0 + self.second;
        (day0, sod)
    }

    /// Build from a 0h Julian day and seconds of day (which may be ≥ 86 400
    /// only during a leap second).
    fn from_day0_and_seconds(day0: JulianDay, sod: Seconds) -> UtcDateTime {
        let (year, month, day) = calendar::calendar_date(day0);
        let day = libm::round(day) as u8;
        let (hour, minute, second) = if sod >= SECONDS_PER_DAY {
            (23, 59, sod - 86_340.0)
        } else {
            let sod = sod.max(0.0);
            let hour = libm::floor(sod / 3600.0).min(23.0);
            let minute = libm::floor((sod - hour * 3600.0) / 60.0).min(59.0);
            let second = sod - hour * 3600.0 - minute * 60.0;
            (hour as u8, minute as u8, second)
        };
        UtcDateTime {
            year,
            month,
            day,
            hour,
            minute,
            second,
        }
    }
}

/// One moment, carried in two time scales: TT (Terrestrial Time, for the
/// dynamics; TDB − TT is neglected in this crate) and UT1 (the Earth's
/// rotation angle, for sidereal time). Both are Julian days.
///
/// An f64 Julian day resolves about 40 µs near the present (half an ulp,
/// 20 µs, is the rounding of any conversion into it).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Instant {
    /// Julian day, Terrestrial Time.
    pub jd_tt: JulianDay,
    /// Julian day, UT1.
    pub jd_ut1: JulianDay,
}

#[inline]
fn day0_of(jd: JulianDay) -> JulianDay {
    libm::floor(jd - 0.5) + 0.5
}

/// UT1 − UTC that applies after the IERS table: its last value, faded out
/// linearly over [`POST_TABLE_FADE_DAYS`].
fn post_table_ut1_minus_utc(jd_utc: JulianDay) -> Seconds {
    let (end, dut1) = delta_t::daily_end();
    let w = (1.0 - (jd_utc - end) / POST_TABLE_FADE_DAYS).clamp(0.0, 1.0);
    dut1 * w
}

impl Instant {
    /// The instant of a UTC clock reading, following the rules in the
    /// [module documentation](self): leap seconds (TT = TAI + 32.184 s) and the
    /// IERS UT1 − UTC table from 1972 to the table's end; UT1 = UTC and
    /// TT = UT1 + ΔT(model) before 1972 and (after a one-year fade of the last
    /// UT1 − UTC) after the table.
    ///
    /// Always `Ok` for a validated [`UtcDateTime`]; errors only if its fields
    /// were set by hand to invalid values.
    pub fn from_utc(utc: &UtcDateTime) -> Result<Instant, AstroError> {
        let checked = UtcDateTime::new(
            utc.year, utc.month, utc.day, utc.hour, utc.minute, utc.second,
        )?;
        let (day0, sod) = checked.day0_and_seconds();
        let jd_utc = day0 + sod / SECONDS_PER_DAY;
        if day0 < JD_UTC_1972 {
            return Ok(Instant::from_ut1(jd_utc));
        }
        if day0 > delta_t::daily_last_jd_utc() || jd_utc > delta_t::daily_last_jd_utc() {
            let ut1 = day0 + (sod + post_table_ut1_minus_utc(jd_utc)) / SECONDS_PER_DAY;
            return Ok(Instant::from_ut1(ut1));
        }
        let tt_minus_utc = TT_MINUS_TAI + day_offset(day0);
        let jd_tt = day0 + (sod + tt_minus_utc) / SECONDS_PER_DAY;
        let jd_ut1 = if delta_t::in_daily_table(jd_utc) {
            // UT1 = TT − ΔT(table): equals UTC + (UT1 − UTC), with the
            // leap-second step of UT1 − UTC falling exactly at the leap second.
            day0 + (sod + tt_minus_utc - delta_t::delta_t(jd_tt)) / SECONDS_PER_DAY
        } else {
            jd_utc
        };
        Ok(Instant { jd_tt, jd_ut1 })
    }

    /// The instant at TT Julian day `jd_tt`, with UT1 = TT − ΔT(model).
    pub fn from_tt(jd_tt: JulianDay) -> Instant {
        Instant {
            jd_tt,
            jd_ut1: jd_tt - delta_t::delta_t(jd_tt) / SECONDS_PER_DAY,
        }
    }

    /// The instant at UT1 Julian day `jd_ut1`, with TT solving
    /// TT = UT1 + ΔT(TT) (fixed-point iteration; ΔT changes by far less than
    /// a day per day, so three rounds converge to the last bit).
    pub fn from_ut1(jd_ut1: JulianDay) -> Instant {
        let mut jd_tt = jd_ut1 + delta_t::delta_t(jd_ut1) / SECONDS_PER_DAY;
        for _ in 0..3 {
            jd_tt = jd_ut1 + delta_t::delta_t(jd_tt) / SECONDS_PER_DAY;
        }
        Instant { jd_tt, jd_ut1 }
    }

    /// The instant given both scales explicitly (e.g. from an external
    /// Earth-orientation source).
    pub fn from_tt_ut1(jd_tt: JulianDay, jd_ut1: JulianDay) -> Instant {
        Instant { jd_tt, jd_ut1 }
    }

    /// ΔT = TT − UT1 of this instant, seconds.
    pub fn delta_t(&self) -> Seconds {
        (self.jd_tt - self.jd_ut1) * SECONDS_PER_DAY
    }

    /// Julian centuries of TT since J2000.0: (JD_TT − 2451545.0)/36525.
    pub fn centuries_tt(&self) -> JulianCenturies {
        // A product rather than a quotient: every series waits on this value
        // first, and a division's latency is several multiplications'.
        (self.jd_tt - J2000) * (1.0 / DAYS_PER_CENTURY)
    }

    /// The UTC clock reading of this instant, inverting [`Instant::from_utc`]
    /// (to the ~20 µs rounding of an f64 Julian day). During a leap second the
    /// second is in [60, 61).
    ///
    /// The era is chosen as in `from_utc`: UT1 before 1972-01-01 gives UTC =
    /// UT1; from 1972 to the IERS table end UTC follows from TT through the
    /// leap seconds; after the table, from UT1 (undoing the faded UT1 − UTC).
    pub fn to_utc(&self) -> UtcDateTime {
        if self.jd_ut1.is_nan() || self.jd_ut1 < JD_UTC_1972 {
            return utc_from_plain_jd(self.jd_ut1);
        }
        // Leap-second era: seconds of TAI past a UTC day's 0h, renormalised
        // across day boundaries (whose lengths include leap seconds).
        let mut day0 = day0_of(self.jd_tt);
        let mut sod = (self.jd_tt - day0) * SECONDS_PER_DAY - TT_MINUS_TAI - day_offset(day0);
        for _ in 0..4 {
            if sod < 0.0 {
                day0 -= 1.0;
                sod += utc_day_length(day0);
            } else if sod >= utc_day_length(day0) {
                sod -= utc_day_length(day0);
                day0 += 1.0;
            } else {
                break;
            }
        }
        let jd_utc = day0 + sod.min(SECONDS_PER_DAY) / SECONDS_PER_DAY;
        if day0 < JD_UTC_1972 {
            // Only for instants not made by `from_utc` (TT and UT1 inconsistent
            // with the leap seconds): fall back on UT1.
            return utc_from_plain_jd(self.jd_ut1);
        }
        if jd_utc <= delta_t::daily_last_jd_utc() {
            return UtcDateTime::from_day0_and_seconds(day0, sod);
        }
        // After the table: UTC = UT1 − faded (UT1 − UTC); the fade changes by
        // under 3e-8 s per second, so a short fixed-point iteration converges.
        // Seconds of day are kept apart from the large day number.
        let mut day0 = day0_of(self.jd_ut1);
        let ut1_sod = (self.jd_ut1 - day0) * SECONDS_PER_DAY;
        let mut sod = ut1_sod;
        for _ in 0..3 {
            sod = ut1_sod - post_table_ut1_minus_utc(day0 + sod / SECONDS_PER_DAY);
        }
        if sod < 0.0 {
            day0 -= 1.0;
            sod += SECONDS_PER_DAY;
        } else if sod >= SECONDS_PER_DAY {
            day0 += 1.0;
            sod -= SECONDS_PER_DAY;
        }
        UtcDateTime::from_day0_and_seconds(day0, sod)
    }
}

/// Calendar date and clock time of a Julian day with no leap seconds.
fn utc_from_plain_jd(jd: JulianDay) -> UtcDateTime {
    let mut day0 = day0_of(jd);
    let mut sod = (jd - day0) * SECONDS_PER_DAY;
    if sod >= SECONDS_PER_DAY {
        day0 += 1.0;
        sod -= SECONDS_PER_DAY;
    }
    UtcDateTime::from_day0_and_seconds(day0, sod)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn utc(y: i32, mo: u8, d: u8, h: u8, mi: u8, s: f64) -> UtcDateTime {
        UtcDateTime::new(y, mo, d, h, mi, s).unwrap()
    }

    #[test]
    fn invalid_dates_are_errors() {
        assert!(matches!(
            UtcDateTime::new(2020, 13, 1, 0, 0, 0.0),
            Err(AstroError::InvalidDate { what: "month", .. })
        ));
        assert!(matches!(
            UtcDateTime::new(2020, 0, 1, 0, 0, 0.0),
            Err(AstroError::InvalidDate { what: "month", .. })
        ));
        assert!(matches!(
            UtcDateTime::new(2021, 2, 30, 0, 0, 0.0),
            Err(AstroError::InvalidDate { what: "day", .. })
        ));
        assert!(UtcDateTime::new(2021, 2, 29, 0, 0, 0.0).is_err());
        assert!(UtcDateTime::new(2020, 2, 29, 0, 0, 0.0).is_ok());
        assert!(UtcDateTime::new(1900, 2, 29, 0, 0, 0.0).is_err());
        assert!(UtcDateTime::new(1500, 2, 29, 0, 0, 0.0).is_ok()); // Julian
        assert!(UtcDateTime::new(1582, 10, 10, 0, 0, 0.0).is_err());
        assert!(UtcDateTime::new(2020, 1, 1, 24, 0, 0.0).is_err());
        assert!(UtcDateTime::new(2020, 1, 1, 0, 60, 0.0).is_err());
        assert!(matches!(
            UtcDateTime::new(2020, 1, 1, 0, 0, f64::NAN),
            Err(AstroError::OutOfRange { what: "second", .. })
        ));
        assert!(UtcDateTime::new(2020, 1, 1, 0, 0, -0.5).is_err());
        assert!(UtcDateTime::new(2020, 1, 1, 0, 0, f64::INFINITY).is_err());
        // Second 60 on a day without a leap second, or not at 23:59.
        assert!(matches!(
            UtcDateTime::new(2017, 12, 31, 23, 59, 60.0),
            Err(AstroError::InvalidDate { what: "second", .. })
        ));
        assert!(UtcDateTime::new(2016, 12, 31, 23, 58, 60.0).is_err());
        assert!(UtcDateTime::new(1960, 12, 31, 23, 59, 60.0).is_err());
        assert!(UtcDateTime::new(2016, 12, 31, 23, 59, 61.0).is_err());
        assert!(UtcDateTime::new(2016, 12, 31, 23, 59, 60.5).is_ok());
        assert!(UtcDateTime::new(1972, 6, 30, 23, 59, 60.0).is_ok());
        // Instant::from_utc re-validates fields set by hand.
        let mut bad = utc(2020, 1, 1, 0, 0, 0.0);
        bad.day = 32;
        assert!(Instant::from_utc(&bad).is_err());
    }

    #[test]
    fn leap_second_2016_tt_strictly_increasing() {
        let a = Instant::from_utc(&utc(2016, 12, 31, 23, 59, 59.0)).unwrap();
        let b = Instant::from_utc(&utc(2016, 12, 31, 23, 59, 60.0)).unwrap();
        let c = Instant::from_utc(&utc(2017, 1, 1, 0, 0, 0.0)).unwrap();
        let ab = (b.jd_tt - a.jd_tt) * SECONDS_PER_DAY;
        let bc = (c.jd_tt - b.jd_tt) * SECONDS_PER_DAY;
        assert!(
            (ab - 1.0).abs() < 1e-4 && (bc - 1.0).abs() < 1e-4,
            "{ab} {bc}"
        );
        // TT − UTC is 68.184 s before and 69.184 s after.
        let jd0 = julian_day(2017, 1, 1.0);
        assert!(((c.jd_tt - jd0) * SECONDS_PER_DAY - 69.184).abs() < 1e-4);
        // UT1 is continuous through the leap second (it advances ~1 s per s).
        let ut1_ab = (b.jd_ut1 - a.jd_ut1) * SECONDS_PER_DAY;
        let ut1_bc = (c.jd_ut1 - b.jd_ut1) * SECONDS_PER_DAY;
        assert!((ut1_ab - 1.0).abs() < 1e-3 && (ut1_bc - 1.0).abs() < 1e-3);
        // And back.
        let back = b.to_utc();
        assert_eq!(
            (back.year, back.month, back.day, back.hour, back.minute),
            (2016, 12, 31, 23, 59)
        );
        assert!((back.second - 60.0).abs() < 1e-4, "{}", back.second);
        let back = c.to_utc();
        assert_eq!(
            (back.year, back.month, back.day, back.hour, back.minute),
            (2017, 1, 1, 0, 0)
        );
    }

    #[test]
    fn delta_t_of_instants_matches_skyfield() {
        // 2000-01-01 12:00 UTC: Skyfield 1.55 (finals2000A.all) gives
        // TT = 2451545.0007428704 and ΔT = 63.8289604 s
        // (`python3 tools/gen_delta_t.py --check`).
        let i = Instant::from_utc(&utc(2000, 1, 1, 12, 0, 0.0)).unwrap();
        assert!((i.jd_tt - 2_451_545.000_742_870_4).abs() * SECONDS_PER_DAY < 5e-5);
        assert!((i.delta_t() - 63.828_960_4).abs() < 1e-4);
        // ΔT model and the instant agree inside the table.
        assert!((i.delta_t() - delta_t(i.jd_tt)).abs() < 1e-4);
    }

    #[test]
    fn from_tt_and_from_ut1_are_consistent() {
        for jd in [
            -1e6,
            0.0,
            1_000_000.0,
            2_299_160.5,
            2_451_545.0,
            2_470_000.0,
            3_000_000.0,
        ] {
            let a = Instant::from_tt(jd);
            let b = Instant::from_ut1(a.jd_ut1);
            assert!((b.jd_tt - jd).abs() * SECONDS_PER_DAY < 1e-4, "{jd}");
            assert!((a.delta_t() - delta_t(jd)).abs() < 1e-3);
        }
        let i = Instant::from_tt(J2000 + 36525.0);
        assert!((i.centuries_tt() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn utc_round_trip() {
        // Dates in every era: before 1972, 1972, table, prediction, fade, after.
        let cases = [
            (-500, 3, 1, 12, 0, 0.0),
            (1582, 10, 15, 0, 0, 0.0),
            (1900, 1, 1, 0, 0, 0.0),
            (1971, 12, 31, 23, 59, 59.9),
            (1972, 1, 1, 0, 0, 0.0),
            (1972, 6, 30, 23, 59, 60.25),
            (1973, 1, 2, 0, 0, 0.0),
            (1999, 12, 31, 23, 59, 59.999),
            (2016, 12, 31, 23, 59, 60.999),
            (2017, 1, 1, 0, 0, 0.0),
            (2024, 2, 29, 13, 45, 12.345678),
            (2026, 6, 1, 0, 0, 0.0),
            (2027, 3, 1, 6, 0, 30.0),
            (2100, 7, 4, 18, 30, 0.5),
            (3000, 1, 1, 0, 0, 0.0),
        ];
        let mut worst: f64 = 0.0;
        for (y, mo, d, h, mi, s) in cases {
            let t = utc(y, mo, d, h, mi, s);
            let back = Instant::from_utc(&t).unwrap().to_utc();
            assert!(UtcDateTime::new(
                back.year,
                back.month,
                back.day,
                back.hour,
                back.minute,
                back.second
            )
            .is_ok());
            // Difference in seconds (no leap second falls between the two).
            let (d0, s0) = t.day0_and_seconds();
            let (d1, s1) = back.day0_and_seconds();
            let diff = (d1 - d0) * SECONDS_PER_DAY + (s1 - s0);
            assert!(diff.abs() < 1e-3, "{t:?} -> {back:?}");
            worst = worst.max(diff.abs());
        }
        // Bounded by the rounding of one f64 Julian day (2^-32 d ≈ 20 µs).
        assert!(worst < 2.1e-5, "worst {worst} s");
    }

    #[test]
    fn utc_to_tt_is_continuous_and_monotonic_across_eras() {
        // Step a second at a time over the seams that have no physical jump.
        // (The 2017-01-01 leap second is covered by its own test.)
        let seams = [(1973, 1, 2), (2000, 1, 1)];
        for (y, m, d) in seams {
            let jd0 = julian_day(y, m, d as f64);
            let (py, pm, pd) = calendar_date(jd0 - 1.0);
            let mut prev = Instant::from_utc(&utc(py, pm, pd as u8, 23, 59, 50.0)).unwrap();
            for s in 1..20 {
                let t = if s <= 9 {
                    utc(py, pm, pd as u8, 23, 59, 50.0 + s as f64)
                } else {
                    utc(y, m, d, 0, 0, (s - 10) as f64)
                };
                let i = Instant::from_utc(&t).unwrap();
                let step = (i.jd_tt - prev.jd_tt) * SECONDS_PER_DAY;
                assert!(step > 0.5 && step < 1.5, "{t:?}: {step}");
                prev = i;
            }
        }
        // Across the end of the IERS table: UT1 and TT continuous.
        let (end, _) = delta_t::daily_end();
        let (y, m, d) = calendar_date(end);
        let before = Instant::from_utc(&utc(y, m, d as u8 - 1, 23, 59, 59.0)).unwrap();
        let at = Instant::from_utc(&utc(y, m, d as u8, 0, 0, 0.0)).unwrap();
        let (y2, m2, d2) = calendar_date(end + 1.0);
        let after = Instant::from_utc(&utc(y2, m2, d2 as u8, 0, 0, 0.0)).unwrap();
        for (p, q, secs) in [(before, at, 1.0), (at, after, 86_400.0)] {
            let dtt = (q.jd_tt - p.jd_tt) * SECONDS_PER_DAY - secs;
            let dut = (q.jd_ut1 - p.jd_ut1) * SECONDS_PER_DAY - secs;
            assert!(dtt.abs() < 0.01 && dut.abs() < 0.01, "{dtt} {dut}");
        }
    }

    #[cfg(feature = "chrono")]
    #[test]
    fn from_chrono_keeps_fractions_and_leap_seconds() {
        use chrono::{TimeZone, Timelike};
        let t = chrono::Utc
            .with_ymd_and_hms(2016, 12, 31, 23, 59, 59)
            .unwrap()
            .with_nanosecond(1_500_000_000)
            .unwrap();
        let u = UtcDateTime::try_from(t).unwrap();
        assert_eq!(
            (u.year, u.month, u.day, u.hour, u.minute),
            (2016, 12, 31, 23, 59)
        );
        assert!((u.second - 60.5).abs() < 1e-9);
    }
}
