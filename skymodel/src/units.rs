//! Unit-carrying type aliases (names say the unit; values are plain floats).

pub use himmel_astro::units::{Degrees, Km, Radians};

/// Nanometres.
pub type Nanometres = f64;
/// Luminance, cd/m².
pub type CandelaPerM2 = f32;
/// Illuminance, lux (lm/m²).
pub type Lux = f64;
/// Steradians.
pub type Steradians = f64;
/// Extinction or scattering coefficient, km⁻¹.
pub type PerKm = f32;
