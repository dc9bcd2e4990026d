//! Screen-space reflections (`lighting.ssr`, issue 16;
//! `shaders/lighting/ssr.wgsl`), after the lighting pass:
//!
//! 1. the lit frame is copied (this frame's radiance before reflections);
//! 2. the hierarchical depth chain (Hi-Z) is built from the G-buffer:
//!    1 / view depth per pixel, each coarser level the nearest surface of
//!    2 × 2 texels;
//! 3. per pixel with roughness ≤ `max_roughness`, `samples` GGX reflected
//!    rays are traced through the chain; a hit reads the lit radiance
//!    there — the previous frame's final image reprojected with its
//!    view-projection when `history` is on and the point lies in it, else
//!    the copy of 1 — and the reflection replaces the lighting pass's
//!    prefiltered sky specular for the share of rays that hit
//!    (`L + W·S − C·E`, ssr.wgsl), written back into the frame's target;
//! 4. with `history`, the final frame is kept for the next.
//!
//! The lighting pass writes E and W (`spec_env`, `spec_w`: the sky's
//! specular term and its split-sum weight, both as they reach the camera)
//! only while the pass is armed ([`Reflections::arm`]); otherwise it binds
//! 1 × 1 stand-ins it does not write.
//!
//! What a reflected ray reads is the radiance the hit surface sends to the
//! *camera* (the lit image): exact for the Lambertian part, approximate for
//! the hit surface's own specular; the aerial perspective between the eye
//! and the hit surface is in it too (small over a world's distances).

use glam::Mat4;
use himmel_skymodel::renderer::PassStat;
use himmel_skymodel::{RenderError, SsrSettings};

use super::resources::{texture, GBuffer};
use super::view::{CameraBlock, WorldCamera};
use crate::gpu::{bind, bind_group, Gpu};

/// The pass's uniforms (`Ssr` in ssr.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SsrUniforms {
    cam: CameraBlock,
    prev_view_proj: [f32; 16],
    params: [f32; 4],
    q: [u32; 4],
    jitter: [f32; 4],
}

/// The reflections' confidence of the last frame, read back: per pixel
/// the share of its reflected rays (weighted) that met a surface on
/// screen, edge fade included; 0 where the pass did not reflect.
#[derive(Debug, Clone, PartialEq)]
pub struct SsrImage {
    /// Width, px.
    pub width: u32,
    /// Height, px.
    pub height: u32,
    /// Confidence per pixel, row-major, in [0, 1].
    pub confidence: Vec<f32>,
}

/// The most levels of the Hi-Z chain.
const MAX_LEVELS: u32 = 8;

struct SsrPipes {
    hiz_layout: wgpu::BindGroupLayout,
    resolve_layout: [wgpu::BindGroupLayout; 2],
    first: wgpu::ComputePipeline,
    down: wgpu::ComputePipeline,
    resolve: wgpu::ComputePipeline,
}

struct Images {
    size: (u32, u32),
    spec_env: wgpu::TextureView,
    spec_w: wgpu::TextureView,
    lit: wgpu::Texture,
    lit_view: wgpu::TextureView,
    history: wgpu::Texture,
    history_view: wgpu::TextureView,
    hiz_view: wgpu::TextureView,
    hiz_levels: Vec<wgpu::TextureView>,
    conf: wgpu::Texture,
    conf_view: wgpu::TextureView,
}

/// The ssr pass and its images, kept between frames.
#[derive(Default)]
pub struct Reflections {
    pipes: Option<SsrPipes>,
    images: Option<Images>,
    stand_ins: Option<[wgpu::TextureView; 2]>,
    armed: bool,
    /// The view-projection of the frame kept in `history`.
    history_vp: Option<Mat4>,
}

const LIT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

fn pipes(gpu: &Gpu) -> SsrPipes {
    let f = bind::float_2d();
    let gbuf = [bind::uniform(), f, f, bind::uint_2d()];
    let mut hiz = gbuf.to_vec();
    hiz.extend([bind::write_2d(wgpu::TextureFormat::R32Float), f]);
    let hiz_layout = gpu.compute_layout("ssr hiz", &hiz);
    let resolve_layout = [
        gpu.compute_layout("ssr gbuffer", &gbuf),
        gpu.compute_layout(
            "ssr resolve",
            &[
                f,
                f,
                f,
                f,
                f,
                bind::write_2d(LIT),
                bind::write_2d(wgpu::TextureFormat::R32Float),
            ],
        ),
    ];
    let module = gpu.shader("ssr.wgsl", include_str!("../../shaders/lighting/ssr.wgsl"));
    let hl = gpu.pipeline_layout("ssr hiz", &[&hiz_layout]);
    let rl = gpu.pipeline_layout("ssr resolve", &[&resolve_layout[0], &resolve_layout[1]]);
    SsrPipes {
        first: gpu.compute_pipeline(&hl, &module, "hiz_first"),
        down: gpu.compute_pipeline(&hl, &module, "hiz_down"),
        resolve: gpu.compute_pipeline(&rl, &module, "resolve"),
        hiz_layout,
        resolve_layout,
    }
}

