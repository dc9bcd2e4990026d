//! Screen-space reflections (`lighting.ssr`, issue 16) against Mitsuba 3:
//! the plane with boxes on a polished metal floor of roughness 0.05 and 0.3
//! (`tools/ssr_cases.json`, 240 × 135), rendered with and without the `ssr`
//! pass, against `tests/fixtures/ssr_ref/` (`tools/ssr_reference.py`:
//! Mitsuba's `path`, max_depth 3, the same sky and Sun).
//!
//! The error is `mean_relative_error` (Σ|ΔY| / ΣY_ref) of the floor's
//! radiance — all of it the metal's specular reflection — over the pixels
//! whose reflected ray meets geometry on screen: the reference's mask G
//! (floor, the mirror ray meets geometry, eroded by one pixel) and the
//! pass's confidence ≥ 0.5 (`WgpuRenderer::ssr_image`). The same pixels
//! with the pass off (the prefiltered sky only, which the world's
//! visibility maps darken where the boxes hide it) show what it gains.
//!
//! Bounds: the 15 % and the measured error plus 0.02 per case; the
//! pass must at least halve the error of the sky-only render.
//! `cargo test -p himmel-tests --test world_ssr -- --nocapture` prints the
//! table the README quotes; `HIMMEL_SSR='{"samples": 16}'` (a
//! `lighting.ssr` object) measures other settings too (printed, not
//! asserted).

mod wgpu_common;
mod world_common;

use himmel_skymodel::{Effect, SkyRenderer, SkyState, SsrSettings};
use himmel_wgpu::WgpuRenderer;
use serde_json::Value;
use world_common::cases::{case, root};
use world_common::metrics::{flip, mask_channel, mean_relative_error, read_exr, RgbImage, SKYLIT};
use world_common::render::render_world;

const CASES: [&str; 2] = ["glossy_floor_005", "glossy_floor_030"];

/// The measured errors with the defaults plus 0.02 (so that a change for
/// the worse fails), under the 0.15: measured 0.0532 and 0.0988.
const BOUND: [f64; 2] = [0.074, 0.119];

/// The least share of the reference's reflecting pixels (the mirror ray
/// meets geometry) that the pass must reach with confidence ≥ 0.5.
const HITS: [f64; 2] = [0.8, 0.5];

struct Frame {
    image: RgbImage,
    ms: f64,
    confidence: Option<Vec<f32>>,
}

/// The case's frame by `r`, with the ssr pass (`Some`) or without.
fn frame(r: &mut WgpuRenderer, c: &Value, ssr: Option<SsrSettings>) -> Frame {
    let mut s = world_common::cases::case_scene(c);
    if let Some(q) = ssr {
        s.effects.push(Effect::Ssr);
        s.lighting.ssr = q;
    }
    s.lighting.validate().unwrap();
    let out = render_world(r, &s);
    let stat = out.passes.iter().find(|p| p.name == "ssr").unwrap();
    assert_eq!(stat.ran, ssr.is_some(), "{:?}", stat.reason);
    assert_eq!(out.passes.iter().filter(|p| p.name == "ssr").count(), 1);
    let confidence = ssr.map(|_| r.ssr_image().unwrap().expect("ran").confidence);
    let image = RgbImage::from(out.image);
    if let Some(d) = std::env::var_os("HIMMEL_TEST_OUT") {
        let tag = if ssr.is_some() { "ssr" } else { "env" };
        let name = c["name"].as_str().unwrap();
        let p = std::path::Path::new(&d).join(format!("{name}_{tag}.exr"));
        let hdr = himmel_skymodel::HdrImage {
            width: image.width,
            height: image.height,
            pixels: image.pixels.clone(),
            valid: vec![true; image.pixels.len()],
        };
        himmel_cpu::output::write_exr(&p, &hdr).unwrap();
        if let Some(c) = &confidence {
            let p = std::path::Path::new(&d).join(format!("{name}_confidence.exr"));
            let hdr = himmel_skymodel::HdrImage {
                pixels: c.iter().map(|&v| [v; 3]).collect(),
                ..hdr
            };
            himmel_cpu::output::write_exr(&p, &hdr).unwrap();
        }
    }
    Frame {
        image,
        ms: stat.ms.unwrap_or(0.0),
        confidence,
    }
}

struct Measured {
    on: f64,
    off: f64,
    /// FLIP of the tone-mapped image against the reference's over the
    /// compared pixels, with the pass and without it.
    flip_on: f64,
    flip_off: f64,
    ms: f64,
    pixels: usize,
    /// The reference's pixels whose mirror ray meets geometry.
    want: usize,
}

fn measure(r: &mut WgpuRenderer, name: &str, settings: SsrSettings) -> Measured {
    let c = case("tools/ssr_cases.json", name);
    let dir = root().join("tests/fixtures/ssr_ref");
    let reference = read_exr(dir.join(format!("{name}.exr"))).unwrap();
    let reflects = mask_channel(
        &read_exr(dir.join(format!("{name}_mask.exr"))).unwrap(),
        SKYLIT,
    );
    let on = frame(r, &c, Some(settings));
    let off = frame(r, &c, None);
    let conf = on.confidence.as_ref().unwrap();
    assert!(conf.iter().all(|c| (0.0..=1.0).contains(c)));
    let mask: Vec<bool> = reflects
        .iter()
        .zip(conf)
        .map(|(m, c)| *m && *c >= 0.5)
        .collect();
    let pixels = mask.iter().filter(|m| **m).count();
    let want = reflects.iter().filter(|m| **m).count();
    Measured {
        on: mean_relative_error(&on.image, &reference, &mask),
        off: mean_relative_error(&off.image, &reference, &mask),
        flip_on: flip(&on.image, &reference, Some(&mask)),
        flip_off: flip(&off.image, &reference, Some(&mask)),
        ms: on.ms,
        pixels,
        want,
    }
}

