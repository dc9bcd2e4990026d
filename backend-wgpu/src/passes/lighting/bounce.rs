//! Near-field indirect light (`lighting.ao.bounce`, issue 16): one diffuse
//! bounce of the lit image from the surfaces on screen
//! (`shaders/lighting/bounce.wgsl`), added to the frame's target after the
//! lighting pass and before the reflections and the temporal filter.
//!
//! It runs with the `ao` pass (it needs the sky's light, as AO does) when
//! `lighting.ao.bounce` is true; `--stats` names it `bounce` and says why
//! it did not run where it was asked for. What it adds is the light that
//! the Sun, the Moon and the sky put on the visible surfaces within the
//! radius, reflected once by the pixel's diffuse albedo — the floor's
//! sunlight on the shaded wall beside it. The lit image it reads already
//! holds the aerial perspective between each surface and the camera; at
//! the distances of near-field light (metres) that is a fraction of a per
//! cent.

use himmel_skymodel::renderer::PassStat;
use himmel_skymodel::{AoSettings, RenderError};

use super::resources::{texture, GBuffer};
use super::view::{CameraBlock, WorldCamera};
use super::WorldInputs;
use crate::gpu::{bind, bind_group, Gpu};

/// The pass's uniforms (`Bounce` in bounce.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct BounceUniforms {
    cam: CameraBlock,
    params: [f32; 4],
    q: [u32; 4],
}

struct Pipes {
    layout: wgpu::BindGroupLayout,
    gather: wgpu::ComputePipeline,
    blur: wgpu::ComputePipeline,
}

struct Images {
    size: (u32, u32),
    /// The copy of the lit target.
    lit: wgpu::Texture,
    /// The raw (unblurred) bounce.
    raw: wgpu::TextureView,
}

/// The bounce pass and its images, kept between frames.
#[derive(Default)]
pub struct Bounce {
    pipes: Option<Pipes>,
    images: Option<Images>,
}

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

fn pipes(gpu: &Gpu) -> Pipes {
    let f = bind::float_2d();
    let layout = gpu.compute_layout(
        "bounce",
        &[
            bind::uniform(),
            f,
            f,
            f,
            bind::uint_2d(),
            f,
            bind::write_2d(FORMAT),
            f,
        ],
    );
    let module = gpu.shader(
        "bounce.wgsl",
        concat!(
            include_str!("../../shaders/lighting/screen.wgsl"),
            include_str!("../../shaders/lighting/bounce.wgsl")
        ),
    );
    let pl = gpu.pipeline_layout("bounce", &[&layout]);
    Pipes {
        gather: gpu.compute_pipeline(&pl, &module, "gather"),
        blur: gpu.compute_pipeline(&pl, &module, "blur"),
        layout,
    }
}

/// The uniforms of a frame seen by `cam` with radius `radius_m`.
fn uniforms(cam: &WorldCamera, s: &AoSettings, radius_m: f32) -> BounceUniforms {
    BounceUniforms {
        cam: cam.block(),
        params: [radius_m, 0.0, cam.jitter.x, cam.jitter.y],
        q: [
            s.bounce_samples.max(1),
            s.bounce_steps.max(1),
            cam.frame,
            s.blur_px,
        ],
    }
}

fn skipped(why: &str) -> Option<PassStat> {
    Some(PassStat {
        name: "bounce".into(),
        ran: false,
        ms: None,
        reason: Some(why.into()),
    })
}

/// Why the pass does not run for this frame (`None`: it runs). `extent`:
/// the world's bounding-box diagonal, metres (`None`: no geometry).
pub fn decide(inputs: &WorldInputs, extent: Option<f32>) -> Option<&'static str> {
    let up = |l: &Option<himmel_skymodel::frame::DirectLight>| {
        l.is_some_and(|l| l.dir_world().y > 0.0 && l.rgb.iter().any(|&c| c > 0.0))
    };
    if !inputs.ao {
        Some("needs the ao pass (--effects ao with the atmosphere)")
    } else if extent.is_none() {
        Some("the world has no geometry")
    } else if inputs.env.is_none() && !up(&inputs.direct.sun) && !up(&inputs.direct.moon) {
        Some("nothing lights the world")
    } else {
        None
    }
}

