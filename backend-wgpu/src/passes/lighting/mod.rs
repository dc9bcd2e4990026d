//! The lighting passes of a 3D world under the sky (`spec/world.md`),
//! after the sky passes have filled the frame's target:
//!
//! 1. **G-buffer** ([`pipelines`], `gbuffer.wgsl`) — distance, normal,
//!    roughness, base colour, metalness, material, velocity;
//! 2. **sky visibility** ([`view::hemisphere_directions`]) — one
//!    orthographic depth map of the world per direction of the sky's cells
//!    ([`env`]); built once per world and kept while it does not change;
//!    not built with `lighting.sky.occlusion` `ao` (the ao pass alone
//!    occludes the sky: scalar AO, or with `lighting.ao.sh` S3HO);
//! 3. **shadows** — the Sun's and the Moon's cascades ([`view::cascades`]),
//!    rebuilt when the light or the camera moved;
//! 4. **ambient occlusion** ([`ao`], `ao.wgsl`), when `ao` runs: AO and
//!    bent normals from the G-buffer, which the lighting pass applies to
//!    the sky's diffuse light only (see [`ao`] for how it meets the
//!    visibility maps); after the lighting pass, when `lighting.ao.bounce`
//!    asks for it, one diffuse bounce from the lit surfaces on screen
//!    ([`bounce`], `bounce.wgsl`);
//! 5. **lighting** (`shade.wgsl`) — the Sun and Moon (Lambert + GGX,
//!    filtered shadows), the sky (occluded diffuse cells, prefiltered
//!    specular; the sky's cells are split over an N × N block of pixels
//!    and gathered back, `sky` in `shade.wgsl`, each cell through its
//!    visibility map in `sky_cells.wgsl`, `gather` in `sky_gather.wgsl`), emission,
//!    fog and aerial perspective, written into the
//!    target where the G-buffer has a surface; before it, when `godrays`
//!    runs, the fog's in-scattering marched along the view rays
//!    ([`godrays`], `godrays.wgsl`), blurred in screen space
//!    ([`radial`], `radial.wgsl`) or integrated through a frustum-aligned
//!    volume ([`froxel`], `froxel.wgsl`), which it adds;
//! 6. **screen-space reflections** ([`ssr`], `ssr.wgsl`), when `ssr` runs
//!    and a material of the world is smooth enough: a Hi-Z march of GGX
//!    reflected rays that replaces the sky's specular term where they hit;
//! 7. **temporal filter** ([`temporal`], `temporal.wgsl`), when `temporal`
//!    runs: the world drawn through a jittered camera, blended with its
//!    reprojected history.
//!
//! The sky's environment light itself ([`env::EnvLight`]) is built by the
//! renderer from a cube map of the frame's sky (`world_frame.rs`).

pub mod ao;
pub mod bounce;
pub mod cloud_shadow;
pub mod env;
pub mod froxel;
pub mod godrays;
mod light_maps;
pub mod mesh;
pub mod pipelines;
pub mod radial;
pub mod resources;
pub mod ssr;
pub mod temporal;
pub mod view;

use std::time::Instant as Clock;

use glam::{Mat4, Vec3};
use himmel_skymodel::frame::{AerialPerspective, DirectLight, DirectLights};
use himmel_skymodel::renderer::PassStat;
use himmel_skymodel::{FogSpec, RenderError, Scene, ShadowFilter};

use crate::gpu::{bind_group, Gpu};
use env::EnvLight;
use light_maps::ShadowKey;
use mesh::GpuWorld;
use pipelines::{Pipelines, MATRIX_STRIDE};
use resources::{GBuffer, LightMaps, ShadeTables};
use temporal::TemporalImage;
use view::{LightView, WorldCamera};

/// The lighting uniforms (`Shade` in shade.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ShadeUniforms {
    eye: [f32; 4],
    forward: [f32; 4],
    right: [f32; 4],
    up: [f32; 4],
    sun_dir: [f32; 4],
    sun_rgb: [f32; 4],
    moon_dir: [f32; 4],
    moon_rgb: [f32; 4],
    fog: [f32; 4],
    scales: [f32; 4],
    counts: [u32; 4],
    flags: [u32; 4],
    cascade: [[f32; 16]; 8],
    cascade_info: [[f32; 4]; 8],
    shafts: [f32; 4],
    shaft_q: [u32; 4],
    clouds: [f32; 4],
    jitter: [f32; 4],
    sky_sh: [[f32; 4]; 9],
    occlusion: [u32; 4],
}

