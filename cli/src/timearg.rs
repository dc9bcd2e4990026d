//! Parsing and printing of instants: RFC 3339 civil UTC (offsets converted),
//! leap seconds included, date-only `YYYY-MM-DD` (0h UTC), or `now`.
//!
//! One calendar in and out: dates before 1582-10-15 are Julian-calendar
//! dates, later ones Gregorian (as astronomical tables print them); years
//! are astronomical (0 = 1 BC) and outside 0000–9999 carry a sign
//! (`-0500-01-01`, `+10000-01-01`). Everything [`format_utc`] prints is read
//! back by [`parse_date_or_time`] as the same instant (to the millisecond
//! it prints).

use himmel_astro::UtcDateTime;

use crate::inputs::printable;

/// Parses `[±]YYYY-MM-DD` (0h UTC) or an RFC 3339 time for `flag`
/// (`--time`, `--from`, `--to`), and `now` where `allow_now`.
pub fn parse_date_or_time(flag: &str, s: &str, allow_now: bool) -> Result<UtcDateTime, String> {
    if allow_now && s.trim().eq_ignore_ascii_case("now") {
        return now();
    }
    himmel_astro::time::parse_date_or_rfc3339(s).map_err(|e| {
        let now = if allow_now { " or now" } else { "" };
        format!(
            "{flag}: '{}' is not a date or RFC 3339 time ({e}); expected e.g. 2024-04-08, \
             2024-04-08T18:42:00Z, -0500-03-01 (Julian calendar before 1582-10-15){now}",
            printable(s)
        )
    })
}

/// Parses a date-only `[±]YYYY-MM-DD` for `flag` (Julian calendar before
/// 1582-10-15); returns (year, month, day).
pub fn parse_date(flag: &str, s: &str) -> Result<(i32, u8, u8), String> {
    let t = himmel_astro::time::parse_date(s).map_err(|e| {
        format!(
            "{flag}: '{}' is not a date ({e}); expected YYYY-MM-DD, e.g. 2024-04-08 or -0500-03-01",
            printable(s)
        )
    })?;
    Ok((t.year, t.month, t.day))
}

/// The current civil UTC time from the system clock.
pub fn now() -> Result<UtcDateTime, String> {
    UtcDateTime::try_from(chrono::Utc::now()).map_err(|e| format!("system clock: {e}"))
}

/// Formats civil UTC as RFC 3339 with milliseconds and a `Z` suffix
/// (truncated, so that 59.9996 s never turns into second 60).
pub fn format_utc(t: &UtcDateTime) -> String {
    // A second read back from "…05.344Z" may be 5.343999…: a nanosecond of
    // slack keeps the printed millisecond, the clamp keeps 59.9999999996
    // (or 60.99…, in a leap second) from printing as the next minute.
    let last_ms = if t.second < 60.0 { 59_999 } else { 60_999 };
    let ms = ((t.second * 1000.0 + 1e-6).floor() as i64).min(last_ms);
    format!(
        "{}T{:02}:{:02}:{:02}.{:03}Z",
        format_date(t.year, t.month, t.day),
        t.hour,
        t.minute,
        ms / 1000,
        ms % 1000
    )
}

