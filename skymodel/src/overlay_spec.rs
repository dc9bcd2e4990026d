//! The scene key `overlay`: constellation figures and labels drawn over the
//! developed 8-bit image (PNG) after the camera stage, never into the
//! radiance (EXR). Where they go is [`crate::overlay`]; the drawing is the
//! output stage's (`himmel_cpu::overlay`).

use serde::{Deserialize, Serialize};

use crate::scene_error::SceneError;
use crate::world_spec::range;

/// The chart overlay of a PNG (default: off).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OverlaySpec {
    /// The 88 constellations' stick figures as lines (default false).
    pub constellations: bool,
    /// Names: each constellation's at the centre of its figure, the named
    /// stars' down to `star_names_max_mag`, and the rendered planets'
    /// (default false).
    pub labels: bool,
    /// Faintest V magnitude of a star that is named, in [−2, 6.5]
    /// (default 1.5: the 22 first-magnitude stars).
    pub star_names_max_mag: f64,
    /// Colour of lines and labels, display sRGB components in [0, 1]
    /// (default [0.55, 0.7, 1.0], a light blue).
    pub colour: [f64; 3],
    /// Line width, pixels, in [0.25, 16] (default 1).
    pub line_width: f64,
    /// Label size (the font's em), pixels, in [4, 256] (default 13).
    pub label_px: f64,
}

impl Default for OverlaySpec {
    fn default() -> Self {
        OverlaySpec {
            constellations: false,
            labels: false,
            star_names_max_mag: 1.5,
            colour: [0.55, 0.7, 1.0],
            line_width: 1.0,
            label_px: 13.0,
        }
    }
}

/// The parts of the overlay that `--overlay` names.
pub const OVERLAY_PARTS: [&str; 2] = ["constellations", "labels"];

impl OverlaySpec {
    /// Whether anything is drawn.
    pub fn is_on(&self) -> bool {
        self.constellations || self.labels
    }

    /// Sets the parts from a comma list of [`OVERLAY_PARTS`] (`none` or an
    /// empty list: nothing); the other settings are kept.
    pub fn set_parts(&mut self, list: &str) -> Result<(), String> {
        let (mut c, mut l) = (false, false);
        for part in list.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            match part.to_ascii_lowercase().as_str() {
                "constellations" => c = true,
                "labels" => l = true,
                "none" => {}
                other => {
                    return Err(format!(
                    "unknown part '{}'; expected a comma list of constellations, labels (or none)",
                    himmel_astro::error::printable(other)
                ))
                }
            }
        }
        (self.constellations, self.labels) = (c, l);
        Ok(())
    }

    /// Checks every number against its range, naming the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        range(
            "overlay.star_names_max_mag",
            self.star_names_max_mag,
            -2.0,
            6.5,
        )?;
        for (k, c) in self.colour.iter().enumerate() {
            range(&format!("overlay.colour[{k}]"), *c, 0.0, 1.0)?;
        }
        range("overlay.line_width", self.line_width, 0.25, 16.0)?;
        range("overlay.label_px", self.label_px, 4.0, 256.0)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_parse_and_ranges_name_their_fields() {
        let mut o = OverlaySpec::default();
        assert!(!o.is_on());
        o.set_parts("constellations, Labels").unwrap();
        assert!(o.constellations && o.labels);
        o.set_parts("none").unwrap();
        assert!(!o.is_on());
        assert!(o.set_parts("grid").unwrap_err().contains("'grid'"));
        o.validate().unwrap();
        o.colour[2] = 1.5;
        assert_eq!(o.validate().unwrap_err().field, "overlay.colour[2]");
        o.colour[2] = 1.0;
        o.line_width = 0.0;
        assert_eq!(o.validate().unwrap_err().field, "overlay.line_width");
    }
}
