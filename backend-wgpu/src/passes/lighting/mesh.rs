//! A world on the GPU: one vertex and one index buffer for every mesh, the
//! materials as a storage buffer, the base-colour textures resampled into
//! one mip-mapped 2D array, and the ground plane as a mesh of its own that
//! follows the camera.

use himmel_world::{Aabb, World};
use wgpu::util::DeviceExt;

use crate::gpu::Gpu;

/// Side of each base-colour texture layer, texels.
pub const TEXTURE_SIDE: u32 = 512;

/// A vertex: position and normal (world frame), texture coordinates.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// Position, metres.
    pub pos: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
    /// Texture coordinates.
    pub uv: [f32; 2],
}

/// A material as the shaders read it (`MaterialGpu` in WGSL).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MaterialGpu {
    /// Linear base colour and alpha.
    pub base_color: [f32; 4],
    /// Emitted radiance (cd/m²), and the texture layer + 1 (0: none).
    pub emissive_texture: [f32; 4],
    /// Metallic, roughness, 0, 0.
    pub metallic_roughness: [f32; 4],
}

/// One draw: an index range of one material.
#[derive(Debug, Clone, Copy)]
pub struct Draw {
    /// First index.
    pub first: u32,
    /// Index count.
    pub count: u32,
    /// Material index.
    pub material: u32,
}

/// Half-side of the ground plane, metres (beyond it the sky model's own
/// ground shows, seen under less than 0.002° at eye height).
pub const GROUND_HALF_M: f32 = 50_000.0;

/// A world uploaded to the GPU.
pub struct GpuWorld {
    /// Vertices of every mesh.
    pub vertices: wgpu::Buffer,
    /// Indices (u32) of every mesh, each draw's range.
    pub indices: wgpu::Buffer,
    /// The draws.
    pub draws: Vec<Draw>,
    /// The materials (`MaterialGpu`), the ground's last.
    pub materials: wgpu::Buffer,
    /// The base-colour textures (a 1×1 white layer when there are none).
    pub textures: wgpu::TextureView,
    /// The ground plane's four vertices (rewritten per frame).
    pub ground: wgpu::Buffer,
    /// The ground's index buffer (two triangles).
    pub ground_indices: wgpu::Buffer,
    /// The ground's material index.
    pub ground_material: u32,
    /// The world's bounds (`None` when empty).
    pub bounds: Option<Aabb>,
    /// Triangles and materials, for `--stats`.
    pub triangles: usize,
    /// See `triangles`.
    pub material_count: usize,
    /// The identity of the uploaded world's content ([`identity`]), to
    /// know when a new one is given.
    pub identity: (usize, usize, usize),
    /// The least roughness of a drawn material that is not Lambertian
    /// (metallic, or roughness < 1); `None` when all are Lambertian (the
    /// ssr pass's test).
    pub min_roughness: Option<f32>,
}

