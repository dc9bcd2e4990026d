//! The scene keys of a 3D world under the sky (`shared/spec/world.md`):
//! the world file, the fog medium and the lighting passes' settings. The
//! model of the light itself (the Sun and Moon as directional lights, the
//! sky as an environment light, the aerial perspective) is in
//! [`crate::frame::lights`]; the passes are the wgpu backend's.

use serde::{Deserialize, Serialize};

use crate::scene_error::SceneError;
use crate::units::show;

/// A 3D world under the sky.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldSpec {
    /// The glTF 2.0 file (`.gltf` or `.glb`), relative to the scene file.
    pub gltf: String,
    /// Adds an infinite Lambertian plane at y = 0 with
    /// `atmosphere.ground_albedo` (default false).
    #[serde(default)]
    pub ground: bool,
}

/// The phase function of the fog.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum FogPhase {
    /// Rayleigh scattering, (3/16π)(1 + cos²θ).
    Rayleigh,
    /// Isotropic, 1/4π.
    Isotropic,
    /// Henyey–Greenstein with asymmetry `g` in (−1, 1).
    Hg(f64),
}

/// A homogeneous fog filling y ≤ `top_m` (world.md `fog`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FogSpec {
    /// Scattering coefficient σ_s, 1/m, in [0, 10] (default 0.002: a
    /// meteorological visibility of about 2 km).
    pub scattering_per_m: f64,
    /// Absorption coefficient σ_a, 1/m, in [0, 10] (default 0).
    pub absorption_per_m: f64,
    /// The phase function (default `{"hg": 0.6}`).
    pub phase: FogPhase,
    /// The fog's top, metres above the ground, in [0, 1e5] (default none:
    /// the fog fills the whole world).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub top_m: Option<f64>,
}

impl Default for FogSpec {
    fn default() -> Self {
        FogSpec {
            scattering_per_m: 0.002,
            absorption_per_m: 0.0,
            phase: FogPhase::Hg(0.6),
            top_m: None,
        }
    }
}

impl FogPhase {
    /// The phase function p(θ), 1/sr, at cos θ = `cos_theta` between the
    /// light's direction of travel before and after scattering (1: forward).
    /// Each integrates to 1 over the sphere.
    pub fn eval(self, cos_theta: f64) -> f64 {
        use std::f64::consts::PI;
        match self {
            FogPhase::Rayleigh => 3.0 / (16.0 * PI) * (1.0 + cos_theta * cos_theta),
            FogPhase::Isotropic => 1.0 / (4.0 * PI),
            FogPhase::Hg(g) => {
                let d = 1.0 + g * g - 2.0 * g * cos_theta;
                (1.0 - g * g) / (4.0 * PI * d * d.sqrt())
            }
        }
    }

    /// The shader's code of the phase (0 isotropic, 1 Rayleigh, 2 HG) and
    /// its asymmetry g (0 unless HG).
    pub fn code(self) -> (u32, f64) {
        match self {
            FogPhase::Isotropic => (0, 0.0),
            FogPhase::Rayleigh => (1, 0.0),
            FogPhase::Hg(g) => (2, g),
        }
    }
}

impl FogSpec {
    /// The extinction coefficient σ_t = σ_s + σ_a, 1/m.
    pub fn extinction_per_m(&self) -> f64 {
        self.scattering_per_m + self.absorption_per_m
    }

    /// The top of the fog, metres (`f64::INFINITY` without `top_m`).
    pub fn top(&self) -> f64 {
        self.top_m.unwrap_or(f64::INFINITY)
    }

    /// Transmittance of sunlight (or moonlight) at altitude `alt_rad` down
    /// to height `y_m`: exp(−σ_t · (top − y) / sin h), world.md. 0 when the
    /// light is at or below the horizon and the point is in the fog; 1 above it.
    pub fn light_transmittance(&self, y_m: f64, alt_rad: f64) -> f64 {
        let depth = (self.top() - y_m).max(0.0);
        if depth == 0.0 {
            return 1.0;
        }
        let s = alt_rad.sin();
        if s <= 0.0 {
            return 0.0;
        }
        (-self.extinction_per_m() * depth / s).exp()
    }

