//! The lighting passes' pipelines, built once on the first world frame:
//! the G-buffer raster (`shaders/lighting/gbuffer.wgsl`), the depth-only
//! raster of the light maps (`depth.wgsl`), the light shafts' march
//! (`godrays.wgsl`) and the lighting compute pass (`shade.wgsl`), with
//! their bind-group layouts and samplers.

use crate::gpu::Gpu;

use super::mesh::Vertex;

/// The G-buffer's colour formats, in location order: distance, normal +
/// roughness, base colour + metallic, material + 1, velocity.
pub const GBUFFER_FORMATS: [wgpu::TextureFormat; 5] = [
    wgpu::TextureFormat::R32Float,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::R32Uint,
    wgpu::TextureFormat::Rg16Float,
];

/// The depth format of the G-buffer and of the shadow maps.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The depth format of the sky's visibility maps: 16 bits across a
/// world's depth (a millimetre in 60 m) halve the memory of a thousand
/// maps.
pub const VISIBILITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth16Unorm;

/// Stride of the light matrices in their uniform buffer (dynamic offsets).
pub const MATRIX_STRIDE: u64 = 256;

/// Every pipeline of the lighting passes.
pub struct Pipelines {
    /// The G-buffer raster.
    pub gbuffer: wgpu::RenderPipeline,
    /// Its group 0: camera, materials, base-colour textures, sampler.
    pub gbuffer_layout: wgpu::BindGroupLayout,
    /// The shadow maps' depth raster ([`DEPTH_FORMAT`]).
    pub depth: wgpu::RenderPipeline,
    /// The visibility maps' depth raster ([`VISIBILITY_FORMAT`]).
    pub visibility_depth: wgpu::RenderPipeline,
    /// Its group 0: one light matrix at a dynamic offset.
    pub depth_layout: wgpu::BindGroupLayout,
    /// The lighting compute pass.
    pub shade: wgpu::ComputePipeline,
    /// The sky pass (each pixel's interleaved set of cells).
    pub sky: wgpu::ComputePipeline,
    /// Group 1 of the sky pass: its two outputs as storage textures.
    pub sky_out_layout: wgpu::BindGroupLayout,
    /// The gather pass (each pixel's block of sets, shade.wgsl `gather`).
    pub sky_gather: wgpu::ComputePipeline,
    /// Its group 1: the sky pass's outputs as textures.
    pub sky_raw_layout: wgpu::BindGroupLayout,
    /// Its group 2: its three outputs as storage textures.
    pub gather_out_layout: wgpu::BindGroupLayout,
    /// Group 1 of the lighting pass: the sky pass's outputs as textures.
    pub sky_in_layout: wgpu::BindGroupLayout,
    /// Its group 0 (shade.wgsl's bindings 0–17).
    pub shade_layout: wgpu::BindGroupLayout,
    /// The light shafts' march and its full-resolution refinement
    /// (godrays.wgsl `march`, `refine`, `march_list`).
    pub godrays: [wgpu::ComputePipeline; 3],
    /// Its group 0: uniforms, distance, material, shadow maps, comparison
    /// sampler, output, sky cells, their matrices and visibility maps, the
    /// reduced image and the pixels left to march (`refine`).
    pub godrays_layout: wgpu::BindGroupLayout,
    /// Trilinear, repeating (base colour).
    pub repeat: wgpu::Sampler,
    /// Bilinear, clamped (environment, BRDF table, air table).
    pub clamp: wgpu::Sampler,
    /// Bilinear depth comparison (≤), clamped: 2×2 PCF per lookup.
    pub compare: wgpu::Sampler,
}

fn entry(
    binding: u32,
    vis: wgpu::ShaderStages,
    ty: wgpu::BindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: vis,
        ty,
        count: None,
    }
}

fn texture(
    sample_type: wgpu::TextureSampleType,
    dim: wgpu::TextureViewDimension,
) -> wgpu::BindingType {
    wgpu::BindingType::Texture {
        sample_type,
        view_dimension: dim,
        multisampled: false,
    }
}

