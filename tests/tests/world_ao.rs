//! Ambient occlusion (`lighting.ao`, issue 16) against Mitsuba 3: the wgpu
//! `ao` pass's AO image (`WgpuRenderer::ao_image`) for the atrium and the
//! plane with boxes (the cameras of `tools/world_cases.json`), compared
//! with `tests/fixtures/ao_ref/` (`tools/ao_reference.py`: the
//! cosine-weighted unoccluded fraction within the same radius, 4096 rays
//! per pixel, noise ≤ 0.008) by the mean absolute error over the
//! reference's geometry pixels (whole pixel on one plane, eroded by one
//! pixel).
//!
//! Bounds: `gtao` ≤ 0.05 (the goal) and its measured error plus
//! 0.01; `ssao`, `hbao` and `gtao` with the visibility bitmask (0.5 m)
//! at their measured error
//! plus 0.01 (published in the README; its point test reads lighter than
//! the ray-traced reference). `cargo test -p himmel-tests --test world_ao
//! -- --nocapture` prints the table the README quotes;
//! `HIMMEL_AO='{"method": "gtao", "slices": 2}'` (a `lighting.ao` object)
//! measures other settings too (printed, not asserted).

mod wgpu_common;
mod world_common;

use himmel_skymodel::{AoMethod, AoSettings, Effect, Scene};
use himmel_wgpu::WgpuRenderer;
use serde_json::Value;
use world_common::cases::root;
use world_common::metrics::{flip, mask_channel, mean_relative_error, read_exr, RgbImage};
use world_common::metrics::{GEOMETRY, SKYLIT};
use world_common::render::{render_world, world_reference};

const CASES: [&str; 2] = ["atrium_high", "plane_and_boxes_high"];

/// `ssao`'s bounds per case: measured with the defaults (0.0368, 0.0142)
/// plus 0.01.
const SSAO_BOUND: [f64; 2] = [0.047, 0.025];

/// The visibility bitmask's thickness measured, metres.
const BITMASK_THICKNESS_M: f64 = 0.5;

/// The bitmask's bounds per case: measured (0.0298, 0.0076) plus 0.01.
const BITMASK_BOUND: [f64; 2] = [0.040, 0.018];

/// `hbao`'s bounds per case: measured with the defaults (0.0288, 0.0065)
/// plus 0.01.
const HBAO_BOUND: [f64; 2] = [0.039, 0.017];

/// `gtao`'s bounds per case under the 0.05: measured with the
/// defaults (0.0279, 0.0075) plus 0.01, so that a change for the worse
/// fails.
const GTAO_BOUND: [f64; 2] = [0.038, 0.018];

struct Measured {
    mae: f64,
    bias: f64,
    /// The mean AO over the compared pixels.
    mean: f64,
    /// FLIP of the AO image against the reference's, both as grey images
    /// (the reference's exposure), over the compared pixels.
    flip: f64,
    ms: f64,
    pixels: usize,
}

/// The case `name` of `tools/world_cases.json`.
fn case(name: &str) -> Value {
    world_common::cases::case("tools/world_cases.json", name)
}

