//! Image projections of `himmel render`, exactly as the project's
//! conventions define them (spec/conventions.md, "Image projections").
//!
//! Directions are unit vectors in the horizontal frame ENU (x = East,
//! y = North, z = Zenith). Image coordinates are continuous: pixel (x, y)
//! covers [x, x + 1) × [y, y + 1), its centre is (x + 0.5, y + 0.5), y grows
//! downwards.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::units::{show, Degrees, Steradians};

/// The image projection.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Projection {
    /// All-sky azimuthal equidistant, zenith at the centre, North up, East left.
    #[default]
    Fisheye,
    /// Azimuth 0–360° left to right (North at the left edge), altitude 90° to −90°.
    Equirect,
    /// Pinhole camera at (yaw = azimuth, pitch = altitude), no roll, vertical `fov`.
    Perspective,
    /// Six H×H faces +X −X +Y −Y +Z −Z of the scene frame (x East, y Up, z South) in a 6H×H strip.
    Cubemap,
}

impl Projection {
    /// Parses a projection name.
    pub fn from_name(s: &str) -> Option<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "fisheye" => Some(Projection::Fisheye),
            "equirect" => Some(Projection::Equirect),
            "perspective" => Some(Projection::Perspective),
            "cubemap" => Some(Projection::Cubemap),
            _ => None,
        }
    }

    /// The projection's name as the scene and the command line write it.
    pub fn name(self) -> &'static str {
        match self {
            Projection::Fisheye => "fisheye",
            Projection::Equirect => "equirect",
            Projection::Perspective => "perspective",
            Projection::Cubemap => "cubemap",
        }
    }
}

/// The camera: projection, image size and orientation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Camera {
    /// Projection (default fisheye).
    pub projection: Projection,
    /// Image width, pixels, at least 1 with width × height ≤ 64 Mpx
    /// ([`MAX_PIXELS`]) (default 1024; a cube map is always 6 × height
    /// wide and ignores it).
    pub width: u32,
    /// Image height, pixels, at least 1 with width × height ≤ 64 Mpx
    /// (default 1024; the face size of a cube map, 6 × height² ≤ 64 Mpx).
    pub height: u32,
    /// Azimuth the perspective camera looks at, degrees from North through
    /// East, in [−720, 720] (two turns either way, so that sums such as an
    /// azimuth plus an offset need no wrapping) (default 0).
    pub yaw_deg: Degrees,
    /// Altitude the perspective camera looks at, degrees in [−90, 90] (default 0).
    pub pitch_deg: Degrees,
    /// Vertical field of view of the perspective camera, degrees in (0, 180) (default 90).
    pub fov_deg: Degrees,
    /// Position of the perspective camera in the world frame (x East, y Up,
    /// z South), metres, each component in [−1e6, 1e6] (default none:
    /// `[0, 1.7, 0]`, `spec/world.md`). Sky pixels do not depend on it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub position_m: Option<[f64; 3]>,
    /// The world point the perspective camera looks at (world frame,
    /// metres); when given it replaces `yaw_deg`/`pitch_deg` (default none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub look_at_m: Option<[f64; 3]>,
    /// The camera's up hint in the world frame with `look_at_m` (default
    /// `[0, 1, 0]`); the image's vertical is the hint made orthogonal to
    /// the view direction, so a tilted hint rolls the camera.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub up: Option<[f64; 3]>,
}

/// Where the camera stands without `camera.position_m`: 1.7 m above the
/// ground at the origin (`spec/world.md`).
pub const DEFAULT_EYE_M: [f64; 3] = [0.0, 1.7, 0.0];

impl Default for Camera {
    fn default() -> Self {
        Camera {
            projection: Projection::Fisheye,
            width: 1024,
            height: 1024,
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            fov_deg: 90.0,
            position_m: None,
            look_at_m: None,
            up: None,
        }
    }
}

/// Largest image, pixels (W·H ≤ 64 Mpx = 64 × 2²⁰).
pub const MAX_PIXELS: u64 = 64 * 1024 * 1024;

/// An invalid camera setting, naming the field.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraError {
    /// The field (`camera.fov_deg`, …).
    pub field: &'static str,
    /// What is accepted.
    pub message: String,
}

