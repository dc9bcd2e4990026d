//! `himmel-wgpu`: the GPU renderer of Himmel on wgpu, headless (Vulkan,
//! Metal, DX12 — any adapter, software ones such as Mesa's lavapipe
//! included).
//!
//! Every sky pass is a WGSL compute shader (`src/shaders/`: one file per
//! pass after `frame.wgsl`, the bindings and projection helpers they share,
//! compiled as one module per pass, [`uniforms`]) that adds its radiance (linear sRGB, cd/m², conventions.md Photometry) into
//! a per-pixel accumulation buffer, back to front, as the CPU reference
//! renderer (`himmel-cpu`) does; a final `store` pass writes the frame into
//! an `rgba32float` texture: one layer for fisheye, equirect and
//! perspective images, six layers (+X −X +Y −Y +Z −Z, scene frame,
//! conventions.md) for a cube map, which users can bind as a
//! `TextureViewDimension::Cube` texture ([`WgpuRenderer::render_cubemap`]).
//!
//! * Atmosphere: the parameter-dependent LUTs (Hillaire 2020:
//!   transmittance, its δ-scaled twin, multiple scattering Ψ_ms) come from
//!   [`LutSource::Gpu`] — compute shaders ([`luts`], `src/shaders/luts.wgsl`,
//!   a port of the CPU precompute with the same parametrisation, step
//!   counts and directions, within the f32 rounding bound of
//!   tests/gpu_luts.rs), read back once for the CPU-side tables — or
//!   [`LutSource::Cpu`] — `himmel-cpu`'s precompute (in-memory and on-disk
//!   cache), uploaded. The default is the GPU on a hardware adapter and
//!   the CPU on a software one such as lavapipe, which shares the CPU's
//!   cores: there the shaders measured only ≈ 20 % faster than the CPU
//!   precompute, whose disk cache then serves later processes in ≈ 1 ms
//!   ([`LutSource::default_for`], `benches/render.rs` group `precompute`;
//!   [`WgpuRenderer::set_lut_source`] overrides it). Either way they stay
//!   on the GPU while the parameters and configuration do not change. The
//!   per-frame sky-view LUT is computed on the GPU (`skyview.wgsl`) or on
//!   the CPU and uploaded; the shader computes each
//!   pixel's view direction from the projection (projection.rs in f32) and
//!   looks the sky view up bilinearly (lut.rs `SkyView::radiance`). On a
//!   moonlit night (`himmel_skymodel::moon::moonlight_scale`) a second sky
//!   view lit from the Moon follows the Sun's in the same buffer and the
//!   shader adds its lookup with the Moon's direction (cpu lib.rs
//!   `SkyLight`).
//! * Sun: the disk (limb darkening of Hestroffer & Magnan 1998, extinction
//!   by the transmittance LUT) is tabulated on the CPU as linear sRGB over
//!   (normalised disk radius ρ, nodes uniform in asin ρ; line-of-sight
//!   zenith cosine) — the exact `SunDisk::radiance_rgb` at the nodes — and
//!   the shader supersamples
//!   pixels near the disk with [`himmel_cpu::SUN_SUPERSAMPLING`]² sub-pixel
//!   directions, as the CPU does.
//!
//! * Milky Way / night-sky light: skymodel milkyway.rs
//!   `NightBackground::radiance` per pixel (map uploaded once as a storage
//!   buffer, floor, zodiacal light, airglow; per-frame constants in
//!   [`NightUniforms`]) times the CPU's `Extinction` table, whose fourth lane
//!   carries the refraction `unrefracted` takes off low altitudes
//!   ([`night_inputs`]).
//! * Stars and planets: the CPU computes each source's footprint as its
//!   splat does (`himmel_skymodel::stars::splat_plan`: position,
//!   extinction, normalisations of the core and the glare disk) and bins it
//!   into [`POINT_TILE`]² tiles ([`point_lists`]). Two ways to draw them
//!   ([`WgpuRenderer::set_point_method`]), both evaluating the same WGSL
//!   footprint function (points.wgsl `point_footprint`, the CPU's `splat_at`)
//!   on the same records: [`PointMethod::Tiles`], one invocation per pixel
//!   of each non-empty tile summing the footprints of its tile's list over
//!   the pixel's solid angle (no atomics); [`PointMethod::Quads`]
//!   (`src/shaders/quads.wgsl`), a render pass drawing one instanced quad
//!   per record (6 vertices from `vertex_index`, the record read by
//!   `instance_index` from a storage buffer; no geometry shader) over the
//!   footprint's pixel bounds, core and glare disk, clipped to the band and
//!   in a cube map to the record's face (equirect records are per wrap
//!   already); the fragment shader returns footprint / Ω, added by the
//!   blend state (One, One) into a band-sized float target —
//!   `Rgba32Float` where the adapter has `FLOAT32_BLENDABLE` (requested
//!   then; lavapipe has it), otherwise `Rgba16Float`, scaled by a power of
//!   two ([`quad_scale`]) so that the brightest footprint stays below its
//!   65504 and faint stars above its subnormals; its 11-bit significand
//!   costs up to 0.64 % per pixel against the tiles (above 10⁻⁸ × the
//!   brightest pixel; fainter pixels lose more) and moves the median
//!   difference to the CPU from 0.0001 % to 0.04 % — which compute passes
//!   (`quad_resolve_*`, one workgroup per non-empty tile) add into the
//!   accumulation buffer at the pass's place in the order (the Moon pass
//!   after it replaces that light by its coverage). With rgba32float the
//!   two methods agree per pixel to ≤ 1e-6 in luminance (tests/quads.rs).
//!   Timestamps cover the draw and the resolve. The non-empty tiles of the
//!   target are zeroed by a draw before the footprints (no full-target
//!   clear). On lavapipe (2 cores) a 1920×1080 fisheye night frame (stars +
//!   planets + atmosphere) took 193–201 ms with quads and 193–200 ms with
//!   tiles (85–88 ms on the CPU backend; `benches/render.rs`, group
//!   `night`, three runs) — a tie. The default ([`PointMethod::default_for`])
//!   is nevertheless tiles on software adapters: lavapipe's timestamp
//!   queries do not follow its deferred rasteriser, and with a render pass
//!   in the submission they put the compute passes' time elsewhere (a
//!   1024² night frame reported the Milky Way pass at 0.13 ms instead of
//!   ≈ 35 ms), which would make `--stats` wrong; quads on hardware GPUs,
//!   where the rasteriser touches only the footprints' pixels (no hardware
//!   GPU was lent to measure them there).
//!
//! * Moon (`src/shaders/moon.wgsl`, compiled after `frame.wgsl` in one
//!   module, with its own bind group 1): skymodel moon.rs
//!   `MoonShader::{sky_xy, surface_point, radiance, shade}` and cpu
//!   moon_pass.rs `render` per pixel of the disk's bounding rectangle
//!   ([`sun_rect`] around the centre, radius + 2 pixels) — the
//!   albedo and normal maps (uploaded once as one storage buffer, bilinear
//!   as on the CPU, `fast_atan2` for the selenographic coordinates), the
//!   Lommel–Seeliger × opposition surge × phase-law factor, earthshine, and
//!   the per-frame tables built on the CPU with the CPU's own code and
//!   interpolated on the GPU like the CPU interpolates them: extinction
//!   across the disk, the lunar-eclipse table (160 axis distances) and, for
//!   a Moon below 15°, Bennett's refraction that `unrefract` takes off each
//!   pixel ([`moon_uniforms`], [`uniforms::MoonUniforms`]). The disk replaces what
//!   the earlier passes (Milky Way, stars, planets) drew by its coverage
//!   (analytic limb; disks under 16 px in radius supersampled 4 × 4 or
//!   8 × 8 as on the CPU); `--stats` adds the CPU's `moon-eclipse` entry.
//! * Solar eclipses: the Sun pass skips the sub-samples behind the Moon's
//!   disk (`FrameUniforms::eclipse_moon`), and the inner corona
//!   (moon_pass.rs `render_corona`; the disk's mean radiance × the
//!   transmittance tabulated over the zenith cosine) is a second dispatch
//!   of the Sun pass over the rectangle within 6 R☉.
//!
//! Adding a pass: a WGSL file with an entry point of the same shape as
//! `atmosphere`/`sun` that adds into `accum` (extra tables go into further
//! bindings, or a second bind group as the Moon's), its module constant
//! (frame.wgsl + the file) in [`uniforms`], a pipeline in `Pipelines`, and
//! its `Effect` arm where `render_frame`
//! maps planned passes to pipelines and dispatch rectangles; the parity
//! tests then compare it with the CPU pass.
//!
//! Per-pass times come from timestamp queries where the adapter supports
//! them (`Features::TIMESTAMP_QUERY`), otherwise from the CPU clock around
//! each submitted and awaited pass ([`WgpuRenderer::timing`]).

pub mod luts;
pub mod uniforms;

use std::path::PathBuf;
use std::time::Instant as Clock;

use glam::{DVec3, Vec3};
use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::{AtmosphereLuts, SkyViewInput};
use himmel_skymodel::renderer::{HdrImage, PassStat, RenderError, RenderOutput, SkyRenderer};
use himmel_skymodel::spectrum::Spectrum;
use himmel_skymodel::sun::SunDisk;
use himmel_skymodel::{Camera, Effect, Projection, Scene, SkyState};
use wgpu::util::DeviceExt;

pub use luts::LutSource;
use uniforms::{projection_code, SKYVIEW_WGSL};
pub use uniforms::{AtmosphereUniforms, FrameUniforms, NightUniforms, PointRecord};

/// Nodes of the Sun table in normalised disk radius ρ.
pub const SUN_TABLE_RHO: usize = 64;
/// Nodes of the Sun table in line-of-sight zenith cosine.
pub const SUN_TABLE_Z: usize = 128;

/// The texture format of every render target.
pub const TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Why the GPU backend cannot start.
#[derive(Debug, Clone, PartialEq)]
pub enum WgpuError {
    /// No adapter of the enabled backends (`WGPU_BACKEND`) exists.
    NoAdapter(String),
    /// The adapter refused to create a device.
    Device(String),
}

impl std::fmt::Display for WgpuError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WgpuError::NoAdapter(m) => write!(f, "no wgpu adapter available ({m})"),
            WgpuError::Device(m) => write!(f, "the wgpu adapter cannot create a device ({m})"),
        }
    }
}

impl std::error::Error for WgpuError {}

impl From<WgpuError> for RenderError {
    fn from(e: WgpuError) -> Self {
        RenderError::Unavailable(e.to_string())
    }
}

/// How per-pass times were measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Timing {
    /// GPU timestamp queries around each compute pass.
    GpuTimestamps,
    /// CPU clock around each submitted pass, waiting for its completion.
    Cpu,
}

impl Timing {
    /// The `--stats` name: `gpu-timestamps` or `cpu`.
    pub fn name(self) -> &'static str {
        match self {
            Timing::GpuTimestamps => "gpu-timestamps",
            Timing::Cpu => "cpu",
        }
    }
}

/// How the stars' and planets' footprints are drawn. Both evaluate the
/// same per-pixel footprint (points.wgsl `point_footprint`) from the same
/// records ([`point_lists`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointMethod {
    /// Compute passes: one workgroup per non-empty 8 × 8 tile, each pixel
    /// sums the footprints listed for its tile (points.wgsl `stars`/`planets`).
    Tiles,
    /// A render pass: one instanced quad per footprint record (vertex +
    /// fragment shaders, no geometry shader, quads.wgsl), added by the blend
    /// state into a float target ([`WgpuRenderer::quad_format`]) that a
    /// compute pass then adds into the frame.
    Quads,
}

impl PointMethod {
    /// The `--stats` name: `tiles` or `quads`.
    pub fn name(self) -> &'static str {
        match self {
            PointMethod::Tiles => "tiles",
            PointMethod::Quads => "quads",
        }
    }

    /// The default for an adapter of this type: tiles on a software
    /// adapter (`DeviceType::Cpu`, e.g. lavapipe), quads on every other.
    /// On lavapipe the two tie in frame time (`benches/render.rs`, group
    /// `night`), but its timestamp queries misattribute the compute passes'
    /// time once a render pass is in the submission (the `--stats` per-pass
    /// times would be wrong); on hardware GPUs the rasteriser touches only
    /// the footprints' pixels (not measured: no GPU was lent).
    pub fn default_for(device_type: wgpu::DeviceType) -> Self {
        match device_type {
            wgpu::DeviceType::Cpu => PointMethod::Tiles,
            _ => PointMethod::Quads,
        }
    }
}

