//! The `SkyRenderer` trait both backends implement, and its image and
//! statistics types.

use serde::Serialize;

pub use crate::error::{RenderError, Unavailable};
use crate::frame::{LutOrigin, ObserverLights};
use crate::scene::{Effect, Scene};
use crate::state::SkyState;

/// A linear HDR image: linear sRGB, cd/m² (conventions.md, Photometry).
#[derive(Debug, Clone, PartialEq)]
pub struct HdrImage {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Row-major pixels.
    pub pixels: Vec<[f32; 3]>,
    /// Whether a pixel shows the scene (false outside the fisheye circle).
    pub valid: Vec<bool>,
}

/// What a pass did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PassStat {
    /// Pass name (the effect name).
    pub name: String,
    /// Whether it ran.
    pub ran: bool,
    /// Milliseconds spent, when it ran.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ms: Option<f64>,
    /// Why it did not run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

impl PassStat {
    /// The `moon-eclipse` entry both backends list after the passes when
    /// the Moon pass is planned: the lunar-eclipse shading is part of the
    /// Moon pass, and this says whether it ran, or why not.
    pub fn moon_eclipse(state: &SkyState) -> Option<PassStat> {
        state.runs(Effect::Moon).then(|| PassStat {
            name: "moon-eclipse".into(),
            ran: state.moon.eclipse.is_some(),
            ms: None,
            reason: state.moon.eclipse_reason.clone(),
        })
    }
}

/// A rendered frame with its statistics.
#[derive(Debug, Clone)]
pub struct RenderOutput {
    /// The HDR image.
    pub image: HdrImage,
    /// One entry per effect, back to front.
    pub passes: Vec<PassStat>,
    /// Time spent on (or loading) the parameter-dependent LUTs, ms.
    pub precompute_ms: f64,
    /// Where the LUTs came from.
    pub lut_source: LutOrigin,
    /// Time spent on the per-pixel view directions, ms.
    pub geometry_ms: f64,
    /// Time spent on the per-frame sky-view LUT (part of the atmosphere pass), ms.
    pub sky_view_ms: f64,
    /// Time spent building the low cloud layer's height-field maps
    /// (`clouds.low.tier = "heightfield"`: on the CPU, in the frame plan,
    /// before the clouds pass), ms; 0 without them.
    pub cloud_maps_ms: f64,
    /// Time spent building the low layer's 3D diffusion grids
    /// (`clouds.low.scattering = "diffusion"` in the volumetric tier: on
    /// the CPU, in the frame plan, one per light), ms; 0 without them.
    pub cloud_grid_ms: f64,
    /// What the low layer's temporal reprojection gave this frame
    /// ([`crate::frame::CloudHistory`]; `None` when the frame has no
    /// amortised march or the backend keeps no history).
    pub cloud_history: Option<crate::frame::HistoryUse>,
    /// The Sun and Moon as directional lights and the sky's horizontal
    /// illuminance at this instant (what a 3D world receives).
    pub lights: ObserverLights,
}

/// A sky renderer (CPU or GPU): renders the passes that `state` plans for
/// `scene` into an absolute linear HDR image.
pub trait SkyRenderer {
    /// Backend name as reported in `--stats` (`cpu`, `wgpu`).
    fn name(&self) -> &'static str;
    /// Renders one frame.
    fn render(&mut self, scene: &Scene, state: &SkyState) -> Result<RenderOutput, RenderError>;
}
