//! The temporal filter (`lighting.temporal`, issue 16;
//! `shaders/lighting/temporal.wgsl`), the last of the lighting passes:
//!
//! 1. before the G-buffer, [`Temporal::begin`] gives the frame its index in
//!    the run of filtered frames and its sub-pixel jitter (Halton 2, 3
//!    over [`JITTER_PERIOD`] frames; none on the first frame, which has no
//!    history to average with); the world passes draw through the
//!    jittered projection (`WorldCamera::jitter`), the G-buffer takes the
//!    jitter out of its velocity, and AO, SSR and the shadows' disks turn
//!    their per-pixel noise with the index (`WorldCamera::frame`);
//! 2. after the lighting passes, the resolve blends each world pixel with
//!    the history reprojected through the velocity, rejected where the
//!    surface is not the same (disocclusion) and clipped to the
//!    neighbourhood's variance box (temporal.wgsl), into the target and the
//!    next history (ping-pong: colour, and distance + frame count).
//!
//! The sky pixels of the target are never written: they stay what the sky
//! passes drew, unjittered (the sky is not part of the world's jitter). A
//! silhouette against the sky is therefore anti-aliased on its world side
//! only. The history is kept while the image size stays and each frame
//! runs the pass; a new world keeps it too (the disocclusion test and the
//! clipping are what reject what moved).

use glam::{Vec2, Vec3};
use himmel_skymodel::renderer::PassStat;
use himmel_skymodel::{RenderError, TemporalSettings};

use super::resources::{texture, GBuffer};
use super::view::{CameraBlock, WorldCamera};
use crate::gpu::{bind, bind_group, Gpu};

/// Frames after which the jitter sequence repeats (2⁶: the Halton base-2
/// coordinate then covers the pixel in 64 even steps).
pub const JITTER_PERIOD: u32 = 64;

/// Frames after which the noise turns repeat (`WorldCamera::frame` is the
/// index modulo this): the shaders' per-frame offsets (5.588238 px a
/// frame) stay exact in f32.
pub const NOISE_PERIOD: u32 = 1024;

/// The pass's uniforms (`Temporal` in temporal.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct TemporalUniforms {
    cam: CameraBlock,
    prev_eye: [f32; 4],
    jitter: [f32; 4],
    q: [u32; 4],
}

/// The filter's state of the last frame, read back.
#[derive(Debug, Clone, PartialEq)]
pub struct TemporalImage {
    /// Width, px.
    pub width: u32,
    /// Height, px.
    pub height: u32,
    /// The G-buffer's distance from the eye per pixel (m; 0 on the sky),
    /// row-major.
    pub distance: Vec<f32>,
    /// The frames each pixel's history holds (1: this frame alone — the
    /// first frame, a disoccluded or a sky pixel).
    pub frames: Vec<f32>,
    /// The sub-pixel jitter the frame was drawn with, px (x right, y down).
    pub jitter: [f32; 2],
}

struct Images {
    size: (u32, u32),
    current: wgpu::Texture,
    current_view: wgpu::TextureView,
    colour_views: [wgpu::TextureView; 2],
    aux: [wgpu::Texture; 2],
    aux_views: [wgpu::TextureView; 2],
}

/// The temporal pass, its pipeline and its history, kept between frames.
#[derive(Default)]
pub struct Temporal {
    pipe: Option<(wgpu::BindGroupLayout, wgpu::ComputePipeline)>,
    images: Option<Images>,
    /// Which of the ping-pong pair holds the history (the last output).
    latest: usize,
    /// The index of this frame in the run of filtered frames.
    frame: u32,
    /// This frame's jitter, px.
    jitter: Vec2,
    /// The eye of the frame in the history (`None`: no history).
    prev_eye: Option<Vec3>,
    /// What the last frame's scene and lights were.
    last_run: Option<RunKey>,
}

/// The Sun's or Moon's largest step between two frames of one run, degrees
/// (the Sun moves 0.1° in about 24 s): a time-lapse whose light jumps
/// further starts a new run each frame, its frames each as rendered.
pub const LIGHT_STEP_DEG: f32 = 0.1;

/// What a frame must share with the last one for the history to hold: the
/// scene apart from its time and camera (what a sequence steps), and the
/// Sun's and Moon's directions within [`LIGHT_STEP_DEG`]. Another scene
/// on the same renderer starts a new run rather than blend with the last.
#[derive(Debug, Clone, PartialEq)]
pub struct RunKey {
    scene: himmel_skymodel::Scene,
    lights: [Option<Vec3>; 2],
}

