//! The Milky Way pass (`shaders/milkyway.wgsl`): skymodel's
//! `NightBackground::radiance` per pixel — the Milky Way map (uploaded once
//! as a storage buffer), the faint-star floor, zodiacal light and airglow,
//! per-frame constants in [`NightUniforms`] — times the frame plan's
//! extinction table, whose fourth lane carries the refraction that
//! `milkyway::unrefracted` takes off low altitudes ([`night_inputs`]).

use glam::Vec3;
use himmel_skymodel::frame::NightFrame;
use himmel_skymodel::milkyway::{
    unrefracted, MilkyWayMap, AIRGLOW_HEIGHT_KM, EARTH_RADIUS_KM, OBLIQUITY_J2000,
};
use himmel_skymodel::spectrum::Spectrum;
use himmel_skymodel::stars::Extinction;
use himmel_skymodel::{Effect, FramePlan};
use wgpu::util::DeviceExt;

use crate::frame::{FrameBuild, SkyGroup};
use crate::gpu::Gpu;
use crate::pass::{Dispatch, Groups};
use crate::pool::{BufferPool, Slot};
use crate::uniforms::{NightUniforms, MILKYWAY_WGSL};

/// The Milky Way pass.
pub struct MilkyWayPass {
    pipeline: wgpu::ComputePipeline,
    /// The map (uploaded on first use) and its width, height.
    map: Option<(wgpu::Buffer, u32, u32)>,
}

impl MilkyWayPass {
    /// Compiles the pass.
    pub fn new(gpu: &Gpu, sky: &SkyGroup) -> Self {
        let module = gpu.shader("milkyway.wgsl", MILKYWAY_WGSL);
        let layout = gpu.pipeline_layout("milkyway", &[&sky.layout]);
        MilkyWayPass {
            pipeline: gpu.compute_pipeline(&layout, &module, "milkyway"),
            map: None,
        }
    }

    /// Sets the night constants and uploads the map (once) and the
    /// extinction table; the pass over every band, when the plan draws the
    /// Milky Way.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        pool: &BufferPool,
        plan: &FramePlan,
        build: &mut FrameBuild,
    ) -> Option<Dispatch> {
        let night = plan
            .night
            .as_ref()
            .filter(|_| plan.runs(Effect::Milkyway))?;
        let (map, w, h) = self.map(gpu);
        let (u, table) = night_inputs(night, plan.luts.is_some(), w, h);
        let b = &mut build.night;
        b.enu_to_icrs_x = u.enu_to_icrs_x;
        b.sin_obliquity = u.sin_obliquity;
        b.enu_to_icrs_y = u.enu_to_icrs_y;
        b.cos_obliquity = u.cos_obliquity;
        b.enu_to_icrs_z = u.enu_to_icrs_z;
        b.airglow = u.airglow;
        b.van_rhijn_k2 = u.van_rhijn_k2;
        b.zodiacal = u.zodiacal;
        b.floor = u.floor;
        b.map_width = u.map_width;
        b.map_height = u.map_height;
        b.extinction_nodes = u.extinction_nodes;
        build.milkyway_map = Some(map);
        build.extinction = Some(pool.upload(
            &gpu.device,
            &gpu.queue,
            Slot::Extinction,
            bytemuck::cast_slice(&table),
            wgpu::BufferUsages::STORAGE,
        ));
        Some(Dispatch {
            label: "milkyway",
            pipeline: self.pipeline.clone(),
            group1: None,
            groups: Groups::Band,
        })
    }

    /// The map buffer (uploaded once) and its size: a 2 × 2 black map when
    /// the embedded one does not decode, as the CPU then draws no map.
    fn map(&mut self, gpu: &Gpu) -> (wgpu::Buffer, u32, u32) {
        if let Some((b, w, h)) = &self.map {
            return (b.clone(), *w, *h);
        }
        let (texels, w, h) = match MilkyWayMap::embedded() {
            Ok(m) => {
                let (w, h) = m.size();
                let t: Vec<[f32; 4]> = m.texels().iter().map(|c| [c[0], c[1], c[2], 0.0]).collect();
                (t, w as u32, h as u32)
            }
            Err(_) => (vec![[0.0; 4]; 4], 2, 2),
        };
        let buf = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("Milky Way map"),
                contents: bytemuck::cast_slice(&texels),
                usage: wgpu::BufferUsages::STORAGE,
            });
        self.map = Some((buf.clone(), w, h));
        (buf, w, h)
    }
}

/// The Milky Way pass's constants and extinction table: the
/// `NightBackground` constants of `night`, and its extinction table (with
/// the atmosphere; factors of 1 at full resolution without) with, in the
/// fourth lane, the refraction (rad) that `milkyway::unrefracted` takes off
/// the apparent altitude asin μ at each node μ. `map_w` × `map_h` is the
/// uploaded map's size.
pub fn night_inputs(
    night: &NightFrame,
    atmosphere: bool,
    map_w: u32,
    map_h: u32,
) -> (NightUniforms, Vec<[f32; 4]>) {
    let ones;
    let extinction = if atmosphere {
        &night.extinction
    } else {
        ones = Extinction::from_transmittance(|_| Spectrum::ONE);
        &ones
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
    let bg = &night.background;
    let m = bg.enu_to_icrs();
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
        ..bytemuck::Zeroable::zeroed()
    };
    (u, rows)
}
