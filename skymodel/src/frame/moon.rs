//! The Moon pass's frame: the shader's per-frame constants and tables
//! ([`MoonShader`]: photometry, extinction across the disk, lunar-eclipse
//! table), the angular size of a pixel at the Moon, the margin and
//! sub-sampling of the disk's edge, and the pixel rectangle the disk can
//! touch.

use glam::DVec3;

use crate::atmosphere::AtmosphereLuts;
use crate::frame::sun::pixel_rect;
use crate::moon::{refraction_of_apparent, MoonShader};
use crate::projection::Camera;
use crate::scene::Scene;
use crate::state::SkyState;

/// The Moon of one frame.
#[derive(Debug, Clone)]
pub struct MoonFrame {
    /// The shader: constants and tables of this frame (extinction through
    /// the LUTs when the atmosphere pass runs).
    pub shader: MoonShader,
    /// The angular size of a pixel at the Moon's centre, rad
    /// ([`local_pixel_angle`]).
    pub pixel: f32,
    /// The margin around the disk within which pixel centres are shaded,
    /// rad ([`limb_margin`]).
    pub margin: f32,
    /// cos(radius + margin): the bounding test of pixel centres.
    pub cos_bound: f32,
    /// Sub-samples per axis of each pixel (0: the analytic limb;
    /// [`supersampling`]).
    pub supersampling: usize,
    /// The pixel rectangle [x0, y0, x1, y1) that holds every pixel the disk
    /// touches: centres within radius + ½ pixel have coverage
    /// ([`MoonShader::shade`]) and sub-samples reach half a pixel's
    /// diagonal, which the camera's largest pixel angle bounds where the
    /// Moon can be seen; never beyond the margin.
    pub rect: [u32; 4],
}

impl MoonFrame {
    /// The Moon of `state` as `scene` draws it, seen from radius `r0` (km)
    /// through `luts` when the atmosphere pass runs.
    pub fn new(
        scene: &Scene,
        state: &SkyState,
        luts: Option<&AtmosphereLuts>,
        r0: f32,
    ) -> MoonFrame {
        let pole = DVec3::from_array(state.celestial_pole).as_vec3();
        let shader = MoonShader::new(
            &state.moon,
            scene.moon_scale,
            luts,
            r0,
            pole,
            &scene.atmosphere,
        );
        let cam = &scene.camera;
        let pixel = local_pixel_angle(cam, shader.centre.as_dvec3()) as f32;
        let margin = limb_margin(pixel);
        let reach = (2.0 * pixel.max(cam.max_pixel_angle() as f32)).min(margin);
        MoonFrame {
            cos_bound: shader.cos_bound(margin),
            supersampling: supersampling(shader.radius / pixel),
            rect: pixel_rect(
                cam,
                shader.centre.as_dvec3(),
                (shader.radius + reach) as f64,
            ),
            shader,
            pixel,
            margin,
        }
    }

    /// Bennett's refraction (rad, [`refraction_of_apparent`]) at `n`
    /// apparent altitudes over the disk (radius + margin around the
    /// centre, and the sub-samples of the pixels at its edge), for shaders
    /// that un-refract a low Moon's pixels by interpolation: the first
    /// altitude, the spacing (rad) and the values (zeros when the disk is
    /// high enough to be drawn without refraction).
    pub fn refraction_table(&self, cam: &Camera, n: usize) -> (f32, f32, Vec<f32>) {
        let s = &self.shader;
        let alt_c = s.centre.z.clamp(-1.0, 1.0).asin();
        let span = (s.radius + self.margin + cam.max_pixel_angle() as f32) * 1.1 + 1e-4;
        let (alt0, dalt) = (alt_c - span, 2.0 * span / (n.max(2) - 1) as f32);
        let values = (0..n)
            .map(|k| {
                if s.refract {
                    refraction_of_apparent(alt0 + dalt * k as f32)
                } else {
                    0.0
                }
            })
            .collect();
        (alt0, dalt, values)
    }
}

/// The margin (rad) around the disk within which pixel centres are
/// shaded, for pixels of `pixel` rad: two pixels, and at least 10⁻³ rad
/// (f32 dot products resolve ~0.02° near 1: the margin stays above that).
pub fn limb_margin(pixel: f32) -> f32 {
    (2.0 * pixel).max(1e-3)
}

/// Sub-samples per axis for a disk of `r_px` pixels in radius: small disks
/// (a few pixels across, e.g. all-sky images) are supersampled 8 × 8 or
/// 4 × 4 so that the light and the shape stay right; large ones (0) use
/// the analytic edge coverage.
pub fn supersampling(r_px: f32) -> usize {
    if r_px < 4.0 {
        8
    } else if r_px < 16.0 {
        4
    } else {
        0
    }
}

/// The angular size of a pixel at direction `c` (geometric mean of its
/// two sides, so that the anti-aliased edge keeps the disk's area); the
/// camera's largest pixel angle where `c` is not in the image.
pub fn local_pixel_angle(cam: &Camera, c: DVec3) -> f64 {
    let fallback = cam.max_pixel_angle();
    let Some((x, y)) = cam.dir_to_pixel(c) else {
        return fallback;
    };
    let at = |x: f64, y: f64| cam.pixel_to_dir(x, y);
    match (
        at(x - 0.5, y),
        at(x + 0.5, y),
        at(x, y - 0.5),
        at(x, y + 0.5),
    ) {
        (Some(a), Some(b), Some(u), Some(v)) => {
            let s = (a.angle_between(b) * u.angle_between(v)).sqrt();
            if s.is_finite() && s > 0.0 {
                s
            } else {
                fallback
            }
        }
        _ => fallback,
    }
}