/// The point-source quads: the draw (bind group 0: frame, night
/// constants, records) and the resolve pass (the sky's bind group 0 and the
/// quad target in group 1).
struct QuadPipelines {
    draw_layout: wgpu::BindGroupLayout,
    target_layout: wgpu::BindGroupLayout,
    draw: wgpu::RenderPipeline,
    /// Zeroes the non-empty tiles before the draw (no full-target clear).
    clear: wgpu::RenderPipeline,
    /// The resolve passes of the stars' and the planets' lists.
    resolve: [wgpu::ComputePipeline; 2],
}

struct Pipelines {
    layout: wgpu::BindGroupLayout,
    atmosphere: wgpu::ComputePipeline,
    sun: wgpu::ComputePipeline,
    milkyway: wgpu::ComputePipeline,
    stars: wgpu::ComputePipeline,
    planets: wgpu::ComputePipeline,
    store: wgpu::ComputePipeline,
}

/// A frame left on the GPU: the target texture (rgba32float; 1 layer, or 6
/// cube faces) and the frame's statistics.
#[derive(Debug)]
pub struct GpuFrame {
    /// The target: `TEXTURE_BINDING | STORAGE_BINDING | COPY_SRC`, alpha 1
    /// where the projection shows the scene. A cube map's six layers are
    /// the faces +X −X +Y −Y +Z −Z of the scene frame (x East, y Up,
    /// z South): bind it through a `TextureViewDimension::Cube` view.
    pub texture: wgpu::Texture,
    /// Image width and height (the 6H×H strip for a cube map).
    pub width: u32,
    /// Image height (the face size for a cube map).
    pub height: u32,
    /// Whether the texture holds six cube faces.
    pub cube: bool,
    /// Per-pass statistics, back to front.
    pub passes: Vec<PassStat>,
    /// LUT time (memory, disk or computation), ms.
    pub precompute_ms: f64,
    /// Where the LUTs came from: `gpu` (computed by the LUT compute
    /// shaders for this frame), `memory` (kept from an earlier frame),
    /// `disk-cache`, `computed` (CPU precompute), `none`.
    pub lut_source: &'static str,
    /// CPU time of the per-frame sky-view LUT, ms.
    pub sky_view_ms: f64,
    /// How the stars and planets were drawn (`None` when neither pass
    /// ran): the renderer's [`PointMethod`], or tiles where a quad target
    /// of the image's width exceeds the adapter's texture limit.
    pub points: Option<PointMethod>,
}

/// The wgpu renderer.
pub struct WgpuRenderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
    pipelines: Pipelines,
    timestamps: bool,
    timestamps_supported: bool,
    max_band_bytes: Option<u64>,
    /// The CPU renderer whose LUT cache (memory and disk) feeds the GPU.
    cpu: CpuRenderer,
    skyview: SkyViewPipelines,
    gpu_luts: Option<GpuLuts>,
    /// Where the parameter-dependent LUTs come from.
    lut_source: LutSource,
    /// The LUT passes, compiled on first use.
    lut_pipelines: Option<luts::LutPipelines>,
    /// The GPU sky view's buffers, kept across frames.
    sky_view_buffers: Option<SkyViewBuffers>,
    sky_view_on_gpu: bool,
    /// The Milky Way map (uploaded on first use) and its width, height.
    mw_map: Option<(wgpu::Buffer, u32, u32)>,
    moon: MoonPipelines,
    /// The lunar albedo and normal maps (uploaded on first use) and their
    /// sizes (albedo width, height; normal map width, height).
    moon_maps: Option<(wgpu::Buffer, [u32; 4])>,
    /// The per-frame buffers (tables, uniforms, accumulation, read-back),
    /// kept across frames.
    pool: BufferPool,
    point_method: PointMethod,
    quads: QuadPipelines,
    /// The quad target's format: rgba32float when the adapter blends it.
    quad_format: wgpu::TextureFormat,
    /// The quad target (band-sized), kept across frames.
    quad_target: Option<wgpu::Texture>,
}

/// Buffers kept across frames, one per slot name: a frame rewrites a
/// slot with `Queue::write_buffer` (ordered after every earlier
/// submission's reads) and a new buffer is made only when the frame needs a
/// larger one or another usage, so a real-time loop allocates nothing per
/// frame but its target texture.
#[derive(Default)]
struct BufferPool(std::sync::Mutex<std::collections::HashMap<&'static str, wgpu::Buffer>>);

impl BufferPool {
    /// The slot's buffer, at least `size` bytes (and 16), with `usage` and
    /// `COPY_DST`. A grown buffer gets the next power of two within the
    /// adapter's buffer limit, so a slightly larger next frame reuses it.
    fn get(
        &self,
        dev: &wgpu::Device,
        slot: &'static str,
        size: u64,
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        let size = size.max(16).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        let mut slots = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(b) = slots.get(slot) {
            if b.size() >= size && b.usage() == usage {
                return b.clone();
            }
        }
        let grown = size
            .next_power_of_two()
            .min(dev.limits().max_buffer_size)
            .max(size);
        let b = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some(slot),
            size: grown,
            usage,
            mapped_at_creation: false,
        });
        slots.insert(slot, b.clone());
        b
    }

    /// The slot's buffer holding `bytes` from offset 0, and the binding of
    /// exactly those bytes (16 zero bytes when `bytes` is empty).
    fn upload(
        &self,
        dev: &wgpu::Device,
        queue: &wgpu::Queue,
        slot: &'static str,
        bytes: &[u8],
        usage: wgpu::BufferUsages,
    ) -> PoolBinding {
        let buffer = self.get(dev, slot, bytes.len() as u64, usage);
        let size = if bytes.is_empty() {
            queue.write_buffer(&buffer, 0, &[0u8; 16]);
            16
        } else {
            queue.write_buffer(&buffer, 0, bytes);
            bytes.len() as u64
        };
        PoolBinding {
            buffer,
            offset: 0,
            size,
        }
    }

    /// The number of buffers held.
    fn len(&self) -> usize {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).len()
    }
}

/// A range of a pooled buffer, as bound by a frame.
struct PoolBinding {
    buffer: wgpu::Buffer,
    offset: u64,
    size: u64,
}

impl PoolBinding {
    fn resource(&self) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.buffer,
            offset: self.offset,
            size: std::num::NonZeroU64::new(self.size),
        })
    }
}

/// The Moon pass and the corona (frame.wgsl + moon.wgsl): bind group 0 is
/// the sky passes', bind group 1 the Moon's uniform and maps.
struct MoonPipelines {
    layout: wgpu::BindGroupLayout,
    disk: wgpu::ComputePipeline,
    corona: wgpu::ComputePipeline,
}

struct SkyViewPipelines {
    layout: wgpu::BindGroupLayout,
    sky_view: wgpu::ComputePipeline,
    ground: wgpu::ComputePipeline,
}

/// The parameter-dependent LUTs on the GPU (three vec4 band groups per
/// texel), for the parameters they were uploaded or computed for.
struct GpuLuts {
    params: himmel_skymodel::atmosphere::AtmosphereParams,
    config: himmel_skymodel::atmosphere::LutConfig,
    /// Computed by the LUT compute shaders (not uploaded).
    on_gpu: bool,
    trans: wgpu::Buffer,
    trans_s: wgpu::Buffer,
    multi: wgpu::Buffer,
}

