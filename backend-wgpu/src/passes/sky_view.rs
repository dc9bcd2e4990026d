//! The per-frame sky views (`shaders/skyview.wgsl`): the sky-view LUT of
//! Hillaire (2020, §5) — a port of skymodel lut.rs `SkyView::transfer`,
//! one invocation per texel — and the ground's luminance below the
//! horizon, for the Sun's input and, on a moonlit night, the Moon's. The
//! frame's `sky` binding holds them one after the other (per input:
//! w × h texels, then the ground).
//!
//! Two sources: the compute shaders ([`SkyViewPass::compute`]), or the
//! CPU's sky views of the frame plan uploaded (`set_sky_view_on_gpu(false)`).
//! When the frame plan needs the sky light on the CPU side (the night
//! passes' metering and culling), [`GpuSkyViews`] computes them on the GPU
//! and reads them back; the frame then binds the same buffer without
//! computing them again.

use himmel_skymodel::atmosphere::{AtmosphereLuts, SkyView, SkyViewInput};
use himmel_skymodel::frame::{CpuSkyViews, SkyViewSource};
use himmel_skymodel::spectrum::BandWeights;
use himmel_skymodel::{FramePlan, RenderError};

use super::luts::{band_groups, GpuLuts, LutSlot};
use crate::frame::FrameBuild;
use crate::gpu::{bind_group, storage_entry, uniform_entry, Gpu};
use crate::pool::{BufferPool, Slot};
use crate::uniforms::{AtmosphereUniforms, SKYVIEW_WGSL};

/// The sky-view passes and their buffers, kept across frames while the LUT
/// buffers, the sky-view size and the number of inputs stay the same (the
/// uniforms are rewritten each frame).
pub struct SkyViewPass {
    layout: wgpu::BindGroupLayout,
    sky_view: wgpu::ComputePipeline,
    ground: wgpu::ComputePipeline,
    buffers: Option<SkyViewBuffers>,
    /// Whether the output buffer holds this frame's views.
    fresh: bool,
}

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

impl SkyViewPass {
    /// Compiles the passes.
    pub fn new(gpu: &Gpu) -> Self {
        let module = gpu.shader("skyview.wgsl", SKYVIEW_WGSL);
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("sky view"),
                entries: &[
                    uniform_entry::<AtmosphereUniforms>(0),
                    storage_entry(1, true),
                    storage_entry(2, true),
                    storage_entry(3, true),
                    storage_entry(4, false),
                ],
            });
        let pl = gpu.pipeline_layout("sky view", &[&layout]);
        SkyViewPass {
            sky_view: gpu.compute_pipeline(&pl, &module, "sky_view"),
            ground: gpu.compute_pipeline(&pl, &module, "ground"),
            layout,
            buffers: None,
            fresh: false,
        }
    }

    /// Forgets this frame's views (called at the start of each frame).
    pub fn begin_frame(&mut self) {
        self.fresh = false;
    }

    /// Computes the sky-view LUT and the ground luminance on the GPU for
    /// each of `inputs` (the Sun's, then the Moon's on a moonlit night)
    /// from the LUTs `gl`; returns the buffer (per input: w × h texels,
    /// then the ground) after completion.
    pub fn compute(
        &mut self,
        gpu: &Gpu,
        gl: &GpuLuts,
        luts: &AtmosphereLuts,
        inputs: &[SkyViewInput],
    ) -> Result<wgpu::Buffer, RenderError> {
        let (w, h) = (luts.config.sky_view_w as u32, luts.config.sky_view_h as u32);
        let view_bytes = (w as u64 * h as u64 + 1) * 16;
        let key = (w, h, inputs.len().max(1));
        let lut_bufs = [gl.trans.clone(), gl.trans_s.clone(), gl.multi.clone()];
        let c = match self.buffers.take() {
            Some(c) if c.key == key && c.luts == lut_bufs => c,
            _ => self.buffers_for(gpu, gl, key, view_bytes),
        };
        let c = self.buffers.insert(c);
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        for (k, (input, (uniform, sky, bind))) in inputs.iter().zip(&c.slots).enumerate() {
            let u = atmosphere_uniforms(luts, input);
            gpu.queue.write_buffer(uniform, 0, bytemuck::bytes_of(&u));
            for (label, pipeline, groups) in [
                ("sky view", &self.sky_view, (w.div_ceil(8), h.div_ceil(8))),
                ("ground", &self.ground, (1, 1)),
            ] {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(label),
                    timestamp_writes: None,
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, bind, &[]);
                pass.dispatch_workgroups(groups.0, groups.1, 1);
            }
            enc.copy_buffer_to_buffer(sky, 0, &c.out, k as u64 * view_bytes, view_bytes);
        }
        gpu.queue.submit([enc.finish()]);
        gpu.wait()?;
        self.fresh = true;
        Ok(c.out.clone())
    }

    fn buffers_for(
        &self,
        gpu: &Gpu,
        gl: &GpuLuts,
        key: (u32, u32, usize),
        view_bytes: u64,
    ) -> SkyViewBuffers {
        let dev = &gpu.device;
        let buffer = |label, size, usage| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        use wgpu::BufferUsages as U;
        let out = buffer(
            "sky views",
            view_bytes * key.2 as u64,
            U::STORAGE | U::COPY_DST | U::COPY_SRC,
        );
        let slots = (0..key.2)
            .map(|_| {
                let size = std::mem::size_of::<AtmosphereUniforms>() as u64;
                let uniform = buffer("atmosphere", size, U::UNIFORM | U::COPY_DST);
                let sky = buffer("sky view", view_bytes, U::STORAGE | U::COPY_SRC);
                let bind = bind_group(
                    dev,
                    "sky view",
                    &self.layout,
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
            luts: [gl.trans.clone(), gl.trans_s.clone(), gl.multi.clone()],
            out,
            slots,
        }
    }

    /// Binds the frame's sky views (computed on the GPU unless this frame
    /// already did, or the plan's CPU views uploaded when `on_gpu` is off)
    /// and sets the frame uniforms that look them up. Returns the time
    /// spent, ms.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        pool: &BufferPool,
        gpu_luts: &mut LutSlot,
        plan: &mut FramePlan,
        on_gpu: bool,
        build: &mut FrameBuild,
    ) -> Result<(), RenderError> {
        let (Some(luts), Some(inputs)) = (plan.luts.clone(), plan.sky_inputs) else {
            return Ok(());
        };
        let list = inputs.list();
        let t = std::time::Instant::now();
        let buffer = if !on_gpu {
            let light = plan.sky_light(&mut CpuSkyViews)?;
            let mut rgba: Vec<[f32; 4]> = Vec::new();
            let views = light
                .into_iter()
                .flat_map(|l| std::iter::once(&l.sun).chain(l.moon.as_ref().map(|(v, _)| v)));
            for sv in views {
                rgba.extend(sv.lut.data.iter().map(|p| [p[0], p[1], p[2], 0.0]));
                let g = sv.ground_rgb;
                rgba.push([g[0], g[1], g[2], 0.0]);
            }
            pool.upload(
                &gpu.device,
                &gpu.queue,
                Slot::SkyView,
                bytemuck::cast_slice(&rgba),
                wgpu::BufferUsages::STORAGE,
            )
            .buffer
        } else if self.fresh {
            self.buffers
                .as_ref()
                .map(|b| b.out.clone())
                .ok_or_else(|| RenderError::Device("the sky views of this frame are gone".into()))?
        } else {
            let gl = gpu_luts.upload(gpu, &luts);
            let b = self.compute(gpu, gl, &luts, &list)?;
            plan.sky_view_ms += t.elapsed().as_secs_f64() * 1e3;
            b
        };
        build.sky = Some(buffer);
        let u = &mut build.uniforms;
        u.sky_view_width = luts.config.sky_view_w as u32;
        u.sky_view_height = luts.config.sky_view_h as u32;
        if let Some((_, dir)) = inputs.moon {
            u.moonlight = dir.to_array();
            u.moonlit = 1;
        }
        Ok(())
    }
}

