//! Typed errors of the catalogue crate: every parser names the line (or the
//! byte offset of a binary table) and the field that is wrong.

use himmel_astro::error::printable;

use std::fmt;

/// What went wrong while reading catalogue data.
#[derive(Debug, Clone, PartialEq)]
pub enum CatalogError {
    /// A text line is shorter than the columns it must hold.
    TruncatedLine {
        /// Which source (e.g. `"hip2.dat"`).
        source: &'static str,
        /// 1-based line number.
        line: usize,
        /// Characters found.
        len: usize,
        /// Characters needed.
        needed: usize,
    },
    /// A field does not parse, is not finite or lies outside its range.
    BadField {
        /// Which source.
        source: &'static str,
        /// 1-based line number.
        line: usize,
        /// The field's name (e.g. `"RArad"`).
        field: &'static str,
        /// The offending text.
        text: String,
        /// Why it was rejected.
        reason: &'static str,
    },
    /// JSON that does not parse or lacks a member.
    Json {
        /// Which source.
        source: &'static str,
        /// 1-based line number.
        line: usize,
        /// The parser's message.
        message: String,
    },
    /// An embedded binary table is malformed.
    Binary {
        /// Which table (e.g. `"stars.bin"`).
        table: &'static str,
        /// Byte offset.
        offset: usize,
        /// Why.
        reason: &'static str,
    },
    /// A value given to a library function is out of range.
    OutOfRange {
        /// The quantity.
        what: &'static str,
        /// The value given.
        value: f64,
        /// Smallest accepted value.
        min: f64,
        /// Largest accepted value.
        max: f64,
    },
}

impl CatalogError {
    /// `Ok(value)` when finite and in `[min, max]`, else [`CatalogError::OutOfRange`].
    pub fn check_range(what: &'static str, value: f64, min: f64, max: f64) -> Result<f64, Self> {
        if value.is_finite() && value >= min && value <= max {
            Ok(value)
        } else {
            Err(CatalogError::OutOfRange {
                what,
                value,
                min,
                max,
            })
        }
    }
}

impl fmt::Display for CatalogError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CatalogError::TruncatedLine {
                source,
                line,
                len,
                needed,
            } => write!(
                f,
                "{source} line {line}: truncated ({len} characters, at least {needed} needed)"
            ),
            CatalogError::BadField {
                source,
                line,
                field,
                text,
                reason,
            } => write!(
                f,
                "{source} line {line}: field {field} '{}': {reason}",
                printable(text)
            ),
            CatalogError::Json {
                source,
                line,
                message,
            } => write!(f, "{source} line {line}: {message}"),
            CatalogError::Binary {
                table,
                offset,
                reason,
            } => write!(f, "{table} at byte {offset}: {reason}"),
            CatalogError::OutOfRange {
                what,
                value,
                min,
                max,
            } => write!(f, "{what} {value} is outside [{min}, {max}]"),
        }
    }
}

impl std::error::Error for CatalogError {}