fn measure(name: &str, settings: AoSettings) -> Measured {
    let c = case(name);
    let dir = root().join("tests/fixtures/ao_ref");
    let info: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join(format!("{name}_ao.json"))).unwrap(),
    )
    .unwrap();
    let radius = info["radius_m"].as_f64().unwrap();
    let mut s = world_common::cases::case_scene(&c);
    s.effects.push(Effect::Ao);
    s.lighting.ao = AoSettings {
        radius_m: Some(radius),
        ..settings
    };
    s.lighting.validate().unwrap();
    let (out, img) = {
        let mut r = wgpu_common::gpu();
        let out = render_world(&mut r, &s);
        (out, r.ao_image().unwrap().expect("the ao pass ran"))
    };
    if let Some(d) = std::env::var_os("HIMMEL_TEST_OUT") {
        // AO in R, G, B for inspection: `<case>_<method>_ao.exr`.
        let method = format!("{:?}", settings.method).to_lowercase();
        let p = std::path::Path::new(&d).join(format!("{name}_{method}_ao.exr"));
        let hdr = himmel_skymodel::HdrImage {
            width: img.width as usize,
            height: img.height as usize,
            pixels: img.ao.iter().map(|&a| [a; 3]).collect(),
            valid: vec![true; img.ao.len()],
        };
        himmel_cpu::output::write_exr(&p, &hdr).unwrap();
    }
    let stat = out.passes.iter().find(|p| p.name == "ao").unwrap();
    assert!(stat.ran, "{:?}", stat.reason);
    assert_eq!(img.radius_m, radius as f32);
    let reference = read_exr(dir.join(format!("{name}_ao.exr"))).unwrap();
    let mask = mask_channel(
        &read_exr(dir.join(format!("{name}_ao_mask.exr"))).unwrap(),
        GEOMETRY,
    );
    assert_eq!(
        (img.width as usize, img.height as usize),
        (reference.width, reference.height)
    );
    let (mut sum, mut bias, mut total, mut n) = (0.0, 0.0, 0.0, 0usize);
    for ((a, r), m) in img.ao.iter().zip(&reference.pixels).zip(&mask) {
        if *m {
            let d = *a as f64 - r[0] as f64;
            sum += d.abs();
            bias += d;
            total += *a as f64;
            n += 1;
        }
    }
    assert!(n > 10_000, "{name}: {n} geometry pixels");
    // The bent normal: unit, and on open ground (AO ≈ 1 in the reference;
    // the worlds' floors face +y) the normal itself.
    let (mut open, mut tilted) = (0usize, 0.0f64);
    for ((b, r), m) in img.bent_normal.iter().zip(&reference.pixels).zip(&mask) {
        if *m {
            let len = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-3, "{name}: |bent normal| {len}");
            if r[0] > 0.999 && b[1] > 0.5 {
                open += 1;
                tilted = tilted.max((b[1] as f64).clamp(-1.0, 1.0).acos().to_degrees());
            }
        }
    }
    println!("{name}: {open} open floor pixels, bent normal at most {tilted:.1}° off +y");
    // Measured: gtao 5.4° (atrium), 6.0° (plane and boxes); ssao 1.5°, 4.2°.
    assert!(open > 10_000, "{name}: {open} open floor pixels");
    assert!(
        tilted < 8.0,
        "{name}: bent normal {tilted:.1}° off the open floor's normal"
    );
    assert!(img.ao.iter().all(|a| (0.0..=1.0).contains(a)));
    Measured {
        mae: sum / n as f64,
        bias: bias / n as f64,
        mean: total / n as f64,
        flip: {
            let grey = |v: Vec<f32>| RgbImage {
                width: reference.width,
                height: reference.height,
                pixels: v.into_iter().map(|a| [a; 3]).collect(),
            };
            let r = grey(reference.pixels.iter().map(|p| p[0]).collect());
            flip(&grey(img.ao.clone()), &r, Some(&mask))
        },
        ms: stat.ms.unwrap_or(0.0),
        pixels: n,
    }
}

fn row(name: &str, label: &str, m: &Measured) {
    println!(
        "| {name} | {label} | {:.4} | {:+.4} | {:.3} | {:.1} | {} |",
        m.mae, m.bias, m.flip, m.ms, m.pixels
    );
}

#[test]
fn ao_against_mitsuba() {
    println!("| case | method | MAE | mean error | FLIP | ms | pixels |");
    println!("|---|---|---|---|---|---|---|");
    let gtao = AoSettings::default();
    let ssao = AoSettings {
        method: AoMethod::Ssao,
        ..AoSettings::default()
    };
    let hbao = AoSettings {
        method: AoMethod::Hbao,
        ..AoSettings::default()
    };
    let bitmask = AoSettings {
        thickness_m: Some(BITMASK_THICKNESS_M),
        ..AoSettings::default()
    };
    let thick = AoSettings {
        thickness_m: Some(100.0),
        ..AoSettings::default()
    };
    let custom: Option<AoSettings> = std::env::var("HIMMEL_AO")
        .ok()
        .map(|j| serde_json::from_str(&j).expect("HIMMEL_AO: a `lighting.ao` object"));
    // The first render compiles the pipelines: not timed.
    measure(CASES[0], gtao);
    for (k, name) in CASES.into_iter().enumerate() {
        let g = measure(name, gtao);
        row(name, "gtao", &g);
        let s = measure(name, ssao);
        row(name, "ssao", &s);
        let h = measure(name, hbao);
        row(name, "hbao", &h);
        let b = measure(name, bitmask);
        row(name, "gtao, bitmask 0.5 m", &b);
        let t = measure(name, thick);
        row(name, "gtao, bitmask 100 m", &t);
        if let Some(c) = custom {
            row(name, &format!("{c:?}"), &measure(name, c));
        }
        assert!(g.mae <= 0.05, "{name}: gtao MAE {:.4} > 0.05", g.mae);
        // A thick enough bitmask is the horizon (32 sectors against the
        // exact arcs, no fade at R); a thinner one only opens sky.
        assert!(
            (t.mean - g.mean).abs() < 0.01,
            "{name}: bitmask 100 m mean {:.4}, gtao {:.4}",
            t.mean,
            g.mean
        );
        assert!(
            b.mean >= t.mean,
            "{name}: bitmask {BITMASK_THICKNESS_M} m mean {:.4} below 100 m {:.4}",
            b.mean,
            t.mean
        );
        for (method, m, bound) in [
            ("gtao", &g, GTAO_BOUND[k]),
            ("ssao", &s, SSAO_BOUND[k]),
            ("bitmask", &b, BITMASK_BOUND[k]),
            ("hbao", &h, HBAO_BOUND[k]),
        ] {
            assert!(
                m.mae <= bound,
                "{name}: {method} MAE {:.4} > {bound}",
                m.mae
            );
        }
    }
}

