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
/// Years outside 0000–9999 may be written with a sign (`-2000-03-01T00:00:00Z`).
pub fn parse_rfc3339(s: &str) -> Result<UtcDateTime, Rfc3339Error> {
    let fail = Rfc3339Error::Syntax;
    let b = s.trim();
    // Optional sign for expanded years.
    let (sign, body) = match b.as_bytes().first() {
        Some(b'-') => (-1i64, &b[1..]),
        Some(b'+') => (1, &b[1..]),
        _ => (1, b),
    };
    let dash = body.find('-').ok_or_else(|| fail("no date"))?;
    let year_digits = &body[..dash];
    if year_digits.len() < 4 || !year_digits.bytes().all(|c| c.is_ascii_digit()) {
        return Err(fail("year must have at least four digits"));
    }
    let year: i64 = year_digits.parse().map_err(|_| fail("bad year"))?;
    let year = sign * year;
    let rest = &body[dash + 1..];
    let bytes = rest.as_bytes();
    // MM-DDTHH:MM:SS
    if bytes.len() < 14 {
        return Err(fail("too short"));
    }
    let num = |r: core::ops::Range<usize>, what: &'static str| -> Result<i64, Rfc3339Error> {
        let t = rest.get(r).ok_or_else(|| fail(what))?;
        if t.bytes().all(|c| c.is_ascii_digit()) {
            t.parse::<i64>().map_err(|_| fail(what))
        } else {
            Err(fail(what))
        }
    };
    let month = num(0..2, "month")?;
    if bytes[2] != b'-' {
        return Err(fail("date must be YYYY-MM-DD"));
    }
    let day = num(3..5, "day")?;
    if !matches!(bytes[5], b'T' | b't' | b' ') {
        return Err(fail("missing 'T' between date and time"));
    }
    let hour = num(6..8, "hour")?;
    if bytes[8] != b':' || bytes[11] != b':' {
        return Err(fail("time must be HH:MM:SS"));
    }
    let minute = num(9..11, "minute")?;
    let mut i = 14;
    let whole_sec = num(12..14, "second")?;
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
        // Digit by digit (no allocation); beyond 1e-15 s nothing counts.
        let mut scale = 0.1;
        for &c in &bytes[start..end.min(start + 15)] {
            second += f64::from(c - b'0') * scale;
            scale *= 0.1;
        }
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
    if !(1..=12).contains(&month) || !(1..=31).contains(&day) || hour > 23 || minute > 59 {
        return Err(fail("field out of range"));
    }
    if year.abs() > 1_000_000 {
        return Err(fail("year out of range"));
    }
    // Validate the local civil fields first (catches 2023-02-30 in any zone).
    let local = UtcDateTime::new(
        year as i32,
        month as u8,
        day as u8,
        hour as u8,
        minute as u8,
        second.min(59.0),
    )
    .map_err(Rfc3339Error::Date)?;
    let (mut y, mut mo, mut d) = (local.year as i64, month, day);
    let mut minutes = hour * 60 + minute - offset_min;
    // Move whole days; the days-from-civil algorithm keeps this exact.
    let mut days = days_from_civil(y, mo, d);
    days += minutes.div_euclid(1440);
    minutes = minutes.rem_euclid(1440);
    (y, mo, d) = civil_from_days(days);
    if !(i32::MIN as i64..=i32::MAX as i64).contains(&y) {
        return Err(fail("year out of range"));
    }
    UtcDateTime::new(
        y as i32,
        mo as u8,
        d as u8,
        (minutes / 60) as u8,
        (minutes % 60) as u8,
        second,
    )
    .map_err(Rfc3339Error::Date)
}

/// Days since 1970-01-01 in the proleptic Gregorian calendar (H. Hinnant's
/// civil-date algorithm).
fn days_from_civil(y: i64, m: i64, d: i64) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// Inverse of [`days_from_civil`].
fn civil_from_days(z: i64) -> (i64, i64, i64) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let y = yoe + era * 400;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    (if m <= 2 { y + 1 } else { y }, m, d)
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
    fn civil_days_round_trip() {
        for z in [-1_000_000, -719_468, -1, 0, 1, 10_957, 2_932_896] {
            let (y, m, d) = civil_from_days(z);
            assert_eq!(days_from_civil(y, m, d), z);
        }
        assert_eq!(days_from_civil(2000, 1, 1), 10_957);
    }
}
