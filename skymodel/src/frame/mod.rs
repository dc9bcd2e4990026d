//! The frame plan: everything the passes of one frame consume, computed
//! once per frame and independent of any backend. A backend only executes
//! it (`himmel-cpu` per pixel in Rust, `himmel-wgpu` in WGSL).
//!
//! ```text
//! Scene ─┐
//!        ├─> SkyState::at ──> FramePlan::prepare ──> backend passes ──> camera stage ──> file
//! instant┘   (astronomy,      (LUTs, sky light,     (back to front,    (exposure, tone
//!             pass plan)       exposure, culling,    into one HDR       curve, sRGB)
//!                              Sun/Moon/night)       image, cd/m²)
//! ```
//!
//! * [`LutStore`] ([`luts`]) — the parameter-dependent atmosphere LUTs of
//!   the last parameters in memory and in a checksummed disk cache;
//! * [`SkyLight`] ([`sky_light`]) — the sunlit and moonlit sky views,
//!   computed by whichever [`SkyViewSource`] the backend passes;
//! * [`SunFrame`], [`CoronaFrame`] ([`sun`]) — the disk, its margin,
//!   supersampling, occluding Moon, pixel rectangle, table; the eclipse
//!   corona;
//! * [`MoonFrame`] ([`moon`]) — the Moon shader's constants and tables,
//!   pixel angle, margin, supersampling, rectangle;
//! * [`NightFrame`] ([`night`]) — the exposure, extinction, background,
//!   point sources and the culling of the night passes;
//! * [`TextureFrame`] ([`texture`]) — a texture-mapped sky's textures,
//!   cross-fade gains, rotation, blend and horizon band;
//! * [`PixelDirections`] ([`pixels`]) — pixel-centre view directions in
//!   f32 as the CPU walks the image;
//! * [`CloudFrame`] ([`clouds`]) — the cloud layers' fields, lights,
//!   ambient light and their composition over the sky;
//! * [`DirectLights`], [`AerialPerspective`] ([`lights`]) — what a 3D
//!   world receives: the Sun and Moon as directional lights after the
//!   atmosphere, the sky's horizontal illuminance, the aerial perspective.

pub mod cloud_grid;
pub mod cloud_history;
pub mod cloud_shadow;
pub mod clouds;
pub mod lights;
pub mod luts;
pub mod moon;
pub mod night;
pub mod overcast;
pub mod pixels;
pub mod sky_light;
pub mod sun;
pub mod texture;

use std::sync::Arc;
use std::time::Instant as Clock;

use glam::DVec3;

pub use cloud_grid::{grid_nodes, LowCloudGrid, AGREE_TRANSMITTANCE};
pub use cloud_history::{
    CloudHistory, HistoryClock, HistoryKey, HistoryMiss, HistoryStep, HistoryUse,
};
pub use cloud_shadow::CloudShadowMap;
pub use clouds::{CloudFrame, GridStore, GroundLight, SeenHit};
pub use lights::{AerialPerspective, DirectLight, DirectLights, ObserverLights};
pub use luts::{LutOrigin, LutProgress, LutStore};
pub use moon::MoonFrame;
pub use night::NightFrame;
pub use pixels::PixelDirections;
pub use sky_light::{CpuSkyViews, SkyInputs, SkyLight, SkyViewSource};
pub use sun::{CoronaFrame, SunFrame};
pub use texture::TextureFrame;

use crate::atmosphere::{AtmosphereLuts, SkyViewInput};
use crate::error::RenderError;
use crate::plan::{PlannedPass, SkipReason};
use crate::scene::{Effect, Scene};
use crate::state::SkyState;

