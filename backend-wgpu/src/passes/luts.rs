//! The parameter-dependent atmosphere LUTs computed by WGSL compute
//! shaders (`src/shaders/luts.wgsl`), a port of skymodel lut.rs
//! `AtmosphereLuts::transmittance_lut` and `AtmosphereLuts::multiscatter_row`
//! (Hillaire 2020, "A scalable and production ready sky and atmosphere
//! rendering technique", EGSR, §4–5; the transmittance parameterisation of
//! Bruneton 2017): the same parametrisation, step counts and direction set
//! ([`sphere_directions`], uploaded), written in the buffer layout the
//! sky-view shader reads (three vec4 band groups per texel).
//!
//! [`LutSource`] chooses between these and the CPU precompute
//! (the frame plan's LUT store: `himmel_skymodel::frame::luts::precompute`
//! with its disk cache) uploaded, held in a [`LutSlot`].

use bytemuck::{Pod, Zeroable};
use himmel_skymodel::atmosphere::lut::{forward_scattering, sphere_directions, Lut2};
use himmel_skymodel::atmosphere::{AtmosphereLuts, AtmosphereParams, LutConfig, Medium};
use himmel_skymodel::renderer::RenderError;
use himmel_skymodel::spectrum::{Spectrum, BANDS};
use wgpu::util::DeviceExt;

use crate::gpu::{bind_group, device_error, storage_entry, uniform_entry, Gpu};

/// The WGSL source of the LUT passes: `luts.wgsl` followed by the medium
/// functions it shares with the sky-view passes (`medium.wgsl`).
pub const LUTS_WGSL: &str = concat!(
    include_str!("../shaders/luts.wgsl"),
    include_str!("../shaders/medium.wgsl"),
    include_str!("../shaders/bilinear.wgsl")
);

/// Where [`crate::WgpuRenderer`] takes the parameter-dependent LUTs from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LutSource {
    /// Computed by the compute shaders of this module (`lut_source`
    /// `gpu`), read back once per parameter set for the CPU-side tables
    /// (Sun disk, star extinction).
    Gpu,
    /// The LUT store's CPU precompute (`himmel_skymodel::frame::LutStore`, memory and disk
    /// cache: `lut_source` `computed`, `disk-cache`, `memory`), uploaded.
    Cpu,
}

impl LutSource {
    /// `gpu` or `cpu`.
    pub fn name(self) -> &'static str {
        match self {
            LutSource::Gpu => "gpu",
            LutSource::Cpu => "cpu",
        }
    }

    /// The default for an adapter: the compute shaders on a hardware GPU;
    /// the CPU precompute on a software adapter (`DeviceType::Cpu`, e.g.
    /// Mesa's lavapipe), which runs on the same cores: there the shaders
    /// gain little per computation while the CPU precompute's disk cache
    /// serves every later process in about a millisecond (figures: README,
    /// `tests/benches/wgpu_render.rs` group `precompute`).
    pub fn default_for(device_type: wgpu::DeviceType) -> Self {
        match device_type {
            wgpu::DeviceType::Cpu => LutSource::Cpu,
            _ => LutSource::Gpu,
        }
    }
}

