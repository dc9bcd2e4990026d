//! `himmel-skymodel`: the scene, the sky state of one instant with its pass
//! plan, and the physical sky models in absolute photometric units.
//!
//! * [`scene`] — [`Scene`] (serde, documented defaults) and effects;
//! * [`state`] — [`SkyState::at`]: the Sun's refracted apparent direction,
//!   distance, size and illuminance, and the pass plan;
//! * [`atmosphere`] — Rayleigh/aerosol/ozone atmosphere with Hillaire (2020)
//!   LUTs and a brute-force reference;
//! * [`sun`] — the limb-darkened Sun disk, energy-conserving;
//! * [`moon`] — the Moon's state, Hapke BRDF, albedo map, earthshine,
//!   lunar-eclipse shading;
//! * [`stars`] — stars and planets as point sources, the energy-conserving
//!   PSF, extinction and scintillation;
//! * [`milkyway`] — the Milky Way map, faint-star light, zodiacal light, airglow;
//! * [`night`] — the night sky of one instant and the culling of its passes;
//! * [`spectrum`] — bands, solar spectrum, CIE functions, sRGB;
//! * [`projection`] — fisheye, equirect, perspective, cube map;
//! * [`camera`] — metering, exposure, night vision, tone curve, sRGB, dither;
//! * [`renderer`] — the [`SkyRenderer`] trait.

// Band loops index several arrays at once; indices read better there.
#![allow(clippy::needless_range_loop)]

pub mod atmosphere;
pub mod camera;
pub mod milkyway;
pub mod moon;
pub mod night;
pub mod projection;
pub mod renderer;
pub mod scene;
pub mod spectrum;
pub mod stars;
pub mod state;
pub mod sun;
pub mod units;

pub use camera::Exposure;
pub use projection::{Camera, Projection};
pub use renderer::{HdrImage, PassStat, RenderError, RenderOutput, SkyRenderer};
pub use scene::{Effect, Scene, SceneError, StarParams};
pub use state::{SkyState, SunState};
