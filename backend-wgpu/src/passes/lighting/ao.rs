//! Ambient occlusion (`lighting.ao`, issue 16): `ssao` or `gtao` from the
//! G-buffer's distance and normal (`shaders/lighting/ao.wgsl`), then a
//! depth-aware blur; the result (bent normal + AO, rgba32float) is what the
//! lighting pass reads and [`Occlusion::read_back`] returns. With S3HO
//! (`lighting.ao.sh`), a second image holds the light the pixel's blockers
//! hide: by default (`sh_sky` `radiance`) the blocked arcs of gtao's
//! slices weighted by the sky's radiance itself, read from a 64 × 32
//! equirect radiance map (the environment's narrowest prefiltered level,
//! uploaded here when the sky changes) — directional occlusion — or
//! (`sh2`) the projection of the blocked part of the cosine-weighted
//! visibility onto the SH of l = 1, 2, which the lighting pass weights with
//! the sky's own radiance coefficients (`ao.wgsl`). Either way the sky is
//! shadowed directionally and an open pixel keeps its light exactly.
//!
//! **How AO meets the sky's visibility maps.** The sky light already comes
//! through the world's visibility maps (one per sky cell,
//! `lighting.sky`), which see every blocker the maps' texels resolve, far
//! or near, but not the contact detail below a texel (a few centimetres
//! to decimetres outdoors). AO sees that detail within its radius, but only
//! what the camera sees. Both estimate the fraction of the sky's light that
//! reaches the surface, so multiplying them would count a blocker both see
//! twice. The lighting pass therefore takes the smaller of the two: the
//! sky's diffuse irradiance E, which the maps have already reduced, is
//! compared with E_open, the same cells' irradiance with nothing in the way;
//! their luminance ratio Y(E)/Y(E_open) is the maps' cosine-weighted
//! visibility, and E is scaled by min(1, AO / that ratio) — AO darkens only
//! where it finds more occlusion than the maps (creases, contacts), and
//! never the Sun's or the Moon's light. (The maps' ratio is weighted by the
//! sky's radiance, AO by a uniform sky: where a blocker hides the bright
//! side of the sky the maps' ratio is the lower and AO changes nothing,
//! which is right, as the maps see it directionally.) With
//! `lighting.sky.occlusion` `ao` no maps are built and the open sky's
//! irradiance is simply scaled by AO, or with S3HO less the blocked light.

use himmel_skymodel::renderer::PassStat;
use himmel_skymodel::{AoMethod, AoSettings, RenderError, ShSky};

use super::env::{EnvLight, SPECULAR_SIZE};
use super::resources::{texture, GBuffer};
use super::view::{CameraBlock, WorldCamera};
use crate::gpu::{bind, bind_group, Gpu};

/// The AO pass's uniforms (`Ao` in ao.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct AoUniforms {
    cam: CameraBlock,
    params: [f32; 4],
    q: [u32; 4],
    q2: [u32; 4],
}

/// The AO image of the last frame, read back.
#[derive(Debug, Clone, PartialEq)]
pub struct AoImage {
    /// Width, px.
    pub width: u32,
    /// Height, px.
    pub height: u32,
    /// The radius it was computed with, metres.
    pub radius_m: f32,
    /// AO per pixel, row-major, in [0, 1] (1 on sky pixels).
    pub ao: Vec<f32>,
    /// The bent normal per pixel (world frame, unit; 0 on sky pixels).
    pub bent_normal: Vec<[f32; 3]>,
}

struct AoPipes {
    layout: wgpu::BindGroupLayout,
    occlude: wgpu::ComputePipeline,
    blur: wgpu::ComputePipeline,
}

struct Images {
    size: (u32, u32),
    /// Whether the S3HO images are full size (else 1 × 1, not written).
    sh: bool,
    raw: wgpu::TextureView,
    out: wgpu::Texture,
    out_view: wgpu::TextureView,
    sh_raw: wgpu::TextureView,
    sh_out: wgpu::TextureView,
}

