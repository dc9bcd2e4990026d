//! Buffers kept across frames, one per [`Slot`]: a frame rewrites a slot
//! with `Queue::write_buffer` (ordered after every earlier submission's
//! reads) and a new buffer is made only when the frame needs a larger one
//! or another usage, so a real-time loop allocates nothing per frame but
//! its target texture.

use std::collections::HashMap;
use std::sync::Mutex;

/// The per-frame buffers: one slot per table, uniform and scratch buffer
/// of the passes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Slot {
    /// The accumulation band (one vec4 per pixel of the band).
    Accum,
    /// The bands' frame uniforms, each at an aligned offset.
    Frame,
    /// The sky-view LUTs uploaded from the CPU.
    SkyView,
    /// A black sky view when the atmosphere does not run.
    NoSky,
    /// The Sun table.
    SunTable,
    /// The Moon's uniform and tables.
    Moon,
    /// The night passes' uniform.
    Night,
    /// The Milky Way pass's extinction table.
    Extinction,
    /// A black Milky Way map when its pass does not run.
    NoMilkyWayMap,
    /// The point sources' footprint records.
    PointRecords,
    /// The point sources' per-tile lists.
    PointTiles,
    /// Timestamp queries resolved.
    Timestamps,
    /// Timestamps mapped for reading.
    TimestampsRead,
    /// A frame mapped for reading.
    FrameRead,
}

/// The buffers kept across frames.
#[derive(Default)]
pub struct BufferPool(Mutex<HashMap<Slot, wgpu::Buffer>>);

/// A range of a pooled buffer, as bound by a frame.
#[derive(Debug, Clone)]
pub struct PoolBinding {
    /// The buffer.
    pub buffer: wgpu::Buffer,
    /// First byte.
    pub offset: u64,
    /// Bytes.
    pub size: u64,
}

impl PoolBinding {
    /// The binding of exactly these bytes.
    pub fn resource(&self) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.buffer,
            offset: self.offset,
            size: std::num::NonZeroU64::new(self.size),
        })
    }
}

impl BufferPool {
    /// The slot's buffer, at least `size` bytes (and 16), with `usage` and
    /// `COPY_DST`. A grown buffer gets the next power of two within the
    /// adapter's buffer limit, so a slightly larger next frame reuses it.
    pub fn get(
        &self,
        dev: &wgpu::Device,
        slot: Slot,
        size: u64,
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        let size = size.max(16).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        let mut slots = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(b) = slots.get(&slot) {
            if b.size() >= size && b.usage() == usage {
                return b.clone();
            }
        }
        let grown = size
            .next_power_of_two()
            .min(dev.limits().max_buffer_size)
            .max(size);
        let b = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some(slot.label()),
            size: grown,
            usage,
            mapped_at_creation: false,
        });
        slots.insert(slot, b.clone());
        b
    }

    /// The slot's buffer holding `bytes` from offset 0, and the binding of
    /// exactly those bytes (16 zero bytes when `bytes` is empty).
    pub fn upload(
        &self,
        dev: &wgpu::Device,
        queue: &wgpu::Queue,
        slot: Slot,
        bytes: &[u8],
        usage: wgpu::BufferUsages,
    ) -> PoolBinding {
        let buffer = self.get(dev, slot, bytes.len() as u64, usage);
        let size = if bytes.is_empty() {
            queue.write_buffer(&buffer, 0, &[0u8; 16]);
            16
        } else {
            queue.write_buffer(&buffer, 0, bytes);
            bytes.len() as u64
        };
        PoolBinding {
            buffer,
            offset: 0,
            size,
        }
    }

    /// The number of buffers held.
    pub fn len(&self) -> usize {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    /// Whether no buffer is held yet.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl Slot {
    /// The buffer's debug label.
    pub fn label(self) -> &'static str {
        match self {
            Slot::Accum => "accum",
            Slot::Frame => "frame",
            Slot::SkyView => "sky view",
            Slot::NoSky => "no sky",
            Slot::SunTable => "sun table",
            Slot::Moon => "moon",
            Slot::Night => "night",
            Slot::Extinction => "extinction",
            Slot::NoMilkyWayMap => "no Milky Way map",
            Slot::PointRecords => "point sources",
            Slot::PointTiles => "point tiles",
            Slot::Timestamps => "timestamps",
            Slot::TimestampsRead => "timestamps read",
            Slot::FrameRead => "frame read",
        }
    }
}
