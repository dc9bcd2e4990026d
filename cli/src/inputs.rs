//! Validation of the observer's numbers and parsing of `himmel ephemeris
//! --batch` lines (spec/cli.md): CSV `time,lat,lon,elevation_m`, one
//! observation per line; errors name the flag or the line and column.

pub use himmel_astro::error::printable;

use himmel_astro::{Observer, UtcDateTime};

use crate::timearg::parse_date_or_time;

/// Checks a finite value against a range, naming the flag in the error.
pub fn check(flag: &str, v: f64, min: f64, max: f64) -> Result<f64, String> {
    if !v.is_finite() {
        Err(format!(
            "{flag} {v} is not a finite number; expected a value in [{min}, {max}]"
        ))
    } else if v < min || v > max {
        Err(format!("{flag} {v} is outside [{min}, {max}]"))
    } else {
        Ok(v)
    }
}

/// The observer of `--lat` (degrees in [−90, 90]), `--lon` (east, degrees;
/// 360-wrapped input accepted) and `--elevation` (metres).
pub fn observer(lat: f64, lon: f64, elevation: f64) -> Result<Observer, String> {
    let lat = check("--lat", lat, -90.0, 90.0)?;
    let lon = check("--lon", lon, -360.0, 360.0)?;
    let elevation = check("--elevation", elevation, -12_000.0, 100_000.0)?;
    Observer::new(lat, lon, elevation).map_err(|e| e.to_string())
}

/// The header line that a batch file may start with.
pub const BATCH_HEADER: &str = "time,lat,lon,elevation_m";

/// One parsed `--batch` line: the instant and the validated observer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BatchLine {
    /// The instant (civil UTC).
    pub utc: UtcDateTime,
    /// The observer.
    pub observer: Observer,
}

/// Parses line `n` (1-based) of a `--batch` file: `None` for a blank line or
/// the header on line 1, else the observation, or an error starting with
/// `--batch: line n:` that names the column.
pub fn parse_batch_line(n: usize, line: &str) -> Result<Option<BatchLine>, String> {
    let line = line.trim();
    if line.is_empty() || (n == 1 && line.replace(' ', "") == BATCH_HEADER) {
        return Ok(None);
    }
    let cols: Vec<&str> = line.split(',').map(str::trim).collect();
    if cols.len() != 4 {
        return Err(format!(
            "--batch: line {n}: expected 4 columns time,lat,lon,elevation_m, found {}",
            cols.len()
        ));
    }
    let num = |s: &str, what: &str| -> Result<f64, String> {
        s.parse::<f64>().map_err(|_| {
            format!(
                "--batch: line {n}: {what} '{}' is not a number",
                printable(s)
            )
        })
    };
    let (lat, lon, elevation) = (
        num(cols[1], "lat")?,
        num(cols[2], "lon")?,
        num(cols[3], "elevation_m")?,
    );
    let line_error = |e: String| format!("--batch: line {n}: {}", e.trim_start_matches("--"));
    let utc = parse_date_or_time("--time", cols[0], true).map_err(line_error)?;
    let observer = observer(lat, lon, elevation).map_err(line_error)?;
    Ok(Some(BatchLine { utc, observer }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batch_lines() {
        assert_eq!(
            parse_batch_line(1, " time, lat,lon ,elevation_m "),
            Ok(None)
        );
        assert_eq!(parse_batch_line(3, "   "), Ok(None));
        let b = parse_batch_line(2, "-1900-02-29T13:03:17Z, 52.5, 13.4, 34")
            .unwrap()
            .unwrap();
        assert_eq!((b.utc.year, b.utc.month, b.utc.day), (-1900, 2, 29));
        let e = parse_batch_line(2, "time,lat,lon,elevation_m").unwrap_err();
        assert_eq!(e, "--batch: line 2: lat 'lat' is not a number");
        let e = parse_batch_line(2, "yesterday,1,2,3").unwrap_err();
        assert!(e.starts_with("--batch: line 2: time: 'yesterday'"), "{e}");
        let e = parse_batch_line(7, "2024-01-01,91,0,0").unwrap_err();
        assert_eq!(e, "--batch: line 7: lat 91 is outside [-90, 90]");
        let e = parse_batch_line(4, "2024-01-01,1,x,0").unwrap_err();
        assert_eq!(e, "--batch: line 4: lon 'x' is not a number");
        let e = parse_batch_line(5, "2024-01-01,1,2").unwrap_err();
        assert!(e.ends_with("found 3"), "{e}");
        let e = parse_batch_line(2, "2024-01-01\r\u{1b}[2J,1,2,3").unwrap_err();
        assert!(e.contains("'2024-01-01\\r\\u{1b}[2J'"), "{e}");
    }
}