/// The GPU as the frame plan's sky-view source: the compute shaders, their
/// result read back into [`SkyView`]s (the ground as the shader computed
/// it) for the plan's metering and culling.
pub struct GpuSkyViews<'a> {
    /// The sky-view passes.
    pub pass: &'a mut SkyViewPass,
    /// The GPU.
    pub gpu: &'a Gpu,
    /// The LUTs on the GPU (uploaded if the plan's are not there yet).
    pub luts: &'a mut LutSlot,
}

impl SkyViewSource for GpuSkyViews<'_> {
    fn sky_views(
        &mut self,
        luts: &AtmosphereLuts,
        inputs: &[SkyViewInput],
    ) -> Result<Vec<SkyView>, RenderError> {
        let gl = self.luts.upload(self.gpu, luts);
        let out = self.pass.compute(self.gpu, gl, luts, inputs)?;
        let (w, h) = (luts.config.sky_view_w, luts.config.sky_view_h);
        let size = ((w * h + 1) * 16 * inputs.len()) as u64;
        let read = self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sky views read"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = self.gpu.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(&out, 0, &read, 0, size);
        self.gpu.queue.submit([enc.finish()]);
        let bytes = self.gpu.map_read(&read, size)?;
        let texels: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
        let views = texels
            .chunks_exact(w * h + 1)
            .zip(inputs)
            .map(|(t, input)| {
                let rows = t[..w * h]
                    .chunks_exact(w)
                    .map(|r| r.iter().map(|p| [p[0], p[1], p[2]]).collect())
                    .collect();
                let mut sv = SkyView::from_rows(luts, input, rows);
                let g = t[w * h];
                sv.ground_rgb = [g[0], g[1], g[2]];
                sv
            })
            .collect();
        Ok(views)
    }
}

/// The uniforms of the GPU sky view (lut.rs `SkyView::row` inputs).
pub fn atmosphere_uniforms(luts: &AtmosphereLuts, input: &SkyViewInput) -> AtmosphereUniforms {
    let m = &luts.medium;
    let cfg = &luts.config;
    let weights = BandWeights::solar();
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
    let sun = SkyView::sun_local(input.sun_sin_elevation);
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