impl std::fmt::Debug for WgpuRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WgpuRenderer")
            .field("adapter", &self.info.name)
            .field("backend", &self.info.backend)
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
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|e| WgpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut features = if timestamps {
            wgpu::Features::TIMESTAMP_QUERY
        } else {
            wgpu::Features::empty()
        };
        // Additive blending into rgba32float for the point-source quads.
        let blend32 = adapter
            .features()
            .contains(wgpu::Features::FLOAT32_BLENDABLE);
        if blend32 {
            features |= wgpu::Features::FLOAT32_BLENDABLE;
        }
        let quad_format = if blend32 {
            wgpu::TextureFormat::Rgba32Float
        } else {
            wgpu::TextureFormat::Rgba16Float
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("himmel"),
            required_features: features,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| WgpuError::Device(e.to_string()))?;
        let pipelines = Self::pipelines(&device);
        let skyview = skyview_pipelines(&device);
        let lut_source = LutSource::default_for(info.device_type);
        let quads = quad_pipelines(&device, &pipelines.layout, quad_format);
        Ok(WgpuRenderer {
            point_method: PointMethod::default_for(info.device_type),
            quads,
            quad_format,
            quad_target: None,
            moon: moon_pipelines(&device, &pipelines.layout),
            device,
            queue,
            info,
            pipelines,
            timestamps,
            timestamps_supported: timestamps,
            max_band_bytes: None,
            cpu: CpuRenderer::new(cache_dir),
            skyview,
            gpu_luts: None,
            lut_source,
            lut_pipelines: None,
            sky_view_buffers: None,
            sky_view_on_gpu: true,
            mw_map: None,
            moon_maps: None,
            pool: BufferPool::default(),
        })
    }

    /// The image passes: one shader module per pass ([`uniforms`]), one
    /// bind group layout for all (every module declares the same group 0,
    /// frame.wgsl; the explicit pipeline layout holds the bindings a pass
    /// does not use), so one bind group per band serves every pass.
    fn pipelines(device: &wgpu::Device) -> Pipelines {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sky"),
            entries: &[
                uniform_entry::<FrameUniforms>(0),
                storage_entry(1, false),
                storage_entry(2, true),
                storage_entry(3, true),
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: TARGET_FORMAT,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                    },
                    count: None,
                },
                uniform_entry::<NightUniforms>(5),
                storage_entry(6, true),
                storage_entry(7, true),
                storage_entry(8, true),
                storage_entry(9, true),
            ],
        });
        let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sky"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = |label, wgsl: &str| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(wgsl.into()),
            })
        };
        let pipeline = |module: &wgpu::ShaderModule, entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pl),
                module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let points = module("points.wgsl", uniforms::POINTS_WGSL);
        Pipelines {
            atmosphere: pipeline(
                &module("atmosphere.wgsl", uniforms::ATMOSPHERE_WGSL),
                "atmosphere",
            ),
            sun: pipeline(&module("sun.wgsl", uniforms::SUN_WGSL), "sun"),
            milkyway: pipeline(
                &module("milkyway.wgsl", uniforms::MILKYWAY_WGSL),
                "milkyway",
            ),
            stars: pipeline(&points, "stars"),
            planets: pipeline(&points, "planets"),
            store: pipeline(&module("store.wgsl", uniforms::STORE_WGSL), "store"),
            layout,
        }
    }

    /// Chooses how stars and planets are drawn (default:
    /// [`PointMethod::default_for`] the adapter).
    pub fn set_point_method(&mut self, method: PointMethod) {
        self.point_method = method;
    }

    /// How stars and planets are drawn.
    pub fn point_method(&self) -> PointMethod {
        self.point_method
    }

    /// The format of the point-source quad target: `Rgba32Float` where the
    /// adapter offers `Features::FLOAT32_BLENDABLE` (requested then),
    /// otherwise `Rgba16Float` (11-bit significand: each quad pass's sum
    /// rounded to ≈ 5e-4 relative, radiance above 65504 cd/m² saturating).
    pub fn quad_format(&self) -> wgpu::TextureFormat {
        self.quad_format
    }

    /// Sets the point-source quad target's format: `Rgba16Float` (any
    /// adapter) or `Rgba32Float` (where the device has
    /// `Features::FLOAT32_BLENDABLE`, which [`Self::new`] requests when the
    /// adapter offers it); other formats are refused. Recompiles the draw.
    pub fn set_quad_format(&mut self, format: wgpu::TextureFormat) -> Result<(), RenderError> {
        let ok = match format {
            wgpu::TextureFormat::Rgba16Float => true,
            wgpu::TextureFormat::Rgba32Float => self
                .device
                .features()
                .contains(wgpu::Features::FLOAT32_BLENDABLE),
            _ => false,
        };
        if !ok {
            return Err(RenderError::Unavailable(format!(
                "the point-source quads cannot blend into {format:?} on this adapter"
            )));
        }
        if format != self.quad_format {
            self.quads = quad_pipelines(&self.device, &self.pipelines.layout, format);
            self.quad_format = format;
            self.quad_target = None;
        }
        Ok(())
    }

    /// The device (to bind [`GpuFrame::texture`] in your own passes).
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue of [`Self::device`].
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// The adapter: name, backend, device type (`Cpu` for lavapipe).
    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.info
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
        self.timestamps = on && self.timestamps_supported;
    }

    /// Caps the accumulation buffer (bytes; `None`: the adapter's storage
    /// buffer limit). Frames larger than the cap render in bands of rows.
    pub fn set_max_band_bytes(&mut self, cap: Option<u64>) {
        self.max_band_bytes = cap;
    }

    /// Computes the per-frame sky-view LUT in a compute shader (`true`,
    /// the default) or on the CPU (uploaded each frame).
    pub fn set_sky_view_on_gpu(&mut self, on: bool) {
        self.sky_view_on_gpu = on;
    }

    /// Chooses where the parameter-dependent LUTs come from (default:
    /// [`LutSource::default_for`] the adapter's type). A change drops the
    /// LUTs held in memory, so the next frame computes or loads them anew.
    pub fn set_lut_source(&mut self, source: LutSource) {
        if source != self.lut_source {
            self.lut_source = source;
            self.gpu_luts = None;
            self.cpu.replace_luts(None);
        }
    }

    /// Where the parameter-dependent LUTs come from.
    pub fn lut_source(&self) -> LutSource {
        self.lut_source
    }

    /// Computes the parameter-dependent LUTs for `params`/`config` anew
    /// from the current [`LutSource`], bypassing the memory and disk
    /// caches, and keeps them for the next frames: on the GPU (compute,
    /// await, read back) or on the CPU (all cores) and uploaded. Returns
    /// after the GPU has finished. For benchmarks and warm-up.
    pub fn precompute_luts(
        &mut self,
        params: &himmel_skymodel::atmosphere::AtmosphereParams,
        config: &himmel_skymodel::atmosphere::LutConfig,
    ) -> Result<(), RenderError> {
        self.gpu_luts = None;
        match self.lut_source {
            LutSource::Gpu => {
                self.ensure_gpu_luts(params, config)?;
            }
            LutSource::Cpu => {
                let l = himmel_cpu::precompute(params, config, false);
                upload_luts(&self.device, &mut self.gpu_luts, &l);
                self.cpu.replace_luts(Some(l));
                self.wait()?;
            }
        }
        Ok(())
    }

    /// With [`LutSource::Gpu`], makes sure the GPU-computed LUTs for
    /// `params`/`config` are held (computing and reading them back into
    /// the CPU renderer's memory cache, which the CPU-side tables read);
    /// returns whether they were computed now.
    fn ensure_gpu_luts(
        &mut self,
        params: &himmel_skymodel::atmosphere::AtmosphereParams,
        config: &himmel_skymodel::atmosphere::LutConfig,
    ) -> Result<bool, RenderError> {
        if self.lut_source != LutSource::Gpu {
            return Ok(false);
        }
        if let Some(g) = &self.gpu_luts {
            if g.on_gpu && g.params == *params && g.config == *config {
                return Ok(false);
            }
        }
        let pipelines = self
            .lut_pipelines
            .get_or_insert_with(|| luts::LutPipelines::new(&self.device));
        let (bufs, cpu_copy) = luts::compute(&self.device, &self.queue, pipelines, params, config)?;
        self.gpu_luts = Some(GpuLuts {
            params: params.clone(),
            config: *config,
            on_gpu: true,
            trans: bufs.trans,
            trans_s: bufs.trans_s,
            multi: bufs.multi,
        });
        self.cpu.replace_luts(Some(cpu_copy));
        Ok(true)
    }

    /// Whether the sky-view LUT is computed on the GPU.
    pub fn sky_view_on_gpu(&self) -> bool {
        self.sky_view_on_gpu
    }

    /// Shows a progress bar during a long LUT precomputation (terminal only).
    pub fn set_progress(&mut self, on: bool) {
        self.cpu.progress = on;
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

    /// Renders one frame into a new target texture, leaving it on the GPU.
    pub fn render_frame(
        &mut self,
        scene: &Scene,
        state: &SkyState,
    ) -> Result<GpuFrame, RenderError> {
        scene
            .validate()
            .map_err(|e| RenderError::Scene(e.field, e.message))?;
        // Night passes invisible at this exposure are culled as on the CPU.
        let night_frame = self.cpu.night_frame(scene, state);
        let culled_reason = |e: Effect| {
            night_frame
                .as_ref()
                .and_then(|f| f.reason(e))
                .map(str::to_string)
        };
        for p in state.passes.iter().filter(|p| p.run) {
            if culled_reason(p.effect).is_some() {
                continue;
            }
            if !matches!(
                p.effect,
                Effect::Atmosphere
                    | Effect::Sun
                    | Effect::Moon
                    | Effect::Milkyway
                    | Effect::Stars
                    | Effect::Planets
            ) {
                // Unavailable: `--backend auto` then falls back to the CPU.
                return Err(RenderError::Unavailable(format!(
                    "the {} pass is not yet available in the wgpu backend",
                    p.effect.name()
                )));
            }
        }
        let cam = scene.camera;
        let (w, h) = cam.image_size();
        let cube = cam.projection == Projection::Cubemap;
        let (tw, layers) = if cube { (h, 6) } else { (w, 1) };
        let limits = self.device.limits();
        // The accumulation buffer holds a band of rows within the buffer limits.
        let row_bytes = w as u64 * 16;
        let max_bytes = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size)
            .min(self.max_band_bytes.unwrap_or(u64::MAX));
        if tw.max(h) > limits.max_texture_dimension_2d || row_bytes > max_bytes {
            return Err(RenderError::Unavailable(format!(
                "a {w}×{h} image exceeds this wgpu adapter's limits ({} px per side)",
                limits.max_texture_dimension_2d,
            )));
        }
        let band_rows = (max_bytes / row_bytes).min(h as u64).max(1) as u32;
        let bands: Vec<(u32, u32)> = (0..h.div_ceil(band_rows))
            .map(|b| (b * band_rows, band_rows.min(h - b * band_rows)))
            .collect();
        let sun_dir = state.sun.dir().as_vec3().normalize();
        let atmosphere = state.runs(Effect::Atmosphere);
        let moon_runs = state.runs(Effect::Moon);
        let corona_runs = state.runs(Effect::Sun) && state.sun.visible_fraction < 1.0;
        let milkyway = state.runs(Effect::Milkyway) && culled_reason(Effect::Milkyway).is_none();
        // The maps (uploaded once) and the LUTs (GPU or CPU precompute,
        // memory or disk cache): `cpu_luts` then serves every table below.
        let moon_maps = (moon_runs || corona_runs).then(|| self.upload_moon_maps());
        let mw_dims = milkyway.then(|| self.upload_milkyway_map());
        let tp = Clock::now();
        let mut lut_source = "none";
        let cpu_luts = if atmosphere {
            let on_gpu = self.ensure_gpu_luts(&scene.atmosphere, &scene.lut)?;
            let (luts, source) = self.cpu.luts(&scene.atmosphere, &scene.lut);
            lut_source = if on_gpu { "gpu" } else { source };
            Some(luts)
        } else {
            None
        };

        // The sky view on the GPU (default) or on the CPU, uploaded. `sky`
        // holds the sky-view LUT, then the ground luminance.
        let mut precompute_ms = 0.0;
        let mut sky_view_ms = 0.0;
        let (mut sky_w, mut sky_h) = (1u32, 1u32);
        let mut sky = None;
        let mut moonlight = None;
        if let Some(luts) = cpu_luts {
            let mut inputs = vec![SkyViewInput {
                observer_altitude_km: state.observer_altitude_km as f32,
                sun_sin_elevation: sun_dir.z,
                irradiance_scale: state.sun.sky_irradiance_scale() as f32,
            }];
            // The moonlit sky (cpu lib.rs `SkyLight`): a second sky view lit
            // from the Moon, looked up with the Moon's direction.
            let pole = glam::DVec3::from_array(state.celestial_pole).as_vec3();
            if let Some(scale) =
                himmel_skymodel::moon::moonlight_scale(scene, &state.sun, &state.moon, pole)
            {
                let dir = state.moon.dir().as_vec3().normalize();
                inputs.push(SkyViewInput {
                    observer_altitude_km: state.observer_altitude_km as f32,
                    sun_sin_elevation: dir.z,
                    irradiance_scale: scale as f32,
                });
                moonlight = Some(dir);
            }
            sky_w = luts.config.sky_view_w as u32;
            sky_h = luts.config.sky_view_h as u32;
            if self.sky_view_on_gpu {
                let gl = upload_luts(&self.device, &mut self.gpu_luts, luts);
                precompute_ms = ms(tp);
                let tsv = Clock::now();
                sky = Some(gpu_sky_view(
                    &self.device,
                    &self.queue,
                    &self.skyview,
                    gl,
                    luts,
                    &inputs,
                    &mut self.sky_view_buffers,
                )?);
                sky_view_ms = ms(tsv);
            } else {
                precompute_ms = ms(tp);
                let tsv = Clock::now();
                let mut rgba: Vec<[f32; 4]> = Vec::new();
                for input in &inputs {
                    let sv = himmel_cpu::sky_view(luts, input);
                    rgba.extend(sv.lut.data.iter().map(|p| [p[0], p[1], p[2], 0.0]));
                    let g = sv.ground_rgb;
                    rgba.push([g[0], g[1], g[2], 0.0]);
                }
                sky = Some(
                    self.pool
                        .upload(
                            &self.device,
                            &self.queue,
                            "sky view",
                            bytemuck::cast_slice(&rgba),
                            wgpu::BufferUsages::STORAGE,
                        )
                        .buffer,
                );
                sky_view_ms = ms(tsv);
            }
        }
        let sky = match sky {
            Some(b) => b,
            None => {
                self.pool
                    .upload(
                        &self.device,
                        &self.queue,
                        "no sky",
                        bytemuck::cast_slice(&[[0.0f32; 4]; 2]),
                        wgpu::BufferUsages::STORAGE,
                    )
                    .buffer
            }
        };
        // The drawn radius as SunDisk clamps it.
        let radius = (state.sun.angular_radius * scene.sun_scale).clamp(1e-6, 0.5);
        let margin = (radius + 1.5 * cam.max_pixel_angle()).min(3.0);
        let (sun_table, z_range) = if state.runs(Effect::Sun) {
            sun_table(
                sun_dir.z as f64,
                radius,
                state.sun.irradiance_scale,
                cpu_luts,
                state.observer_altitude_km as f32,
            )
        } else {
            (vec![[0.0; 4]; SUN_TABLE_RHO * SUN_TABLE_Z], [0.0, 1.0])
        };

        let sun_rect = sun_rect(&cam, state.sun.dir().normalize(), margin);
        let (f, r, u, t) = perspective_basis(&cam);
        let code = match cam.projection {
            Projection::Fisheye => projection_code::FISHEYE,
            Projection::Equirect => projection_code::EQUIRECT,
            Projection::Perspective => projection_code::PERSPECTIVE,
            Projection::Cubemap => projection_code::CUBEMAP,
        };
        let frame = FrameUniforms {
            width: w,
            height: h,
            projection: code,
            face_size: h,
            forward: f.as_vec3().to_array(),
            tan_half_fov: t as f32,
            right: r.as_vec3().to_array(),
            _pad0: 0.0,
            up: u.as_vec3().to_array(),
            _pad1: 0.0,
            sun: sun_dir.to_array(),
            cos_sun_margin: margin.cos() as f32,
            moonlight: moonlight.unwrap_or(Vec3::ZERO).to_array(),
            moonlit: moonlight.is_some() as u32,
            eclipse_moon: state.moon.dir().as_vec3().to_array(),
            sin_moon_radius: (state.moon.angular_radius * scene.moon_scale).sin() as f32,
            sin_sun_radius: radius.sin() as f32,
            sun_z_min: z_range[0],
            sun_z_max: z_range[1],
            sun_subsamples: himmel_cpu::SUN_SUPERSAMPLING as u32,
            sun_rho_nodes: SUN_TABLE_RHO as u32,
            sun_z_nodes: SUN_TABLE_Z as u32,
            sun_x0: sun_rect.0,
            sun_y0: sun_rect.1,
            sky_view_width: sky_w,
            sky_view_height: sky_h,
            band_first_row: 0,
            band_rows: h,
        };

        // The Moon pass and the solar-eclipse corona: constants and tables
        // (CPU), maps (uploaded once).
        let moon_bind = if let Some((maps_buf, maps)) = moon_maps {
            let (mu, rows) = moon_uniforms(scene, state, cpu_luts, maps);
            let mut bytes = bytemuck::bytes_of(&mu).to_vec();
            bytes.extend_from_slice(bytemuck::cast_slice(&rows));
            let uniform = self.pool.upload(
                &self.device,
                &self.queue,
                "moon",
                &bytes,
                wgpu::BufferUsages::UNIFORM,
            );
            let bind = bind_group(
                &self.device,
                "moon",
                &self.moon.layout,
                &[uniform.resource(), maps_buf.as_entire_binding()],
            );
            Some((bind, mu.disk_rect(), mu.corona_rect()))
        } else {
            None
        };

        // The Milky Way pass's constants, map and extinction table (dummies
        // when it does not run).
        let (mut night_u, ext_table) = if let Some((w, h)) = mw_dims {
            night_inputs(state, cpu_luts, w, h)
        } else {
            (
                NightUniforms {
                    map_width: 2,
                    map_height: 2,
                    extinction_nodes: 2,
                    ..bytemuck::Zeroable::zeroed()
                },
                vec![[0.0; 4]; 2],
            )
        };
        // The point sources' footprints (CPU: positions, extinction and
        // normalisation as the CPU splat computes them) and per-tile lists.
        let point_pass = |e: Effect| state.runs(e) && culled_reason(e).is_none();
        let (star_plans, planet_plans) = match &night_frame {
            Some(f) => (
                if point_pass(Effect::Stars) {
                    f.splat_plans(scene, &himmel_cpu::night_pass::star_sources(scene, state))
                } else {
                    Vec::new()
                },
                if point_pass(Effect::Planets) {
                    f.splat_plans(scene, &himmel_cpu::night_pass::planet_sources(state))
                } else {
                    Vec::new()
                },
            ),
            None => (Vec::new(), Vec::new()),
        };
        let PointLists {
            records: points,
            words: tile_words,
            tiles_per_row,
            lists,
            busy,
            ranges,
        } = point_lists(&cam, &[&star_plans, &planet_plans]);
        night_u.tile_size = POINT_TILE;
        night_u.tiles_per_row = tiles_per_row;
        [night_u.star_list, night_u.planet_list] = lists;
        [night_u.star_busy_first, night_u.planet_busy_first] = [busy[0].0, busy[1].0];
        [night_u.star_busy_count, night_u.planet_busy_count] = [busy[0].1, busy[1].1];
        let active = [busy[0].1, busy[1].1];
        if let Some((p, _)) = star_plans.first().or(planet_plans.first()) {
            night_u.core_radius = p.r as f32;
            night_u.inv_two_sigma2 = p.inv2s2;
        }
        night_u.quad_scale = if self.quad_format == wgpu::TextureFormat::Rgba32Float {
            1.0
        } else {
            quad_scale(&cam, star_plans.iter().chain(&planet_plans))
        };
        // Point sources as quads: a float target of the band's size (where
        // the adapter's texture limit allows the image width).
        let quads = self.point_method == PointMethod::Quads
            && w <= limits.max_texture_dimension_2d
            && (point_pass(Effect::Stars) || point_pass(Effect::Planets));
        if quads {
            let fits = self.quad_target.as_ref().is_some_and(|t| {
                t.width() >= w && t.height() >= band_rows && t.format() == self.quad_format
            });
            if !fits {
                self.quad_target = Some(self.device.create_texture(&wgpu::TextureDescriptor {
                    label: Some("point-source quads"),
                    size: wgpu::Extent3d {
                        width: w,
                        height: band_rows,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: self.quad_format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                        | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                }));
            }
        }
        let quad_view = self
            .quad_target
            .as_ref()
            .filter(|_| quads)
            .map(|t| t.create_view(&Default::default()));
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let dev = &self.device;
        let pool = &self.pool;
        let upload = |slot, bytes: &[u8], usage| pool.upload(dev, &self.queue, slot, bytes, usage);
        let storage = wgpu::BufferUsages::STORAGE;
        let points_buf = upload("point sources", bytemuck::cast_slice(&points), storage);
        let tiles_buf = upload("point tiles", bytemuck::cast_slice(&tile_words), storage);
        let night_buf = upload(
            "night",
            bytemuck::bytes_of(&night_u),
            wgpu::BufferUsages::UNIFORM,
        );
        let ext_buf = upload("extinction", bytemuck::cast_slice(&ext_table), storage);
        let map_buf = match (&self.mw_map, milkyway) {
            (Some((b, _, _)), true) => b.clone(),
            _ => {
                upload(
                    "no Milky Way map",
                    bytemuck::cast_slice(&[[0.0f32; 4]; 4]),
                    storage,
                )
                .buffer
            }
        };
        // One uniform per band: its rows and its part of the Sun's rectangle.
        let band_frames: Vec<FrameUniforms> = bands
            .iter()
            .map(|&(row0, rows)| {
                let y0 = sun_rect.1.clamp(row0, row0 + rows);
                FrameUniforms {
                    sun_y0: y0,
                    band_first_row: row0,
                    band_rows: rows,
                    ..frame
                }
            })
            .collect();
        let accum = pool.get(dev, "accum", row_bytes * band_rows as u64, storage);
        let accum_size = row_bytes * band_rows as u64;
        let sun_buf = upload("sun table", bytemuck::cast_slice(&sun_table), storage);
        // The bands' uniforms in one buffer, each at an aligned offset.
        let stride = (std::mem::size_of::<FrameUniforms>() as u64)
            .next_multiple_of(limits.min_uniform_buffer_offset_alignment as u64);
        let mut frame_bytes = vec![0u8; stride as usize * band_frames.len()];
        for (k, bf) in band_frames.iter().enumerate() {
            let at = k * stride as usize;
            frame_bytes[at..at + std::mem::size_of::<FrameUniforms>()]
                .copy_from_slice(bytemuck::bytes_of(bf));
        }
        let frames_buf = upload("frame", &frame_bytes, wgpu::BufferUsages::UNIFORM);
        let texture = dev.create_texture(&wgpu::TextureDescriptor {
            label: Some(if cube {
                "himmel cube map"
            } else {
                "himmel frame"
            }),
            size: wgpu::Extent3d {
                width: tw,
                height: h,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: TARGET_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let binds: Vec<wgpu::BindGroup> = (0..band_frames.len() as u64)
            .map(|k| {
                let uniform = PoolBinding {
                    buffer: frames_buf.buffer.clone(),
                    offset: k * stride,
                    size: std::mem::size_of::<FrameUniforms>() as u64,
                };
                let accum = PoolBinding {
                    buffer: accum.clone(),
                    offset: 0,
                    size: accum_size,
                };
                bind_group(
                    dev,
                    "sky",
                    &self.pipelines.layout,
                    &[
                        uniform.resource(),
                        accum.resource(),
                        sky.as_entire_binding(),
                        sun_buf.resource(),
                        wgpu::BindingResource::TextureView(&view),
                        night_buf.resource(),
                        map_buf.as_entire_binding(),
                        ext_buf.resource(),
                        points_buf.resource(),
                        tiles_buf.resource(),
                    ],
                )
            })
            .collect();
        // The quads' bind groups: per band the draw's (frame, night
        // constants, records), and the target for the resolve pass.
        let quad_binds = quad_view.as_ref().map(|view| {
            let draws: Vec<wgpu::BindGroup> = (0..band_frames.len() as u64)
                .map(|k| {
                    let uniform = PoolBinding {
                        buffer: frames_buf.buffer.clone(),
                        offset: k * stride,
                        size: std::mem::size_of::<FrameUniforms>() as u64,
                    };
                    dev.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some("quads"),
                        layout: &self.quads.draw_layout,
                        entries: &[
                            wgpu::BindGroupEntry {
                                binding: 0,
                                resource: uniform.resource(),
                            },
                            wgpu::BindGroupEntry {
                                binding: 5,
                                resource: night_buf.resource(),
                            },
                            wgpu::BindGroupEntry {
                                binding: 8,
                                resource: points_buf.resource(),
                            },
                            wgpu::BindGroupEntry {
                                binding: 9,
                                resource: tiles_buf.resource(),
                            },
                        ],
                    })
                })
                .collect();
            let target = bind_group(
                dev,
                "quad target",
                &self.quads.target_layout,
                &[wgpu::BindingResource::TextureView(view)],
            );
            (draws, target)
        });
        // Passes back to front, then `store`, band by band.
        // Dispatch shape: 0 the band, 1 the Sun's rectangle, 2/3 the
        // stars'/planets' non-empty tiles, 4 the Moon's rectangle, 5 the
        // corona's (part of the Sun pass), 6/7 the stars'/planets'
        // non-empty tiles reading the quad target (group 1). Each run adds its time to the pass statistic it
        // names; with quads, the stars' and planets' runs are their draw
        // (a render pass, `None`) and its resolve.
        let mut runs: Vec<(String, Option<&wgpu::ComputePipeline>, u8, Option<usize>)> = Vec::new();
        let mut stats = Vec::new();
        for planned in &state.passes {
            let culled = culled_reason(planned.effect);
            let run = planned.run && culled.is_none();
            if run {
                let (p, shape) = match planned.effect {
                    Effect::Atmosphere => (&self.pipelines.atmosphere, 0),
                    Effect::Milkyway => (&self.pipelines.milkyway, 0),
                    Effect::Stars => (&self.pipelines.stars, 2),
                    Effect::Planets => (&self.pipelines.planets, 3),
                    Effect::Moon => (&self.moon.disk, 4),
                    _ => (&self.pipelines.sun, 1),
                };
                let stat = Some(stats.len());
                let name = planned.effect.name();
                if quad_binds.is_some() && matches!(shape, 2 | 3) {
                    runs.push((name.into(), None, shape, stat));
                    let resolve = &self.quads.resolve[(shape - 2) as usize];
                    runs.push((name.into(), Some(resolve), shape + 4, stat));
                    stats.push(PassStat {
                        name: name.into(),
                        ran: run,
                        ms: None,
                        reason: planned.reason.clone().or(culled),
                    });
                    continue;
                }
                runs.push((name.into(), Some(p), shape, stat));
                if planned.effect == Effect::Sun && corona_runs {
                    runs.push(("corona".into(), Some(&self.moon.corona), 5, stat));
                }
            }
            stats.push(PassStat {
                name: planned.effect.name().into(),
                ran: run,
                ms: None,
                reason: planned.reason.clone().or(culled),
            });
        }
        stats.extend(PassStat::moon_eclipse(state));
        runs.push(("store".into(), Some(&self.pipelines.store), 0, None));
        let n_runs = runs.len();
        let queries = self.timestamps.then(|| {
            dev.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass times"),
                ty: wgpu::QueryType::Timestamp,
                count: (2 * n_runs * bands.len()) as u32,
            })
        });
        // With timestamps every pass goes into one submission; without,
        // each pass is submitted and awaited so that the CPU clock times it.
        let mut enc = dev.create_command_encoder(&Default::default());
        let mut cpu_ms = vec![0.0; n_runs];
        for (b, &(row0, rows)) in bands.iter().enumerate() {
            enc.clear_buffer(&accum, 0, Some(accum_size));
            for (k, (name, pipeline, shape, _)) in runs.iter().enumerate() {
                // The rows of a rectangle [x0, y0, x1, y1] in this band.
                let in_band = |r: [u32; 4]| {
                    let y0 = r[1].clamp(row0, row0 + rows);
                    let y1 = r[3].clamp(row0, row0 + rows);
                    (
                        r[2].saturating_sub(r[0]).div_ceil(8),
                        y1.saturating_sub(y0).div_ceil(8),
                    )
                };
                let g = match shape {
                    4 | 5 => match &moon_bind {
                        Some((_, rect, corona_rect)) => {
                            in_band(if *shape == 4 { *rect } else { *corona_rect })
                        }
                        None => (0, 0),
                    },
                    1 => {
                        let y0 = band_frames[b].sun_y0;
                        let y1 = sun_rect.3.clamp(row0, row0 + rows);
                        (
                            (sun_rect.2 - sun_rect.0).div_ceil(8),
                            y1.saturating_sub(y0).div_ceil(8),
                        )
                    }
                    2 | 3 | 6 | 7 => {
                        // One 8 × 8 workgroup per non-empty tile, in rows
                        // of at most ACTIVE_ROW workgroups.
                        let n = active[((*shape - 2) % 4) as usize];
                        (n.min(ACTIVE_ROW), n.div_ceil(ACTIVE_ROW))
                    }
                    _ => (w.div_ceil(8), rows.div_ceil(8)),
                };
                let q = 2 * (b * n_runs + k) as u32;
                let t0 = Clock::now();
                if let (None, Some((draws, _)), Some(view)) = (pipeline, &quad_binds, &quad_view) {
                    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some(name),
                        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                            view,
                            depth_slice: None,
                            resolve_target: None,
                            // The non-empty tiles are cleared by a draw.
                            ops: wgpu::Operations {
                                load: wgpu::LoadOp::Load,
                                store: wgpu::StoreOp::Store,
                            },
                        })],
                        depth_stencil_attachment: None,
                        timestamp_writes: queries.as_ref().map(|qs| {
                            wgpu::RenderPassTimestampWrites {
                                query_set: qs,
                                beginning_of_pass_write_index: Some(q),
                                end_of_pass_write_index: Some(q + 1),
                            }
                        }),
                        occlusion_query_set: None,
                        multiview_mask: None,
                    });
                    pass.set_viewport(0.0, 0.0, w as f32, rows as f32, 0.0, 1.0);
                    pass.set_bind_group(0, &draws[b], &[]);
                    let (word, n) = busy[(*shape - 2) as usize];
                    if n > 0 {
                        pass.set_pipeline(&self.quads.clear);
                        pass.draw(0..6, word..word + n);
                    }
                    pass.set_pipeline(&self.quads.draw);
                    let (first, end) = ranges[(*shape - 2) as usize];
                    if end > first {
                        pass.draw(0..6, first..end);
                    }
                } else if let Some(pipeline) = pipeline {
                    let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some(name),
                        timestamp_writes: queries.as_ref().map(|qs| {
                            wgpu::ComputePassTimestampWrites {
                                query_set: qs,
                                beginning_of_pass_write_index: Some(q),
                                end_of_pass_write_index: Some(q + 1),
                            }
                        }),
                    });
                    pass.set_pipeline(pipeline);
                    pass.set_bind_group(0, &binds[b], &[]);
                    if let (4 | 5, Some((mb, _, _))) = (shape, &moon_bind) {
                        pass.set_bind_group(1, mb, &[]);
                    }
                    if let (6 | 7, Some((_, target))) = (shape, &quad_binds) {
                        pass.set_bind_group(1, target, &[]);
                    }
                    pass.dispatch_workgroups(g.0, g.1, 1);
                }
                if queries.is_none() {
                    let done = std::mem::replace(
                        &mut enc,
                        dev.create_command_encoder(&Default::default()),
                    );
                    self.queue.submit([done.finish()]);
                    self.wait()?;
                    cpu_ms[k] += ms(t0);
                }
            }
        }
        self.queue.submit([enc.finish()]);
        let gpu_ms = match &queries {
            Some(qs) => {
                let t = self.read_timestamps(qs, n_runs * bands.len())?;
                let mut sum = vec![0.0; n_runs];
                for (i, v) in t.iter().enumerate() {
                    sum[i % n_runs] += v;
                }
                Some(sum)
            }
            None => None,
        };
        let times = gpu_ms.unwrap_or(cpu_ms);
        for ((.., stat), t) in runs.iter().zip(&times) {
            if let Some(s) = stat.and_then(|i| stats.get_mut(i)) {
                s.ms = Some(s.ms.unwrap_or(0.0) + t);
            }
        }
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RenderError::Other(format!("wgpu: {e}")));
        }
        Ok(GpuFrame {
            texture,
            width: w,
            height: h,
            cube,
            passes: stats,
            precompute_ms,
            lut_source,
            sky_view_ms,
            points: if quads {
                Some(PointMethod::Quads)
            } else if point_pass(Effect::Stars) || point_pass(Effect::Planets) {
                Some(PointMethod::Tiles)
            } else {
                None
            },
        })
    }

    /// The number of per-frame buffers kept across frames (tables,
    /// uniforms, the accumulation band, read-back): constant for a repeated
    /// scene, so a real-time loop allocates only each frame's target texture.
    pub fn pooled_buffers(&self) -> usize {
        self.pool.len()
    }

    /// Uploads the Milky Way map (once); returns its width and height (a
    /// 2 × 2 black map when the embedded one does not decode, as the CPU
    /// then draws no map).
    fn upload_milkyway_map(&mut self) -> (u32, u32) {
        if let Some((_, w, h)) = &self.mw_map {
            return (*w, *h);
        }
        let (texels, w, h) = match himmel_skymodel::milkyway::MilkyWayMap::embedded() {
            Ok(m) => {
                let (w, h) = m.size();
                let t: Vec<[f32; 4]> = m.texels().iter().map(|c| [c[0], c[1], c[2], 0.0]).collect();
                (t, w as u32, h as u32)
            }
            Err(_) => (vec![[0.0; 4]; 4], 2, 2),
        };
        let buf = self
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("Milky Way map"),
                contents: bytemuck::cast_slice(&texels),
                usage: wgpu::BufferUsages::STORAGE,
            });
        self.mw_map = Some((buf, w, h));
        (w, h)
    }

    /// Uploads the lunar albedo map followed by the normal map's (east,
    /// north) pairs (once); returns the buffer and the maps' sizes (albedo
    /// width, height; normal map width, height).
    fn upload_moon_maps(&mut self) -> (wgpu::Buffer, [u32; 4]) {
        if let Some((buf, dims)) = &self.moon_maps {
            return (buf.clone(), *dims);
        }
        use himmel_skymodel::moon::{AlbedoMap, NormalMap};
        let (a, n) = (AlbedoMap::get(), NormalMap::get());
        let mut data: Vec<f32> = a.data.clone();
        data.extend(n.data.iter().flatten());
        let buf = self
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("Moon maps"),
                contents: bytemuck::cast_slice(&data),
                usage: wgpu::BufferUsages::STORAGE,
            });
        let dims = [a.w as u32, a.h as u32, n.w as u32, n.h as u32];
        self.moon_maps = Some((buf.clone(), dims));
        (buf, dims)
    }

    fn wait(&self) -> Result<(), RenderError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| RenderError::Other(format!("wgpu: {e}")))
    }

    /// Maps the first `size` bytes of `buffer` (MAP_READ) and returns them.
    fn map_read(&self, buffer: &wgpu::Buffer, size: u64) -> Result<Vec<u8>, RenderError> {
        let slice = buffer.slice(..size);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv()
            .map_err(|e| RenderError::Other(format!("wgpu: {e}")))?
            .map_err(|e| RenderError::Other(format!("wgpu: {e}")))?;
        let bytes = slice
            .get_mapped_range()
            .map_err(|e| RenderError::Other(format!("wgpu: {e}")))?
            .to_vec();
        buffer.unmap();
        Ok(bytes)
    }

    fn read_timestamps(&self, q: &wgpu::QuerySet, n: usize) -> Result<Vec<f64>, RenderError> {
        let size = (2 * n * 8) as u64;
        let resolve = self.pool.get(
            &self.device,
            "timestamps",
            size,
            wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        );
        let read = self.pool.get(
            &self.device,
            "timestamps read",
            size,
            wgpu::BufferUsages::MAP_READ,
        );
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.resolve_query_set(q, 0..2 * n as u32, &resolve, 0);
        enc.copy_buffer_to_buffer(&resolve, 0, &read, 0, size);
        self.queue.submit([enc.finish()]);
        let bytes = self.map_read(&read, size)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        let period = self.queue.get_timestamp_period() as f64;
        Ok((0..n)
            .map(|k| ticks[2 * k + 1].wrapping_sub(ticks[2 * k]) as f64 * period * 1e-6)
            .collect())
    }

    /// Copies a frame back into an [`HdrImage`] (a cube map as its 6H×H
    /// strip): rows padded to 256 bytes on the GPU side.
    pub fn read_back(&self, frame: &GpuFrame) -> Result<HdrImage, RenderError> {
        let size = frame.texture.size();
        let (tw, th, layers) = (size.width, size.height, size.depth_or_array_layers);
        let row = tw as u64 * 16;
        let padded = row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as u64)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as u64;
        let read_size = padded * th as u64 * layers as u64;
        let read = self.pool.get(
            &self.device,
            "frame read",
            read_size,
            wgpu::BufferUsages::MAP_READ,
        );
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.copy_texture_to_buffer(
            frame.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &read,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded as u32),
                    rows_per_image: Some(th),
                },
            },
            size,
        );
        self.queue.submit([enc.finish()]);
        let bytes = self.map_read(&read, read_size)?;
        let texels: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
        let (w, h) = (frame.width as usize, frame.height as usize);
        let stride = padded as usize / 16;
        let mut pixels = vec![[0.0f32; 3]; w * h];
        let mut valid = vec![false; w * h];
        for y in 0..h {
            for x in 0..w {
                let (layer, lx) = if frame.cube { (x / h, x % h) } else { (0, x) };
                let t = texels[(layer * th as usize + y) * stride + lx];
                pixels[y * w + x] = [t[0], t[1], t[2]];
                valid[y * w + x] = t[3] > 0.5;
            }
        }
        Ok(HdrImage {
            width: w,
            height: h,
            pixels,
            valid,
        })
    }
}

