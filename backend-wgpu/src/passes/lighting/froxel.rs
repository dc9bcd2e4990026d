//! Light shafts, `froxel` (`lighting.godrays.method`, issue 15; Wronski
//! 2014, Hillaire 2015; `froxel.wgsl` derives the terms): a fog volume
//! aligned with the view frustum, one froxel per `resolution_divisor` ×
//! `resolution_divisor` pixels and `steps` slices out to the frame's
//! farthest surface.
//!
//! 1. **extent** — the farthest surface's distance (an atomic maximum over
//!    the G-buffer, kept on the device; the previous frame's kept beside);
//! 2. **inject** — each froxel's in-scattering per metre from the Sun, the
//!    Moon (shadow maps, at `interleave` points stratified over the slice)
//!    and the sky (its cells' visibility maps, as `toth`, at the first),
//!    the points jittered per frame, blended with the previous
//!    frame's volume at the reprojected place (`temporal`);
//! 3. **integrate** — front to back along each column, energy-conserving;
//! 4. **apply** — each pixel's integral at its surface's distance, into
//!    the shafts' image ([`super::godrays::Shafts`]) at full resolution,
//!    which the lighting pass adds as `toth`'s.
//!
//! The blended volumes alternate between two textures; the history holds
//! while the grid, the temporal weight, the world and the fog stay,
//! across the frames of one renderer (`himmel render --frames N`); the
//! frames' jitter sequence starts again with a new grid, world or fog.

use glam::{Mat4, Vec3};
use himmel_skymodel::{GodraysSettings, RenderError};
use wgpu::util::DeviceExt;

use super::godrays::{marched_size, MarchInputs, Shafts};
use super::resources::texture;
use super::view::WorldCamera;
use crate::gpu::{bind, bind_group, Gpu};

/// The froxel uniforms (`Froxel` in froxel.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct FroxelUniforms {
    prev_view_proj: [f32; 16],
    prev_eye: [f32; 4],
    grid: [u32; 4],
    params: [f32; 4],
}

struct FroxelPipes {
    layout: wgpu::BindGroupLayout,
    extent: wgpu::ComputePipeline,
    inject: wgpu::ComputePipeline,
    integrate: wgpu::ComputePipeline,
    apply: wgpu::ComputePipeline,
}

/// The volumes of one grid: the blended in-scattering (two, alternating)
/// and its integral.
struct Volumes {
    grid: [u32; 3],
    scatter: [wgpu::TextureView; 2],
    integrated: wgpu::TextureView,
}

/// What a volume's history belongs to: the world's identity
/// ([`super::mesh::identity`]) and the fog (σ_s, σ_t, top).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Key {
    /// The world's identity.
    pub world: (usize, usize, usize),
    /// The fog's σ_s, σ_t (1/m) and top (m).
    pub fog: [f32; 3],
}

/// What the last frame left for the next one.
#[derive(Clone, Copy)]
struct History {
    view_proj: Mat4,
    eye: Vec3,
    grid: [u32; 3],
    temporal: f32,
    key: Key,
}

/// The froxel pass's pipelines, volumes and history.
#[derive(Default)]
pub struct Froxels {
    pipes: Option<FroxelPipes>,
    volumes: Option<Volumes>,
    extent: Option<[wgpu::Buffer; 2]>,
    history: Option<History>,
    frame: u32,
}

/// The froxel grid of a frame of `w` × `h`: columns per side and slices.
pub fn grid(w: u32, h: u32, settings: &GodraysSettings) -> [u32; 3] {
    let (gx, gy) = marched_size(w, h, settings.resolution_divisor);
    [gx, gy, settings.steps.max(1)]
}

/// The jitter of frame `n` along its froxels' slices: the golden-ratio
/// sequence from ½ (evenly spread over any run of frames).
pub fn jitter(n: u32) -> f32 {
    let g = 0.618_034_f64;
    ((0.5 + f64::from(n) * g) % 1.0) as f32
}

