//! What the light-shaft reference tests share (`godrays_mitsuba`,
//! `godrays_froxel`): the cases of `tools/godrays_cases.json` as scenes,
//! their worlds with every surface black, and the fog's added radiance
//! measured against the references of `tests/fixtures/godrays_ref/`.

use himmel_skymodel::{Effect, FogSpec, GodraysSettings, PassStat, RenderOutput, Scene};
use serde_json::Value;

use super::metrics::{flip, mask_channel, mean_relative_error, read_exr, RgbImage, GEOMETRY};

/// The cases of `tools/godrays_cases.json`.
pub fn cases() -> Value {
    serde_json::from_str(&std::fs::read_to_string(root().join("tools/godrays_cases.json")).unwrap())
        .unwrap()
}

/// The workspace's root.
pub use super::cases::root;

/// The case's scene with its fog, and `godrays` when given.
pub fn case_scene(c: &Value, godrays: Option<GodraysSettings>) -> Scene {
    let mut s = super::cases::case_scene(c);
    let fog: FogSpec = serde_json::from_value(c["fog"].clone()).expect("a case's `fog`");
    s.fog = Some(fog);
    if let Some(g) = godrays {
        s.effects.push(Effect::Godrays);
        s.lighting.godrays = g;
    }
    s.validate().expect("a valid scene");
    s
}

/// The case's world with every surface black (as the reference's).
pub fn black_world(c: &Value) -> himmel_world::World {
    let mut w = himmel_world::gltf_io::load(&root().join(c["world"].as_str().unwrap())).unwrap();
    for m in &mut w.materials {
        m.base_color = [0.0, 0.0, 0.0, 1.0];
        m.base_color_texture = None;
        m.metallic = 0.0;
        m.roughness = 1.0;
        m.emissive = [0.0; 3];
    }
    w
}

fn masked(img: &RgbImage, mask: &[bool]) -> RgbImage {
    RgbImage {
        width: img.width,
        height: img.height,
        pixels: img
            .pixels
            .iter()
            .zip(mask)
            .map(|(p, m)| if *m { *p } else { [0.0; 3] })
            .collect(),
    }
}

/// A render's added radiance against the reference.
pub struct Measured {
    /// Luminance-weighted mean relative error.
    pub error: f64,
    /// FLIP of the masked tone-mapped images.
    pub flip: f64,
    /// The godrays pass's time, ms.
    pub ms: f64,
}

/// The added radiance of the render `on` against the reference.
pub fn measure_output(c: &Value, on: &RenderOutput, off: &RenderOutput) -> Measured {
    let stat: &PassStat = on.passes.iter().find(|p| p.name == "godrays").unwrap();
    assert!(stat.ran, "{stat:?}");
    let mut m = measure_added(c, &added_radiance(on, off), 1);
    m.ms = stat.ms.unwrap_or(f64::NAN);
    m
}

/// The godrays pass's added radiance: `on` minus `off`.
pub fn added_radiance(on: &RenderOutput, off: &RenderOutput) -> RgbImage {
    RgbImage {
        width: on.image.width,
        height: on.image.height,
        pixels: on
            .image
            .pixels
            .iter()
            .zip(&off.image.pixels)
            .map(|(a, b)| [0, 1, 2].map(|k| a[k] - b[k]))
            .collect(),
    }
}

/// The mean of each `k` × `k` block: a render at `k` times the
/// reference's resolution as the reference's pixels (each the mean over
/// its pixel's area, as `tools/godrays_reference.py` samples them).
pub fn box_reduce(img: &RgbImage, k: usize) -> RgbImage {
    let (w, h) = (img.width / k, img.height / k);
    RgbImage::from_fn(w, h, |x, y| {
        let mut s = [0.0f32; 3];
        for dy in 0..k {
            for dx in 0..k {
                let p = img.pixels[(y * k + dy) * img.width + x * k + dx];
                for c in 0..3 {
                    s[c] += p[c] / (k * k) as f32;
                }
            }
        }
        s
    })
}

/// An added-radiance image at `k` times the reference's resolution
/// against the reference (`ms` left NaN).
pub fn measure_added(c: &Value, added: &RgbImage, k: usize) -> Measured {
    let name = c["name"].as_str().unwrap();
    if let Some(d) = std::env::var_os("HIMMEL_TEST_OUT") {
        let p = std::path::Path::new(&d).join(format!("{name}_added_{k}.exr"));
        let img = himmel_skymodel::HdrImage {
            width: added.width,
            height: added.height,
            pixels: added.pixels.clone(),
            valid: vec![true; added.pixels.len()],
        };
        himmel_cpu::output::write_exr(&p, &img).unwrap();
    }
    let added = box_reduce(added, k);
    let dir = root().join("tests/fixtures/godrays_ref");
    let reference = read_exr(dir.join(format!("{name}.exr"))).unwrap();
    let mask = mask_channel(
        &read_exr(dir.join(format!("{name}_mask.exr"))).unwrap(),
        GEOMETRY,
    );
    Measured {
        error: mean_relative_error(&added, &reference, &mask),
        flip: flip(
            &masked(&added, &mask),
            &masked(&reference, &mask),
            Some(&mask),
        ),
        ms: f64::NAN,
    }
}
