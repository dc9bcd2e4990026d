//! The frame's light maps, steps 2 and 3 of [`LightingPasses::render`]:
//! the sky's visibility maps and the Sun's and Moon's shadow maps, each
//! kept while what they depend on holds.

use std::time::Instant as Clock;

use glam::Vec3;
use himmel_skymodel::frame::DirectLight;
use himmel_skymodel::renderer::PassStat;
use himmel_skymodel::{RenderError, SkyOcclusion};

use super::view::{self, LightView, WorldCamera};
use super::{ms, stat, LightingPasses, WorldInputs};
use crate::gpu::Gpu;

/// Why the shadow maps of the last frame still hold.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct ShadowKey {
    sun: Option<Vec3>,
    moon: Option<Vec3>,
    camera: [f32; 12],
    settings: himmel_skymodel::world_spec::ShadowSettings,
    world: (usize, usize, usize),
}

impl LightingPasses {
    /// Step 2: the sky's visibility maps, kept while the world and the cells'
    /// directions do not change.
    pub(super) fn visibility_step(
        &mut self,
        gpu: &Gpu,
        inputs: &WorldInputs,
    ) -> Result<PassStat, RenderError> {
        let (Some(world), Some(pipes)) = (self.world.as_ref(), self.pipes.as_ref()) else {
            return Err(RenderError::WorldMissing);
        };
        let t = Clock::now();
        if inputs.scene.lighting.sky.occlusion == SkyOcclusion::Ao {
            let why = "lighting.sky.occlusion is ao: the ao pass occludes the sky light";
            return Ok(stat("world/sky-visibility", false, None, Some(why.into())));
        }
        let (env, bounds) = match (inputs.env, world.bounds) {
            (Some(e), Some(b)) => (e, b),
            (None, _) => {
                let why = "no sky light: the atmosphere pass does not run";
                return Ok(stat("world/sky-visibility", false, None, Some(why.into())));
            }
            (_, None) => {
                let why = "the world has no geometry";
                return Ok(stat("world/sky-visibility", false, None, Some(why.into())));
            }
        };
        let dirs: Vec<Vec3> = env.cells.iter().map(|c| c.dir).collect();
        let res = inputs.scene.lighting.sky.visibility_resolution;
        if self.maps.visibility_current(&dirs, res) {
            let why = "reused: the world and the sky's directions have not changed";
            return Ok(stat("world/sky-visibility", false, None, Some(why.into())));
        }
        let centre = (bounds.min + bounds.max) * 0.5;
        let half = 0.5 * bounds.extent() * 1.01;
        let views: Vec<LightView> = dirs
            .iter()
            .map(|&d| view::ortho_light(d, centre, half, &bounds, res))
            .collect();
        let drawn = self
            .maps
            .build_visibility(gpu, pipes, world, &views, &dirs, res)?;
        // Only the aureoles' maps follow the Sun and Moon: say so when the
        // others were kept.
        let why = (drawn < views.len()).then(|| {
            format!(
                "redrew {drawn} of {} maps (the aureoles' directions moved)",
                views.len()
            )
        });
        Ok(stat("world/sky-visibility", true, Some(ms(t)), why))
    }

    /// Step 3: the Sun's and Moon's cascades, kept while the lights, the camera
    /// and the world do not move.
    pub(super) fn shadow_step(
        &mut self,
        gpu: &Gpu,
        inputs: &WorldInputs,
        cam: &WorldCamera,
    ) -> Result<Option<PassStat>, RenderError> {
        let (Some(world), Some(pipes)) = (self.world.as_ref(), self.pipes.as_ref()) else {
            return Err(RenderError::WorldMissing);
        };
        let t = Clock::now();
        let settings = inputs.scene.lighting.shadows;
        let light_dir = |l: &Option<DirectLight>| l.map(|l| l.dir_world().as_vec3().normalize());
        let (sun, moon) = (
            light_dir(&inputs.direct.sun),
            light_dir(&inputs.direct.moon),
        );
        let Some(bounds) = world
            .bounds
            .filter(|_| inputs.shadows && (sun.is_some() || moon.is_some()))
        else {
            // The maps are dropped: a later frame with the same lights and
            // camera must draw them again, not reuse an empty set.
            self.shadow_views.clear();
            self.sun_layers = 0;
            self.shadow_key = None;
            return Ok(None);
        };
        let key = ShadowKey {
            sun,
            moon,
            camera: [
                cam.eye.x,
                cam.eye.y,
                cam.eye.z,
                cam.forward.x,
                cam.forward.y,
                cam.forward.z,
                cam.up.x,
                cam.up.y,
                cam.up.z,
                cam.tan_half,
                cam.aspect,
                0.0,
            ],
            settings,
            world: world.identity,
        };
        if self.shadow_key.as_ref() == Some(&key) {
            let why = "reused: the lights, the camera and the world have not moved";
            return Ok(Some(stat("shadows", false, None, Some(why.into()))));
        }
        let cascades = |d: Option<Vec3>| {
            d.map(|d| {
                view::cascades(
                    cam,
                    d,
                    &bounds,
                    settings.cascades,
                    settings.max_distance_m as f32,
                    settings.split_lambda as f32,
                    settings.resolution,
                )
            })
            .unwrap_or_default()
        };
        let mut views = cascades(sun);
        self.sun_layers = views.len() as u32;
        views.extend(cascades(moon));
        self.maps
            .build_shadows(gpu, pipes, world, &views, settings.resolution)?;
        self.shadow_views = views;
        self.shadow_key = Some(key);
        Ok(Some(stat("shadows", true, Some(ms(t)), None)))
    }
}