    fn validate(&self) -> Result<(), SceneError> {
        range("fog.scattering_per_m", self.scattering_per_m, 0.0, 10.0)?;
        range("fog.absorption_per_m", self.absorption_per_m, 0.0, 10.0)?;
        if let Some(t) = self.top_m {
            range("fog.top_m", t, 0.0, 1e5)?;
        }
        if let FogPhase::Hg(g) = self.phase {
            if !(g.is_finite() && g > -1.0 && g < 1.0) {
                return Err(SceneError {
                    field: "fog.phase.hg".into(),
                    message: format!("{} is outside (-1, 1)", show(g)),
                });
            }
        }
        Ok(())
    }
}

/// How shadow-map lookups are filtered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShadowFilter {
    /// One depth comparison per pixel: hard, aliased edges.
    Off,
    /// Percentage-closer filtering over a fixed 3×3-texel footprint.
    Pcf,
    /// Percentage-closer soft shadows: a blocker search, then a disk filter
    /// whose width is the light's real angular diameter × the
    /// blocker–receiver distance (the Sun's 0.53° penumbra).
    Soft,
}

/// Directional shadow maps of the Sun and the Moon (`lighting.shadows`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ShadowSettings {
    /// Filtering (default `soft`).
    pub filter: ShadowFilter,
    /// Side of each cascade's map, texels, in [128, 8192] (default 2048).
    pub resolution: u32,
    /// Cascades over the view, in [1, 4] (default 3; fewer are used when
    /// the world fits in fewer).
    pub cascades: u32,
    /// Shadows are drawn up to this distance from the camera, metres, in
    /// [1, 1e5] (default 500).
    pub max_distance_m: f64,
    /// How the view depth range is split between cascades, 0 = uniform,
    /// 1 = logarithmic, in [0, 1] (default 0.75).
    pub split_lambda: f64,
}

impl Default for ShadowSettings {
    fn default() -> Self {
        ShadowSettings {
            filter: ShadowFilter::Soft,
            resolution: 2048,
            cascades: 3,
            max_distance_m: 500.0,
            split_lambda: 0.75,
        }
    }
}

/// What occludes the sky's diffuse light (`lighting.sky.occlusion`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum SkyOcclusion {
    /// The world's visibility maps, one per sky cell (the default): every
    /// blocker the maps' texels resolve, on screen or not; the ao pass, when
    /// it runs, only adds the contact detail the maps miss.
    #[default]
    Maps,
    /// No visibility maps are built: the sky's diffuse light is the open
    /// sky's irradiance times the ao pass's occlusion — its scalar AO, or
    /// with `lighting.ao.sh` its directional (S3HO) occlusion of the sky's
    /// own radiance. Screen space: blockers off screen or beyond
    /// `lighting.ao.radius_m` do not shadow; without the ao pass nothing
    /// does. The sky's specular light is not occluded.
    Ao,
}

/// The sky as an environment light (`lighting.sky`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SkyLightSettings {
    /// Face size of the sky cube map the environment light is built from,
    /// texels, in [8, 512] (default 64).
    pub cube_face: u32,
    /// Directions per set from which the world's occlusion of the sky is
    /// sampled (one visibility map each; half of them in the upper
    /// hemisphere, which alone count over a ground plane), in [8, 256]
    /// (default 64).
    pub directions: u32,
    /// Interleaving: N × N sets of directions, one per pixel of each N × N
    /// block, blurred over the block where the surface is continuous
    /// (Keller & Heidrich 2001's interleaved sampling, as Tóth &
    /// Umenhoffer 2009 use it for light shafts), in [1, 4] (default 4:
    /// 16 sets). Fewer when the adapter holds fewer map layers.
    pub interleave: u32,
    /// Side of each visibility map, texels, in [64, 4096] (default 512:
    /// 1 024 maps of 16-bit depth, 512 MiB; outdoors the maps span the
    /// whole world, and a texel of a tenth of a metre or less keeps the
    /// sky that a box hides from the floor beside it).
    pub visibility_resolution: u32,
    /// Parts per cell, in [1, 64] (default 1: one lookup along the cell's
    /// direction). More cut each cell's sky into about this many parts,
    /// each looked up in the cell's map where its rays cross the nearest
    /// blocker, so that an opening (a window) lets through the part of a
    /// cell it frames rather than the whole cell or none of it: 16 halves
    /// the error of a room lit through a window, at several times the
    /// lighting pass's cost, and lets up to 2 × 10⁻⁴ of the open sky's
    /// light into a closed box (surfaces the maps see edge-on).
    pub parts: u32,
    /// The environment light is rebuilt when the Sun or Moon moved more
    /// than this, degrees, in [0, 10] (default 0.05; 0 = every frame).
    pub reuse_tolerance_deg: f64,
    /// What occludes the sky's diffuse light: `maps` (default) or `ao`
    /// ([`SkyOcclusion`]).
    pub occlusion: SkyOcclusion,
}

