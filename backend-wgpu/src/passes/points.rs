//! Stars and planets (`shaders/points.wgsl`, `shaders/quads.wgsl`): the
//! frame plan computes each source's footprint as the CPU's splat does
//! (`NightFrame::splat_plans`: position, extinction, normalisations of the
//! core and the glare disk); [`point_lists`] bins them into
//! [`POINT_TILE`]² tiles. Two ways to draw them, both evaluating the same
//! WGSL footprint function (points.wgsl `point_footprint`, the CPU's
//! `splat_at`) on the same records:
//!
//! * [`PointMethod::Tiles`] — compute passes, one workgroup per non-empty
//!   tile, each pixel summing the footprints of its tile's list over its
//!   solid angle (no atomics);
//! * [`PointMethod::Quads`] — a render pass drawing one instanced quad per
//!   record (6 vertices from `vertex_index`, the record read by
//!   `instance_index`; no geometry shader) over the footprint's pixel
//!   bounds, clipped to the band and in a cube map to the record's face;
//!   the fragment shader returns footprint / Ω, added by the blend state
//!   (One, One) into a band-sized float target — `Rgba32Float` where the
//!   adapter has `FLOAT32_BLENDABLE`, otherwise `Rgba16Float` scaled by a
//!   power of two ([`quad_scale`]) — which compute passes
//!   (`quad_resolve_*`, one workgroup per non-empty tile) add into the
//!   accumulation band at the pass's place in the order (the Moon pass
//!   after it replaces that light by its coverage). The non-empty tiles of
//!   the target are zeroed by a draw first (no full-target clear).
//!
//! The default ([`PointMethod::default_for`]) is tiles on software
//! adapters, whose timestamp queries misattribute compute-pass time once a
//! render pass is in the submission (lavapipe), and quads on hardware GPUs.

use himmel_skymodel::{Camera, Effect, FramePlan, Projection, RenderError, Scene, Unavailable};

use crate::frame::{FrameBuild, FrameLayout, SkyGroup};
use crate::gpu::{bind_group, storage_entry, uniform_entry, Gpu, TimestampSlot};
use crate::pass::{Band, Dispatch, Groups, Step};
use crate::pool::{BufferPool, Slot};
use crate::uniforms::{FrameUniforms, NightUniforms, PointRecord, POINTS_WGSL, QUADS_WGSL};

/// The point passes: the tiled compute pipelines, the quads' pipelines and
/// target (kept across frames), and this frame's lists.
pub struct PointsPass {
    /// How stars and planets are drawn.
    pub method: PointMethod,
    tiles: [wgpu::ComputePipeline; 2],
    quads: QuadPipelines,
    format: wgpu::TextureFormat,
    target: Option<wgpu::Texture>,
    frame: Option<PointsFrame>,
}

/// A frame's point lists as the steps draw them.
struct PointsFrame {
    /// Per list (stars, planets): the first word and the number of its
    /// non-empty tiles.
    busy: [(u32, u32); 2],
    /// Per list: its records (the quads' instances).
    ranges: [(u32, u32); 2],
    /// The quad target's view and the resolve's group 1, when quads draw.
    quads: Option<(wgpu::TextureView, wgpu::BindGroup)>,
}

impl PointsPass {
    /// Compiles the passes (quads into the adapter's blendable float format).
    pub fn new(gpu: &Gpu, sky: &SkyGroup) -> Self {
        let module = gpu.shader("points.wgsl", POINTS_WGSL);
        let layout = gpu.pipeline_layout("points", &[&sky.layout]);
        let format = if gpu.float32_blendable {
            wgpu::TextureFormat::Rgba32Float
        } else {
            wgpu::TextureFormat::Rgba16Float
        };
        PointsPass {
            method: PointMethod::default_for(gpu.info.device_type),
            tiles: ["stars", "planets"].map(|e| gpu.compute_pipeline(&layout, &module, e)),
            quads: quad_pipelines(&gpu.device, &sky.layout, format),
            format,
            target: None,
            frame: None,
        }
    }

