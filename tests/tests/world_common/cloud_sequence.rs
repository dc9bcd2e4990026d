//! The scene and instants of the cloud-sequence tests (`cloud_amortised`,
//! `cloud_temporal`, `wgpu_cloud_temporal`).

use himmel_skymodel::atmosphere::LutConfig;
use himmel_skymodel::{Effect, Projection, Scene};

/// Cumulus (coverage 0.5) over Munich on a summer morning, fisheye
/// `n` × `n`, the low layer marched with `stride`, wind `wind` m/s
/// towards the east.
pub fn scene(n: u32, stride: u32, utc: &str, wind: f64) -> Scene {
    let mut s = Scene::default();
    s.time.utc = utc.into();
    s.observer.lat_deg = 48.14;
    s.observer.lon_deg = 11.58;
    s.effects = vec![Effect::Atmosphere, Effect::Sun, Effect::Clouds];
    s.camera.projection = Projection::Fisheye;
    s.camera.width = n;
    s.camera.height = n;
    s.lut = LutConfig::small();
    s.clouds.low.coverage = 0.5;
    s.clouds.low.wind_m_s = [wind, 0.0];
    s.clouds.low.march_stride = stride;
    s
}

/// `2024-06-21T08:00:00Z` plus `k` × `step_s` seconds (under an hour).
pub fn utc(k: u32, step_s: u32) -> String {
    let t = k * step_s;
    format!("2024-06-21T08:{:02}:{:02}Z", t / 60, t % 60)
}

/// [`scene`] without its clouds (the clear sky that tells the cloud
/// pixels of a frame).
pub fn clear(n: u32, utc: &str) -> Scene {
    let mut s = scene(n, 1, utc, 0.0);
    s.effects.retain(|e| *e != Effect::Clouds);
    s
}
