//! Temporal reprojection of the low layer's amortised march on the GPU
//! (`clouds.low.reproject` with `clouds.low.march_stride` ≥ 2;
//! `shaders/clouds_history.wgsl`), as skymodel's `frame::CloudHistory`
//! does it on the CPU: a renderer that draws frame after frame keeps the
//! last frame's lattice (its coarse nodes, each with the frames since its
//! value was marched) and marches only a rotating quarter of the nodes and
//! those the last frame cannot give; the others are the last frame's,
//! moved with the wind.
//!
//! The two lattices alternate: a frame writes one and reads the other.
//! The per-frame decisions — whether the last frame may serve at all
//! (`HistoryMiss`), the quarter, the field's move, which ages' lights still
//! hold — are skymodel's [`HistoryClock`], shared with the CPU backend;
//! the shader counts the nodes reused and marched into a small buffer that
//! [`GpuCloudHistory::read_use`] reads back (`--stats` `cloud_history`).

use himmel_skymodel::frame::cloud_history::{HISTORY_AGREE, HISTORY_MAX_AGE, HISTORY_NEGLIGIBLE};
use himmel_skymodel::frame::{CloudFrame, HistoryClock, HistoryKey, HistoryStep, HistoryUse};
use himmel_skymodel::RenderError;

use super::clouds::CloudUniforms;
use crate::gpu::Gpu;

/// Bytes of the node counters (reused, marched, marched because a light
/// moved, 0).
const COUNTER_BYTES: u64 = 16;

/// The buffers a frame's clouds pass binds for the amortised march.
pub struct LatticeBuffers {
    /// The lattice this frame writes.
    pub lattice: wgpu::Buffer,
    /// The last frame's lattice (read).
    pub prev: wgpu::Buffer,
    /// The node counters.
    pub counters: wgpu::Buffer,
    /// Whether the frame keeps a history (`clouds_grid_coarse_history` in
    /// place of `clouds_grid_coarse`).
    pub history: bool,
}

/// The lattices, the counters and the clock, kept across frames.
#[derive(Default)]
pub struct GpuCloudHistory {
    clock: HistoryClock,
    lattices: [Option<wgpu::Buffer>; 2],
    /// The lattice the last frame wrote.
    current: usize,
    counters: Option<wgpu::Buffer>,
    read: Option<wgpu::Buffer>,
    /// This frame's step (`None`: the frame keeps no history).
    step: Option<HistoryStep>,
    /// The last frame's step, whose counts `counters` holds.
    last: Option<HistoryStep>,
}

/// The buffer kept in `slot`, at least `bytes` long with `usage` (a new
/// one when it is shorter).
pub fn grown(
    gpu: &Gpu,
    slot: &mut Option<wgpu::Buffer>,
    label: &str,
    bytes: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    match slot {
        Some(b) if b.size() >= bytes => b.clone(),
        _ => {
            let b = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            });
            *slot = Some(b.clone());
            b
        }
    }
}

/// `Clouds::history` and `history_shift` for `step` (zero: none).
pub fn history_uniforms(step: Option<&HistoryStep>) -> ([u32; 4], [f32; 4]) {
    let Some(s) = step else {
        return ([0; 4], [0.0; 4]);
    };
    let lit = s
        .lit
        .iter()
        .enumerate()
        .fold(0u32, |bits, (a, &l)| bits | (u32::from(l) << a));
    (
        [
            u32::from(s.miss.is_none()),
            s.phase as u32,
            lit,
            HISTORY_MAX_AGE as u32,
        ],
        [
            s.delta_km.x,
            s.delta_km.y,
            HISTORY_AGREE,
            HISTORY_NEGLIGIBLE,
        ],
    )
}

impl GpuCloudHistory {
    /// Forgets the last frame: the next marches every coarse node (its
    /// `cloud_history` says `first frame`).
    pub fn clear(&mut self) {
        self.clock.clear();
    }

    /// Starts a frame: it keeps no history until [`Self::buffers`] says so.
    pub fn begin_frame(&mut self) {
        self.step = None;
    }

