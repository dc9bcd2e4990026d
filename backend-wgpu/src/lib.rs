//! `himmel-wgpu`: the GPU renderer of Himmel on wgpu, headless (Vulkan,
//! Metal, DX12 — any adapter, software ones such as Mesa's lavapipe
//! included). It executes the frame plan of `himmel-skymodel`
//! ([`FramePlan`]) in WGSL and depends on nothing but the sky model and
//! wgpu.
//!
//! Every sky pass is a module under [`passes`] beside its WGSL file and
//! follows one contract ([`pass`]): built once, prepared per frame from
//! the plan, recorded into the frame's encoder band by band, timed. The
//! passes add their radiance (linear sRGB, cd/m², conventions.md
//! Photometry) into a per-pixel accumulation band, back to front, as the
//! CPU reference renderer does; the store pass writes it into an
//! `rgba32float` texture: one layer for fisheye, equirect and perspective
//! images, six layers (+X −X +Y −Y +Z −Z, scene frame, conventions.md)
//! for a cube map, which users can bind as a `TextureViewDimension::Cube`
//! texture ([`WgpuRenderer::render_cubemap`]).
//!
//! * [`passes::luts`] — the parameter-dependent atmosphere LUTs: compute
//!   shaders ([`LutSource::Gpu`], read back once into the frame plan's LUT
//!   store) or the store's CPU precompute and disk cache, uploaded
//!   ([`LutSource::Cpu`]); the default follows the adapter
//!   ([`LutSource::default_for`]).
//! * [`passes::sky_view`] — the per-frame sky views (sunlit, and moonlit on
//!   a moonlit night) in compute shaders, read back only when the plan's
//!   night metering needs them; or the plan's CPU sky views uploaded.
//! * [`passes::atmosphere`], [`passes::sun`], [`passes::moon`] (disk and
//!   eclipse corona), [`passes::milkyway`], [`passes::points`] (stars and
//!   planets as tiles or instanced quads, [`PointMethod`]),
//!   [`passes::texture`] (texture-mapped skies), [`passes::clouds`] (the
//!   low and high cloud layers over what lies behind them),
//!   [`passes::store`].
//!
//! Frames larger than the adapter's storage-buffer limit render in bands of
//! rows ([`frame::FrameLayout`]). Per-pass times come from timestamp
//! queries where the adapter supports them, otherwise from the CPU clock
//! around each submitted and awaited pass ([`WgpuRenderer::timing`]).
//! `docs/architecture.md` walks through one frame and through adding a
//! pass; the measured speed and parity are in the README.

pub mod frame;
pub mod gpu;
pub mod pass;
pub mod passes;
pub mod pool;
pub mod uniforms;
pub mod world_frame;

use std::path::PathBuf;
use std::time::Instant as Clock;

use himmel_skymodel::frame::{CpuSkyViews, HistoryUse, LutOrigin, LutStore, SkyViewSource};
use himmel_skymodel::renderer::{HdrImage, PassStat, RenderError, RenderOutput, SkyRenderer};
use himmel_skymodel::{Camera, Effect, FramePlan, Projection, Scene, SkyState, Unavailable};

pub use frame::{GpuFrame, TARGET_FORMAT};
pub use gpu::{Timing, WgpuError};
pub use passes::lighting::ao::AoImage;
pub use passes::lighting::ssr::SsrImage;
pub use passes::lighting::temporal::TemporalImage;
pub use passes::luts::{self as luts, LutSource};
pub use passes::moon::moon_uniforms;
pub use passes::points::{point_lists, quad_scale, PointLists, PointMethod, POINT_TILE};
pub use uniforms::{AtmosphereUniforms, FrameUniforms, NightUniforms, PointRecord};

use frame::{FrameBuild, FrameLayout, SkyGroup};
use gpu::{Gpu, Timer};
use pass::{Band, Step};
use passes::luts::LutSlot;
use passes::sky_view::GpuSkyViews;
use pool::BufferPool;

/// Every pass, built once.
struct Passes {
    sky: SkyGroup,
    sky_view: passes::sky_view::SkyViewPass,
    atmosphere: passes::atmosphere::AtmospherePass,
    sun: passes::sun::SunPass,
    moon: passes::moon::MoonPass,
    milkyway: passes::milkyway::MilkyWayPass,
    points: passes::points::PointsPass,
    store: passes::store::StorePass,
    texture: passes::texture::TexturePass,
    clouds: passes::clouds::CloudsPass,
    /// The LUT compute passes, compiled on first use.
    luts: Option<passes::luts::LutPipelines>,
}

