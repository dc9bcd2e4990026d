//! Near-field indirect light (`lighting.ao.bounce`, issue 16 item 2)
//! against Mitsuba 3: the wgpu `bounce` pass's contribution — the render
//! with the bounce minus the same render without it (both with `ao`) — for
//! the plane with boxes under the high Sun (`plane_and_boxes_high` of
//! `tools/world_cases.json`), compared with `tests/fixtures/bounce_ref/`
//! (`tools/bounce_reference.py`: Mitsuba `path` at max_depth 3 minus
//! max_depth 2, the one-bounce light) by the luminance-weighted mean
//! relative error Σ|ΔY| / ΣY_ref over the reference's mask: the boxes'
//! walls in the Sun's shadow, beside the sunlit floor. Two references: the
//! bounce from the surfaces the camera sees (`_bounce_onscreen.exr`, what
//! a screen-space pass can gather: bound at the measured error plus 0.8 %)
//! and the whole bounce (`_bounce.exr`: bound 30 %, the issue's).
//!
//! `cargo test -p himmel-tests --test world_bounce -- --nocapture` prints
//! the figures the README quotes; `HIMMEL_BOUNCE='{"bounce_samples": 64}'`
//! (a `lighting.ao` object, `bounce` set to true) measures other settings
//! too (printed, not asserted).

mod wgpu_common;
mod world_common;

use himmel_skymodel::renderer::PassStat;
use himmel_skymodel::{AoSettings, Effect, Scene};
use world_common::cases::{case, root};
use world_common::metrics::{luminance, mask_channel, mean_relative_error, read_exr, RgbImage};
use world_common::metrics::{GEOMETRY, SUNLIT};
use world_common::render::render_world;

const CASE: &str = "plane_and_boxes_high";

/// The bound on the error against the bounce from on-screen surfaces
/// (`_bounce_onscreen.exr`): measured 9.2 % with the defaults, plus 0.8 %
/// (the goal is 30 %), so that a change for the worse fails.
const BOUND: f64 = 0.10;

/// The bound on the error against the whole one-bounce light
/// (`_bounce.exr`): the 30 %; measured 29.6 % (signed −25.5 %: the
/// reference's bounce comes to 29 % from surfaces the camera does not see —
/// the floor below the image's bottom edge and behind the camera).
const BOUND_ALL: f64 = 0.30;

/// The case's scene with `ao` among the effects when `ao`, and `bounce`.
fn scene(ao: bool, bounce: Option<AoSettings>) -> Scene {
    let mut s = world_common::cases::case_scene(&case("tools/world_cases.json", CASE));
    if ao {
        s.effects.push(Effect::Ao);
    }
    s.lighting.ao = bounce.unwrap_or_default();
    s.lighting.validate().unwrap();
    s
}

/// The frame of `s` and its `bounce` entry in `--stats` (if any).
fn render(s: &Scene) -> (RgbImage, Option<PassStat>) {
    let out = render_world(&mut wgpu_common::gpu(), s);
    let stat = out.passes.iter().find(|p| p.name == "bounce").cloned();
    (out.image.into(), stat)
}

struct Measured {
    /// Against the bounce from the surfaces on screen.
    error: f64,
    bias: f64,
    /// Against the whole one-bounce light.
    error_all: f64,
    bias_all: f64,
    /// Against the whole one-bounce light on the other geometry pixels
    /// (mostly open floor; printed, not asserted).
    error_rest: f64,
    ms: f64,
    pixels: usize,
}

/// The luminance-weighted mean signed error Σ(Y − Y_ref) / ΣY_ref.
fn signed_error(test: &RgbImage, reference: &RgbImage, mask: &[bool]) -> f64 {
    let (mut signed, mut total) = (0.0, 0.0);
    for ((t, r), m) in test.pixels.iter().zip(&reference.pixels).zip(mask) {
        if *m {
            signed += luminance(*t) - luminance(*r);
            total += luminance(*r);
        }
    }
    signed / total
}

/// Himmel's bounce (on minus off) against the reference over its mask.
fn measure(settings: AoSettings) -> Measured {
    let dir = root().join("tests/fixtures/bounce_ref");
    let reference = read_exr(dir.join(format!("{CASE}_bounce.exr"))).unwrap();
    let onscreen = read_exr(dir.join(format!("{CASE}_bounce_onscreen.exr"))).unwrap();
    let mask = mask_channel(
        &read_exr(dir.join(format!("{CASE}_bounce_mask.exr"))).unwrap(),
        SUNLIT,
    );
    let mask_image = read_exr(dir.join(format!("{CASE}_bounce_mask.exr"))).unwrap();
    let rest: Vec<bool> = mask_channel(&mask_image, GEOMETRY)
        .iter()
        .zip(&mask)
        .map(|(g, m)| *g && !*m)
        .collect();
    let (off, none) = render(&scene(true, None));
    assert_eq!(none.unwrap().reason.as_deref(), Some("not requested"));
    let on_settings = AoSettings {
        bounce: true,
        ..settings
    };
    let (on, stat) = render(&scene(true, Some(on_settings)));
    let stat = stat.expect("a bounce entry");
    assert!(stat.ran, "{:?}", stat.reason);
    assert_eq!((on.width, on.height), (reference.width, reference.height));
    let diff = RgbImage {
        width: on.width,
        height: on.height,
        pixels: on
            .pixels
            .iter()
            .zip(&off.pixels)
            .map(|(a, b)| [0, 1, 2].map(|k| a[k] - b[k]))
            .collect(),
    };
    if let Some(d) = std::env::var_os("HIMMEL_TEST_OUT") {
        let p = std::path::Path::new(&d).join(format!("{CASE}_bounce.exr"));
        let hdr = himmel_skymodel::HdrImage {
            width: diff.width,
            height: diff.height,
            pixels: diff.pixels.clone(),
            valid: vec![true; diff.pixels.len()],
        };
        himmel_cpu::output::write_exr(&p, &hdr).unwrap();
    }
    Measured {
        error: mean_relative_error(&diff, &onscreen, &mask),
        bias: signed_error(&diff, &onscreen, &mask),
        error_all: mean_relative_error(&diff, &reference, &mask),
        bias_all: signed_error(&diff, &reference, &mask),
        error_rest: mean_relative_error(&diff, &reference, &rest),
        ms: stat.ms.unwrap_or(0.0),
        pixels: mask.iter().filter(|m| **m).count(),
    }
}