    /// The quad target's format.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// Sets the quad target's format (`Rgba16Float`, or `Rgba32Float`
    /// where the device blends it) and recompiles the draw.
    pub fn set_format(
        &mut self,
        gpu: &Gpu,
        sky: &SkyGroup,
        format: wgpu::TextureFormat,
    ) -> Result<(), RenderError> {
        let ok = match format {
            wgpu::TextureFormat::Rgba16Float => true,
            wgpu::TextureFormat::Rgba32Float => gpu.float32_blendable,
            _ => false,
        };
        if !ok {
            return Err(RenderError::Unavailable(Unavailable::QuadFormat(format!(
                "{format:?}"
            ))));
        }
        if format != self.format {
            self.quads = quad_pipelines(&gpu.device, &sky.layout, format);
            self.format = format;
            self.target = None;
        }
        Ok(())
    }

    /// Bins the plan's stars and planets into tile lists (uploaded with
    /// their records), sets the point constants of the night uniforms and,
    /// for quads, the target; returns how the points are drawn (`None`
    /// when neither pass runs).
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        pool: &BufferPool,
        scene: &Scene,
        plan: &FramePlan,
        layout: &FrameLayout,
        build: &mut FrameBuild,
    ) -> Result<Option<PointMethod>, RenderError> {
        self.frame = None;
        let (stars, planets) = (plan.runs(Effect::Stars), plan.runs(Effect::Planets));
        let Some(night) = plan.night.as_ref().filter(|_| stars || planets) else {
            return Ok(None);
        };
        let cam = &scene.camera;
        let plans = |on: bool, s| {
            if on {
                night.splat_plans(scene, s)
            } else {
                Vec::new()
            }
        };
        let star_plans = plans(stars, &night.stars);
        let planet_plans = plans(planets, &night.planets);
        let lists = point_lists(cam, &[&star_plans, &planet_plans]);
        let n = &mut build.night;
        n.tile_size = POINT_TILE;
        n.tiles_per_row = lists.tiles_per_row;
        [n.star_list, n.planet_list] = lists.lists;
        [n.star_busy_first, n.planet_busy_first] = [lists.busy[0].0, lists.busy[1].0];
        [n.star_busy_count, n.planet_busy_count] = [lists.busy[0].1, lists.busy[1].1];
        if let Some((p, _)) = star_plans.first().or(planet_plans.first()) {
            n.core_radius = p.r as f32;
            n.inv_two_sigma2 = p.inv2s2;
        }
        n.quad_scale = if self.format == wgpu::TextureFormat::Rgba32Float {
            1.0
        } else {
            quad_scale(cam, star_plans.iter().chain(&planet_plans))
        };
        let storage = wgpu::BufferUsages::STORAGE;
        build.points = Some(pool.upload(
            &gpu.device,
            &gpu.queue,
            Slot::PointRecords,
            bytemuck::cast_slice(&lists.records),
            storage,
        ));
        build.tiles = Some(pool.upload(
            &gpu.device,
            &gpu.queue,
            Slot::PointTiles,
            bytemuck::cast_slice(&lists.words),
            storage,
        ));
        // Quads: a float target of the band's size (where the adapter's
        // texture limit allows the image width).
        let quads = self.method == PointMethod::Quads
            && layout.width <= gpu.device.limits().max_texture_dimension_2d;
        let quads = quads.then(|| self.quad_target(gpu, layout));
        self.frame = Some(PointsFrame {
            busy: lists.busy,
            ranges: lists.ranges,
            quads,
        });
        Ok(Some(
            if self.frame.as_ref().is_some_and(|f| f.quads.is_some()) {
                PointMethod::Quads
            } else {
                PointMethod::Tiles
            },
        ))
    }

    /// The quad target (kept while it is large enough), its view and the
    /// resolve's group 1.
    fn quad_target(
        &mut self,
        gpu: &Gpu,
        layout: &FrameLayout,
    ) -> (wgpu::TextureView, wgpu::BindGroup) {
        let (w, rows) = (layout.width, layout.band_rows);
        let format = self.format;
        let target = match self.target.take() {
            Some(t) if t.width() >= w && t.height() >= rows && t.format() == format => t,
            _ => gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("point-source quads"),
                size: wgpu::Extent3d {
                    width: w,
                    height: rows,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            }),
        };
        let view = self.target.insert(target).create_view(&Default::default());
        let group = bind_group(
            &gpu.device,
            "quad target",
            &self.quads.target_layout,
            &[wgpu::BindingResource::TextureView(&view)],
        );
        (view, group)
    }

    /// The steps of the stars' (`Effect::Stars`) or the planets' list.
    pub fn steps(&self, effect: Effect) -> Vec<Box<dyn Step>> {
        let Some(f) = &self.frame else {
            return Vec::new();
        };
        let l = if effect == Effect::Stars { 0 } else { 1 };
        let label = if l == 0 { "stars" } else { "planets" };
        // One 8 × 8 workgroup per non-empty tile, in rows of at most
        // ACTIVE_ROW workgroups.
        let n = f.busy[l].1;
        let groups = Groups::Fixed(n.min(ACTIVE_ROW), n.div_ceil(ACTIVE_ROW));
        match &f.quads {
            None => vec![Box::new(Dispatch {
                label,
                pipeline: self.tiles[l].clone(),
                group1: None,
                groups,
            })],
            Some((view, target)) => vec![
                Box::new(QuadDraw {
                    label,
                    device: self.quads.device.clone(),
                    layout: self.quads.draw_layout.clone(),
                    draw: self.quads.draw.clone(),
                    clear: self.quads.clear.clone(),
                    view: view.clone(),
                    busy: f.busy[l],
                    range: f.ranges[l],
                }),
                Box::new(Dispatch {
                    label,
                    pipeline: self.quads.resolve[l].clone(),
                    group1: Some(target.clone()),
                    groups,
                }),
            ],
        }
    }
}

