//! The scene keys of the cloud layers (`clouds.low`, `clouds.high`). The
//! model (density field, ray march, lighting) is [`crate::clouds`]; a
//! layer with `coverage` 0 (the default) is no layer, so a scene without
//! these keys has no clouds.

use serde::{Deserialize, Serialize};

use crate::scene_error::{check_range, SceneError};
use crate::units::show;

/// The kind of the low, volumetric layer: its vertical density profile
/// (after Schneider & Vos 2015's height gradients per cloud type).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LowCloudKind {
    /// Cumulus: dense from near the base up to about 60 % of the slab,
    /// thinning to the top (tall, billowy cells).
    Cumulus,
    /// Stratocumulus: a lower, flatter profile (dense in the lower half).
    Stratocumulus,
    /// Stratus: a thin sheet in the lowest fifth of the slab.
    Stratus,
}

impl LowCloudKind {
    /// The kind's name (scene key and `--clouds-type`).
    pub fn name(self) -> &'static str {
        match self {
            LowCloudKind::Cumulus => "cumulus",
            LowCloudKind::Stratocumulus => "stratocumulus",
            LowCloudKind::Stratus => "stratus",
        }
    }

    /// Parses a kind's name (case-insensitive).
    pub fn from_name(s: &str) -> Option<Self> {
        [
            LowCloudKind::Cumulus,
            LowCloudKind::Stratocumulus,
            LowCloudKind::Stratus,
        ]
        .into_iter()
        .find(|k| k.name().eq_ignore_ascii_case(s.trim()))
    }
}

/// How the low layer's light scattered more than once is approximated
/// (`clouds.low.scattering`; [`crate::clouds::MultipleScattering`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CloudScattering {
    /// The diffusion solution: half the diffuse light from the P1
    /// equations solved on a 3D grid over the layer once per light
    /// ([`crate::clouds::DiffusionGrid`]), half from the column along the
    /// light (two light marches per step; the default, within 15 % of a
    /// path tracer at Sun altitudes of 20° and 60°). The height-field
    /// tier takes the column alone.
    Diffusion,
    /// The diffusion solution of the column along the light alone (no
    /// grid; within about 21 % of a path tracer at a low Sun).
    Column,
    /// Wrenninge's octaves (one light march per step; cheaper, less exact).
    Octaves,
}

/// How the low layer is drawn (`clouds.low.tier`; [`crate::clouds::height_field`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LowCloudTier {
    /// The ray-marched volume (the default): the density field sampled
    /// along the view ray, a light march per step.
    Volumetric,
    /// The cheap tier after Dubé (2005): the field reduced once per frame
    /// to 2D maps of each column's cloud bottom, top and mean extinction,
    /// the view and light rays intersected with that height-field volume
    /// by a few probes.
    Heightfield,
}

