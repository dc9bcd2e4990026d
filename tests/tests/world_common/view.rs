//! Cameras of the world tests.

use glam::DVec3;
use himmel_skymodel::{Projection, Scene};

/// A scene at `time` in Munich with a perspective camera at `eye` looking
/// at `at` (world frame, metres), `size` pixels, vertical field `fov`
/// degrees; no effects or world yet.
pub fn munich_view(
    time: &str,
    eye: [f64; 3],
    at: [f64; 3],
    up: [f64; 3],
    size: (u32, u32),
    fov: f64,
) -> Scene {
    let mut s = Scene::default();
    s.time.utc = time.into();
    s.observer.lat_deg = 48.14;
    s.observer.lon_deg = 11.58;
    s.camera.projection = Projection::Perspective;
    s.camera.width = size.0;
    s.camera.height = size.1;
    s.camera.fov_deg = fov;
    s.camera.position_m = Some(eye);
    s.camera.look_at_m = Some(at);
    s.camera.up = Some(up);
    s
}

/// Where the ray through pixel (x, y) meets the ground y = 0 (world frame).
pub fn ground_point(s: &Scene, x: usize, y: usize) -> Option<DVec3> {
    let d = s.camera.pixel_to_dir(x as f64 + 0.5, y as f64 + 0.5)?;
    let d = himmel_skymodel::projection::scene_from_enu(d);
    let eye = s.camera.eye_m();
    (d.y < 0.0).then(|| eye + d * (-eye.y / d.y))
}
