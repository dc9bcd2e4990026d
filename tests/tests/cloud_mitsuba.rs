//! The low cloud layer against Mitsuba 3 (issue 18): the path-traced
//! references of `tests/fixtures/cloud_ref/` (`tools/cloud_reference.py`:
//! Himmel's own density field exported on a voxel grid, Mitsuba's `volpath`
//! with every order of scattering) beside Himmel's march of the same field
//! ([`march_low_with_grids`]: self-shadowing light march and each
//! multiple-scattering model, the default diffusion solution with its 3D
//! grid, the column model alone and Wrenninge's octaves), in
//! the isolated configuration: a directional Sun of irradiance 1, no
//! atmosphere, no sky light, a black world.
//!
//! * radiance, seen from the ground looking at the zenith, at two Sun
//!   altitudes: the luminance-weighted mean relative error Σ|ΔY| / ΣY_ref
//!   over the cloud pixels (Himmel's transmittance below 0.9); the goal
//!   is 15 %, the bounds are what this version achieves
//!   ([`radiance_bound`]);
//! * the transmittance of the direct Sun through the layer along parallel
//!   rays towards the Sun ([`optical_depth_ray`], the view march's
//!   stepping): Σ|ΔT| / ΣT_ref over the pixels whose ray meets cloud ≤ 5 %.
//!
//! The grid sum in `references.json` must equal the sum of Himmel's field
//! on the same grid ([`LowField::voxel_grid`]): the references were made
//! from the field rendered here. `cargo test -p himmel-tests --test
//! cloud_mitsuba -- --nocapture` prints the figures the README quotes.

mod world_common;

use glam::Vec3;
use himmel_skymodel::clouds::{
    march_height_field, march_low_with_grids, optical_depth_ray, CloudLight, DiffusionGrid,
    HeightField, LowField, MarchSettings, MultipleScattering, Shell, DIFFUSION, GRID, OCTAVES,
};
use himmel_skymodel::scene::LowCloudSpec;
use serde_json::Value;
use world_common::metrics::{mean_relative_error, pixel_relative_error, read_exr, RgbImage};

const R_GROUND: f32 = 6360.0;

/// The references of the test's field.
const TEST_FIELD: &str = "";
/// The references of the field the diffusion model's constants were
/// chosen on (seed 7, radiance only).
const TUNING_FIELD: &str = "seed7";

fn dir(field: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/cloud_ref")
        .join(field)
}

fn json(field: &str, name: &str) -> Value {
    let text = std::fs::read_to_string(dir(field).join(name)).expect("fixture");
    serde_json::from_str(&text).expect("JSON")
}

/// ENU unit vector at altitude/azimuth (degrees).
fn towards(alt_deg: f64, az_deg: f64) -> Vec3 {
    let (a, z) = (alt_deg.to_radians(), az_deg.to_radians());
    Vec3::new(
        (a.cos() * z.sin()) as f32,
        (a.cos() * z.cos()) as f32,
        a.sin() as f32,
    )
}

struct Setup {
    field: LowField,
    spec: LowCloudSpec,
    shell: Shell,
    settings: MarchSettings,
    v: Value,
}

fn setup(field: &str) -> Setup {
    let v = json(field, "setup.json");
    let spec: LowCloudSpec = serde_json::from_value(v["low"].clone()).expect("clouds.low");
    Setup {
        field: LowField::new(&spec, 0.0),
        settings: MarchSettings {
            steps: spec.steps,
            light_steps: spec.light_steps,
            scattering: MultipleScattering::Diffusion(DIFFUSION),
        },
        spec,
        shell: Shell {
            r_ground: R_GROUND,
            r_observer: R_GROUND,
        },
        v,
    }
}

/// The Suns of the setup's references: each one's name (the references'
/// prefix, e.g. `sun60`) and its direction ([`towards`] its altitude and
/// azimuth).
fn suns(s: &Setup) -> Vec<(&str, Vec3)> {
    s.v["suns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|sun| {
            let l = towards(
                sun["alt_deg"].as_f64().unwrap(),
                sun["az_deg"].as_f64().unwrap(),
            );
            (sun["name"].as_str().unwrap(), l)
        })
        .collect()
}

