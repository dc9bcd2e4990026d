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

/// A number for an error message: plain notation, or exponent notation
/// for very large or very small magnitudes (`1e300`, not 301 digits).
pub fn show(v: f64) -> String {
    let a = v.abs();
    if v.is_finite() && a != 0.0 && !(1e-4..1e15).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}
