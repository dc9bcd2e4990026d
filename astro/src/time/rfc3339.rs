//! RFC 3339 timestamps → civil UTC, leap seconds and UTC offsets included.

use core::fmt;

use super::UtcDateTime;
use crate::error::AstroError;

/// Why a string is not an RFC 3339 timestamp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Rfc3339Error {
    /// The text does not have the shape `YYYY-MM-DDTHH:MM:SS[.f](Z|±HH:MM)`;
    /// the reason names the part.
    Syntax(&'static str),
    /// The fields do not form a valid civil date and time (e.g. 2023-02-30).
    Date(AstroError),
}

impl fmt::Display for Rfc3339Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Rfc3339Error::Syntax(why) => f.write_str(why),
            Rfc3339Error::Date(e) => write!(f, "{e}"),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for Rfc3339Error {}

/// Parses an RFC 3339 timestamp (`2024-04-08T18:42:00Z`,
/// `2024-04-08T20:42:00.5+02:00`, `2016-12-31T23:59:60Z`) into civil UTC.
///
/// Years outside 0000–9999 are written with a sign and at least four digits
/// (`-1900-02-29T13:03:17Z`, `+10000-01-01T00:00:00Z`; ISO 8601 expanded
/// years, astronomical numbering: year 0 = 1 BC). Dates are read in the
/// calendar that Himmel prints them in ([`UtcDateTime`]): the Julian calendar
/// before 1582 October 15, the Gregorian from then on; 1582 October 5–14
/// do not exist. A UTC offset moves the time across that switch like any
/// other day boundary (`1582-10-15T01:00:00+02:00` is 1582 October 4, 23h UTC).
pub fn parse_rfc3339(s: &str) -> Result<UtcDateTime, Rfc3339Error> {
    let (year, month, day, rest) = split_date(s.trim())?;
    parse_time_of_day(year, month, day, rest)
}

/// Parses a date-only `[±]YYYY-MM-DD` (0h UTC, years and calendar as in
/// [`parse_rfc3339`]) or a full RFC 3339 timestamp.
pub fn parse_date_or_rfc3339(s: &str) -> Result<UtcDateTime, Rfc3339Error> {
    let (year, month, day, rest) = split_date(s.trim())?;
    if rest.is_empty() {
        return civil(year, month, day, 0, 0, 0.0);
    }
    parse_time_of_day(year, month, day, rest)
}

/// Parses a date-only `[±]YYYY-MM-DD` (years and calendar as in
/// [`parse_rfc3339`]) as 0h UTC of that day.
pub fn parse_date(s: &str) -> Result<UtcDateTime, Rfc3339Error> {
    let (year, month, day, rest) = split_date(s.trim())?;
    if !rest.is_empty() {
        return Err(Rfc3339Error::Syntax("expected a date only, YYYY-MM-DD"));
    }
    civil(year, month, day, 0, 0, 0.0)
}

/// Splits `[±]YYYY-MM-DD…` into year, month, day and the rest of the text.
fn split_date(b: &str) -> Result<(i64, i64, i64, &str), Rfc3339Error> {
    let fail = Rfc3339Error::Syntax;
    // Optional sign for expanded years.
    let (sign, body) = match b.as_bytes().first() {
        Some(b'-') => (-1i64, &b[1..]),
        Some(b'+') => (1, &b[1..]),
        _ => (1, b),
    };
    let dash = body
        .find('-')
        .ok_or_else(|| fail("no date: expected YYYY-MM-DD"))?;
    let year_digits = &body[..dash];
    if year_digits.len() < 4 || !year_digits.bytes().all(|c| c.is_ascii_digit()) {
        return Err(fail("year must have at least four digits"));
    }
    if year_digits.len() > 7 {
        return Err(fail("year out of range"));
    }
    let year: i64 = year_digits.parse().map_err(|_| fail("bad year"))?;
    let rest = &body[dash + 1..];
    let two = |r: core::ops::Range<usize>, what: &'static str| -> Result<i64, Rfc3339Error> {
        let t = rest.get(r).ok_or(fail("date must be YYYY-MM-DD"))?;
        if t.bytes().all(|c| c.is_ascii_digit()) {
            t.parse::<i64>().map_err(|_| fail(what))
        } else {
            Err(fail(what))
        }
    };
    let month = two(0..2, "month")?;
    if rest.as_bytes().get(2) != Some(&b'-') {
        return Err(fail("date must be YYYY-MM-DD"));
    }
    let day = two(3..5, "day")?;
    Ok((sign * year, month, day, &rest[5..]))
}