/// The scene of case `c` with the ao pass or without it (`ao`), with the
/// Sun or without it (`sun`).
fn lit_scene(c: &Value, ao: bool, sun: bool) -> Scene {
    let mut s = world_common::cases::case_scene(c);
    if ao {
        s.effects.push(Effect::Ao);
    }
    if !sun {
        s.effects.retain(|e| *e != Effect::Sun);
    }
    s
}

/// The lit image of the atrium's case with and without the ao pass, with
/// the Sun or without it (`sun`), by renderer `r`.
fn lit(r: &mut WgpuRenderer, ao: bool, sun: bool) -> Vec<[f32; 3]> {
    let out = render_world(r, &lit_scene(&case("atrium_high"), ao, sun));
    let stat = out.passes.iter().find(|p| p.name == "ao").unwrap();
    assert_eq!(stat.ran, ao, "{:?}", stat.reason);
    if !ao {
        assert_eq!(stat.reason.as_deref(), Some("not requested"));
    }
    out.image.pixels
}

/// AO multiplies only the sky's light: it darkens (never brightens), and
/// never takes away more than the sky's light of the pixel (the same frame
/// without the Sun; its sky cells differ only by the Sun's aureole).
#[test]
fn ao_darkens_only_the_sky_light() {
    // One renderer with the Sun, one without: each keeps its sky light
    // between its two frames.
    let mut r = WgpuRenderer::new(None).unwrap();
    let (sun_off, sun_on) = (lit(&mut r, false, true), lit(&mut r, true, true));
    let mut r = WgpuRenderer::new(None).unwrap();
    let sky = lit(&mut r, false, false);
    let y = |p: &[f32; 3]| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64;
    let (mut changed, mut worst, mut sun_share) = (0usize, 0.0f64, 0.0f64);
    for k in 0..sun_off.len() {
        let (a, b, c) = (y(&sun_off[k]), y(&sun_on[k]), y(&sky[k]));
        assert!(b <= a * (1.0 + 1e-5) + 1e-6, "pixel {k}: {b} > {a}");
        if a - b > 1e-3 * a {
            changed += 1;
            worst = worst.max((a - b) / c.max(1e-9));
            sun_share = sun_share.max((a - c) / a);
        }
    }
    println!(
        "pixels darkened by > 0.1 %: {changed}; the most taken from one, in units of its sky light: {worst:.3}; the Sun's largest share of a darkened pixel: {sun_share:.2}"
    );
    assert!(changed > 100, "AO changed {changed} pixels");
    assert!(sun_share > 0.5, "AO darkens sunlit pixels too");
    assert!(worst <= 1.05, "AO took {worst} × the sky's light");
}

/// The full render against the world references (`tests/fixtures/world_ref`,
/// Mitsuba `max_depth` 2): AO on the sky-lit (shadowed) pixels must not
/// move the render away from the reference by more than 0.5 % of their
/// luminance (it darkens only where it finds more occlusion than the sky's
/// visibility maps).
#[test]
fn ao_in_the_lit_render_against_mitsuba() {
    for name in CASES {
        let c = case(name);
        let (reference, mask) = world_reference(name);
        let mask = mask_channel(&mask, SKYLIT);
        let mut errors = Vec::new();
        for ao in [false, true] {
            let out = render_world(&mut wgpu_common::gpu(), &lit_scene(&c, ao, true));
            if let Some(d) = std::env::var_os("HIMMEL_TEST_OUT") {
                let p = std::path::Path::new(&d).join(format!("{name}_lit_ao{}.exr", ao as u8));
                himmel_cpu::output::write_exr(&p, &out.image).unwrap();
            }
            let img = RgbImage::from(out.image);
            errors.push(mean_relative_error(&img, &reference, &mask));
        }
        println!(
            "{name}: sky-lit error against Mitsuba without AO {:.2} %, with gtao (default radius) {:.2} %",
            errors[0] * 100.0,
            errors[1] * 100.0
        );
        assert!(errors[1] <= errors[0] + 0.005, "{name}: {errors:?}");
    }
}
