//! Light shafts in screen space (`lighting.godrays.method` `mitchell` and
//! `sousa`, issue 15; `radial.wgsl` derives the terms):
//!
//! 1. **source** — per texel of an image `resolution_divisor` times smaller
//!    on each side (`sousa`: twice that, a quarter of the texels, the
//!    reduced target of Sousa's passes in Crysis), the unoccluded fog column's in-scattering of the Sun
//!    (the Moon by night), S = E σ_s p(θ) ∫ T_light T_view dt in closed
//!    form, and the light's mask M: 1 on sky texels, else the light's
//!    shadow-map visibility at the fog in front of the surface;
//! 2. **radial blur** of M toward the light's image, each tap weighted by
//!    the medium (the view ray's and the light's extinction at the point of
//!    the column that the tap's occluder would shadow), normalised so that
//!    with no occluder the pixel gets S exactly:
//!    * `mitchell` (GPU Gems 3, ch. 13): one pass of `samples` taps;
//!    * `sousa` (Crysis, SIGGRAPH 2007): three passes of `samples` / 3
//!      taps, each blurring the previous one's output with a stride
//!      `samples` / 3 times longer (the taps compose to (`samples` / 3)³);
//!
//! the last pass writes S · B into the shafts' image ([`super::godrays`]),
//! which the lighting pass gathers and adds as `toth`'s. The sky's light
//! in the fog is left out. The plan skips these methods when the light is
//! far off screen (`himmel_skymodel::plan::shaft_light_off_screen`).

use himmel_skymodel::{GodraysMethod, GodraysSettings, RenderError};
use wgpu::util::DeviceExt;

use super::godrays::{image, image_divisor, marched_size, MarchInputs, Shafts};
use super::pipelines::Pipelines;
use crate::gpu::{bind, bind_group, Gpu};

/// One blur pass: its taps, their stride in the finest steps, the finest
/// steps from a texel to the light's image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlurPass {
    /// Taps of the pass.
    pub taps: u32,
    /// Their stride, in the finest steps.
    pub stride: u32,
    /// The finest steps from a texel to the light's image.
    pub steps: u32,
}

/// The blur passes of `settings`' method: `mitchell` one of `samples`
/// taps; `sousa` three of n = `samples` / 3 taps with strides 1, n, n²
/// over n³ steps. Empty for `toth` and `froxel`.
pub fn blur_passes(settings: &GodraysSettings) -> Vec<BlurPass> {
    let s = settings.samples.max(1);
    match settings.method {
        GodraysMethod::Toth | GodraysMethod::Froxel => Vec::new(),
        GodraysMethod::Mitchell => vec![BlurPass {
            taps: s,
            stride: 1,
            steps: s,
        }],
        GodraysMethod::Sousa => {
            let n = (s / 3).max(1);
            let steps = n.saturating_pow(3);
            (0..3)
                .map(|k| BlurPass {
                    taps: n,
                    stride: n.pow(k),
                    steps,
                })
                .collect()
        }
    }
}

/// What the screen-space passes read.
pub struct RadialInputs<'a> {
    /// The lighting uniforms (with the shafts' part).
    pub uniforms: &'a wgpu::Buffer,
    /// The G-buffer's distance.
    pub distance: &'a wgpu::TextureView,
    /// The G-buffer's material ids.
    pub material: &'a wgpu::TextureView,
    /// The Sun's and Moon's cascades (or the 1-texel stand-in).
    pub shadows: &'a wgpu::TextureView,
    /// The shadow maps' comparison sampler.
    pub compare: &'a wgpu::Sampler,
}

struct RadialPipes {
    layout: wgpu::BindGroupLayout,
    source: wgpu::ComputePipeline,
    blur: wgpu::ComputePipeline,
}

/// The screen-space passes' pipelines and their two working images.
#[derive(Default)]
pub struct Radial {
    pipes: Option<RadialPipes>,
    work: Option<((u32, u32), [wgpu::TextureView; 2])>,
}

fn pipes(gpu: &Gpu) -> RadialPipes {
    let f = bind::float_2d();
    let layout = gpu.compute_layout(
        "radial",
        &[
            bind::uniform(),
            f,
            bind::uint_2d(),
            bind::depth_array(),
            bind::comparison(),
            f,
            bind::write_2d(wgpu::TextureFormat::Rgba32Float),
            bind::uniform(),
        ],
    );
    let module = gpu.shader(
        "radial.wgsl",
        concat!(
            include_str!("../../shaders/lighting/common.wgsl"),
            include_str!("../../shaders/lighting/shafts.wgsl"),
            include_str!("../../shaders/lighting/radial.wgsl")
        ),
    );
    let pl = gpu.pipeline_layout("radial", &[&layout]);
    RadialPipes {
        source: gpu.compute_pipeline(&pl, &module, "source"),
        blur: gpu.compute_pipeline(&pl, &module, "blur"),
        layout,
    }
}

