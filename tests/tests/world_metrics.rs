//! The metrics of the 3D-world reference tests (`world_common/metrics.rs`),
//! tested on synthetic images, and the committed Mitsuba references
//! (`tests/fixtures/world_ref/`) read back through them.

mod world_common;

use world_common::metrics::*;

/// A synthetic "render": a gradient floor, a bright patch and a dark corner.
fn scene(w: usize, h: usize) -> RgbImage {
    RgbImage::from_fn(w, h, |x, y| {
        let base = 50.0 + 400.0 * y as f32 / h as f32;
        let lit = if (20..40).contains(&x) && (10..30).contains(&y) {
            8.0
        } else {
            1.0
        };
        let v = base * lit * if x < 5 { 0.01 } else { 1.0 };
        [v * 0.9, v, v * 1.2]
    })
}

#[test]
fn identical_images_have_no_error() {
    let r = scene(64, 48);
    let all = vec![true; r.pixels.len()];
    assert_eq!(mean_relative_error(&r, &r, &all), 0.0);
    assert_eq!(pixel_relative_error(&r, &r, &all), 0.0);
    assert_eq!(flip(&r, &r, None), 0.0);
}

#[test]
fn a_ten_percent_scale_is_a_ten_percent_error() {
    let r = scene(64, 48);
    let t = r.map(|p| p.map(|c| c * 1.1));
    let all = vec![true; r.pixels.len()];
    assert!((mean_relative_error(&t, &r, &all) - 0.1).abs() < 1e-6);
    assert!((pixel_relative_error(&t, &r, &all) - 0.1).abs() < 1e-6);
    let t = r.map(|p| p.map(|c| c * 0.9));
    assert!((mean_relative_error(&t, &r, &all) - 0.1).abs() < 1e-6);
}

#[test]
fn the_mask_selects_the_pixels_judged() {
    let r = scene(64, 48);
    // 50 % too bright in the left half only.
    let t = RgbImage::from_fn(64, 48, |x, y| {
        let p = r.pixels[y * 64 + x];
        if x < 32 {
            p.map(|c| c * 1.5)
        } else {
            p
        }
    });
    let left: Vec<bool> = (0..64 * 48).map(|i| i % 64 < 32).collect();
    let right: Vec<bool> = left.iter().map(|b| !b).collect();
    assert!((mean_relative_error(&t, &r, &left) - 0.5).abs() < 1e-6);
    assert_eq!(mean_relative_error(&t, &r, &right), 0.0);
    assert!(mean_relative_error(&t, &r, &vec![false; 64 * 48]).is_nan());
    assert!(flip(&t, &r, Some(&left)) > flip(&t, &r, Some(&right)));
}

#[test]
fn the_weighted_error_is_robust_to_dark_pixels() {
    // An absolute offset of 1 cd/m²: huge relative to the dark corner
    // (0.5–4.5 cd/m²), small relative to the image.
    let r = scene(64, 48);
    let t = r.map(|p| p.map(|c| c + 1.0));
    let all = vec![true; r.pixels.len()];
    let (weighted, plain) = (
        mean_relative_error(&t, &r, &all),
        pixel_relative_error(&t, &r, &all),
    );
    assert!(weighted < 0.01, "{weighted}");
    assert!(plain > 2.0 * weighted, "{plain} vs {weighted}");
}

#[test]
fn flip_grows_with_the_perturbation() {
    let r = scene(96, 64);
    // Deterministic pseudo-random noise of two strengths, and a shift.
    let noisy = |amp: f32| {
        RgbImage::from_fn(96, 64, |x, y| {
            let h = ((x * 7919 + y * 104_729) % 1000) as f32 / 1000.0 - 0.5;
            r.pixels[y * 96 + x].map(|c| c * (1.0 + amp * h))
        })
    };
    let (small, large) = (flip(&noisy(0.1), &r, None), flip(&noisy(0.6), &r, None));
    assert!(small > 0.0 && large > small, "{small} {large}");
    let dark = r.map(|p| p.map(|c| c * 0.5));
    let darker = r.map(|p| p.map(|c| c * 0.25));
    assert!(flip(&darker, &r, None) > flip(&dark, &r, None));
}

#[test]
fn the_tone_map_puts_the_median_at_middle_grey() {
    let r = RgbImage::from_fn(3, 1, |x, _| [[1.0; 3], [10.0; 3], [1000.0; 3]][x]);
    assert!((median_luminance(&r) - 10.0).abs() < 1e-9);
    let k = exposure_for(&r);
    let ldr = tone_map(&r, k);
    // 0.18 → sRGB 0.4614 → 118; 18 → clipped to 255; 0.018 → 36.
    assert_eq!(&ldr[..3], &[36, 36, 36]);
    assert_eq!(&ldr[3..6], &[118, 118, 118]);
    assert_eq!(&ldr[6..9], &[255, 255, 255]);
}

/// The committed references read back (OpenEXR as written by Mitsuba) with
/// masks that make sense: sunlit pixels brighter than sky-lit ones.
#[test]
fn the_committed_references_read_back() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/world_ref");
    let cases: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tools/world_cases.json"
        ))
        .expect("tools/world_cases.json"),
    )
    .expect("valid JSON");
    let cases = cases["cases"].as_array().expect("cases");
    assert_eq!(cases.len(), 9);
    for case in cases {
        let name = case["name"].as_str().expect("name");
        let img = read_exr(format!("{dir}/{name}.exr")).unwrap();
        let mask = read_exr(format!("{dir}/{name}_mask.exr")).unwrap();
        let cam = &case["camera"];
        assert_eq!(
            (img.width as u64, img.height as u64),
            (
                cam["width"].as_u64().unwrap(),
                cam["height"].as_u64().unwrap()
            ),
            "{name}"
        );
        assert_eq!((mask.width, mask.height), (img.width, img.height));
        let (lit, sky, geo) = (
            mask_channel(&mask, SUNLIT),
            mask_channel(&mask, SKYLIT),
            mask_channel(&mask, GEOMETRY),
        );
        let count = |m: &[bool]| m.iter().filter(|b| **b).count();
        assert!(count(&lit) > 100 && count(&sky) > 100, "{name}");
        assert!(lit.iter().zip(&geo).all(|(l, g)| !l || *g), "{name}");
        assert!(lit.iter().zip(&sky).all(|(l, s)| !(*l && *s)), "{name}");
        let mean = |m: &[bool]| {
            let y: Vec<f64> = img
                .luminance()
                .into_iter()
                .zip(m)
                .filter(|(_, b)| **b)
                .map(|(y, _)| y)
                .collect();
            y.iter().sum::<f64>() / y.len() as f64
        };
        assert!(mean(&lit) > 2.0 * mean(&sky), "{name}");
        // Finite; tiny negative channels (out-of-gamut colours of the night
        // sky, > −1e-5 cd/m²) come from Himmel's environment itself.
        assert!(img
            .pixels
            .iter()
            .flatten()
            .all(|c| c.is_finite() && *c > -1e-3));
        assert_eq!(mean_relative_error(&img, &img, &geo), 0.0);
    }
}