/// The G-buffer camera (`GCamera` in gbuffer.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GCamera {
    view_proj: [f32; 16],
    prev_view_proj: [f32; 16],
    eye: [f32; 4],
    size: [f32; 4],
}

/// What one world frame is lit by.
pub struct WorldInputs<'a> {
    /// The scene (camera, fog, lighting settings, world spec).
    pub scene: &'a Scene,
    /// The Sun and Moon as directional lights.
    pub direct: DirectLights,
    /// The sky's environment light (`None`: no atmosphere pass).
    pub env: Option<&'a EnvLight>,
    /// Whether the environment light changed since the last frame.
    pub env_changed: bool,
    /// The aerial perspective over the view (`None`: no atmosphere pass).
    pub air: Option<&'a AerialPerspective>,
    /// Whether the shadows pass runs.
    pub shadows: bool,
    /// Whether the godrays pass runs (the plan's decision).
    pub godrays: bool,
    /// The frame's clouds, whose shadows fall on the world (`None`: no
    /// clouds pass).
    pub clouds: Option<&'a himmel_skymodel::frame::CloudFrame>,
    /// Whether the ao pass runs (the plan's decision).
    pub ao: bool,
    /// Whether the ssr pass is requested (the plan's decision; it also
    /// needs a smooth enough material, [`LightingPasses::render`]).
    pub ssr: bool,
    /// Whether the temporal pass runs (the plan's decision).
    pub temporal: bool,
}

/// The lighting passes and what they keep between frames.
#[derive(Default)]
pub struct LightingPasses {
    pipes: Option<Pipelines>,
    world: Option<GpuWorld>,
    maps: LightMaps,
    gbuffer: Option<GBuffer>,
    tables: Option<ShadeTables>,
    shadow_key: Option<ShadowKey>,
    shadow_views: Vec<LightView>,
    sun_layers: u32,
    prev_view_proj: Option<Mat4>,
    shafts: godrays::Shafts,
    clouds: cloud_shadow::CloudShadows,
    ao: ao::Occlusion,
    bounce: bounce::Bounce,
    radial: radial::Radial,
    froxel: froxel::Froxels,
    ssr: ssr::Reflections,
    temporal: temporal::Temporal,
}

fn ms(t: Clock) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

fn stat(name: &str, ran: bool, ms: Option<f64>, reason: Option<String>) -> PassStat {
    PassStat {
        name: name.into(),
        ran,
        ms,
        reason,
    }
}

impl LightingPasses {
    /// Uploads `world` unless it is the one already held (same value).
    pub fn set_world(&mut self, gpu: &Gpu, world: &himmel_world::World, ground_albedo: f32) -> f64 {
        let t = Clock::now();
        let id = mesh::identity(world);
        if self.world.as_ref().map(|w| w.identity) != Some(id) {
            self.world = Some(GpuWorld::new(gpu, world, ground_albedo));
            self.maps.invalidate_visibility();
            self.shadow_key = None;
            self.ssr.forget_history();
        }
        ms(t)
    }

    /// The uploaded world.
    pub fn world(&self) -> Option<&GpuWorld> {
        self.world.as_ref()
    }

    /// The directions of the sky cells for `scene` and how many
    /// interleaved sets they form: `lighting.sky.directions` per set (all
    /// in the upper hemisphere over a ground plane, else half in each),
    /// `interleave`² sets, fewer when the adapter's texture arrays hold
    /// fewer than `max_layers` maps (with the aureoles' maps).
    pub fn cell_directions(scene: &Scene, max_layers: u32) -> (Vec<Vec3>, usize) {
        let ground = scene.world.as_ref().is_some_and(|w| w.ground);
        let n = scene.lighting.sky.directions as usize;
        let mut side = scene.lighting.sky.interleave.max(1) as usize;
        // Room for the Sun's and the Moon's aureoles too.
        let aureoles = 2 * env::AUREOLE_DIRECTIONS;
        while side > 1 && side * side * n + aureoles > max_layers as usize {
            side -= 1;
        }
        let sets = side * side;
        let dirs = if ground {
            view::direction_sets(n, false, sets)
        } else {
            view::direction_sets(n / 2, true, sets)
        };
        (dirs, sets)
    }