/// The low, volumetric cloud layer (`clouds.low`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LowCloudSpec {
    /// Fraction of the sky the layer covers, in [0, 1] (default 0: no layer).
    pub coverage: f64,
    /// `cumulus` (default), `stratocumulus` or `stratus`.
    pub kind: LowCloudKind,
    /// Base altitude above the observer's ground, km, in [0.1, 10] (default 1.5).
    pub base_km: f64,
    /// Top altitude, km, in (base_km, 12] (default 3.0).
    pub top_km: f64,
    /// Extinction coefficient of the densest cloud, km⁻¹, in [0.1, 500]
    /// (default 40: a cumulus core, visibility about 100 m).
    pub extinction_per_km: f64,
    /// Horizontal size of the largest noise cells, km, in [0.2, 50] (default 3).
    pub scale_km: f64,
    /// Wind, m/s towards East and North, each in [−100, 100] (default [5, 2]):
    /// the field moves by wind × (scene time − 2000-01-01T12:00 TT).
    pub wind_m_s: [f64; 2],
    /// Seed of the noise, any u32 (default 0).
    pub seed: u32,
    /// View-ray march steps through the slab, in [4, 512] (default 64).
    pub steps: u32,
    /// Steps of the march towards the Sun or Moon (self-shadowing), in
    /// [1, 32] (default 6).
    pub light_steps: u32,
    /// Half-width of a square patch of cloud centred above the observer,
    /// km, in [0, 1000]; 0 (default) = the layer is unbounded. A patch
    /// isolates a cloud for references (`tools/cloud_reference.py`).
    pub extent_km: f64,
    /// `diffusion` (default) or `octaves`: the multiple-scattering model.
    pub scattering: CloudScattering,
    /// Amortised marching, in [1, 16] (default 1: every pixel marched). With
    /// N ≥ 2 the view ray is marched on a grid of every N-th pixel, a pixel
    /// between four grid pixels that agree is interpolated from them, and
    /// the others (cloud edges) are marched.
    pub march_stride: u32,
    /// Temporal reprojection over frame sequences (default true; both
    /// backends, with `march_stride` ≥ 2): a renderer that draws frame after
    /// frame marches a rotating quarter of the grid's coarse nodes and takes
    /// the others from the last frame, moved with the wind, where that
    /// still holds (`frame::CloudHistory`). false: every frame is marched
    /// for itself (`--stats` `cloud_history` null).
    pub reproject: bool,
    /// `volumetric` (default) or `heightfield`: the ray-marched volume or
    /// the cheap height-field tier.
    pub tier: LowCloudTier,
}

impl Default for LowCloudSpec {
    fn default() -> Self {
        LowCloudSpec {
            coverage: 0.0,
            kind: LowCloudKind::Cumulus,
            base_km: 1.5,
            top_km: 3.0,
            extinction_per_km: 40.0,
            scale_km: 3.0,
            wind_m_s: [5.0, 2.0],
            seed: 0,
            steps: 64,
            light_steps: 6,
            extent_km: 0.0,
            scattering: CloudScattering::Diffusion,
            march_stride: 1,
            reproject: true,
            tier: LowCloudTier::Volumetric,
        }
    }
}

/// The high, thin cloud layer (`clouds.high`): cirrus as a 2D sheet.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HighCloudSpec {
    /// Fraction of the sky the layer covers, in [0, 1] (default 0: no layer).
    pub coverage: f64,
    /// Altitude above the observer's ground, km, in [4, 15] (default 9).
    pub altitude_km: f64,
    /// Vertical optical depth of the densest cloud, in [0, 10] (default 0.6).
    pub optical_depth: f64,
    /// Size of the largest noise cells across the wind, km, in [0.5, 200]
    /// (default 12).
    pub scale_km: f64,
    /// Stretch of the cells along the wind (cirrus streaks), in [1, 20]
    /// (default 4).
    pub stretch: f64,
    /// Wind, m/s towards East and North, each in [−100, 100] (default [20, 5]).
    pub wind_m_s: [f64; 2],
    /// Seed of the noise, any u32 (default 1).
    pub seed: u32,
}

impl Default for HighCloudSpec {
    fn default() -> Self {
        HighCloudSpec {
            coverage: 0.0,
            altitude_km: 9.0,
            optical_depth: 0.6,
            scale_km: 12.0,
            stretch: 4.0,
            wind_m_s: [20.0, 5.0],
            seed: 1,
        }
    }
}

/// Both cloud layers (`clouds`).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CloudsSpec {
    /// The low, volumetric layer.
    pub low: LowCloudSpec,
    /// The high, thin layer.
    pub high: HighCloudSpec,
}

fn steps(field: &str, v: u32, lo: u32, hi: u32) -> Result<(), SceneError> {
    if (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(SceneError::new(
            field,
            format!("{v} is outside [{lo}, {hi}]"),
        ))
    }
}

impl CloudsSpec {
    /// Whether the low layer exists (coverage above 0).
    pub fn has_low(&self) -> bool {
        self.low.coverage > 0.0
    }

    /// Whether the high layer exists (coverage and optical depth above 0).
    pub fn has_high(&self) -> bool {
        self.high.coverage > 0.0 && self.high.optical_depth > 0.0
    }