impl std::fmt::Display for CameraError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.field, self.message)
    }
}

impl std::error::Error for CameraError {}

impl Camera {
    /// The image size actually rendered (a cube map is 6H × H).
    pub fn image_size(&self) -> (u32, u32) {
        match self.projection {
            Projection::Cubemap => (self.height.saturating_mul(6), self.height),
            _ => (self.width, self.height),
        }
    }

    /// Checks sizes and angles.
    pub fn validate(&self) -> Result<(), CameraError> {
        if self.width == 0 {
            return Err(CameraError {
                field: "camera.width",
                message: "must be at least 1 pixel".into(),
            });
        }
        if self.height == 0 {
            return Err(CameraError {
                field: "camera.height",
                message: "must be at least 1 pixel".into(),
            });
        }
        let (w, h) = self.image_size();
        if w as u64 * h as u64 > MAX_PIXELS || w == u32::MAX {
            // The size that makes the image too large: the height of a cube
            // map (its width follows), else the larger side.
            let field = if self.projection == Projection::Cubemap || self.height > self.width {
                "camera.height"
            } else {
                "camera.width"
            };
            return Err(CameraError {
                field,
                message: format!(
                    "image of {w}×{h} pixels exceeds the limit of 64 Mpx ({MAX_PIXELS} pixels)"
                ),
            });
        }
        if !(self.fov_deg.is_finite() && self.fov_deg > 0.0 && self.fov_deg < 180.0) {
            return Err(CameraError {
                field: "camera.fov_deg",
                message: format!("{} is outside (0, 180) degrees", show(self.fov_deg)),
            });
        }
        if !(self.yaw_deg.is_finite() && (-720.0..=720.0).contains(&self.yaw_deg)) {
            return Err(CameraError {
                field: "camera.yaw_deg",
                message: format!("{} is outside [-720, 720] degrees", show(self.yaw_deg)),
            });
        }
        if !(self.pitch_deg.is_finite() && (-90.0..=90.0).contains(&self.pitch_deg)) {
            return Err(CameraError {
                field: "camera.pitch_deg",
                message: format!("{} is outside [-90, 90] degrees", show(self.pitch_deg)),
            });
        }
        for (field, v) in [
            ("camera.position_m", self.position_m),
            ("camera.look_at_m", self.look_at_m),
            ("camera.up", self.up),
        ] {
            if let Some(v) = v {
                if !v.iter().all(|c| c.is_finite() && c.abs() <= 1e6) {
                    return Err(CameraError {
                        field,
                        message: format!(
                            "[{}, {}, {}]: each component must be a finite number in [-1e6, 1e6]",
                            show(v[0]),
                            show(v[1]),
                            show(v[2])
                        ),
                    });
                }
            }
        }
        if self.look_at_m.is_some() {
            let f = DVec3::from_array(self.look_at_m.unwrap_or_default()) - self.eye_m();
            if f.length() < 1e-6 {
                return Err(CameraError {
                    field: "camera.look_at_m",
                    message: "coincides with camera.position_m: no view direction".into(),
                });
            }
            let up = DVec3::from_array(self.up.unwrap_or([0.0, 1.0, 0.0]));
            if f.normalize().cross(up).length() < 1e-6 {
                return Err(CameraError {
                    field: "camera.up",
                    message: "is zero or parallel to the view direction (look_at_m − position_m)"
                        .into(),
                });
            }
        } else if self.up.is_some() {
            return Err(CameraError {
                field: "camera.up",
                message: "needs camera.look_at_m (yaw/pitch cameras have no roll)".into(),
            });
        }
        Ok(())
    }

    /// The camera's position in the world frame, metres
    /// (`position_m`, or [`DEFAULT_EYE_M`]).
    pub fn eye_m(&self) -> DVec3 {
        DVec3::from_array(self.position_m.unwrap_or(DEFAULT_EYE_M))
    }