/// A bind group whose entries are `resources` at bindings 0, 1, 2, …
fn bind_group(
    dev: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .enumerate()
        .map(|(k, r)| wgpu::BindGroupEntry {
            binding: k as u32,
            resource: r.clone(),
        })
        .collect();
    dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A compute-stage uniform buffer binding sized for `T`.
fn uniform_entry<T>(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<T>() as u64),
        },
        count: None,
    }
}

/// A factory of compute pipelines (one per entry point of `module`) that
/// share one bind group `layout`.
fn compute_pipelines<'a>(
    device: &'a wgpu::Device,
    module: &'a wgpu::ShaderModule,
    layout: &wgpu::BindGroupLayout,
    label: &str,
) -> impl Fn(&str) -> wgpu::ComputePipeline + 'a {
    let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    move |entry: &str| {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&pl),
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    }
}

/// The point-source quads' pipelines (quads.wgsl): the instanced draw
/// into a `format` target with additive blending (One, One), and the
/// resolve pass that adds the target into `accum`.
fn quad_pipelines(
    device: &wgpu::Device,
    sky: &wgpu::BindGroupLayout,
    format: wgpu::TextureFormat,
) -> QuadPipelines {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("quads.wgsl"),
        source: wgpu::ShaderSource::Wgsl(uniforms::QUADS_WGSL.into()),
    });
    let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
    let draw_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("quads"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                visibility: vf,
                ..uniform_entry::<FrameUniforms>(0)
            },
            wgpu::BindGroupLayoutEntry {
                visibility: vf,
                ..uniform_entry::<NightUniforms>(5)
            },
            wgpu::BindGroupLayoutEntry {
                visibility: vf,
                ..storage_entry(8, true)
            },
            wgpu::BindGroupLayoutEntry {
                visibility: vf,
                ..storage_entry(9, true)
            },
        ],
    });
    let target_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("quad target"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        }],
    });
    let draw_pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("quads"),
        bind_group_layouts: &[Some(&draw_layout)],
        immediate_size: 0,
    });
    let add = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    };
    let render = |vs: &str, fs: &str, blend: Option<wgpu::BlendState>| {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(fs),
            layout: Some(&draw_pl),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some(vs),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
    };
    let draw = render(
        "quad_vs",
        "quad_fs",
        Some(wgpu::BlendState {
            color: add,
            alpha: add,
        }),
    );
    let clear = render("quad_clear_vs", "quad_clear_fs", None);
    let resolve_pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("quad resolve"),
        bind_group_layouts: &[Some(sky), Some(&target_layout)],
        immediate_size: 0,
    });
    let resolve = ["quad_resolve_stars", "quad_resolve_planets"].map(|entry| {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&resolve_pl),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    });
    QuadPipelines {
        draw_layout,
        target_layout,
        draw,
        clear,
        resolve,
    }
}

