//! The clouds pass (`shaders/clouds.wgsl`, its own bind group 1: the
//! [`CloudUniforms`], the atmosphere's uniforms and its transmittance and
//! multiple-scattering LUTs, the height-field tier's maps): the frame plan's [`CloudFrame`] per pixel
//! as the CPU's `PixelPass::Clouds` composes it — the high layer, then the
//! low one, each over what the earlier passes drew (stars, planets, Milky
//! Way and Moon dimmed by the layer's transmittance), with the aerial
//! perspective in front of it.
//!
//! The WGSL ports skymodel's `clouds::{noise, field, march}` and
//! `frame::clouds` function by function; every constant of the model
//! (fields, phase function, octaves, march settings, lights, ambient
//! light) reaches it through [`cloud_uniforms`], built from the Rust
//! values, so that tuning the model in `skymodel` needs no WGSL edit
//! beyond re-syncing the marked `march_low` block when its algorithm
//! changes. The lights' transmittance at the cloud and the aerial
//! perspective are looked up and marched per pixel in the same LUTs the
//! CPU uses (`atmo.wgsl`).

use bytemuck::{Pod, Zeroable};
use himmel_skymodel::clouds::field::{
    ProfileShape, CLOSE_DECK, CLOSE_FROM, HIGH_OCTAVES, LOW_OCTAVES, NOISE_CONTRAST,
    NOISE_PERIOD_CELLS,
};
use himmel_skymodel::clouds::height_field::PROBE_DIVISOR;
use himmel_skymodel::clouds::march::MAX_MARCH_KM;
use himmel_skymodel::clouds::noise::OCTAVE_SHIFT;
use himmel_skymodel::clouds::{MultipleScattering, Octaves, CLOUD_PHASE, OCTAVES};
use himmel_skymodel::frame::clouds::CLEAR;
use himmel_skymodel::frame::lights::AERIAL_STEPS;
use himmel_skymodel::frame::{CloudFrame, HistoryKey, SkyInputs};
use himmel_skymodel::spectrum::{BandWeights, Spectrum};
use himmel_skymodel::{FramePlan, RenderError, Scene};
use wgpu::util::DeviceExt;

use super::clouds_amortise::{CloudsStep, GridPipelines, GridShape};
use super::clouds_history::{grown, GpuCloudHistory};
use super::luts::{band_groups, LutSlot};
use super::sky_view::atmosphere_uniforms;
use crate::frame::{FrameLayout, SkyGroup};
use crate::gpu::{bind_group, storage_entry, uniform_entry, Gpu};
use crate::uniforms::AtmosphereUniforms;

/// The clouds pass: frame.wgsl, clouds.wgsl, its diffusion model
/// (clouds_diffusion.wgsl), its height-field tier
/// (clouds_heightfield.wgsl), the diffusion grids (clouds_grid.wgsl), the
/// composition and the amortised march (clouds_amortise.wgsl), its temporal
/// reprojection (clouds_history.wgsl), then the atmosphere's
/// uniforms and lookups (atmo.wgsl), the medium (medium.wgsl) and the
/// bilinear lookup (bilinear.wgsl).
pub const CLOUDS_WGSL: &str = concat!(
    include_str!("../shaders/frame.wgsl"),
    include_str!("../shaders/clouds.wgsl"),
    include_str!("../shaders/clouds_diffusion.wgsl"),
    include_str!("../shaders/clouds_heightfield.wgsl"),
    include_str!("../shaders/clouds_grid.wgsl"),
    include_str!("../shaders/clouds_amortise.wgsl"),
    include_str!("../shaders/clouds_history.wgsl"),
    include_str!("../shaders/atmo.wgsl"),
    include_str!("../shaders/medium.wgsl"),
    include_str!("../shaders/bilinear.wgsl")
);

