//! S3HO against scalar AO (issue 16): the sky's diffuse light occluded by
//! the ao pass alone (`lighting.sky.occlusion` `ao`: no visibility maps),
//! once by `gtao`'s scalar AO and twice with S3HO (`lighting.ao.sh`): its
//! default weighting, the blocked arcs integrated against the sky's
//! radiance (`sh_sky` `radiance`), and the order-2 SH projection (`sh2`),
//! each compared with Mitsuba's `max_depth` 2 reference of the same case
//! (`tests/fixtures/world_ref/`, `tools/world_reference.py`) on its
//! sky-lit-only pixels (in the Sun's shadow or facing away from it, whole
//! pixels on one plane): the luminance-weighted mean relative error
//! Σ|ΔY| / ΣY_ref, as `world_mitsuba` measures it.
//!
//! The cases lie under the low winter Sun (10°, from the south), whose sky
//! is far from uniform (its aureole and the bright southern horizon
//! against a darker north): the atrium from above and towards the wall
//! that hides the Sun — its shadowed floor sees the bright side over the
//! walls only, so a scalar AO, which takes the same fraction of every side
//! of the sky, gives it too much light — and the plane with boxes, whose
//! shadowed ground loses mostly the aureole behind each box. The issue's
//! goal, S3HO's error ≤ 0.7 × scalar AO's, is asserted for `radiance` in
//! every case; `sh2` (which meets it on the atrium views only) is bounded
//! at its measured ratio; each error is also bounded a little above what
//! this version measures, so that a change for the worse fails; and S3HO
//! must leave open pixels (AO 1) alone.
//!
//! `cargo test -p himmel-tests --test world_s3ho -- --nocapture` prints the
//! figures the README quotes; `HIMMEL_S3HO='{"radius_m": 6}'` (a
//! `lighting.ao` object; `sh` and `sh_sky` are set by the test) measures
//! other settings (printed, not asserted).

mod wgpu_common;
mod world_common;

use himmel_skymodel::{AoSettings, Effect, ShSky, SkyOcclusion};
use world_common::cases::case;
use world_common::metrics::{luminance, mask_channel, mean_relative_error};
use world_common::metrics::{RgbImage, SKYLIT};
use world_common::render::{render_world, world_reference};

/// (case, its file of cases): the atrium from above and towards the low
/// Sun's wall (`tools/s3ho_cases.json`), and the plane with boxes under the
/// same Sun (`tools/world_cases.json`).
const CASES: [(&str, &str); 3] = [
    ("atrium_low_top", "tools/s3ho_cases.json"),
    ("atrium_low_south", "tools/s3ho_cases.json"),
    ("plane_and_boxes_low", "tools/world_cases.json"),
];

/// The ao pass's settings of the comparison: `gtao` with a radius that
/// reaches across the atrium's courtyard (its walls are the blockers).
fn settings() -> AoSettings {
    match std::env::var("HIMMEL_S3HO") {
        Ok(json) => serde_json::from_str(&json).expect("HIMMEL_S3HO: a `lighting.ao` object"),
        // 32 steps a side: the outer walls' tops, seen from above, are a
        // few pixels wide, and 12 quadratically spaced steps jump them.
        Err(_) => AoSettings {
            radius_m: Some(RADIUS_M),
            slices: 8,
            steps: 32,
            ..AoSettings::default()
        },
    }
}

/// Metres: from the courtyard's floor its walls (8 m high, up to 13.5 m
/// away) are within reach.
const RADIUS_M: f64 = 20.0;

/// One render of a case with S3HO on or off.
struct Measured {
    /// The sky-lit pixels' error against Mitsuba.
    err: f64,
    /// The ao pass's `--stats` ms.
    ao_ms: f64,
    /// The render.
    img: RgbImage,
    /// Its AO image (row-major).
    ao: Vec<f32>,
    /// Its bent normals (0 on sky pixels).
    bent: Vec<[f32; 3]>,
}

/// A run's name: `scalar`, `radiance` or `sh2`.
fn label(sh: Option<ShSky>) -> &'static str {
    match sh {
        None => "scalar",
        Some(ShSky::Radiance) => "radiance",
        Some(ShSky::Sh2) => "sh2",
    }
}

/// One render of a case: scalar AO (`None`) or S3HO with this weighting.
fn measure(which: (&str, &str), sh: Option<ShSky>) -> Measured {
    let (name, file) = which;
    let c = case(file, name);
    let mut s = world_common::cases::case_scene(&c);
    s.effects.push(Effect::Ao);
    s.lighting.sky.occlusion = SkyOcclusion::Ao;
    // The scalar run keeps the default weighting (`sh_sky` needs `sh`).
    s.lighting.ao = AoSettings {
        sh: sh.is_some(),
        sh_sky: sh.unwrap_or(ShSky::Radiance),
        ..settings()
    };
    s.lighting.validate().unwrap();
    let (out, ao_img) = {
        let mut r = wgpu_common::gpu();
        let out = render_world(&mut r, &s);
        (out, r.ao_image().unwrap().expect("the ao pass ran"))
    };
    let pass = |name: &str| out.passes.iter().find(|p| p.name == name).unwrap();
    let ao = pass("ao");
    assert!(ao.ran, "{:?}", ao.reason);
    let maps = pass("world/sky-visibility");
    assert!(
        !maps.ran,
        "the visibility maps were built: {:?}",
        maps.reason
    );
    assert!(maps.reason.as_deref().unwrap().contains("occlusion is ao"));
    if let Some(d) = std::env::var_os("HIMMEL_TEST_OUT") {
        let p = std::path::Path::new(&d).join(format!("{name}_{}.exr", label(sh)));
        himmel_cpu::output::write_exr(&p, &out.image).unwrap();
    }
    let img = RgbImage::from(out.image);
    let (reference, mask) = world_reference(name);
    let mask = mask_channel(&mask, SKYLIT);
    assert!(mask.iter().filter(|m| **m).count() > 1_000);
    Measured {
        err: mean_relative_error(&img, &reference, &mask),
        ao_ms: ao.ms.unwrap(),
        img,
        ao: ao_img.ao,
        bent: ao_img.bent_normal,
    }
}