fn buffer(ty: wgpu::BufferBindingType, dynamic: bool) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty,
        has_dynamic_offset: dynamic,
        min_binding_size: None,
    }
}

const STORAGE_RO: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: true };

impl Pipelines {
    /// Compiles the lighting passes on `gpu`.
    pub fn new(gpu: &Gpu) -> Pipelines {
        let dev = &gpu.device;
        let (gbuffer_layout, depth_layout, shade_layout) = layouts(dev);
        let attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2];
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &attrs,
        };
        let gmod = gpu.shader(
            "gbuffer.wgsl",
            include_str!("../../shaders/lighting/gbuffer.wgsl"),
        );
        let targets: Vec<Option<wgpu::ColorTargetState>> = GBUFFER_FORMATS
            .iter()
            .map(|&format| {
                Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })
            })
            .collect();
        let gbuffer = dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("gbuffer"),
            layout: Some(&gpu.pipeline_layout("gbuffer", &[&gbuffer_layout])),
            vertex: wgpu::VertexState {
                module: &gmod,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[Some(vertex_layout)],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::GreaterEqual),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &gmod,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        });
        let depth = depth_pipeline(gpu, &depth_layout, DEPTH_FORMAT);
        let visibility_depth = depth_pipeline(gpu, &depth_layout, VISIBILITY_FORMAT);
        let smod = gpu.shader(
            "shade.wgsl",
            concat!(
                include_str!("../../shaders/lighting/common.wgsl"),
                include_str!("../../shaders/lighting/shade.wgsl"),
                include_str!("../../shaders/lighting/sky_cells.wgsl"),
                include_str!("../../shaders/lighting/sky_gather.wgsl"),
                include_str!("../../shaders/lighting/shafts_gather.wgsl")
            ),
        );
        let [sky_out_layout, gather_out_layout, sky_raw_layout, sky_in_layout] = sky_layouts(dev);
        let (godrays, godrays_layout) = godrays_pipeline(gpu);
        let shade = gpu.compute_pipeline(
            &gpu.pipeline_layout("shade", &[&shade_layout, &sky_in_layout]),
            &smod,
            "shade",
        );
        let sky = gpu.compute_pipeline(
            &gpu.pipeline_layout("sky", &[&shade_layout, &sky_out_layout]),
            &smod,
            "sky",
        );
        let sky_gather = gpu.compute_pipeline(
            &gpu.pipeline_layout(
                "sky gather",
                &[&shade_layout, &sky_raw_layout, &gather_out_layout],
            ),
            &smod,
            "gather",
        );
        let sampler = |label, mode, compare| {
            dev.create_sampler(&wgpu::SamplerDescriptor {
                label: Some(label),
                address_mode_u: mode,
                address_mode_v: mode,
                address_mode_w: wgpu::AddressMode::ClampToEdge,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                compare,
                ..Default::default()
            })
        };
        Pipelines {
            gbuffer,
            gbuffer_layout,
            depth,
            visibility_depth,
            depth_layout,
            shade,
            shade_layout,
            sky,
            sky_out_layout,
            sky_gather,
            sky_raw_layout,
            gather_out_layout,
            sky_in_layout,
            godrays,
            godrays_layout,
            repeat: sampler("repeat", wgpu::AddressMode::Repeat, None),
            clamp: sampler("clamp", wgpu::AddressMode::ClampToEdge, None),
            compare: sampler(
                "compare",
                wgpu::AddressMode::ClampToEdge,
                Some(wgpu::CompareFunction::LessEqual),
            ),
        }
    }
}