impl Default for SkyLightSettings {
    fn default() -> Self {
        SkyLightSettings {
            cube_face: 64,
            directions: 64,
            interleave: 4,
            visibility_resolution: 512,
            parts: 1,
            reuse_tolerance_deg: 0.05,
            occlusion: SkyOcclusion::Maps,
        }
    }
}

/// How light shafts in the fog are drawn (`lighting.godrays.method`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GodraysMethod {
    /// Tóth & Umenhoffer 2009: each view ray marched through the fog to
    /// the surface, the Sun's and Moon's shadow maps looked up per step
    /// (2×2 PCF), N × N interleaved start offsets gathered over the block,
    /// at a reduced resolution with a depth-aware upsample.
    Toth,
    /// Mitchell (GPU Gems 3, ch. 13): a screen-space radial blur, with
    /// `samples` taps, of the light's visibility mask toward the light's
    /// screen position, scaling each pixel's unoccluded fog column; its
    /// decay and weight follow from the medium (`radial.wgsl`).
    Mitchell,
    /// Sousa (Crysis, SIGGRAPH 2007): the same blur in three passes of
    /// `samples` / 3 taps each, every pass blurring the previous one's
    /// output with a stride `samples` / 3 times longer.
    Sousa,
    /// A frustum-aligned fog volume (Wronski 2014; Hillaire 2015): the
    /// fog's in-scattering per metre computed per froxel (a grid of one
    /// froxel per `resolution_divisor` × `resolution_divisor` pixels,
    /// `steps` depth slices out to the frame's farthest surface,
    /// quadratically spaced), each froxel's sample depth jittered per
    /// frame and blended with the previous frame's volume at the
    /// reprojected place (`temporal`), then integrated front to back along
    /// each column; a pixel takes the integral at its surface's distance
    /// (`froxel.wgsl`).
    Froxel,
}

impl GodraysMethod {
    /// Whether the method works in screen space (and so needs the light
    /// near the frame: [`crate::plan`]'s `ShaftLightOffScreen`).
    pub fn screen_space(self) -> bool {
        matches!(self, GodraysMethod::Mitchell | GodraysMethod::Sousa)
    }
}

/// Light shafts: the fog's single scattering of the Sun, Moon and sky
/// (`lighting.godrays`).
///
/// The defaults depend on the method ([`GodraysSettings::of`]): a key left
/// out takes the default of the method the object names.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(from = "GodraysKeys")]
pub struct GodraysSettings {
    /// The method (default `toth`).
    pub method: GodraysMethod,
    /// March steps per view ray, in [1, 512] (default 48); `froxel`: the
    /// volume's depth slices (default 32).
    pub steps: u32,
    /// Interleaving: N × N start offsets of the march, one per pixel of
    /// each N × N block of the marched image, averaged over the block where
    /// the depth is continuous (an N²-fold finer march), in [1, 8]
    /// (default 4); `froxel`: the Sun's and Moon's samples per froxel and
    /// frame, stratified over its slice.
    pub interleave: u32,
    /// The march runs on an image this many times smaller on each side,
    /// upsampled by depth (bilateral); pixels whose nearest texels show
    /// another surface or the sky are marched themselves (`toth`), in
    /// [1, 8] (default 2).
    pub resolution_divisor: u32,
    /// Sky cells (of the environment light's, `lighting.sky`) looked up per
    /// step for the sky's in-scattering, each in its visibility map, in
    /// [0, 64] (default 16, `froxel` 8; 0 = no sky light in the fog). A step looks up
    /// every k-th cell, the next step the next ones, so that the march
    /// sweeps them all (`toth`; `froxel` the same per froxel along each
    /// column; the screen-space methods leave the sky's light in the fog
    /// out).
    pub sky_cells: u32,
    /// Radial-blur taps per pixel in total (`mitchell`, `sousa`: three
    /// passes of `samples` / 3), in [3, 256] (default 64). The screen-space
    /// methods run at 1 / `resolution_divisor` of the frame too (`sousa`
    /// at half of that on each side, as its passes ran in Crysis); `froxel`'s
    /// grid has one froxel per `resolution_divisor` × `resolution_divisor`
    /// pixels.
    pub samples: u32,
    /// `froxel`: the previous frame's share of each froxel's in-scattering
    /// where its reprojected position lies in the previous volume (an
    /// exponential moving average over the frames of a sequence; 0 = no
    /// history), in [0, 0.98] (default 0.9).
    pub temporal: f64,
}