fn moon_pipelines(device: &wgpu::Device, sky: &wgpu::BindGroupLayout) -> MoonPipelines {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("moon.wgsl"),
        source: wgpu::ShaderSource::Wgsl(uniforms::MOON_WGSL.into()),
    });
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("moon"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: wgpu::BufferSize::new(
                        (std::mem::size_of::<uniforms::MoonUniforms>()
                            + 16 * uniforms::MOON_TABLE_ROWS) as u64,
                    ),
                },
                count: None,
            },
            storage_entry(1, true),
        ],
    });
    let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("moon"),
        bind_group_layouts: &[Some(sky), Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = |entry: &str| {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&pl),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    };
    MoonPipelines {
        disk: pipeline("moon_disk"),
        corona: pipeline("corona"),
        layout,
    }
}

/// The Moon pass's and the corona's uniform ([`uniforms::MoonUniforms`]) and its
/// [`uniforms::MOON_TABLE_ROWS`] table rows for `state`, with `maps` the
/// uploaded maps' sizes (albedo width, height; normal map width, height):
/// the constants of skymodel moon.rs `MoonShader` (built as cpu
/// moon_pass.rs `render` builds it: extinction from `luts`, which are
/// given when the atmosphere pass runs), its extinction and
/// lunar-eclipse tables, Bennett's refraction (`moon::unrefract`) at
/// [`uniforms::MOON_REFR_N`] apparent altitudes over the disk, the disk's
/// pixel angle, limb margin, sub-sampling and rectangle as the CPU pass
/// chooses them; and, when the Moon hides part of the Sun, the corona's
/// (cpu moon_pass.rs `render_corona`): the disk's mean radiance × the
/// transmittance as linear sRGB at [`uniforms::MOON_COR_N`] zenith cosines
/// over the corona, and its rectangle. Exact CPU values at the nodes.
pub fn moon_uniforms(
    scene: &Scene,
    state: &SkyState,
    luts: Option<&AtmosphereLuts>,
    maps: [u32; 4],
) -> (uniforms::MoonUniforms, Vec<[f32; 4]>) {
    use himmel_skymodel::moon::MoonShader;
    use himmel_skymodel::spectrum::BandWeights;
    use uniforms::{
        MoonUniforms, MOON_COR, MOON_COR_N, MOON_ECL, MOON_EXT, MOON_REFR, MOON_REFR_N,
    };
    let cam = &scene.camera;
    let mut rows = vec![[0.0f32; 4]; uniforms::MOON_TABLE_ROWS];
    // Two-node tables where the Moon does not run (the corona may).
    let [albedo_width, albedo_height, normal_width, normal_height] = maps;
    let mut u = MoonUniforms {
        albedo_width,
        albedo_height,
        normal_width,
        normal_height,
        extinction_nodes: 2,
        refraction_nodes: 2,
        ..bytemuck::Zeroable::zeroed()
    };
    let r0 = luts.map_or(0.0, |l| l.medium.bottom + state.observer_altitude_km as f32);
    if state.runs(Effect::Moon) {
        let shader = MoonShader::for_frame(scene, state, luts, r0);
        let p = shader.parts();
        let pixel = himmel_cpu::moon_pass::local_pixel_angle(cam, p.centre.as_dvec3()) as f32;
        let margin = himmel_cpu::moon_pass::limb_margin(pixel);
        let cos_bound = shader.cos_bound(margin);
        let n = himmel_cpu::moon_pass::supersampling(p.radius / pixel) as u32;
        let c = |a: [f32; 3], w: f32| [a[0], a[1], a[2], w];
        // Bennett's refraction over the apparent altitudes the disk test
        // lets through (radius + margin around the centre, and the
        // sub-samples of the pixels at its edge).
        let alt_c = p.centre.z.clamp(-1.0, 1.0).asin();
        let span = (p.radius + margin + cam.max_pixel_angle() as f32) * 1.1 + 1e-4;
        let (alt0, dalt) = (alt_c - span, 2.0 * span / (MOON_REFR_N - 1) as f32);
        if p.refract {
            for k in 0..MOON_REFR_N {
                let alt = alt0 + dalt * k as f32;
                rows[MOON_REFR + k][0] = himmel_skymodel::moon::refraction_of_apparent(alt);
            }
        }
        let ext_n = p.ext.len().min(MOON_REFR - MOON_EXT);
        for (k, e) in p.ext.iter().take(ext_n).enumerate() {
            rows[MOON_EXT + k] = c(*e, 0.0);
        }
        let mut ecl_n = 0;
        let (mut offset, mut semidiameter, mut d_max) = ([0.0; 2], 0.0, 0.0);
        let (mut geo_e, mut geo_n) = (Vec3::ZERO, Vec3::ZERO);
        if let Some(e) = &p.eclipse {
            ecl_n = e.table.len().min(MOON_COR - MOON_ECL);
            for (k, t) in e.table.iter().take(ecl_n).enumerate() {
                rows[MOON_ECL + k] = c(*t, 0.0);
            }
            (offset, semidiameter, d_max) = (e.offset, e.semidiameter, e.d_max);
            (geo_e, geo_n) = (e.geo_east, e.geo_north);
        }
        // The rectangle holds every pixel the disk can touch: centres within
        // radius + ½ pixel have coverage (`shade`), sub-samples reach half a
        // pixel's diagonal, which the camera's largest pixel angle bounds
        // where the Moon can be seen; never beyond the CPU's limb margin.
        let reach = (2.0 * pixel.max(cam.max_pixel_angle() as f32)).min(margin);
        let rect = sun_rect(cam, p.centre.as_dvec3(), (p.radius + reach) as f64);
        u = MoonUniforms {
            centre: p.centre.to_array(),
            radius: p.radius,
            east: p.east.to_array(),
            sin_radius: p.sin_radius,
            north: p.north.to_array(),
            refract: p.refract as u32,
            sun: p.sun.to_array(),
            sun_factor: p.sun_factor,
            axis_x: p.axes[0].to_array(),
            pixel_angle: pixel,
            axis_y: p.axes[1].to_array(),
            cos_bound,
            axis_z: p.axes[2].to_array(),
            sun_rgb: p.sun_rgb,
            extinction_z0: p.ext_z0,
            earth_rgb: p.earth_rgb,
            extinction_dz: p.ext_dz,
            geo_east: geo_e.to_array(),
            refraction_alt0: alt0,
            geo_north: geo_n.to_array(),
            refraction_dalt: dalt,
            shadow_east: offset[0],
            shadow_north: offset[1],
            semidiameter,
            shadow_last: d_max,
            extinction_nodes: ext_n as u32,
            eclipse_nodes: ecl_n as u32,
            refraction_nodes: MOON_REFR_N as u32,
            subsamples: n,
            disk_x0: rect.0,
            disk_y0: rect.1,
            disk_x1: rect.2,
            disk_y1: rect.3,
            ..u
        };
    }
    if state.runs(Effect::Sun) && state.sun.visible_fraction < 1.0 {
        let sun = state.sun.dir();
        let rs = state.sun.angular_radius * scene.sun_scale;
        let rm = (state.moon.angular_radius * scene.moon_scale) as f32;
        let w = BandWeights::solar();
        let rs32 = rs as f32;
        let mean = (state.sun.irradiance_scale
            / (std::f64::consts::PI * (rs32 as f64).sin().powi(2))) as f32;
        let half = std::f64::consts::FRAC_PI_2;
        let alt = sun.z.clamp(-1.0, 1.0).asin();
        let reach = 6.0 * rs * 1.1 + 1e-5;
        let z0 = (alt - reach).max(-half).sin() as f32;
        let z1 = (alt + reach).min(half).sin() as f32;
        let dz = (z1 - z0).max(1e-9) / (MOON_COR_N - 1) as f32;
        for k in 0..MOON_COR_N {
            let z = z0 + dz * k as f32;
            let t = luts.map_or(Spectrum::ONE, |l| l.sun_transmittance(r0, z));
            rows[MOON_COR + k] = {
                let rgb = w.to_rgb(&(t * mean));
                [rgb[0], rgb[1], rgb[2], 0.0]
            };
        }
        let rect = sun_rect(cam, sun.normalize(), 6.0 * rs);
        (u.corona_x0, u.corona_y0, u.corona_x1, u.corona_y1) = rect;
        u.corona_cos_outer = (6.0 * rs32).cos();
        u.corona_sun_radius = rs32;
        u.corona_moon_radius = rm;
        u.max_pixel_angle = cam.max_pixel_angle() as f32;
        u.corona_z0 = z0;
        u.corona_dz = dz;
        u.corona_nodes = MOON_COR_N as u32;
        u.corona_floor = himmel_skymodel::sun::corona_relative(6.0) as f32;
    }
    (u, rows)
}

