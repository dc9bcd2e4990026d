//! Ambient occlusion of a 3D world's sky light (`lighting.ao`, issue 16):
//! the scene keys of the wgpu backend's `ao` pass (`passes/lighting/ao.rs`).
//!
//! The pass estimates, per pixel of the G-buffer, the cosine-weighted
//! fraction of the hemisphere above the surface that no geometry closer than
//! `radius_m` blocks — (1/π) ∫ V_R(ω) (n·ω) dω — and the bent normal (the
//! mean unblocked direction). It multiplies only the sky's diffuse light,
//! never the Sun's or the Moon's.

use serde::{Deserialize, Serialize};

use crate::scene_error::{check_range, SceneError};

/// How ambient occlusion is estimated (`lighting.ao.method`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AoMethod {
    /// Screen-space AO with a hemisphere kernel (Mittring 2007, the
    /// normal-oriented variant): `samples` points in the hemisphere of
    /// radius `radius_m` about the normal, cosine-distributed, the kernel
    /// rotated per pixel by interleaved gradient noise; a point counts as
    /// blocked when the surface the G-buffer shows there lies in front of
    /// it (within the radius). Then the depth-aware blur.
    Ssao,
    /// Ground-truth AO (Jimenez et al. 2016, as in XeGTAO): `slices`
    /// screen-space slices through the view vector per pixel, in each the
    /// two horizons found by `steps` samples per side within the radius,
    /// and the exact cosine-weighted visibility between them; the slices'
    /// angles interleaved over 4 × 4 pixels. Then the depth-aware blur.
    Gtao,
    /// Horizon-based AO (Bavoil, Sainz & Dimitrov 2008): the same slices
    /// and steps as `gtao`, but the published estimator — along each
    /// screen direction the horizon rises from the surface's tangent, and
    /// each rise in the sine of its elevation above the plane normal to
    /// the view vector is added, attenuated by 1 − r²/R². Not cosine
    /// weighted about the normal, so it differs from `gtao` and the
    /// reference on tilted surfaces. Then the depth-aware blur.
    Hbao,
}

/// What S3HO weights the blocked part of a pixel's cosine-weighted
/// visibility with (`lighting.ao.sh_sky`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShSky {
    /// The sky's radiance itself (the default): along each slice's
    /// blocked arcs the pass reads the frame's sky radiance map (the
    /// environment's narrowest prefiltered level) and integrates the
    /// light those directions would have sent, cosine-weighted —
    /// directional occlusion, which follows the low Sun's aureole and
    /// reduces exactly to scalar AO under a uniform sky.
    Radiance,
    /// The order-2 spherical-harmonic projection (the seed's S3HO): the
    /// blocked visibility's coefficients B_lm, weighted in the lighting
    /// pass with the sky radiance's own nine L_lm. Smooth, but it spreads
    /// a low Sun's aureole over the whole side of the sky.
    Sh2,
}