/// Formats a calendar date `YYYY-MM-DD`, with a sign and at least four
/// digits for years outside 0000–9999 (ISO 8601 expanded years).
pub fn format_date(year: i32, month: u8, day: u8) -> String {
    if (0..=9999).contains(&year) {
        format!("{year:04}-{month:02}-{day:02}")
    } else {
        format!("{year:+05}-{month:02}-{day:02}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use himmel_astro::time::{calendar_date, julian_day};

    fn parse(s: &str) -> UtcDateTime {
        parse_date_or_time("--time", s, false).unwrap()
    }

    #[test]
    fn leap_second_round_trip() {
        let t = parse("2017-01-01T08:59:60+09:00");
        assert_eq!(format_utc(&t), "2016-12-31T23:59:60.000Z");
        let t = UtcDateTime::new(2024, 1, 1, 23, 59, 59.999_999_999_9).unwrap();
        assert_eq!(format_utc(&t), "2024-01-01T23:59:59.999Z");
        let t = UtcDateTime::new(2016, 12, 31, 23, 59, 60.999_999_999_9).unwrap();
        assert_eq!(format_utc(&t), "2016-12-31T23:59:60.999Z");
        let t = UtcDateTime::new(2024, 1, 1, 0, 0, 5.9996).unwrap();
        assert_eq!(format_utc(&t), "2024-01-01T00:00:05.999Z");
        let e = parse_date_or_time("--time", "yesterday", true).unwrap_err();
        assert!(
            e.starts_with("--time: 'yesterday'") && e.ends_with("or now"),
            "{e}"
        );
        assert!(!parse_date_or_time("--from", "now", false)
            .unwrap_err()
            .contains("or now"));
    }

    /// What `eclipses` prints for a Julian-calendar leap day comes back as
    /// the same instant (issue 19: it used to come back as March 1).
    #[test]
    fn printed_julian_dates_read_back() {
        let s = "-1900-02-29T13:03:17.000Z";
        assert_eq!(format_utc(&parse(s)), s);
        assert_eq!(format_utc(&parse("-1900-02-29T13:03:17Z")), s);
        assert_eq!(
            format_utc(&parse("-0500-01-01")),
            "-0500-01-01T00:00:00.000Z"
        );
        assert_eq!(
            format_utc(&parse("+10000-01-01")),
            "+10000-01-01T00:00:00.000Z"
        );
        assert_eq!(format_utc(&parse("0000-02-29")), "0000-02-29T00:00:00.000Z");
        assert_eq!(format_date(-500, 3, 1), "-0500-03-01");
        assert_eq!(format_date(12_345, 3, 1), "+12345-03-01");
        assert_eq!(parse_date("--date", "-0500-03-01"), Ok((-500, 3, 1)));
        assert!(parse_date("--date", "1582-10-10")
            .unwrap_err()
            .contains("Gregorian reform"));
    }

    /// −4712 January 1, 12h (Julian calendar) is JD 0.0 (Meeus ch. 7), and
    /// 1582 October 4 is followed by October 15.
    #[test]
    fn julian_day_zero_and_the_gregorian_switch() {
        let t = parse("-4712-01-01T12:00:00Z");
        assert_eq!(julian_day(t.year, t.month, f64::from(t.day) + 0.5), 0.0);
        let a = parse("1582-10-04");
        let b = parse("1582-10-15");
        let jd = |t: UtcDateTime| julian_day(t.year, t.month, f64::from(t.day));
        assert_eq!(jd(b) - jd(a), 1.0);
        assert_eq!(jd(b), 2_299_160.5);
    }

    /// Random instants from −3000 to +3000 (a fixed-seed generator): the
    /// printed text reads back as the same fields, and the fields as the same
    /// Julian day, over both calendars.
    #[test]
    fn format_parse_round_trip_over_six_millennia() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let jd_lo = julian_day(-3000, 1, 1.0);
        let jd_hi = julian_day(3000, 12, 31.0);
        for _ in 0..20_000 {
            let u = (next() >> 11) as f64 / (1u64 << 53) as f64;
            let jd = jd_lo + u * (jd_hi - jd_lo);
            let (y, m, d) = calendar_date(jd);
            let day = d.floor();
            let sod = ((d - day) * 86_400_000.0).floor() / 1000.0;
            let (h, rest) = ((sod / 3600.0) as u8, sod % 3600.0);
            let t = UtcDateTime::new(y, m, day as u8, h, (rest / 60.0) as u8, rest % 60.0).unwrap();
            let text = format_utc(&t);
            let back = parse(&text);
            assert_eq!(format_utc(&back), text);
            assert_eq!(
                (back.year, back.month, back.day),
                (y, m, day as u8),
                "{text}"
            );
            assert_eq!((back.hour, back.minute), (t.hour, t.minute), "{text}");
            assert!((back.second - t.second).abs() < 1e-3, "{text}");
            assert_eq!(
                julian_day(y, m, day),
                julian_day(back.year, back.month, f64::from(back.day))
            );
        }
    }
}