/// The layouts of the sky and gather passes' outputs (storage), of the
/// gather pass's inputs and of the lighting pass's group 1 (shade.wgsl).
fn sky_layouts(dev: &wgpu::Device) -> [wgpu::BindGroupLayout; 4] {
    let c = wgpu::ShaderStages::COMPUTE;
    let storage = |binding, format| {
        entry(
            binding,
            c,
            wgpu::BindingType::StorageTexture {
                access: wgpu::StorageTextureAccess::WriteOnly,
                format,
                view_dimension: wgpu::TextureViewDimension::D2,
            },
        )
    };
    let sky_out_layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("sky out"),
        entries: &[
            storage(0, wgpu::TextureFormat::Rgba32Float),
            storage(1, wgpu::TextureFormat::Rgba32Float),
        ],
    });
    let gather_out_layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("sky gather out"),
        entries: &[
            storage(0, wgpu::TextureFormat::Rgba32Float),
            storage(1, wgpu::TextureFormat::Rgba32Float),
            storage(2, wgpu::TextureFormat::R32Float),
        ],
    });
    let unfiltered = wgpu::TextureSampleType::Float { filterable: false };
    let plain = |binding| {
        entry(
            binding,
            c,
            texture(unfiltered, wgpu::TextureViewDimension::D2),
        )
    };
    let sky_raw_layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("sky raw"),
        entries: &[plain(11), plain(12)],
    });
    let sky_in_layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("sky in"),
        entries: &[
            entry(2, c, texture(unfiltered, wgpu::TextureViewDimension::D2)),
            entry(3, c, texture(unfiltered, wgpu::TextureViewDimension::D2)),
            plain(10),
            entry(4, c, texture(unfiltered, wgpu::TextureViewDimension::D2)),
            entry(8, c, texture(unfiltered, wgpu::TextureViewDimension::D2)),
            entry(5, c, texture(unfiltered, wgpu::TextureViewDimension::D2)),
            entry(
                9,
                c,
                texture(
                    wgpu::TextureSampleType::Uint,
                    wgpu::TextureViewDimension::D2,
                ),
            ),
            storage(6, wgpu::TextureFormat::Rgba32Float),
            storage(7, wgpu::TextureFormat::Rgba32Float),
        ],
    });
    [
        sky_out_layout,
        gather_out_layout,
        sky_raw_layout,
        sky_in_layout,
    ]
}

/// The light shafts' march (`godrays.wgsl`) and its group 0: uniforms,
/// distance, material, shadow maps, comparison sampler, output, sky cells,
/// their matrices and visibility maps, the reduced image and the pixels
/// left to march (`refine`).
fn godrays_pipeline(gpu: &Gpu) -> ([wgpu::ComputePipeline; 3], wgpu::BindGroupLayout) {
    let dev = &gpu.device;
    let c = wgpu::ShaderStages::COMPUTE;
    let unfiltered = wgpu::TextureSampleType::Float { filterable: false };
    let rmod = gpu.shader(
        "godrays.wgsl",
        concat!(
            include_str!("../../shaders/lighting/common.wgsl"),
            include_str!("../../shaders/lighting/shafts.wgsl"),
            include_str!("../../shaders/lighting/shafts_sky.wgsl"),
            include_str!("../../shaders/lighting/godrays.wgsl"),
            include_str!("../../shaders/lighting/shafts_gather.wgsl")
        ),
    );
    let godrays_layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("godrays"),
        entries: &[
            entry(0, c, buffer(wgpu::BufferBindingType::Uniform, false)),
            entry(1, c, texture(unfiltered, wgpu::TextureViewDimension::D2)),
            entry(
                2,
                c,
                texture(
                    wgpu::TextureSampleType::Uint,
                    wgpu::TextureViewDimension::D2,
                ),
            ),
            entry(
                3,
                c,
                texture(
                    wgpu::TextureSampleType::Depth,
                    wgpu::TextureViewDimension::D2Array,
                ),
            ),
            entry(
                4,
                c,
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
            ),
            entry(
                5,
                c,
                wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format: wgpu::TextureFormat::Rgba32Float,
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
            ),
            entry(6, c, buffer(STORAGE_RO, false)),
            entry(7, c, buffer(STORAGE_RO, false)),
            entry(
                8,
                c,
                texture(
                    wgpu::TextureSampleType::Depth,
                    wgpu::TextureViewDimension::D2Array,
                ),
            ),
            entry(9, c, texture(unfiltered, wgpu::TextureViewDimension::D2)),
            entry(
                10,
                c,
                buffer(wgpu::BufferBindingType::Storage { read_only: false }, false),
            ),
        ],
    });
    let pl = gpu.pipeline_layout("godrays", &[&godrays_layout]);
    let godrays = [
        gpu.compute_pipeline(&pl, &rmod, "march"),
        gpu.compute_pipeline(&pl, &rmod, "refine"),
        gpu.compute_pipeline(&pl, &rmod, "march_list"),
    ];
    (godrays, godrays_layout)
}