/// Sub-samples per pixel side: Mitsuba's box filter averages over the
/// pixel, so Himmel's images average an n × n grid of sub-pixel samples.
const SUB: usize = 3;

/// Normalised device coordinates (y up) of sub-sample (si, sj) of pixel
/// (i, j) of a w × h image.
fn ndc(i: usize, j: usize, (si, sj): (usize, usize), w: usize, h: usize) -> (f32, f32) {
    let fx = (si as f32 + 0.5) / SUB as f32;
    let fy = (sj as f32 + 0.5) / SUB as f32;
    (
        2.0 * (i as f32 + fx) / w as f32 - 1.0,
        1.0 - 2.0 * (j as f32 + fy) / h as f32,
    )
}

/// The mean of `f` over the pixel's sub-samples.
fn box_filter(
    i: usize,
    j: usize,
    w: usize,
    h: usize,
    f: impl Fn(f32, f32) -> [f32; 3],
) -> [f32; 3] {
    let mut acc = [0.0f32; 3];
    for sj in 0..SUB {
        for si in 0..SUB {
            let (x, y) = ndc(i, j, (si, sj), w, h);
            let v = f(x, y);
            for c in 0..3 {
                acc[c] += v[c] / (SUB * SUB) as f32;
            }
        }
    }
    acc
}

/// Mitsuba's `look_at` camera basis (forward, right = forward × up, up).
fn basis(forward: Vec3, up_hint: Vec3) -> (Vec3, Vec3) {
    let right = forward.cross(up_hint).normalize();
    (right, right.cross(forward))
}

