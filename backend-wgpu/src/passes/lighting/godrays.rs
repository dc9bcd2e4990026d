//! Light shafts (`lighting.godrays`, issue 15): the fog's single scattering
//! of the Sun, the Moon and the sky along each view ray.
//!
//! `toth` (Tóth & Umenhoffer 2009, `godrays.wgsl`): every view ray is
//! marched through the fog to the surface the G-buffer shows, with the
//! Sun's and Moon's shadow maps looked up per step, on an image
//! `resolution_divisor` times smaller on each side, the march's start
//! offset interleaved over N × N texels; the lighting pass (`shade.wgsl`)
//! gathers it back by depth and adds it after the view ray's extinction.
//! On a reduced image a `refine` pass makes the full-resolution image
//! first: each pixel takes that gather, except where the texels around it
//! show the sky or another surface, where its own view ray is marched (the
//! reduced image cannot say what that ray sees); the lighting pass then
//! reads the refined image as it is.
//! The sky's part comes from the environment light's cells above the
//! horizon (each one's ∫L dΩ, the phase at its direction), each seen
//! through its visibility map from the point in the fog and attenuated
//! along its own direction to the fog's top; a step looks up a share of
//! the cells in turn (every cell over the march), the pixel's interleaved
//! set as the sky pass's.

use himmel_skymodel::{FogSpec, GodraysMethod, GodraysSettings, RenderError};

use super::pipelines::Pipelines;
use super::resources::texture;
use crate::gpu::{bind_group, Gpu};

/// The marched in-scattering (rgba32float: rgb, cd/m²) and its stand-in
/// when the pass does not run.
#[derive(Default)]
pub struct Shafts {
    image: Option<((u32, u32), wgpu::TextureView)>,
    refined: Option<((u32, u32), wgpu::TextureView)>,
    /// The pixels `refine` leaves to `march_list` (a count, then one u32
    /// per pixel of the frame).
    todo: Option<((u32, u32), wgpu::Buffer)>,
    /// Whether the last march refined its image (the lighting pass reads
    /// `refined` then).
    use_refined: bool,
    stand_in: Option<wgpu::TextureView>,
}

/// The size of the marched image for a frame of `w` × `h`.
pub fn marched_size(w: u32, h: u32, divisor: u32) -> (u32, u32) {
    let d = divisor.max(1);
    (w.div_ceil(d).max(1), h.div_ceil(d).max(1))
}

/// The divisor of the shafts' image for `settings`: the requested
/// `resolution_divisor`, except that `sousa` works on half of it on each
/// side (a quarter of the texels: the reduced target Sousa's three passes
/// ran on in Crysis, which is where the method's saving over Mitchell's
/// one long pass lies) and `froxel` writes a full-resolution image.
pub fn image_divisor(settings: &GodraysSettings) -> u32 {
    let d = settings.resolution_divisor.max(1);
    match settings.method {
        GodraysMethod::Froxel => 1,
        GodraysMethod::Sousa => 2 * d,
        GodraysMethod::Toth | GodraysMethod::Mitchell => d,
    }
}

/// An rgba32float image the shafts' passes write and read.
pub fn image(gpu: &Gpu, (w, h): (u32, u32)) -> wgpu::TextureView {
    texture(
        gpu,
        "shafts",
        (w, h, 1),
        wgpu::TextureDimension::D2,
        wgpu::TextureFormat::Rgba32Float,
        wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
    )
    .create_view(&Default::default())
}

/// The shafts' uniforms (`shafts`, `shaft_q` in common.wgsl): off when
/// the pass does not run.
pub fn uniforms(
    fog: Option<&FogSpec>,
    settings: &GodraysSettings,
    on: bool,
) -> ([f32; 4], [u32; 4]) {
    let Some(f) = fog.filter(|_| on) else {
        return ([0.0; 4], [0, 1, 1, 0]);
    };
    let (kind, g) = f.phase.code();
    (
        [
            f.scattering_per_m as f32,
            kind as f32,
            g as f32,
            if refines(settings) { 2.0 } else { 1.0 },
        ],
        [
            settings.steps.max(1),
            // The screen-space methods and `froxel` have no interleaved
            // offsets: their image is gathered bilinearly (shade.wgsl);
            // `froxel`'s is at full resolution.
            if settings.method == GodraysMethod::Toth {
                settings.interleave.max(1)
            } else {
                1
            },
            image_divisor(settings),
            settings.sky_cells,
        ],
    )
}

/// Whether `toth`'s reduced image is refined to full resolution (its
/// shafts' uniform w is then 2: the lighting pass reads it pixel by pixel).
pub fn refines(settings: &GodraysSettings) -> bool {
    settings.method == GodraysMethod::Toth && settings.resolution_divisor > 1
}

/// What the march reads.
pub struct MarchInputs<'a> {
    /// The lighting uniforms (with the shafts' part).
    pub uniforms: &'a wgpu::Buffer,
    /// The G-buffer's distance and material views.
    pub distance: &'a wgpu::TextureView,
    /// The G-buffer's material ids.
    pub material: &'a wgpu::TextureView,
    /// The Sun's and Moon's cascades (or the 1-texel stand-in).
    pub shadows: &'a wgpu::TextureView,
    /// The sky's cells (env.rs).
    pub cells: &'a wgpu::Buffer,
    /// Their visibility maps' matrices.
    pub cell_view: &'a wgpu::Buffer,
    /// Their visibility maps (or the stand-in).
    pub visibility: &'a wgpu::TextureView,
}

