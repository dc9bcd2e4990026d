//! Amortised marching of the low cloud layer on the GPU
//! (`clouds.low.march_stride` N ≥ 2; `shaders/clouds_amortise.wgsl`): the
//! two-level grid of skymodel's `frame::LowCloudGrid`, in two dispatches
//! recorded before the clouds pass's per-pixel dispatch, inside the same
//! compute pass (so `--stats`' `clouds` entry times all three):
//!
//! 1. `clouds_grid_coarse` marches the coarse nodes (every N-th pixel of
//!    every N-th row, and the last column and row) into a lattice buffer;
//! 2. `clouds_grid_refine` marches the midpoints of the edges and the
//!    centre of each coarse cell whose corners disagree (a corner outside
//!    the projection, or transmittances spread by more than
//!    [`AGREE_TRANSMITTANCE`]);
//! 3. `clouds_grid_pixels` (in place of `clouds_pass`) interpolates each
//!    pixel from its cell's corners, or its half-size cell's, where they
//!    agree, and queues the others;
//! 4. `clouds_edges` marches the queued pixels side by side (a pixel
//!    marched inside `clouds_pass` would hold up the interpolated pixels
//!    that share its SIMD lanes: on lavapipe the pass then took 0.68 of
//!    the full march's time at stride 4, fisheye 192²).
//!
//! The grid covers the whole image and is marched with the first band of
//! rows; later bands read it. The lattice holds (2 nx − 1) × (2 ny − 1)
//! entries of 48 bytes (4 per N² pixels); an image whose lattice exceeds
//! the adapter's storage-buffer binding size is marched at every pixel,
//! as with N = 1 ([`GridShape::of`] says which).

use himmel_skymodel::frame::{grid_nodes, AGREE_TRANSMITTANCE};

use crate::gpu::TimestampSlot;
use crate::pass::{Band, Step};

/// Bytes of one lattice entry (three vec4).
pub const ENTRY_BYTES: u64 = 48;

/// The coarse grid of an image: stride and nodes along x and y.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GridShape {
    /// The stride N, px.
    pub stride: u32,
    /// Nodes along x.
    pub nx: u32,
    /// Nodes along y.
    pub ny: u32,
}

impl GridShape {
    /// The grid of a `width` × `height` image at `stride`, when the frame
    /// marches on one: a stride of at least 2, two nodes along each axis,
    /// and a lattice within `max_bytes`.
    pub fn of(width: u32, height: u32, stride: u32, max_bytes: u64) -> Option<GridShape> {
        if stride < 2 {
            return None;
        }
        let nx = grid_nodes(width as usize, stride as usize) as u32;
        let ny = grid_nodes(height as usize, stride as usize) as u32;
        let g = GridShape { stride, nx, ny };
        (nx >= 2 && ny >= 2 && g.bytes() <= max_bytes).then_some(g)
    }

    /// Lattice points along x and y.
    pub fn lattice(&self) -> (u32, u32) {
        (2 * self.nx - 1, 2 * self.ny - 1)
    }

    /// Bytes of the lattice buffer.
    pub fn bytes(&self) -> u64 {
        let (lx, ly) = self.lattice();
        lx as u64 * ly as u64 * ENTRY_BYTES
    }

    /// `Clouds::march_grid`: N, nx, ny and the agreement threshold's bits.
    pub fn uniform(shape: Option<GridShape>) -> [u32; 4] {
        match shape {
            Some(g) => [g.stride, g.nx, g.ny, AGREE_TRANSMITTANCE.to_bits()],
            None => [1, 0, 0, AGREE_TRANSMITTANCE.to_bits()],
        }
    }
}

/// The amortised march's pipelines and grid.
pub struct GridPipelines {
    /// `clouds_grid_coarse`.
    pub coarse: wgpu::ComputePipeline,
    /// `clouds_grid_refine`.
    pub refine: wgpu::ComputePipeline,
    /// `clouds_grid_pixels` (in place of `clouds_pass`).
    pub pixels: wgpu::ComputePipeline,
    /// `clouds_edges_reset`.
    pub reset: wgpu::ComputePipeline,
    /// `clouds_edges`.
    pub edges: wgpu::ComputePipeline,
    /// The grid.
    pub shape: GridShape,
}

/// The clouds pass's work for one frame: the grid's two dispatches (with
/// the first band), the per-pixel dispatch and, when amortised, the edge
/// queue's reset before it and its march after it (every band).
pub struct CloudsStep {
    /// The per-pixel pipeline (`clouds_pass`).
    pub pixels: wgpu::ComputePipeline,
    /// The amortised march's pipelines, when the frame has one.
    pub grid: Option<GridPipelines>,
    /// The pass's bind group 1.
    pub group1: wgpu::BindGroup,
}

impl Step for CloudsStep {
    fn label(&self) -> &'static str {
        "clouds"
    }

    fn record(
        &self,
        enc: &mut wgpu::CommandEncoder,
        band: &Band,
        timestamps: Option<TimestampSlot>,
    ) {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("clouds"),
            timestamp_writes: timestamps.as_ref().map(TimestampSlot::compute),
        });
        pass.set_bind_group(0, band.sky, &[]);
        pass.set_bind_group(1, &self.group1, &[]);
        let (x, y) = band.full();
        if let Some(g) = &self.grid {
            if band.index == 0 {
                let s = g.shape;
                pass.set_pipeline(&g.coarse);
                pass.dispatch_workgroups(s.nx.div_ceil(8), s.ny.div_ceil(8), 1);
                let (lx, ly) = s.lattice();
                pass.set_pipeline(&g.refine);
                pass.dispatch_workgroups(lx.div_ceil(8), ly.div_ceil(8), 1);
            }
            pass.set_pipeline(&g.reset);
            pass.dispatch_workgroups(1, 1, 1);
        }
        match &self.grid {
            Some(g) => {
                pass.set_pipeline(&g.pixels);
                pass.dispatch_workgroups(x, y, 1);
                pass.set_pipeline(&g.edges);
                pass.dispatch_workgroups(x, y, 1);
            }
            None => {
                pass.set_pipeline(&self.pixels);
                pass.dispatch_workgroups(x, y, 1);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The grid's nodes are the CPU's, and frames that cannot march on
    /// one (stride 1, a single node, a lattice over the limit) do not.
    #[test]
    fn shapes_follow_the_cpu_grid() {
        let g = GridShape::of(640, 360, 4, u64::MAX).expect("a grid");
        assert_eq!((g.nx, g.ny), (161, 91));
        assert_eq!(g.lattice(), (321, 181));
        assert_eq!(g.bytes(), 321 * 181 * 48);
        assert_eq!(GridShape::uniform(Some(g))[..3], [4, 161, 91]);
        assert_eq!(
            f32::from_bits(GridShape::uniform(Some(g))[3]),
            AGREE_TRANSMITTANCE
        );
        assert!(GridShape::of(640, 360, 1, u64::MAX).is_none());
        assert!(GridShape::of(1, 360, 4, u64::MAX).is_none());
        assert!(GridShape::of(640, 360, 4, g.bytes() - 1).is_none());
        assert_eq!(GridShape::uniform(None)[0], 1);
    }
}