/// Mirror of WGSL `struct LutParams` (src/shaders/luts.wgsl): the medium
/// (medium.rs `Medium`, coefficients in km⁻¹, spectra as three vec4 band
/// groups, the last two lanes zero) and the LUT configuration. 320 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct LutUniforms {
    /// Rayleigh scattering at sea level, km⁻¹.
    pub rayleigh: [[f32; 4]; 3],
    /// Aerosol scattering at sea level, km⁻¹.
    pub mie_scattering: [[f32; 4]; 3],
    /// Aerosol extinction at sea level, km⁻¹.
    pub mie_extinction: [[f32; 4]; 3],
    /// Ozone absorption at the peak, km⁻¹.
    pub ozone: [[f32; 4]; 3],
    /// δ-scaled forward scattering f·σ_M (lut.rs `forward_scattering`), km⁻¹.
    pub forward: [[f32; 4]; 3],
    /// Ground radius, km.
    pub bottom_radius: f32,
    /// Top-of-atmosphere radius, km.
    pub top_radius: f32,
    /// Inverse Rayleigh scale height, km⁻¹.
    pub inv_h_rayleigh: f32,
    /// Inverse aerosol scale height, km⁻¹.
    pub inv_h_mie: f32,
    /// Ozone peak altitude, km.
    pub ozone_peak: f32,
    /// Inverse ozone half width, km⁻¹.
    pub inv_ozone_width: f32,
    /// Aerosol asymmetry parameter g.
    pub mie_g: f32,
    /// Ground albedo.
    pub ground_albedo: f32,
    /// The Sun's angular radius, rad.
    pub sun_angular_radius: f32,
    /// cos of the forward peak's half angle.
    pub cos_forward_peak: f32,
    /// 1 when the aerosol phase is flattened within the forward peak, 0
    /// otherwise.
    pub forward_peak: u32,
    /// Scattering orders of the multiple-scattering series (0: all).
    pub orders: u32,
    /// Transmittance LUT width, texels.
    pub transmittance_width: u32,
    /// Transmittance LUT height, texels.
    pub transmittance_height: u32,
    /// Ray-march steps per transmittance texel.
    pub transmittance_steps: u32,
    /// Multiple-scattering LUT size n (n × n texels).
    pub multiscatter_n: u32,
    /// Multiple-scattering directions (k², as [`sphere_directions`]
    /// returns them).
    pub multiscatter_dirs: u32,
    /// Ray-march steps per multiple-scattering direction.
    pub multiscatter_steps: u32,
    /// Padding.
    pub _pad0: u32,
    /// Padding.
    pub _pad1: u32,
}

/// The uniforms of the LUT passes for `medium` and `config`; `dirs` is the
/// number of multiple-scattering directions.
pub fn lut_uniforms(medium: &Medium, config: &LutConfig, dirs: usize) -> LutUniforms {
    let m = medium;
    LutUniforms {
        rayleigh: band_groups(&m.rayleigh),
        mie_scattering: band_groups(&m.mie_scattering),
        mie_extinction: band_groups(&m.mie_extinction),
        ozone: band_groups(&m.ozone),
        forward: band_groups(&forward_scattering(m, config)),
        bottom_radius: m.bottom,
        top_radius: m.top,
        inv_h_rayleigh: m.inv_h_r,
        inv_h_mie: m.inv_h_m,
        ozone_peak: m.ozone_peak,
        inv_ozone_width: m.inv_ozone_w,
        mie_g: m.g,
        ground_albedo: m.albedo,
        sun_angular_radius: m.sun_angular_radius,
        cos_forward_peak: config.forward_peak_deg.to_radians().cos(),
        forward_peak: (config.forward_peak_deg > 0.0) as u32,
        orders: config.orders,
        transmittance_width: config.transmittance_w as u32,
        transmittance_height: config.transmittance_h as u32,
        transmittance_steps: config.transmittance_steps as u32,
        multiscatter_n: config.multiscatter_n as u32,
        multiscatter_dirs: dirs as u32,
        multiscatter_steps: config.multiscatter_steps as u32,
        _pad0: 0,
        _pad1: 0,
    }
}

/// The compiled LUT passes (`transmittance`, `multiscatter`) and their
/// bind group layout.
#[derive(Debug)]
pub struct LutPipelines {
    layout: wgpu::BindGroupLayout,
    transmittance: wgpu::ComputePipeline,
    multiscatter: wgpu::ComputePipeline,
}

impl LutPipelines {
    /// Compiles `luts.wgsl` on `device`.
    pub fn new(device: &wgpu::Device) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("luts.wgsl"),
            source: wgpu::ShaderSource::Wgsl(LUTS_WGSL.into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("atmosphere LUTs"),
            entries: &[
                uniform_entry::<LutUniforms>(0),
                storage_entry(1, false),
                storage_entry(2, false),
                storage_entry(3, false),
                storage_entry(4, true),
            ],
        });
        let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("atmosphere LUTs"),
            bind_group_layouts: &[Some(&layout)],
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
        LutPipelines {
            transmittance: pipeline("transmittance"),
            multiscatter: pipeline("multiscatter"),
            layout,
        }
    }
}

