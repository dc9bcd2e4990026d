//! The contract of a pass. Every pass is a module under `passes/` beside
//! its WGSL file (`shaders/<name>.wgsl`, prepended by the shared
//! `shaders/frame.wgsl`) and follows the same life cycle:
//!
//! 1. **built once** — `XPass::new(gpu, …)` compiles its shader module and
//!    pipelines against the frame's bind-group layout (group 0,
//!    [`crate::frame::SkyGroup`]) and, where it has tables of its own,
//!    a group-1 layout;
//! 2. **prepared per frame** — `XPass::prepare(&mut self, gpu, plan, …,
//!    &mut FrameBuild)` reads what it needs from the frame plan
//!    (`himmel_skymodel::FramePlan`: never the physics itself), writes its
//!    uniforms and tables into typed pool slots ([`crate::pool::Slot`]) or
//!    the shared frame uniforms and bindings ([`crate::frame::FrameBuild`]),
//!    and returns a [`Step`] when it has work this frame;
//! 3. **recorded** — [`Step::record`] records its dispatches (or draws)
//!    for one band of rows into the frame's command encoder, inside a
//!    compute or render pass that carries the timestamp writes it is
//!    given;
//! 4. **timed** — the renderer maps each step to the `--stats` entry of
//!    its effect and sums the step's GPU time (timestamps) or CPU time
//!    (each step submitted and awaited) over the bands.

use crate::gpu::TimestampSlot;
use crate::pool::PoolBinding;

/// One band of rows of the frame, as the steps record it.
pub struct Band<'a> {
    /// The band's index in the frame.
    pub index: usize,
    /// The first image row of the band.
    pub row0: u32,
    /// Rows in the band.
    pub rows: u32,
    /// Image width, px.
    pub width: u32,
    /// The frame's group 0 for this band (frame uniforms with the band's
    /// rows, the accumulation band, the shared tables, the target).
    pub sky: &'a wgpu::BindGroup,
    /// The band's frame uniforms (for passes with a layout of their own).
    pub frame: &'a PoolBinding,
    /// The night constants.
    pub night: &'a PoolBinding,
    /// The point sources' records.
    pub points: &'a PoolBinding,
    /// The point sources' tile lists.
    pub tiles: &'a PoolBinding,
}

impl Band<'_> {
    /// Workgroups (8 × 8) over the part of the pixel rectangle `r` =
    /// [x0, y0, x1, y1) in this band.
    pub fn workgroups(&self, r: [u32; 4]) -> (u32, u32) {
        let y0 = r[1].clamp(self.row0, self.row0 + self.rows);
        let y1 = r[3].clamp(self.row0, self.row0 + self.rows);
        (
            r[2].saturating_sub(r[0]).div_ceil(8),
            y1.saturating_sub(y0).div_ceil(8),
        )
    }

    /// Workgroups (8 × 8) over the whole band.
    pub fn full(&self) -> (u32, u32) {
        (self.width.div_ceil(8), self.rows.div_ceil(8))
    }
}

/// A pass's prepared work for one frame.
pub trait Step {
    /// The label of its compute or render pass (debuggers, validation
    /// messages).
    fn label(&self) -> &'static str;

    /// Records the work for `band` into `enc`, inside one compute or
    /// render pass that writes `timestamps` at its beginning and end.
    fn record(
        &self,
        enc: &mut wgpu::CommandEncoder,
        band: &Band,
        timestamps: Option<TimestampSlot>,
    );
}

/// How many workgroups a [`Dispatch`] records in a band.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Groups {
    /// 8 × 8 pixels each over the whole band.
    Band,
    /// 8 × 8 pixels each over the band's part of a pixel rectangle
    /// [x0, y0, x1, y1).
    Rect([u32; 4]),
    /// A fixed grid (the point passes: one workgroup per non-empty tile).
    Fixed(u32, u32),
}

/// One compute dispatch per band of a pipeline with the band's group 0
/// and, if given, a group 1 of the pass's own: the shape of most sky
/// passes.
#[derive(Debug, Clone)]
pub struct Dispatch {
    /// The compute pass's label.
    pub label: &'static str,
    /// The pipeline.
    pub pipeline: wgpu::ComputePipeline,
    /// The pass's own bind group 1.
    pub group1: Option<wgpu::BindGroup>,
    /// Its workgroups per band.
    pub groups: Groups,
}

impl Step for Dispatch {
    fn label(&self) -> &'static str {
        self.label
    }

    fn record(
        &self,
        enc: &mut wgpu::CommandEncoder,
        band: &Band,
        timestamps: Option<TimestampSlot>,
    ) {
        let groups = match self.groups {
            Groups::Band => band.full(),
            Groups::Rect(r) => band.workgroups(r),
            Groups::Fixed(x, y) => (x, y),
        };
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(self.label),
            timestamp_writes: timestamps.as_ref().map(TimestampSlot::compute),
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, band.sky, &[]);
        if let Some(g) = &self.group1 {
            pass.set_bind_group(1, g, &[]);
        }
        pass.dispatch_workgroups(groups.0, groups.1, 1);
    }
}
