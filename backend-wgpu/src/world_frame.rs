//! A frame with a 3D world (`spec/world.md`): the sky passes fill the
//! target as for a sky-only frame, then the lighting passes
//! ([`crate::passes::lighting`]) draw the world into it, lit by the Sun and
//! Moon of the frame plan and by the sky's environment light, which is
//! built here from a cube map of the same sky (the Sun and Moon disks
//! left out: they light the world as directional lights).

use std::time::Instant as Clock;

use glam::{DVec3, Vec3};
use himmel_skymodel::clouds::{HighField, LowField};
use himmel_skymodel::frame::{AerialPerspective, ObserverLights};
use himmel_skymodel::renderer::PassStat;
use himmel_skymodel::{Camera, Effect, FramePlan, Projection, RenderError, Scene, SkyState};

use crate::passes::lighting::env::EnvLight;
use crate::passes::lighting::mesh::GROUND_HALF_M;
use crate::passes::lighting::resources::AIR_GRID;
use crate::passes::lighting::view::aabb_corners;
use crate::passes::lighting::{LightingPasses, WorldInputs};
use crate::WgpuRenderer;

/// The sky effects the environment light is made of (the clouds
/// included: a cloudy sky lights the world with its clouds).
const ENV_EFFECTS: [Effect; 5] = [
    Effect::Atmosphere,
    Effect::Milkyway,
    Effect::Stars,
    Effect::Planets,
    Effect::Clouds,
];

/// What the environment light was built for.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvKey {
    sun: DVec3,
    moon: DVec3,
    sun_scale: f64,
    moon_scale: Option<f32>,
    atmosphere: himmel_skymodel::atmosphere::AtmosphereParams,
    effects: Vec<Effect>,
    face: u32,
    parts: u32,
    directions: Vec<[u32; 3]>,
    observer_km: f64,
    /// Whether the Sun and the Moon light the world (they have aureoles).
    bodies: [bool; 2],
    /// The clouds' fields at the frame's instant (they move with the wind).
    clouds: Option<(Option<LowField>, Option<HighField>)>,
}

impl EnvKey {
    fn new(
        scene: &Scene,
        state: &SkyState,
        plan: &FramePlan,
        dirs: &[Vec3],
        bodies: [Option<Vec3>; 2],
    ) -> EnvKey {
        EnvKey {
            sun: state.sun.dir(),
            moon: state.moon.dir(),
            sun_scale: state.sun.sky_irradiance_scale(),
            moon_scale: plan
                .sky_inputs
                .as_ref()
                .and_then(|i| i.moon.map(|(m, _)| m.irradiance_scale)),
            atmosphere: scene.atmosphere.clone(),
            effects: env_effects(scene),
            face: scene.lighting.sky.cube_face,
            parts: scene.lighting.sky.parts,
            directions: dirs
                .iter()
                .map(|d| d.to_array().map(f32::to_bits))
                .collect(),
            observer_km: state.observer_altitude_km,
            bodies: bodies.map(|b| b.is_some()),
            clouds: plan.clouds.as_ref().map(|c| (c.low, c.high)),
        }
    }

    /// Why the environment built for `self` still serves `now`, or `None`.
    fn reuse(&self, now: &EnvKey, tolerance_deg: f64) -> Option<String> {
        let angle = |a: DVec3, b: DVec3| {
            a.normalize()
                .dot(b.normalize())
                .clamp(-1.0, 1.0)
                .acos()
                .to_degrees()
        };
        let (ds, dm) = (angle(self.sun, now.sun), angle(self.moon, now.moon));
        let same = self.atmosphere == now.atmosphere
            && self.effects == now.effects
            && self.face == now.face
            && self.parts == now.parts
            && self.directions == now.directions
            && self.moon_scale.is_some() == now.moon_scale.is_some()
            && self.bodies == now.bodies
            && self.clouds == now.clouds
            && (self.sun_scale / now.sun_scale - 1.0).abs() < 1e-3
            && (self.observer_km - now.observer_km).abs() < 1e-3
            && ds <= tolerance_deg
            && dm <= tolerance_deg;
        same.then(|| {
            format!(
                "reused: the Sun moved {ds:.4}° and the Moon {dm:.4}° (tolerance {tolerance_deg}°), the sky's parameters are unchanged"
            )
        })
    }
}