/// The identity of a world's content: an FNV-1a hash of its vertices,
/// indices and materials, with its triangle and material counts.
pub fn identity(world: &World) -> (usize, usize, usize) {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bits: u32| {
        for b in bits.to_le_bytes() {
            h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    for m in &world.meshes {
        m.positions.iter().flatten().for_each(|v| eat(v.to_bits()));
        m.normals.iter().flatten().for_each(|v| eat(v.to_bits()));
        m.indices.iter().for_each(|&i| eat(i));
        eat(m.material as u32);
    }
    for m in &world.materials {
        m.base_color
            .iter()
            .chain(&m.emissive)
            .for_each(|v| eat(v.to_bits()));
        eat(m.metallic.to_bits());
        eat(m.roughness.to_bits());
    }
    (h as usize, world.triangles(), world.materials.len())
}

impl GpuWorld {
    /// Uploads `world`; the ground material has linear albedo `ground_albedo`.
    pub fn new(gpu: &Gpu, world: &World, ground_albedo: f32) -> GpuWorld {
        let dev = &gpu.device;
        let mut vertices = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        let mut draws = Vec::new();
        for m in &world.meshes {
            let base = vertices.len() as u32;
            for (k, p) in m.positions.iter().enumerate() {
                vertices.push(Vertex {
                    pos: *p,
                    normal: m.normals.get(k).copied().unwrap_or([0.0, 1.0, 0.0]),
                    uv: m.uvs.get(k).copied().unwrap_or([0.0; 2]),
                });
            }
            let first = indices.len() as u32;
            indices.extend(m.indices.iter().map(|i| i + base));
            draws.push(Draw {
                first,
                count: m.indices.len() as u32,
                material: m.material as u32,
            });
        }
        if vertices.is_empty() {
            vertices.push(Vertex {
                pos: [0.0; 3],
                normal: [0.0, 1.0, 0.0],
                uv: [0.0; 2],
            });
        }
        if indices.is_empty() {
            indices.extend([0, 0, 0]);
        }
        let mut materials: Vec<MaterialGpu> = world
            .materials
            .iter()
            .map(|m| MaterialGpu {
                base_color: m.base_color,
                emissive_texture: [
                    m.emissive[0],
                    m.emissive[1],
                    m.emissive[2],
                    m.base_color_texture.map_or(0.0, |t| t as f32 + 1.0),
                ],
                metallic_roughness: [m.metallic, m.roughness, 0.0, 0.0],
            })
            .collect();
        let ground_material = materials.len() as u32;
        materials.push(MaterialGpu {
            base_color: [ground_albedo, ground_albedo, ground_albedo, 1.0],
            emissive_texture: [0.0; 4],
            metallic_roughness: [0.0, 1.0, 0.0, 0.0],
        });
        let init = |label, contents: &[u8], usage| {
            dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let ground = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("world ground"),
            size: 4 * std::mem::size_of::<Vertex>() as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let min_roughness = draws
            .iter()
            .filter_map(|d| world.materials.get(d.material as usize))
            .filter(|m| m.metallic > 0.0 || m.roughness < 1.0)
            .map(|m| m.roughness)
            .reduce(f32::min);
        GpuWorld {
            vertices: init(
                "world vertices",
                bytemuck::cast_slice(&vertices),
                wgpu::BufferUsages::VERTEX,
            ),
            indices: init(
                "world indices",
                bytemuck::cast_slice(&indices),
                wgpu::BufferUsages::INDEX,
            ),
            draws,
            materials: init(
                "world materials",
                bytemuck::cast_slice(&materials),
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            ),
            textures: textures(gpu, world),
            ground,
            ground_indices: init(
                "world ground indices",
                bytemuck::cast_slice(&[0u32, 1, 2, 0, 2, 3]),
                wgpu::BufferUsages::INDEX,
            ),
            ground_material,
            bounds: world.bounds(),
            min_roughness,
            triangles: world.triangles(),
            material_count: world.materials.len(),
            identity: identity(world),
        }
    }

    /// Sets the ground plane's linear albedo (the scene's
    /// `atmosphere.ground_albedo`).
    pub fn set_ground_albedo(&self, gpu: &Gpu, albedo: f32) {
        let m = MaterialGpu {
            base_color: [albedo, albedo, albedo, 1.0],
            emissive_texture: [0.0; 4],
            metallic_roughness: [0.0, 1.0, 0.0, 0.0],
        };
        let at = self.ground_material as u64 * std::mem::size_of::<MaterialGpu>() as u64;
        gpu.queue
            .write_buffer(&self.materials, at, bytemuck::bytes_of(&m));
    }

    /// Centres the ground plane under the eye (x, z).
    pub fn place_ground(&self, gpu: &Gpu, eye: glam::Vec3) {
        let h = GROUND_HALF_M;
        let v = |x: f32, z: f32| Vertex {
            pos: [eye.x + x, 0.0, eye.z + z],
            normal: [0.0, 1.0, 0.0],
            uv: [0.0; 2],
        };
        // Counter-clockwise seen from above (+y).
        let quad = [v(-h, h), v(h, h), v(h, -h), v(-h, -h)];
        gpu.queue
            .write_buffer(&self.ground, 0, bytemuck::cast_slice(&quad));
    }
}

/// The base-colour textures resampled (bilinear) to [`TEXTURE_SIDE`]² and
/// mip-mapped (box filter) in one rgba16float 2D array.
fn textures(gpu: &Gpu, world: &World) -> wgpu::TextureView {
    let layers = world.textures.len().max(1) as u32;
    let (side, mips) = if world.textures.is_empty() {
        (1, 1)
    } else {
        (TEXTURE_SIDE, TEXTURE_SIDE.ilog2() + 1)
    };
    let tex = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("world base colour"),
        size: wgpu::Extent3d {
            width: side,
            height: side,
            depth_or_array_layers: layers,
        },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba16Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let white = [vec![[1.0f32; 4]]];
    let mut all: Vec<Vec<Vec<[f32; 4]>>> = Vec::new();
    if world.textures.is_empty() {
        all.push(white.to_vec());
    }
    for t in &world.textures {
        let mut level = resample(t, side as usize);
        let mut chain = vec![level.clone()];
        let mut s = side as usize;
        while s > 1 {
            level = halve(&level, s);
            s /= 2;
            chain.push(level.clone());
        }
        all.push(chain);
    }
    for (layer, chain) in all.iter().enumerate() {
        for (mip, data) in chain.iter().enumerate() {
            let s = (side >> mip).max(1);
            let half: Vec<u16> = data
                .iter()
                .flat_map(|p| p.map(|c| half::f16::from_f32(c).to_bits()))
                .collect();
            gpu.queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &tex,
                    mip_level: mip as u32,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: layer as u32,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(&half),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(s * 8),
                    rows_per_image: Some(s),
                },
                wgpu::Extent3d {
                    width: s,
                    height: s,
                    depth_or_array_layers: 1,
                },
            );
        }
    }
    tex.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

/// Bilinear resampling of a texture to `side`² (wrapping, as glTF's default
/// sampler repeats).
fn resample(t: &himmel_world::Texture, side: usize) -> Vec<[f32; 4]> {
    let (w, h) = (t.width.max(1) as usize, t.height.max(1) as usize);
    let at = |x: isize, y: isize| {
        let (x, y) = (
            x.rem_euclid(w as isize) as usize,
            y.rem_euclid(h as isize) as usize,
        );
        t.texels.get(y * w + x).copied().unwrap_or([1.0; 4])
    };
    let mut out = Vec::with_capacity(side * side);
    for j in 0..side {
        for i in 0..side {
            let u = (i as f32 + 0.5) / side as f32 * w as f32 - 0.5;
            let v = (j as f32 + 0.5) / side as f32 * h as f32 - 0.5;
            let (x0, y0) = (u.floor(), v.floor());
            let (fx, fy) = (u - x0, v - y0);
            let (x0, y0) = (x0 as isize, y0 as isize);
            let mut p = [0.0f32; 4];
            for (dx, dy, wgt) in [
                (0, 0, (1.0 - fx) * (1.0 - fy)),
                (1, 0, fx * (1.0 - fy)),
                (0, 1, (1.0 - fx) * fy),
                (1, 1, fx * fy),
            ] {
                let q = at(x0 + dx, y0 + dy);
                for c in 0..4 {
                    p[c] += q[c] * wgt;
                }
            }
            out.push(p);
        }
    }
    out
}

/// The next mip level (2 × 2 box filter) of a `side`² level.
fn halve(level: &[[f32; 4]], side: usize) -> Vec<[f32; 4]> {
    let s = (side / 2).max(1);
    let mut out = Vec::with_capacity(s * s);
    for j in 0..s {
        for i in 0..s {
            let mut p = [0.0f32; 4];
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let q = level[(2 * j + dy).min(side - 1) * side + (2 * i + dx).min(side - 1)];
                for c in 0..4 {
                    p[c] += 0.25 * q[c];
                }
            }
            out.push(p);
        }
    }
    out
}
