//! The lighting passes' GPU resources, kept between frames: the G-buffer
//! targets, the light maps (the sky's visibility maps and the Sun's and
//! Moon's shadow cascades), and the tables the lighting pass reads (sky
//! cells, prefiltered environment, BRDF table, aerial perspective).

use glam::Vec3;
use himmel_skymodel::frame::AerialPerspective;
use himmel_skymodel::RenderError;
use wgpu::util::DeviceExt;

use super::env::{brdf_lut, EnvLight, BRDF_LUT_SIZE, SPECULAR_LEVELS, SPECULAR_SIZE};
use super::mesh::GpuWorld;
use super::pipelines::{
    Pipelines, DEPTH_FORMAT, GBUFFER_FORMATS, MATRIX_STRIDE, VISIBILITY_FORMAT,
};
use super::view::LightView;
use crate::gpu::{bind_group, Gpu};

pub(super) fn texture(
    gpu: &Gpu,
    label: &str,
    size: (u32, u32, u32),
    dim: wgpu::TextureDimension,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: size.2,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: dim,
        format,
        usage,
        view_formats: &[],
    })
}

/// The G-buffer targets of one image size.
pub struct GBuffer {
    /// Width and height, px.
    pub size: (u32, u32),
    /// The colour targets (pipelines::GBUFFER_FORMATS order).
    pub textures: Vec<wgpu::Texture>,
    /// Their views.
    pub views: Vec<wgpu::TextureView>,
    /// The depth target (reversed Z).
    pub depth: wgpu::TextureView,
    /// The sky pass's outputs (rgba32float): the interleaved set's
    /// irradiance + open fraction; the aureoles' irradiance + specular
    /// visibility. Then the gather pass's: the block's mean of the sets'
    /// irradiance + their spread; the aureoles' irradiance + the open
    /// fraction (rgba32float); the specular visibility (r32float).
    pub sky: [wgpu::TextureView; 5],
}

impl GBuffer {
    /// Targets of `w` × `h`.
    pub fn new(gpu: &Gpu, w: u32, h: u32) -> GBuffer {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let d2 = wgpu::TextureDimension::D2;
        let textures: Vec<wgpu::Texture> = GBUFFER_FORMATS
            .iter()
            .map(|&f| {
                texture(
                    gpu,
                    "gbuffer",
                    (w, h, 1),
                    d2,
                    f,
                    usage | wgpu::TextureUsages::COPY_SRC,
                )
            })
            .collect();
        let views = textures
            .iter()
            .map(|t| t.create_view(&Default::default()))
            .collect();
        let depth = texture(gpu, "gbuffer depth", (w, h, 1), d2, DEPTH_FORMAT, usage)
            .create_view(&Default::default());
        let sky_use = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
        let rgba = wgpu::TextureFormat::Rgba32Float;
        let sky = [rgba, rgba, rgba, rgba, wgpu::TextureFormat::R32Float].map(|f| {
            texture(gpu, "sky light", (w, h, 1), d2, f, sky_use).create_view(&Default::default())
        });
        GBuffer {
            size: (w, h),
            textures,
            views,
            depth,
            sky,
        }
    }
}

/// Draws every mesh (and the ground) into the G-buffer.
pub fn gbuffer_pass(
    gpu: &Gpu,
    pipes: &Pipelines,
    world: &GpuWorld,
    gb: &GBuffer,
    camera: &[u8],
    ground: bool,
) -> Result<(), RenderError> {
    let ubuf = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("gbuffer camera"),
            contents: camera,
            usage: wgpu::BufferUsages::UNIFORM,
        });
    let group = bind_group(
        &gpu.device,
        "gbuffer",
        &pipes.gbuffer_layout,
        &[
            ubuf.as_entire_binding(),
            world.materials.as_entire_binding(),
            wgpu::BindingResource::TextureView(&world.textures),
            wgpu::BindingResource::Sampler(&pipes.repeat),
        ],
    );
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    {
        let attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = gb
            .views
            .iter()
            .map(|v| {
                Some(wgpu::RenderPassColorAttachment {
                    view: v,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })
            })
            .collect();
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer"),
            color_attachments: &attachments,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &gb.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipes.gbuffer);
        pass.set_bind_group(0, &group, &[]);
        // The ground first: with ≥ depth tests the world's own floor wins
        // where it lies in the ground plane.
        if ground {
            pass.set_vertex_buffer(0, world.ground.slice(..));
            pass.set_index_buffer(world.ground_indices.slice(..), wgpu::IndexFormat::Uint32);
            let m = world.ground_material;
            pass.draw_indexed(0..6, 0, m..m + 1);
        }
        pass.set_vertex_buffer(0, world.vertices.slice(..));
        pass.set_index_buffer(world.indices.slice(..), wgpu::IndexFormat::Uint32);
        for d in &world.draws {
            pass.draw_indexed(d.first..d.first + d.count, 0, d.material..d.material + 1);
        }
    }
    gpu.queue.submit([enc.finish()]);
    gpu.wait()
}