/// The quads' draw of one list: its non-empty tiles of the target zeroed
/// by a draw, then one instance per record.
struct QuadDraw {
    label: &'static str,
    device: wgpu::Device,
    layout: wgpu::BindGroupLayout,
    draw: wgpu::RenderPipeline,
    clear: wgpu::RenderPipeline,
    view: wgpu::TextureView,
    busy: (u32, u32),
    range: (u32, u32),
}

impl Step for QuadDraw {
    fn label(&self) -> &'static str {
        self.label
    }

    fn record(&self, enc: &mut wgpu::CommandEncoder, band: &Band, ts: Option<TimestampSlot>) {
        // The draw's group: the band's frame uniforms, the night constants,
        // the records and the tile lists.
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("quads"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: band.frame.resource(),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: band.night.resource(),
                },
                wgpu::BindGroupEntry {
                    binding: 8,
                    resource: band.points.resource(),
                },
                wgpu::BindGroupEntry {
                    binding: 9,
                    resource: band.tiles.resource(),
                },
            ],
        });
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(self.label),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.view,
                depth_slice: None,
                resolve_target: None,
                // The non-empty tiles are cleared by a draw.
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: ts.as_ref().map(TimestampSlot::render),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_viewport(0.0, 0.0, band.width as f32, band.rows as f32, 0.0, 1.0);
        pass.set_bind_group(0, &group, &[]);
        let (word, n) = self.busy;
        if n > 0 {
            pass.set_pipeline(&self.clear);
            pass.draw(0..6, word..word + n);
        }
        pass.set_pipeline(&self.draw);
        let (first, end) = self.range;
        if end > first {
            pass.draw(0..6, first..end);
        }
    }
}

/// How the stars' and planets' footprints are drawn. Both evaluate the
/// same per-pixel footprint (points.wgsl `point_footprint`) from the same
/// records ([`point_lists`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointMethod {
    /// Compute passes: one workgroup per non-empty 8 × 8 tile, each pixel
    /// sums the footprints listed for its tile (points.wgsl `stars`/`planets`).
    Tiles,
    /// A render pass: one instanced quad per footprint record (vertex +
    /// fragment shaders, no geometry shader, quads.wgsl), added by the blend
    /// state into a float target ([`WgpuRenderer::quad_format`]) that a
    /// compute pass then adds into the frame.
    Quads,
}

