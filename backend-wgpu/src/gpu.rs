//! The GPU context: adapter, device and queue, the features Himmel asks
//! for (timestamp queries, blending into rgba32float), waiting and
//! mapping, pass timing, and the bind-group helpers every pass uses.

use himmel_skymodel::{RenderError, Unavailable};

/// Why the GPU backend cannot start.
#[derive(Debug, Clone, PartialEq)]
pub enum WgpuError {
    /// No adapter of the enabled backends (`WGPU_BACKEND`) exists.
    NoAdapter(String),
    /// The adapter refused to create a device.
    Device(String),
}

impl WgpuError {
    /// The reason as the renderers' [`Unavailable`].
    pub fn unavailable(&self) -> Unavailable {
        match self {
            WgpuError::NoAdapter(m) => Unavailable::NoAdapter(m.clone()),
            WgpuError::Device(m) => Unavailable::DeviceRefused(m.clone()),
        }
    }
}

impl std::fmt::Display for WgpuError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.unavailable().fmt(f)
    }
}

impl std::error::Error for WgpuError {}

impl From<WgpuError> for RenderError {
    fn from(e: WgpuError) -> Self {
        RenderError::Unavailable(e.unavailable())
    }
}

/// How per-pass times were measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Timing {
    /// GPU timestamp queries around each compute or render pass.
    GpuTimestamps,
    /// CPU clock around each submitted pass, waiting for its completion.
    Cpu,
}

impl Timing {
    /// The `--stats` name: `gpu-timestamps` or `cpu`.
    pub fn name(self) -> &'static str {
        match self {
            Timing::GpuTimestamps => "gpu-timestamps",
            Timing::Cpu => "cpu",
        }
    }
}

/// Adapter, device and queue.
pub struct Gpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter: name, backend, device type (`Cpu` for lavapipe).
    pub info: wgpu::AdapterInfo,
    /// Whether the device has `Features::TIMESTAMP_QUERY`.
    pub timestamps_supported: bool,
    /// Whether the device has `Features::FLOAT32_BLENDABLE`.
    pub float32_blendable: bool,
}

impl std::fmt::Debug for Gpu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Gpu")
            .field("adapter", &self.info.name)
            .field("backend", &self.info.backend)
            .finish()
    }
}

impl Gpu {
    /// The first adapter wgpu offers (high-performance preference;
    /// software adapters included) among the backends that `WGPU_BACKEND`
    /// allows (all by default), with its own limits, timestamp queries and
    /// rgba32float blending where it has them.
    pub fn new() -> Result<Gpu, WgpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|e| WgpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let wanted = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::FLOAT32_BLENDABLE;
        let features = adapter.features() & wanted;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("himmel"),
            required_features: features,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| WgpuError::Device(e.to_string()))?;
        Ok(Gpu {
            device,
            queue,
            info,
            timestamps_supported: features.contains(wgpu::Features::TIMESTAMP_QUERY),
            float32_blendable: features.contains(wgpu::Features::FLOAT32_BLENDABLE),
        })
    }

    /// Waits for all submitted work.
    pub fn wait(&self) -> Result<(), RenderError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(device_error)
    }

    /// The texels of a one-layer 2D `texture`, row-major and tightly
    /// packed: copied into a buffer (rows padded to the copy alignment),
    /// mapped and unpadded. `T` is one texel (its size the format's).
    pub fn read_texels<T: bytemuck::Pod>(
        &self,
        texture: &wgpu::Texture,
        label: &str,
    ) -> Result<Vec<T>, RenderError> {
        let (w, h) = (texture.width(), texture.height());
        let texel = std::mem::size_of::<T>() as u64;
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as u64;
        let row = (w as u64 * texel).div_ceil(align) * align;
        let buf = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: row * h as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buf,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row as u32),
                    rows_per_image: Some(h),
                },
            },
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
        self.queue.submit([enc.finish()]);
        let bytes = self.map_read(&buf, row * h as u64)?;
        let line = (w as u64 * texel) as usize;
        Ok(bytes
            .chunks_exact(row as usize)
            .flat_map(|r| r[..line].chunks_exact(texel as usize))
            .map(bytemuck::pod_read_unaligned)
            .collect())
    }

    /// Maps the first `size` bytes of `buffer` (MAP_READ) and returns them.
    pub fn map_read(&self, buffer: &wgpu::Buffer, size: u64) -> Result<Vec<u8>, RenderError> {
        let slice = buffer.slice(..size);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv().map_err(device_error)?.map_err(device_error)?;
        let bytes = slice.get_mapped_range().map_err(device_error)?.to_vec();
        buffer.unmap();
        Ok(bytes)
    }

    /// A compute-stage bind-group layout whose binding k is `types[k]`
    /// (see [`bind`]).
    pub fn compute_layout(
        &self,
        label: &str,
        types: &[wgpu::BindingType],
    ) -> wgpu::BindGroupLayout {
        let entries: Vec<wgpu::BindGroupLayoutEntry> = types
            .iter()
            .enumerate()
            .map(|(k, ty)| wgpu::BindGroupLayoutEntry {
                binding: k as u32,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: *ty,
                count: None,
            })
            .collect();
        self.device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &entries,
            })
    }

    /// A compute pipeline layout over `layouts` (bind groups 0, 1, …).
    pub fn pipeline_layout(
        &self,
        label: &str,
        layouts: &[&wgpu::BindGroupLayout],
    ) -> wgpu::PipelineLayout {
        let groups: Vec<Option<&wgpu::BindGroupLayout>> =
            layouts.iter().map(|l| Some(*l)).collect();
        self.device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &groups,
                immediate_size: 0,
            })
    }

    /// A WGSL shader module.
    pub fn shader(&self, label: &str, source: &str) -> wgpu::ShaderModule {
        self.device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            })
    }

    /// The compute pipeline of `entry` in `module` with `layout`.
    pub fn compute_pipeline(
        &self,
        layout: &wgpu::PipelineLayout,
        module: &wgpu::ShaderModule,
        entry: &str,
    ) -> wgpu::ComputePipeline {
        self.device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(layout),
                module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
    }
}