/// The light maps: the sky's visibility maps and the shadow cascades.
#[derive(Default)]
pub struct LightMaps {
    visibility: Option<(wgpu::Texture, wgpu::TextureView)>,
    vis_key: Option<(Vec<[u32; 3]>, u32)>,
    cell_matrices: Option<wgpu::Buffer>,
    shadows: Option<(wgpu::Texture, wgpu::TextureView, u32, u32)>,
    dummy: Option<wgpu::TextureView>,
}

fn dir_key(dirs: &[Vec3]) -> Vec<[u32; 3]> {
    dirs.iter()
        .map(|d| d.to_array().map(f32::to_bits))
        .collect()
}

/// Renders the world's depth into layer k of `tex` from `views[k]` with
/// `pipeline` (the raster of `tex`'s format), for every k that `redo`
/// selects.
fn render_layers(
    gpu: &Gpu,
    pipes: &Pipelines,
    pipeline: &wgpu::RenderPipeline,
    world: &GpuWorld,
    tex: &wgpu::Texture,
    views: &[LightView],
    redo: impl Fn(usize) -> bool,
) -> Result<(), RenderError> {
    let bytes = super::matrix_bytes(views);
    let ubuf = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light matrices"),
            contents: &bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        });
    let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("light depth"),
        layout: &pipes.depth_layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &ubuf,
                offset: 0,
                size: wgpu::BufferSize::new(64),
            }),
        }],
    });
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    for k in (0..views.len()).filter(|&k| redo(k)) {
        let mut pass = layer_pass(&mut enc, tex, k as u32);
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &group, &[(k as u64 * MATRIX_STRIDE) as u32]);
        pass.set_vertex_buffer(0, world.vertices.slice(..));
        pass.set_index_buffer(world.indices.slice(..), wgpu::IndexFormat::Uint32);
        for d in &world.draws {
            pass.draw_indexed(d.first..d.first + d.count, 0, 0..1);
        }
    }
    gpu.queue.submit([enc.finish()]);
    gpu.wait()
}

fn depth_array(
    gpu: &Gpu,
    label: &str,
    res: u32,
    layers: u32,
    format: wgpu::TextureFormat,
) -> (wgpu::Texture, wgpu::TextureView) {
    let tex = texture(
        gpu,
        label,
        (res, res, layers.max(1)),
        wgpu::TextureDimension::D2,
        format,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
    );
    let view = tex.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    (tex, view)
}

impl LightMaps {
    /// Forgets the visibility maps (a new world).
    pub fn invalidate_visibility(&mut self) {
        self.vis_key = None;
    }

    /// Whether the visibility maps were built for these directions and size.
    pub fn visibility_current(&self, dirs: &[Vec3], res: u32) -> bool {
        self.vis_key.as_ref() == Some(&(dir_key(dirs), res))
    }