/// The LUTs on the GPU (three vec4 band groups per texel, row-major):
/// transmittance, δ-scaled transmittance, multiple scattering Ψ_ms.
#[derive(Debug)]
pub struct LutBuffers {
    /// Transmittance to the top of the atmosphere, `transmittance_w` ×
    /// `transmittance_h` texels.
    pub trans: wgpu::Buffer,
    /// δ-scaled transmittance, same size.
    pub trans_s: wgpu::Buffer,
    /// Ψ_ms, `multiscatter_n`² texels (u: μ_s, v: altitude).
    pub multi: wgpu::Buffer,
}

/// Why `config` cannot be computed on the GPU (a zero size or step count).
fn check(config: &LutConfig) -> Result<(), RenderError> {
    let sizes = [
        ("transmittance_w", config.transmittance_w),
        ("transmittance_h", config.transmittance_h),
        ("transmittance_steps", config.transmittance_steps),
        ("multiscatter_n", config.multiscatter_n),
        ("multiscatter_dirs", config.multiscatter_dirs),
        ("multiscatter_steps", config.multiscatter_steps),
    ];
    for (name, v) in sizes {
        if v == 0 || v > u32::MAX as usize / 64 {
            return Err(RenderError::Scene(himmel_skymodel::SceneError {
                field: format!("lut.{name}"),
                message: format!("must be in 1..={}, got {v}", u32::MAX / 64),
            }));
        }
    }
    Ok(())
}

/// Records and submits the LUT passes for `params` and `config` (the
/// transmittance pair, then Ψ_ms from the δ-scaled transmittance); does
/// not wait for completion. Returns the output buffers (`STORAGE |
/// COPY_SRC`).
pub fn dispatch(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    p: &LutPipelines,
    params: &AtmosphereParams,
    config: &LutConfig,
) -> Result<LutBuffers, RenderError> {
    check(config)?;
    let medium = Medium::new(params);
    let dirs: Vec<[f32; 4]> = sphere_directions(config.multiscatter_dirs)
        .iter()
        .map(|d| [d.x, d.y, d.z, 0.0])
        .collect();
    let u = lut_uniforms(&medium, config, dirs.len());
    let (tw, th, n) = (
        config.transmittance_w as u64,
        config.transmittance_h as u64,
        config.multiscatter_n as u64,
    );
    let out = |label, texels: u64| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: texels * 48,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        })
    };
    let bufs = LutBuffers {
        trans: out("transmittance", tw * th),
        trans_s: out("scattering transmittance", tw * th),
        multi: out("multiple scattering", n * n),
    };
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("LUT parameters"),
        contents: bytemuck::bytes_of(&u),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let dir_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("multiple-scattering directions"),
        contents: bytemuck::cast_slice(&dirs),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let bind = bind_group(
        device,
        "atmosphere LUTs",
        &p.layout,
        &[
            uniform.as_entire_binding(),
            bufs.trans.as_entire_binding(),
            bufs.trans_s.as_entire_binding(),
            bufs.multi.as_entire_binding(),
            dir_buf.as_entire_binding(),
        ],
    );
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("transmittance LUTs"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&p.transmittance);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups((tw as u32).div_ceil(8), (th as u32).div_ceil(8), 1);
    }
    {
        // A separate pass: Ψ_ms reads the δ-scaled transmittance.
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("multiple-scattering LUT"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&p.multiscatter);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(n as u32, n as u32, 1);
    }
    queue.submit([enc.finish()]);
    Ok(bufs)
}

