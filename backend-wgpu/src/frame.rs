//! Frame resources: the target texture a frame leaves on the GPU, the
//! bands of rows the accumulation buffer holds at a time, the read-back
//! into an [`HdrImage`] (the 3D lighting passes keep their G-buffer in
//! `passes::lighting`).

use glam::DVec3;
use himmel_skymodel::renderer::{HdrImage, PassStat};
use himmel_skymodel::{Camera, LutOrigin, Projection, RenderError, SkyState, Unavailable};

use crate::gpu::{bind_group, storage_entry, uniform_entry, Gpu};
use crate::pool::{BufferPool, PoolBinding, Slot};
use crate::uniforms::{projection_code, FrameUniforms, NightUniforms};
use crate::PointMethod;

/// The texture format of every render target.
pub const TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

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
    /// Where the LUTs came from.
    pub lut_source: LutOrigin,
    /// Time of the per-frame sky-view LUTs, ms.
    pub sky_view_ms: f64,
    /// Time of the low clouds' height-field maps (CPU, frame plan), ms.
    pub cloud_maps_ms: f64,
    /// Time of the low clouds' diffusion grids (CPU, frame plan), ms.
    pub cloud_grid_ms: f64,
    /// How the stars and planets were drawn (`None` when neither pass
    /// ran): the renderer's [`PointMethod`], or tiles where a quad target
    /// of the image's width exceeds the adapter's texture limit.
    pub points: Option<PointMethod>,
    /// The Sun and Moon as directional lights and the sky's horizontal
    /// illuminance of this frame.
    pub lights: himmel_skymodel::frame::ObserverLights,
}

/// The image of a frame and how it is cut into bands of rows.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameLayout {
    /// Image width and height, px (the 6H×H strip for a cube map).
    pub width: u32,
    /// See `width`.
    pub height: u32,
    /// Whether the image is a cube map (six texture layers of H × H).
    pub cube: bool,
    /// Rows per band: the accumulation buffer holds this many rows.
    pub band_rows: u32,
    /// Each band's first row and row count.
    pub bands: Vec<(u32, u32)>,
}

impl FrameLayout {
    /// The layout of `cam`'s image on `gpu`: bands of rows within the
    /// storage-buffer limits (and `cap` bytes, if given); an error when a
    /// row or a texture side exceeds the adapter's limits.
    pub fn new(gpu: &Gpu, cam: &Camera, cap: Option<u64>) -> Result<FrameLayout, RenderError> {
        let (w, h) = cam.image_size();
        let cube = cam.projection == Projection::Cubemap;
        let tw = if cube { h } else { w };
        let limits = gpu.device.limits();
        let row_bytes = w as u64 * 16;
        let max_bytes = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size)
            .min(cap.unwrap_or(u64::MAX));
        if tw.max(h) > limits.max_texture_dimension_2d || row_bytes > max_bytes {
            return Err(RenderError::Unavailable(Unavailable::ImageTooLarge {
                width: w,
                height: h,
                max_side: limits.max_texture_dimension_2d,
            }));
        }
        let band_rows = (max_bytes / row_bytes).min(h as u64).max(1) as u32;
        let bands = (0..h.div_ceil(band_rows))
            .map(|b| (b * band_rows, band_rows.min(h - b * band_rows)))
            .collect();
        Ok(FrameLayout {
            width: w,
            height: h,
            cube,
            band_rows,
            bands,
        })
    }

    /// Bytes of the accumulation band.
    pub fn accum_bytes(&self) -> u64 {
        self.width as u64 * 16 * self.band_rows as u64
    }

    /// The frame's target texture: one layer, or six cube faces.
    pub fn target(&self, gpu: &Gpu) -> wgpu::Texture {
        let (tw, layers) = if self.cube {
            (self.height, 6)
        } else {
            (self.width, 1)
        };
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(if self.cube {
                "himmel cube map"
            } else {
                "himmel frame"
            }),
            size: wgpu::Extent3d {
                width: tw,
                height: self.height,
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
        })
    }
}

