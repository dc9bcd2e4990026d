//! The wgpu world renderer against Mitsuba 3 (issue 14): each case of
//! `tools/world_cases.json` — the three procedural worlds at a high Sun, a
//! low Sun and a moonlit night — rendered here on the adapter at hand
//! (lavapipe in CI) and compared with the path-traced reference of
//! `tests/fixtures/world_ref/` (direct light: Sun or Moon + sky, shadows):
//!
//! * the luminance-weighted mean relative error Σ|ΔY| / ΣY_ref over the
//!   directly lit pixels and over the sky-lit-only (shadowed) pixels of
//!   the reference's masks;
//! * FLIP (`nv-flip`) of the tone-mapped images.
//!
//! `cargo test -p himmel-tests --test world_mitsuba -- --nocapture` prints
//! the table the README quotes. The bounds are the goals (3 % lit,
//! 5 % sky-lit, FLIP 0.05) for every case.

mod wgpu_common;
mod world_common;

use himmel_skymodel::Scene;
use serde_json::Value;
use world_common::cases::root;
use world_common::metrics::{flip, mask_channel, mean_relative_error, RgbImage};
use world_common::metrics::{SKYLIT, SUNLIT};
use world_common::render::{render_world, world_reference};

/// The scene of a case (as its `himmel_args`).
fn case_scene(c: &Value) -> Scene {
    let mut s = world_common::cases::case_scene(c);
    // The case's own lighting settings (the sun room's: its cells in
    // parts, for the window), then others to measure them:
    // HIMMEL_WORLD_LIGHTING='{"sky": {"interleave": 2, "directions": 256}}'
    // (the scene file's `lighting` object).
    if let Ok(json) = std::env::var("HIMMEL_WORLD_LIGHTING") {
        s.lighting =
            serde_json::from_str(&json).expect("HIMMEL_WORLD_LIGHTING: a `lighting` object");
        s.lighting
            .validate()
            .expect("HIMMEL_WORLD_LIGHTING in range");
    }
    s
}

/// (case, lit error, sky-lit error, FLIP).
fn measure(c: &Value) -> (String, f64, f64, f64) {
    let name = c["name"].as_str().unwrap().to_string();
    let out = render_world(&mut wgpu_common::gpu(), &case_scene(c));
    if let Some(d) = std::env::var_os("HIMMEL_TEST_OUT") {
        let p = std::path::Path::new(&d).join(format!("{name}.exr"));
        himmel_cpu::output::write_exr(&p, &out.image).unwrap();
    }
    let img = RgbImage::from(out.image);
    let (reference, mask) = world_reference(&name);
    let lit = mean_relative_error(&img, &reference, &mask_channel(&mask, SUNLIT));
    let sky = mean_relative_error(&img, &reference, &mask_channel(&mask, SKYLIT));
    let f = flip(&img, &reference, None);
    if let Some(d) = std::env::var_os("HIMMEL_TEST_OUT") {
        // The FLIP map, 0 black to 1 white, where the error lies.
        let map = world_common::metrics::flip_map(&img, &reference);
        let bytes: Vec<u8> = map.iter().map(|e| (e * 255.0).round() as u8).collect();
        let p = std::path::Path::new(&d).join(format!("{name}_flip.png"));
        image::GrayImage::from_raw(img.width as u32, img.height as u32, bytes)
            .unwrap()
            .save(p)
            .unwrap();
    }
    (name, lit, sky, f)
}

#[test]
fn worlds_against_mitsuba() {
    let cases: Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("tools/world_cases.json")).unwrap(),
    )
    .unwrap();
    // The goals: lit 3 %, sky-lit 5 %, FLIP 0.05.
    let goal = (0.03, 0.05, 0.05);
    let bounds = |name: &str| -> (f64, f64, f64) {
        match name {
            "sun_room_high" | "sun_room_low" | "sun_room_night" => goal,
            "atrium_high" | "atrium_low" | "atrium_night" => goal,
            "plane_and_boxes_high" | "plane_and_boxes_low" | "plane_and_boxes_night" => goal,
            other => panic!("no bounds for case {other}"),
        }
    };
    println!("| case | lit pixels | sky-lit pixels | FLIP |");
    println!("|---|---|---|---|");
    let mut failures = Vec::new();
    let only = std::env::var("HIMMEL_WORLD_CASE").ok();
    for c in cases["cases"].as_array().unwrap() {
        if only.as_deref().is_some_and(|o| c["name"] != o) {
            continue;
        }
        let (name, lit, sky, f) = measure(c);
        println!(
            "| {name} | {:.2} % | {:.2} % | {f:.3} |",
            lit * 100.0,
            sky * 100.0
        );
        let (bl, bs, bf) = bounds(&name);
        if !(lit <= bl && sky <= bs && f <= bf) {
            failures.push(format!(
                "{name}: lit {lit:.4} (≤ {bl}), sky-lit {sky:.4} (≤ {bs}), FLIP {f:.3} (≤ {bf})"
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The README gallery's sun room (`tools/gallery.sh`,
/// `--scene tools/sun_room_lighting.json`) uses the sky-light settings
/// its cases are measured with.
#[test]
fn the_gallery_sun_room_has_the_cases_settings() {
    let read = |p: &str| -> Value {
        serde_json::from_str(&std::fs::read_to_string(root().join(p)).unwrap()).unwrap()
    };
    let gallery = read("tools/sun_room_lighting.json");
    let cases = read("tools/world_cases.json");
    for c in cases["cases"].as_array().unwrap() {
        if c["name"].as_str().unwrap().starts_with("sun_room") {
            assert_eq!(c["lighting"], gallery["lighting"], "{}", c["name"]);
        }
    }
}