/// Everything the passes of one frame consume.
#[derive(Debug, Clone)]
pub struct FramePlan {
    /// Every effect back to front: the state's plan with the night passes
    /// that are invisible at this exposure culled.
    pub passes: Vec<PlannedPass>,
    /// The atmosphere LUTs, when the atmosphere pass runs (their
    /// transmittance then extincts every pass behind it).
    pub luts: Option<Arc<AtmosphereLuts>>,
    /// Where the LUTs came from.
    pub lut_origin: LutOrigin,
    /// Time spent getting the LUTs (memory, disk or computation), ms.
    pub precompute_ms: f64,
    /// The observer's distance from the Earth's centre in the atmosphere
    /// model, km (0 without LUTs).
    pub observer_radius_km: f32,
    /// The sky views' inputs (the Sun's; the Moon's on a moonlit night),
    /// when the atmosphere pass runs.
    pub sky_inputs: Option<SkyInputs>,
    /// The sky light, when it was needed on the CPU side (the night
    /// passes' metering and culling) or asked for ([`Self::sky_light`]).
    pub sky_light: Option<SkyLight>,
    /// Time spent on the sky views, ms.
    pub sky_view_ms: f64,
    /// The Sun, when its pass runs.
    pub sun: Option<SunFrame>,
    /// The eclipse corona, when the Sun pass runs and the Moon hides part
    /// of the disk.
    pub corona: Option<CoronaFrame>,
    /// The Moon, when its pass runs.
    pub moon: Option<MoonFrame>,
    /// The night passes, when one of them is planned.
    pub night: Option<NightFrame>,
    /// The sky texture, when its pass runs.
    pub texture: Option<TextureFrame>,
    /// The cloud layers, when their pass runs.
    pub clouds: Option<CloudFrame>,
}

impl FramePlan {
    /// Plans the frame of `scene` at `state`: the LUTs from `store`, the
    /// sky views from `views` when the night passes need them for their
    /// metering and culling, and every pass's frame.
    pub fn prepare(
        scene: &Scene,
        state: &SkyState,
        store: &mut LutStore,
        views: &mut dyn SkyViewSource,
    ) -> Result<FramePlan, RenderError> {
        scene.validate().map_err(RenderError::Scene)?;
        let atmosphere = state.runs(Effect::Atmosphere);
        let tp = Clock::now();
        let (luts, lut_origin) = if atmosphere {
            let (l, o) = store.get(&scene.atmosphere, &scene.lut);
            (Some(l), o)
        } else {
            (None, LutOrigin::None)
        };
        let precompute_ms = ms(tp);
        let r0 = luts
            .as_ref()
            .map_or(0.0, |l| l.medium.bottom + state.observer_altitude_km as f32);
        let sky_inputs = atmosphere.then(|| sky_inputs(scene, state));
        let mut plan = FramePlan {
            passes: state.passes.clone(),
            luts,
            lut_origin,
            precompute_ms,
            observer_radius_km: r0,
            sky_inputs,
            sky_light: None,
            sky_view_ms: 0.0,
            sun: None,
            corona: None,
            moon: None,
            night: None,
            texture: None,
            clouds: None,
        };
        let texture_spec = scene
            .sky_texture
            .as_ref()
            .filter(|_| state.runs(Effect::Texture));
        if let Some(spec) = texture_spec {
            texture::arrange(&mut plan.passes, spec);
        }
        let night_passes = [Effect::Milkyway, Effect::Stars, Effect::Planets];
        if plan.runs(Effect::Clouds) && night_passes.iter().any(|&e| plan.runs(e)) {
            if let Some(t) = overcast::overcast(scene, state, plan.luts.as_deref()) {
                for p in plan.passes.iter_mut() {
                    if night_passes.contains(&p.effect) {
                        p.skip(SkipReason::Overcast {
                            max_transmittance: t,
                        });
                    }
                }
            }
        }
        let night_planned = night_passes.into_iter().any(|e| plan.runs(e));
        if night_planned {
            plan.sky_light(views)?;
            let luts = plan.luts.as_deref();
            let night = NightFrame::prepare(scene, state, luts, r0, plan.sky_light.as_ref());
            for (e, why) in &night.culled {
                if let Some(p) = plan.passes.iter_mut().find(|p| p.effect == *e) {
                    p.skip(SkipReason::Culled(why.clone()));
                }
            }
            plan.night = Some(night);
        }
        if plan.runs(Effect::Sun) {
            plan.sun = Some(SunFrame::new(scene, state));
            plan.corona = CoronaFrame::new(scene, state);
        }
        if plan.runs(Effect::Moon) {
            plan.moon = Some(MoonFrame::new(scene, state, plan.luts.as_deref(), r0));
        }
        if let Some(spec) = texture_spec {
            let sky_lux = if spec.units == crate::texture_spec::TextureUnits::Sky {
                plan.sky_light(views)?
                    .map(|s| {
                        crate::spectrum::luminance(lights::sky_horizontal_rgb(s).map(|v| v as f32))
                    })
                    .map(f64::from)
            } else {
                None
            };
            plan.texture = Some(TextureFrame::prepare(
                spec,
                state,
                &mut store.textures,
                sky_lux,
            )?);
        }
        if plan.runs(Effect::Clouds) {
            let sky_lux = plan.sky_light(views)?.map(lights::sky_horizontal_rgb);
            let (luts, inputs) = (plan.luts.clone(), plan.sky_inputs);
            plan.clouds = Some(CloudFrame::prepare(
                scene,
                state,
                luts,
                inputs,
                sky_lux,
                &mut store.cloud_grids,
            ));
        }
        Ok(plan)
    }