impl PointMethod {
    /// The `--stats` name: `tiles` or `quads`.
    pub fn name(self) -> &'static str {
        match self {
            PointMethod::Tiles => "tiles",
            PointMethod::Quads => "quads",
        }
    }

    /// The default for an adapter of this type: tiles on a software
    /// adapter (`DeviceType::Cpu`, e.g. lavapipe), quads on every other.
    /// On lavapipe the two tie in frame time (`tests/benches/wgpu_render.rs`, group
    /// `night`), but its timestamp queries misattribute the compute passes'
    /// time once a render pass is in the submission (the `--stats` per-pass
    /// times would be wrong); on hardware GPUs the rasteriser touches only
    /// the footprints' pixels (not measured: no GPU was lent).
    pub fn default_for(device_type: wgpu::DeviceType) -> Self {
        match device_type {
            wgpu::DeviceType::Cpu => PointMethod::Tiles,
            _ => PointMethod::Quads,
        }
    }
}

/// The point-source quads: the draw (bind group 0: frame, night
/// constants, records) and the resolve pass (the sky's bind group 0 and the
/// quad target in group 1).
struct QuadPipelines {
    /// The device (the draw's bind groups are made per band).
    device: wgpu::Device,
    draw_layout: wgpu::BindGroupLayout,
    target_layout: wgpu::BindGroupLayout,
    draw: wgpu::RenderPipeline,
    /// Zeroes the non-empty tiles before the draw (no full-target clear).
    clear: wgpu::RenderPipeline,
    /// The resolve passes of the stars' and the planets' lists.
    resolve: [wgpu::ComputePipeline; 2],
}

/// The point-source quads' pipelines (quads.wgsl): the instanced draw
/// into a `format` target with additive blending (One, One), and the
/// resolve pass that adds the target into `accum`.
fn quad_pipelines(
    device: &wgpu::Device,
    sky: &wgpu::BindGroupLayout,
    format: wgpu::TextureFormat,
) -> QuadPipelines {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("quads.wgsl"),
        source: wgpu::ShaderSource::Wgsl(QUADS_WGSL.into()),
    });
    let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
    let draw_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("quads"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                visibility: vf,
                ..uniform_entry::<FrameUniforms>(0)
            },
            wgpu::BindGroupLayoutEntry {
                visibility: vf,
                ..uniform_entry::<NightUniforms>(5)
            },
            wgpu::BindGroupLayoutEntry {
                visibility: vf,
                ..storage_entry(8, true)
            },
            wgpu::BindGroupLayoutEntry {
                visibility: vf,
                ..storage_entry(9, true)
            },
        ],
    });
    let target_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("quad target"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        }],
    });
    let draw_pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("quads"),
        bind_group_layouts: &[Some(&draw_layout)],
        immediate_size: 0,
    });
    let add = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    };
    let render = |vs: &str, fs: &str, blend: Option<wgpu::BlendState>| {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(fs),
            layout: Some(&draw_pl),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some(vs),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
    };
    let draw = render(
        "quad_vs",
        "quad_fs",
        Some(wgpu::BlendState {
            color: add,
            alpha: add,
        }),
    );
    let clear = render("quad_clear_vs", "quad_clear_fs", None);
    let resolve_pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("quad resolve"),
        bind_group_layouts: &[Some(sky), Some(&target_layout)],
        immediate_size: 0,
    });
    let resolve = ["quad_resolve_stars", "quad_resolve_planets"].map(|entry| {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&resolve_pl),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    });
    QuadPipelines {
        device: device.clone(),
        draw_layout,
        target_layout,
        draw,
        clear,
        resolve,
    }
}

/// Tile size (px) of the point-source lists (the workgroup size of the
/// `stars` and `planets` entry points, 8 × 8).
pub const POINT_TILE: u32 = 8;

/// Workgroups per dispatch row of the point passes (one per non-empty tile).
const ACTIVE_ROW: u32 = 32768;

/// The output of [`point_lists`].
#[derive(Debug, Clone, PartialEq)]
pub struct PointLists {
    /// One record per footprint (and wrap).
    pub records: Vec<PointRecord>,
    /// Per list: tile start words, record indices, non-empty tile indices.
    pub words: Vec<u32>,
    /// Tiles per image row (`Night.tiles_per_row`).
    pub tiles_per_row: u32,
    /// Per list: the first word of its tile starts (`Night.star_list`,
    /// `Night.planet_list`).
    pub lists: [u32; 2],
    /// Per list: the first word and the number of its non-empty tiles.
    pub busy: [(u32, u32); 2],
    /// Per list: its records, `records[start..end]` (the instances of its
    /// quads, [`PointMethod::Quads`]).
    pub ranges: [(u32, u32); 2],
}

