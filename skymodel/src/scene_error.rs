//! The error of an invalid scene, naming the field (its own module so
//! that the scene's parts can report it without importing the scene).

use himmel_astro::error::printable;

/// An invalid scene, naming the field.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// The field or flag-like path (`observer.lat_deg`, `camera.fov_deg`, …).
    pub field: String,
    /// What is wrong and what is accepted.
    pub message: String,
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.field, self.message)
    }
}

impl std::error::Error for SceneError {}

impl SceneError {
    /// An error of `field`; control characters that came from the input
    /// (a key or string with a newline) are escaped, so that the message
    /// stays one printable line.
    pub fn new(field: &str, message: impl Into<String>) -> Self {
        SceneError {
            field: printable(field),
            message: printable(&message.into()),
        }
    }
}

/// A finite `v` in [lo, hi], or an error naming `field` and the range.
pub(crate) fn check_range(field: &str, v: f64, lo: f64, hi: f64) -> Result<(), SceneError> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(SceneError::new(
            field,
            format!(
                "{} is outside [{}, {}]",
                crate::units::show(v),
                crate::units::show(lo),
                crate::units::show(hi)
            ),
        ))
    }
}

/// [`check_range`] over a table of (field, value, lo, hi), in order: the
/// first value outside its range is the error.
pub(crate) fn check_ranges(table: &[(&str, f64, f64, f64)]) -> Result<(), SceneError> {
    table
        .iter()
        .try_for_each(|&(field, v, lo, hi)| check_range(field, v, lo, hi))
}

/// Asserts that `validate` rejects each settings value of `cases`, naming
/// its field (the `*_spec` modules' range tests).
#[cfg(test)]
pub(crate) fn assert_rejected<S>(
    cases: impl IntoIterator<Item = (S, &'static str)>,
    validate: impl Fn(&S) -> Result<(), SceneError>,
) {
    for (bad, field) in cases {
        match validate(&bad) {
            Ok(()) => panic!("{field}: accepted"),
            Err(e) => assert_eq!(e.field, field),
        }
    }
}