    /// Checks every value against its documented range, naming the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        let (l, h) = (&self.low, &self.high);
        for (f, v, lo, hi) in [
            ("clouds.low.coverage", l.coverage, 0.0, 1.0),
            ("clouds.low.base_km", l.base_km, 0.1, 10.0),
            ("clouds.low.top_km", l.top_km, 0.1, 12.0),
            (
                "clouds.low.extinction_per_km",
                l.extinction_per_km,
                0.1,
                500.0,
            ),
            ("clouds.low.scale_km", l.scale_km, 0.2, 50.0),
            ("clouds.low.wind_m_s[0]", l.wind_m_s[0], -100.0, 100.0),
            ("clouds.low.wind_m_s[1]", l.wind_m_s[1], -100.0, 100.0),
            ("clouds.low.extent_km", l.extent_km, 0.0, 1000.0),
            ("clouds.high.coverage", h.coverage, 0.0, 1.0),
            ("clouds.high.altitude_km", h.altitude_km, 4.0, 15.0),
            ("clouds.high.optical_depth", h.optical_depth, 0.0, 10.0),
            ("clouds.high.scale_km", h.scale_km, 0.5, 200.0),
            ("clouds.high.stretch", h.stretch, 1.0, 20.0),
            ("clouds.high.wind_m_s[0]", h.wind_m_s[0], -100.0, 100.0),
            ("clouds.high.wind_m_s[1]", h.wind_m_s[1], -100.0, 100.0),
        ] {
            check_range(f, v, lo, hi)?;
        }
        if l.top_km <= l.base_km {
            return Err(SceneError::new(
                "clouds.low.top_km",
                format!(
                    "{} must be above clouds.low.base_km ({})",
                    show(l.top_km),
                    show(l.base_km)
                ),
            ));
        }
        steps("clouds.low.steps", l.steps, 4, 512)?;
        steps("clouds.low.light_steps", l.light_steps, 1, 32)?;
        steps("clouds.low.march_stride", l.march_stride, 1, 16)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_have_no_clouds_and_validate() {
        let c = CloudsSpec::default();
        assert!(!c.has_low() && !c.has_high());
        c.validate().unwrap();
    }

    #[test]
    fn ranges_name_the_field() {
        let mut c = CloudsSpec::default();
        c.low.coverage = 1.5;
        assert_eq!(c.validate().unwrap_err().field, "clouds.low.coverage");
        c.low.coverage = 0.5;
        c.low.top_km = 1.0;
        let e = c.validate().unwrap_err();
        assert_eq!(e.field, "clouds.low.top_km");
        assert!(e.message.contains("above clouds.low.base_km"), "{e}");
        c.low.top_km = 3.0;
        c.low.steps = 2;
        assert_eq!(c.validate().unwrap_err().field, "clouds.low.steps");
        c.low.steps = 64;
        c.high.optical_depth = f64::NAN;
        assert_eq!(c.validate().unwrap_err().field, "clouds.high.optical_depth");
        c.high.optical_depth = 0.5;
        c.high.wind_m_s[1] = 300.0;
        assert_eq!(c.validate().unwrap_err().field, "clouds.high.wind_m_s[1]");
    }

    #[test]
    fn tiers_parse() {
        let l: LowCloudSpec = serde_json::from_str(r#"{"reproject": false}"#).unwrap();
        assert!(!l.reproject && LowCloudSpec::default().reproject);
        let l: LowCloudSpec = serde_json::from_str(r#"{"tier": "heightfield"}"#).unwrap();
        assert_eq!(l.tier, LowCloudTier::Heightfield);
        assert_eq!(LowCloudSpec::default().tier, LowCloudTier::Volumetric);
        assert!(serde_json::from_str::<LowCloudSpec>(r#"{"tier": "sprites"}"#).is_err());
    }

    #[test]
    fn kinds_parse() {
        assert_eq!(
            LowCloudKind::from_name(" Stratocumulus"),
            Some(LowCloudKind::Stratocumulus)
        );
        assert_eq!(LowCloudKind::from_name("cirrus"), None);
    }
}