/// The wgpu renderer.
pub struct WgpuRenderer {
    gpu: Gpu,
    passes: Passes,
    /// The frame plan's LUT store (memory and disk cache).
    store: LutStore,
    /// The parameter-dependent LUTs on the GPU.
    gpu_luts: LutSlot,
    lut_source: LutSource,
    sky_view_on_gpu: bool,
    timestamps: bool,
    max_band_bytes: Option<u64>,
    /// The per-frame buffers, kept across frames.
    pool: BufferPool,
    /// The lighting passes of 3D worlds and their world.
    lighting: passes::lighting::LightingPasses,
    /// The sky's environment light of the last world frame.
    env: Option<world_frame::EnvCache>,
}

impl std::fmt::Debug for WgpuRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WgpuRenderer")
            .field("adapter", &self.gpu.info.name)
            .field("backend", &self.gpu.info.backend)
            .field("timestamps", &self.timestamps)
            .finish()
    }
}

fn ms(t: Clock) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

impl WgpuRenderer {
    /// A renderer on the first adapter wgpu offers (high-performance
    /// preference; software adapters included) among the backends that
    /// `WGPU_BACKEND` allows (all by default), with the LUT disk cache in
    /// `cache_dir`. Errors when no adapter or device is available.
    pub fn new(cache_dir: Option<PathBuf>) -> Result<Self, WgpuError> {
        let gpu = Gpu::new()?;
        let sky = SkyGroup::new(&gpu);
        let passes = Passes {
            sky_view: passes::sky_view::SkyViewPass::new(&gpu),
            atmosphere: passes::atmosphere::AtmospherePass::new(&gpu, &sky),
            sun: passes::sun::SunPass::new(&gpu, &sky),
            moon: passes::moon::MoonPass::new(&gpu, &sky),
            milkyway: passes::milkyway::MilkyWayPass::new(&gpu, &sky),
            points: passes::points::PointsPass::new(&gpu, &sky),
            store: passes::store::StorePass::new(&gpu, &sky),
            texture: passes::texture::TexturePass::new(&gpu, &sky),
            clouds: passes::clouds::CloudsPass::new(&gpu, &sky),
            luts: None,
            sky,
        };
        Ok(WgpuRenderer {
            lut_source: LutSource::default_for(gpu.info.device_type),
            timestamps: gpu.timestamps_supported,
            passes,
            gpu,
            store: LutStore::new(cache_dir),
            gpu_luts: LutSlot::default(),
            sky_view_on_gpu: true,
            max_band_bytes: None,
            pool: BufferPool::default(),
            lighting: Default::default(),
            env: None,
        })
    }

    /// Chooses how stars and planets are drawn (default:
    /// [`PointMethod::default_for`] the adapter).
    pub fn set_point_method(&mut self, method: PointMethod) {
        self.passes.points.method = method;
    }

    /// How stars and planets are drawn.
    pub fn point_method(&self) -> PointMethod {
        self.passes.points.method
    }

    /// The format of the point-source quad target: `Rgba32Float` where the
    /// adapter offers `Features::FLOAT32_BLENDABLE` (requested then),
    /// otherwise `Rgba16Float` (11-bit significand: each quad pass's sum
    /// rounded to ≈ 5e-4 relative, radiance above 65504 cd/m² saturating).
    pub fn quad_format(&self) -> wgpu::TextureFormat {
        self.passes.points.format()
    }

    /// Sets the point-source quad target's format: `Rgba16Float` (any
    /// adapter) or `Rgba32Float` (where the device has
    /// `Features::FLOAT32_BLENDABLE`); other formats are refused.
    pub fn set_quad_format(&mut self, format: wgpu::TextureFormat) -> Result<(), RenderError> {
        self.passes
            .points
            .set_format(&self.gpu, &self.passes.sky, format)
    }

    /// The device (to bind [`GpuFrame::texture`] in your own passes).
    pub fn device(&self) -> &wgpu::Device {
        &self.gpu.device
    }

    /// The queue of [`Self::device`].
    pub fn queue(&self) -> &wgpu::Queue {
        &self.gpu.queue
    }