/// Mirror of WGSL `struct Clouds` (src/shaders/clouds.wgsl): the frame's
/// cloud fields, the model's constants, the lights and the aerial
/// perspective's inputs, the ground's cloud shadows, the height-field
/// tier's maps, the amortised march's grid and history. 608 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct CloudUniforms {
    /// `LowField::offset_km`, km.
    pub low_offset_km: [f32; 2],
    /// `LowField::inv_scale`, km⁻¹.
    pub low_inv_scale: f32,
    /// `LowField::coverage`.
    pub low_coverage: f32,
    /// `LowField::base_km`.
    pub low_base_km: f32,
    /// `LowField::top_km`.
    pub low_top_km: f32,
    /// `LowField::extinction_per_km`, km⁻¹.
    pub low_extinction_per_km: f32,
    /// `LowField::half_extent_km` (`f32::MAX` for an unbounded layer).
    pub low_half_extent_km: f32,
    /// `ProfileShape::rise` of the kind.
    pub low_rise: f32,
    /// `ProfileShape::fall0`.
    pub low_fall0: f32,
    /// `ProfileShape::fall1`.
    pub low_fall1: f32,
    /// `LowField::seed`.
    pub low_seed: u32,
    /// `HighField::offset_km`, km.
    pub high_offset_km: [f32; 2],
    /// `HighField::along` (unit).
    pub high_along: [f32; 2],
    /// `HighField::inv_scale_along`, km⁻¹.
    pub high_inv_scale_along: f32,
    /// `HighField::inv_scale_across`, km⁻¹.
    pub high_inv_scale_across: f32,
    /// `HighField::coverage`.
    pub high_coverage: f32,
    /// `HighField::altitude_km`.
    pub high_altitude_km: f32,
    /// `HighField::optical_depth`.
    pub high_optical_depth: f32,
    /// `HighField::seed`.
    pub high_seed: u32,
    /// 1 when the frame has a low layer.
    pub has_low: u32,
    /// 1 when the frame has a high layer.
    pub has_high: u32,
    /// `noise::OCTAVE_SHIFT`.
    pub octave_shift: [f32; 3],
    /// `field::NOISE_CONTRAST`.
    pub noise_contrast: f32,
    /// `field::NOISE_PERIOD_CELLS`.
    pub noise_period_cells: u32,
    /// `field::LOW_OCTAVES`.
    pub low_octaves: u32,
    /// `field::HIGH_OCTAVES`.
    pub high_octaves: u32,
    /// `MarchSettings::steps`.
    pub steps: u32,
    /// `MarchSettings::light_steps`.
    pub light_steps: u32,
    /// `Octaves::n`.
    pub octave_count: u32,
    /// `Octaves::a`.
    pub octave_a: f32,
    /// `Octaves::b`.
    pub octave_b: f32,
    /// `Octaves::c`.
    pub octave_c: f32,
    /// `CLOUD_PHASE.g_forward`.
    pub phase_g_forward: f32,
    /// `CLOUD_PHASE.g_back`.
    pub phase_g_back: f32,
    /// `CLOUD_PHASE.w_forward`.
    pub phase_w_forward: f32,
    /// `Shell::r_ground`, km.
    pub r_ground: f32,
    /// `Shell::r_observer`, km.
    pub r_observer: f32,
    /// `march::MAX_MARCH_KM`.
    pub max_march_km: f32,
    /// `frame::clouds::CLEAR`.
    pub clear: f32,
    /// `CloudFrame::ambient_rgb`, cd/m².
    pub ambient: [f32; 3],
    /// Number of lights (0–2).
    pub light_count: u32,
    /// The first light's unit ENU direction.
    pub light0_dir: [f32; 3],
    /// 1 when the atmosphere pass runs (its LUTs are bound).
    pub air: u32,
    /// The first light's band factors outside the atmosphere.
    pub light0_spectrum: [[f32; 4]; 3],
    /// The first light's linear sRGB irradiance without the atmosphere, lux.
    pub light0_rgb: [f32; 3],
    /// `lights::AERIAL_STEPS`.
    pub air_steps: u32,
    /// The second light's direction.
    pub light1_dir: [f32; 3],
    /// `Diffusion::gain` (0: the octaves model).
    pub diffusion_gain: f32,
    /// The second light's band factors.
    pub light1_spectrum: [[f32; 4]; 3],
    /// The second light's irradiance without the atmosphere, lux.
    pub light1_rgb: [f32; 3],
    /// `Diffusion::g`.
    pub diffusion_g: f32,
    /// `SkyInputs::sun_dir`.
    pub air_sun: [f32; 3],
    /// `SkyInputs::sun.irradiance_scale`.
    pub air_sun_scale: f32,
    /// The Moon's direction of `SkyInputs::moon`.
    pub air_moon: [f32; 3],
    /// Its irradiance scale (0: no moonlit air).
    pub air_moon_scale: f32,
    /// `field::CLOSE_FROM`.
    pub close_from: f32,
    /// `field::CLOSE_DECK`.
    pub close_deck: f32,
    /// `CloudFrame::ground_direct`'s length (0–2).
    pub ground_count: u32,
    /// 1 when the observer stands on the ground (`ground_at_observer`
    /// serves every ground pixel).
    pub ground_flat: u32,
    /// The first ground light's direction and its transmittance at the
    /// observer (w).
    pub ground0_dir: [f32; 4],
    /// The first ground light's direct part of the ground, cd/m².
    pub ground0_rgb: [f32; 4],
    /// The second ground light's direction and transmittance.
    pub ground1_dir: [f32; 4],
    /// The second ground light's direct part of the ground.
    pub ground1_rgb: [f32; 4],
    /// `Diffusion::gap_density`, `surface_step`, `surface_weight` and
    /// `forward_orders` (0 with the octaves model).
    pub diffusion_shape: [f32; 4],
    /// The height-field tier (`clouds_heightfield.wgsl`): `PROBE_DIVISOR`
    /// (0: the volumetric tier), `HeightField::n`, `half_width_km`,
    /// `texel_km`.
    pub hf_map: [f32; 4],
    /// `HeightField::warp_km`, the number of `light_dirs`, 0, 0.
    pub hf_warp: [f32; 4],
    /// The diffusion grids' (`clouds_grid.wgsl`) corner (km) and cell
    /// (km).
    pub grid_origin: [f32; 4],
    /// Cells along x, y, z and the number of grids (0: none).
    pub grid_dims: [f32; 4],
    /// `DiffusionGrid::weight`, `fade_km`, `g`, 0.
    pub grid_weight: [f32; 4],
    /// The amortised march ([`GridShape::uniform`]): the stride (1: every
    /// pixel marched), the coarse nodes along x and y, the bits of
    /// `AGREE_TRANSMITTANCE`.
    pub march_grid: [u32; 4],
    /// The temporal reprojection
    /// ([`super::clouds_history::history_uniforms`]): 1 when the last
    /// frame's nodes may serve, the quarter's phase, the ages whose lights
    /// hold (bits), `HISTORY_MAX_AGE`.
    pub history: [u32; 4],
    /// The field's move since the last frame (km), `HISTORY_AGREE`,
    /// `HISTORY_NEGLIGIBLE`.
    pub history_shift: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<CloudUniforms>() == 608);