/// The AO pass and its images, kept between frames.
#[derive(Default)]
pub struct Occlusion {
    pipes: Option<AoPipes>,
    images: Option<Images>,
    stand_in: Option<wgpu::TextureView>,
    sh_stand_in: Option<wgpu::TextureView>,
    /// S3HO `radiance`'s sky radiance map (level 0 of the prefiltered
    /// environment, f32), or a 1 × 1 black stand-in before a sky came.
    sky_map: Option<wgpu::TextureView>,
    /// Whether `sky_map` holds a sky (not the stand-in).
    sky_loaded: bool,
    radius_m: f32,
    /// The last run's S3HO ([`s3ho_mode`]).
    sh: u32,
}

/// S3HO's mode in the uniforms: 0 off, 1 `sh2`, 2 `radiance` (`gtao`
/// only).
pub fn s3ho_mode(s: &AoSettings) -> u32 {
    match (s.sh && s.method == AoMethod::Gtao, s.sh_sky) {
        (false, _) => 0,
        (true, ShSky::Sh2) => 1,
        (true, ShSky::Radiance) => 2,
    }
}

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// S3HO's B_1,-1 … B_2,2 as f16 pairs (`sh2`), or the blocked light's
/// red, green and blue as f32 (`radiance`).
const SH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

fn sh_image(gpu: &Gpu, size: (u32, u32)) -> wgpu::TextureView {
    let usage = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
    let d = wgpu::TextureDimension::D2;
    texture(gpu, "ao sh", (size.0, size.1, 1), d, SH_FORMAT, usage).create_view(&Default::default())
}

fn image(gpu: &Gpu, (w, h): (u32, u32), copy: bool) -> wgpu::Texture {
    let mut usage = wgpu::TextureUsages::STORAGE_BINDING
        | wgpu::TextureUsages::TEXTURE_BINDING
        | wgpu::TextureUsages::COPY_DST;
    if copy {
        usage |= wgpu::TextureUsages::COPY_SRC;
    }
    texture(
        gpu,
        "ao",
        (w, h, 1),
        wgpu::TextureDimension::D2,
        FORMAT,
        usage,
    )
}

fn pipes(gpu: &Gpu) -> AoPipes {
    let f = bind::float_2d();
    let layout = gpu.compute_layout(
        "ao",
        &[
            bind::uniform(),
            f,
            f,
            bind::uint_2d(),
            bind::write_2d(FORMAT),
            f,
            bind::write_2d(SH_FORMAT),
            bind::uint_2d(),
            f,
        ],
    );
    let module = gpu.shader(
        "ao.wgsl",
        concat!(
            include_str!("../../shaders/lighting/screen.wgsl"),
            include_str!("../../shaders/lighting/ao.wgsl"),
            include_str!("../../shaders/lighting/ao_hbao.wgsl")
        ),
    );
    let pl = gpu.pipeline_layout("ao", &[&layout]);
    AoPipes {
        occlude: gpu.compute_pipeline(&pl, &module, "occlude"),
        blur: gpu.compute_pipeline(&pl, &module, "blur"),
        layout,
    }
}

/// The uniforms of a frame seen by `cam` with radius `radius_m`.
fn uniforms(cam: &WorldCamera, s: &AoSettings, radius_m: f32) -> AoUniforms {
    AoUniforms {
        cam: cam.block(),
        params: [
            radius_m,
            s.thickness_m.unwrap_or(0.0) as f32,
            cam.jitter.x,
            cam.jitter.y,
        ],
        q: [
            match s.method {
                AoMethod::Ssao => 0,
                AoMethod::Gtao => 1,
                AoMethod::Hbao => 2,
            },
            s.slices.max(1),
            s.steps.max(1),
            s.samples.max(1),
        ],
        q2: [s.blur_px, cam.frame, s3ho_mode(s), 0],
    }
}

/// The sky radiance map of S3HO `radiance`: `SPECULAR_SIZE` texels of
/// `env`'s narrowest prefiltered level (its first), or a black texel.
fn sky_map(gpu: &Gpu, env: Option<&EnvLight>) -> wgpu::TextureView {
    let (w, h) = SPECULAR_SIZE;
    let texels: Vec<[f32; 4]> = match env {
        Some(e) if e.specular.len() >= w * h => e.specular[..w * h]
            .iter()
            .map(|l| [l[0], l[1], l[2], 1.0])
            .collect(),
        _ => vec![[0.0; 4]],
    };
    let size = if texels.len() == 1 {
        (1, 1)
    } else {
        (w as u32, h as u32)
    };
    let usage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
    let t = texture(
        gpu,
        "ao sky",
        (size.0, size.1, 1),
        wgpu::TextureDimension::D2,
        FORMAT,
        usage,
    );
    gpu.queue.write_texture(
        t.as_image_copy(),
        bytemuck::cast_slice(&texels),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(16 * size.0),
            rows_per_image: Some(size.1),
        },
        wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        },
    );
    t.create_view(&Default::default())
}