impl Radial {
    /// Runs the passes of `settings` with the march's inputs into the
    /// shafts' image of `shafts`.
    pub fn run_on(
        &mut self,
        gpu: &Gpu,
        pipes: &Pipelines,
        march: &MarchInputs,
        settings: &GodraysSettings,
        frame: (u32, u32),
        shafts: &mut Shafts,
    ) -> Result<(), RenderError> {
        let inputs = RadialInputs {
            uniforms: march.uniforms,
            distance: march.distance,
            material: march.material,
            shadows: march.shadows,
            compare: &pipes.compare,
        };
        let size = marched_size(frame.0, frame.1, image_divisor(settings));
        self.run(gpu, &inputs, settings, frame, shafts.output(gpu, size))
    }

    /// Runs the source and the blur passes of `settings` for a frame of
    /// `w` × `h` into `out` (the shafts' image, of
    /// [`marched_size`]), waits for the device.
    pub fn run(
        &mut self,
        gpu: &Gpu,
        inputs: &RadialInputs,
        settings: &GodraysSettings,
        (w, h): (u32, u32),
        out: &wgpu::TextureView,
    ) -> Result<(), RenderError> {
        let passes = blur_passes(settings);
        if passes.is_empty() {
            return Err(RenderError::Device(
                "the screen-space shafts run for mitchell and sousa only".into(),
            ));
        }
        let size = marched_size(w, h, image_divisor(settings));
        if self.work.as_ref().map(|x| x.0) != Some(size) {
            self.work = Some((size, [image(gpu, size), image(gpu, size)]));
        }
        let pipes = self.pipes.get_or_insert_with(|| pipes(gpu));
        let Some((_, work)) = self.work.as_ref() else {
            return Err(RenderError::Device("radial images missing".into()));
        };
        let group = |input: &wgpu::TextureView, output: &wgpu::TextureView, q: &wgpu::Buffer| {
            let tv = wgpu::BindingResource::TextureView;
            bind_group(
                &gpu.device,
                "radial",
                &pipes.layout,
                &[
                    inputs.uniforms.as_entire_binding(),
                    tv(inputs.distance),
                    tv(inputs.material),
                    tv(inputs.shadows),
                    wgpu::BindingResource::Sampler(inputs.compare),
                    tv(input),
                    tv(output),
                    q.as_entire_binding(),
                ],
            )
        };
        let params = |p: BlurPass, last: bool| {
            let q: [u32; 4] = [p.taps, p.stride, p.steps, last as u32];
            gpu.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("radial pass"),
                    contents: bytemuck::cast_slice(&q),
                    usage: wgpu::BufferUsages::UNIFORM,
                })
        };
        let groups = (size.0.div_ceil(8), size.1.div_ceil(8), 1);
        // source → work[0]; the blurs alternate work[0] ↔ work[1], the
        // last into `out`.
        let mut bound = vec![(
            &pipes.source,
            group(&work[1], &work[0], &params(passes[0], false)),
        )];
        for (k, p) in passes.iter().enumerate() {
            let last = k + 1 == passes.len();
            let input = &work[k % 2];
            let output = if last { out } else { &work[(k + 1) % 2] };
            bound.push((&pipes.blur, group(input, output, &params(*p, last))));
        }
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        {
            // One compute pass: wgpu orders each dispatch after the writes
            // of the one before it.
            let mut pass = enc.begin_compute_pass(&Default::default());
            for (pipeline, g) in &bound {
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, g, &[]);
                pass.dispatch_workgroups(groups.0, groups.1, groups.2);
            }
        }
        gpu.queue.submit([enc.finish()]);
        gpu.wait()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sousa_spends_mitchells_taps_in_three_growing_passes() {
        let mut s = GodraysSettings {
            method: GodraysMethod::Mitchell,
            samples: 63,
            ..GodraysSettings::default()
        };
        let m = blur_passes(&s);
        assert_eq!(
            m,
            vec![BlurPass {
                taps: 63,
                stride: 1,
                steps: 63
            }]
        );
        s.method = GodraysMethod::Sousa;
        let p = blur_passes(&s);
        assert_eq!(p.iter().map(|p| p.taps).sum::<u32>(), 63);
        assert_eq!(p.iter().map(|p| p.stride).collect::<Vec<_>>(), [1, 21, 441]);
        // The last pass's last tap reaches (n − 1) n² of the n³ steps.
        assert!(p.iter().all(|p| p.steps == 21 * 21 * 21));
        s.method = GodraysMethod::Toth;
        assert!(blur_passes(&s).is_empty());
    }
}