/// Parses `THH:MM:SS[.f](Z|±HH:MM)` after a date and converts to UTC.
fn parse_time_of_day(
    year: i64,
    month: i64,
    day: i64,
    rest: &str,
) -> Result<UtcDateTime, Rfc3339Error> {
    let fail = Rfc3339Error::Syntax;
    let bytes = rest.as_bytes();
    // THH:MM:SS
    if bytes.len() < 9 {
        return Err(fail(if bytes.is_empty() {
            "missing time: expected e.g. T18:42:00Z"
        } else {
            "too short"
        }));
    }
    let num = |r: core::ops::Range<usize>, what: &'static str| -> Result<i64, Rfc3339Error> {
        let t = rest.get(r).ok_or_else(|| fail(what))?;
        if t.bytes().all(|c| c.is_ascii_digit()) {
            t.parse::<i64>().map_err(|_| fail(what))
        } else {
            Err(fail(what))
        }
    };
    if !matches!(bytes[0], b'T' | b't' | b' ') {
        return Err(fail("missing 'T' between date and time"));
    }
    let hour = num(1..3, "hour")?;
    if bytes[3] != b':' || bytes[6] != b':' {
        return Err(fail("time must be HH:MM:SS"));
    }
    let minute = num(4..6, "minute")?;
    let mut i = 9;
    let whole_sec = num(7..9, "second")?;
    let mut second = whole_sec as f64;
    if bytes.get(i) == Some(&b'.') {
        let start = i + 1;
        let mut end = start;
        while end < bytes.len() && bytes[end].is_ascii_digit() {
            end += 1;
        }
        if end == start {
            return Err(fail("empty fraction of a second"));
        }
        // The first 15 digits as one integer over a power of ten (one
        // rounding: "…05.344" gives the f64 nearest 5.344); beyond 1e-15 s
        // nothing counts.
        let digits = &bytes[start..end.min(start + 15)];
        let n = digits
            .iter()
            .fold(0u64, |n, &c| n * 10 + u64::from(c - b'0'));
        const POW10: [f64; 16] = [
            1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
        ];
        second += n as f64 / POW10[digits.len()];
        i = end;
    }
    let offset_min: i64 = match bytes.get(i) {
        Some(b'Z') | Some(b'z') if i + 1 == bytes.len() => 0,
        Some(&c @ (b'+' | b'-')) if i + 6 == bytes.len() && bytes[i + 3] == b':' => {
            let oh = num(i + 1..i + 3, "offset hours")?;
            let om = num(i + 4..i + 6, "offset minutes")?;
            if oh > 23 || om > 59 {
                return Err(fail("offset out of range"));
            }
            let m = oh * 60 + om;
            if c == b'+' {
                m
            } else {
                -m
            }
        }
        None => return Err(fail("missing time zone: append Z for UTC")),
        _ => return Err(fail("unexpected characters after the time")),
    };
    if hour > 23 || minute > 59 {
        return Err(fail("field out of range"));
    }
    // Validate the local civil fields first (catches 2023-02-30 in any zone).
    let local = civil(year, month, day, hour as u8, minute as u8, second.min(59.0))?;
    if offset_min == 0 {
        return civil(year, month, day, hour as u8, minute as u8, second);
    }
    // Move whole days through the Julian day number, which counts across
    // the Julian–Gregorian switch without a gap; integral Julian days at 0h
    // (…​.5) are exact in f64 for every year accepted here.
    let mut minutes = hour * 60 + minute - offset_min;
    let day0 = super::calendar::julian_day(local.year, local.month, f64::from(local.day));
    let shift = minutes.div_euclid(1440);
    minutes = minutes.rem_euclid(1440);
    let (y, mo, d) = super::calendar::calendar_date(day0 + shift as f64);
    civil(
        i64::from(y),
        i64::from(mo),
        d as i64,
        (minutes / 60) as u8,
        (minutes % 60) as u8,
        second,
    )
}