/// Copies a frame back into an [`HdrImage`] (a cube map as its 6H×H
/// strip): rows padded to 256 bytes on the GPU side.
pub fn read_back(gpu: &Gpu, pool: &BufferPool, frame: &GpuFrame) -> Result<HdrImage, RenderError> {
    let size = frame.texture.size();
    let (tw, th, layers) = (size.width, size.height, size.depth_or_array_layers);
    let row = tw as u64 * 16;
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as u64;
    let padded = row.div_ceil(align) * align;
    let read_size = padded * th as u64 * layers as u64;
    let read = pool.get(
        &gpu.device,
        Slot::FrameRead,
        read_size,
        wgpu::BufferUsages::MAP_READ,
    );
    let mut enc = gpu.device.create_command_encoder(&Default::default());
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
    gpu.queue.submit([enc.finish()]);
    let bytes = gpu.map_read(&read, read_size)?;
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

/// Group 0 of every sky pass (shaders/frame.wgsl): the frame uniforms of
/// the band, the accumulation band, the sky views, the Sun table, the
/// target texture, the night constants, the Milky Way map, the extinction
/// table, the point records and their tile lists. One bind group per band
/// serves every pass; a pass that runs binds what it reads, the others get
/// small placeholders.
pub struct SkyGroup {
    /// The layout (built once).
    pub layout: wgpu::BindGroupLayout,
}

impl SkyGroup {
    /// The layout of group 0.
    pub fn new(gpu: &Gpu) -> SkyGroup {
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
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
        SkyGroup { layout }
    }
}

/// A frame under construction: the frame uniforms the passes fill in
/// (camera, Sun, sky-view sizes, …) and the group-0 resources they
/// prepare.
pub struct FrameBuild {
    /// The frame uniforms (the band's rows are set per band).
    pub uniforms: FrameUniforms,
    /// The sky views (per input: w × h texels, then the ground).
    pub sky: Option<wgpu::Buffer>,
    /// The Sun table.
    pub sun_table: Option<PoolBinding>,
    /// The night constants: the Milky Way pass fills its part, the point
    /// passes theirs.
    pub night: NightUniforms,
    /// The Milky Way map.
    pub milkyway_map: Option<wgpu::Buffer>,
    /// The Milky Way pass's extinction table.
    pub extinction: Option<PoolBinding>,
    /// The point sources' footprint records.
    pub points: Option<PoolBinding>,
    /// The point sources' per-tile lists.
    pub tiles: Option<PoolBinding>,
}

impl FrameBuild {
    /// An empty frame with these uniforms.
    pub fn new(uniforms: FrameUniforms) -> FrameBuild {
        FrameBuild {
            uniforms,
            sky: None,
            sun_table: None,
            night: NightUniforms {
                map_width: 2,
                map_height: 2,
                extinction_nodes: 2,
                ..bytemuck::Zeroable::zeroed()
            },
            milkyway_map: None,
            extinction: None,
            points: None,
            tiles: None,
        }
    }

    /// Group 0 of each band of `layout`: the bands' uniforms in one buffer
    /// at aligned offsets, the accumulation band, the target's view and
    /// the prepared resources (placeholders for those no pass prepared).
    pub fn bind(
        &self,
        gpu: &Gpu,
        pool: &BufferPool,
        group: &SkyGroup,
        layout: &FrameLayout,
        target: &wgpu::TextureView,
    ) -> BoundFrame {
        let dev = &gpu.device;
        let storage = wgpu::BufferUsages::STORAGE;
        let placeholder = |slot: Slot, bytes: usize| {
            pool.upload(dev, &gpu.queue, slot, &vec![0u8; bytes], storage)
        };
        let whole = |b: &wgpu::Buffer| PoolBinding {
            buffer: b.clone(),
            offset: 0,
            size: b.size(),
        };
        let sky = self
            .sky
            .as_ref()
            .map(whole)
            .unwrap_or_else(|| placeholder(Slot::NoSky, 32));
        let sun_table = self
            .sun_table
            .clone()
            .unwrap_or_else(|| placeholder(Slot::SunTable, 16));
        let night = pool.upload(
            dev,
            &gpu.queue,
            Slot::Night,
            bytemuck::bytes_of(&self.night),
            wgpu::BufferUsages::UNIFORM,
        );
        let map = self
            .milkyway_map
            .as_ref()
            .map(whole)
            .unwrap_or_else(|| placeholder(Slot::NoMilkyWayMap, 64));
        let extinction = self
            .extinction
            .clone()
            .unwrap_or_else(|| placeholder(Slot::Extinction, 32));
        let points = self
            .points
            .clone()
            .unwrap_or_else(|| placeholder(Slot::PointRecords, 48));
        let tiles = self
            .tiles
            .clone()
            .unwrap_or_else(|| placeholder(Slot::PointTiles, 16));
        // The bands' uniforms in one buffer, each at an aligned offset.
        let size = std::mem::size_of::<FrameUniforms>();
        let align = dev.limits().min_uniform_buffer_offset_alignment as usize;
        let stride = size.next_multiple_of(align);
        let mut bytes = vec![0u8; stride * layout.bands.len()];
        for (k, &(row0, rows)) in layout.bands.iter().enumerate() {
            let u = FrameUniforms {
                band_first_row: row0,
                band_rows: rows,
                sun_y0: self.uniforms.sun_y0.clamp(row0, row0 + rows),
                ..self.uniforms
            };
            bytes[k * stride..k * stride + size].copy_from_slice(bytemuck::bytes_of(&u));
        }
        let frames = pool.upload(
            dev,
            &gpu.queue,
            Slot::Frame,
            &bytes,
            wgpu::BufferUsages::UNIFORM,
        );
        let accum = PoolBinding {
            buffer: pool.get(dev, Slot::Accum, layout.accum_bytes(), storage),
            offset: 0,
            size: layout.accum_bytes(),
        };
        let uniforms: Vec<PoolBinding> = (0..layout.bands.len())
            .map(|k| PoolBinding {
                buffer: frames.buffer.clone(),
                offset: (k * stride) as u64,
                size: size as u64,
            })
            .collect();
        let groups = uniforms
            .iter()
            .map(|uniform| {
                bind_group(
                    dev,
                    "sky",
                    &group.layout,
                    &[
                        uniform.resource(),
                        accum.resource(),
                        sky.resource(),
                        sun_table.resource(),
                        wgpu::BindingResource::TextureView(target),
                        night.resource(),
                        map.resource(),
                        extinction.resource(),
                        points.resource(),
                        tiles.resource(),
                    ],
                )
            })
            .collect();
        BoundFrame {
            groups,
            uniforms,
            night,
            points,
            tiles,
        }
    }
}

/// A frame's group 0 per band and the bindings passes with layouts of
/// their own bind again (the point quads).
pub struct BoundFrame {
    /// Group 0 of each band.
    pub groups: Vec<wgpu::BindGroup>,
    /// Each band's frame uniforms.
    pub uniforms: Vec<PoolBinding>,
    /// The night constants.
    pub night: PoolBinding,
    /// The point records.
    pub points: PoolBinding,
    /// The point tile lists.
    pub tiles: PoolBinding,
}

/// The frame uniforms every pass reads: the camera (image size,
/// projection, perspective basis) and the directions the sky lookups use
/// (the Sun; the Moon that hides it). The passes add their own fields.
pub fn base_uniforms(cam: &Camera, state: &SkyState) -> FrameUniforms {
    let (w, h) = cam.image_size();
    let (f, r, u, t) = perspective_basis(cam);
    let projection = match cam.projection {
        Projection::Fisheye => projection_code::FISHEYE,
        Projection::Equirect => projection_code::EQUIRECT,
        Projection::Perspective => projection_code::PERSPECTIVE,
        Projection::Cubemap => projection_code::CUBEMAP,
    };
    FrameUniforms {
        width: w,
        height: h,
        projection,
        face_size: h,
        forward: f.as_vec3().to_array(),
        tan_half_fov: t as f32,
        right: r.as_vec3().to_array(),
        up: u.as_vec3().to_array(),
        sun: state.sun.dir().as_vec3().normalize().to_array(),
        eclipse_moon: state.moon.dir().as_vec3().to_array(),
        sky_view_width: 1,
        sky_view_height: 1,
        band_rows: h,
        ..bytemuck::Zeroable::zeroed()
    }
}

/// The perspective camera's basis (ENU: forward, right, up) and
/// tan(fov / 2), as projection.rs builds it.
fn perspective_basis(cam: &Camera) -> (DVec3, DVec3, DVec3, f64) {
    let (f, right, up) = cam.basis();
    (f, right, up, (cam.fov_deg.to_radians() / 2.0).tan())
}