impl RunKey {
    /// The key of a frame of `scene` lit from `sun` and `moon` (unit
    /// vectors towards them; `None`: not lighting the world).
    pub fn of(scene: &himmel_skymodel::Scene, sun: Option<Vec3>, moon: Option<Vec3>) -> Self {
        let mut scene = scene.clone();
        scene.time = Default::default();
        scene.camera = Default::default();
        RunKey {
            scene,
            lights: [sun, moon],
        }
    }

    /// Whether a frame of `self` continues a run whose last frame was `last`.
    pub fn continues(&self, last: &RunKey) -> bool {
        let cos_step = LIGHT_STEP_DEG.to_radians().cos();
        self.scene == last.scene
            && self
                .lights
                .iter()
                .zip(&last.lights)
                .all(|(a, b)| match (a, b) {
                    (Some(a), Some(b)) => a.dot(*b) >= cos_step,
                    (None, None) => true,
                    _ => false,
                })
    }
}

/// The radical inverse of `i` in `base`: the Halton sequence's coordinate.
pub fn halton(mut i: u32, base: u32) -> f32 {
    let (mut f, mut r) = (1.0f32, 0.0f32);
    while i > 0 {
        f /= base as f32;
        r += f * (i % base) as f32;
        i /= base;
    }
    r
}

/// The jitter of frame `k` of a run, px in [−0.5, 0.5)²: none for the
/// first frame; then Halton (2, 3) at indices 1 … [`JITTER_PERIOD`],
/// repeating.
pub fn jitter(k: u32) -> Vec2 {
    if k == 0 {
        return Vec2::ZERO;
    }
    let i = (k - 1) % JITTER_PERIOD + 1;
    Vec2::new(halton(i, 2) - 0.5, halton(i, 3) - 0.5)
}

const LIT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const AUX: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

fn pipe(gpu: &Gpu) -> (wgpu::BindGroupLayout, wgpu::ComputePipeline) {
    let f = bind::float_2d();
    let layout = gpu.compute_layout(
        "temporal",
        &[
            bind::uniform(),
            f,
            bind::uint_2d(),
            f,
            f,
            f,
            f,
            bind::write_2d(LIT),
            bind::write_2d(LIT),
            bind::write_2d(AUX),
            f,
        ],
    );
    let module = gpu.shader(
        "temporal.wgsl",
        include_str!("../../shaders/lighting/temporal.wgsl"),
    );
    let pl = gpu.pipeline_layout("temporal", &[&layout]);
    let pipeline = gpu.compute_pipeline(&pl, &module, "resolve");
    (layout, pipeline)
}

fn images(gpu: &Gpu, size: (u32, u32)) -> Images {
    use wgpu::TextureUsages as U;
    let d2 = wgpu::TextureDimension::D2;
    let make = |label, format, usage| texture(gpu, label, (size.0, size.1, 1), d2, format, usage);
    let view = |t: &wgpu::Texture| t.create_view(&Default::default());
    let rw = U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC;
    let current = make("temporal current", LIT, U::TEXTURE_BINDING | U::COPY_DST);
    let colour = [0, 1].map(|_| make("temporal history", LIT, rw));
    let aux = [0, 1].map(|_| make("temporal history aux", AUX, rw));
    Images {
        size,
        current_view: view(&current),
        current,
        colour_views: [view(&colour[0]), view(&colour[1])],
        aux_views: [view(&aux[0]), view(&aux[1])],
        aux,
    }
}

fn uniforms(cam: &WorldCamera, s: &TemporalSettings, prev_eye: Option<Vec3>) -> TemporalUniforms {
    let v4 = |v: Vec3, w: f32| [v.x, v.y, v.z, w];
    TemporalUniforms {
        cam: cam.block(),
        prev_eye: prev_eye.map_or([0.0; 4], |e| v4(e, 1.0)),
        jitter: [
            cam.jitter.x,
            cam.jitter.y,
            s.variance_gamma as f32,
            s.depth_tolerance as f32,
        ],
        q: [s.max_frames.max(1), 0, 0, 0],
    }
}

/// The G-buffer camera's `size` (gbuffer.wgsl): the image's width and
/// height, px, and the jitter the frame is drawn with.
pub fn gbuffer_size(cam: &WorldCamera) -> [f32; 4] {
    let (w, h) = (cam.width as f32, cam.height as f32);
    [w, h, cam.jitter.x, cam.jitter.y]
}