/// Waits for the LUT passes, copies the three buffers back and assembles
/// them as [`AtmosphereLuts`] (`AtmosphereLuts::from_parts`) for the
/// CPU-side users of the LUTs (the Sun-disk table, the stars' extinction,
/// the CPU sky view).
pub fn read_back(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    bufs: &LutBuffers,
    params: &AtmosphereParams,
    config: &LutConfig,
) -> Result<AtmosphereLuts, RenderError> {
    let (tw, th, n) = (
        config.transmittance_w,
        config.transmittance_h,
        config.multiscatter_n,
    );
    let (t_bytes, m_bytes) = ((tw * th * 48) as u64, (n * n * 48) as u64);
    let read = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("LUT read"),
        size: 2 * t_bytes + m_bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&Default::default());
    enc.copy_buffer_to_buffer(&bufs.trans, 0, &read, 0, t_bytes);
    enc.copy_buffer_to_buffer(&bufs.trans_s, 0, &read, t_bytes, t_bytes);
    enc.copy_buffer_to_buffer(&bufs.multi, 0, &read, 2 * t_bytes, m_bytes);
    queue.submit([enc.finish()]);
    let slice = read.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(device_error)?;
    rx.recv().map_err(device_error)?.map_err(device_error)?;
    let spectra: Vec<Spectrum> = {
        let bytes = slice.get_mapped_range().map_err(device_error)?;
        let groups: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
        groups
            .chunks_exact(3)
            .map(|g| Spectrum(std::array::from_fn(|b| g[b / 4][b % 4])))
            .collect()
    };
    read.unmap();
    debug_assert_eq!(BANDS, 10);
    let lut = |range: std::ops::Range<usize>, w, h| Lut2 {
        w,
        h,
        data: spectra[range].to_vec(),
    };
    let t = lut(0..tw * th, tw, th);
    let ts = lut(tw * th..2 * tw * th, tw, th);
    let rows = spectra[2 * tw * th..]
        .chunks_exact(n)
        .map(<[Spectrum]>::to_vec)
        .collect();
    Ok(AtmosphereLuts::from_parts(params, config, t, ts, rows))
}

/// The LUTs for `params`/`config` computed on the GPU, awaited and read
/// back: the GPU buffers and their CPU copy.
pub fn compute(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    p: &LutPipelines,
    params: &AtmosphereParams,
    config: &LutConfig,
) -> Result<(LutBuffers, AtmosphereLuts), RenderError> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let bufs = dispatch(device, queue, p, params, config)?;
    let luts = read_back(device, queue, &bufs, params, config);
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(device_error(e));
    }
    Ok((bufs, luts?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::size_of;

    use crate::uniforms::tests::{assert_wgsl_layout, fields};

    /// `LutUniforms` has the size, field offsets and types naga computes
    /// for the WGSL `LutParams` (uniform address space rules).
    #[test]
    fn lut_uniforms_mirror_the_wgsl_struct() {
        assert_eq!(size_of::<LutUniforms>(), 320);
        let rust = fields!(
            LutUniforms,
            [
                rayleigh,
                mie_scattering,
                mie_extinction,
                ozone,
                forward,
                bottom_radius,
                top_radius,
                inv_h_rayleigh,
                inv_h_mie,
                ozone_peak,
                inv_ozone_width,
                mie_g,
                ground_albedo,
                sun_angular_radius,
                cos_forward_peak,
                forward_peak,
                orders,
                transmittance_width,
                transmittance_height,
                transmittance_steps,
                multiscatter_n,
                multiscatter_dirs,
                multiscatter_steps,
                _pad0,
                _pad1,
            ]
        );
        assert_wgsl_layout(LUTS_WGSL, "LutParams", size_of::<LutUniforms>(), &rust);
    }

    /// The shader validates with its two entry points.
    #[test]
    fn luts_shader_validates() {
        let module = naga::front::wgsl::parse_str(LUTS_WGSL).expect("luts.wgsl parses");
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::empty(),
        )
        .validate(&module)
        .expect("luts.wgsl validates");
        let names: Vec<_> = module
            .entry_points
            .iter()
            .map(|e| e.name.as_str())
            .collect();
        assert_eq!(names, ["transmittance", "multiscatter"]);
    }

    /// The policy: the shaders on every adapter but a software (CPU) one.
    #[test]
    fn default_source_by_adapter_type() {
        use wgpu::DeviceType as D;
        assert_eq!(LutSource::default_for(D::Cpu), LutSource::Cpu);
        for d in [D::DiscreteGpu, D::IntegratedGpu, D::VirtualGpu, D::Other] {
            assert_eq!(LutSource::default_for(d), LutSource::Gpu);
        }
        assert_eq!(
            (LutSource::Gpu.name(), LutSource::Cpu.name()),
            ("gpu", "cpu")
        );
    }

    /// The uniforms carry the configuration and the direction count of the
    /// CPU's direction set (k² for k = round(√n)).
    #[test]
    fn uniforms_carry_the_configuration() {
        let params = AtmosphereParams::default();
        let cfg = LutConfig::default();
        let m = Medium::new(&params);
        let dirs = sphere_directions(cfg.multiscatter_dirs).len();
        let u = lut_uniforms(&m, &cfg, dirs);
        let dims = [
            u.transmittance_width,
            u.transmittance_height,
            u.transmittance_steps,
            u.multiscatter_n,
        ];
        assert_eq!(dims, [256, 64, 40, 48]);
        let ms = [u.multiscatter_dirs, u.multiscatter_steps, u.orders];
        assert_eq!(ms, [64, 20, 0]);
        assert_eq!(sphere_directions(50).len(), 49);
        assert_eq!(u.rayleigh[2][2], 0.0);
        assert_eq!(u.rayleigh[0][0], m.rayleigh.0[0]);
        assert_eq!(u.forward[1][1], forward_scattering(&m, &cfg).0[5]);
        assert!((u.cos_forward_peak - 15f32.to_radians().cos()).abs() < 1e-7);
        assert_eq!(u.forward_peak, 1);
    }
}