    /// Builds one visibility map per direction; of maps kept from the
    /// last call (same world, size and count) only those whose direction
    /// changed (the aureoles', which follow the Sun and Moon) are redrawn.
    /// Returns how many were drawn.
    pub fn build_visibility(
        &mut self,
        gpu: &Gpu,
        pipes: &Pipelines,
        world: &GpuWorld,
        views: &[LightView],
        dirs: &[Vec3],
        res: u32,
    ) -> Result<usize, RenderError> {
        let layers = views.len() as u32;
        let key = dir_key(dirs);
        let kept = match (&self.visibility, &self.vis_key) {
            (Some((tex, _)), Some((old, r)))
                if *r == res && old.len() == key.len() && tex.depth_or_array_layers() == layers =>
            {
                Some(old.clone())
            }
            _ => None,
        };
        let (tex, view) = match (kept.is_some(), self.visibility.take()) {
            (true, Some(t)) => t,
            _ => depth_array(gpu, "sky visibility", res, layers, VISIBILITY_FORMAT),
        };
        let redo = |k: usize| kept.as_ref().is_none_or(|old| old[k] != key[k]);
        let drawn = (0..views.len()).filter(|&k| redo(k)).count();
        render_layers(
            gpu,
            pipes,
            &pipes.visibility_depth,
            world,
            &tex,
            views,
            redo,
        )?;
        let mats: Vec<[f32; 16]> = views.iter().map(|v| v.matrix.to_cols_array()).collect();
        self.cell_matrices = Some(gpu.device.create_buffer_init(
            &wgpu::util::BufferInitDescriptor {
                label: Some("sky cell matrices"),
                contents: bytemuck::cast_slice(&mats),
                usage: wgpu::BufferUsages::STORAGE,
            },
        ));
        self.visibility = Some((tex, view));
        self.vis_key = Some((key, res));
        Ok(drawn)
    }

    /// Builds the shadow cascades (Sun's, then Moon's layers).
    pub fn build_shadows(
        &mut self,
        gpu: &Gpu,
        pipes: &Pipelines,
        world: &GpuWorld,
        views: &[LightView],
        res: u32,
    ) -> Result<(), RenderError> {
        let layers = views.len() as u32;
        let keep = matches!(&self.shadows, Some((_, _, r, l)) if *r == res && *l == layers);
        if !keep {
            let (tex, view) = depth_array(gpu, "shadow cascades", res, layers, DEPTH_FORMAT);
            self.shadows = Some((tex, view, res, layers));
        }
        if let Some((tex, ..)) = &self.shadows {
            render_layers(gpu, pipes, &pipes.depth, world, tex, views, |_| true)?;
        }
        Ok(())
    }

    /// Creates the stand-ins bound when a frame has no visibility or
    /// shadow maps: a 1×1 map cleared to depth 1 (nothing occludes) and
    /// one identity matrix.
    pub fn ensure_stand_ins(&mut self, gpu: &Gpu) -> Result<(), RenderError> {
        if self.dummy.is_none() {
            let (tex, view) = depth_array(gpu, "no light map", 1, 1, DEPTH_FORMAT);
            clear_depth(gpu, &tex)?;
            self.dummy = Some(view);
        }
        if self.cell_matrices.is_none() {
            let id = glam::Mat4::IDENTITY.to_cols_array();
            self.cell_matrices = Some(gpu.device.create_buffer_init(
                &wgpu::util::BufferInitDescriptor {
                    label: Some("no sky cells"),
                    contents: bytemuck::cast_slice(&id),
                    usage: wgpu::BufferUsages::STORAGE,
                },
            ));
        }
        Ok(())
    }

    /// The visibility maps (the stand-in when there are none).
    pub fn visibility_view(&self) -> Option<&wgpu::TextureView> {
        self.visibility
            .as_ref()
            .map(|v| &v.1)
            .or(self.dummy.as_ref())
    }

    /// The shadow cascades (the stand-in when there are none).
    pub fn shadow_view(&self) -> Option<&wgpu::TextureView> {
        self.shadows.as_ref().map(|v| &v.1).or(self.dummy.as_ref())
    }

    /// The sky cells' light matrices (the stand-in when there are none).
    pub fn cell_matrices(&self) -> Option<&wgpu::Buffer> {
        self.cell_matrices.as_ref()
    }
}

/// A depth-only render pass into layer `k` of a depth array, cleared to 1
/// (nothing occludes until the world is drawn).
fn layer_pass<'e>(
    enc: &'e mut wgpu::CommandEncoder,
    tex: &wgpu::Texture,
    k: u32,
) -> wgpu::RenderPass<'e> {
    let layer = tex.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        base_array_layer: k,
        array_layer_count: Some(1),
        ..Default::default()
    });
    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("light depth"),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &layer,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// Clears every layer of a depth array to 1.