/// The point sources of the GPU's point passes: one [`PointRecord`] per
/// footprint (equirect footprints that cross the 0°/360° seam once per
/// wrap, as the CPU's `pixel_index` wraps them) and, per list in `lists`
/// (stars, planets), the records that may touch each
/// [`POINT_TILE`]² tile: `tiles + 1` absolute start words, then the
/// record indices, then the indices of the non-empty tiles. Returns the
/// records, the words, the tiles per row, the first word of each list and
/// per list the first word and the number of its non-empty tiles.
pub fn point_lists(
    cam: &Camera,
    lists: &[&[(himmel_skymodel::stars::SplatPlan, [f32; 3])]; 2],
) -> PointLists {
    let (w, h) = cam.image_size();
    let (w, h) = (w as i64, h as i64);
    let ts = POINT_TILE as i64;
    let (tx, ty) = ((w + ts - 1) / ts, (h + ts - 1) / ts);
    let n_tiles = (tx * ty) as usize;
    let mut records = Vec::new();
    let mut words = Vec::new();
    let mut bases = [0u32; 2];
    let mut active = [(0u32, 0u32); 2];
    let mut ranges = [(0u32, 0u32); 2];
    for (l, plans) in lists.iter().enumerate() {
        let start_record = records.len() as u32;
        let mut per_tile: Vec<Vec<u32>> = vec![Vec::new(); n_tiles];
        for (plan, rgb) in plans.iter() {
            let (cx, cy) = plan.pos;
            let (ci, cj) = (cx.floor() as i64, cy.floor() as i64);
            let reach = plan.r.max(plan.glare_r_px.ceil() as i64);
            let (y0, y1) = ((cj - reach).max(0), (cj + reach).min(h - 1));
            if y0 > y1 {
                continue;
            }
            let wraps = if cam.projection == Projection::Equirect {
                (ci - reach).div_euclid(w)..=(ci + reach).div_euclid(w)
            } else {
                0..=0
            };
            for k in wraps {
                let (sx, si) = (cx - (k * w) as f64, ci - k * w);
                let (x0, x1) = ((si - reach).max(0), (si + reach).min(w - 1));
                if x0 > x1 {
                    continue;
                }
                let idx = records.len() as u32;
                records.push(PointRecord {
                    x: sx as f32,
                    y: cy as f32,
                    core_scale: plan.core_scale,
                    glare_radius: plan.glare_r_px,
                    colour: *rgb,
                    glare_scale: plan.glare_scale,
                    pixel_x: si as i32,
                    pixel_y: cj as i32,
                    face: plan.face as i32,
                    near_horizon: plan.near_horizon as u32,
                });
                for j in y0 / ts..=y1 / ts {
                    for i in x0 / ts..=x1 / ts {
                        per_tile[(j * tx + i) as usize].push(idx);
                    }
                }
            }
        }
        bases[l] = words.len() as u32;
        let start = words.len() + n_tiles + 1;
        let mut at = start as u32;
        for t in &per_tile {
            words.push(at);
            at += t.len() as u32;
        }
        words.push(at);
        for t in &per_tile {
            words.extend(t);
        }
        let first = words.len() as u32;
        words.extend(
            per_tile
                .iter()
                .enumerate()
                .filter(|(_, t)| !t.is_empty())
                .map(|(i, _)| i as u32),
        );
        active[l] = (first, words.len() as u32 - first);
        ranges[l] = (start_record, records.len() as u32);
    }
    if records.is_empty() {
        records.push(bytemuck::Zeroable::zeroed());
    }
    PointLists {
        records,
        words,
        tiles_per_row: tx as u32,
        lists: bases,
        busy: active,
        ranges,
    }
}