    /// The adapter: name, backend, device type (`Cpu` for lavapipe).
    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.gpu.info
    }

    /// How per-pass times are measured on this adapter.
    pub fn timing(&self) -> Timing {
        if self.timestamps {
            Timing::GpuTimestamps
        } else {
            Timing::Cpu
        }
    }

    /// Uses timestamp queries for the per-pass times when the adapter has
    /// them (`true`, the default) or the CPU clock around each awaited pass.
    pub fn set_timestamps(&mut self, on: bool) {
        self.timestamps = on && self.gpu.timestamps_supported;
    }

    /// Caps the accumulation buffer (bytes; `None`: the adapter's storage
    /// buffer limit). Frames larger than the cap render in bands of rows.
    pub fn set_max_band_bytes(&mut self, cap: Option<u64>) {
        self.max_band_bytes = cap;
    }

    /// Computes the per-frame sky views in compute shaders (`true`, the
    /// default) or on the CPU (uploaded each frame).
    pub fn set_sky_view_on_gpu(&mut self, on: bool) {
        self.sky_view_on_gpu = on;
    }

    /// Whether the sky views are computed on the GPU.
    pub fn sky_view_on_gpu(&self) -> bool {
        self.sky_view_on_gpu
    }

    /// Chooses where the parameter-dependent LUTs come from (default:
    /// [`LutSource::default_for`] the adapter's type). A change drops the
    /// LUTs held in memory, so the next frame computes or loads them anew.
    pub fn set_lut_source(&mut self, source: LutSource) {
        if source != self.lut_source {
            self.lut_source = source;
            self.gpu_luts = LutSlot::default();
            self.store.clear();
        }
    }

    /// Where the parameter-dependent LUTs come from.
    pub fn lut_source(&self) -> LutSource {
        self.lut_source
    }

    /// Sets the decoder of sky texture files (this crate reads no image
    /// format; the CPU backend's `texture_io::ImageLoader` reads PNG, JPEG,
    /// EXR and HDR).
    pub fn set_texture_loader(
        &mut self,
        loader: std::sync::Arc<dyn himmel_skymodel::texture_sky::TextureLoader>,
    ) {
        self.store.textures.set_loader(loader);
    }

    /// The sky textures kept by this renderer (register generated images
    /// with `TextureStore::insert`).
    pub fn textures(&mut self) -> &mut himmel_skymodel::texture_sky::TextureStore {
        &mut self.store.textures
    }

    /// Shows a progress bar during a long CPU LUT precomputation (through
    /// `progress`, e.g. a terminal bar; none: silent).
    pub fn set_progress(
        &mut self,
        progress: Option<std::sync::Arc<dyn himmel_skymodel::frame::LutProgress>>,
    ) {
        self.store.set_progress(progress);
    }

    /// Computes the parameter-dependent LUTs for `params`/`config` anew
    /// from the current [`LutSource`], bypassing the memory and disk
    /// caches, and keeps them for the next frames. Returns after the GPU
    /// has finished. For benchmarks and warm-up.
    pub fn precompute_luts(
        &mut self,
        params: &himmel_skymodel::atmosphere::AtmosphereParams,
        config: &himmel_skymodel::atmosphere::LutConfig,
    ) -> Result<(), RenderError> {
        self.gpu_luts = LutSlot::default();
        match self.lut_source {
            LutSource::Gpu => {
                self.ensure_gpu_luts(params, config)?;
            }
            LutSource::Cpu => {
                let l = himmel_skymodel::frame::luts::precompute(params, config, None);
                let l = self.store.insert(l);
                self.gpu_luts.upload(&self.gpu, &l);
                self.gpu.wait()?;
            }
        }
        Ok(())
    }

    /// With [`LutSource::Gpu`], makes sure the GPU-computed LUTs for
    /// `params`/`config` are held (computing them and reading them back
    /// into the LUT store, which the plan's CPU-side tables read); returns
    /// whether they were computed now.
    fn ensure_gpu_luts(
        &mut self,
        params: &himmel_skymodel::atmosphere::AtmosphereParams,
        config: &himmel_skymodel::atmosphere::LutConfig,
    ) -> Result<bool, RenderError> {
        if self.lut_source != LutSource::Gpu || self.gpu_luts.computed_for(params, config) {
            return Ok(false);
        }
        let pipelines = self
            .passes
            .luts
            .get_or_insert_with(|| passes::luts::LutPipelines::new(&self.gpu.device));
        let (bufs, cpu_copy) =
            passes::luts::compute(&self.gpu.device, &self.gpu.queue, pipelines, params, config)?;
        self.gpu_luts.set_computed(params, config, bufs);
        self.store.insert(cpu_copy);
        Ok(true)
    }

    /// Renders a cube map of the scene with faces of `face` × `face`
    /// pixels (the scene's camera is replaced by a cube-map camera) and
    /// leaves it on the GPU.
    pub fn render_cubemap(
        &mut self,
        scene: &Scene,
        state: &SkyState,
        face: u32,
    ) -> Result<GpuFrame, RenderError> {
        let mut s = scene.clone();
        s.camera = Camera {
            projection: Projection::Cubemap,
            width: face,
            height: face,
            ..s.camera
        };
        self.render_frame(&s, state)
    }

    /// The frame plan of `scene` at `state` as this renderer makes it: the
    /// LUTs from its store (computed on the GPU first with
    /// [`LutSource::Gpu`]), the sky views for the night metering from the
    /// GPU (or the CPU when [`Self::set_sky_view_on_gpu`] is off). Returns
    /// the plan and whether the LUTs were computed on the GPU for it.
    pub fn plan(
        &mut self,
        scene: &Scene,
        state: &SkyState,
    ) -> Result<(FramePlan, bool), RenderError> {
        scene.validate().map_err(RenderError::Scene)?;
        let tp = Clock::now();
        let on_gpu = state.runs(Effect::Atmosphere)
            && self.ensure_gpu_luts(&scene.atmosphere, &scene.lut)?;
        let gpu_lut_ms = ms(tp);
        self.passes.sky_view.begin_frame();
        let mut source: Box<dyn SkyViewSource + '_> = if self.sky_view_on_gpu {
            Box::new(GpuSkyViews {
                pass: &mut self.passes.sky_view,
                gpu: &self.gpu,
                luts: &mut self.gpu_luts,
            })
        } else {
            Box::new(CpuSkyViews)
        };
        let mut plan = FramePlan::prepare(scene, state, &mut self.store, source.as_mut())?;
        plan.precompute_ms += gpu_lut_ms;
        if on_gpu {
            plan.lut_origin = LutOrigin::Gpu;
        }
        Ok((plan, on_gpu))
    }

    /// Renders one frame into a new target texture, leaving it on the GPU.
    pub fn render_frame(
        &mut self,
        scene: &Scene,
        state: &SkyState,
    ) -> Result<GpuFrame, RenderError> {
        scene.validate().map_err(RenderError::Scene)?;
        let layout = FrameLayout::new(&self.gpu, &scene.camera, self.max_band_bytes)?;
        let (mut plan, _) = self.plan(scene, state)?;
        let scope = self
            .gpu
            .device
            .push_error_scope(wgpu::ErrorFilter::Validation);
        let mut build = FrameBuild::new(frame::base_uniforms(&scene.camera, state));
        self.passes.clouds.history.begin_frame();
        let prepared = self.prepare_steps(scene, &mut plan, &layout, &mut build);
        // A frame without the clouds' history breaks their sequence.
        self.passes.clouds.history.end_frame();
        let (steps, mut stats, points) = prepared?;
        let target = layout.target(&self.gpu);
        let view = target.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let bound = build.bind(&self.gpu, &self.pool, &self.passes.sky, &layout, &view);
        let times = self.record(&layout, &bound, &steps)?;
        for ((stat, _), t) in steps.iter().zip(&times) {
            if let Some(s) = stat.and_then(|i| stats.get_mut(i)) {
                s.ms = Some(s.ms.unwrap_or(0.0) + t);
            }
        }
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RenderError::Device(e.to_string()));
        }
        stats.extend(PassStat::moon_eclipse(state));
        let mut lights = self.observer_lights(scene, state, &mut plan)?;
        if scene.world.is_some() && plan.runs(Effect::World) {
            let world_stats = self.render_world(scene, state, &plan, &lights, &target)?;
            // The sky light the world received, from its own cube map.
            if let Some(env) = self.env_light() {
                lights.sky_horizontal_rgb = env.horizontal_rgb;
            }
            let world_ms: f64 = world_stats
                .iter()
                .filter(|s| s.name.starts_with("world/"))
                .filter_map(|s| s.ms)
                .sum();
            for s in stats.iter_mut() {
                match s.name.as_str() {
                    "world" => s.ms = Some(world_ms),
                    "shadows" | "godrays" | "ao" | "ssr" | "temporal" => {
                        if let Some(w) = world_stats.iter().find(|w| w.name == s.name) {
                            *s = w.clone();
                        }
                    }
                    _ => {}
                }
            }
            stats.extend(world_stats.into_iter().filter(|s| {
                !matches!(
                    s.name.as_str(),
                    "shadows" | "godrays" | "ao" | "ssr" | "temporal"
                )
            }));
        }
        Ok(GpuFrame {
            texture: target,
            width: layout.width,
            height: layout.height,
            cube: layout.cube,
            passes: stats,
            precompute_ms: plan.precompute_ms,
            lut_source: plan.lut_origin,
            sky_view_ms: plan.sky_view_ms,
            cloud_maps_ms: plan.clouds.as_ref().map_or(0.0, |c| c.height_field_ms),
            cloud_grid_ms: plan.clouds.as_ref().map_or(0.0, |c| c.diffusion_grid_ms),
            points,
            lights,
        })
    }

    /// The plan's observer lights, the sky views from the GPU (read back)
    /// or the CPU as the renderer computes them.
    fn observer_lights(
        &mut self,
        scene: &Scene,
        state: &SkyState,
        plan: &mut FramePlan,
    ) -> Result<himmel_skymodel::frame::ObserverLights, RenderError> {
        if self.sky_view_on_gpu {
            plan.observer_lights(
                scene,
                state,
                &mut GpuSkyViews {
                    pass: &mut self.passes.sky_view,
                    gpu: &self.gpu,
                    luts: &mut self.gpu_luts,
                },
            )
        } else {
            plan.observer_lights(scene, state, &mut CpuSkyViews)
        }
    }

    /// Prepares every pass the plan runs, back to front, then the store:
    /// the steps (each with the index of the `--stats` entry its time goes
    /// to), the entries, and how the point sources are drawn.
    #[allow(clippy::type_complexity)]
    fn prepare_steps(
        &mut self,
        scene: &Scene,
        plan: &mut FramePlan,
        layout: &FrameLayout,
        build: &mut FrameBuild,
    ) -> Result<
        (
            Vec<(Option<usize>, Box<dyn Step>)>,
            Vec<PassStat>,
            Option<PointMethod>,
        ),
        RenderError,
    > {
        let (gpu, pool, p) = (&self.gpu, &self.pool, &mut self.passes);
        let cam = &scene.camera;
        let mut steps: Vec<(Option<usize>, Box<dyn Step>)> = Vec::new();
        let mut stats = Vec::new();
        let (moon, corona) = p.moon.prepare(gpu, pool, plan, cam);
        let (mut moon, mut corona) = (moon, corona);
        let points = p.points.prepare(gpu, pool, scene, plan, layout, build)?;
        for planned in plan.passes.clone() {
            let stat = stats.len();
            stats.push(PassStat {
                name: planned.effect.name().into(),
                ran: planned.run,
                ms: None,
                reason: planned.reason.as_ref().map(ToString::to_string),
            });
            if !planned.run {
                continue;
            }
            let mut add = |s: Box<dyn Step>| steps.push((Some(stat), s));
            match planned.effect {
                Effect::Atmosphere => {
                    let on_gpu = self.sky_view_on_gpu;
                    p.sky_view
                        .prepare(gpu, pool, &mut self.gpu_luts, plan, on_gpu, build)?;
                    add(Box::new(p.atmosphere.step()));
                }
                Effect::Sun => {
                    if let Some(s) = p.sun.prepare(gpu, pool, plan, build) {
                        add(Box::new(s));
                    }
                    if let Some(c) = corona.take() {
                        add(Box::new(c));
                    }
                }
                Effect::Moon => {
                    if let Some(m) = moon.take() {
                        add(Box::new(m));
                    }
                }
                Effect::Milkyway => {
                    if let Some(m) = p.milkyway.prepare(gpu, pool, plan, build) {
                        add(Box::new(m));
                    }
                }
                Effect::Stars | Effect::Planets => {
                    for s in p.points.steps(planned.effect) {
                        add(s);
                    }
                }
                Effect::Texture => {
                    if let Some(t) = p.texture.prepare(gpu, plan)? {
                        add(Box::new(t));
                    }
                }
                Effect::Clouds => {
                    if let Some(c) =
                        p.clouds
                            .prepare(gpu, &mut self.gpu_luts, scene, plan, layout)?
                    {
                        add(Box::new(c));
                    }
                }
                // The world, its shadows, light shafts and ambient
                // occlusion are drawn after the sky (world_frame.rs).
                Effect::World
                | Effect::Shadows
                | Effect::Godrays
                | Effect::Ao
                | Effect::Ssr
                | Effect::Temporal => {}
                other => {
                    // `--backend auto` then falls back to the CPU.
                    return Err(RenderError::Unavailable(Unavailable::PassNotPorted(other)));
                }
            }
        }
        steps.push((None, Box::new(p.store.step())));
        Ok((steps, stats, points))
    }

    /// Records every step band by band and submits: one submission timed
    /// by timestamp queries, or each step submitted and awaited under the
    /// CPU clock. Returns each step's time summed over the bands, ms.
    fn record(
        &self,
        layout: &FrameLayout,
        bound: &frame::BoundFrame,
        steps: &[(Option<usize>, Box<dyn Step>)],
    ) -> Result<Vec<f64>, RenderError> {
        let gpu = &self.gpu;
        let mut timer = Timer::new(gpu, self.timestamps, steps.len(), layout.bands.len());
        let accum = self.pool.get(
            &gpu.device,
            pool::Slot::Accum,
            layout.accum_bytes(),
            wgpu::BufferUsages::STORAGE,
        );
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        for (b, &(row0, rows)) in layout.bands.iter().enumerate() {
            enc.clear_buffer(&accum, 0, Some(layout.accum_bytes()));
            let band = Band {
                index: b,
                row0,
                rows,
                width: layout.width,
                sky: &bound.groups[b],
                frame: &bound.uniforms[b],
                night: &bound.night,
                points: &bound.points,
                tiles: &bound.tiles,
            };
            for (k, (_, step)) in steps.iter().enumerate() {
                let t0 = Clock::now();
                step.record(&mut enc, &band, timer.slot(b, k));
                if !timer.on_gpu() {
                    let done = std::mem::replace(
                        &mut enc,
                        gpu.device.create_command_encoder(&Default::default()),
                    );
                    gpu.queue.submit([done.finish()]);
                    gpu.wait()?;
                    timer.add_cpu(k, ms(t0));
                }
            }
        }
        gpu.queue.submit([enc.finish()]);
        timer.times(gpu, &self.pool, layout.bands.len())
    }

    /// The number of per-frame buffers kept across frames (tables,
    /// uniforms, the accumulation band, read-back): constant for a repeated
    /// scene, so a real-time loop allocates only each frame's target texture.
    pub fn pooled_buffers(&self) -> usize {
        self.pool.len()
    }

    /// The ambient-occlusion image (AO and bent normals) of the last world
    /// frame that ran the `ao` pass (`None` before the first).
    pub fn ao_image(&self) -> Result<Option<AoImage>, RenderError> {
        self.lighting.ao_image(&self.gpu)
    }

    /// The reflections' confidence image of the last world frame that ran
    /// the `ssr` pass (`None` before the first).
    pub fn ssr_image(&self) -> Result<Option<SsrImage>, RenderError> {
        self.lighting.ssr_image(&self.gpu)
    }

    /// The temporal filter's distance and frame count per pixel after the
    /// last world frame that ran the `temporal` pass (`None` before the
    /// first).
    pub fn temporal_image(&self) -> Result<Option<TemporalImage>, RenderError> {
        self.lighting.temporal_image(&self.gpu)
    }

    /// Forgets the last frame's cloud lattice: the next frame marches every
    /// coarse node (its `cloud_history` says `first frame`).
    pub fn clear_cloud_history(&mut self) {
        self.passes.clouds.history.clear();
    }

    /// What the low clouds' history gave the last frame
    /// (`clouds.low.reproject`; `None` when it kept none): the nodes
    /// reused and marched, read back from the GPU (waits for the frame).
    pub fn cloud_history(&mut self) -> Result<Option<HistoryUse>, RenderError> {
        self.passes.clouds.history.read_use(&self.gpu)
    }

    /// Copies a frame back into an [`HdrImage`] (a cube map as its 6H×H
    /// strip).
    pub fn read_back(&self, frame: &GpuFrame) -> Result<HdrImage, RenderError> {
        frame::read_back(&self.gpu, &self.pool, frame)
    }
}

impl SkyRenderer for WgpuRenderer {
    fn name(&self) -> &'static str {
        "wgpu"
    }

    fn render(&mut self, scene: &Scene, state: &SkyState) -> Result<RenderOutput, RenderError> {
        let frame = self.render_frame(scene, state)?;
        let image = self.read_back(&frame)?;
        let cloud_history = self.cloud_history()?;
        Ok(RenderOutput {
            image,
            passes: frame.passes,
            precompute_ms: frame.precompute_ms,
            lut_source: frame.lut_source,
            geometry_ms: 0.0,
            sky_view_ms: frame.sky_view_ms,
            cloud_maps_ms: frame.cloud_maps_ms,
            cloud_grid_ms: frame.cloud_grid_ms,
            cloud_history,
            lights: frame.lights,
        })
    }
}