/// The light of `CloudFrame::light_sources` at slot `k` of `u`.
fn set_light(u: &mut CloudUniforms, k: usize, dir: glam::Vec3, s: &Spectrum) {
    let rgb = BandWeights::solar().to_rgb(s).map(|v| v.max(0.0));
    let (d, sp, c) = match k {
        0 => (&mut u.light0_dir, &mut u.light0_spectrum, &mut u.light0_rgb),
        _ => (&mut u.light1_dir, &mut u.light1_spectrum, &mut u.light1_rgb),
    };
    *d = dir.to_array();
    *sp = band_groups(s);
    *c = rgb;
}

/// The lattice's stand-in without amortised marching (one entry), bytes.
const ENTRY_STAND_IN: u64 = super::clouds_amortise::ENTRY_BYTES;

/// The pass's uniforms for the frame plan's clouds `c`, with `air` the
/// lights of the aerial perspective when the atmosphere pass runs (the
/// plan's `sky_inputs`, its LUTs bound beside).
pub fn cloud_uniforms(c: &CloudFrame, air: Option<&SkyInputs>) -> CloudUniforms {
    let m = &c.march;
    // The diffusion model marches the octaves' first term (single
    // scattering) and adds the diffuse source (march.rs `march_low`).
    let (octaves, diffusion_g, diffusion_gain, diffusion_shape) = match m.scattering {
        MultipleScattering::Octaves(o) => (o, 0.0, 0.0, [0.0; 4]),
        MultipleScattering::Diffusion(d) => (
            Octaves { n: 1, ..OCTAVES },
            d.g,
            d.gain,
            [
                d.gap_density,
                d.surface_step,
                d.surface_weight,
                d.forward_orders as f32,
            ],
        ),
    };
    let mut u = CloudUniforms {
        octave_shift: OCTAVE_SHIFT.to_array(),
        noise_contrast: NOISE_CONTRAST,
        noise_period_cells: NOISE_PERIOD_CELLS,
        low_octaves: LOW_OCTAVES,
        high_octaves: HIGH_OCTAVES,
        steps: m.steps,
        light_steps: m.light_steps,
        octave_count: octaves.n,
        octave_a: octaves.a,
        octave_b: octaves.b,
        octave_c: octaves.c,
        diffusion_g,
        diffusion_gain,
        diffusion_shape,
        phase_g_forward: CLOUD_PHASE.g_forward,
        phase_g_back: CLOUD_PHASE.g_back,
        phase_w_forward: CLOUD_PHASE.w_forward,
        r_ground: c.shell.r_ground,
        r_observer: c.shell.r_observer,
        max_march_km: MAX_MARCH_KM,
        clear: CLEAR,
        ambient: c.ambient_rgb,
        air_steps: AERIAL_STEPS as u32,
        close_from: CLOSE_FROM,
        close_deck: CLOSE_DECK,
        ..Zeroable::zeroed()
    };
    if let Some(f) = &c.low {
        let shape = ProfileShape::of(f.kind);
        u.has_low = 1;
        u.low_offset_km = f.offset_km.to_array();
        u.low_inv_scale = f.inv_scale;
        u.low_coverage = f.coverage;
        u.low_base_km = f.base_km;
        u.low_top_km = f.top_km;
        u.low_extinction_per_km = f.extinction_per_km;
        u.low_half_extent_km = f.half_extent_km.min(f32::MAX);
        u.low_rise = shape.rise;
        u.low_fall0 = shape.fall0;
        u.low_fall1 = shape.fall1;
        u.low_seed = f.seed;
    }
    if let Some(f) = &c.high {
        u.has_high = 1;
        u.high_offset_km = f.offset_km.to_array();
        u.high_along = f.along.to_array();
        u.high_inv_scale_along = f.inv_scale_along;
        u.high_inv_scale_across = f.inv_scale_across;
        u.high_coverage = f.coverage;
        u.high_altitude_km = f.altitude_km;
        u.high_optical_depth = f.optical_depth;
        u.high_seed = f.seed;
    }
    if let Some(hf) = &c.height_field {
        u.hf_map = [
            PROBE_DIVISOR as f32,
            hf.n as f32,
            hf.half_width_km,
            hf.texel_km,
        ];
        u.hf_warp = [hf.warp_km, hf.light_dirs.len().min(2) as f32, 0.0, 0.0];
    }
    if let Some(g) = c.diffusion_grids.first() {
        u.grid_origin = g.origin.extend(g.cell_km).to_array();
        let [nx, ny, nz] = g.dims;
        let count = c.diffusion_grids.len().min(2);
        u.grid_dims = [nx as f32, ny as f32, nz as f32, count as f32];
        u.grid_weight = [g.weight, g.fade_km, g.g, 0.0];
    }
    u.ground_count = c.ground_direct.len().min(2) as u32;
    u.ground_flat = (c.shell.r_observer - c.shell.r_ground < 1e-3) as u32;
    for (k, g) in c.ground_direct.iter().take(2).enumerate() {
        let t = c.ground_at_observer.get(k).copied().unwrap_or(1.0);
        let (d, rgb) = match k {
            0 => (&mut u.ground0_dir, &mut u.ground0_rgb),
            _ => (&mut u.ground1_dir, &mut u.ground1_rgb),
        };
        *d = g.dir.extend(t).to_array();
        *rgb = [g.rgb[0], g.rgb[1], g.rgb[2], 0.0];
    }
    let lights = c.light_sources();
    u.light_count = lights.len().min(2) as u32;
    for (k, (dir, s)) in lights.iter().take(2).enumerate() {
        set_light(&mut u, k, *dir, s);
    }
    if let Some(inputs) = air {
        u.air = 1;
        u.air_sun = inputs.sun_dir.to_array();
        u.air_sun_scale = inputs.sun.irradiance_scale;
        if let Some((m, dir)) = inputs.moon {
            u.air_moon = dir.to_array();
            u.air_moon_scale = m.irradiance_scale;
        }
    }
    u
}

