//! The Moon pass and the eclipse corona (`shaders/moon.wgsl`, its own bind
//! group 1: the [`MoonUniforms`] header with [`MOON_TABLE_ROWS`] table rows,
//! and the lunar maps).
//!
//! The Moon: skymodel's `MoonShader::{sky_xy, surface_point, radiance,
//! shade}` per pixel of the disk's rectangle ([`MoonFrame::rect`]) — the
//! albedo and normal maps (uploaded once as one storage buffer, bilinear
//! as on the CPU, `fast_atan2` for the selenographic coordinates), the
//! Lommel–Seeliger × opposition surge × phase-law factor, earthshine, and
//! the frame plan's tables interpolated on the GPU as the CPU interpolates
//! them: extinction across the disk, the lunar-eclipse table and, for a
//! Moon below 15°, Bennett's refraction that `unrefract` takes off each
//! pixel. The disk replaces what the earlier passes drew by its coverage
//! (analytic limb; small disks supersampled 4 × 4 or 8 × 8 as on the CPU).
//!
//! The corona (`CoronaFrame`): the disk's mean radiance × the
//! transmittance tabulated over the zenith cosine, Baumbach's profile,
//! hidden by the Moon; a second dispatch of the Sun pass.

use glam::Vec3;
use himmel_skymodel::frame::MoonFrame;
use himmel_skymodel::{Camera, FramePlan};
use wgpu::util::DeviceExt;

use crate::frame::SkyGroup;
use crate::gpu::{bind_group, storage_entry, uniform_entry_sized, Gpu};
use crate::pass::{Dispatch, Groups};
use crate::pool::{BufferPool, Slot};
use crate::uniforms::{
    MoonUniforms, MOON_COR, MOON_COR_N, MOON_ECL, MOON_EXT, MOON_REFR, MOON_REFR_N,
    MOON_TABLE_ROWS, MOON_WGSL,
};

/// The Moon and corona passes.
pub struct MoonPass {
    layout: wgpu::BindGroupLayout,
    disk: wgpu::ComputePipeline,
    corona: wgpu::ComputePipeline,
    /// The albedo map followed by the normal map's (east, north) pairs
    /// (uploaded on first use), and their sizes.
    maps: Option<(wgpu::Buffer, [u32; 4])>,
}

impl MoonPass {
    /// Compiles the passes.
    pub fn new(gpu: &Gpu, sky: &SkyGroup) -> Self {
        let module = gpu.shader("moon.wgsl", MOON_WGSL);
        let size = std::mem::size_of::<MoonUniforms>() + 16 * MOON_TABLE_ROWS;
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("moon"),
                entries: &[uniform_entry_sized(0, size), storage_entry(1, true)],
            });
        let pl = gpu.pipeline_layout("moon", &[&sky.layout, &layout]);
        MoonPass {
            disk: gpu.compute_pipeline(&pl, &module, "moon_disk"),
            corona: gpu.compute_pipeline(&pl, &module, "corona"),
            layout,
            maps: None,
        }
    }

    /// The Moon's and the corona's dispatches of this frame (each when the
    /// plan draws it), sharing one uniform buffer and the maps.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        pool: &BufferPool,
        plan: &FramePlan,
        cam: &Camera,
    ) -> (Option<Dispatch>, Option<Dispatch>) {
        if plan.moon.is_none() && plan.corona.is_none() {
            return (None, None);
        }
        let (maps, dims) = self.maps(gpu);
        let (u, rows) = moon_uniforms(plan, cam, dims);
        let mut bytes = bytemuck::bytes_of(&u).to_vec();
        bytes.extend_from_slice(bytemuck::cast_slice(&rows));
        let uniform = pool.upload(
            &gpu.device,
            &gpu.queue,
            Slot::Moon,
            &bytes,
            wgpu::BufferUsages::UNIFORM,
        );
        let group = bind_group(
            &gpu.device,
            "moon",
            &self.layout,
            &[uniform.resource(), maps.as_entire_binding()],
        );
        let step = |label, pipeline: &wgpu::ComputePipeline, rect| Dispatch {
            label,
            pipeline: pipeline.clone(),
            group1: Some(group.clone()),
            groups: Groups::Rect(rect),
        };
        let disk = plan.moon.as_ref().map(|m| step("moon", &self.disk, m.rect));
        let corona = plan
            .corona
            .as_ref()
            .map(|c| step("corona", &self.corona, c.rect));
        (disk, corona)
    }

    /// Uploads the lunar albedo map followed by the normal map's (east,
    /// north) pairs (once); returns the buffer and the maps' sizes.
    fn maps(&mut self, gpu: &Gpu) -> (wgpu::Buffer, [u32; 4]) {
        if let Some((buf, dims)) = &self.maps {
            return (buf.clone(), *dims);
        }
        use himmel_skymodel::moon::{AlbedoMap, NormalMap};
        let (a, n) = (AlbedoMap::get(), NormalMap::get());
        let mut data: Vec<f32> = a.data.clone();
        data.extend(n.data.iter().flatten());
        let buf = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("Moon maps"),
                contents: bytemuck::cast_slice(&data),
                usage: wgpu::BufferUsages::STORAGE,
            });
        let dims = [a.w as u32, a.h as u32, n.w as u32, n.h as u32];
        self.maps = Some((buf.clone(), dims));
        (buf, dims)
    }
}