fn volume(gpu: &Gpu, [x, y, z]: [u32; 3]) -> wgpu::TextureView {
    texture(
        gpu,
        "froxels",
        (x, y, z),
        wgpu::TextureDimension::D3,
        wgpu::TextureFormat::Rgba32Float,
        wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
    )
    .create_view(&Default::default())
}

fn pipes(gpu: &Gpu) -> FroxelPipes {
    let d3 = wgpu::TextureViewDimension::D3;
    let rgba = wgpu::TextureFormat::Rgba32Float;
    let layout = gpu.compute_layout(
        "froxel",
        &[
            bind::uniform(),
            bind::float_2d(),
            bind::uint_2d(),
            bind::depth_array(),
            bind::comparison(),
            bind::write_2d(rgba),
            bind::storage(true),
            bind::storage(true),
            bind::depth_array(),
            bind::uniform(),
            bind::storage(false),
            bind::texture(wgpu::TextureSampleType::Float { filterable: false }, d3),
            bind::write(rgba, d3),
        ],
    );
    let module = gpu.shader(
        "froxel.wgsl",
        concat!(
            include_str!("../../shaders/lighting/common.wgsl"),
            include_str!("../../shaders/lighting/shafts.wgsl"),
            include_str!("../../shaders/lighting/shafts_sky.wgsl"),
            include_str!("../../shaders/lighting/froxel.wgsl")
        ),
    );
    let pl = gpu.pipeline_layout("froxel", &[&layout]);
    FroxelPipes {
        extent: gpu.compute_pipeline(&pl, &module, "extent_max"),
        inject: gpu.compute_pipeline(&pl, &module, "inject"),
        integrate: gpu.compute_pipeline(&pl, &module, "integrate"),
        apply: gpu.compute_pipeline(&pl, &module, "apply"),
        layout,
    }
}

/// This frame's froxel uniforms: the history `held` (if any), the grid,
/// the frame's number and the settings' weight, samples and divisor.
fn uniforms(
    held: Option<History>,
    grid: [u32; 3],
    frame: u32,
    settings: &GodraysSettings,
) -> FroxelUniforms {
    let prev = held.map_or(Mat4::IDENTITY, |p| p.view_proj);
    let prev_eye = held.map_or(Vec3::ZERO, |p| p.eye);
    FroxelUniforms {
        prev_view_proj: prev.to_cols_array(),
        prev_eye: [
            prev_eye.x,
            prev_eye.y,
            prev_eye.z,
            if held.is_some() { 1.0 } else { 0.0 },
        ],
        grid: [
            grid[0],
            grid[1],
            grid[2],
            (frame & 0xffff) | (settings.interleave.clamp(1, 8) << 16),
        ],
        params: [
            held.map_or(0.0, |p| p.temporal),
            jitter(frame),
            settings.resolution_divisor.max(1) as f32,
            0.0,
        ],
    }
}