#[test]
fn ssr_against_mitsuba() {
    println!("| case | settings | error (ssr) | error (sky only) | FLIP (ssr) | FLIP (sky only) | ms | pixels hit / reflecting |");
    println!("|---|---|---|---|---|---|---|---|");
    let custom: Option<SsrSettings> = std::env::var("HIMMEL_SSR")
        .ok()
        .map(|j| serde_json::from_str(&j).expect("HIMMEL_SSR: a `lighting.ssr` object"));
    let mut guard = wgpu_common::gpu();
    let r = &mut *guard;
    let defaults = SsrSettings {
        history: false,
        ..SsrSettings::default()
    };
    // The first render compiles the pipelines: not timed.
    measure(r, CASES[0], defaults);
    for (k, name) in CASES.into_iter().enumerate() {
        let m = measure(r, name, defaults);
        println!(
            "| {name} | defaults | {:.4} | {:.4} | {:.3} | {:.3} | {:.1} | {} / {} |",
            m.on, m.off, m.flip_on, m.flip_off, m.ms, m.pixels, m.want
        );
        if let Some(c) = custom {
            let x = measure(r, name, c);
            println!(
                "| {name} | {c:?} | {:.4} | {:.4} | {:.3} | {:.3} | {:.1} | {} / {} |",
                x.on, x.off, x.flip_on, x.flip_off, x.ms, x.pixels, x.want
            );
        }
        // The pass finds most of what the reference's mirror rays meet
        // (at roughness 0.3 the lobe is wide: fewer pixels reach 0.5).
        assert!(
            m.pixels as f64 >= HITS[k] * m.want as f64,
            "{name}: the pass hit {} of {} pixels",
            m.pixels,
            m.want
        );
        assert!(m.on <= 0.15, "{name}: error {:.4} > 0.15", m.on);
        assert!(m.on <= BOUND[k], "{name}: error {:.4} > {}", m.on, BOUND[k]);
        assert!(
            m.on * 2.0 <= m.off,
            "{name}: ssr {:.4} vs sky only {:.4}",
            m.on,
            m.off
        );
        // Perceptually too: the reflections bring the image closer.
        assert!(
            m.flip_on < m.flip_off,
            "{name}: FLIP {:.3} with ssr, {:.3} without",
            m.flip_on,
            m.flip_off
        );
    }
}

/// With `history` (the default), the second frame of a sequence reads the
/// first frame's final image reprojected with its view-projection (here
/// the same camera): the stat says so, and the floor's error stays within
/// 0.01 of the first frame's (boxes are Lambertian: the reflections of
/// reflections the history adds are not on them).
#[test]
fn ssr_reads_the_previous_frame() {
    let name = CASES[0];
    let c = case("tools/ssr_cases.json", name);
    let dir = root().join("tests/fixtures/ssr_ref");
    let reference = read_exr(dir.join(format!("{name}.exr"))).unwrap();
    let reflects = mask_channel(
        &read_exr(dir.join(format!("{name}_mask.exr"))).unwrap(),
        SKYLIT,
    );
    let mut r = WgpuRenderer::new(None).unwrap();
    let mut s = world_common::cases::case_scene(&c);
    s.effects.push(Effect::Ssr);
    let world = himmel_world::gltf_io::load(&root().join(c["world"].as_str().unwrap())).unwrap();
    r.set_world(&world);
    let state = SkyState::at(&s).unwrap();
    let mut errors = Vec::new();
    for source in ["this frame", "the previous frame, reprojected"] {
        let out = r.render(&s, &state).unwrap();
        let stat = out.passes.iter().find(|p| p.name == "ssr").unwrap();
        let why = stat.reason.as_deref().unwrap_or("");
        assert!(stat.ran && why.ends_with(source), "{why}");
        let conf = r.ssr_image().unwrap().unwrap().confidence;
        let mask: Vec<bool> = reflects
            .iter()
            .zip(&conf)
            .map(|(m, c)| *m && *c >= 0.5)
            .collect();
        let img = RgbImage::from(out.image);
        errors.push(mean_relative_error(&img, &reference, &mask));
    }
    println!(
        "{name}: error {:.4} (this frame), {:.4} (history)",
        errors[0], errors[1]
    );
    assert!((errors[1] - errors[0]).abs() <= 0.01, "{errors:?}");
}

/// The pass runs only where it can show: not for a world without a smooth
/// material (the plane with boxes is all Lambertian), and not when
/// `max_roughness` lies below the floor's roughness.
#[test]
fn ssr_runs_only_for_smooth_materials() {
    let mut r = wgpu_common::gpu();
    let c = case("tools/ssr_cases.json", "glossy_floor_030");
    for (world, max) in [("plane_and_boxes.glb", 1.0), ("glossy_floor_030.glb", 0.2)] {
        let mut s = world_common::cases::case_scene(&c);
        s.effects.push(Effect::Ssr);
        s.lighting.ssr.max_roughness = max;
        let w =
            himmel_world::gltf_io::load(&root().join("tests/fixtures/worlds").join(world)).unwrap();
        r.set_world(&w);
        let out = r.render(&s, &SkyState::at(&s).unwrap()).unwrap();
        let stat = out.passes.iter().find(|p| p.name == "ssr").unwrap();
        assert!(!stat.ran, "{world}");
        let why = stat.reason.as_deref().unwrap_or("");
        assert!(why.contains("smooth enough"), "{world}: {why}");
    }
}