/// The tier measured: the volumetric march (its diffuse light from a
/// [`DiffusionGrid`] where one is given) or the height-field tier.
#[derive(Clone, Copy)]
enum Tier<'a> {
    Volume(Option<&'a DiffusionGrid>),
    HeightField(&'a HeightField),
}

/// Himmel's radiance and transmittance through the zenith camera: the
/// volumetric march, or the height-field tier's (the transmittance, which
/// picks the cloud pixels, is the volume's in both).
fn himmel_radiance(
    s: &Setup,
    sun: Vec3,
    settings: &MarchSettings,
    tier: Tier,
) -> (RgbImage, Vec<f32>) {
    let cam = &s.v["camera"];
    let (w, h) = (
        cam["width"].as_u64().unwrap() as usize,
        cam["height"].as_u64().unwrap() as usize,
    );
    let tan = (cam["fov_deg"].as_f64().unwrap().to_radians() * 0.5).tan() as f32;
    let (right, up) = basis(Vec3::Z, Vec3::Y);
    let lights = [CloudLight {
        dir: sun,
        irradiance_rgb: [1.0; 3],
    }];
    let aspect = w as f32 / h as f32;
    let view = |x: f32, y: f32| (Vec3::Z + right * (x * tan * aspect) + up * (y * tan)).normalize();
    let img = RgbImage::from_fn(w, h, |i, j| {
        box_filter(i, j, w, h, |x, y| {
            let v = view(x, y);
            match tier {
                Tier::HeightField(hf) => {
                    march_height_field(hf, &s.field, &s.shell, v, &lights, [0.0; 3], settings)
                }
                Tier::Volume(grid) => march_low_with_grids(
                    &s.field,
                    &s.shell,
                    v,
                    &lights,
                    [0.0; 3],
                    settings,
                    grid.map(std::slice::from_ref).unwrap_or(&[]),
                ),
            }
            .radiance
        })
    });
    let origin = Vec3::new(0.0, 0.0, R_GROUND);
    let trans = RgbImage::from_fn(w, h, |i, j| {
        box_filter(i, j, w, h, |x, y| {
            let tau = optical_depth_ray(&s.field, &s.shell, origin, view(x, y), s.spec.steps);
            [(-tau).exp(); 3]
        })
    });
    let trans = trans.pixels.iter().map(|p| p[1]).collect();
    (img, trans)
}

/// Himmel's transmittance towards the Sun along the rays through the
/// points of the plane through the origin perpendicular to the Sun, from
/// `back_km` behind it (Mitsuba's orthographic camera); through the
/// height-field volume when `hf` is given.
fn himmel_transmittance(s: &Setup, sun: Vec3, hf: Option<&HeightField>) -> RgbImage {
    let cam = &s.v["shadow_camera"];
    let (w, h) = (
        cam["width"].as_u64().unwrap() as usize,
        cam["height"].as_u64().unwrap() as usize,
    );
    let half = cam["half_width_km"].as_f64().unwrap() as f32;
    let back = cam["back_km"].as_f64().unwrap() as f32;
    let (right, up) = basis(sun, Vec3::Y);
    RgbImage::from_fn(w, h, |i, j| {
        box_filter(i, j, w, h, |x, y| {
            let q = (right * x + up * y) * half - sun * back;
            let pos = Vec3::new(q.x, q.y, R_GROUND + q.z);
            let tau = match hf {
                Some(hf) => hf.depth_ray(&s.field, &s.shell, pos, sun, s.spec.steps),
                None => optical_depth_ray(&s.field, &s.shell, pos, sun, s.spec.steps),
            };
            [(-tau).exp(); 3]
        })
    })
}

#[test]
fn references_were_made_from_this_field() {
    for field in [TEST_FIELD, TUNING_FIELD] {
        let s = setup(field);
        let res: [usize; 3] = serde_json::from_value(s.v["grid"].clone()).unwrap();
        let sum: f64 = s.field.voxel_grid(res).iter().map(|&x| x as f64).sum();
        let refs = json(field, "references.json");
        let expect = refs["grid_sum"].as_f64().unwrap();
        assert!(
            (sum / expect - 1.0).abs() < 1e-6,
            "{field}: the field changed since the references were made: grid sum {sum} vs {expect} (rerun tools/cloud_reference.py)"
        );
    }
}

/// Himmel's radiance against the reference of Sun `name` in the
/// zenith view: the number of cloud pixels (Himmel's transmittance below
/// 0.9), Σ|ΔY|/ΣY over them, printed with the mean per-pixel error and
/// the ratio of the sums. `march`: the settings, and the height-field
/// tier's maps when it is the one measured.
fn radiance_error(
    s: &Setup,
    field: &str,
    name: &str,
    model: &str,
    l: Vec3,
    (settings, tier): (&MarchSettings, Tier),
    bound: f64,
) -> (usize, f64) {
    let reference = read_exr(dir(field).join(format!("{name}_radiance.exr"))).unwrap();
    let (img, trans) = himmel_radiance(s, l, settings, tier);
    let cloud: Vec<bool> = trans.iter().map(|&t| t < 0.9).collect();
    let n = cloud.iter().filter(|&&c| c).count();
    let weighted = mean_relative_error(&img, &reference, &cloud);
    let per_pixel = pixel_relative_error(&img, &reference, &cloud);
    let sums = img
        .luminance()
        .iter()
        .zip(reference.luminance())
        .zip(&cloud)
        .filter(|(_, c)| **c)
        .fold((0.0, 0.0), |(a, b), ((x, y), _)| (a + x, b + y));
    let label = if field.is_empty() {
        name.to_string()
    } else {
        format!("{field} {name}")
    };
    println!(
        "{label} {model}: radiance over {n} cloud pixels: Σ|ΔY|/ΣY {:.1} % (bound {:.1} %), mean |ΔY|/Y {:.1} %, ΣY_himmel/ΣY_mitsuba {:.3}",
        weighted * 100.0,
        bound * 100.0,
        per_pixel * 100.0,
        sums.0 / sums.1
    );
    (n, weighted)
}

/// The radiance bound of each model and Sun. The goal is 15 %.
/// The column model (`clouds.low.scattering = "column"`: the diffusion
/// model without its 3D grid) achieves 7.3 % (Sun at 60°) and 20.3 % (Sun
/// at 20°; its slab turned towards the flanks a low Sun lights from the
/// side, the column ended at gaps, the forward lobes of the light
/// scattered a few times, its constants chosen on another field); what
/// remains at the low Sun is the pixel-to-pixel pattern of the 3D light a
/// column cannot see, which the default adds from a 3D grid
/// ([`the_diffusion_grid_against_mitsuba`]). Wrenninge's octaves achieve
/// 20.7 % and 32.6 %: blind to the Sun's altitude and to how much cloud
/// surrounds a point. A change that makes any figure worse fails.
fn radiance_bound(model: &str, sun: &str) -> f64 {
    match (model, sun) {
        ("column", "sun60") => 0.08,
        ("column", _) => 0.21,
        (_, "sun60") => 0.22,
        _ => 0.34,
    }
}

#[test]
fn cloud_radiance_and_sun_transmittance_match_mitsuba() {
    let s = setup(TEST_FIELD);
    let mut failures = Vec::new();
    for (name, l) in suns(&s) {
        let mut n = 0;
        for (model, scattering) in [
            ("column", MultipleScattering::Diffusion(DIFFUSION)),
            ("octaves", MultipleScattering::Octaves(OCTAVES)),
        ] {
            let bound = radiance_bound(model, name);
            let mut s_model = s.settings;
            s_model.scattering = scattering;
            let weighted;
            (n, weighted) = radiance_error(
                &s,
                TEST_FIELD,
                name,
                model,
                l,
                (&s_model, Tier::Volume(None)),
                bound,
            );
            if weighted.is_nan() || weighted > bound {
                failures.push(format!("{name} {model} radiance {:.1} %", weighted * 100.0));
            }
        }
        let t_ref = read_exr(dir(TEST_FIELD).join(format!("{name}_transmittance.exr"))).unwrap();
        let t_him = himmel_transmittance(&s, l, None);
        let through: Vec<bool> = t_him.pixels.iter().map(|p| p[1] < 0.999).collect();
        let e = mean_relative_error(&t_him, &t_ref, &through);
        let m = through.iter().filter(|&&c| c).count();
        println!(
            "{name}: Sun transmittance over {m} pixels: Σ|ΔT|/ΣT {:.2} %",
            e * 100.0
        );
        if e.is_nan() || e > 0.05 {
            failures.push(format!("{name} transmittance {:.2} %", e * 100.0));
        }
        assert!(n > 50 && m > 50, "{name}: too few cloud pixels ({n}, {m})");
    }
    assert!(failures.is_empty(), "{failures:?}");
}

/// The field the diffusion model's constants (`DIFFUSION`: gain,
/// gap_density, surface_weight; `GRID`: cell, threshold, weight) were
/// chosen on, seed 7, with the column model alone (references at
/// 4096 spp, noise 4.1 % and 8.8 % per pixel): 9.0 % (Sun at 60°) and
/// 20.3 % (Sun at 20°). A change that makes either worse fails.
#[test]
fn the_field_the_constants_were_chosen_on() {
    let s = setup(TUNING_FIELD);
    let mut failures = Vec::new();
    for (name, l) in suns(&s) {
        let bound = if name == "sun60" { 0.10 } else { 0.21 };
        let (n, e) = radiance_error(
            &s,
            TUNING_FIELD,
            name,
            "column",
            l,
            (&s.settings, Tier::Volume(None)),
            bound,
        );
        assert!(n > 50, "{name}: too few cloud pixels ({n})");
        if e.is_nan() || e > bound {
            failures.push(format!("{name} radiance {:.1} %", e * 100.0));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

/// The height-field tier (`clouds.low.tier = "heightfield"`, the cheap
/// tier: [`HeightField`] maps of each column's bottom, top and mean
/// extinction, a few probes per ray) against the same references, with
/// the default diffusion model: its radiance on both fields and the
/// transmittance of the direct Sun on the test's. The issue sets no goal
/// for it; the bounds are the measured figures (README) with a margin,
/// so that the tier does not silently get worse.
#[test]
fn the_height_field_tier_against_mitsuba() {
    let mut failures = Vec::new();
    for field in [TEST_FIELD, TUNING_FIELD] {
        let s = setup(field);
        for (name, l) in suns(&s) {
            let hf = HeightField::build(&s.field, &s.shell, &[l], &s.settings);
            let bound = height_field_bound(field, name);
            let (n, e) = radiance_error(
                &s,
                field,
                name,
                "heightfield",
                l,
                (&s.settings, Tier::HeightField(&hf)),
                bound,
            );
            assert!(n > 50, "{field} {name}: too few cloud pixels ({n})");
            if e.is_nan() || e > bound {
                failures.push(format!(
                    "{field} {name} height-field radiance {:.1} %",
                    e * 100.0
                ));
            }
            if field != TEST_FIELD {
                continue;
            }
            let t_ref = read_exr(dir(field).join(format!("{name}_transmittance.exr"))).unwrap();
            let t_him = himmel_transmittance(&s, l, Some(&hf));
            let through: Vec<bool> = t_ref.pixels.iter().map(|p| p[1] < 0.999).collect();
            let e = mean_relative_error(&t_him, &t_ref, &through);
            println!(
                "{name} heightfield: Sun transmittance over {} pixels: Σ|ΔT|/ΣT {:.2} %",
                through.iter().filter(|&&c| c).count(),
                e * 100.0
            );
            let bound = if name == "sun60" { 0.09 } else { 0.25 };
            if e.is_nan() || e > bound {
                failures.push(format!(
                    "{name} height-field transmittance {:.2} %",
                    e * 100.0
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

/// The height-field tier's radiance bounds: measured + a margin (15.0 %
/// and 27.7 % on the test's field, 12.5 % and 31.7 % on seed 7; the Sun's
/// transmittance through it 7.5 % and 22.1 %: a slant ray through a
/// column of uniform extinction between its bottom and top).
fn height_field_bound(field: &str, sun: &str) -> f64 {
    match (field, sun) {
        (TEST_FIELD, "sun60") => 0.17,
        (TEST_FIELD, _) => 0.30,
        (_, "sun60") => 0.15,
        _ => 0.35,
    }
}

/// The default diffusion model (`clouds.low.scattering = "diffusion"`):
/// half its diffuse light from the 3D grid ([`DiffusionGrid`], `GRID`:
/// the P1 equations solved on 200 m cells), half from the column model,
/// on both fields and both Suns, with the grid's build time and
/// iterations. The radiance goal, 15 %, is met on both.
#[test]
fn the_diffusion_grid_against_mitsuba() {
    let mut failures = Vec::new();
    for field in [TEST_FIELD, TUNING_FIELD] {
        let s = setup(field);
        for (name, l) in suns(&s) {
            let t = std::time::Instant::now();
            let grid = DiffusionGrid::build(&s.field, &s.shell, l, &GRID).unwrap();
            println!(
                "{field} {name} grid: {:?} cells, {} iterations, built in {:.3} s",
                grid.dims,
                grid.iterations,
                t.elapsed().as_secs_f64()
            );
            let bound = grid_bound(field, name);
            let (n, e) = radiance_error(
                &s,
                field,
                name,
                "diffusion",
                l,
                (&s.settings, Tier::Volume(Some(&grid))),
                bound,
            );
            assert!(n > 50, "{field} {name}: too few cloud pixels ({n})");
            if e.is_nan() || e > bound {
                failures.push(format!("{field} {name} grid radiance {:.1} %", e * 100.0));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

/// The default model's radiance bounds: what it achieves, 5.5 % and
/// 13.0 % on the test's field (Sun at 60° and 20°), 6.3 % and 14.1 % on
/// seed 7 (the grid's cell, cell threshold, beam step and weight against
/// the column model were chosen there), rounded up. A change that makes
/// any worse fails.
fn grid_bound(field: &str, sun: &str) -> f64 {
    match (field, sun) {
        (TEST_FIELD, "sun60") => 0.06,
        (TEST_FIELD, _) => 0.135,
        (_, "sun60") => 0.07,
        _ => 0.145,
    }
}
