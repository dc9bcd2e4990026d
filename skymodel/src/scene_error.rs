//! The error of an invalid scene, naming the field (its own module so
//! that the scene's parts can report it without importing the scene).

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
    /// An error of `field`.
    pub fn new(field: &str, message: impl Into<String>) -> Self {
        SceneError {
            field: field.into(),
            message: message.into(),
        }
    }
}