/// The cells of the frame's diffusion grids (at most 2) for
/// `clouds_grid.wgsl`: (U, F) per cell, U = −1 in a clear cell.
fn grid_cells(c: &CloudFrame) -> Vec<[f32; 4]> {
    c.diffusion_grids
        .iter()
        .take(2)
        .flat_map(|g| {
            g.cells
                .iter()
                .zip(&g.cloudy)
                .map(|(cell, &cloudy)| if cloudy { *cell } else { [-1.0, 0.0, 0.0, 0.0] })
        })
        .collect()
}

/// The clouds pass.
pub struct CloudsPass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
    /// The amortised march's coarse and refining pipelines.
    coarse: wgpu::ComputePipeline,
    refine: wgpu::ComputePipeline,
    /// The per-pixel pipeline that reads the grid, the edge queue's reset
    /// and march pipelines.
    grid_pixels: wgpu::ComputePipeline,
    reset: wgpu::ComputePipeline,
    edges: wgpu::ComputePipeline,
    /// Zero-filled LUT stand-ins for frames without the atmosphere pass.
    no_luts: Option<wgpu::Buffer>,
    /// `clouds_grid_coarse_history`.
    coarse_history: wgpu::ComputePipeline,
    /// The amortised march's lattices and temporal reprojection, kept
    /// across frames (grown as needed); a small stand-in without
    /// amortised marching.
    pub history: GpuCloudHistory,
    /// The band's queue of pixels the grid cannot give (a count, then
    /// pixel indices), kept across frames likewise.
    queue: Option<wgpu::Buffer>,
}

