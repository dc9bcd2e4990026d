//! The Sun pass's frame: the limb-darkened disk ([`SunDisk`]) as drawn
//! (`sun_scale`), the margin within which pixels are supersampled, the
//! Moon that hides it during a solar eclipse, the pixel rectangle a
//! backend needs to visit, the disk tabulated for shaders, and the inner
//! corona of an eclipsed Sun ([`CoronaFrame`]).

use glam::{DVec3, Vec3};

use crate::atmosphere::AtmosphereLuts;
use crate::projection::{Camera, Projection};
use crate::scene::Scene;
use crate::spectrum::{BandWeights, Spectrum};
use crate::state::SkyState;
use crate::sun::{corona_relative, SunDisk};

/// Sub-samples per axis for pixels near the Sun's disk.
pub const SUN_SUPERSAMPLING: usize = 16;

/// Nodes of the Sun table ([`SunFrame::table`]) in normalised disk radius ρ.
pub const SUN_TABLE_RHO: usize = 64;
/// Nodes of the Sun table in line-of-sight zenith cosine.
pub const SUN_TABLE_Z: usize = 128;

/// The Sun of one frame.
#[derive(Debug, Clone)]
pub struct SunFrame {
    /// The disk as drawn: centre (ENU, unit), radius × `sun_scale`,
    /// irradiance at the Sun's distance.
    pub disk: SunDisk,
    /// The drawn radius (rad), clamped as the disk clamps it, in f64.
    pub radius: f64,
    /// Pixels whose centre lies within this angle (rad) of the centre are
    /// supersampled: the radius plus 1.5 of the camera's largest pixel
    /// angle, at most 3 rad.
    pub margin: f64,
    /// cos [`Self::margin`].
    pub cos_margin: f32,
    /// Sub-samples per axis of those pixels ([`SUN_SUPERSAMPLING`]).
    pub supersampling: usize,
    /// The Moon's centre (ENU, unit) and the sine of its drawn radius:
    /// sub-samples behind it are hidden (solar eclipses).
    pub moon_centre: Vec3,
    /// See `moon_centre`.
    pub moon_sin_radius: f32,
    /// The pixel rectangle [x0, y0, x1, y1) holding every pixel within the
    /// margin ([`pixel_rect`]).
    pub rect: [u32; 4],
    /// (1 AU / distance)² of the Sun.
    pub irradiance_scale: f64,
}

impl SunFrame {
    /// The Sun of `state` as `scene` draws it.
    pub fn new(scene: &Scene, state: &SkyState) -> SunFrame {
        let cam = &scene.camera;
        let dir = state.sun.dir().as_vec3().normalize();
        let radius = (state.sun.angular_radius * scene.sun_scale).clamp(1e-6, 0.5);
        let margin = (radius + 1.5 * cam.max_pixel_angle()).min(3.0);
        SunFrame {
            disk: SunDisk::new(
                dir,
                state.sun.angular_radius * scene.sun_scale,
                state.sun.irradiance_scale,
            ),
            radius,
            margin,
            cos_margin: margin.cos() as f32,
            supersampling: SUN_SUPERSAMPLING,
            moon_centre: state.moon.dir().as_vec3(),
            moon_sin_radius: (state.moon.angular_radius * scene.moon_scale).sin() as f32,
            rect: pixel_rect(cam, state.sun.dir().normalize(), margin),
            irradiance_scale: state.sun.irradiance_scale,
        }
    }