/// The bind-group layouts of the G-buffer, the light depth and the
/// lighting passes.
fn layouts(
    dev: &wgpu::Device,
) -> (
    wgpu::BindGroupLayout,
    wgpu::BindGroupLayout,
    wgpu::BindGroupLayout,
) {
    use wgpu::ShaderStages as S;
    use wgpu::TextureSampleType as T;
    use wgpu::TextureViewDimension as D;
    let float = T::Float { filterable: true };
    let unfiltered = T::Float { filterable: false };
    let layout = |label: &str, entries: &[wgpu::BindGroupLayoutEntry]| {
        dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries,
        })
    };
    let gbuffer_layout = layout(
        "gbuffer",
        &[
            entry(
                0,
                S::VERTEX_FRAGMENT,
                buffer(wgpu::BufferBindingType::Uniform, false),
            ),
            entry(1, S::FRAGMENT, buffer(STORAGE_RO, false)),
            entry(2, S::FRAGMENT, texture(float, D::D2Array)),
            entry(
                3,
                S::FRAGMENT,
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            ),
        ],
    );
    let depth_layout = layout(
        "light depth",
        &[entry(
            0,
            S::VERTEX,
            buffer(wgpu::BufferBindingType::Uniform, true),
        )],
    );
    let c = S::COMPUTE;
    let shade_layout = layout(
        "shade",
        &[
            entry(0, c, buffer(wgpu::BufferBindingType::Uniform, false)),
            entry(1, c, texture(unfiltered, D::D2)),
            entry(2, c, texture(unfiltered, D::D2)),
            entry(3, c, texture(unfiltered, D::D2)),
            entry(4, c, texture(T::Uint, D::D2)),
            entry(
                5,
                c,
                wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format: crate::TARGET_FORMAT,
                    view_dimension: D::D2,
                },
            ),
            entry(6, c, buffer(STORAGE_RO, false)),
            entry(7, c, buffer(STORAGE_RO, false)),
            entry(8, c, buffer(STORAGE_RO, false)),
            entry(9, c, texture(T::Depth, D::D2Array)),
            entry(10, c, texture(T::Depth, D::D2Array)),
            entry(
                11,
                c,
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
            ),
            entry(12, c, texture(float, D::D2Array)),
            entry(13, c, texture(float, D::D2)),
            entry(
                14,
                c,
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            ),
            entry(15, c, texture(float, D::D3)),
            entry(16, c, texture(float, D::D3)),
            entry(17, c, buffer(STORAGE_RO, false)),
        ],
    );
    (gbuffer_layout, depth_layout, shade_layout)
}

/// The depth-only raster of the light maps (positions only).
fn depth_pipeline(
    gpu: &Gpu,
    depth_layout: &wgpu::BindGroupLayout,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    let dev = &gpu.device;
    let pos_only = [wgpu::VertexAttribute {
        format: wgpu::VertexFormat::Float32x3,
        offset: 0,
        shader_location: 0,
    }];
    let pos_layout = wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &pos_only,
    };
    let dmod = gpu.shader(
        "depth.wgsl",
        include_str!("../../shaders/lighting/depth.wgsl"),
    );
    dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("light depth"),
        layout: Some(&gpu.pipeline_layout("light depth", &[depth_layout])),
        vertex: wgpu::VertexState {
            module: &dmod,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[Some(pos_layout)],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::LessEqual),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    })
}