fn skyview_pipelines(device: &wgpu::Device) -> SkyViewPipelines {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("skyview.wgsl"),
        source: wgpu::ShaderSource::Wgsl(SKYVIEW_WGSL.into()),
    });
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("sky view"),
        entries: &[
            uniform_entry::<AtmosphereUniforms>(0),
            storage_entry(1, true),
            storage_entry(2, true),
            storage_entry(3, true),
            storage_entry(4, false),
        ],
    });
    let pipeline = compute_pipelines(device, &module, &layout, "sky view");
    SkyViewPipelines {
        sky_view: pipeline("sky_view"),
        ground: pipeline("ground"),
        layout,
    }
}

/// A spectrum as three vec4 band groups (the last two lanes zero).
fn band_groups(s: &Spectrum) -> [[f32; 4]; 3] {
    let mut g = [[0.0f32; 4]; 3];
    for (b, v) in s.0.iter().enumerate() {
        g[b / 4][b % 4] = *v;
    }
    g
}

fn lut_groups(l: &himmel_skymodel::atmosphere::lut::Lut2<Spectrum>) -> Vec<[f32; 4]> {
    l.data.iter().flat_map(band_groups).collect()
}

/// Uploads the parameter-dependent LUTs unless they are already on the GPU.
fn upload_luts<'a>(
    device: &wgpu::Device,
    slot: &'a mut Option<GpuLuts>,
    luts: &AtmosphereLuts,
) -> &'a GpuLuts {
    if let Some(g) = slot.take() {
        if g.params == luts.params && g.config == luts.config {
            return slot.insert(g);
        }
    }
    let buf = |label, l| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(&lut_groups(l)),
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    slot.insert(GpuLuts {
        params: luts.params.clone(),
        config: luts.config,
        on_gpu: false,
        trans: buf("transmittance", &luts.transmittance),
        trans_s: buf("scattering transmittance", &luts.scattering_transmittance),
        multi: buf("multiple scattering", &luts.multiscatter),
    })
}

/// The uniforms of the GPU sky view (lut.rs `SkyView::row` inputs).
pub fn atmosphere_uniforms(luts: &AtmosphereLuts, input: &SkyViewInput) -> AtmosphereUniforms {
    let m = &luts.medium;
    let cfg = &luts.config;
    let weights = himmel_skymodel::spectrum::BandWeights::solar();
    let mut w = [[[0.0f32; 4]; 3]; 3];
    for (b, rgb) in weights.rgb.iter().enumerate() {
        for c in 0..3 {
            w[c][b / 4][b % 4] = rgb[c];
        }
    }
    let r0 = m.bottom
        + input
            .observer_altitude_km
            .clamp(0.0, m.top - m.bottom - 0.01);
    let sun = himmel_skymodel::atmosphere::SkyView::sun_local(input.sun_sin_elevation);
    AtmosphereUniforms {
        rayleigh: band_groups(&m.rayleigh),
        mie_scattering: band_groups(&m.mie_scattering),
        mie_extinction: band_groups(&m.mie_extinction),
        ozone: band_groups(&m.ozone),
        forward: band_groups(&luts.forward),
        w_r: w[0],
        w_g: w[1],
        w_b: w[2],
        sun: sun.to_array(),
        irradiance_scale: input.irradiance_scale,
        bottom_radius: m.bottom,
        top_radius: m.top,
        inv_h_rayleigh: m.inv_h_r,
        inv_h_mie: m.inv_h_m,
        ozone_peak: m.ozone_peak,
        inv_ozone_width: m.inv_ozone_w,
        mie_g: m.g,
        ground_albedo: m.albedo,
        sun_angular_radius: m.sun_angular_radius,
        observer_radius: r0,
        cos_forward_peak: cfg.forward_peak_deg.to_radians().cos(),
        forward_peak: (cfg.forward_peak_deg > 0.0) as u32,
        transmittance_width: luts.transmittance.w as u32,
        transmittance_height: luts.transmittance.h as u32,
        multiscatter_n: luts.multiscatter.w as u32,
        sky_view_steps: cfg.sky_view_steps as u32,
        sky_view_width: cfg.sky_view_w as u32,
        sky_view_height: cfg.sky_view_h as u32,
        _pad0: 0,
        _pad1: 0,
    }
}