    /// Whether the pass of `e` runs in this frame.
    pub fn runs(&self, e: Effect) -> bool {
        self.passes.iter().any(|p| p.effect == e && p.run)
    }

    /// The sky light of this frame, computed by `views` on first use
    /// (`None` when the atmosphere pass does not run).
    pub fn sky_light(
        &mut self,
        views: &mut dyn SkyViewSource,
    ) -> Result<Option<&SkyLight>, RenderError> {
        if self.sky_light.is_none() {
            if let (Some(luts), Some(inputs)) = (&self.luts, &self.sky_inputs) {
                let t = Clock::now();
                let v = views.sky_views(luts, &inputs.list())?;
                self.sky_light = SkyLight::from_views(inputs, v);
                self.sky_view_ms += ms(t);
            }
        }
        Ok(self.sky_light.as_ref())
    }

    /// The Sun and Moon as directional lights and the sky's horizontal
    /// illuminance of this frame (the sky light computed by `views` on
    /// first use).
    pub fn observer_lights(
        &mut self,
        scene: &Scene,
        state: &SkyState,
        views: &mut dyn SkyViewSource,
    ) -> Result<ObserverLights, RenderError> {
        let direct = DirectLights::new(
            scene,
            state,
            self.luts.as_deref(),
            self.observer_radius_km,
            self.sky_inputs.as_ref(),
        );
        let sky_horizontal_rgb = self
            .sky_light(views)?
            .map_or([0.0; 3], lights::sky_horizontal_rgb);
        Ok(ObserverLights {
            direct,
            sky_horizontal_rgb,
        })
    }

    /// The EV100 the frame plan assumed (the night passes' metering or the
    /// fixed exposure), when the night passes are planned.
    pub fn ev100(&self) -> Option<f64> {
        self.night.as_ref().map(|n| n.ev100)
    }
}

/// The sky views' inputs of `state`: the Sun's, scaled by the visible
/// fraction of its disk (solar eclipses), and on a moonlit night
/// ([`crate::moon::moonlight_scale`]) a second one lit from the Moon.
pub fn sky_inputs(scene: &Scene, state: &SkyState) -> SkyInputs {
    let sun_dir = state.sun.dir().as_vec3().normalize();
    let altitude = state.observer_altitude_km as f32;
    let pole = DVec3::from_array(state.celestial_pole).as_vec3();
    let moon = crate::moon::moonlight_scale(scene, &state.sun, &state.moon, pole).map(|scale| {
        let dir = state.moon.dir().as_vec3().normalize();
        let input = SkyViewInput {
            observer_altitude_km: altitude,
            sun_sin_elevation: dir.z,
            irradiance_scale: scale as f32,
        };
        (input, dir)
    });
    SkyInputs {
        sun: SkyViewInput {
            observer_altitude_km: altitude,
            sun_sin_elevation: sun_dir.z,
            irradiance_scale: state.sun.sky_irradiance_scale() as f32,
        },
        sun_dir,
        moon,
    }
}

fn ms(t: Clock) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}