    /// The disk tabulated for shaders: linear sRGB radiance (cd/m²) at
    /// normalised radius ρ = sin(π/2 · i/(n−1)) (uniform in asin ρ: dense
    /// at the limb, where the limb darkening μ^α with μ = √(1 − ρ²) falls
    /// steeply; nodes uniform in ρ left limb pixels of a 17 px disk up to
    /// 70 % dark) and line-of-sight zenith cosine z over the disk's range;
    /// each node is the exact [`SunDisk::radiance_rgb`] after the
    /// transmittance `luts.sun_transmittance(r0, z)` (none without the
    /// atmosphere). Returns the table (row-major, [`SUN_TABLE_Z`] rows of
    /// [`SUN_TABLE_RHO`]) and [z_min, z_max].
    pub fn table(&self, luts: Option<&AtmosphereLuts>, r0: f32) -> (Vec<[f32; 4]>, [f32; 2]) {
        let radius = self.radius;
        let alt = (self.disk.centre.z as f64).clamp(-1.0, 1.0).asin();
        let half = std::f64::consts::FRAC_PI_2;
        let pad = radius * 0.02 + 1e-6;
        let z0 = (alt - radius - pad).max(-half).sin();
        let z1 = (alt + radius + pad).min(half).sin();
        // The same disk about the zenith: ρ only enters through |d × c|.
        let probe = SunDisk::new(Vec3::Z, radius, self.irradiance_scale);
        let sr = (probe.radius as f64).sin();
        let mut out = Vec::with_capacity(SUN_TABLE_RHO * SUN_TABLE_Z);
        for j in 0..SUN_TABLE_Z {
            let z = z0 + (z1 - z0) * j as f64 / (SUN_TABLE_Z - 1) as f64;
            let t = luts.map_or(Spectrum::ONE, |l| l.sun_transmittance(r0, z as f32));
            for i in 0..SUN_TABLE_RHO {
                let rho = (half * i as f64 / (SUN_TABLE_RHO - 1) as f64)
                    .sin()
                    .min(1.0 - 1e-6);
                let g = (rho * sr).asin();
                let dir = Vec3::new(g.sin() as f32, 0.0, g.cos() as f32);
                let rgb = if probe.covers(dir) {
                    probe.radiance_rgb(dir, &t)
                } else {
                    [0.0; 3]
                };
                out.push([rgb[0], rgb[1], rgb[2], 0.0]);
            }
        }
        (out, [z0 as f32, z1 as f32])
    }
}

/// The inner corona around an eclipsed Sun (drawn by the Sun pass when the
/// Moon hides part of the disk; against the uneclipsed daylight sky the
/// corona, ~10⁻⁶ of the disk's radiance, is invisible): Baumbach's profile
/// ([`corona_relative`], less its value at 6 solar radii, where the drawing
/// ends) times the disk's mean radiance and the transmittance along the
/// line of sight, hidden by the Moon's disk (anti-aliased over one pixel).
#[derive(Debug, Clone, PartialEq)]
pub struct CoronaFrame {
    /// The Sun's centre (ENU, unit).
    pub sun: Vec3,
    /// The Sun's drawn radius, rad.
    pub sun_radius: f32,
    /// The Moon's centre (ENU, unit).
    pub moon: Vec3,
    /// The Moon's drawn radius, rad.
    pub moon_radius: f32,
    /// The camera's largest pixel angle (rad): the width of the Moon's
    /// anti-aliased edge.
    pub pixel: f32,
    /// cos of 6 solar radii: the corona's outer edge.
    pub cos_outer: f32,
    /// The disk's mean radiance per unit band transfer (sr⁻¹).
    pub mean: f32,
    /// The profile at the outer edge, subtracted so that it ends without a step.
    pub edge: f32,
    /// The pixel rectangle [x0, y0, x1, y1) within 6 solar radii.
    pub rect: [u32; 4],
    /// The solar band weights (band transfer → linear sRGB).
    pub weights: BandWeights,
}