    /// The perspective camera's basis in ENU: (forward, right, up). From
    /// `look_at_m`/`up` when given (world frame converted to ENU), else
    /// from `yaw_deg`/`pitch_deg` with zenith up and no roll.
    pub fn basis(&self) -> (DVec3, DVec3, DVec3) {
        if let Some(target) = self.look_at_m {
            let f = enu_from_scene(DVec3::from_array(target) - self.eye_m());
            let hint = enu_from_scene(DVec3::from_array(self.up.unwrap_or([0.0, 1.0, 0.0])));
            let f = f.normalize();
            let right = f.cross(hint).normalize();
            return (f, right, right.cross(f));
        }
        let (yaw, pitch) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        let f = enu_from_alt_az(pitch, yaw);
        let right = DVec3::new(yaw.cos(), -yaw.sin(), 0.0);
        let up = right.cross(f);
        (f, right, up)
    }

    fn perspective_basis(&self) -> (DVec3, DVec3, DVec3) {
        self.basis()
    }

    /// The ENU direction seen at continuous image position (px, py), or
    /// `None` outside the projection's domain (fisheye beyond 180° from
    /// the zenith, perspective never).
    pub fn pixel_to_dir(&self, px: f64, py: f64) -> Option<DVec3> {
        let (w, h) = self.image_size();
        let (w, h) = (w as f64, h as f64);
        match self.projection {
            Projection::Fisheye => {
                let dx = px - w / 2.0;
                let dy = py - h / 2.0;
                let r = w.min(h) / 2.0;
                let zenith = std::f64::consts::FRAC_PI_2 * (dx * dx + dy * dy).sqrt() / r;
                if zenith > std::f64::consts::PI {
                    return None;
                }
                let az = (-dx).atan2(-dy);
                Some(enu_from_alt_az(std::f64::consts::FRAC_PI_2 - zenith, az))
            }
            Projection::Equirect => {
                let az = std::f64::consts::TAU * px / w;
                let alt = std::f64::consts::FRAC_PI_2 - std::f64::consts::PI * py / h;
                Some(enu_from_alt_az(
                    alt.clamp(-std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2),
                    az,
                ))
            }
            Projection::Perspective => {
                let (f, right, up) = self.perspective_basis();
                let t = (self.fov_deg.to_radians() / 2.0).tan();
                let nx = (px - w / 2.0) / (h / 2.0) * t;
                let ny = -(py - h / 2.0) / (h / 2.0) * t;
                Some((f + right * nx + up * ny).normalize())
            }
            Projection::Cubemap => {
                let face = ((px / h).floor() as i64).clamp(0, 5);
                let s = (px - face as f64 * h) / h;
                let t = py / h;
                Some(cube_face_dir(face as usize, 2.0 * s - 1.0, 2.0 * t - 1.0))
            }
        }
    }

    /// The continuous image position of ENU direction `d` (unit), or
    /// `None` when the projection does not show it.
    pub fn dir_to_pixel(&self, d: DVec3) -> Option<(f64, f64)> {
        let (w, h) = self.image_size();
        let (w, h) = (w as f64, h as f64);
        match self.projection {
            Projection::Fisheye => {
                let zenith = d.z.clamp(-1.0, 1.0).acos();
                let az = d.x.atan2(d.y);
                let rho = zenith / std::f64::consts::FRAC_PI_2 * w.min(h) / 2.0;
                Some((w / 2.0 - rho * az.sin(), h / 2.0 - rho * az.cos()))
            }
            Projection::Equirect => {
                let alt = d.z.clamp(-1.0, 1.0).asin();
                let az = d.x.atan2(d.y).rem_euclid(std::f64::consts::TAU);
                Some((
                    az / std::f64::consts::TAU * w,
                    (std::f64::consts::FRAC_PI_2 - alt) / std::f64::consts::PI * h,
                ))
            }
            Projection::Perspective => {
                let (f, right, up) = self.perspective_basis();
                let z = d.dot(f);
                if z <= 1e-12 {
                    return None;
                }
                let t = (self.fov_deg.to_radians() / 2.0).tan();
                let nx = d.dot(right) / z / t;
                let ny = d.dot(up) / z / t;
                Some((w / 2.0 + nx * h / 2.0, h / 2.0 - ny * h / 2.0))
            }
            Projection::Cubemap => {
                let (face, sc, tc) = cube_face_coords(d);
                Some((face as f64 * h + (sc + 1.0) / 2.0 * h, (tc + 1.0) / 2.0 * h))
            }
        }
    }