/// Ambient occlusion (`lighting.ao`; runs with `--effects ao`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AoSettings {
    /// The method (default `gtao`).
    pub method: AoMethod,
    /// World-space radius, metres, in [0.01, 100]: geometry farther than
    /// this does not occlude. Absent (the default): a twentieth of the
    /// diagonal of the world's bounding box, within [0.1, 5] m
    /// ([`AoSettings::radius_for`]; `null` in the template).
    pub radius_m: Option<f64>,
    /// `gtao`, `hbao`: slices per pixel, in [1, 16] (default 4; `hbao`
    /// walks both sides of each, 2 × slices directions).
    pub slices: u32,
    /// `gtao`, `hbao`: horizon samples per side of a slice, in [1, 64]
    /// (default 12).
    pub steps: u32,
    /// `ssao`: kernel samples per pixel, in [1, 256] (default 32).
    pub samples: u32,
    /// Half side of the depth-aware (bilateral) blur, pixels, in [0, 4]
    /// (default 2: a 5 × 5 window, covering the 4 × 4 interleaving); the
    /// bounce's blur too.
    pub blur_px: u32,
    /// Near-field indirect light (the `bounce` pass, SSDO-style): one
    /// diffuse bounce of the lit image from the on-screen surfaces within
    /// `bounce_radius_m`. Default false: it costs about as much as the AO
    /// itself and sees only what the camera sees.
    pub bounce: bool,
    /// Bounce: cosine-distributed directions per pixel, in [1, 256]
    /// (default 16; the blur, `blur_px`, gathers its neighbours').
    pub bounce_samples: u32,
    /// Bounce: screen-space steps along each direction, in [1, 64]
    /// (default 12).
    pub bounce_steps: u32,
    /// Bounce: how far a direction is followed, metres, in [0.01, 1000].
    /// Absent (the default): a fifth of the world's bounding-box diagonal,
    /// within [0.5, 20] m ([`AoSettings::bounce_radius_for`]).
    pub bounce_radius_m: Option<f64>,
    /// S3HO (`gtao` only): the pass also weights the blocked part of each
    /// pixel's cosine-weighted visibility, (1 − V(ω)) max(0, n·ω), with the
    /// sky's radiance — by default ([`ShSky::Radiance`]) the radiance itself
    /// along gtao's blocked arcs, or ([`ShSky::Sh2`]) through spherical
    /// harmonics (l ≤ 2, world frame: B_lm, then Σ L_lm B_lm with the sky's
    /// own radiance coefficients L_lm) — and the lighting pass takes that
    /// light from the open sky's diffuse light: the sky is shadowed
    /// directionally (a blocker in front of the bright side takes more of
    /// the light), where scalar AO takes the same fraction of every side.
    /// Used only with `lighting.sky.occlusion` `ao`. Default false.
    pub sh: bool,
    /// S3HO's weighting of the blocked visibility ([`ShSky`]): `radiance`
    /// (default) or `sh2`. Only with `sh`.
    pub sh_sky: ShSky,
    /// `gtao`'s visibility bitmask (Therrien, Levesque & Gilet 2023):
    /// metres, in [0.01, 100], that each surface the G-buffer shows is
    /// taken to be thick. A slice's half-disk is cut into 32 sectors and a
    /// sample blocks those between its front and its back (that point
    /// `thickness_m` farther along its view ray), so a thin pole or a
    /// railing occludes its own width rather than everything below its
    /// horizon. Absent (the default): infinitely thick, classic `gtao`.
    pub thickness_m: Option<f64>,
}

impl Default for AoSettings {
    fn default() -> Self {
        AoSettings {
            method: AoMethod::Gtao,
            radius_m: None,
            slices: 4,
            steps: 12,
            samples: 32,
            blur_px: 2,
            bounce: false,
            bounce_samples: 16,
            bounce_steps: 12,
            bounce_radius_m: None,
            sh: false,
            sh_sky: ShSky::Radiance,
            thickness_m: None,
        }
    }
}

impl AoSettings {
    /// The radius for a world whose bounding box has this diagonal
    /// (metres): `radius_m`, else diagonal / 20 within [0.1, 5] m.
    pub fn radius_for(&self, diagonal_m: f64) -> f64 {
        self.radius_m
            .unwrap_or_else(|| (diagonal_m / 20.0).clamp(0.1, 5.0))
    }

    /// The bounce's radius for a world whose bounding box has this
    /// diagonal (metres): `bounce_radius_m`, else diagonal / 5 within
    /// [0.5, 20] m.
    pub fn bounce_radius_for(&self, diagonal_m: f64) -> f64 {
        self.bounce_radius_m
            .unwrap_or_else(|| (diagonal_m / 5.0).clamp(0.5, 20.0))
    }

