//! Screen-space reflections of a 3D world (`lighting.ssr`, issue 16): the
//! scene keys of the wgpu backend's `ssr` pass (`passes/lighting/ssr.rs`).
//!
//! For every pixel whose surface has a roughness ≤ `max_roughness`, the
//! pass traces `samples` reflected rays (GGX importance samples of the
//! surface's lobe, α = roughness²) through a hierarchical min-depth chain
//! of the G-buffer (Hi-Z), and where a ray meets a surface on screen it
//! reads that surface's lit radiance (the previous frame's, reprojected,
//! when `history` and a previous frame exist; else the current frame's
//! before reflections). The reflection *replaces* the sky's prefiltered
//! specular term for the share of rays that hit, weighted by the same
//! split-sum factor (F0·A + B); rays that leave the screen, pass behind a
//! surface or meet nothing keep the prefiltered sky.

use serde::{Deserialize, Serialize};

use crate::scene_error::{check_ranges, SceneError};

/// Screen-space reflections (`lighting.ssr`; runs with `--effects ssr`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SsrSettings {
    /// Surfaces rougher than this get no screen-space reflection (only the
    /// prefiltered sky), in [0, 1] (default 0.5). When no material of the
    /// world (the ground plane, Lambertian, excluded) is this smooth, the
    /// pass does not run.
    pub max_roughness: f64,
    /// Reflected rays per pixel (GGX importance samples, rotated per pixel
    /// by interleaved gradient noise), in [1, 64] (default 8). A surface
    /// smoother than roughness 0.02 traces one mirror ray.
    pub samples: u32,
    /// Hi-Z traversal steps per ray, in [4, 512] (default 64).
    pub max_steps: u32,
    /// How far behind the surface a pixel shows, along the view axis, a ray
    /// still counts as hitting it, metres, in [0.001, 100] (default 0.5).
    pub thickness_m: f64,
    /// The share of the image's half width (height) next to each border
    /// over which reflections fade to the prefiltered sky, in [0, 0.5]
    /// (default 0.1).
    pub edge_fade: f64,
    /// Whether reflected rays read the previous frame's final image
    /// (reflections included), reprojected with its view-projection, where
    /// the hit point lies in it (default true); the first frame, and hits
    /// outside the previous frame, read the current frame before
    /// reflections.
    pub history: bool,
}

impl Default for SsrSettings {
    fn default() -> Self {
        SsrSettings {
            max_roughness: 0.5,
            samples: 8,
            max_steps: 64,
            thickness_m: 0.5,
            edge_fade: 0.1,
            history: true,
        }
    }
}

impl SsrSettings {
    /// Checks every value against its documented range, naming the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        check_ranges(&[
            ("lighting.ssr.max_roughness", self.max_roughness, 0.0, 1.0),
            ("lighting.ssr.samples", self.samples as f64, 1.0, 64.0),
            ("lighting.ssr.max_steps", self.max_steps as f64, 4.0, 512.0),
            ("lighting.ssr.thickness_m", self.thickness_m, 0.001, 100.0),
            ("lighting.ssr.edge_fade", self.edge_fade, 0.0, 0.5),
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_and_ranges() {
        let a = SsrSettings::default();
        assert!(a.validate().is_ok());
        crate::scene_error::assert_rejected(
            [
                (
                    SsrSettings {
                        max_roughness: 1.5,
                        ..a
                    },
                    "lighting.ssr.max_roughness",
                ),
                (SsrSettings { samples: 0, ..a }, "lighting.ssr.samples"),
                (SsrSettings { max_steps: 3, ..a }, "lighting.ssr.max_steps"),
                (
                    SsrSettings {
                        thickness_m: 0.0,
                        ..a
                    },
                    "lighting.ssr.thickness_m",
                ),
                (
                    SsrSettings {
                        edge_fade: f64::NAN,
                        ..a
                    },
                    "lighting.ssr.edge_fade",
                ),
            ],
            SsrSettings::validate,
        );
    }

    #[test]
    fn keys_parse() {
        let a: SsrSettings =
            serde_json::from_str(r#"{"max_roughness": 0.3, "samples": 8, "history": false}"#)
                .unwrap();
        assert_eq!((a.max_roughness, a.samples, a.history), (0.3, 8, false));
        assert_eq!(a.max_steps, 64);
        assert!(serde_json::from_str::<SsrSettings>(r#"{"steps": 1}"#).is_err());
    }

    #[test]
    fn the_world_template_shows_the_keys() {
        let t: serde_json::Value =
            serde_json::from_str(&crate::Scene::template_world_json()).unwrap();
        let s = &t["lighting"]["ssr"];
        assert_eq!(s["max_roughness"], 0.5);
        assert_eq!(s["samples"], 8);
        assert_eq!(s["history"], true);
    }
}