impl Occlusion {
    /// Runs the pass over the G-buffer `gb` of `cam` (occlusion, then the
    /// blur) and waits for the device; S3HO `radiance` reads the radiance
    /// of `sky` (the frame's environment light; uploaded again when
    /// `sky.1`, it changed). Returns its `--stats` entry.
    pub fn run(
        &mut self,
        gpu: &Gpu,
        (gb, cam): (&GBuffer, &WorldCamera),
        settings: &AoSettings,
        radius_m: f32,
        sky: (Option<&EnvLight>, bool),
    ) -> Result<PassStat, RenderError> {
        // The pipelines once per renderer, outside the pass's time.
        let pipes = self.pipes.get_or_insert_with(|| pipes(gpu));
        let t = std::time::Instant::now();
        let size = (cam.width, cam.height);
        let mode = s3ho_mode(settings);
        let sh = mode != 0;
        // The radiance map when S3HO reads it and the sky changed (or it
        // holds none yet); else what there is, or a stand-in.
        let load = mode == 2 && sky.0.is_some() && (sky.1 || !self.sky_loaded);
        if load || self.sky_map.is_none() {
            self.sky_map = Some(sky_map(gpu, sky.0.filter(|_| load)));
            self.sky_loaded = load;
        } else if sky.1 {
            // A sky that changed while S3HO did not read it: load it when
            // it does.
            self.sky_loaded = false;
        }
        let Some(sky_view) = self.sky_map.as_ref() else {
            return Err(RenderError::Device("ao sky map missing".into()));
        };
        if self.images.as_ref().map(|i| (i.size, i.sh)) != Some((size, sh)) {
            let out = image(gpu, size, true);
            let sh_size = if sh { size } else { (1, 1) };
            self.images = Some(Images {
                size,
                sh,
                raw: image(gpu, size, false).create_view(&Default::default()),
                out_view: out.create_view(&Default::default()),
                out,
                sh_raw: sh_image(gpu, sh_size),
                sh_out: sh_image(gpu, sh_size),
            });
        }
        let Some(img) = self.images.as_ref() else {
            return Err(RenderError::Device("ao images missing".into()));
        };
        let u = uniforms(cam, settings, radius_m);
        let ubuf = wgpu::util::DeviceExt::create_buffer_init(
            &gpu.device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("ao uniforms"),
                contents: bytemuck::bytes_of(&u),
                usage: wgpu::BufferUsages::UNIFORM,
            },
        );
        let tv = wgpu::BindingResource::TextureView;
        let group = |(out, sh_out), (input, sh_in)| {
            bind_group(
                &gpu.device,
                "ao",
                &pipes.layout,
                &[
                    ubuf.as_entire_binding(),
                    tv(&gb.views[0]),
                    tv(&gb.views[1]),
                    tv(&gb.views[3]),
                    tv(out),
                    tv(input),
                    tv(sh_out),
                    tv(sh_in),
                    tv(sky_view),
                ],
            )
        };
        let first = group((&img.raw, &img.sh_raw), (&img.out_view, &img.sh_out));
        let second = group((&img.out_view, &img.sh_out), (&img.raw, &img.sh_raw));
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        let groups = (size.0.div_ceil(8), size.1.div_ceil(8));
        for (pipe, g) in [(&pipes.occlude, &first), (&pipes.blur, &second)] {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipe);
            pass.set_bind_group(0, g, &[]);
            pass.dispatch_workgroups(groups.0, groups.1, 1);
        }
        gpu.queue.submit([enc.finish()]);
        gpu.wait()?;
        self.radius_m = radius_m;
        self.sh = mode;
        let method = match settings.method {
            AoMethod::Ssao => "ssao",
            AoMethod::Gtao if mode == 2 => "gtao + S3HO (sky radiance)",
            AoMethod::Gtao if sh => "gtao + S3HO (order-2 SH)",
            AoMethod::Gtao => "gtao",
            AoMethod::Hbao => "hbao",
        };
        Ok(PassStat {
            name: "ao".into(),
            ran: true,
            ms: Some(t.elapsed().as_secs_f64() * 1e3),
            reason: Some(match settings.thickness_m {
                Some(t) => format!("{method}, radius {radius_m:.2} m, bitmask thickness {t:.2} m"),
                None => format!("{method}, radius {radius_m:.2} m"),
            }),
        })
    }

    /// The S3HO image's mode for the lighting pass ([`s3ho_mode`]; 0
    /// unless the pass runs, `on`, and its last run made one).
    pub fn s3ho(&self, on: bool) -> u32 {
        if on && self.images.is_some() {
            self.sh
        } else {
            0
        }
    }

    /// The AO image and the S3HO image of the last run, or (`on` false, or
    /// no S3HO) 1 × 1 stand-ins that the lighting pass binds and recognises
    /// by their size or [`Occlusion::s3ho`] (the AO stand-in holds AO 1,
    /// which changes nothing, should a 1 × 1 frame read it).
    pub fn views(&mut self, gpu: &Gpu, on: bool) -> [&wgpu::TextureView; 2] {
        let stand_in = self.stand_in.get_or_insert_with(|| {
            let t = image(gpu, (1, 1), false);
            let one: [f32; 4] = [0.0, 0.0, 0.0, 1.0];
            gpu.queue.write_texture(
                t.as_image_copy(),
                bytemuck::bytes_of(&one),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(16),
                    rows_per_image: Some(1),
                },
                wgpu::Extent3d {
                    width: 1,
                    height: 1,
                    depth_or_array_layers: 1,
                },
            );
            t.create_view(&Default::default())
        });
        let sh_stand_in = self
            .sh_stand_in
            .get_or_insert_with(|| sh_image(gpu, (1, 1)));
        match self.images.as_ref().filter(|_| on) {
            Some(i) if self.sh != 0 => [&i.out_view, &i.sh_out],
            Some(i) => [&i.out_view, sh_stand_in],
            None => [stand_in, sh_stand_in],
        }
    }

    /// The AO image of the last run (`None` before the first).
    pub fn read_back(&self, gpu: &Gpu) -> Result<Option<AoImage>, RenderError> {
        let Some(img) = self.images.as_ref() else {
            return Ok(None);
        };
        let (w, h) = img.size;
        let texels: Vec<[f32; 4]> = gpu.read_texels(&img.out, "ao read back")?;
        let ao = texels.iter().map(|v| v[3]).collect();
        let bent_normal = texels.iter().map(|v| [v[0], v[1], v[2]]).collect();
        Ok(Some(AoImage {
            width: w,
            height: h,
            radius_m: self.radius_m,
            ao,
            bent_normal,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use himmel_skymodel::Camera;

    #[test]
    fn uniforms_carry_the_method_and_the_quality() {
        let cam = WorldCamera::new(&Camera::default());
        let s = AoSettings {
            method: AoMethod::Ssao,
            samples: 24,
            blur_px: 3,
            ..AoSettings::default()
        };
        let u = uniforms(&cam, &s, 1.5);
        assert_eq!(u.q, [0, s.slices, s.steps, 24]);
        assert_eq!(u.q2[0], 3);
        assert_eq!(u.params[0], 1.5);
        let g = uniforms(&cam, &AoSettings::default(), 2.0);
        assert_eq!(g.q[0], 1);
        // S3HO: flagged for gtao only.
        assert_eq!(g.q2[2], 0);
        let sh = AoSettings {
            sh: true,
            ..AoSettings::default()
        };
        assert_eq!(uniforms(&cam, &sh, 2.0).q2[2], 2);
        let sh2 = AoSettings {
            sh_sky: ShSky::Sh2,
            ..sh
        };
        assert_eq!(uniforms(&cam, &sh2, 2.0).q2[2], 1);
        assert_eq!(uniforms(&cam, &AoSettings { sh: true, ..s }, 2.0).q2[2], 0);
        assert_eq!(std::mem::size_of::<AoUniforms>(), 7 * 16);
    }
}
