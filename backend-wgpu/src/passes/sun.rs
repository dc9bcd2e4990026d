//! The Sun pass (`shaders/sun.wgsl`): the limb-darkened disk of the frame
//! plan's [`SunFrame`], tabulated on the CPU ([`SunFrame::table`]: the exact
//! `SunDisk::radiance_rgb` after the transmittance at each node) and
//! supersampled per pixel within the frame's margin as the CPU does;
//! sub-samples behind the Moon's disk are skipped (solar eclipses). It is
//! dispatched over the disk's pixel rectangle only.

use himmel_skymodel::frame::sun::{SUN_TABLE_RHO, SUN_TABLE_Z};
use himmel_skymodel::frame::SunFrame;
use himmel_skymodel::FramePlan;

use crate::frame::{FrameBuild, SkyGroup};
use crate::gpu::Gpu;
use crate::pass::{Dispatch, Groups};
use crate::pool::{BufferPool, Slot};
use crate::uniforms::SUN_WGSL;

/// The Sun pass.
pub struct SunPass {
    pipeline: wgpu::ComputePipeline,
}

impl SunPass {
    /// Compiles the pass.
    pub fn new(gpu: &Gpu, sky: &SkyGroup) -> Self {
        let module = gpu.shader("sun.wgsl", SUN_WGSL);
        let layout = gpu.pipeline_layout("sun", &[&sky.layout]);
        SunPass {
            pipeline: gpu.compute_pipeline(&layout, &module, "sun"),
        }
    }

    /// Uploads the Sun table and sets the Sun's frame uniforms; the pass
    /// over the disk's rectangle, when the plan draws the Sun.
    pub fn prepare(
        &self,
        gpu: &Gpu,
        pool: &BufferPool,
        plan: &FramePlan,
        build: &mut FrameBuild,
    ) -> Option<Dispatch> {
        let sun: &SunFrame = plan.sun.as_ref()?;
        let (table, [z0, z1]) = sun.table(plan.luts.as_deref(), plan.observer_radius_km);
        build.sun_table = Some(pool.upload(
            &gpu.device,
            &gpu.queue,
            Slot::SunTable,
            bytemuck::cast_slice(&table),
            wgpu::BufferUsages::STORAGE,
        ));
        let u = &mut build.uniforms;
        u.cos_sun_margin = sun.cos_margin;
        u.sin_sun_radius = sun.radius.sin() as f32;
        u.sun_z_min = z0;
        u.sun_z_max = z1;
        u.sun_subsamples = sun.supersampling as u32;
        u.sun_rho_nodes = SUN_TABLE_RHO as u32;
        u.sun_z_nodes = SUN_TABLE_Z as u32;
        u.sun_x0 = sun.rect[0];
        u.sun_y0 = sun.rect[1];
        u.eclipse_moon = sun.moon_centre.to_array();
        u.sin_moon_radius = sun.moon_sin_radius;
        Some(Dispatch {
            label: "sun",
            pipeline: self.pipeline.clone(),
            group1: None,
            groups: Groups::Rect(sun.rect),
        })
    }
}