/// The Moon pass's and the corona's uniform ([`MoonUniforms`]) and its
/// [`MOON_TABLE_ROWS`] table rows for the frame plan `plan` of camera
/// `cam`, with `maps` the uploaded maps' sizes (albedo w, h; normals w, h):
/// the Moon shader's constants and tables ([`MoonFrame`]), Bennett's
/// refraction at [`MOON_REFR_N`] apparent altitudes over the disk, and the
/// corona's constants and its table at [`MOON_COR_N`] zenith cosines
/// (`CoronaFrame::table`). Exact CPU values at the nodes.
pub fn moon_uniforms(
    plan: &FramePlan,
    cam: &Camera,
    maps: [u32; 4],
) -> (MoonUniforms, Vec<[f32; 4]>) {
    let mut rows = vec![[0.0f32; 4]; MOON_TABLE_ROWS];
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
    if let Some(m) = &plan.moon {
        u = moon_disk_uniforms(m, cam, &mut rows, u);
    }
    if let Some(c) = &plan.corona {
        let (table, z0, dz) = c.table(plan.luts.as_deref(), plan.observer_radius_km, MOON_COR_N);
        rows[MOON_COR..MOON_COR + MOON_COR_N].copy_from_slice(&table);
        [u.corona_x0, u.corona_y0, u.corona_x1, u.corona_y1] = c.rect;
        u.corona_cos_outer = c.cos_outer;
        u.corona_sun_radius = c.sun_radius;
        u.corona_moon_radius = c.moon_radius;
        u.max_pixel_angle = c.pixel;
        u.corona_z0 = z0;
        u.corona_dz = dz;
        u.corona_nodes = MOON_COR_N as u32;
        u.corona_floor = c.edge;
    }
    (u, rows)
}

/// The disk's part of [`moon_uniforms`]: the shader's constants, and its
/// extinction, eclipse and refraction tables written into `rows`.
fn moon_disk_uniforms(
    m: &MoonFrame,
    cam: &Camera,
    rows: &mut [[f32; 4]],
    base: MoonUniforms,
) -> MoonUniforms {
    let s = &m.shader;
    let c = |a: [f32; 3]| [a[0], a[1], a[2], 0.0];
    let (alt0, dalt, refraction) = m.refraction_table(cam, MOON_REFR_N);
    for (k, r) in refraction.iter().enumerate() {
        rows[MOON_REFR + k][0] = *r;
    }
    let ext_n = s.ext.len().min(MOON_REFR - MOON_EXT);
    for (k, e) in s.ext.iter().take(ext_n).enumerate() {
        rows[MOON_EXT + k] = c(*e);
    }
    let mut ecl_n = 0;
    let (mut offset, mut semidiameter, mut d_max) = ([0.0; 2], 0.0, 0.0);
    let (mut geo_e, mut geo_n) = (Vec3::ZERO, Vec3::ZERO);
    if let Some(e) = &s.eclipse {
        ecl_n = e.table.len().min(MOON_COR - MOON_ECL);
        for (k, t) in e.table.iter().take(ecl_n).enumerate() {
            rows[MOON_ECL + k] = c(*t);
        }
        (offset, semidiameter, d_max) = (e.offset, e.semidiameter, e.d_max);
        (geo_e, geo_n) = (e.geo_east, e.geo_north);
    }
    MoonUniforms {
        centre: s.centre.to_array(),
        radius: s.radius,
        east: s.east.to_array(),
        sin_radius: s.sin_radius,
        north: s.north.to_array(),
        refract: s.refract as u32,
        sun: s.sun.to_array(),
        sun_factor: s.sun_factor,
        axis_x: s.axes[0].to_array(),
        pixel_angle: m.pixel,
        axis_y: s.axes[1].to_array(),
        cos_bound: m.cos_bound,
        axis_z: s.axes[2].to_array(),
        sun_rgb: s.sun_rgb,
        extinction_z0: s.ext_z0,
        earth_rgb: s.earth_rgb,
        extinction_dz: s.ext_dz,
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
        subsamples: m.supersampling as u32,
        disk_x0: m.rect[0],
        disk_y0: m.rect[1],
        disk_x1: m.rect[2],
        disk_y1: m.rect[3],
        ..base
    }
}