/// The GPU sky view's buffers and bind groups, kept across frames while
/// the LUT buffers, the sky-view size and the number of inputs stay the
/// same (the uniforms are rewritten each frame).
struct SkyViewBuffers {
    /// Sky-view width, height, number of inputs.
    key: (u32, u32, usize),
    /// The LUT buffers the bind groups hold.
    luts: [wgpu::Buffer; 3],
    /// Per input: w × h texels, then the ground.
    out: wgpu::Buffer,
    /// Per input: uniform buffer, sky-view buffer, bind group.
    slots: Vec<(wgpu::Buffer, wgpu::Buffer, wgpu::BindGroup)>,
}

/// Computes the sky-view LUT and the ground luminance on the GPU for each
/// of `inputs` (the Sun's, then the Moon's on a moonlit night); returns the
/// buffer (per input: w × h texels, then the ground), after completion.
/// The buffers live in `cache` (rebuilt when the LUTs or sizes change).
fn gpu_sky_view(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    p: &SkyViewPipelines,
    gl: &GpuLuts,
    luts: &AtmosphereLuts,
    inputs: &[SkyViewInput],
    cache: &mut Option<SkyViewBuffers>,
) -> Result<wgpu::Buffer, RenderError> {
    let (w, h) = (luts.config.sky_view_w as u32, luts.config.sky_view_h as u32);
    let view_bytes = (w as u64 * h as u64 + 1) * 16;
    let key = (w, h, inputs.len().max(1));
    let lut_bufs = [gl.trans.clone(), gl.trans_s.clone(), gl.multi.clone()];
    let c = match cache.take() {
        Some(c) if c.key == key && c.luts == lut_bufs => c,
        _ => {
            let out = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sky views"),
                size: view_bytes * key.2 as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let slots = (0..key.2)
                .map(|_| {
                    let uniform = device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("atmosphere"),
                        size: std::mem::size_of::<AtmosphereUniforms>() as u64,
                        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    });
                    let sky = device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("sky view"),
                        size: view_bytes,
                        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                        mapped_at_creation: false,
                    });
                    let bind = bind_group(
                        device,
                        "sky view",
                        &p.layout,
                        &[
                            uniform.as_entire_binding(),
                            gl.trans.as_entire_binding(),
                            gl.trans_s.as_entire_binding(),
                            gl.multi.as_entire_binding(),
                            sky.as_entire_binding(),
                        ],
                    );
                    (uniform, sky, bind)
                })
                .collect();
            SkyViewBuffers {
                key,
                luts: lut_bufs,
                out,
                slots,
            }
        }
    };
    let c = cache.insert(c);
    let mut enc = device.create_command_encoder(&Default::default());
    for (k, (input, (uniform, sky, bind))) in inputs.iter().zip(&c.slots).enumerate() {
        let u = atmosphere_uniforms(luts, input);
        debug_assert_eq!((u.sky_view_width, u.sky_view_height), (w, h));
        queue.write_buffer(uniform, 0, bytemuck::bytes_of(&u));
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("sky view"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&p.sky_view);
            pass.set_bind_group(0, bind, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("ground"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&p.ground);
            pass.set_bind_group(0, bind, &[]);
            pass.dispatch_workgroups(1, 1, 1);
        }
        enc.copy_buffer_to_buffer(sky, 0, &c.out, k as u64 * view_bytes, view_bytes);
    }
    queue.submit([enc.finish()]);
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| RenderError::Other(format!("wgpu: {e}")))?;
    Ok(c.out.clone())
}

/// The Milky Way pass's uniforms and extinction table for `state`: the
/// CPU's `NightBackground` (skymodel milkyway.rs) constants, and its
/// `Extinction` table (from `luts`' transmittance at the observer; none
/// without the atmosphere) with, in the fourth lane, the refraction (rad)
/// that `milkyway::unrefracted` takes off the apparent altitude asin μ at
/// each node μ. `map_w` × `map_h` is the uploaded map's size.
pub fn night_inputs(
    state: &SkyState,
    luts: Option<&AtmosphereLuts>,
    map_w: u32,
    map_h: u32,
) -> (NightUniforms, Vec<[f32; 4]>) {
    use himmel_skymodel::milkyway::{unrefracted, NightBackground, OBLIQUITY_J2000};
    use himmel_skymodel::stars::Extinction;
    let bg = NightBackground::new(state.night.star_frame.icrs_to_enu);
    let m = bg.enu_to_icrs();
    let extinction = match luts {
        Some(l) => {
            let r0 = l.medium.bottom + state.observer_altitude_km as f32;
            Extinction::from_transmittance(|mu| l.sun_transmittance(r0, mu))
        }
        // Factors of 1, tabulated at the full resolution for the refraction lane.
        None => Extinction::from_transmittance(|_| himmel_skymodel::spectrum::Spectrum::ONE),
    };
    let table = extinction.table();
    let n = table.len();
    let rows: Vec<[f32; 4]> = table
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let mu = i as f32 / (n - 1) as f32;
            let d = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
            let r = (mu.asin() - unrefracted(d).z.clamp(-1.0, 1.0).asin()).max(0.0);
            [t[0], t[1], t[2], r]
        })
        .collect();
    use himmel_skymodel::milkyway::{AIRGLOW_HEIGHT_KM, EARTH_RADIUS_KM};
    let k = (EARTH_RADIUS_KM / (EARTH_RADIUS_KM + AIRGLOW_HEIGHT_KM)) as f32;
    let (se, ce) = OBLIQUITY_J2000.sin_cos();
    let [ag, zl, fl] = bg.colours();
    // The rows of the ENU → ICRS rotation (glam matrices are column-major).
    let row = |i: usize| [m.x_axis[i], m.y_axis[i], m.z_axis[i]];
    let u = NightUniforms {
        enu_to_icrs_x: row(0),
        sin_obliquity: se,
        enu_to_icrs_y: row(1),
        cos_obliquity: ce,
        enu_to_icrs_z: row(2),
        airglow: ag,
        van_rhijn_k2: k * k,
        zodiacal: zl,
        floor: fl,
        map_width: map_w,
        map_height: map_h,
        extinction_nodes: n as u32,
        tile_size: POINT_TILE,
        tiles_per_row: 1,
        quad_scale: 1.0,
        // The point sources' lists and footprint constants: render_frame.
        ..bytemuck::Zeroable::zeroed()
    };
    (u, rows)
}

/// Tile size (px) of the point-source lists (the workgroup size of the
/// `stars` and `planets` entry points, 8 × 8).
pub const POINT_TILE: u32 = 8;

/// Workgroups per dispatch row of the point passes (one per non-empty tile).
const ACTIVE_ROW: u32 = 32768;

/// The output of [`point_lists`].
#[derive(Debug, Clone, PartialEq)]
pub struct PointLists {
    /// One record per footprint (and wrap).
    pub records: Vec<PointRecord>,
    /// Per list: tile start words, record indices, non-empty tile indices.
    pub words: Vec<u32>,
    /// Tiles per image row (`Night.tiles_per_row`).
    pub tiles_per_row: u32,
    /// Per list: the first word of its tile starts (`Night.star_list`,
    /// `Night.planet_list`).
    pub lists: [u32; 2],
    /// Per list: the first word and the number of its non-empty tiles.
    pub busy: [(u32, u32); 2],
    /// Per list: its records, `records[start..end]` (the instances of its
    /// quads, [`PointMethod::Quads`]).
    pub ranges: [(u32, u32); 2],
}

/// The point sources of the GPU's point passes: one [`PointRecord`] per
/// footprint (equirect footprints that cross the 0°/360° seam once per
/// wrap, as the CPU's `pixel_index` wraps them) and, per list in `lists`
/// (stars, planets), the records that may touch each
/// [`POINT_TILE`]² tile: `tiles + 1` absolute start words, then the
/// record indices, then the indices of the non-empty tiles. Returns the
/// records, the words, the tiles per row, the first word of each list and
/// per list the first word and the number of its non-empty tiles.
pub fn point_lists(
    cam: &Camera,
    lists: &[&[(himmel_skymodel::stars::SplatPlan, [f32; 3])]; 2],
) -> PointLists {
    let (w, h) = cam.image_size();
    let (w, h) = (w as i64, h as i64);
    let ts = POINT_TILE as i64;
    let (tx, ty) = ((w + ts - 1) / ts, (h + ts - 1) / ts);
    let n_tiles = (tx * ty) as usize;
    let mut records = Vec::new();
    let mut words = Vec::new();
    let mut bases = [0u32; 2];
    let mut active = [(0u32, 0u32); 2];
    let mut ranges = [(0u32, 0u32); 2];
    for (l, plans) in lists.iter().enumerate() {
        let start_record = records.len() as u32;
        let mut per_tile: Vec<Vec<u32>> = vec![Vec::new(); n_tiles];
        for (plan, rgb) in plans.iter() {
            let (cx, cy) = plan.pos;
            let (ci, cj) = (cx.floor() as i64, cy.floor() as i64);
            let reach = plan.r.max(plan.glare_r_px.ceil() as i64);
            let (y0, y1) = ((cj - reach).max(0), (cj + reach).min(h - 1));
            if y0 > y1 {
                continue;
            }
            let wraps = if cam.projection == Projection::Equirect {
                (ci - reach).div_euclid(w)..=(ci + reach).div_euclid(w)
            } else {
                0..=0
            };
            for k in wraps {
                let (sx, si) = (cx - (k * w) as f64, ci - k * w);
                let (x0, x1) = ((si - reach).max(0), (si + reach).min(w - 1));
                if x0 > x1 {
                    continue;
                }
                let idx = records.len() as u32;
                records.push(PointRecord {
                    x: sx as f32,
                    y: cy as f32,
                    core_scale: plan.core_scale,
                    glare_radius: plan.glare_r_px,
                    colour: *rgb,
                    glare_scale: plan.glare_scale,
                    pixel_x: si as i32,
                    pixel_y: cj as i32,
                    face: plan.face as i32,
                    near_horizon: plan.near_horizon as u32,
                });
                for j in y0 / ts..=y1 / ts {
                    for i in x0 / ts..=x1 / ts {
                        per_tile[(j * tx + i) as usize].push(idx);
                    }
                }
            }
        }
        bases[l] = words.len() as u32;
        let start = words.len() + n_tiles + 1;
        let mut at = start as u32;
        for t in &per_tile {
            words.push(at);
            at += t.len() as u32;
        }
        words.push(at);
        for t in &per_tile {
            words.extend(t);
        }
        let first = words.len() as u32;
        words.extend(
            per_tile
                .iter()
                .enumerate()
                .filter(|(_, t)| !t.is_empty())
                .map(|(i, _)| i as u32),
        );
        active[l] = (first, words.len() as u32 - first);
        ranges[l] = (start_record, records.len() as u32);
    }
    if records.is_empty() {
        records.push(bytemuck::Zeroable::zeroed());
    }
    PointLists {
        records,
        words,
        tiles_per_row: tx as u32,
        lists: bases,
        busy: active,
        ranges,
    }
}

/// The scale of an rgba16float quad target (`NightUniforms::quad_scale`): the
/// power of two that brings the largest footprint radiance — (core + glare
/// scale) × the brightest colour channel / the solid angle of the pixel at
/// the footprint's centre — near 2¹³, so that it stays below the format's
/// 65504 and the faint stars above its subnormals (6.1 × 10⁻⁵; a star
/// 10⁸ × fainter than the brightest source still gets a normal number).
pub fn quad_scale<'a>(
    cam: &Camera,
    plans: impl Iterator<Item = &'a (himmel_skymodel::stars::SplatPlan, [f32; 3])>,
) -> f32 {
    let mut peak = 0.0f64;
    for (p, rgb) in plans {
        let omega = cam.pixel_solid_angle(p.pos.0, p.pos.1);
        if omega > 0.0 {
            let c = rgb.iter().fold(0.0f32, |m, v| m.max(*v)) as f64;
            peak = peak.max((p.core_scale + p.glare_scale) as f64 * c / omega);
        }
    }
    if !(peak > 0.0 && peak.is_finite()) {
        return 1.0;
    }
    (2.0f64).powi((8192.0 / peak).log2().round().clamp(-120.0, 120.0) as i32) as f32
}

