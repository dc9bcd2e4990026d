//! `himmel-skymodel`: the scene, the sky state of one instant with its pass
//! plan, the physical sky models in absolute photometric units, and the
//! frame plan that every backend executes.
//!
//! * [`scene`] — [`Scene`] (serde, documented defaults) and effects;
//! * [`state`] — [`SkyState::at`]: the Sun's refracted apparent direction,
//!   distance, size and illuminance, the Moon, the night sky, the pass plan;
//! * [`plan`] — the pass plan: every effect back to front, whether it
//!   runs, and why not ([`SkipReason`]);
//! * [`frame`] — [`FramePlan::prepare`]: per frame and independent of any
//!   backend, the LUTs ([`LutStore`], memory and checksummed disk cache),
//!   the sunlit and moonlit sky views, exposure, culling, and the Sun,
//!   Moon and night passes' constants and tables;
//! * [`atmosphere`] — Rayleigh/aerosol/ozone atmosphere with Hillaire (2020)
//!   LUTs and a brute-force reference;
//! * [`sun`] — the limb-darkened Sun disk, energy-conserving, and the corona;
//! * [`moon`] — the Moon's state, Hapke BRDF, albedo map, earthshine,
//!   lunar-eclipse shading;
//! * [`stars`] — stars and planets as point sources, the energy-conserving
//!   PSF, extinction and scintillation;
//! * [`milkyway`] — the Milky Way map, faint-star light, zodiacal light, airglow;
//! * [`clouds`] — the cloud layers' density fields (value-noise fBm,
//!   identical in WGSL), the low layer's ray march with self-shadowing and
//!   multiple-scattering octaves, the thin high layer; their scene keys in
//!   [`cloud_spec`];
//! * [`night`] — the night sky of one instant and the culling criterion of
//!   its passes;
//! * [`spectrum`] — bands, solar spectrum, CIE functions, sRGB;
//! * [`angle`] — `f32` arctangent and arcsine for the per-pixel lookups;
//! * [`projection`] — fisheye, equirect, perspective, cube map;
//! * [`refraction`] — ENU directions raised or lowered by the standard
//!   refraction;
//! * [`sequence`] — frame sequences ([`sequence::Sequence`]): time steps,
//!   `time.speed`, camera paths, per-frame history, the exposure curve of a
//!   sequence;
//! * [`solar_time`] — local apparent solar time, `time.day_fraction`;
//! * [`camera`] — metering, exposure, night vision, tone curve, sRGB, dither;
//! * [`renderer`], [`error`] — the [`SkyRenderer`] trait, its output and errors;
//! * `file` — [`file::write_file`]: every file written through a synced
//!   temporary renamed into place, every error reported.
//!
//! Module dependencies run one way (no cycles; `tests/tests/architecture.rs`
//! checks it): `units`, `spectrum` ← the models (`atmosphere`, `sun`,
//! `moon`, `stars`, `milkyway`, `night`, `clouds`) ← `plan` ← `state` ← `frame`,
//! `renderer`.

// Band loops index several arrays at once; indices read better there.
#![allow(clippy::needless_range_loop)]

pub mod angle;
pub mod ao_spec;
pub mod atmosphere;
pub mod camera;
pub mod cloud_spec;
pub mod clouds;
pub mod error;
#[cfg(feature = "std")]
pub mod file;
pub mod frame;
pub mod milkyway;
pub mod moon;
pub mod night;
pub mod overlay;
pub mod overlay_spec;
pub mod plan;
pub mod projection;
pub mod refraction;
pub mod renderer;
pub mod scene;
pub mod scene_error;
pub mod sequence;
pub mod solar_time;
pub mod spectrum;
pub mod ssr_spec;
pub mod stars;
pub mod state;
pub mod sun;
pub mod temporal_spec;
pub mod texture_sky;
pub mod texture_spec;
pub mod units;
pub mod world_spec;

pub use ao_spec::{AoMethod, AoSettings, ShSky};
pub use camera::Exposure;
pub use frame::{FramePlan, LutOrigin, LutStore};
pub use plan::{PlannedPass, SkipReason};
pub use projection::{Camera, Projection};
pub use renderer::{HdrImage, PassStat, RenderError, RenderOutput, SkyRenderer, Unavailable};
pub use scene::{Effect, OverlaySpec, Scene, SceneError, StarParams};
pub use ssr_spec::SsrSettings;
pub use state::{SkyState, SunState};
pub use temporal_spec::TemporalSettings;
pub use texture_spec::SkyTextureSpec;
pub use world_spec::{
    FogPhase, FogSpec, GodraysMethod, GodraysSettings, LightingSpec, ShadowFilter, SkyOcclusion,
    WorldSpec,
};