fn clear_depth(gpu: &Gpu, tex: &wgpu::Texture) -> Result<(), RenderError> {
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    for k in 0..tex.depth_or_array_layers() {
        layer_pass(&mut enc, tex, k);
    }
    gpu.queue.submit([enc.finish()]);
    gpu.wait()
}

/// A read-only storage buffer of `rows` (one zero row when there are none:
/// a binding cannot be empty).
fn storage<const N: usize>(gpu: &Gpu, label: &str, rows: &[[f32; N]]) -> wgpu::Buffer {
    let zero = [[0.0f32; N]];
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(if rows.is_empty() { &zero } else { rows }),
            usage: wgpu::BufferUsages::STORAGE,
        })
}

/// Screen cells × distance slices of the aerial-perspective table.
pub const AIR_GRID: (u32, u32, u32) = (32, 18, 32);

/// The tables the lighting pass reads.
pub struct ShadeTables {
    /// The sky cells (`SkyCell` in shade.wgsl).
    pub cells: wgpu::Buffer,
    /// Their parts (`CellPart` in shade.wgsl).
    pub parts: wgpu::Buffer,
    /// The prefiltered environment (equirect, one layer per roughness),
    /// rgba16float scaled by 1 / `env_scale`.
    pub specular: wgpu::TextureView,
    specular_tex: wgpu::Texture,
    /// The split-sum BRDF table.
    pub brdf: wgpu::TextureView,
    /// The aerial perspective: in-scattering (rgba16float, scaled) and
    /// transmittance.
    pub air_in: wgpu::TextureView,
    /// See `air_in`.
    pub air_t: wgpu::TextureView,
    air_tex: (wgpu::Texture, wgpu::Texture),
    env_scale: f32,
    has_env: bool,
}

fn f16s(data: impl Iterator<Item = f32>) -> Vec<u16> {
    data.map(|v| half::f16::from_f32(v).to_bits()).collect()
}

/// A power of two that brings `max` to at most 2¹⁵ (half floats keep 11
/// bits of significand over their whole range; the scale keeps sunlit
/// skies below their 65504 ceiling).
fn half_scale(max: f32) -> f32 {
    if max > 32768.0 {
        2f32.powi((max / 32768.0).log2().ceil() as i32)
    } else {
        1.0
    }
}

fn write_3d(gpu: &Gpu, tex: &wgpu::Texture, data: &[u16], size: (u32, u32, u32)) {
    gpu.queue.write_texture(
        tex.as_image_copy(),
        bytemuck::cast_slice(data),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(size.0 * 8),
            rows_per_image: Some(size.1),
        },
        wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: size.2,
        },
    );
}