    /// The solid angle (sr) of the pixel whose centre is at continuous image
    /// position (px, py): the exact area element of each projection times
    /// one pixel. Fisheye (azimuthal equidistant, a = 90°/R per pixel):
    /// a² · sin z / z at zenith angle z; equirect: (2π/W) · (sin h₁ − sin h₀)
    /// over the pixel's altitude band; perspective and cube-map faces:
    /// s² / (1 + x² + y²)^(3/2) on the tangent plane (s = pixel pitch in
    /// tangent units). 0 outside the projection's domain.
    pub fn pixel_solid_angle(&self, px: f64, py: f64) -> Steradians {
        let (w, h) = self.image_size();
        let (w, h) = (w as f64, h as f64);
        match self.projection {
            Projection::Fisheye => {
                let a = std::f64::consts::FRAC_PI_2 / (w.min(h) / 2.0);
                let (dx, dy) = (px - w / 2.0, py - h / 2.0);
                let z = a * (dx * dx + dy * dy).sqrt();
                if z > std::f64::consts::PI {
                    0.0
                } else if z < 1e-9 {
                    a * a
                } else {
                    a * a * z.sin() / z
                }
            }
            Projection::Equirect => {
                let row = py.floor();
                let h0 = std::f64::consts::FRAC_PI_2 - std::f64::consts::PI * (row + 1.0) / h;
                let h1 = std::f64::consts::FRAC_PI_2 - std::f64::consts::PI * row / h;
                std::f64::consts::TAU / w * (h1.sin() - h0.sin()).abs()
            }
            Projection::Perspective => {
                let s = 2.0 * (self.fov_deg.to_radians() / 2.0).tan() / h;
                let (x, y) = ((px - w / 2.0) * s, (py - h / 2.0) * s);
                let q = 1.0 + x * x + y * y;
                s * s / (q * q.sqrt())
            }
            Projection::Cubemap => {
                let face = (px / h).floor().clamp(0.0, 5.0);
                let s = 2.0 / h;
                let (x, y) = ((px - face * h) * s - 1.0, py * s - 1.0);
                let q = 1.0 + x * x + y * y;
                s * s / (q * q.sqrt())
            }
        }
    }

    /// An upper bound of the angle one pixel spans, radians (used to find
    /// the pixels that need supersampling near small bright sources).
    pub fn max_pixel_angle(&self) -> f64 {
        let (w, h) = self.image_size();
        let (w, h) = (w as f64, h as f64);
        match self.projection {
            Projection::Fisheye => std::f64::consts::FRAC_PI_2 / (w.min(h) / 2.0) * 2.0,
            Projection::Equirect => (std::f64::consts::TAU / w).hypot(std::f64::consts::PI / h),
            Projection::Perspective => 2.0 * (self.fov_deg.to_radians() / 2.0).tan() / h * 1.5,
            Projection::Cubemap => 2.0 / h * 1.5,
        }
    }
}

/// The ENU direction at face coordinates (sc, tc) of cube face `face`
/// (0–5: +X −X +Y −Y +Z −Z of the scene frame, OpenGL orientation; sc
/// grows to the right, tc downwards, both −1 … 1 across the face and
/// continued beyond its edges on the face's plane).
pub fn cube_face_dir(face: usize, sc: f64, tc: f64) -> DVec3 {
    let v = match face {
        0 => DVec3::new(1.0, -tc, -sc),
        1 => DVec3::new(-1.0, -tc, sc),
        2 => DVec3::new(sc, 1.0, tc),
        3 => DVec3::new(sc, -1.0, -tc),
        4 => DVec3::new(sc, -tc, 1.0),
        _ => DVec3::new(-sc, -tc, -1.0),
    };
    enu_from_scene(v.normalize())
}