    /// Renders the world into `target` (rgba32float, the frame's sky
    /// already in it). Returns the lighting passes' `--stats` entries.
    pub fn render(
        &mut self,
        gpu: &Gpu,
        inputs: &WorldInputs,
        target: &wgpu::Texture,
    ) -> Result<Vec<PassStat>, RenderError> {
        if self.world.is_none() {
            return Err(RenderError::WorldMissing);
        }
        self.pipes.get_or_insert_with(|| Pipelines::new(gpu));
        let mut cam = WorldCamera::new(&inputs.scene.camera);
        let q = &inputs.scene.lighting.temporal;
        let dir = |l: &Option<DirectLight>| l.map(|l| l.dir_world().as_vec3().normalize());
        let run = temporal::RunKey::of(
            inputs.scene,
            dir(&inputs.direct.sun),
            dir(&inputs.direct.moon),
        );
        self.temporal.begin(inputs.temporal, q, &mut cam, run);
        let mut stats = vec![self.gbuffer_step(gpu, inputs.scene, &cam)?];
        stats.extend(self.ao_step(gpu, inputs, &cam)?);
        stats.push(self.visibility_step(gpu, inputs)?);
        let shadows = self.shadow_step(gpu, inputs, &cam)?;
        stats.extend(self.cloud_shadow_step(gpu, inputs, &cam));
        // Step 3c: whether the ssr pass runs, armed before the lighting pass.
        let least = self.world.as_ref().and_then(|w| w.min_roughness);
        let reflect = ssr::decide(inputs.scene, inputs.ssr, inputs.env.is_some(), least);
        let on = inputs.ssr && reflect.is_ok();
        self.ssr.arm(gpu, on, (cam.width, cam.height));
        let (lit, shafts) = self.lighting_step(gpu, inputs, &cam, target)?;
        stats.push(lit);
        stats.extend(shadows);
        stats.extend(shafts);
        if let Some(gb) = self.gbuffer.as_ref() {
            let extent = self
                .world
                .as_ref()
                .and_then(|w| w.bounds)
                .map(|b| b.extent());
            stats.extend(self.bounce.step(gpu, inputs, gb, extent, (&cam, target))?);
        }
        if let Some(gb) = self.gbuffer.as_ref().filter(|_| inputs.ssr) {
            stats.push(match reflect {
                Ok(()) => {
                    let s = &inputs.scene.lighting.ssr;
                    let frame = (target, cam.view_projection());
                    self.ssr.run(gpu, gb, &cam, s, frame)?
                }
                Err(why) => stat("ssr", false, None, Some(why)),
            });
        }
        if let Some(gb) = self.gbuffer.as_ref().filter(|_| inputs.temporal) {
            stats.push(self.temporal.run(gpu, gb, &cam, q, target)?);
        }
        Ok(stats)
    }

    /// The reflections' confidence image of the last frame that ran the
    /// ssr pass.
    pub fn ssr_image(&self, gpu: &Gpu) -> Result<Option<ssr::SsrImage>, RenderError> {
        self.ssr.read_back(gpu)
    }

    /// The temporal filter's distance and frame counts of the last frame.
    pub fn temporal_image(&self, gpu: &Gpu) -> Result<Option<TemporalImage>, RenderError> {
        self.temporal.read_back(gpu)
    }

    /// Step 1: the G-buffer (and the ground plane under the eye).
    fn gbuffer_step(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        cam: &WorldCamera,
    ) -> Result<PassStat, RenderError> {
        let (Some(world), Some(pipes)) = (self.world.as_ref(), self.pipes.as_ref()) else {
            return Err(RenderError::WorldMissing);
        };
        let t = Clock::now();
        let ground = scene.world.as_ref().is_some_and(|w| w.ground);
        if ground {
            world.place_ground(gpu, cam.eye);
        }
        // Drawn jittered; the motion is measured without it (gbuffer.wgsl).
        let (vp, centred) = (cam.view_projection(), cam.unjittered().view_projection());
        let prev = self.prev_view_proj.unwrap_or(centred);
        self.prev_view_proj = Some(centred);
        let gb = match self.gbuffer.take() {
            Some(g) if g.size == (cam.width, cam.height) => g,
            _ => GBuffer::new(gpu, cam.width, cam.height),
        };
        let camera = GCamera {
            view_proj: vp.to_cols_array(),
            prev_view_proj: prev.to_cols_array(),
            eye: cam.eye.extend(1.0).to_array(),
            size: temporal::gbuffer_size(cam),
        };
        resources::gbuffer_pass(gpu, pipes, world, &gb, bytemuck::bytes_of(&camera), ground)?;
        self.gbuffer = Some(gb);
        Ok(stat("world/gbuffer", true, Some(ms(t)), None))
    }