impl ShadeTables {
    /// Empty tables and the BRDF table.
    pub fn new(gpu: &Gpu) -> ShadeTables {
        let f16 = wgpu::TextureFormat::Rgba16Float;
        let use_ = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
        let d2 = wgpu::TextureDimension::D2;
        let (sw, sh) = SPECULAR_SIZE;
        let specular_tex = texture(
            gpu,
            "prefiltered sky",
            (sw as u32, sh as u32, SPECULAR_LEVELS as u32),
            d2,
            f16,
            use_,
        );
        let n = BRDF_LUT_SIZE as u32;
        let brdf_tex = texture(gpu, "split-sum brdf", (n, n, 1), d2, f16, use_);
        let table = brdf_lut();
        write_3d(
            gpu,
            &brdf_tex,
            &f16s(table.iter().flat_map(|v| [v[0], v[1], 0.0, 1.0])),
            (n, n, 1),
        );
        let d3 = wgpu::TextureDimension::D3;
        let air_in = texture(gpu, "air in-scattering", AIR_GRID, d3, f16, use_);
        let air_t = texture(gpu, "air transmittance", AIR_GRID, d3, f16, use_);
        let view = |t: &wgpu::Texture, dim| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(dim),
                ..Default::default()
            })
        };
        ShadeTables {
            cells: storage::<20>(gpu, "sky cells", &[]),
            parts: storage::<16>(gpu, "sky cell parts", &[]),
            specular: view(&specular_tex, wgpu::TextureViewDimension::D2Array),
            specular_tex,
            brdf: view(&brdf_tex, wgpu::TextureViewDimension::D2),
            air_in: view(&air_in, wgpu::TextureViewDimension::D3),
            air_t: view(&air_t, wgpu::TextureViewDimension::D3),
            air_tex: (air_in, air_t),
            env_scale: 1.0,
            has_env: false,
        }
    }

    /// Whether an environment light was uploaded.
    pub fn has_env(&self) -> bool {
        self.has_env
    }

    /// The scale of the half-float environment maps.
    pub fn env_scale(&self) -> f32 {
        self.env_scale
    }

    /// Uploads the sky cells (with their visibility maps' texel size, m)
    /// and the prefiltered environment (when `specular`).
    pub fn upload_env(&mut self, gpu: &Gpu, env: &EnvLight, texel_m: f32, specular: bool) {
        let cells: Vec<[f32; 20]> = env
            .cells
            .iter()
            .map(|c| {
                let mut v = [0.0f32; 20];
                v[..4].copy_from_slice(&[c.dir.x, c.dir.y, c.dir.z, texel_m]);
                let w = [c.solid_angle, 0.0, 0.0];
                for ch in 0..3 {
                    let m = c.moment[ch];
                    v[4 + 4 * ch..8 + 4 * ch].copy_from_slice(&[m.x, m.y, m.z, w[ch]]);
                }
                let horizon = if c.horizon { 1.0 } else { 0.0 };
                v[16..].copy_from_slice(&[
                    c.first_part as f32,
                    c.parts as f32,
                    c.tan_radius,
                    horizon,
                ]);
                v
            })
            .collect();
        let parts: Vec<[f32; 16]> = env
            .parts
            .iter()
            .map(|p| {
                let mut v = [0.0f32; 16];
                let w = [p.offset[0], p.offset[1], 0.0];
                for ch in 0..3 {
                    let m = p.moment[ch];
                    v[4 * ch..4 * ch + 4].copy_from_slice(&[m.x, m.y, m.z, w[ch]]);
                }
                v[12..14].copy_from_slice(&p.extent);
                v
            })
            .collect();
        self.cells = storage(gpu, "sky cells", &cells);
        self.parts = storage(gpu, "sky cell parts", &parts);
        if !specular {
            return;
        }
        self.env_scale = half_scale(env.max_radiance);
        let k = 1.0 / self.env_scale;
        let (sw, sh) = SPECULAR_SIZE;
        write_3d(
            gpu,
            &self.specular_tex,
            &f16s(
                env.specular
                    .iter()
                    .flat_map(|p| [p[0] * k, p[1] * k, p[2] * k, 1.0]),
            ),
            (sw as u32, sh as u32, SPECULAR_LEVELS as u32),
        );
        self.has_env = true;
    }

    /// Uploads the aerial perspective; returns (in-scattering scale, largest
    /// distance, slices) for the uniforms.
    pub fn upload_air(&mut self, gpu: &Gpu, air: &AerialPerspective) -> (f32, f32, f32) {
        let max = air
            .table
            .iter()
            .flat_map(|(l, _)| *l)
            .fold(0.0f32, f32::max);
        let scale = half_scale(max);
        let k = 1.0 / scale;
        // The table is per direction (row-major over the screen grid), then
        // per slice; the texture is x, y, then slice.
        let (gx, gy, gz) = AIR_GRID;
        let mut ins = Vec::with_capacity((gx * gy * gz) as usize);
        let mut tr = Vec::with_capacity(ins.capacity());
        for z in 0..gz as usize {
            for d in 0..(gx * gy) as usize {
                let (l, t) = air.table[d * gz as usize + z];
                ins.push([l[0] * k, l[1] * k, l[2] * k, 1.0]);
                tr.push([t[0], t[1], t[2], 1.0]);
            }
        }
        write_3d(
            gpu,
            &self.air_tex.0,
            &f16s(ins.into_iter().flatten()),
            AIR_GRID,
        );
        write_3d(
            gpu,
            &self.air_tex.1,
            &f16s(tr.into_iter().flatten()),
            AIR_GRID,
        );
        let dmax = air.distances_m.last().copied().unwrap_or(0.0);
        (scale, dmax, gz as f32)
    }

    /// A uniform buffer holding `bytes`.
    pub fn uniforms(&self, gpu: &Gpu, bytes: &[u8]) -> wgpu::Buffer {
        gpu.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("shade uniforms"),
                contents: bytes,
                usage: wgpu::BufferUsages::UNIFORM,
            })
    }
}
