//! The temporal filter of a 3D world (`lighting.temporal`, issue 16): the
//! scene keys of the wgpu backend's `temporal` pass
//! (`passes/lighting/temporal.rs`).
//!
//! Over a sequence of frames the world passes see the scene through a
//! camera jittered by a sub-pixel offset per frame (the Halton (2, 3)
//! sequence), and the noisy passes (AO, SSR, the shadows' disk rotation)
//! turn their per-pixel noise with the frame's index. The pass then blends
//! each world pixel with the previous frames' result, reprojected through
//! the G-buffer's velocity: the history is rejected where the surface it
//! held is not the one seen now (disocclusion: its distance from the
//! previous eye differs by more than `depth_tolerance`), and clipped to
//! the box about the mean of the pixel's 3 × 3 neighbourhood in YCoCg,
//! `variance_gamma` times the neighbourhood's standard deviation plus the
//! pixel's own over its past frames wide (what moved or changed its
//! lighting). A pixel's history counts its frames up to `max_frames` (a
//! clipped history fewer, the farther outside the box it lay); each frame
//! weighs 1 / that count, so a static view becomes the running mean of its
//! jittered frames (anti-aliasing, and AO/SSR noise averaged away).

use serde::{Deserialize, Serialize};

use crate::scene_error::{check_ranges, SceneError};

/// The temporal filter (`lighting.temporal`; runs with `--effects temporal`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TemporalSettings {
    /// Whether the world passes' camera moves by a sub-pixel offset per
    /// frame (Halton 2, 3 over 64 frames; default true). Without it the
    /// filter still averages the passes' noise, but does not anti-alias.
    pub jitter: bool,
    /// The most frames a pixel's history holds, in [1, 256] (default 32):
    /// frame n of a still pixel weighs 1 / min(n, max_frames). 1 turns the
    /// filter off (each frame as rendered, jittered).
    pub max_frames: u32,
    /// The half width of the clip box about the neighbourhood's mean, in
    /// standard deviations (the neighbourhood's in this frame plus the
    /// pixel's over its frames), in [0.25, 8] (default 1.25): smaller rejects
    /// ghosts sooner, larger keeps more history (less noise).
    pub variance_gamma: f64,
    /// The largest relative difference between a surface's distance from
    /// the previous eye and the previous frame's distance where it is
    /// reprojected for the history to count as the same surface, in
    /// [0.001, 1] (default 0.02).
    pub depth_tolerance: f64,
}

impl Default for TemporalSettings {
    fn default() -> Self {
        TemporalSettings {
            jitter: true,
            max_frames: 32,
            variance_gamma: 1.25,
            depth_tolerance: 0.02,
        }
    }
}

impl TemporalSettings {
    /// Checks every value against its documented range, naming the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        check_ranges(&[
            (
                "lighting.temporal.max_frames",
                self.max_frames as f64,
                1.0,
                256.0,
            ),
            (
                "lighting.temporal.variance_gamma",
                self.variance_gamma,
                0.25,
                8.0,
            ),
            (
                "lighting.temporal.depth_tolerance",
                self.depth_tolerance,
                0.001,
                1.0,
            ),
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_and_ranges() {
        let a = TemporalSettings::default();
        assert!(a.validate().is_ok());
        crate::scene_error::assert_rejected(
            [
                (
                    TemporalSettings { max_frames: 0, ..a },
                    "lighting.temporal.max_frames",
                ),
                (
                    TemporalSettings {
                        max_frames: 257,
                        ..a
                    },
                    "lighting.temporal.max_frames",
                ),
                (
                    TemporalSettings {
                        variance_gamma: f64::NAN,
                        ..a
                    },
                    "lighting.temporal.variance_gamma",
                ),
                (
                    TemporalSettings {
                        depth_tolerance: 0.0,
                        ..a
                    },
                    "lighting.temporal.depth_tolerance",
                ),
            ],
            TemporalSettings::validate,
        );
    }

    #[test]
    fn keys_parse() {
        let a: TemporalSettings =
            serde_json::from_str(r#"{"jitter": false, "max_frames": 8}"#).unwrap();
        assert_eq!((a.jitter, a.max_frames), (false, 8));
        assert_eq!(a.variance_gamma, 1.25);
        assert!(serde_json::from_str::<TemporalSettings>(r#"{"blend": 0.9}"#).is_err());
    }

    #[test]
    fn the_world_template_shows_the_keys() {
        let t: serde_json::Value =
            serde_json::from_str(&crate::Scene::template_world_json()).unwrap();
        let s = &t["lighting"]["temporal"];
        assert_eq!(s["jitter"], true);
        assert_eq!(s["max_frames"], 32);
        assert_eq!(s["depth_tolerance"], 0.02);
    }
}