/// The cube face (0–5) that shows ENU direction `d` and its face
/// coordinates (sc, tc) in [−1, 1] ([`cube_face_dir`]'s inverse).
pub fn cube_face_coords(d: DVec3) -> (usize, f64, f64) {
    let v = scene_from_enu(d);
    let a = v.abs();
    if a.x >= a.y && a.x >= a.z {
        if v.x > 0.0 {
            (0, -v.z / a.x, -v.y / a.x)
        } else {
            (1, v.z / a.x, -v.y / a.x)
        }
    } else if a.y >= a.z {
        if v.y > 0.0 {
            (2, v.x / a.y, v.z / a.y)
        } else {
            (3, v.x / a.y, -v.z / a.y)
        }
    } else if v.z > 0.0 {
        (4, v.x / a.z, -v.y / a.z)
    } else {
        (5, -v.x / a.z, -v.y / a.z)
    }
}

/// ENU unit vector from altitude and azimuth (radians, azimuth from North through East).
pub fn enu_from_alt_az(alt: f64, az: f64) -> DVec3 {
    let (sa, ca) = alt.sin_cos();
    DVec3::new(ca * az.sin(), ca * az.cos(), sa)
}

/// Scene frame (x East, y Up, z South) → ENU.
pub fn enu_from_scene(v: DVec3) -> DVec3 {
    DVec3::new(v.x, -v.z, v.y)
}