impl Shafts {
    /// Marches the frame's view rays into the marched image (the frame is
    /// `w` × `h`), waits for the device.
    pub fn march(
        &mut self,
        gpu: &Gpu,
        pipes: &Pipelines,
        inputs: &MarchInputs,
        (w, h): (u32, u32),
        divisor: u32,
    ) -> Result<(), RenderError> {
        let size = marched_size(w, h, divisor);
        let refine = divisor > 1;
        if refine && self.refined.as_ref().map(|i| i.0) != Some((w, h)) {
            self.refined = Some(((w, h), image(gpu, (w, h))));
        }
        let pixels = u64::from(w) * u64::from(h);
        if self.todo.as_ref().map(|t| t.0) != Some((w, h)) {
            let buf = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("shafts to march"),
                size: 4 * (1 + pixels),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            self.todo = Some(((w, h), buf));
        }
        self.output(gpu, size);
        let stand_in = self
            .stand_in
            .get_or_insert_with(|| image(gpu, (1, 1)))
            .clone();
        let (Some((_, low)), refined, Some((_, todo))) = (
            self.image.as_ref(),
            self.refined.as_ref(),
            self.todo.as_ref(),
        ) else {
            return Err(RenderError::Device("the shafts' image is missing".into()));
        };
        let group = |out: &wgpu::TextureView, input: &wgpu::TextureView| {
            let tv = wgpu::BindingResource::TextureView;
            bind_group(
                &gpu.device,
                "godrays",
                &pipes.godrays_layout,
                &[
                    inputs.uniforms.as_entire_binding(),
                    tv(inputs.distance),
                    tv(inputs.material),
                    tv(inputs.shadows),
                    wgpu::BindingResource::Sampler(&pipes.compare),
                    tv(out),
                    inputs.cells.as_entire_binding(),
                    inputs.cell_view.as_entire_binding(),
                    tv(inputs.visibility),
                    tv(input),
                    todo.as_entire_binding(),
                ],
            )
        };
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        enc.clear_buffer(todo, 0, Some(4));
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipes.godrays[0]);
            pass.set_bind_group(0, &group(low, &stand_in), &[]);
            pass.dispatch_workgroups(size.0.div_ceil(8), size.1.div_ceil(8), 1);
            if let Some((_, fine)) = refined.filter(|_| refine) {
                let g = group(fine, low);
                pass.set_pipeline(&pipes.godrays[1]);
                pass.set_bind_group(0, &g, &[]);
                pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
                // One thread per pixel that may be left (64 a group, rows
                // of at most 65 535 groups); the surplus returns at once.
                let groups = pixels.div_ceil(64) as u32;
                let x = groups.min(65_535);
                pass.set_pipeline(&pipes.godrays[2]);
                pass.dispatch_workgroups(x, groups.div_ceil(x), 1);
            }
        }
        gpu.queue.submit([enc.finish()]);
        self.use_refined = refine;
        gpu.wait()
    }

    /// The shafts' image of `size` (kept while the size holds), which
    /// the march or the screen-space blur (radial.rs) writes.
    pub fn output(&mut self, gpu: &Gpu, size: (u32, u32)) -> &wgpu::TextureView {
        if self.image.as_ref().map(|i| i.0) != Some(size) {
            self.image = None;
        }
        self.use_refined = false;
        &self.image.get_or_insert_with(|| (size, image(gpu, size))).1
    }

    /// The marched image of the last march, or (`on` false) a 1 × 1
    /// stand-in the lighting pass binds and does not read.
    pub fn view(&mut self, gpu: &Gpu, on: bool) -> &wgpu::TextureView {
        if on {
            let last = if self.use_refined {
                self.refined.as_ref()
            } else {
                self.image.as_ref()
            };
            if let Some((_, v)) = last {
                return v;
            }
        }
        self.stand_in.get_or_insert_with(|| image(gpu, (1, 1)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use himmel_skymodel::FogPhase;

    #[test]
    fn the_marched_image_rounds_up() {
        assert_eq!(marched_size(320, 180, 1), (320, 180));
        assert_eq!(marched_size(321, 181, 2), (161, 91));
        assert_eq!(marched_size(5, 3, 8), (1, 1));
    }

    #[test]
    fn uniforms_carry_the_medium_and_the_quality() {
        let f = FogSpec {
            scattering_per_m: 0.05,
            phase: FogPhase::Hg(0.4),
            ..FogSpec::default()
        };
        let s = GodraysSettings::default();
        let (a, c) = uniforms(Some(&f), &s, true);
        // The default `toth` (÷2) is refined: w = 2.
        assert_eq!(a, [0.05, 2.0, 0.4, 2.0]);
        let full = GodraysSettings {
            resolution_divisor: 1,
            ..s
        };
        assert_eq!(uniforms(Some(&f), &full, true).0[3], 1.0);
        assert_eq!(
            c,
            [s.steps, s.interleave, s.resolution_divisor, s.sky_cells]
        );
        let (a, _) = uniforms(Some(&f), &s, false);
        assert_eq!(a[3], 0.0);
        // `froxel` writes a full-resolution image: no interleave, no
        // divisor in the gather.
        let s = GodraysSettings {
            method: GodraysMethod::Froxel,
            ..s
        };
        let (_, c) = uniforms(Some(&f), &s, true);
        assert_eq!(c, [s.steps, 1, 1, s.sky_cells]);
    }
}