/// A spectrum as three vec4 band groups (the last two lanes zero).
pub fn band_groups(s: &Spectrum) -> [[f32; 4]; 3] {
    let mut g = [[0.0f32; 4]; 3];
    for (b, v) in s.0.iter().enumerate() {
        g[b / 4][b % 4] = *v;
    }
    g
}

fn lut_groups(l: &Lut2<Spectrum>) -> Vec<[f32; 4]> {
    l.data.iter().flat_map(band_groups).collect()
}

/// The parameter-dependent LUTs on the GPU (three vec4 band groups per
/// texel), for the parameters they were uploaded or computed for.
pub struct GpuLuts {
    params: AtmosphereParams,
    config: LutConfig,
    /// Computed by the LUT compute shaders (not uploaded).
    on_gpu: bool,
    /// Transmittance.
    pub trans: wgpu::Buffer,
    /// δ-scaled transmittance.
    pub trans_s: wgpu::Buffer,
    /// Multiple scattering Ψ_ms.
    pub multi: wgpu::Buffer,
}

/// The renderer's LUTs on the GPU, kept while the parameters do not change.
#[derive(Default)]
pub struct LutSlot(Option<GpuLuts>);

impl LutSlot {
    /// The LUTs of `luts`' parameters on the GPU, uploaded unless they are
    /// there already (uploaded or computed by the shaders).
    pub fn upload(&mut self, gpu: &Gpu, luts: &AtmosphereLuts) -> &GpuLuts {
        if let Some(g) = self.0.take() {
            if g.params == luts.params && g.config == luts.config {
                return self.0.insert(g);
            }
        }
        let buf = |label, l| {
            gpu.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytemuck::cast_slice(&lut_groups(l)),
                    usage: wgpu::BufferUsages::STORAGE,
                })
        };
        self.0.insert(GpuLuts {
            params: luts.params.clone(),
            config: luts.config,
            on_gpu: false,
            trans: buf("transmittance", &luts.transmittance),
            trans_s: buf("scattering transmittance", &luts.scattering_transmittance),
            multi: buf("multiple scattering", &luts.multiscatter),
        })
    }

    /// Whether it holds LUTs the shaders computed for these parameters.
    pub fn computed_for(&self, params: &AtmosphereParams, config: &LutConfig) -> bool {
        self.0
            .as_ref()
            .is_some_and(|g| g.on_gpu && g.params == *params && g.config == *config)
    }

    /// Holds LUTs the shaders computed for these parameters.
    pub fn set_computed(&mut self, params: &AtmosphereParams, config: &LutConfig, b: LutBuffers) {
        self.0 = Some(GpuLuts {
            params: params.clone(),
            config: *config,
            on_gpu: true,
            trans: b.trans,
            trans_s: b.trans_s,
            multi: b.multi,
        });
    }
}