/// ENU → scene frame (x East, y Up, z South).
pub fn scene_from_enu(d: DVec3) -> DVec3 {
    DVec3::new(d.x, d.z, -d.y)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(p: Projection, w: u32, h: u32) -> Camera {
        Camera {
            projection: p,
            width: w,
            height: h,
            yaw_deg: 30.0,
            pitch_deg: 20.0,
            fov_deg: 70.0,
            ..Camera::default()
        }
    }

    #[test]
    fn fisheye_orientation_per_conventions() {
        let c = cam(Projection::Fisheye, 200, 200);
        // Centre → zenith; top → North; left → East.
        assert!((c.pixel_to_dir(100.0, 100.0).unwrap().z - 1.0).abs() < 1e-12);
        let top = c.pixel_to_dir(100.0, 0.5).unwrap();
        assert!(top.y > 0.99 && top.z.abs() < 0.02, "{top}");
        let left = c.pixel_to_dir(0.5, 100.0).unwrap();
        assert!(left.x > 0.99, "{left}");
        // Corners beyond 180° from the zenith are outside.
        let big = cam(Projection::Fisheye, 400, 100);
        assert!(big.pixel_to_dir(0.5, 0.5).is_none());
    }

    #[test]
    fn equirect_orientation_per_conventions() {
        let c = cam(Projection::Equirect, 360, 180);
        let east = c.pixel_to_dir(90.0, 90.0).unwrap();
        assert!((east - DVec3::X).length() < 1e-12, "{east}");
        let north = c.pixel_to_dir(0.0, 90.0).unwrap();
        assert!((north - DVec3::Y).length() < 1e-12);
        let up = c.pixel_to_dir(10.0, 0.0).unwrap();
        assert!((up.z - 1.0).abs() < 1e-12);
    }

    #[test]
    fn perspective_looks_at_yaw_pitch_with_zenith_up() {
        let mut c = cam(Projection::Perspective, 300, 200);
        let d = c.pixel_to_dir(150.0, 100.0).unwrap();
        assert!((d - enu_from_alt_az(20f64.to_radians(), 30f64.to_radians())).length() < 1e-12);
        // Up in the image is towards the zenith, and the vertical fov is exact.
        let top = c.pixel_to_dir(150.0, 0.0).unwrap();
        let alt = top.z.asin().to_degrees();
        assert!((alt - 55.0).abs() < 1e-9, "{alt}");
        c.yaw_deg = 0.0;
        c.pitch_deg = 0.0;
        let right = c.pixel_to_dir(299.9, 100.0).unwrap();
        assert!(
            right.x > 0.5,
            "looking North, East is on the right: {right}"
        );
    }

    #[test]
    fn cubemap_faces_in_scene_frame_order() {
        let c = cam(Projection::Cubemap, 0, 64);
        let centres = [
            DVec3::X,
            -DVec3::X,
            DVec3::Y,
            -DVec3::Y,
            DVec3::Z,
            -DVec3::Z,
        ];
        for (f, want) in centres.iter().enumerate() {
            let d = c.pixel_to_dir(f as f64 * 64.0 + 32.0, 32.0).unwrap();
            assert!(
                (scene_from_enu(d) - *want).length() < 1e-12,
                "face {f}: {d}"
            );
        }
        // +Y (Up) is the zenith; +Z is South.
        assert!((c.pixel_to_dir(2.0 * 64.0 + 32.0, 32.0).unwrap().z - 1.0).abs() < 1e-12);
        assert!((c.pixel_to_dir(4.0 * 64.0 + 32.0, 32.0).unwrap().y + 1.0).abs() < 1e-12);
    }

    #[test]
    fn round_trips_direction_pixel_direction() {
        for p in [
            Projection::Fisheye,
            Projection::Equirect,
            Projection::Perspective,
            Projection::Cubemap,
        ] {
            let c = cam(p, 240, 120);
            let (w, h) = c.image_size();
            let mut n = 0;
            for j in 0..h {
                for i in 0..w {
                    let (px, py) = (i as f64 + 0.5, j as f64 + 0.5);
                    let Some(d) = c.pixel_to_dir(px, py) else {
                        continue;
                    };
                    assert!((d.length() - 1.0).abs() < 1e-9);
                    let (qx, qy) = c.dir_to_pixel(d).expect("visible");
                    let back = c.pixel_to_dir(qx, qy).unwrap();
                    assert!((back - d).length() < 1e-9, "{p:?} {i},{j}");
                    // The pixel itself round-trips (except at the equirect poles and the fisheye nadir ring).
                    if (p != Projection::Equirect || (j > 0 && j + 1 < h))
                        && (p != Projection::Fisheye || d.z > -0.99)
                    {
                        assert!(
                            (qx - px).abs() < 1e-6 && (qy - py).abs() < 1e-6,
                            "{p:?} {i},{j}: {qx},{qy}"
                        );
                    }
                    n += 1;
                }
            }
            assert!(n > 1000);
        }
    }

    #[test]
    fn pixel_solid_angles_sum_to_the_covered_sphere() {
        let sum = |c: &Camera| {
            let (w, h) = c.image_size();
            let mut s = 0.0;
            for j in 0..h {
                for i in 0..w {
                    s += c.pixel_solid_angle(i as f64 + 0.5, j as f64 + 0.5);
                }
            }
            s
        };
        let four_pi = 4.0 * std::f64::consts::PI;
        let e = sum(&cam(Projection::Equirect, 90, 45));
        assert!((e / four_pi - 1.0).abs() < 1e-9, "{e}");
        let c = sum(&cam(Projection::Cubemap, 0, 64));
        assert!((c / four_pi - 1.0).abs() < 1e-3, "{c}");
        // Fisheye, square: the disk to the horizon is the hemisphere.
        let mut f = cam(Projection::Fisheye, 400, 400);
        let (w, h) = f.image_size();
        let mut hemi = 0.0;
        for j in 0..h {
            for i in 0..w {
                let (px, py) = (i as f64 + 0.5, j as f64 + 0.5);
                if f.pixel_to_dir(px, py).unwrap().z >= 0.0 {
                    hemi += f.pixel_solid_angle(px, py);
                }
            }
        }
        assert!(
            (hemi / (2.0 * std::f64::consts::PI) - 1.0).abs() < 5e-3,
            "{hemi}"
        );
        // Perspective: a 90° square frame covers 4π/6 (one cube face).
        f = cam(Projection::Perspective, 200, 200);
        f.fov_deg = 90.0;
        let p = sum(&f);
        assert!((p / (four_pi / 6.0) - 1.0).abs() < 1e-3, "{p}");
    }

    #[test]
    fn validation_names_fields() {
        let mut c = Camera {
            fov_deg: 0.0,
            ..Camera::default()
        };
        assert_eq!(c.validate().unwrap_err().field, "camera.fov_deg");
        c.fov_deg = 200.0;
        assert_eq!(c.validate().unwrap_err().field, "camera.fov_deg");
        c.fov_deg = 90.0;
        c.width = 0;
        assert_eq!(c.validate().unwrap_err().field, "camera.width");
        c.width = 100_000;
        c.height = 100_000;
        assert!(c.validate().is_err());
        c.width = 8192;
        c.height = 8192;
        assert!(c.validate().is_ok());
    }
}