#[test]
fn bounce_against_mitsuba() {
    let custom: Option<AoSettings> = std::env::var("HIMMEL_BOUNCE")
        .ok()
        .map(|j| serde_json::from_str(&j).expect("HIMMEL_BOUNCE: a `lighting.ao` object"));
    let print = |label: &str, m: &Measured| {
        println!(
            "{CASE} {label}: bounce error vs the on-screen bounce {:.1} % (signed {:+.1} %), \
             vs the whole bounce {:.1} % (signed {:+.1} %), over {} pixels, {:.1} ms; \
             the other geometry pixels vs the whole bounce {:.1} %",
            100.0 * m.error,
            100.0 * m.bias,
            100.0 * m.error_all,
            100.0 * m.bias_all,
            m.pixels,
            m.ms,
            100.0 * m.error_rest
        )
    };
    let m = measure(AoSettings::default());
    print("default", &m);
    if let Some(c) = custom {
        print(&format!("{c:?}"), &measure(c));
    }
    assert!(m.pixels > 300, "{} masked pixels", m.pixels);
    assert!(m.error <= BOUND, "bounce error {:.3} > {BOUND}", m.error);
    assert!(
        m.error_all <= BOUND_ALL,
        "bounce error (whole) {:.3} > {BOUND_ALL}",
        m.error_all
    );
}

/// The bounce only adds light (never takes any), never touches the sky's
/// pixels, and adds at most the brightest lit radiance on screen (it is
/// an albedo-weighted mean of lit radiances, albedo ≤ 1); pixels in the
/// Sun's shadow next to the sunlit floor get some.
#[test]
fn bounce_adds_bounded_light_to_surfaces_only() {
    let (off, _) = render(&scene(true, None));
    let on_settings = AoSettings {
        bounce: true,
        ..AoSettings::default()
    };
    let (on, _) = render(&scene(true, Some(on_settings)));
    let geometry = mask_channel(
        &read_exr(root().join(format!("tests/fixtures/bounce_ref/{CASE}_bounce_mask.exr")))
            .unwrap(),
        GEOMETRY,
    );
    let brightest = off
        .pixels
        .iter()
        .map(|p| p[0].max(p[1]).max(p[2]))
        .fold(0.0f32, f32::max);
    let (mut sky_same, mut gained) = (0usize, 0usize);
    for (k, (a, b)) in on.pixels.iter().zip(&off.pixels).enumerate() {
        for c in 0..3 {
            let d = a[c] - b[c];
            assert!(d >= -1e-3 * b[c].abs(), "pixel {k}: {} < {}", a[c], b[c]);
            assert!(d <= brightest * 1.0001, "pixel {k}: +{d} > {brightest}");
        }
        if a == b {
            sky_same += 1;
        } else if geometry[k] {
            gained += 1;
        }
    }
    // Sky pixels (no geometry in the reference's masks, with margin).
    let sky = geometry.iter().filter(|g| !**g).count();
    println!(
        "{gained} geometry pixels gained light; {sky_same} pixels unchanged ({sky} without geometry)"
    );
    assert!(gained > 1000, "{gained} pixels gained light");
    let top_rows = (on.width * 10).min(on.pixels.len());
    // The camera looks at the horizon: the top rows are sky, untouched.
    assert_eq!(on.pixels[..top_rows], off.pixels[..top_rows]);
}

/// `--stats`: the pass is listed only where asked for or beside `ao`, runs
/// only with `ao`, and says why not.
#[test]
fn bounce_runs_only_when_requested() {
    let on = Some(AoSettings {
        bounce: true,
        ..AoSettings::default()
    });
    let (_, plain) = render(&scene(false, None));
    assert!(plain.is_none(), "{plain:?}");
    let (_, without_ao) = render(&scene(false, on));
    let s = without_ao.expect("a bounce entry");
    assert!(!s.ran);
    assert!(s.ms.is_none());
    assert!(s.reason.as_deref().unwrap().contains("ao pass"), "{s:?}");
    let (_, with_ao) = render(&scene(true, on));
    let s = with_ao.expect("a bounce entry");
    assert!(s.ran, "{s:?}");
    assert!(s.ms.is_some_and(|ms| ms > 0.0));
    assert!(s.reason.as_deref().unwrap().contains("radius"), "{s:?}");
}
