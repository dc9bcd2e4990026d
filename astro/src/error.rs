//! Typed errors of the astronomy crate. Nothing in this crate panics on user
//! input: every fallible public function returns [`AstroError`].

use core::fmt;

/// What went wrong, naming the offending quantity and its accepted range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AstroError {
    /// A numeric input lies outside its accepted range (or is not finite).
    OutOfRange {
        /// The quantity, e.g. `"latitude"`.
        what: &'static str,
        /// The value given.
        value: f64,
        /// Smallest accepted value.
        min: f64,
        /// Largest accepted value.
        max: f64,
    },
    /// A calendar date or clock time that does not exist (e.g. February 30,
    /// or second 60 on a day without a leap second).
    InvalidDate {
        /// Which field is wrong: `"month"`, `"day"`, `"second"`, …
        what: &'static str,
        /// Why.
        reason: &'static str,
    },
    /// The body is not available from this ephemeris (e.g. a [`crate::Manual`]
    /// provider that was given no position for it).
    BodyUnavailable {
        /// The body's lower-case name.
        body: &'static str,
    },
}

impl AstroError {
    /// Shorthand for a range check: `Ok(value)` when finite and within
    /// `[min, max]`, else [`AstroError::OutOfRange`].
    pub fn check_range(what: &'static str, value: f64, min: f64, max: f64) -> Result<f64, Self> {
        if value.is_finite() && value >= min && value <= max {
            Ok(value)
        } else {
            Err(AstroError::OutOfRange {
                what,
                value,
                min,
                max,
            })
        }
    }
}

impl fmt::Display for AstroError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AstroError::OutOfRange {
                what,
                value,
                min,
                max,
            } => write!(f, "{what} {value} is outside [{min}, {max}]"),
            AstroError::InvalidDate { what, reason } => write!(f, "invalid {what}: {reason}"),
            AstroError::BodyUnavailable { body } => {
                write!(f, "no position available for {body}")
            }
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for AstroError {}

/// `s` with control characters escaped (`\n`, `\u{1b}`), for text taken
/// from an input and echoed in a one-line error (every crate's errors and
/// the command line use this one).
#[cfg(feature = "std")]
pub fn printable(s: &str) -> std::string::String {
    s.chars()
        .flat_map(|c| {
            let escaped = c.is_control().then(|| c.escape_default());
            let plain = (!c.is_control()).then_some(c);
            escaped.into_iter().flatten().chain(plain)
        })
        .collect()
}
