//! The scene of a reference case (an entry of `tools/world_cases.json` or
//! `tools/godrays_cases.json`), as the reference tools render it.

use himmel_skymodel::{Effect, Projection, Scene, WorldSpec};
use serde_json::Value;

/// The repository's root: the cases' files, their worlds and the
/// references are named relative to it.
pub fn root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The case `name` of the cases file `file` (relative to the root, e.g.
/// `tools/world_cases.json`): an entry of its `cases` array.
pub fn case(file: &str, name: &str) -> Value {
    let cases: Value =
        serde_json::from_str(&std::fs::read_to_string(root().join(file)).unwrap()).unwrap();
    cases["cases"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == name)
        .unwrap_or_else(|| panic!("no case {name} in {file}"))
        .clone()
}

/// A JSON array of three numbers.
pub fn triple(v: &Value) -> [f64; 3] {
    [0, 1, 2].map(|k| v[k].as_f64().expect("a number"))
}

/// The scene of case `c`: its instant, site, perspective camera, the sky
/// and world passes (atmosphere, Sun, Moon, stars, planets, Milky Way,
/// world, shadows), its world file and ground, and its own `lighting`
/// object when it has one.
pub fn case_scene(c: &Value) -> Scene {
    let mut s = Scene::default();
    s.time.utc = c["time"].as_str().expect("a case's time").into();
    s.observer.lat_deg = c["lat"].as_f64().expect("a case's lat");
    s.observer.lon_deg = c["lon"].as_f64().expect("a case's lon");
    s.observer.elevation_m = c["elevation_m"].as_f64().unwrap_or(0.0);
    let cam = &c["camera"];
    s.camera.projection = Projection::Perspective;
    s.camera.width = cam["width"].as_u64().expect("camera width") as u32;
    s.camera.height = cam["height"].as_u64().expect("camera height") as u32;
    s.camera.fov_deg = cam["fov_deg"].as_f64().expect("camera fov");
    s.camera.position_m = Some(triple(&cam["position_m"]));
    s.camera.look_at_m = Some(triple(&cam["look_at_m"]));
    s.camera.up = Some(triple(&cam["up"]));
    s.effects = vec![
        Effect::Atmosphere,
        Effect::Sun,
        Effect::Moon,
        Effect::Stars,
        Effect::Planets,
        Effect::Milkyway,
        Effect::World,
        Effect::Shadows,
    ];
    // The references' sky is Himmel's default atmosphere (ground albedo 0.2).
    assert_eq!(
        c["ground_albedo"].as_f64(),
        Some(s.atmosphere.ground_albedo)
    );
    s.world = Some(WorldSpec {
        gltf: c["world"].as_str().expect("a case's world").into(),
        ground: c["ground"].as_bool().unwrap_or(false),
    });
    if let Some(l) = c.get("lighting") {
        s.lighting = serde_json::from_value(l.clone()).expect("a case's `lighting` object");
    }
    s
}