impl CoronaFrame {
    /// The corona of `state`, when the Moon hides part of the Sun.
    pub fn new(scene: &Scene, state: &SkyState) -> Option<CoronaFrame> {
        if state.sun.visible_fraction >= 1.0 {
            return None;
        }
        let cam = &scene.camera;
        let rs = state.sun.angular_radius * scene.sun_scale;
        let rs32 = rs as f32;
        Some(CoronaFrame {
            sun: state.sun.dir().as_vec3(),
            sun_radius: rs32,
            moon: state.moon.dir().as_vec3(),
            moon_radius: (state.moon.angular_radius * scene.moon_scale) as f32,
            pixel: cam.max_pixel_angle() as f32,
            cos_outer: (6.0 * rs32).cos(),
            mean: (state.sun.irradiance_scale
                / (std::f64::consts::PI * (rs32 as f64).sin().powi(2))) as f32,
            edge: corona_relative(6.0) as f32,
            rect: pixel_rect(cam, state.sun.dir().normalize(), 6.0 * rs),
            weights: BandWeights::solar(),
        })
    }

    /// The corona's linear sRGB radiance (cd/m²) towards `d` (ENU, unit)
    /// through `luts` from radius `r0`, or `None` outside it or behind the
    /// Moon.
    #[inline]
    pub fn radiance(&self, d: Vec3, luts: Option<&AtmosphereLuts>, r0: f32) -> Option<[f32; 3]> {
        if d.z < 0.0 || d.dot(self.sun) < self.cos_outer {
            return None;
        }
        let r = d.cross(self.sun).length().atan2(d.dot(self.sun)) / self.sun_radius;
        let rel = (corona_relative(r as f64) - corona_relative(6.0)) as f32;
        if rel <= 0.0 {
            return None;
        }
        let gm = d.cross(self.moon).length().atan2(d.dot(self.moon));
        let visible = 1.0 - ((self.moon_radius - gm) / self.pixel + 0.5).clamp(0.0, 1.0);
        if visible <= 0.0 {
            return None;
        }
        let t = luts.map_or(Spectrum::ONE, |l| l.sun_transmittance(r0, d.z));
        Some(self.weights.to_rgb(&(t * (self.mean * rel * visible))))
    }

    /// The corona's brightness (mean radiance × transmittance, linear sRGB)
    /// at `n` zenith cosines over its extent, for shaders: the table, its
    /// first node and spacing.
    pub fn table(
        &self,
        luts: Option<&AtmosphereLuts>,
        r0: f32,
        n: usize,
    ) -> (Vec<[f32; 4]>, f32, f32) {
        let half = std::f64::consts::FRAC_PI_2;
        let rs = self.sun_radius as f64;
        let alt = (self.sun.z as f64).clamp(-1.0, 1.0).asin();
        let reach = 6.0 * rs * 1.1 + 1e-5;
        let z0 = (alt - reach).max(-half).sin() as f32;
        let z1 = (alt + reach).min(half).sin() as f32;
        let dz = (z1 - z0).max(1e-9) / (n.max(2) - 1) as f32;
        let w = &self.weights;
        let rows = (0..n)
            .map(|k| {
                let z = z0 + dz * k as f32;
                let t = luts.map_or(Spectrum::ONE, |l| l.sun_transmittance(r0, z));
                let rgb = w.to_rgb(&(t * self.mean));
                [rgb[0], rgb[1], rgb[2], 0.0]
            })
            .collect();
        (rows, z0, dz)
    }
}

