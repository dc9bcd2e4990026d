//! The atmosphere pass (`shaders/atmosphere.wgsl`): each pixel's sky
//! radiance looked up bilinearly in the frame's sky views (the Sun's and,
//! on a moonlit night, the Moon's; prepared by [`super::sky_view`]) — the
//! CPU's `SkyLight::radiance` — added into the accumulation band; below
//! the horizon the ground's luminance.

use crate::frame::SkyGroup;
use crate::gpu::Gpu;
use crate::pass::{Dispatch, Groups};
use crate::uniforms::ATMOSPHERE_WGSL;

/// The atmosphere pass.
pub struct AtmospherePass {
    pipeline: wgpu::ComputePipeline,
}

impl AtmospherePass {
    /// Compiles the pass.
    pub fn new(gpu: &Gpu, sky: &SkyGroup) -> Self {
        let module = gpu.shader("atmosphere.wgsl", ATMOSPHERE_WGSL);
        let layout = gpu.pipeline_layout("atmosphere", &[&sky.layout]);
        AtmospherePass {
            pipeline: gpu.compute_pipeline(&layout, &module, "atmosphere"),
        }
    }

    /// The pass over every band.
    pub fn step(&self) -> Dispatch {
        Dispatch {
            label: "atmosphere",
            pipeline: self.pipeline.clone(),
            group1: None,
            groups: Groups::Band,
        }
    }
}