    /// The AO image of the last frame that ran the ao pass.
    pub fn ao_image(&self, gpu: &Gpu) -> Result<Option<ao::AoImage>, RenderError> {
        self.ao.read_back(gpu)
    }

    /// Step 1b: ambient occlusion from the G-buffer, when `ao` runs; its
    /// radius from the world's bounds unless `lighting.ao.radius_m` is set.
    fn ao_step(
        &mut self,
        gpu: &Gpu,
        inputs: &WorldInputs,
        cam: &WorldCamera,
    ) -> Result<Option<PassStat>, RenderError> {
        if !inputs.ao {
            return Ok(None);
        }
        let (Some(world), Some(gb)) = (self.world.as_ref(), self.gbuffer.as_ref()) else {
            return Err(RenderError::WorldMissing);
        };
        let Some(bounds) = world.bounds else {
            let why = "the world has no geometry";
            return Ok(Some(stat("ao", false, None, Some(why.into()))));
        };
        let s = &inputs.scene.lighting.ao;
        let radius = s.radius_for(bounds.extent() as f64) as f32;
        // S3HO only without the visibility maps: with them its estimate
        // would replace their exact directional shadow wherever it finds
        // less light (README, S3HO).
        let maps = inputs.scene.lighting.sky.occlusion == himmel_skymodel::SkyOcclusion::Maps;
        let settings = himmel_skymodel::AoSettings {
            sh: s.sh && !maps,
            ..*s
        };
        let sky = (inputs.env, inputs.env_changed);
        let mut stat = self.ao.run(gpu, (gb, cam), &settings, radius, sky)?;
        if s.sh && maps {
            let why = stat.reason.take().unwrap_or_default();
            stat.reason = Some(format!(
                "{why}; S3HO off: the visibility maps occlude the sky"
            ));
        }
        Ok(Some(stat))
    }

    /// Step 3b: the clouds' shadows over the world (when a clouds pass
    /// runs).
    fn cloud_shadow_step(
        &mut self,
        gpu: &Gpu,
        inputs: &WorldInputs,
        cam: &WorldCamera,
    ) -> Option<PassStat> {
        let dir = |l: &Option<DirectLight>| l.map(|l| l.dir_world().as_vec3().normalize());
        let lights =
            [dir(&inputs.direct.sun), dir(&inputs.direct.moon)].map(|d| d.filter(|d| d.y > 0.0));
        let ground = inputs.scene.world.as_ref().is_some_and(|w| w.ground);
        let bounds = self.world.as_ref().and_then(|w| w.bounds);
        self.clouds
            .update(gpu, inputs.clouds, lights, bounds, ground, cam.eye)
    }