/// The largest relative luminance change S3HO makes, against scalar AO, on
/// the geometry pixels nothing occludes (AO 1): none, as it integrates only the
/// blocked arcs (an open surface keeps the open sky's light).
/// (Pixels, change.)
fn open_change(scalar: &Measured, s3ho: &Measured) -> (usize, f64) {
    let y = |p: &[f32; 3]| luminance(*p);
    let mut worst = 0.0f64;
    let mut n = 0;
    let geometry = scalar.bent.iter().map(|b| b.iter().any(|c| *c != 0.0));
    let pairs = scalar.img.pixels.iter().zip(&s3ho.img.pixels);
    for (((a, b), ao), g) in pairs.zip(&scalar.ao).zip(geometry) {
        if g && *ao >= 0.9999 && y(a) > 0.0 {
            worst = worst.max((y(b) - y(a)).abs() / y(a));
            n += 1;
        }
    }
    (n, worst)
}

#[test]
fn s3ho_beats_scalar_ao_under_a_low_sun() {
    println!("Sky light occluded by the ao pass alone; sky-lit pixels vs Mitsuba:");
    println!(
        "| case | scalar AO | S3HO radiance | ratio | S3HO sh2 | ratio | ao ms (scalar, radiance, sh2) |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut failures = Vec::new();
    // The open pixels seen in all cases (the atrium's roofs and wall tops
    // from above, mostly).
    let mut open_pixels = 0;
    for (k, which) in CASES.into_iter().enumerate() {
        let scalar = measure(which, None);
        let runs = [ShSky::Radiance, ShSky::Sh2].map(|m| measure(which, Some(m)));
        for (m, run) in [ShSky::Radiance, ShSky::Sh2].into_iter().zip(&runs) {
            let (open, change) = open_change(&scalar, run);
            println!(
                "{} ({}): {open} open pixels (AO 1), S3HO changes them by ≤ {:.3} %",
                which.0,
                label(Some(m)),
                change * 100.0
            );
            if m == ShSky::Radiance {
                open_pixels += open;
            }
            if change > OPEN_CHANGE {
                failures.push(format!(
                    "{} ({}): {open} open pixels changed by {change:.5} (≤ {OPEN_CHANGE})",
                    which.0,
                    label(Some(m))
                ));
            }
        }
        let [radiance, sh2] = [runs[0].err, runs[1].err];
        println!(
            "| {} | {:.2} % | {:.2} % | {:.3} | {:.2} % | {:.3} | {:.0}, {:.0}, {:.0} |",
            which.0,
            scalar.err * 100.0,
            radiance * 100.0,
            radiance / scalar.err,
            sh2 * 100.0,
            sh2 / scalar.err,
            scalar.ao_ms,
            runs[0].ao_ms,
            runs[1].ao_ms
        );
        let b = &BOUNDS[k];
        if radiance > GOAL * scalar.err || scalar.err > b.scalar || radiance > b.radiance {
            failures.push(format!(
                "{}: S3HO radiance {radiance:.4} (≤ {GOAL} × scalar, ≤ {}), scalar {:.4} (≤ {})",
                which.0, b.radiance, scalar.err, b.scalar
            ));
        }
        if sh2 > b.sh2_ratio * scalar.err || sh2 > b.sh2 {
            failures.push(format!(
                "{}: S3HO sh2 {sh2:.4} (≤ {} × scalar, ≤ {})",
                which.0, b.sh2_ratio, b.sh2
            ));
        }
    }
    if open_pixels < 1000 {
        failures.push(format!("only {open_pixels} open pixels to check"));
    }
    if std::env::var_os("HIMMEL_S3HO").is_none() {
        assert!(failures.is_empty(), "{failures:#?}");
    }
}

/// The largest relative change S3HO may make to an open pixel's luminance
/// (measured ≤ 0.003 %: `sh2`'s f16 coefficients, or the blur's reach into
/// partly blocked neighbours).
const OPEN_CHANGE: f64 = 1e-3;

/// The goal: S3HO's error ≤ 0.7 × scalar AO's.
const GOAL: f64 = 0.7;

/// A case's bounds: the scalar, `radiance` and `sh2` errors at what this
/// version measures (lavapipe) plus half a percentage point, and the
/// largest `sh2` / scalar ratio (the 0.7 where `sh2` meets it, else
/// what it measures plus about 0.04). `radiance` must meet [`GOAL`]
/// everywhere.
struct Bounds {
    scalar: f64,
    radiance: f64,
    sh2: f64,
    sh2_ratio: f64,
}

const BOUNDS: [Bounds; 3] = [
    // Measured 0.7245; radiance 0.2847 (0.393); sh2 0.4562 (0.630).
    Bounds {
        scalar: 0.73,
        radiance: 0.29,
        sh2: 0.461,
        sh2_ratio: 0.7,
    },
    // Measured 1.1328; radiance 0.6978 (0.616); sh2 0.7872 (0.695).
    Bounds {
        scalar: 1.138,
        radiance: 0.703,
        sh2: 0.792,
        sh2_ratio: 0.7,
    },
    // Measured 0.2400; radiance 0.1474 (0.614); sh2 0.1924 (0.801).
    Bounds {
        scalar: 0.245,
        radiance: 0.1525,
        sh2: 0.1975,
        sh2_ratio: 0.84,
    },
];
