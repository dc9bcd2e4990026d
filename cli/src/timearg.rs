//! Parsing of the `--time` argument: RFC 3339 civil UTC (offsets converted),
//! leap seconds included, or `now`.

use himmel_astro::UtcDateTime;

/// Parses an RFC 3339 timestamp ([`himmel_astro::time::parse_rfc3339`]) with
/// an error message that shows the input and the expected form.
pub fn parse_rfc3339(s: &str) -> Result<UtcDateTime, String> {
    himmel_astro::time::parse_rfc3339(s).map_err(|e| {
        format!("'{s}' is not an RFC 3339 time ({e}); expected e.g. 2024-04-08T18:42:00Z or now")
    })
}

/// The current civil UTC time from the system clock.
pub fn now() -> Result<UtcDateTime, String> {
    UtcDateTime::try_from(chrono::Utc::now()).map_err(|e| format!("system clock: {e}"))
}

/// Formats civil UTC as RFC 3339 with milliseconds and a `Z` suffix
/// (truncated, so that 59.9996 s never turns into second 60).
pub fn format_utc(t: &UtcDateTime) -> String {
    let ms = (t.second * 1000.0).floor() as i64;
    let year = if (0..=9999).contains(&t.year) {
        format!("{:04}", t.year)
    } else {
        format!("{:+05}", t.year)
    };
    format!(
        "{year}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z",
        t.month,
        t.day,
        t.hour,
        t.minute,
        ms / 1000,
        ms % 1000
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn leap_second_round_trip() {
        let t = parse_rfc3339("2017-01-01T08:59:60+09:00").unwrap();
        assert_eq!(format_utc(&t), "2016-12-31T23:59:60.000Z");
        assert!(parse_rfc3339("yesterday")
            .unwrap_err()
            .contains("'yesterday'"));
    }
}