/// A driver error as a [`RenderError`].
pub fn device_error(e: impl std::fmt::Display) -> RenderError {
    RenderError::Device(e.to_string())
}

/// A bind group whose entries are `resources` at bindings 0, 1, 2, …
pub fn bind_group(
    dev: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .enumerate()
        .map(|(k, r)| wgpu::BindGroupEntry {
            binding: k as u32,
            resource: r.clone(),
        })
        .collect();
    dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// The binding types of compute passes' bind-group layouts
/// ([`Gpu::compute_layout`] numbers them by position).
pub mod bind {
    /// A uniform buffer (any size).
    pub fn uniform() -> wgpu::BindingType {
        buffer(wgpu::BufferBindingType::Uniform)
    }

    /// A storage buffer.
    pub fn storage(read_only: bool) -> wgpu::BindingType {
        buffer(wgpu::BufferBindingType::Storage { read_only })
    }

    fn buffer(ty: wgpu::BufferBindingType) -> wgpu::BindingType {
        wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        }
    }

    /// A sampled texture of this sample type and view dimension.
    pub fn texture(
        sample_type: wgpu::TextureSampleType,
        view_dimension: wgpu::TextureViewDimension,
    ) -> wgpu::BindingType {
        wgpu::BindingType::Texture {
            sample_type,
            view_dimension,
            multisampled: false,
        }
    }

    /// A 2D float texture read with `textureLoad` (not filterable).
    pub fn float_2d() -> wgpu::BindingType {
        texture(
            wgpu::TextureSampleType::Float { filterable: false },
            wgpu::TextureViewDimension::D2,
        )
    }

    /// A 2D unsigned-integer texture.
    pub fn uint_2d() -> wgpu::BindingType {
        texture(
            wgpu::TextureSampleType::Uint,
            wgpu::TextureViewDimension::D2,
        )
    }

    /// An array of depth maps (shadow and visibility maps).
    pub fn depth_array() -> wgpu::BindingType {
        texture(
            wgpu::TextureSampleType::Depth,
            wgpu::TextureViewDimension::D2Array,
        )
    }

    /// A write-only storage texture of this format and view dimension.
    pub fn write(
        format: wgpu::TextureFormat,
        view_dimension: wgpu::TextureViewDimension,
    ) -> wgpu::BindingType {
        wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension,
        }
    }

    /// A write-only 2D storage texture of this format.
    pub fn write_2d(format: wgpu::TextureFormat) -> wgpu::BindingType {
        write(format, wgpu::TextureViewDimension::D2)
    }

    /// A comparison sampler (depth maps).
    pub fn comparison() -> wgpu::BindingType {
        wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison)
    }
}

