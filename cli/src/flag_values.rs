//! Numeric flag values of the command line, checked with errors that
//! name the flag.

use crate::CliError;

/// Parses `X,Y,Z` (three finite numbers) for `flag`.
pub(crate) fn triple(flag: &str, s: &str) -> Result<[f64; 3], CliError> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let bad = || CliError::input(format!("{flag} '{s}': expected three numbers X,Y,Z"));
    if parts.len() != 3 {
        return Err(bad());
    }
    let mut v = [0.0; 3];
    for (o, p) in v.iter_mut().zip(&parts) {
        *o = p.parse::<f64>().map_err(|_| bad())?;
        if !o.is_finite() {
            return Err(bad());
        }
    }
    Ok(v)
}

/// `v` for `flag` when it is a finite number.
pub(crate) fn finite(flag: &str, v: f64) -> Result<f64, CliError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(CliError::input(format!(
            "{flag} {v} is not a finite number"
        )))
    }
}

/// `v` pixels for `flag`: at least one, within the image limit.
pub(crate) fn size(flag: &str, v: u64) -> Result<u32, CliError> {
    if v == 0 {
        return Err(CliError::input(format!(
            "{flag} 0: must be at least 1 pixel"
        )));
    }
    u32::try_from(v).map_err(|_| {
        CliError::input(format!(
            "{flag} {v}: image larger than the limit of 64 Mpx (W·H ≤ {})",
            himmel_skymodel::projection::MAX_PIXELS
        ))
    })
}