    /// Checks every value against its documented range, naming the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        if let Some(r) = self.radius_m {
            check_range("lighting.ao.radius_m", r, 0.01, 100.0)?;
        }
        if let Some(r) = self.bounce_radius_m {
            check_range("lighting.ao.bounce_radius_m", r, 0.01, 1000.0)?;
        }
        for (f, v, lo, hi) in [
            ("lighting.ao.slices", self.slices, 1, 16),
            ("lighting.ao.steps", self.steps, 1, 64),
            ("lighting.ao.samples", self.samples, 1, 256),
            ("lighting.ao.blur_px", self.blur_px, 0, 4),
            ("lighting.ao.bounce_samples", self.bounce_samples, 1, 256),
            ("lighting.ao.bounce_steps", self.bounce_steps, 1, 64),
        ] {
            check_range(f, v as f64, lo as f64, hi as f64)?;
        }
        if let Some(t) = self.thickness_m {
            check_range("lighting.ao.thickness_m", t, 0.01, 100.0)?;
            if self.method != AoMethod::Gtao {
                return Err(SceneError::new(
                    "lighting.ao.thickness_m",
                    "the visibility bitmask is gtao's: it needs method gtao",
                ));
            }
        }
        if self.sh && self.method != AoMethod::Gtao {
            return Err(SceneError::new(
                "lighting.ao.sh",
                "S3HO integrates gtao's horizons: it needs method gtao",
            ));
        }
        if self.sh_sky != ShSky::Radiance && !self.sh {
            return Err(SceneError::new(
                "lighting.ao.sh_sky",
                "it chooses S3HO's weighting: it needs lighting.ao.sh true",
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_and_ranges() {
        let a = AoSettings::default();
        assert!(a.validate().is_ok());
        assert_eq!(a.method, AoMethod::Gtao);
        assert_eq!(a.radius_for(40.0), 2.0);
        assert_eq!(a.radius_for(1.0), 0.1);
        assert_eq!(a.radius_for(1000.0), 5.0);
        let b = AoSettings {
            radius_m: Some(0.5),
            ..a
        };
        assert_eq!(b.radius_for(1000.0), 0.5);
        assert!(!a.bounce);
        assert_eq!(a.bounce_radius_for(40.0), 8.0);
        assert_eq!(a.bounce_radius_for(1.0), 0.5);
        assert_eq!(a.bounce_radius_for(1000.0), 20.0);
        for (bad, field) in [
            (
                AoSettings {
                    radius_m: Some(0.0),
                    ..a
                },
                "lighting.ao.radius_m",
            ),
            (AoSettings { slices: 0, ..a }, "lighting.ao.slices"),
            (AoSettings { steps: 65, ..a }, "lighting.ao.steps"),
            (AoSettings { samples: 0, ..a }, "lighting.ao.samples"),
            (AoSettings { blur_px: 5, ..a }, "lighting.ao.blur_px"),
            (
                AoSettings {
                    bounce_samples: 0,
                    ..a
                },
                "lighting.ao.bounce_samples",
            ),
            (
                AoSettings {
                    bounce_steps: 65,
                    ..a
                },
                "lighting.ao.bounce_steps",
            ),
            (
                AoSettings {
                    bounce_radius_m: Some(2000.0),
                    ..a
                },
                "lighting.ao.bounce_radius_m",
            ),
        ] {
            assert_eq!(bad.validate().unwrap_err().field, field);
        }
    }

    #[test]
    fn keys_parse() {
        let a: AoSettings =
            serde_json::from_str(r#"{"method": "ssao", "radius_m": 2, "samples": 16}"#).unwrap();
        assert_eq!(
            (a.method, a.radius_m, a.samples, a.slices),
            (AoMethod::Ssao, Some(2.0), 16, 4)
        );
        let b: AoSettings =
            serde_json::from_str(r#"{"bounce": true, "bounce_radius_m": 3}"#).unwrap();
        assert_eq!((b.bounce, b.bounce_radius_m), (true, Some(3.0)));
        let h: AoSettings = serde_json::from_str(r#"{"method": "hbao"}"#).unwrap();
        assert_eq!(h.method, AoMethod::Hbao);
        assert!(serde_json::from_str::<AoSettings>(r#"{"method": "vxao"}"#).is_err());
        let c: AoSettings = serde_json::from_str(r#"{"sh": true}"#).unwrap();
        assert!(c.sh && c.validate().is_ok());
        let d = AoSettings {
            method: AoMethod::Ssao,
            ..c
        };
        assert_eq!(d.validate().unwrap_err().field, "lighting.ao.sh");
        assert_eq!(c.sh_sky, ShSky::Radiance);
        let e: AoSettings = serde_json::from_str(r#"{"sh": true, "sh_sky": "sh2"}"#).unwrap();
        assert!(e.sh_sky == ShSky::Sh2 && e.validate().is_ok());
        let f = AoSettings { sh: false, ..e };
        assert_eq!(f.validate().unwrap_err().field, "lighting.ao.sh_sky");
        assert!(serde_json::from_str::<AoSettings>(r#"{"sh": true, "sh_sky": "sh3"}"#).is_err());
        let t: AoSettings = serde_json::from_str(r#"{"thickness_m": 0.5}"#).unwrap();
        assert!(t.thickness_m == Some(0.5) && t.validate().is_ok());
        for bad in [
            AoSettings {
                thickness_m: Some(0.0),
                ..t
            },
            AoSettings {
                method: AoMethod::Hbao,
                ..t
            },
        ] {
            assert_eq!(bad.validate().unwrap_err().field, "lighting.ao.thickness_m");
        }
        assert!(serde_json::from_str::<AoSettings>(r#"{"radius": 1}"#).is_err());
    }
}