/// The Hi-Z chain's levels for an image of `(w, h)`.
fn levels((w, h): (u32, u32)) -> u32 {
    (32 - w.max(h).max(1).leading_zeros()).min(MAX_LEVELS)
}

fn images(gpu: &Gpu, size: (u32, u32)) -> Images {
    use wgpu::TextureUsages as U;
    let d2 = wgpu::TextureDimension::D2;
    let (w, h) = size;
    let make = |label, format, usage| texture(gpu, label, (w, h, 1), d2, format, usage);
    let view = |t: &wgpu::Texture| t.create_view(&Default::default());
    let rw = U::STORAGE_BINDING | U::TEXTURE_BINDING;
    let lit = make("ssr lit", LIT, U::TEXTURE_BINDING | U::COPY_DST);
    let history = make("ssr history", LIT, U::TEXTURE_BINDING | U::COPY_DST);
    let conf = make(
        "ssr confidence",
        wgpu::TextureFormat::R32Float,
        rw | U::COPY_SRC,
    );
    let n = levels(size);
    let hiz = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("ssr hiz"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: n,
        sample_count: 1,
        dimension: d2,
        format: wgpu::TextureFormat::R32Float,
        usage: rw,
        view_formats: &[],
    });
    let hiz_levels = (0..n)
        .map(|l| {
            hiz.create_view(&wgpu::TextureViewDescriptor {
                base_mip_level: l,
                mip_level_count: Some(1),
                ..Default::default()
            })
        })
        .collect();
    Images {
        size,
        spec_env: view(&make("ssr spec env", LIT, rw)),
        spec_w: view(&make("ssr spec weight", LIT, rw)),
        lit_view: view(&lit),
        lit,
        history_view: view(&history),
        history,
        hiz_view: view(&hiz),
        hiz_levels,
        conf_view: view(&conf),
        conf,
    }
}

/// The uniforms of a frame seen by `cam`; `prev`: the history's
/// view-projection when it is read.
fn uniforms(cam: &WorldCamera, s: &SsrSettings, levels: u32, prev: Option<Mat4>) -> SsrUniforms {
    SsrUniforms {
        cam: cam.block(),
        prev_view_proj: prev.unwrap_or(Mat4::IDENTITY).to_cols_array(),
        params: [
            s.max_roughness as f32,
            s.thickness_m as f32,
            s.edge_fade as f32,
            cam.frame as f32,
        ],
        q: [
            s.samples.max(1),
            s.max_steps.max(1),
            levels.max(1),
            prev.is_some() as u32,
        ],
        jitter: [cam.jitter.x, cam.jitter.y, 0.0, 0.0],
    }
}

/// Whether the ssr pass runs: `requested` (the plan's decision), with the
/// sky's light (`env`), and some material of the world (not the Lambertian
/// ground) no rougher than `lighting.ssr.max_roughness` — decided from the
/// world's materials (`least`: the least roughness of a non-Lambertian
/// one), not from what is on screen; else why not (`Ok` when not
/// requested: no entry is due then).
pub fn decide(
    scene: &himmel_skymodel::Scene,
    requested: bool,
    env: bool,
    least: Option<f32>,
) -> Result<(), String> {
    let max = scene.lighting.ssr.max_roughness as f32;
    match least {
        _ if !requested => Ok(()),
        _ if !env => Err("no sky light: the atmosphere pass does not run".into()),
        Some(r) if r <= max => Ok(()),
        None => Err("no material of the world is smooth enough (all are Lambertian)".into()),
        Some(r) => Err(format!(
            "no material of the world is smooth enough (least roughness {r:.2} > max_roughness {max:.2})"
        )),
    }
}

fn extent((w, h): (u32, u32)) -> wgpu::Extent3d {
    wgpu::Extent3d {
        width: w,
        height: h,
        depth_or_array_layers: 1,
    }
}

impl Reflections {
    /// Whether this frame reflects (`on`), before the lighting pass: the
    /// images for a frame of `size` are made when it does.
    pub fn arm(&mut self, gpu: &Gpu, on: bool, size: (u32, u32)) {
        self.armed = on;
        if !on {
            // A later frame must not read an image older than its last.
            self.history_vp = None;
            return;
        }
        if self.images.as_ref().map(|i| i.size) != Some(size) {
            self.images = Some(images(gpu, size));
            self.history_vp = None;
        }
    }

    /// Forgets the kept frame (a new world: its image shows the old one).
    pub fn forget_history(&mut self) {
        self.history_vp = None;
    }

    /// The lighting pass's outputs for the pass (the sky's specular term
    /// and its weight): the images when armed, else 1 × 1 stand-ins.
    pub fn outputs(&mut self, gpu: &Gpu) -> [&wgpu::TextureView; 2] {
        if self.armed {
            if let Some(i) = self.images.as_ref() {
                return [&i.spec_env, &i.spec_w];
            }
        }
        let s = self.stand_ins.get_or_insert_with(|| {
            let one = || {
                use wgpu::TextureUsages as U;
                texture(
                    gpu,
                    "ssr stand-in",
                    (1, 1, 1),
                    wgpu::TextureDimension::D2,
                    LIT,
                    U::STORAGE_BINDING | U::TEXTURE_BINDING,
                )
                .create_view(&Default::default())
            };
            [one(), one()]
        });
        [&s[0], &s[1]]
    }