fn env_effects(scene: &Scene) -> Vec<Effect> {
    ENV_EFFECTS
        .into_iter()
        .filter(|e| scene.wants(*e))
        .collect()
}

/// The environment light kept between frames.
pub struct EnvCache {
    key: EnvKey,
    env: EnvLight,
}

impl WgpuRenderer {
    /// Gives the renderer the 3D world that scenes with a `world` key
    /// show; uploaded once (a later call with the same world value keeps
    /// it). Returns the upload time, ms.
    pub fn set_world(&mut self, world: &himmel_world::World) -> f64 {
        self.lighting.set_world(&self.gpu, world, 0.3)
    }

    /// The lighting passes (their world, light maps and tables).
    pub fn lighting(&self) -> &LightingPasses {
        &self.lighting
    }

    /// The sky's environment light of the last world frame.
    pub fn env_light(&self) -> Option<&EnvLight> {
        self.env.as_ref().map(|e| &e.env)
    }

    /// Draws the world into `target` (its sky already rendered).
    pub(crate) fn render_world(
        &mut self,
        scene: &Scene,
        state: &SkyState,
        plan: &FramePlan,
        lights: &ObserverLights,
        target: &wgpu::Texture,
    ) -> Result<Vec<PassStat>, RenderError> {
        if self.lighting.world().is_none() {
            return Err(RenderError::WorldMissing);
        }
        if let Some(w) = self.lighting.world() {
            w.set_ground_albedo(&self.gpu, scene.atmosphere.ground_albedo as f32);
        }
        let mut stats = Vec::new();
        let sky_on = plan.runs(Effect::Atmosphere);
        let max_layers = self.gpu.device.limits().max_texture_array_layers;
        let (dirs, sets) = LightingPasses::cell_directions(scene, max_layers);
        // The Sun and the Moon when they light the world: the sky around
        // them gets cells of its own (`env::aureole_directions`).
        let bodies = [lights.direct.sun, lights.direct.moon]
            .map(|l| l.map(|l| l.dir_world().as_vec3().normalize()));
        // The environment light.
        let t = Clock::now();
        let mut env_changed = false;
        if sky_on {
            let key = EnvKey::new(scene, state, plan, &dirs, bodies);
            let tol = scene.lighting.sky.reuse_tolerance_deg;
            match self.env.as_ref().and_then(|e| e.key.reuse(&key, tol)) {
                Some(why) => stats.push(PassStat {
                    name: "world/sky-light".into(),
                    ran: false,
                    ms: None,
                    reason: Some(why),
                }),
                None => {
                    let env = self.build_env(scene, state, &dirs, sets, &bodies)?;
                    self.env = Some(EnvCache { key, env });
                    env_changed = true;
                    stats.push(PassStat {
                        name: "world/sky-light".into(),
                        ran: true,
                        ms: Some(t.elapsed().as_secs_f64() * 1e3),
                        reason: None,
                    });
                }
            }
        } else {
            self.env = None;
            stats.push(PassStat {
                name: "world/sky-light".into(),
                ran: false,
                ms: None,
                reason: Some("the atmosphere pass does not run: no sky light".into()),
            });
        }
        // The aerial perspective.
        let t = Clock::now();
        let air = match (&plan.luts, &plan.sky_inputs) {
            (Some(luts), Some(inputs)) if sky_on => {
                let a = self.aerial_perspective(scene, luts, inputs, plan.observer_radius_km);
                stats.push(PassStat {
                    name: "world/aerial-perspective".into(),
                    ran: true,
                    ms: Some(t.elapsed().as_secs_f64() * 1e3),
                    reason: None,
                });
                Some(a)
            }
            _ => None,
        };
        let inputs = WorldInputs {
            scene,
            direct: lights.direct,
            env: self.env.as_ref().map(|e| &e.env).filter(|_| sky_on),
            env_changed,
            air: air.as_ref(),
            shadows: plan.runs(Effect::Shadows),
            godrays: plan.runs(Effect::Godrays),
            clouds: plan.clouds.as_ref(),
            ao: plan.runs(Effect::Ao),
            ssr: plan.runs(Effect::Ssr),
            temporal: plan.runs(Effect::Temporal),
        };
        stats.extend(self.lighting.render(&self.gpu, &inputs, target)?);
        Ok(stats)
    }