impl Default for GodraysSettings {
    fn default() -> Self {
        GodraysSettings::of(GodraysMethod::Toth)
    }
}

impl GodraysSettings {
    /// A method's default quality. `toth`: 48 steps with 16 sky cells
    /// each, 4 × 4 interleaved at half resolution — the optimised march
    /// that issue 15 times against the full-resolution 128-step one
    /// (`tests/tests/godrays_toth_speed.rs`); `froxel`: 32 slices with 8
    /// sky cells per froxel, the cheap modern reference.
    pub fn of(method: GodraysMethod) -> Self {
        let (steps, sky_cells) = match method {
            GodraysMethod::Froxel => (32, 8),
            _ => (48, 16),
        };
        GodraysSettings {
            method,
            steps,
            interleave: 4,
            resolution_divisor: 2,
            sky_cells,
            samples: 64,
            temporal: 0.9,
        }
    }
}

/// `lighting.godrays` as written: each key optional, the rest from the
/// named method's defaults.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GodraysKeys {
    method: Option<GodraysMethod>,
    steps: Option<u32>,
    interleave: Option<u32>,
    resolution_divisor: Option<u32>,
    sky_cells: Option<u32>,
    samples: Option<u32>,
    temporal: Option<f64>,
}

impl From<GodraysKeys> for GodraysSettings {
    fn from(k: GodraysKeys) -> Self {
        let d = GodraysSettings::of(k.method.unwrap_or(GodraysMethod::Toth));
        GodraysSettings {
            method: d.method,
            steps: k.steps.unwrap_or(d.steps),
            interleave: k.interleave.unwrap_or(d.interleave),
            resolution_divisor: k.resolution_divisor.unwrap_or(d.resolution_divisor),
            sky_cells: k.sky_cells.unwrap_or(d.sky_cells),
            samples: k.samples.unwrap_or(d.samples),
            temporal: k.temporal.unwrap_or(d.temporal),
        }
    }
}

/// The lighting passes' settings (`lighting`); each pass documents its keys.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct LightingSpec {
    /// The Sun's and Moon's shadow maps.
    pub shadows: ShadowSettings,
    /// The sky's environment light and its occlusion by the world.
    pub sky: SkyLightSettings,
    /// Light shafts in the fog.
    pub godrays: GodraysSettings,
    /// Ambient occlusion of the sky light ([`crate::ao_spec`]).
    pub ao: crate::ao_spec::AoSettings,
    /// Screen-space reflections ([`crate::ssr_spec`]).
    pub ssr: crate::ssr_spec::SsrSettings,
    /// The temporal filter ([`crate::temporal_spec`]).
    pub temporal: crate::temporal_spec::TemporalSettings,
}

impl LightingSpec {
    /// Checks every value against its documented range, naming the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        let s = &self.shadows;
        let k = &self.sky;
        let g = &self.godrays;
        for (f, v, lo, hi) in [
            (
                "lighting.shadows.resolution",
                s.resolution as f64,
                128.0,
                8192.0,
            ),
            ("lighting.shadows.cascades", s.cascades as f64, 1.0, 4.0),
            (
                "lighting.shadows.max_distance_m",
                s.max_distance_m,
                1.0,
                1e5,
            ),
            ("lighting.shadows.split_lambda", s.split_lambda, 0.0, 1.0),
            ("lighting.sky.cube_face", k.cube_face as f64, 8.0, 512.0),
            ("lighting.sky.directions", k.directions as f64, 8.0, 256.0),
            ("lighting.sky.interleave", k.interleave as f64, 1.0, 4.0),
            (
                "lighting.sky.visibility_resolution",
                k.visibility_resolution as f64,
                64.0,
                4096.0,
            ),
            ("lighting.sky.parts", k.parts as f64, 1.0, 64.0),
            (
                "lighting.sky.reuse_tolerance_deg",
                k.reuse_tolerance_deg,
                0.0,
                10.0,
            ),
            ("lighting.godrays.steps", g.steps as f64, 1.0, 512.0),
            ("lighting.godrays.interleave", g.interleave as f64, 1.0, 8.0),
            (
                "lighting.godrays.resolution_divisor",
                g.resolution_divisor as f64,
                1.0,
                8.0,
            ),
            ("lighting.godrays.sky_cells", g.sky_cells as f64, 0.0, 64.0),
            ("lighting.godrays.samples", g.samples as f64, 3.0, 256.0),
            ("lighting.godrays.temporal", g.temporal, 0.0, 0.98),
        ] {
            range(f, v, lo, hi)?;
        }
        self.ssr.validate()?;
        self.temporal.validate()?;
        self.ao.validate()
    }
}