impl Froxels {
    /// Runs the four passes for `cam`'s frame with the march's inputs into
    /// the shafts' image of `shafts` (full resolution), waits for the
    /// device, and keeps this frame's volume and camera for the next.
    pub fn run_on(
        &mut self,
        gpu: &Gpu,
        march: &MarchInputs,
        compare: &wgpu::Sampler,
        settings: &GodraysSettings,
        (cam, key): (&WorldCamera, Key),
        shafts: &mut Shafts,
    ) -> Result<(), RenderError> {
        let (w, h) = (cam.width, cam.height);
        let grid = grid(w, h, settings);
        let temporal = settings.temporal.clamp(0.0, 0.98) as f32;
        let pipes = self.pipes.get_or_insert_with(|| pipes(gpu));
        if self.volumes.as_ref().map(|v| v.grid) != Some(grid) {
            self.volumes = Some(Volumes {
                grid,
                scatter: [volume(gpu, grid), volume(gpu, grid)],
                integrated: volume(gpu, grid),
            });
            self.history = None;
            self.frame = 0;
        }
        let [extent, scratch] = self.extent.get_or_insert_with(|| {
            [8, 4].map(|size| {
                gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("froxel extent"),
                    size,
                    usage: wgpu::BufferUsages::STORAGE
                        | wgpu::BufferUsages::COPY_DST
                        | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                })
            })
        });
        let Some(vol) = self.volumes.as_ref() else {
            return Err(RenderError::Device("froxel volumes missing".into()));
        };
        if self.history.is_some_and(|p| p.grid != grid || p.key != key) {
            self.history = None;
            self.frame = 0;
        }
        let held = self
            .history
            .filter(|p| p.temporal == temporal && temporal > 0.0);
        let u = uniforms(held, grid, self.frame, settings);
        let ubuf = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("froxel uniforms"),
                contents: bytemuck::bytes_of(&u),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        let out = shafts.output(gpu, (w, h));
        let cur = (self.frame % 2) as usize;
        let tv = wgpu::BindingResource::TextureView;
        let group = |src, dst| {
            bind_group(
                &gpu.device,
                "froxel",
                &pipes.layout,
                &[
                    march.uniforms.as_entire_binding(),
                    tv(march.distance),
                    tv(march.material),
                    tv(march.shadows),
                    wgpu::BindingResource::Sampler(compare),
                    tv(out),
                    march.cells.as_entire_binding(),
                    march.cell_view.as_entire_binding(),
                    tv(march.visibility),
                    ubuf.as_entire_binding(),
                    extent.as_entire_binding(),
                    wgpu::BindingResource::TextureView(src),
                    wgpu::BindingResource::TextureView(dst),
                ],
            )
        };
        let (this, last) = (&vol.scatter[cur], &vol.scatter[1 - cur]);
        // The unused destination of the extent and apply passes is one the
        // pass does not read.
        let steps = [
            (
                &pipes.extent,
                group(last, this),
                (w.div_ceil(8), h.div_ceil(8), 1),
            ),
            (
                &pipes.inject,
                group(last, this),
                (
                    grid[0].div_ceil(4),
                    grid[1].div_ceil(4),
                    grid[2].div_ceil(4),
                ),
            ),
            (
                &pipes.integrate,
                group(this, &vol.integrated),
                (grid[0].div_ceil(8), grid[1].div_ceil(8), 1),
            ),
            (
                &pipes.apply,
                group(&vol.integrated, this),
                (w.div_ceil(8), h.div_ceil(8), 1),
            ),
        ];
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        // The previous frame's extent moves aside; this frame's starts at 0.
        enc.copy_buffer_to_buffer(extent, 0, scratch, 0, 4);
        enc.copy_buffer_to_buffer(scratch, 0, extent, 4, 4);
        enc.clear_buffer(extent, 0, Some(4));
        for (pipe, g, (x, y, z)) in &steps {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipe);
            pass.set_bind_group(0, g, &[]);
            pass.dispatch_workgroups(*x, *y, *z);
        }
        gpu.queue.submit([enc.finish()]);
        gpu.wait()?;
        self.history = Some(History {
            view_proj: cam.view_projection(),
            eye: cam.eye,
            grid,
            temporal,
            key,
        });
        self.frame = self.frame.wrapping_add(1);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_follows_the_divisor_and_the_slices() {
        let s = GodraysSettings {
            steps: 48,
            resolution_divisor: 8,
            ..GodraysSettings::default()
        };
        assert_eq!(grid(160, 90, &s), [20, 12, 48]);
    }

    #[test]
    fn the_jitter_spreads_over_the_slice() {
        assert_eq!(jitter(0), 0.5);
        let mut j: Vec<f32> = (0..16).map(jitter).collect();
        assert!(j.iter().all(|v| (0.0..1.0).contains(v)));
        j.sort_by(f32::total_cmp);
        // No gap wider than 1/8 over 16 frames (golden-ratio sequence).
        let gaps = j.windows(2).map(|w| w[1] - w[0]);
        assert!(gaps.fold(0.0f32, f32::max) < 0.125);
    }
}