    /// Step 4: the light shafts' march (when `godrays` runs), then the
    /// lighting pass into the target. Returns their `--stats` entries.
    fn lighting_step(
        &mut self,
        gpu: &Gpu,
        inputs: &WorldInputs,
        cam: &WorldCamera,
        target: &wgpu::Texture,
    ) -> Result<(PassStat, Option<PassStat>), RenderError> {
        let t = Clock::now();
        self.maps.ensure_stand_ins(gpu)?;
        let (Some(world), Some(pipes), Some(gb)) = (
            self.world.as_ref(),
            self.pipes.as_ref(),
            self.gbuffer.as_ref(),
        ) else {
            return Err(RenderError::WorldMissing);
        };
        let tables = self.tables.get_or_insert_with(|| ShadeTables::new(gpu));
        if let Some(env) = inputs.env {
            // The cells carry the visibility maps' texel, which follows the
            // world: written every frame (kilobytes); the prefiltered maps
            // only when the sky changed.
            let res = inputs.scene.lighting.sky.visibility_resolution;
            let extent = world.bounds.map_or(0.0, |b| b.extent());
            let texel = extent * 1.01 / res as f32;
            let specular = inputs.env_changed || !tables.has_env();
            tables.upload_env(gpu, env, texel, specular);
        }
        let air_scale = inputs.air.map(|a| tables.upload_air(gpu, a));
        let mut u = shade_uniforms(
            inputs,
            cam,
            air_scale,
            tables.env_scale(),
            &self.shadow_views,
            self.sun_layers,
            self.clouds.uniform(),
        );
        let ao_on = inputs.ao && world.bounds.is_some();
        u.occlusion[1] = self.ao.s3ho(ao_on);
        let ubuf = tables.uniforms(gpu, bytemuck::bytes_of(&u));
        let missing = || RenderError::Device("light maps missing".into());
        let shafts_stat = if inputs.godrays {
            let tg = Clock::now();
            let march = godrays::MarchInputs {
                uniforms: &ubuf,
                distance: &gb.views[0],
                material: &gb.views[3],
                shadows: self.maps.shadow_view().ok_or_else(missing)?,
                cells: &tables.cells,
                cell_view: self.maps.cell_matrices().ok_or_else(missing)?,
                visibility: self.maps.visibility_view().ok_or_else(missing)?,
            };
            let key = froxel::Key {
                world: world.identity,
                fog: [u.shafts[0], u.fog[0], u.fog[1]],
            };
            let q = &inputs.scene.lighting.godrays;
            let passes = ShaftPasses {
                radial: &mut self.radial,
                froxel: &mut self.froxel,
                shafts: &mut self.shafts,
            };
            passes.run(gpu, pipes, &march, q, (cam, key))?;
            Some(stat("godrays", true, Some(ms(tg)), None))
        } else {
            None
        };
        let shafts_view = self.shafts.view(gpu, inputs.godrays);
        let cloud_map = self.clouds.view(gpu);
        let [ao_view, sh_view] = self.ao.views(gpu, ao_on);
        let [spec_env, spec_w] = self.ssr.outputs(gpu);
        let out = target.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            ..Default::default()
        });
        let tv = wgpu::BindingResource::TextureView;
        let group = bind_group(
            &gpu.device,
            "shade",
            &pipes.shade_layout,
            &[
                ubuf.as_entire_binding(),
                tv(&gb.views[0]),
                tv(&gb.views[1]),
                tv(&gb.views[2]),
                tv(&gb.views[3]),
                tv(&out),
                world.materials.as_entire_binding(),
                tables.cells.as_entire_binding(),
                self.maps
                    .cell_matrices()
                    .ok_or_else(missing)?
                    .as_entire_binding(),
                tv(self.maps.visibility_view().ok_or_else(missing)?),
                tv(self.maps.shadow_view().ok_or_else(missing)?),
                wgpu::BindingResource::Sampler(&pipes.compare),
                tv(&tables.specular),
                tv(&tables.brdf),
                wgpu::BindingResource::Sampler(&pipes.clamp),
                tv(&tables.air_in),
                tv(&tables.air_t),
                tables.parts.as_entire_binding(),
            ],
        );
        let sky_in = sky_in_group(
            gpu,
            pipes,
            gb,
            [shafts_view, cloud_map, ao_view, spec_env, spec_w, sh_view],
        );
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        let groups = (cam.width.div_ceil(8), cam.height.div_ceil(8), 1);
        if inputs.env.is_some() {
            encode_sky(gpu, pipes, gb, &mut enc, &group, groups);
        }
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipes.shade);
            pass.set_bind_group(0, &group, &[]);
            pass.set_bind_group(1, &sky_in, &[]);
            pass.dispatch_workgroups(groups.0, groups.1, groups.2);
        }
        gpu.queue.submit([enc.finish()]);
        gpu.wait()?;
        let lit_ms = ms(t) - shafts_stat.as_ref().and_then(|s| s.ms).unwrap_or(0.0);
        Ok((
            stat("world/lighting", true, Some(lit_ms), None),
            shafts_stat,
        ))
    }
}