/// The pixel rectangle [x0, y0, x1, y1) that holds every pixel whose
/// centre lies within `margin` (rad) of the direction `centre` (ENU,
/// unit): the bounding box of 64 directions on the margin's circle (and
/// the centre) through [`Camera::dir_to_pixel`], padded by 2 px; the whole
/// image for cube maps, wide margins, circles through a pole of an
/// equirect image or across its 0°/360° seam, and directions a perspective
/// camera cannot project.
pub fn pixel_rect(cam: &Camera, centre: DVec3, margin: f64) -> [u32; 4] {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    let (w, h) = cam.image_size();
    let full = [0, 0, w, h];
    if cam.projection == Projection::Cubemap || margin > 0.5 {
        return full;
    }
    let m = margin * 1.05;
    let alt = centre.z.clamp(-1.0, 1.0).asin();
    if cam.projection == Projection::Fisheye && FRAC_PI_2 - alt + m >= PI {
        return full;
    }
    let a = if centre.z.abs() < 0.9 {
        DVec3::Z
    } else {
        DVec3::X
    };
    let e1 = centre.cross(a).normalize();
    let e2 = centre.cross(e1);
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    let (sm, cm) = m.sin_cos();
    for k in 0..=64 {
        let d = if k == 64 {
            centre
        } else {
            let phi = TAU * k as f64 / 64.0;
            centre * cm + (e1 * phi.cos() + e2 * phi.sin()) * sm
        };
        let Some((x, y)) = cam.dir_to_pixel(d) else {
            return full;
        };
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if cam.projection == Projection::Equirect {
        if x1 - x0 > w as f64 / 2.0 || alt + m >= FRAC_PI_2 || alt - m <= -FRAC_PI_2 {
            x0 = 0.0;
            x1 = w as f64;
        }
        if alt + m >= FRAC_PI_2 {
            y0 = 0.0;
        }
        if alt - m <= -FRAC_PI_2 {
            y1 = h as f64;
        }
    }
    let clamp_x = |v: f64| v.clamp(0.0, w as f64) as u32;
    let clamp_y = |v: f64| v.clamp(0.0, h as f64) as u32;
    let (rx0, ry0) = (clamp_x((x0 - 2.0).floor()), clamp_y((y0 - 2.0).floor()));
    let (rx1, ry1) = (clamp_x((x1 + 2.0).ceil()), clamp_y((y1 + 2.0).ceil()));
    [rx0, ry0, rx1.max(rx0), ry1.max(ry0)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::enu_from_alt_az;

    /// Every pixel centre within the margin of the Sun lies in the Sun
    /// pass's rectangle: equirect seam and poles, fisheye horizon and
    /// zenith, perspective edges (brute force over all pixel centres).
    #[test]
    fn pixel_rect_holds_every_pixel_within_the_margin() {
        let cams = [
            (Projection::Equirect, 256, 128, 0.0, 0.0),
            (Projection::Fisheye, 128, 128, 0.0, 0.0),
            (Projection::Perspective, 160, 96, 10.0, 20.0),
        ];
        let suns = [
            (0.5, 0.0),
            (0.5, 359.5),
            (89.0, 120.0),
            (-1.0, 300.0),
            (20.0, 180.0),
            (30.0, 40.0),
            (-89.5, 10.0),
        ];
        for (p, w, h, yaw, pitch) in cams {
            let cam = Camera {
                projection: p,
                width: w,
                height: h,
                yaw_deg: yaw,
                pitch_deg: pitch,
                fov_deg: 90.0,
                ..Camera::default()
            };
            for (alt, az) in suns {
                let sun = enu_from_alt_az(f64::to_radians(alt), f64::to_radians(az));
                let margin = 0.004_65 + 1.5 * cam.max_pixel_angle();
                let [x0, y0, x1, y1] = pixel_rect(&cam, sun, margin);
                let mut inside = 0;
                for y in 0..h {
                    for x in 0..w {
                        let Some(d) = cam.pixel_to_dir(x as f64 + 0.5, y as f64 + 0.5) else {
                            continue;
                        };
                        if d.dot(sun) >= margin.cos() {
                            inside += 1;
                            assert!(
                                (x0..x1).contains(&x) && (y0..y1).contains(&y),
                                "{p:?} Sun ({alt}, {az}): pixel ({x}, {y}) outside {:?}",
                                (x0, y0, x1, y1)
                            );
                        }
                    }
                }
                // The rectangle is tight when it is not the whole image.
                if (x0, y0, x1, y1) != (0, 0, w, h) {
                    assert!(inside > 0 || (x1 - x0) * (y1 - y0) < w * h / 4);
                }
            }
        }
    }
}