/// The validated civil date and time; years limited to ±1 000 000.
fn civil(
    year: i64,
    month: i64,
    day: i64,
    hour: u8,
    minute: u8,
    second: f64,
) -> Result<UtcDateTime, Rfc3339Error> {
    if year.abs() > 1_000_000 {
        return Err(Rfc3339Error::Syntax("year out of range"));
    }
    if !(1..=12).contains(&month) || !(1..=31).contains(&day) {
        return Err(Rfc3339Error::Syntax("field out of range"));
    }
    UtcDateTime::new(year as i32, month as u8, day as u8, hour, minute, second)
        .map_err(Rfc3339Error::Date)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_utc_offsets_and_leap_seconds() {
        let t = parse_rfc3339("2024-04-08T18:42:00Z").unwrap();
        assert_eq!(
            (t.year, t.month, t.day, t.hour, t.minute),
            (2024, 4, 8, 18, 42)
        );
        let t = parse_rfc3339("2024-01-01T01:30:00.250+02:00").unwrap();
        assert_eq!(
            (t.year, t.month, t.day, t.hour, t.minute),
            (2023, 12, 31, 23, 30)
        );
        assert!((t.second - 0.25).abs() < 1e-12);
        let t = parse_rfc3339("2016-12-31T23:59:60.5Z").unwrap();
        assert_eq!(t.second, 60.5);
        let t = parse_rfc3339("2017-01-01T08:59:60+09:00").unwrap();
        assert_eq!(
            (t.year, t.month, t.day, t.hour, t.minute),
            (2016, 12, 31, 23, 59)
        );
        let t = parse_rfc3339("-2000-03-01T00:00:00Z").unwrap();
        assert_eq!(t.year, -2000);
    }

    #[test]
    fn rejects_malformed_times() {
        for bad in [
            "",
            "2024",
            "2024-04-08",
            "2024-04-08T18:42:00",
            "2024-04-08 18:42Z",
            "2024-13-01T00:00:00Z",
            "2023-02-29T00:00:00Z",
            "2024-04-08T24:00:00Z",
            "2024-04-08T18:42:60Z",
            "2024-04-08T18:42:00+25:00",
            "24-04-08T18:42:00Z",
            "2024-04-08T18:42:00.Z",
            "2024-04-08T18:42:00Zjunk",
            "yesterday",
        ] {
            assert!(parse_rfc3339(bad).is_err(), "{bad} accepted");
        }
    }

    #[test]
    fn julian_calendar_before_the_reform() {
        // Julian -1900 is a leap year (every fourth year), Gregorian not:
        // the date that `eclipses` prints must come back unchanged.
        let t = parse_rfc3339("-1900-02-29T13:03:17Z").unwrap();
        assert_eq!((t.year, t.month, t.day, t.hour), (-1900, 2, 29, 13));
        // Meeus Example 7.a / ch. 7: -4712 January 1.5 (Julian) = JD 0.0.
        let t = parse_rfc3339("-4712-01-01T12:00:00Z").unwrap();
        let jd = crate::time::julian_day(t.year, t.month, f64::from(t.day) + 0.5);
        assert_eq!(jd, 0.0);
        // Year 0 (1 BC) is a Julian leap year.
        assert!(parse_date_or_rfc3339("0000-02-29").is_ok());
        // 1582 October 4 (Julian) is followed by October 15 (Gregorian);
        // the ten days between do not exist.
        let t = parse_rfc3339("1582-10-15T01:00:00+02:00").unwrap();
        assert_eq!((t.year, t.month, t.day, t.hour), (1582, 10, 4, 23));
        let t = parse_rfc3339("1582-10-04T23:00:00-02:00").unwrap();
        assert_eq!((t.year, t.month, t.day, t.hour), (1582, 10, 15, 1));
        for missing in ["1582-10-05", "1582-10-10", "1582-10-14"] {
            assert!(parse_date_or_rfc3339(missing).is_err(), "{missing}");
        }
        // Offsets across a Julian leap day and across a year boundary.
        let t = parse_rfc3339("-0500-03-01T01:00:00+03:00").unwrap();
        assert_eq!((t.year, t.month, t.day, t.hour), (-500, 2, 29, 22));
        let t = parse_rfc3339("-0001-12-31T23:30:00-01:00").unwrap();
        assert_eq!((t.year, t.month, t.day, t.hour), (0, 1, 1, 0));
    }

    #[test]
    fn date_only_and_expanded_years() {
        let t = parse_date_or_rfc3339("-0500-01-01").unwrap();
        assert_eq!(
            (t.year, t.month, t.day, t.hour, t.second),
            (-500, 1, 1, 0, 0.0)
        );
        let t = parse_date_or_rfc3339("+10000-01-01").unwrap();
        assert_eq!((t.year, t.month, t.day), (10_000, 1, 1));
        let t = parse_date_or_rfc3339("+10000-12-31T23:59:59.5Z").unwrap();
        assert_eq!((t.year, t.month, t.day, t.second), (10_000, 12, 31, 59.5));
        let t = parse_date_or_rfc3339(" 2024-04-08 ").unwrap();
        assert_eq!((t.year, t.month, t.day), (2024, 4, 8));
        for bad in [
            "-500-01-01",
            "2024-04-8",
            "2024-04-08T",
            "+12345678-01-01",
            "-2000000-01-01",
            "2024-04",
            "--2024-04-08",
        ] {
            assert!(parse_date_or_rfc3339(bad).is_err(), "{bad} accepted");
        }
        // The strict parser wants a time, the date parser none.
        assert!(parse_rfc3339("-0500-01-01").is_err());
        assert!(parse_date("-0500-01-01T00:00:00Z").is_err());
        assert_eq!(
            parse_date("-0500-01-01"),
            parse_date_or_rfc3339("-0500-01-01")
        );
    }
}