    /// Renders the sky (without the Sun and Moon disks) into a cube map,
    /// reads it back and builds the environment light.
    fn build_env(
        &mut self,
        scene: &Scene,
        state: &SkyState,
        dirs: &[Vec3],
        sets: usize,
        bodies: &[Option<Vec3>; 2],
    ) -> Result<EnvLight, RenderError> {
        let mut s = scene.clone();
        s.world = None;
        s.fog = None;
        // The Moon stays requested so that the moonlit sky is part of the
        // atmosphere; its disk's pass is left out below with the Sun's.
        s.effects = env_effects(scene);
        if scene.wants(Effect::Moon) {
            s.effects.push(Effect::Moon);
        }
        let face = scene.lighting.sky.cube_face;
        s.camera = Camera {
            projection: Projection::Cubemap,
            width: face,
            height: face,
            ..Camera::default()
        };
        // The plan follows the state's passes: leave out the Sun and Moon
        // disks (directional lights) and whatever is not sky.
        let mut st = state.clone();
        for p in st.passes.iter_mut() {
            if !ENV_EFFECTS.contains(&p.effect) {
                p.skip(himmel_skymodel::SkipReason::NotRequested);
            }
        }
        let frame = self.render_frame(&s, &st)?;
        let cube = self.read_back(&frame)?;
        let bodies: Vec<Vec3> = bodies.iter().flatten().copied().collect();
        Ok(EnvLight::from_cube(
            &cube,
            dirs,
            sets,
            &bodies,
            scene.lighting.sky.parts as usize,
        ))
    }

    /// The aerial perspective over the camera's view, out to the farthest
    /// point of the world (or the ground plane's edge).
    fn aerial_perspective(
        &self,
        scene: &Scene,
        luts: &himmel_skymodel::atmosphere::AtmosphereLuts,
        inputs: &himmel_skymodel::frame::SkyInputs,
        r0: f32,
    ) -> AerialPerspective {
        let cam = &scene.camera;
        let eye = cam.eye_m().as_vec3();
        let mut far = 1.0f32;
        if let Some(b) = self.lighting.world().and_then(|w| w.bounds) {
            for c in aabb_corners(&b) {
                far = far.max((c - eye).length());
            }
        }
        if scene.world.as_ref().is_some_and(|w| w.ground) {
            far = far.max(GROUND_HALF_M * std::f32::consts::SQRT_2);
        }
        let (gx, gy, gz) = AIR_GRID;
        let (w, h) = cam.image_size();
        let mut dirs = Vec::with_capacity((gx * gy) as usize);
        for j in 0..gy {
            for i in 0..gx {
                let px = (i as f64 + 0.5) / gx as f64 * w as f64;
                let py = (j as f64 + 0.5) / gy as f64 * h as f64;
                let d = cam.pixel_to_dir(px, py).unwrap_or(DVec3::Z);
                dirs.push(d.as_vec3().normalize());
            }
        }
        let distances: Vec<f32> = (0..gz)
            .map(|k| far * (k as f32 / (gz - 1) as f32).powi(2))
            .collect();
        AerialPerspective::compute(luts, inputs, r0, &dirs, &distances)
    }
}