impl CloudsPass {
    /// Compiles the pass.
    pub fn new(gpu: &Gpu, sky: &SkyGroup) -> Self {
        let module = gpu.shader("clouds.wgsl", CLOUDS_WGSL);
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("clouds"),
                entries: &[
                    uniform_entry::<CloudUniforms>(0),
                    uniform_entry::<AtmosphereUniforms>(1),
                    storage_entry(2, true),
                    storage_entry(3, true),
                    storage_entry(4, true),
                    storage_entry(5, true),
                    storage_entry(6, false),
                    storage_entry(7, false),
                    storage_entry(8, true),
                    storage_entry(9, false),
                ],
            });
        let pl = gpu.pipeline_layout("clouds", &[&sky.layout, &layout]);
        CloudsPass {
            pipeline: gpu.compute_pipeline(&pl, &module, "clouds_pass"),
            coarse: gpu.compute_pipeline(&pl, &module, "clouds_grid_coarse"),
            coarse_history: gpu.compute_pipeline(&pl, &module, "clouds_grid_coarse_history"),
            refine: gpu.compute_pipeline(&pl, &module, "clouds_grid_refine"),
            grid_pixels: gpu.compute_pipeline(&pl, &module, "clouds_grid_pixels"),
            reset: gpu.compute_pipeline(&pl, &module, "clouds_edges_reset"),
            edges: gpu.compute_pipeline(&pl, &module, "clouds_edges"),
            layout,
            no_luts: None,
            history: GpuCloudHistory::default(),
            queue: None,
        }
    }

    /// The pass over every band of `layout`'s image when
    /// the plan has cloud layers: its uniforms, the LUTs (uploaded unless
    /// `gpu_luts` holds them), the amortised march's grid when the low
    /// layer has a `march_stride` above 1, with its history over the frames
    /// of `scene` when `clouds.low.reproject` holds.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        gpu_luts: &mut LutSlot,
        scene: &Scene,
        plan: &FramePlan,
        layout: &FrameLayout,
    ) -> Result<Option<CloudsStep>, RenderError> {
        let Some(c) = plan.clouds.as_ref() else {
            return Ok(None);
        };
        let air = plan.luts.as_ref().zip(plan.sky_inputs.as_ref());
        let mut u = cloud_uniforms(c, air.map(|(_, inputs)| inputs));
        let limit = gpu.device.limits().max_storage_buffer_binding_size;
        let shape = c
            .low
            .as_ref()
            .and_then(|_| GridShape::of(layout.width, layout.height, c.march_stride, limit));
        u.march_grid = GridShape::uniform(shape);
        let key = (shape.is_some() && scene.clouds.low.reproject)
            .then(|| (HistoryKey::of(scene, plan, c), c));
        let stand_in = self.no_luts(gpu);
        let bufs = self.history.buffers(
            gpu,
            &mut u,
            shape.map_or(ENTRY_STAND_IN, |g| g.bytes()),
            key,
            stand_in,
        );
        let band_pixels = layout.width as u64 * layout.band_rows as u64;
        let queue = grown(
            gpu,
            &mut self.queue,
            "cloud edge queue",
            // The count and at least one index (the shader's minimum).
            4 + 4 * shape.map_or(1, |_| band_pixels),
            wgpu::BufferUsages::STORAGE,
        );
        let (atmo, luts) = match air {
            Some((luts, inputs)) => {
                let g = gpu_luts.upload(gpu, luts);
                let bufs = [g.trans.clone(), g.trans_s.clone(), g.multi.clone()];
                (atmosphere_uniforms(luts, &inputs.sun), bufs)
            }
            _ => {
                let z = self.no_luts(gpu);
                (Zeroable::zeroed(), [z.clone(), z.clone(), z])
            }
        };
        let init = |label, contents: &[u8]| {
            gpu.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage: wgpu::BufferUsages::UNIFORM,
                })
        };
        let uniform = init("cloud uniforms", bytemuck::bytes_of(&u));
        // The height-field tier's maps (a stand-in without them).
        let columns = match &c.height_field {
            Some(hf) => {
                let all: Vec<[f32; 4]> = hf
                    .columns
                    .iter()
                    .chain(&hf.light_columns)
                    .copied()
                    .collect();
                gpu.device
                    .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("cloud height field"),
                        contents: bytemuck::cast_slice(&all),
                        usage: wgpu::BufferUsages::STORAGE,
                    })
            }
            None if !c.diffusion_grids.is_empty() => {
                gpu.device
                    .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("cloud diffusion grids"),
                        contents: bytemuck::cast_slice(&grid_cells(c)),
                        usage: wgpu::BufferUsages::STORAGE,
                    })
            }
            None => self.no_luts(gpu),
        };
        let atmo = init("cloud atmosphere", bytemuck::bytes_of(&atmo));
        let group = bind_group(
            &gpu.device,
            "clouds",
            &self.layout,
            &[
                uniform.as_entire_binding(),
                atmo.as_entire_binding(),
                luts[0].as_entire_binding(),
                luts[1].as_entire_binding(),
                luts[2].as_entire_binding(),
                columns.as_entire_binding(),
                bufs.lattice.as_entire_binding(),
                queue.as_entire_binding(),
                bufs.prev.as_entire_binding(),
                bufs.counters.as_entire_binding(),
            ],
        );
        Ok(Some(CloudsStep {
            pixels: self.pipeline.clone(),
            grid: shape.map(|shape| GridPipelines {
                coarse: if bufs.history {
                    self.coarse_history.clone()
                } else {
                    self.coarse.clone()
                },
                refine: self.refine.clone(),
                pixels: self.grid_pixels.clone(),
                reset: self.reset.clone(),
                edges: self.edges.clone(),
                shape,
            }),
            group1: group,
        }))
    }

    fn no_luts(&mut self, gpu: &Gpu) -> wgpu::Buffer {
        self.no_luts
            .get_or_insert_with(|| {
                gpu.device
                    .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("no LUTs"),
                        contents: &[0u8; 48],
                        usage: wgpu::BufferUsages::STORAGE,
                    })
            })
            .clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::uniforms::tests::{assert_wgsl_layout, fields};
    use std::mem::size_of;

    /// The module validates and the uniform struct's size, offsets and
    /// types are those naga computes for WGSL `Clouds`.
    #[test]
    fn the_shader_validates_and_its_uniforms_match() {
        let module = naga::front::wgsl::parse_str(CLOUDS_WGSL).expect("clouds.wgsl parses");
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::empty(),
        )
        .validate(&module)
        .expect("clouds.wgsl validates");
        for entry in [
            "clouds_pass",
            "clouds_grid_coarse",
            "clouds_grid_coarse_history",
            "clouds_grid_refine",
            "clouds_grid_pixels",
            "clouds_edges_reset",
            "clouds_edges",
        ] {
            assert!(
                module.entry_points.iter().any(|e| e.name == entry),
                "{entry}"
            );
        }
        let rust = fields!(
            CloudUniforms,
            [
                low_offset_km,
                low_inv_scale,
                low_coverage,
                low_base_km,
                low_top_km,
                low_extinction_per_km,
                low_half_extent_km,
                low_rise,
                low_fall0,
                low_fall1,
                low_seed,
                high_offset_km,
                high_along,
                high_inv_scale_along,
                high_inv_scale_across,
                high_coverage,
                high_altitude_km,
                high_optical_depth,
                high_seed,
                has_low,
                has_high,
                octave_shift,
                noise_contrast,
                noise_period_cells,
                low_octaves,
                high_octaves,
                steps,
                light_steps,
                octave_count,
                octave_a,
                octave_b,
                octave_c,
                phase_g_forward,
                phase_g_back,
                phase_w_forward,
                r_ground,
                r_observer,
                max_march_km,
                clear,
                ambient,
                light_count,
                light0_dir,
                air,
                light0_spectrum,
                light0_rgb,
                air_steps,
                light1_dir,
                diffusion_gain,
                light1_spectrum,
                light1_rgb,
                diffusion_g,
                air_sun,
                air_sun_scale,
                air_moon,
                air_moon_scale,
                close_from,
                close_deck,
                ground_count,
                ground_flat,
                ground0_dir,
                ground0_rgb,
                ground1_dir,
                ground1_rgb,
                diffusion_shape,
                hf_map,
                hf_warp,
                grid_origin,
                grid_dims,
                grid_weight,
                march_grid,
                history,
                history_shift,
            ]
        );
        assert_wgsl_layout(CLOUDS_WGSL, "Clouds", size_of::<CloudUniforms>(), &rust);
    }

    /// The uniforms carry the Rust model's values: the frame's fields, the
    /// phase function, the octaves, the march settings, the lights.
    #[test]
    fn uniforms_carry_the_model() {
        use himmel_skymodel::clouds::DIFFUSION;
        use himmel_skymodel::{Effect, Scene, SkyState};
        let mut s = Scene::default();
        s.time.utc = "2024-06-21T11:00:00Z".into();
        s.effects = vec![Effect::Clouds];
        s.clouds.low.coverage = 0.6;
        s.clouds.low.steps = 48;
        s.clouds.low.extent_km = 3.0;
        s.clouds.high.coverage = 0.3;
        let state = SkyState::at(&s).expect("state");
        let c = CloudFrame::prepare(&s, &state, None, None, None, &mut Default::default());
        let u = cloud_uniforms(&c, None);
        let (low, high) = (c.low.expect("low"), c.high.expect("high"));
        assert_eq!((u.has_low, u.has_high, u.air), (1, 1, 0));
        assert_eq!(u.low_offset_km, low.offset_km.to_array());
        assert_eq!(u.low_half_extent_km, 3.0);
        assert_eq!(u.high_inv_scale_along, high.inv_scale_along);
        assert_eq!((u.steps, u.light_steps), (48, c.march.light_steps));
        assert_eq!(
            [u.octave_a, u.octave_b, u.octave_c],
            [OCTAVES.a, OCTAVES.b, OCTAVES.c]
        );
        // The default diffusion model: single scattering as the octaves'
        // first term, then the diffuse source.
        assert_eq!(u.octave_count, 1);
        assert_eq!(
            (u.diffusion_g, u.diffusion_gain),
            (DIFFUSION.g, DIFFUSION.gain)
        );
        assert_eq!(
            u.diffusion_shape,
            [
                DIFFUSION.gap_density,
                DIFFUSION.surface_step,
                DIFFUSION.surface_weight,
                DIFFUSION.forward_orders as f32
            ]
        );
        assert_eq!(u.phase_g_forward, CLOUD_PHASE.g_forward);
        assert_eq!(u.r_observer, c.shell.r_observer);
        // The Sun, unextinguished without the atmosphere: its irradiance
        // as the CPU lights the cloud with it.
        assert_eq!(u.light_count, 1);
        let cpu = c.lights_at(glam::Vec3::Z, 1.0);
        assert_eq!(u.light0_rgb, cpu[0].irradiance_rgb);
        assert_eq!(u.light0_dir, cpu[0].dir.to_array());
        // An unbounded layer: a finite half-width no position exceeds.
        s.clouds.low.extent_km = 0.0;
        let c = CloudFrame::prepare(&s, &state, None, None, None, &mut Default::default());
        assert_eq!(cloud_uniforms(&c, None).low_half_extent_km, f32::MAX);
    }
}