/// Encodes the sky pass (each pixel's set of cells) and the gather pass
/// (the block's sets), which leave in `gb.sky[2..5]` what the lighting
/// pass reads.
fn encode_sky(
    gpu: &Gpu,
    pipes: &Pipelines,
    gb: &GBuffer,
    enc: &mut wgpu::CommandEncoder,
    group: &wgpu::BindGroup,
    groups: (u32, u32, u32),
) {
    let tv = wgpu::BindingResource::TextureView;
    let sky_out = bind_group(
        &gpu.device,
        "sky out",
        &pipes.sky_out_layout,
        &[tv(&gb.sky[0]), tv(&gb.sky[1])],
    );
    let sky_raw = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("sky raw"),
        layout: &pipes.sky_raw_layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 11,
                resource: tv(&gb.sky[0]),
            },
            wgpu::BindGroupEntry {
                binding: 12,
                resource: tv(&gb.sky[1]),
            },
        ],
    });
    let gather_out = bind_group(
        &gpu.device,
        "sky gather out",
        &pipes.gather_out_layout,
        &[tv(&gb.sky[2]), tv(&gb.sky[3]), tv(&gb.sky[4])],
    );
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipes.sky);
        pass.set_bind_group(0, group, &[]);
        pass.set_bind_group(1, &sky_out, &[]);
        pass.dispatch_workgroups(groups.0, groups.1, groups.2);
    }
    let mut pass = enc.begin_compute_pass(&Default::default());
    pass.set_pipeline(&pipes.sky_gather);
    pass.set_bind_group(0, group, &[]);
    pass.set_bind_group(1, &sky_raw, &[]);
    pass.set_bind_group(2, &gather_out, &[]);
    pass.dispatch_workgroups(groups.0, groups.1, groups.2);
}

/// Group 1 of the lighting pass: the sky pass's outputs, the shafts'
/// image, the clouds' shadow map, the AO image and the sky's specular term
/// and weight for the ssr pass.
fn sky_in_group(
    gpu: &Gpu,
    pipes: &Pipelines,
    gb: &GBuffer,
    [shafts_view, cloud_map, ao_view, spec_env, spec_w, sh_view]: [&wgpu::TextureView; 6],
) -> wgpu::BindGroup {
    let tv = wgpu::BindingResource::TextureView;
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("sky in"),
        layout: &pipes.sky_in_layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 2,
                resource: tv(&gb.sky[2]),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: tv(&gb.sky[3]),
            },
            wgpu::BindGroupEntry {
                binding: 10,
                resource: tv(&gb.sky[4]),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: tv(shafts_view),
            },
            wgpu::BindGroupEntry {
                binding: 8,
                resource: tv(cloud_map),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: tv(ao_view),
            },
            wgpu::BindGroupEntry {
                binding: 6,
                resource: tv(spec_env),
            },
            wgpu::BindGroupEntry {
                binding: 7,
                resource: tv(spec_w),
            },
            wgpu::BindGroupEntry {
                binding: 9,
                resource: tv(sh_view),
            },
        ],
    })
}

/// The light shafts' passes of the three kinds and the image they write.
struct ShaftPasses<'a> {
    radial: &'a mut radial::Radial,
    froxel: &'a mut froxel::Froxels,
    shafts: &'a mut godrays::Shafts,
}

impl ShaftPasses<'_> {
    /// Runs `q`'s method into the shafts' image.
    fn run(
        self,
        gpu: &Gpu,
        pipes: &Pipelines,
        march: &godrays::MarchInputs,
        q: &himmel_skymodel::GodraysSettings,
        (cam, key): (&WorldCamera, froxel::Key),
    ) -> Result<(), RenderError> {
        let frame = (cam.width, cam.height);
        match q.method {
            m if m.screen_space() => self.radial.run_on(gpu, pipes, march, q, frame, self.shafts),
            himmel_skymodel::GodraysMethod::Froxel => {
                let c = &pipes.compare;
                self.froxel
                    .run_on(gpu, march, c, q, (cam, key), self.shafts)
            }
            _ => self
                .shafts
                .march(gpu, pipes, march, frame, q.resolution_divisor),
        }
    }
}