fn extent((w, h): (u32, u32)) -> wgpu::Extent3d {
    wgpu::Extent3d {
        width: w,
        height: h,
        depth_or_array_layers: 1,
    }
}

impl Temporal {
    /// Before a frame of `cam`: whether the pass runs (`on`); sets the
    /// camera's jitter (px) and index in the run (both 0 when it does not
    /// run, or on a run's first frame). A frame without the pass, or of
    /// another size, ends the run and drops the history.
    /// A frame whose scene or lights do not continue the last frame's
    /// ([`RunKey::continues`]) starts a new run.
    pub fn begin(&mut self, on: bool, s: &TemporalSettings, cam: &mut WorldCamera, run: RunKey) {
        if self
            .last_run
            .as_ref()
            .is_some_and(|last| !run.continues(last))
        {
            self.prev_eye = None;
        }
        self.last_run = Some(run);
        (cam.jitter, cam.frame) = self.next(on, s, (cam.width, cam.height));
    }

    fn next(&mut self, on: bool, s: &TemporalSettings, size: (u32, u32)) -> (Vec2, u32) {
        if !on || self.images.as_ref().is_some_and(|i| i.size != size) {
            self.frame = 0;
            self.prev_eye = None;
            self.images = None;
        }
        if !on {
            self.jitter = Vec2::ZERO;
            return (Vec2::ZERO, 0);
        }
        if self.prev_eye.is_none() {
            self.frame = 0;
        }
        self.jitter = if s.jitter {
            jitter(self.frame)
        } else {
            Vec2::ZERO
        };
        (self.jitter, self.frame % NOISE_PERIOD)
    }

