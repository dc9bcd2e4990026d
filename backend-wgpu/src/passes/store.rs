//! The store pass (`shaders/store.wgsl`): the accumulation band written
//! into the frame's rgba32float target (one layer, or the six faces of a
//! cube map), alpha 1 where the projection shows the scene.

use crate::frame::SkyGroup;
use crate::gpu::Gpu;
use crate::pass::{Dispatch, Groups};
use crate::uniforms::STORE_WGSL;

/// The store pass.
pub struct StorePass {
    pipeline: wgpu::ComputePipeline,
}

impl StorePass {
    /// Compiles the pass.
    pub fn new(gpu: &Gpu, sky: &SkyGroup) -> Self {
        let module = gpu.shader("store.wgsl", STORE_WGSL);
        let layout = gpu.pipeline_layout("store", &[&sky.layout]);
        StorePass {
            pipeline: gpu.compute_pipeline(&layout, &module, "store"),
        }
    }

    /// The pass over every band.
    pub fn step(&self) -> Dispatch {
        Dispatch {
            label: "store",
            pipeline: self.pipeline.clone(),
            group1: None,
            groups: Groups::Band,
        }
    }
}