    /// Runs the pass over the lit `target` of the frame `cam` sees through
    /// `view_proj` (after the lighting pass) and waits for the device.
    pub fn run(
        &mut self,
        gpu: &Gpu,
        gb: &GBuffer,
        cam: &WorldCamera,
        settings: &SsrSettings,
        (target, view_proj): (&wgpu::Texture, Mat4),
    ) -> Result<PassStat, RenderError> {
        let pipes = self.pipes.get_or_insert_with(|| pipes(gpu));
        let t = std::time::Instant::now();
        let Some(img) = self.images.as_ref().filter(|_| self.armed) else {
            return Err(RenderError::Device("ssr images missing".into()));
        };
        let n = img.hiz_levels.len() as u32;
        let prev = self.history_vp.filter(|_| settings.history);
        let u = uniforms(cam, settings, n, prev);
        let ubuf = wgpu::util::DeviceExt::create_buffer_init(
            &gpu.device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("ssr uniforms"),
                contents: bytemuck::bytes_of(&u),
                usage: wgpu::BufferUsages::UNIFORM,
            },
        );
        let tv = wgpu::BindingResource::TextureView;
        let gbuf = [
            ubuf.as_entire_binding(),
            tv(&gb.views[0]),
            tv(&gb.views[1]),
            tv(&gb.views[3]),
        ];
        let hiz_group = |level: usize| {
            let mut r = gbuf.to_vec();
            // Level 0 reads nothing below it: the lit copy stands in.
            let below = if level == 0 {
                &img.lit_view
            } else {
                &img.hiz_levels[level - 1]
            };
            r.extend([tv(&img.hiz_levels[level]), tv(below)]);
            bind_group(&gpu.device, "ssr hiz", &pipes.hiz_layout, &r)
        };
        let out = target.create_view(&Default::default());
        let g0 = bind_group(&gpu.device, "ssr gbuffer", &pipes.resolve_layout[0], &gbuf);
        let g1 = bind_group(
            &gpu.device,
            "ssr resolve",
            &pipes.resolve_layout[1],
            &[
                tv(&img.hiz_view),
                tv(&img.lit_view),
                tv(&img.history_view),
                tv(&img.spec_env),
                tv(&img.spec_w),
                tv(&out),
                tv(&img.conf_view),
            ],
        );
        let size = img.size;
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        enc.copy_texture_to_texture(
            target.as_image_copy(),
            img.lit.as_image_copy(),
            extent(size),
        );
        for level in 0..n as usize {
            let (w, h) = ((size.0 >> level).max(1), (size.1 >> level).max(1));
            let g = hiz_group(level);
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(if level == 0 {
                &pipes.first
            } else {
                &pipes.down
            });
            pass.set_bind_group(0, &g, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipes.resolve);
            pass.set_bind_group(0, &g0, &[]);
            pass.set_bind_group(1, &g1, &[]);
            pass.dispatch_workgroups(size.0.div_ceil(8), size.1.div_ceil(8), 1);
        }
        if settings.history {
            enc.copy_texture_to_texture(
                target.as_image_copy(),
                img.history.as_image_copy(),
                extent(size),
            );
        }
        gpu.queue.submit([enc.finish()]);
        gpu.wait()?;
        self.history_vp = settings.history.then_some(view_proj);
        let source = if prev.is_some() {
            "the previous frame, reprojected"
        } else {
            "this frame"
        };
        Ok(PassStat {
            name: "ssr".into(),
            ran: true,
            ms: Some(t.elapsed().as_secs_f64() * 1e3),
            reason: Some(format!(
                "hi-z, {} samples, {} levels, radiance from {source}",
                settings.samples, n
            )),
        })
    }

    /// The confidence image of the last run (`None` before the first).
    pub fn read_back(&self, gpu: &Gpu) -> Result<Option<SsrImage>, RenderError> {
        let Some(img) = self.images.as_ref() else {
            return Ok(None);
        };
        let (w, h) = img.size;
        let confidence: Vec<f32> = gpu.read_texels(&img.conf, "ssr read back")?;
        Ok(Some(SsrImage {
            width: w,
            height: h,
            confidence,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use himmel_skymodel::Camera;

    #[test]
    fn uniforms_and_levels() {
        let cam = WorldCamera::new(&Camera::default());
        let s = SsrSettings {
            samples: 8,
            max_steps: 32,
            ..SsrSettings::default()
        };
        let u = uniforms(&cam, &s, 5, None);
        assert_eq!(u.q, [8, 32, 5, 0]);
        assert_eq!(u.params[0], 0.5);
        let p = uniforms(&cam, &s, 5, Some(Mat4::IDENTITY));
        assert_eq!(p.q[3], 1);
        assert_eq!(levels((160, 90)), 8);
        assert_eq!(levels((100, 20)), 7);
        assert_eq!(levels((1, 1)), 1);
        assert_eq!(std::mem::size_of::<SsrUniforms>(), 11 * 16);
    }
}