/// Validates the fog, if any.
pub fn validate_fog(fog: &Option<FogSpec>) -> Result<(), SceneError> {
    fog.as_ref().map_or(Ok(()), FogSpec::validate)
}

/// The scene's range check, for the world's keys and the overlay's.
pub(crate) use crate::scene_error::check_range as range;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fog_phase_reads_all_three_forms() {
        for (text, want) in [
            (r#""rayleigh""#, FogPhase::Rayleigh),
            (r#""isotropic""#, FogPhase::Isotropic),
            (r#"{"hg": 0.6}"#, FogPhase::Hg(0.6)),
        ] {
            let p: FogPhase = serde_json::from_str(text).unwrap();
            assert_eq!(p, want);
        }
        assert!(serde_json::from_str::<FogPhase>(r#""mie""#).is_err());
    }

    #[test]
    fn sunlight_through_fog_follows_the_slant_path() {
        let f = FogSpec {
            scattering_per_m: 0.01,
            absorption_per_m: 0.0,
            phase: FogPhase::Isotropic,
            top_m: Some(50.0),
        };
        // 50 m of fog at 30°: a 100 m slant path.
        let t = f.light_transmittance(0.0, 30f64.to_radians());
        assert!((t - (-1.0f64).exp()).abs() < 1e-12);
        assert_eq!(f.light_transmittance(60.0, 0.1), 1.0);
        assert_eq!(f.light_transmittance(10.0, -0.1), 0.0);
    }

    #[test]
    fn ranges_name_their_fields() {
        let mut l = LightingSpec::default();
        assert!(l.validate().is_ok());
        l.shadows.cascades = 9;
        assert_eq!(l.validate().unwrap_err().field, "lighting.shadows.cascades");
        let f = FogSpec {
            phase: FogPhase::Hg(1.0),
            ..FogSpec::default()
        };
        assert_eq!(validate_fog(&Some(f)).unwrap_err().field, "fog.phase.hg");
        let mut l = LightingSpec::default();
        l.godrays.steps = 0;
        assert_eq!(l.validate().unwrap_err().field, "lighting.godrays.steps");
        l.godrays.steps = 32;
        l.godrays.resolution_divisor = 9;
        let e = l.validate().unwrap_err();
        assert_eq!(e.field, "lighting.godrays.resolution_divisor");
        let g: GodraysSettings = serde_json::from_str(r#"{"method": "toth", "steps": 8}"#).unwrap();
        assert_eq!(
            (g.method, g.steps, g.interleave),
            (GodraysMethod::Toth, 8, 4)
        );
        assert!(serde_json::from_str::<GodraysSettings>(r#"{"method": "blur"}"#).is_err());
        let g: GodraysSettings =
            serde_json::from_str(r#"{"method": "sousa", "samples": 24}"#).unwrap();
        assert!(g.method.screen_space() && g.samples == 24);
        assert!(!GodraysMethod::Toth.screen_space());
        let g: GodraysSettings =
            serde_json::from_str(r#"{"method": "froxel", "temporal": 0.5}"#).unwrap();
        assert!(g.method == GodraysMethod::Froxel && !g.method.screen_space());
        // A key left out takes the named method's default.
        assert_eq!((g.steps, g.sky_cells), (32, 8));
        let g: GodraysSettings = serde_json::from_str(r#"{"sky_cells": 4}"#).unwrap();
        assert_eq!(
            (g.method, g.steps, g.sky_cells),
            (GodraysMethod::Toth, 48, 4)
        );
        let g: GodraysSettings =
            serde_json::from_str(r#"{"method": "froxel", "steps": 64}"#).unwrap();
        assert_eq!((g.steps, g.sky_cells), (64, 8));
        assert!(serde_json::from_str::<GodraysSettings>(r#"{"stepz": 3}"#).is_err());
        let mut l = LightingSpec::default();
        l.godrays.temporal = 0.99;
        let e = l.validate().unwrap_err();
        assert_eq!(e.field, "lighting.godrays.temporal");
        // `scene-template --world` shows the key with its default.
        let t = serde_json::to_value(LightingSpec::default()).unwrap();
        assert_eq!(t["godrays"]["samples"], 64);
        assert_eq!(t["godrays"]["temporal"], 0.9);
        let mut l = LightingSpec::default();
        l.godrays.samples = 2;
        assert_eq!(l.validate().unwrap_err().field, "lighting.godrays.samples");
    }

    #[test]
    fn sky_occlusion_reads_maps_or_ao() {
        assert_eq!(SkyLightSettings::default().occlusion, SkyOcclusion::Maps);
        let k: SkyLightSettings = serde_json::from_str(r#"{"occlusion": "ao"}"#).unwrap();
        assert_eq!(k.occlusion, SkyOcclusion::Ao);
        assert!(serde_json::from_str::<SkyLightSettings>(r#"{"occlusion": "ssao"}"#).is_err());
        let t = serde_json::to_value(LightingSpec::default()).unwrap();
        assert_eq!(t["sky"]["occlusion"], "maps");
        assert_eq!(t["ao"]["sh"], false);
        assert_eq!(t["ao"]["sh_sky"], "radiance");
    }

    /// ∫ p dΩ over the sphere by the midpoint rule in cos θ (1e5 bands).
    fn sphere_integral(p: FogPhase) -> f64 {
        let n = 100_000;
        let du = 2.0 / n as f64;
        (0..n)
            .map(|i| p.eval(-1.0 + (i as f64 + 0.5) * du) * 2.0 * std::f64::consts::PI * du)
            .sum()
    }

    #[test]
    fn phase_functions_are_normalised() {
        for p in [
            FogPhase::Isotropic,
            FogPhase::Rayleigh,
            FogPhase::Hg(0.0),
            FogPhase::Hg(0.6),
            FogPhase::Hg(-0.3),
            FogPhase::Hg(0.9),
        ] {
            let i = sphere_integral(p);
            assert!((i - 1.0).abs() < 1e-4, "{p:?}: {i}");
        }
    }

    #[test]
    fn phase_functions_have_their_exact_shapes() {
        use std::f64::consts::PI;
        // Rayleigh: 3/(16π)·(1 + μ²): twice as bright forward as sideways.
        let r = FogPhase::Rayleigh;
        assert!((r.eval(0.0) - 3.0 / (16.0 * PI)).abs() < 1e-15);
        assert!((r.eval(1.0) / r.eval(0.0) - 2.0).abs() < 1e-12);
        assert!((r.eval(-0.5) - r.eval(0.5)).abs() < 1e-15);
        // HG: (1 − g²)/(4π (1 + g² − 2gμ)^{3/2}); forward/backward peaks
        // ((1 + g)/(1 − g))³ apart; g = 0 is isotropic.
        let g = 0.6;
        let h = FogPhase::Hg(g);
        assert!((h.eval(1.0) - (1.0 + g) / (4.0 * PI * (1.0 - g).powi(2))).abs() < 1e-12);
        assert!((h.eval(1.0) / h.eval(-1.0) - ((1.0 + g) / (1.0 - g)).powi(3)).abs() < 1e-9);
        let mu: f64 = 0.3;
        let want = (1.0 - g * g) / (4.0 * PI * (1.0 + g * g - 2.0 * g * mu).powf(1.5));
        assert!((h.eval(mu) - want).abs() < 1e-15);
        assert!((FogPhase::Hg(0.0).eval(0.7) - FogPhase::Isotropic.eval(-0.2)).abs() < 1e-15);
        // The mean cosine of HG is g.
        let n = 100_000;
        let du = 2.0 / n as f64;
        let mean: f64 = (0..n)
            .map(|i| {
                let m = -1.0 + (i as f64 + 0.5) * du;
                m * h.eval(m) * 2.0 * PI * du
            })
            .sum();
        assert!((mean - g).abs() < 1e-4, "{mean}");
    }
}
