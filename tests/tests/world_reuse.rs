//! What the world renderer keeps between frames (sky light, visibility
//! maps, shadow cascades) must never change a frame: the atrium's case
//! rendered, then without the Sun (no cascades), then with it again by the
//! same renderer gives the first image again. (The cascades' reuse key once
//! outlived the cascades: the third frame had no Sun shadows, 541 % error
//! on the shadowed pixels against Mitsuba.)

mod world_common;

use himmel_skymodel::{Effect, SkyRenderer, SkyState};
use serde_json::Value;

fn root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

#[test]
fn a_frame_without_the_sun_between_changes_nothing() {
    let cases: Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("tools/world_cases.json")).unwrap(),
    )
    .unwrap();
    let c = cases["cases"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "atrium_high")
        .unwrap()
        .clone();
    let world = himmel_world::gltf_io::load(&root().join(c["world"].as_str().unwrap())).unwrap();
    let mut r = himmel_wgpu::WgpuRenderer::new(None).unwrap();
    r.set_world(&world);
    let mut images = Vec::new();
    for sun in [true, false, true] {
        let mut s = world_common::cases::case_scene(&c);
        s.camera.width = 160;
        s.camera.height = 90;
        if !sun {
            s.effects.retain(|e| *e != Effect::Sun);
        }
        let state = SkyState::at(&s).unwrap();
        let out = r.render(&s, &state).unwrap();
        let shadows = out.passes.iter().find(|p| p.name == "shadows").unwrap();
        println!("sun {sun}: shadows {} {:?}", shadows.ran, shadows.reason);
        images.push(out.image.pixels);
    }
    let y = |p: &[f32; 3]| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64;
    let worst = images[0]
        .iter()
        .zip(&images[2])
        .map(|(a, b)| (y(a) - y(b)).abs() / y(a).max(1e-9))
        .fold(0.0f64, f64::max);
    println!("largest relative difference, first and third frame: {worst:.2e}");
    assert!(worst < 1e-4, "{worst}");
    let darker = images[0]
        .iter()
        .zip(&images[1])
        .filter(|(a, b)| y(b) < 0.5 * y(a))
        .count();
    assert!(darker > 1000, "the Sun lit the first frame: {darker}");
}