impl Bounce {
    /// Runs the pass when `lighting.ao.bounce` asks for it: reads the lit
    /// `target`, adds the bounce into it. Returns its `--stats` entry:
    /// "not requested" beside a running `ao` pass when the key is false,
    /// `None` when neither is asked for.
    pub fn step(
        &mut self,
        gpu: &Gpu,
        inputs: &WorldInputs,
        gb: &GBuffer,
        extent: Option<f32>,
        (cam, target): (&WorldCamera, &wgpu::Texture),
    ) -> Result<Option<PassStat>, RenderError> {
        let s = &inputs.scene.lighting.ao;
        if !s.bounce {
            return Ok(inputs.ao.then(|| skipped("not requested")).flatten());
        }
        if let Some(why) = decide(inputs, extent) {
            return Ok(skipped(why));
        }
        let radius = s.bounce_radius_for(extent.unwrap_or(0.0) as f64) as f32;
        let pipes = self.pipes.get_or_insert_with(|| pipes(gpu));
        let t = std::time::Instant::now();
        let size = (cam.width, cam.height);
        if self.images.as_ref().map(|i| i.size) != Some(size) {
            let image = |label, usage| {
                let dims = (size.0, size.1, 1);
                texture(gpu, label, dims, wgpu::TextureDimension::D2, FORMAT, usage)
            };
            let sampled = wgpu::TextureUsages::TEXTURE_BINDING;
            self.images = Some(Images {
                size,
                lit: image("bounce lit", sampled | wgpu::TextureUsages::COPY_DST),
                raw: image("bounce raw", sampled | wgpu::TextureUsages::STORAGE_BINDING)
                    .create_view(&Default::default()),
            });
        }
        let Some(img) = self.images.as_ref() else {
            return Err(RenderError::Device("bounce images missing".into()));
        };
        let u = uniforms(cam, s, radius);
        let ubuf = wgpu::util::DeviceExt::create_buffer_init(
            &gpu.device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("bounce uniforms"),
                contents: bytemuck::bytes_of(&u),
                usage: wgpu::BufferUsages::UNIFORM,
            },
        );
        let lit_view = img.lit.create_view(&Default::default());
        let out = target.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            ..Default::default()
        });
        let tv = wgpu::BindingResource::TextureView;
        let group = |out, raw| {
            bind_group(
                &gpu.device,
                "bounce",
                &pipes.layout,
                &[
                    ubuf.as_entire_binding(),
                    tv(&gb.views[0]),
                    tv(&gb.views[1]),
                    tv(&gb.views[2]),
                    tv(&gb.views[3]),
                    tv(&lit_view),
                    tv(out),
                    tv(raw),
                ],
            )
        };
        let first = group(&img.raw, &lit_view);
        let second = group(&out, &img.raw);
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        enc.copy_texture_to_texture(
            target.as_image_copy(),
            img.lit.as_image_copy(),
            wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
        );
        for (pipe, g) in [(&pipes.gather, &first), (&pipes.blur, &second)] {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipe);
            pass.set_bind_group(0, g, &[]);
            pass.dispatch_workgroups(size.0.div_ceil(8), size.1.div_ceil(8), 1);
        }
        gpu.queue.submit([enc.finish()]);
        gpu.wait()?;
        Ok(Some(PassStat {
            name: "bounce".into(),
            ran: true,
            ms: Some(t.elapsed().as_secs_f64() * 1e3),
            reason: Some(format!(
                "{} directions × {} steps, radius {radius:.2} m, blur {} px",
                u.q[0], u.q[1], u.q[3]
            )),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use himmel_skymodel::frame::{DirectLight, DirectLights};
    use himmel_skymodel::{Camera, Scene};

    /// The inputs of a frame without the sky's light: the `ao` pass as
    /// `ao`, the Sun at ENU direction `sun` (if any).
    fn inputs(scene: &Scene, ao: bool, sun: Option<DVec3>) -> WorldInputs<'_> {
        let light = |d: DVec3| DirectLight {
            dir_enu: d.normalize(),
            rgb: [1e5; 3],
            angular_radius: 0.0047,
        };
        WorldInputs {
            scene,
            direct: DirectLights {
                sun: sun.map(light),
                moon: None,
            },
            env: None,
            env_changed: false,
            air: None,
            shadows: false,
            godrays: false,
            clouds: None,
            ao,
            ssr: false,
            temporal: false,
        }
    }

    #[test]
    fn it_runs_only_with_ao_geometry_and_light() {
        let s = Scene::default();
        let high = Some(DVec3::new(0.0, -0.6, 0.8));
        let low = Some(DVec3::new(0.0, -0.6, -0.1));
        assert!(decide(&inputs(&s, false, high), Some(10.0)).is_some_and(|w| w.contains("ao pass")));
        assert_eq!(
            decide(&inputs(&s, true, high), None),
            Some("the world has no geometry")
        );
        // No sky light and the Sun below the horizon: nothing is lit, so
        // there is nothing to bounce.
        assert_eq!(
            decide(&inputs(&s, true, low), Some(10.0)),
            Some("nothing lights the world")
        );
        assert_eq!(
            decide(&inputs(&s, true, None), Some(10.0)),
            Some("nothing lights the world")
        );
        assert_eq!(decide(&inputs(&s, true, high), Some(10.0)), None);
    }

    #[test]
    fn uniforms_carry_the_quality_and_the_frame() {
        let mut cam = WorldCamera::new(&Camera::default());
        cam.frame = 7;
        let s = AoSettings {
            bounce_samples: 24,
            bounce_steps: 9,
            blur_px: 3,
            ..AoSettings::default()
        };
        let u = uniforms(&cam, &s, 3.5);
        assert_eq!(u.q, [24, 9, 7, 3]);
        assert_eq!(u.params[0], 3.5);
        assert_eq!(std::mem::size_of::<BounceUniforms>(), 6 * 16);
    }
}