    /// Blends the lit `target` of the frame `cam` sees (its G-buffer `gb`)
    /// with the history, writes the result into `target` and keeps it;
    /// waits for the device. Returns the pass's `--stats` entry.
    pub fn run(
        &mut self,
        gpu: &Gpu,
        gb: &GBuffer,
        cam: &WorldCamera,
        settings: &TemporalSettings,
        target: &wgpu::Texture,
    ) -> Result<PassStat, RenderError> {
        let t = std::time::Instant::now();
        let size = (cam.width, cam.height);
        if self.images.as_ref().map(|i| i.size) != Some(size) {
            self.images = Some(images(gpu, size));
            self.prev_eye = None;
        }
        let (layout, pipeline) = self.pipe.get_or_insert_with(|| pipe(gpu));
        let Some(img) = self.images.as_ref() else {
            return Err(RenderError::Device("temporal images missing".into()));
        };
        let u = uniforms(cam, settings, self.prev_eye);
        let ubuf = wgpu::util::DeviceExt::create_buffer_init(
            &gpu.device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("temporal uniforms"),
                contents: bytemuck::bytes_of(&u),
                usage: wgpu::BufferUsages::UNIFORM,
            },
        );
        let (read, write) = (self.latest, 1 - self.latest);
        let out = target.create_view(&Default::default());
        let tv = wgpu::BindingResource::TextureView;
        let group = bind_group(
            &gpu.device,
            "temporal",
            layout,
            &[
                ubuf.as_entire_binding(),
                tv(&gb.views[0]),
                tv(&gb.views[3]),
                tv(&gb.views[4]),
                tv(&img.current_view),
                tv(&img.colour_views[read]),
                tv(&img.aux_views[read]),
                tv(&out),
                tv(&img.colour_views[write]),
                tv(&img.aux_views[write]),
                tv(&gb.views[1]),
            ],
        );
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        enc.copy_texture_to_texture(
            target.as_image_copy(),
            img.current.as_image_copy(),
            extent(size),
        );
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(size.0.div_ceil(8), size.1.div_ceil(8), 1);
        }
        gpu.queue.submit([enc.finish()]);
        gpu.wait()?;
        let first = self.prev_eye.is_none();
        self.latest = write;
        self.prev_eye = Some(cam.eye);
        let k = self.frame;
        self.frame = self.frame.saturating_add(1);
        let reason = if first {
            "first frame: no history (this frame as rendered, unjittered)".to_string()
        } else {
            format!(
                "frame {k}: jitter ({:+.3}, {:+.3}) px, history of up to {} frames",
                self.jitter.x, self.jitter.y, settings.max_frames
            )
        };
        Ok(PassStat {
            name: "temporal".into(),
            ran: true,
            ms: Some(t.elapsed().as_secs_f64() * 1e3),
            reason: Some(reason),
        })
    }

    /// The distance and frame count of the last frame's history (`None`
    /// before the pass first ran).
    pub fn read_back(&self, gpu: &Gpu) -> Result<Option<TemporalImage>, RenderError> {
        let Some(img) = self.images.as_ref().filter(|_| self.prev_eye.is_some()) else {
            return Ok(None);
        };
        let (w, h) = img.size;
        let aux: Vec<[f32; 4]> = gpu.read_texels(&img.aux[self.latest], "temporal read back")?;
        let distance = aux.iter().map(|v| v[0]).collect();
        let frames = aux.iter().map(|v| v[1]).collect();
        Ok(Some(TemporalImage {
            width: w,
            height: h,
            distance,
            frames,
            jitter: self.jitter.to_array(),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use himmel_skymodel::Camera;

    #[test]
    fn a_run_continues_over_time_and_camera_only() {
        let a = himmel_skymodel::Scene::default();
        let sun = Vec3::new(0.0, 0.5, 0.8).normalize();
        let key = |s: &himmel_skymodel::Scene, d: f32| {
            let r = sun + Vec3::new(d.to_radians(), 0.0, 0.0);
            RunKey::of(s, Some(r.normalize()), None)
        };
        let first = key(&a, 0.0);
        let mut b = a.clone();
        b.time.utc = "2024-06-21T12:00:01Z".into();
        b.camera.yaw_deg += 1.0;
        assert!(key(&b, 0.05).continues(&first));
        // The Sun's step beyond LIGHT_STEP_DEG, or another scene: a new run.
        assert!(!key(&b, 0.2).continues(&first));
        b.sun_scale = 2.0;
        assert!(!key(&b, 0.0).continues(&first));
        assert!(!RunKey::of(&a, None, None).continues(&first));
    }

    #[test]
    fn halton_points_fill_the_pixel_evenly() {
        assert_eq!(halton(1, 2), 0.5);
        assert_eq!(halton(3, 2), 0.75);
        assert!((halton(2, 3) - 2.0 / 3.0).abs() < 1e-6);
        assert_eq!(jitter(0), Vec2::ZERO);
        assert_eq!(jitter(1), jitter(1 + JITTER_PERIOD));
        // The mean offset over a period is nearly 0 (the filter's average is
        // centred on the pixel), every offset inside it.
        let mut sum = Vec2::ZERO;
        for k in 1..=JITTER_PERIOD {
            let j = jitter(k);
            assert!(j.abs().max_element() <= 0.5, "{j}");
            sum += j;
        }
        let mean = sum / JITTER_PERIOD as f32;
        assert!(mean.abs().max_element() < 0.02, "{mean}");
    }

    /// The Rust mirror has naga's layout of the WGSL `Temporal`.
    #[test]
    fn uniforms_mirror_the_wgsl_struct() {
        use crate::uniforms::tests::{assert_wgsl_layout, fields};
        let mut rust = CameraBlock::layout();
        rust.extend(fields!(TemporalUniforms, [prev_eye, jitter, q]));
        let wgsl = include_str!("../../shaders/lighting/temporal.wgsl");
        let size = std::mem::size_of::<TemporalUniforms>();
        assert_wgsl_layout(wgsl, "Temporal", size, &rust);
    }

    #[test]
    fn uniforms_and_runs() {
        let cam = WorldCamera::new(&Camera::default());
        let s = TemporalSettings::default();
        let u = uniforms(&cam, &s, None);
        assert_eq!(u.prev_eye[3], 0.0);
        assert_eq!(u.q[0], 32);
        assert_eq!(u.jitter[2], 1.25);
        assert_eq!(std::mem::size_of::<TemporalUniforms>(), 7 * 16);
        let mut t = Temporal::default();
        // No history yet: unjittered; off: nothing.
        assert_eq!(t.next(true, &s, (8, 8)), (Vec2::ZERO, 0));
        t.prev_eye = Some(Vec3::ZERO);
        t.frame = 3;
        assert_eq!(t.next(true, &s, (8, 8)), (jitter(3), 3));
        let off = TemporalSettings { jitter: false, ..s };
        assert_eq!(t.next(true, &off, (8, 8)), (Vec2::ZERO, 3));
        assert_eq!(t.next(false, &s, (8, 8)), (Vec2::ZERO, 0));
        assert!(t.prev_eye.is_none());
        // The noise index wraps; the jitter follows the run's own index.
        t.prev_eye = Some(Vec3::ZERO);
        t.frame = NOISE_PERIOD + 5;
        assert_eq!(t.next(true, &s, (8, 8)), (jitter(NOISE_PERIOD + 5), 5));
    }
}