/// A compute-stage storage buffer binding.
pub fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A compute-stage uniform buffer binding of at least `size` bytes.
pub fn uniform_entry_sized(binding: u32, size: usize) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(size as u64),
        },
        count: None,
    }
}

/// A compute-stage uniform buffer binding sized for `T`.
pub fn uniform_entry<T>(binding: u32) -> wgpu::BindGroupLayoutEntry {
    uniform_entry_sized(binding, std::mem::size_of::<T>())
}

/// Per-pass times of one frame: a timestamp query pair per recorded pass
/// and band where the adapter has them, otherwise the CPU clock around
/// each pass, submitted and awaited on its own.
pub struct Timer {
    queries: Option<wgpu::QuerySet>,
    /// Recorded passes per band.
    per_band: usize,
    cpu_ms: Vec<f64>,
}

/// Where a pass writes its begin and end timestamps.
#[derive(Clone, Copy)]
pub struct TimestampSlot<'a> {
    /// The frame's query set.
    pub set: &'a wgpu::QuerySet,
    /// The begin timestamp's index; the end's is the next.
    pub begin: u32,
}

impl TimestampSlot<'_> {
    /// The timestamp writes of a compute pass.
    pub fn compute(&self) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: self.set,
            beginning_of_pass_write_index: Some(self.begin),
            end_of_pass_write_index: Some(self.begin + 1),
        }
    }

    /// The timestamp writes of a render pass.
    pub fn render(&self) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: self.set,
            beginning_of_pass_write_index: Some(self.begin),
            end_of_pass_write_index: Some(self.begin + 1),
        }
    }
}

impl Timer {
    /// A timer for `per_band` passes in each of `bands` bands, with
    /// timestamp queries when `timestamps`.
    pub fn new(gpu: &Gpu, timestamps: bool, per_band: usize, bands: usize) -> Timer {
        let queries = timestamps.then(|| {
            gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass times"),
                ty: wgpu::QueryType::Timestamp,
                count: (2 * per_band * bands) as u32,
            })
        });
        Timer {
            queries,
            per_band,
            cpu_ms: vec![0.0; per_band],
        }
    }

    /// Whether the passes are timed by timestamp queries (all passes then
    /// go into one submission).
    pub fn on_gpu(&self) -> bool {
        self.queries.is_some()
    }

    /// The timestamp slot of pass `k` in band `band`.
    pub fn slot(&self, band: usize, k: usize) -> Option<TimestampSlot<'_>> {
        self.queries.as_ref().map(|set| TimestampSlot {
            set,
            begin: 2 * (band * self.per_band + k) as u32,
        })
    }

    /// Adds a CPU-clock measurement of pass `k`.
    pub fn add_cpu(&mut self, k: usize, ms: f64) {
        self.cpu_ms[k] += ms;
    }

    /// The time of each pass summed over the bands, ms: resolved from the
    /// queries (after the frame's submission) or the CPU clock's sums.
    pub fn times(
        self,
        gpu: &Gpu,
        pool: &crate::pool::BufferPool,
        bands: usize,
    ) -> Result<Vec<f64>, RenderError> {
        let Some(q) = &self.queries else {
            return Ok(self.cpu_ms);
        };
        let n = self.per_band * bands;
        let size = (2 * n * 8) as u64;
        use crate::pool::Slot;
        let resolve = pool.get(
            &gpu.device,
            Slot::Timestamps,
            size,
            wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        );
        let read = pool.get(
            &gpu.device,
            Slot::TimestampsRead,
            size,
            wgpu::BufferUsages::MAP_READ,
        );
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        enc.resolve_query_set(q, 0..2 * n as u32, &resolve, 0);
        enc.copy_buffer_to_buffer(&resolve, 0, &read, 0, size);
        gpu.queue.submit([enc.finish()]);
        let bytes = gpu.map_read(&read, size)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        let period = gpu.queue.get_timestamp_period() as f64;
        let mut sum = vec![0.0; self.per_band];
        for k in 0..n {
            sum[k % self.per_band] +=
                ticks[2 * k + 1].wrapping_sub(ticks[2 * k]) as f64 * period * 1e-6;
        }
        Ok(sum)
    }
}