/// The lighting uniforms of this frame.
fn shade_uniforms(
    inputs: &WorldInputs,
    cam: &WorldCamera,
    air_scale: Option<(f32, f32, f32)>,
    env_scale: f32,
    shadow_views: &[LightView],
    sun_layers: u32,
    cloud_uniform: [f32; 4],
) -> ShadeUniforms {
    let scene = inputs.scene;
    let v4 = |v: Vec3, w: f32| [v.x, v.y, v.z, w];
    let light = |l: &Option<DirectLight>| match l {
        Some(l) => (
            v4(l.dir_world().as_vec3().normalize(), 1.0),
            [
                l.rgb[0] as f32,
                l.rgb[1] as f32,
                l.rgb[2] as f32,
                l.angular_radius.tan() as f32,
            ],
        ),
        None => ([0.0; 4], [0.0; 4]),
    };
    let (sun_dir, sun_rgb) = light(&inputs.direct.sun);
    let (moon_dir, moon_rgb) = light(&inputs.direct.moon);
    let fog = match &scene.fog {
        Some(f) => fog_uniform(f),
        None => [0.0, 1e30, 0.0, 0.0],
    };
    let mut cascade = [[0.0f32; 16]; 8];
    let mut cascade_info = [[0.0f32; 4]; 8];
    for (k, v) in shadow_views.iter().take(8).enumerate() {
        cascade[k] = v.matrix.to_cols_array();
        cascade_info[k] = [v.texel_m, v.depth_m, v.split_m.min(1e30), 0.0];
    }
    let moon_layers = shadow_views.len() as u32 - sun_layers.min(shadow_views.len() as u32);
    let filter = match scene.lighting.shadows.filter {
        ShadowFilter::Off => 0,
        ShadowFilter::Pcf => 1,
        ShadowFilter::Soft => 2,
    };
    let (ap_scale, ap_max, ap_slices) = air_scale.unwrap_or((1.0, 0.0, 1.0));
    let (shafts, shaft_q) =
        godrays::uniforms(scene.fog.as_ref(), &scene.lighting.godrays, inputs.godrays);
    ShadeUniforms {
        eye: v4(cam.eye, cam.tan_half),
        forward: v4(cam.forward, cam.aspect),
        right: v4(cam.right, cam.width as f32),
        up: v4(cam.up, cam.height as f32),
        sun_dir,
        sun_rgb,
        moon_dir,
        moon_rgb,
        fog,
        scales: [env_scale, ap_scale, ap_max, ap_slices],
        counts: [
            inputs.env.map_or(0, |e| {
                ((e.cells.len() - e.aureole_cells) / e.sets.max(1)) as u32
            }),
            if sun_dir[3] > 0.0 { sun_layers } else { 0 },
            if moon_dir[3] > 0.0 { moon_layers } else { 0 },
            filter,
        ],
        flags: [
            inputs.env.is_some() as u32,
            sun_layers,
            inputs
                .env
                .map_or(1, |e| (e.sets as f64).sqrt().round() as u32)
                .max(1),
            inputs.env.map_or(0, |e| e.aureole_cells as u32),
        ],
        cascade,
        cascade_info,
        shafts,
        shaft_q,
        clouds: cloud_uniform,
        jitter: [cam.jitter.x, cam.jitter.y, cam.frame as f32, 0.0],
        sky_sh: inputs.env.map_or([[0.0; 4]; 9], |e| {
            std::array::from_fn(|k| [e.sh9[0][k], e.sh9[1][k], e.sh9[2][k], 0.0])
        }),
        occlusion: [
            (scene.lighting.sky.occlusion == himmel_skymodel::SkyOcclusion::Ao) as u32,
            0,
            0,
            0,
        ],
    }
}

/// The fog's uniform: σt, top, on.
fn fog_uniform(f: &FogSpec) -> [f32; 4] {
    [
        f.extinction_per_m() as f32,
        f.top().min(1e30) as f32,
        1.0,
        0.0,
    ]
}

/// Bytes of `n` light matrices at [`MATRIX_STRIDE`].
pub fn matrix_bytes(views: &[LightView]) -> Vec<u8> {
    let mut out = vec![0u8; views.len().max(1) * MATRIX_STRIDE as usize];
    for (k, v) in views.iter().enumerate() {
        let m = v.matrix.to_cols_array();
        let at = k * MATRIX_STRIDE as usize;
        out[at..at + 64].copy_from_slice(bytemuck::cast_slice(&m));
    }
    out
}