    /// Ends a frame: one without the amortised march's history breaks the
    /// sequence (the next starts afresh, as on the CPU).
    pub fn end_frame(&mut self) {
        if self.step.is_none() {
            self.clock.clear();
        }
        self.last = self.step.take();
    }

    /// The lattice buffers of a frame whose lattice takes `bytes`, and its
    /// uniforms `u`'s history fields. `key`: the frame keeps a history
    /// (its clouds `c`); `stand_in`: a small read-only buffer bound for the
    /// last lattice without one.
    pub fn buffers(
        &mut self,
        gpu: &Gpu,
        u: &mut CloudUniforms,
        bytes: u64,
        key: Option<(HistoryKey, &CloudFrame)>,
        stand_in: wgpu::Buffer,
    ) -> LatticeBuffers {
        let usage = wgpu::BufferUsages::STORAGE;
        let counters = grown(
            gpu,
            &mut self.counters,
            "cloud history counters",
            COUNTER_BYTES,
            usage | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        );
        let Some((key, c)) = key else {
            self.step = None;
            let lattice = self.lattice(gpu, self.current, bytes);
            (u.history, u.history_shift) = history_uniforms(None);
            return LatticeBuffers {
                lattice,
                prev: stand_in,
                counters,
                history: false,
            };
        };
        let step = self.clock.step(c, key);
        let prev = self.current;
        self.current = 1 - prev;
        let lattice = self.lattice(gpu, self.current, bytes);
        let prev = self.lattice(gpu, prev, bytes);
        gpu.queue
            .write_buffer(&counters, 0, &[0u8; COUNTER_BYTES as usize]);
        (u.history, u.history_shift) = history_uniforms(Some(&step));
        self.step = Some(step);
        LatticeBuffers {
            lattice,
            prev,
            counters,
            history: true,
        }
    }

    /// Lattice buffer `i` (of the two that alternate), of at least `bytes`.
    fn lattice(&mut self, gpu: &Gpu, i: usize, bytes: u64) -> wgpu::Buffer {
        grown(
            gpu,
            &mut self.lattices[i],
            "cloud march lattice",
            bytes,
            wgpu::BufferUsages::STORAGE,
        )
    }

    /// What the history gave the last frame (`None`: it kept none): the
    /// counters read back.
    pub fn read_use(&mut self, gpu: &Gpu) -> Result<Option<HistoryUse>, RenderError> {
        let (Some(step), Some(counters)) = (self.last, self.counters.as_ref()) else {
            return Ok(None);
        };
        let read = grown(
            gpu,
            &mut self.read,
            "cloud history read-back",
            COUNTER_BYTES,
            wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        );
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(counters, 0, &read, 0, COUNTER_BYTES);
        gpu.queue.submit([enc.finish()]);
        let bytes = gpu.map_read(&read, COUNTER_BYTES)?;
        let n: Vec<u32> = bytes
            .chunks_exact(4)
            .map(bytemuck::pod_read_unaligned)
            .collect();
        let at = |k: usize| n.get(k).copied().unwrap_or(0) as usize;
        Ok(Some(HistoryUse {
            reused: at(0),
            marched: at(1),
            light_moved: at(2),
            miss: step.miss,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    /// The uniforms carry the step: reuse allowed without a miss, the
    /// phase, one bit per age whose lights hold, the shift.
    #[test]
    fn uniforms_carry_the_step() {
        let step = HistoryStep {
            miss: None,
            phase: 3,
            delta_km: Vec2::new(0.25, -0.5),
            lit: [true, true, false, true],
        };
        let (h, s) = history_uniforms(Some(&step));
        assert_eq!(h, [1, 3, 0b1011, HISTORY_MAX_AGE as u32]);
        assert_eq!(s, [0.25, -0.5, HISTORY_AGREE, HISTORY_NEGLIGIBLE]);
        let miss = HistoryStep {
            miss: Some(himmel_skymodel::frame::HistoryMiss::First),
            ..step
        };
        assert_eq!(history_uniforms(Some(&miss)).0[0], 0);
        assert_eq!(history_uniforms(None), ([0; 4], [0.0; 4]));
    }
}