/// The scale of an rgba16float quad target (`NightUniforms::quad_scale`): the
/// power of two that brings the largest footprint radiance — (core + glare
/// scale) × the brightest colour channel / the solid angle of the pixel at
/// the footprint's centre — near 2¹³, so that it stays below the format's
/// 65504 and the faint stars above its subnormals (6.1 × 10⁻⁵; a star
/// 10⁸ × fainter than the brightest source still gets a normal number).
pub fn quad_scale<'a>(
    cam: &Camera,
    plans: impl Iterator<Item = &'a (himmel_skymodel::stars::SplatPlan, [f32; 3])>,
) -> f32 {
    let mut peak = 0.0f64;
    for (p, rgb) in plans {
        let omega = cam.pixel_solid_angle(p.pos.0, p.pos.1);
        if omega > 0.0 {
            let c = rgb.iter().fold(0.0f32, |m, v| m.max(*v)) as f64;
            peak = peak.max((p.core_scale + p.glare_scale) as f64 * c / omega);
        }
    }
    if !(peak > 0.0 && peak.is_finite()) {
        return 1.0;
    }
    (2.0f64).powi((8192.0 / peak).log2().round().clamp(-120.0, 120.0) as i32) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The point passes run one workgroup per tile: their workgroup size
    /// is the tile size (the quads' resolve passes too).
    #[test]
    fn point_workgroups_are_tiles() {
        let module = naga::front::wgsl::parse_str(POINTS_WGSL).expect("points.wgsl parses");
        for name in ["stars", "planets"] {
            let e = module.entry_points.iter().find(|e| e.name == name).unwrap();
            assert_eq!(e.workgroup_size, [POINT_TILE, POINT_TILE, 1], "{name}");
        }
        let module = naga::front::wgsl::parse_str(QUADS_WGSL).expect("quads.wgsl parses");
        for name in ["quad_resolve_stars", "quad_resolve_planets"] {
            let e = module.entry_points.iter().find(|e| e.name == name).unwrap();
            assert_eq!(e.workgroup_size, [POINT_TILE, POINT_TILE, 1], "{name}");
        }
    }

    fn plan(
        x: f64,
        y: f64,
        core: f32,
        glare_r: f32,
    ) -> (himmel_skymodel::stars::SplatPlan, [f32; 3]) {
        (
            himmel_skymodel::stars::SplatPlan {
                pos: (x, y),
                face: 0,
                near_horizon: false,
                r: 2,
                inv2s2: 1.0,
                core_scale: core,
                glare_r_px: glare_r,
                glare_scale: 0.5 * core,
            },
            [1.0, 0.5, 0.25],
        )
    }

    /// Each list's records are a contiguous range (the instances of its
    /// quads): the stars' first, then the planets', one record per
    /// footprint and equirect wrap.
    #[test]
    fn point_list_ranges_are_the_lists_records() {
        let cam = Camera {
            projection: Projection::Equirect,
            width: 64,
            height: 32,
            ..Default::default()
        };
        let stars = [plan(10.5, 10.5, 1e-6, 0.0), plan(63.5, 16.0, 2e-6, 0.0)];
        let planets = [plan(30.0, 20.0, 1e-4, 3.5)];
        let l = point_lists(&cam, &[&stars, &planets]);
        // The second star crosses the seam: two records.
        assert_eq!(l.ranges, [(0, 3), (3, 4)]);
        assert_eq!(l.records.len(), 4);
        assert_eq!(l.records[3].glare_radius, 3.5);
        let empty = point_lists(&cam, &[&[], &planets]);
        assert_eq!(empty.ranges, [(0, 0), (0, 1)]);
    }

    /// The rgba16float target's scale is a power of two that brings the
    /// largest footprint radiance to within a factor √2 of 2¹³; 1 without
    /// sources.
    #[test]
    fn quad_scale_brings_the_peak_near_2_13() {
        let cam = Camera {
            projection: Projection::Fisheye,
            width: 256,
            height: 256,
            ..Default::default()
        };
        for core in [1e-9f32, 1e-6, 1e-3, 10.0] {
            let plans = [
                plan(128.5, 128.5, core, 2.0),
                plan(100.0, 90.0, core * 1e-3, 0.0),
            ];
            let k = quad_scale(&cam, plans.iter());
            assert_eq!(k.log2().fract(), 0.0, "{k}");
            let omega = cam.pixel_solid_angle(128.5, 128.5);
            let peak = 1.5 * core as f64 / omega * k as f64;
            assert!(
                (8192.0 / 2f64.sqrt()..=8192.0 * 2f64.sqrt()).contains(&peak),
                "{core}: {peak}"
            );
        }
        assert_eq!(quad_scale(&cam, [].iter()), 1.0);
    }
}
