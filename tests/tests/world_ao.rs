//! Ambient occlusion (`lighting.ao`, issue 16) against Mitsuba 3: the wgpu
//! `ao` pass's AO image (`WgpuRenderer::ao_image`) for the atrium and the
//! plane with boxes (the cameras of `tools/world_cases.json`), compared
//! with `tests/fixtures/ao_ref/` (`tools/ao_reference.py`: the
//! cosine-weighted unoccluded fraction within the same radius, 4096 rays
//! per pixel, noise ≤ 0.008) by the mean absolute error over the
//! reference's geometry pixels (whole pixel on one plane, eroded by one
//! pixel).
//!
//! Bounds: `gtao` ≤ 0.05 (the goal); `ssao` at its measured error
//! + 0.01 (published in the README; its point test reads lighter than the
//! ray-traced reference). `cargo test -p himmel-tests --test world_ao --
//! --nocapture` prints the table the README quotes; `HIMMEL_AO='{"method":
//! "gtao", "slices": 2}'` (a `lighting.ao` object) measures other settings
//! (printed, not asserted).

mod wgpu_common;
mod world_common;

use himmel_skymodel::{AoMethod, AoSettings, Effect, SkyRenderer, SkyState};
use serde_json::Value;
use world_common::metrics::{mask_channel, read_exr, GEOMETRY};

fn root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

const CASES: [&str; 2] = ["atrium_high", "plane_and_boxes_high"];

/// `ssao`'s bounds per case: measured (defaults) + 0.01.
const SSAO_BOUND: [f64; 2] = [0.05, 0.05];

struct Measured {
    mae: f64,
    bias: f64,
    ms: f64,
    pixels: usize,
}

fn case(name: &str) -> Value {
    let cases: Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("tools/world_cases.json")).unwrap(),
    )
    .unwrap();
    cases["cases"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == name)
        .unwrap()
        .clone()
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
    let world = himmel_world::gltf_io::load(&root().join(c["world"].as_str().unwrap())).unwrap();
    let state = SkyState::at(&s).unwrap();
    let (out, img) = {
        let mut r = wgpu_common::gpu();
        r.set_world(&world);
        let out = r.render(&s, &state).unwrap();
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
    let (mut sum, mut bias, mut n) = (0.0, 0.0, 0usize);
    for ((a, r), m) in img.ao.iter().zip(&reference.pixels).zip(&mask) {
        if *m {
            let d = *a as f64 - r[0] as f64;
            sum += d.abs();
            bias += d;
            n += 1;
        }
    }
    assert!(n > 10_000, "{name}: {n} geometry pixels");
    assert!(img.ao.iter().all(|a| (0.0..=1.0).contains(a)));
    Measured {
        mae: sum / n as f64,
        bias: bias / n as f64,
        ms: stat.ms.unwrap_or(0.0),
        pixels: n,
    }
}

fn row(name: &str, label: &str, m: &Measured) {
    println!(
        "| {name} | {label} | {:.4} | {:+.4} | {:.1} | {} |",
        m.mae, m.bias, m.ms, m.pixels
    );
}

#[test]
fn ao_against_mitsuba() {
    println!("| case | method | MAE | mean error | ms | pixels |");
    println!("|---|---|---|---|---|---|");
    let gtao = AoSettings::default();
    let ssao = AoSettings {
        method: AoMethod::Ssao,
        ..AoSettings::default()
    };
    let custom: Option<AoSettings> = std::env::var("HIMMEL_AO")
        .ok()
        .map(|j| serde_json::from_str(&j).expect("HIMMEL_AO: a `lighting.ao` object"));
    for (k, name) in CASES.into_iter().enumerate() {
        let g = measure(name, gtao);
        row(name, "gtao", &g);
        let s = measure(name, ssao);
        row(name, "ssao", &s);
        if let Some(c) = custom {
            row(name, &format!("{c:?}"), &measure(name, c));
        }
        assert!(g.mae <= 0.05, "{name}: gtao MAE {:.4} > 0.05", g.mae);
        assert!(
            s.mae <= SSAO_BOUND[k],
            "{name}: ssao MAE {:.4} > {}",
            s.mae,
            SSAO_BOUND[k]
        );
    }
}