/// The pixel rectangle [x0, x1) × [y0, y1) that holds every pixel whose
/// centre lies within `margin` (rad) of the Sun's direction `sun` (ENU,
/// unit): the bounding box of 64 directions on the margin's circle (and
/// the centre) through `Camera::dir_to_pixel`, padded by 2 px; the whole
/// image for cube maps, wide margins, circles through a pole of an
/// equirect image or across its 0°/360° seam, and directions a perspective
/// camera cannot project.
pub fn sun_rect(cam: &Camera, sun: DVec3, margin: f64) -> (u32, u32, u32, u32) {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    let (w, h) = cam.image_size();
    let full = (0, 0, w, h);
    if cam.projection == Projection::Cubemap || margin > 0.5 {
        return full;
    }
    let m = margin * 1.05;
    let alt = sun.z.clamp(-1.0, 1.0).asin();
    if cam.projection == Projection::Fisheye && FRAC_PI_2 - alt + m >= PI {
        return full;
    }
    let a = if sun.z.abs() < 0.9 {
        DVec3::Z
    } else {
        DVec3::X
    };
    let e1 = sun.cross(a).normalize();
    let e2 = sun.cross(e1);
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    let (sm, cm) = m.sin_cos();
    for k in 0..=64 {
        let d = if k == 64 {
            sun
        } else {
            let phi = TAU * k as f64 / 64.0;
            sun * cm + (e1 * phi.cos() + e2 * phi.sin()) * sm
        };
        let Some((x, y)) = cam.dir_to_pixel(d) else {
            return full;
        };
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if cam.projection == Projection::Equirect {
        if x1 - x0 > w as f64 / 2.0 || alt + m >= FRAC_PI_2 || alt - m <= -FRAC_PI_2 {
            x0 = 0.0;
            x1 = w as f64;
        }
        if alt + m >= FRAC_PI_2 {
            y0 = 0.0;
        }
        if alt - m <= -FRAC_PI_2 {
            y1 = h as f64;
        }
    }
    let clamp_x = |v: f64| v.clamp(0.0, w as f64) as u32;
    let clamp_y = |v: f64| v.clamp(0.0, h as f64) as u32;
    let (rx0, ry0) = (clamp_x((x0 - 2.0).floor()), clamp_y((y0 - 2.0).floor()));
    let (rx1, ry1) = (clamp_x((x1 + 2.0).ceil()), clamp_y((y1 + 2.0).ceil()));
    (rx0, ry0, rx1.max(rx0), ry1.max(ry0))
}

/// The perspective camera's basis (ENU: forward, right, up) and
/// tan(fov / 2), as projection.rs builds it.
fn perspective_basis(cam: &Camera) -> (DVec3, DVec3, DVec3, f64) {
    let (yaw, pitch) = (cam.yaw_deg.to_radians(), cam.pitch_deg.to_radians());
    let f = himmel_skymodel::projection::enu_from_alt_az(pitch, yaw);
    let right = DVec3::new(yaw.cos(), -yaw.sin(), 0.0);
    let up = right.cross(f);
    (f, right, up, (cam.fov_deg.to_radians() / 2.0).tan())
}

/// The Sun table: linear sRGB radiance (cd/m²) of a disk of angular
/// radius `radius` (rad) carrying `irradiance_scale` × the 1 AU solar
/// irradiance, centred at zenith cosine `centre_z`, at normalised radius
/// ρ = sin(π/2 · i/(n−1)) (uniform in asin ρ: dense at the limb, where the
/// limb darkening μ^α with μ = √(1 − ρ²) falls steeply; uniform nodes in ρ
/// left limb pixels of a 17 px disk up to 70 % dark) and line-of-sight
/// zenith cosine z over the disk's range:
/// each node is the exact `SunDisk::radiance_rgb` after the transmittance
/// `luts.sun_transmittance(r0, z)` (none without the atmosphere). Returns
/// the table (row-major, z rows of ρ) and [z_min, z_max].
pub fn sun_table(
    centre_z: f64,
    radius: f64,
    irradiance_scale: f64,
    luts: Option<&AtmosphereLuts>,
    observer_altitude_km: f32,
) -> (Vec<[f32; 4]>, [f32; 2]) {
    let alt = centre_z.clamp(-1.0, 1.0).asin();
    let half = std::f64::consts::FRAC_PI_2;
    let pad = radius * 0.02 + 1e-6;
    let z0 = (alt - radius - pad).max(-half).sin();
    let z1 = (alt + radius + pad).min(half).sin();
    // The same disk about the zenith: ρ only enters through |d × c|.
    let probe = SunDisk::new(Vec3::Z, radius, irradiance_scale);
    let sr = (probe.radius as f64).sin();
    let r0 = luts.map(|l| l.medium.bottom + observer_altitude_km);
    let mut out = Vec::with_capacity(SUN_TABLE_RHO * SUN_TABLE_Z);
    for j in 0..SUN_TABLE_Z {
        let z = z0 + (z1 - z0) * j as f64 / (SUN_TABLE_Z - 1) as f64;
        let t = match (luts, r0) {
            (Some(l), Some(r0)) => l.sun_transmittance(r0, z as f32),
            _ => Spectrum::ONE,
        };
        for i in 0..SUN_TABLE_RHO {
            let rho = (std::f64::consts::FRAC_PI_2 * i as f64 / (SUN_TABLE_RHO - 1) as f64)
                .sin()
                .min(1.0 - 1e-6);
            let g = (rho * sr).asin();
            let dir = Vec3::new(g.sin() as f32, 0.0, g.cos() as f32);
            let rgb = if probe.covers(dir) {
                probe.radiance_rgb(dir, &t)
            } else {
                [0.0; 3]
            };
            out.push([rgb[0], rgb[1], rgb[2], 0.0]);
        }
    }
    (out, [z0 as f32, z1 as f32])
}

impl SkyRenderer for WgpuRenderer {
    fn name(&self) -> &'static str {
        "wgpu"
    }

    fn render(&mut self, scene: &Scene, state: &SkyState) -> Result<RenderOutput, RenderError> {
        let frame = self.render_frame(scene, state)?;
        let image = self.read_back(&frame)?;
        Ok(RenderOutput {
            image,
            passes: frame.passes,
            precompute_ms: frame.precompute_ms,
            lut_source: frame.lut_source,
            geometry_ms: 0.0,
            sky_view_ms: frame.sky_view_ms,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use himmel_skymodel::projection::enu_from_alt_az;

    /// The point passes run one workgroup per tile: their workgroup size
    /// is the tile size (the quads' resolve passes too).
    #[test]
    fn point_workgroups_are_tiles() {
        let module =
            naga::front::wgsl::parse_str(uniforms::POINTS_WGSL).expect("points.wgsl parses");
        for name in ["stars", "planets"] {
            let e = module.entry_points.iter().find(|e| e.name == name).unwrap();
            assert_eq!(e.workgroup_size, [POINT_TILE, POINT_TILE, 1], "{name}");
        }
        let module = naga::front::wgsl::parse_str(uniforms::QUADS_WGSL).expect("quads.wgsl parses");
        for name in ["quad_resolve_stars", "quad_resolve_planets"] {
            let e = module.entry_points.iter().find(|e| e.name == name).unwrap();
            assert_eq!(e.workgroup_size, [POINT_TILE, POINT_TILE, 1], "{name}");
        }
    }

    /// Every pixel centre within the margin of the Sun lies in the Sun
    /// pass's rectangle: equirect seam and poles, fisheye horizon and
    /// zenith, perspective edges (brute force over all pixel centres).
    #[test]
    fn sun_rect_holds_every_pixel_within_the_margin() {
        let cams = [
            (Projection::Equirect, 256, 128, 0.0, 0.0),
            (Projection::Fisheye, 128, 128, 0.0, 0.0),
            (Projection::Perspective, 160, 96, 10.0, 20.0),
        ];
        let suns = [
            (0.5, 0.0),
            (0.5, 359.5),
            (89.0, 120.0),
            (-1.0, 300.0),
            (20.0, 180.0),
            (30.0, 40.0),
            (-89.5, 10.0),
        ];
        for (p, w, h, yaw, pitch) in cams {
            let cam = Camera {
                projection: p,
                width: w,
                height: h,
                yaw_deg: yaw,
                pitch_deg: pitch,
                fov_deg: 90.0,
            };
            for (alt, az) in suns {
                let sun = enu_from_alt_az(f64::to_radians(alt), f64::to_radians(az));
                let margin = 0.004_65 + 1.5 * cam.max_pixel_angle();
                let (x0, y0, x1, y1) = sun_rect(&cam, sun, margin);
                let mut inside = 0;
                for y in 0..h {
                    for x in 0..w {
                        let Some(d) = cam.pixel_to_dir(x as f64 + 0.5, y as f64 + 0.5) else {
                            continue;
                        };
                        if d.dot(sun) >= margin.cos() {
                            inside += 1;
                            assert!(
                                (x0..x1).contains(&x) && (y0..y1).contains(&y),
                                "{p:?} Sun ({alt}, {az}): pixel ({x}, {y}) outside {:?}",
                                (x0, y0, x1, y1)
                            );
                        }
                    }
                }
                // The rectangle is tight when it is not the whole image.
                if (x0, y0, x1, y1) != (0, 0, w, h) {
                    assert!(inside > 0 || (x1 - x0) * (y1 - y0) < w * h / 4);
                }
            }
        }
    }

    fn plan(
        x: f64,
        y: f64,
        core: f32,
        glare_r: f32,
    ) -> (himmel_skymodel::stars::SplatPlan, [f32; 3]) {
        (
            himmel_skymodel::stars::SplatPlan {
                pos: (x, y),
                face: 0,
                near_horizon: false,
                r: 2,
                inv2s2: 1.0,
                core_scale: core,
                glare_r_px: glare_r,
                glare_scale: 0.5 * core,
            },
            [1.0, 0.5, 0.25],
        )
    }

    /// Each list's records are a contiguous range (the instances of its
    /// quads): the stars' first, then the planets', one record per
    /// footprint and equirect wrap.
    #[test]
    fn point_list_ranges_are_the_lists_records() {
        let cam = Camera {
            projection: Projection::Equirect,
            width: 64,
            height: 32,
            ..Default::default()
        };
        let stars = [plan(10.5, 10.5, 1e-6, 0.0), plan(63.5, 16.0, 2e-6, 0.0)];
        let planets = [plan(30.0, 20.0, 1e-4, 3.5)];
        let l = point_lists(&cam, &[&stars, &planets]);
        // The second star crosses the seam: two records.
        assert_eq!(l.ranges, [(0, 3), (3, 4)]);
        assert_eq!(l.records.len(), 4);
        assert_eq!(l.records[3].glare_radius, 3.5);
        let empty = point_lists(&cam, &[&[], &planets]);
        assert_eq!(empty.ranges, [(0, 0), (0, 1)]);
    }

    /// The rgba16float target's scale is a power of two that brings the
    /// largest footprint radiance to within a factor √2 of 2¹³; 1 without
    /// sources.
    #[test]
    fn quad_scale_brings_the_peak_near_2_13() {
        let cam = Camera {
            projection: Projection::Fisheye,
            width: 256,
            height: 256,
            ..Default::default()
        };
        for core in [1e-9f32, 1e-6, 1e-3, 10.0] {
            let plans = [
                plan(128.5, 128.5, core, 2.0),
                plan(100.0, 90.0, core * 1e-3, 0.0),
            ];
            let k = quad_scale(&cam, plans.iter());
            assert_eq!(k.log2().fract(), 0.0, "{k}");
            let omega = cam.pixel_solid_angle(128.5, 128.5);
            let peak = 1.5 * core as f64 / omega * k as f64;
            assert!(
                (8192.0 / 2f64.sqrt()..=8192.0 * 2f64.sqrt()).contains(&peak),
                "{core}: {peak}"
            );
        }
        assert_eq!(quad_scale(&cam, [].iter()), 1.0);
    }
}
