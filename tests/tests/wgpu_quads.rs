//! Stars and planets as instanced quads (`PointMethod::Quads`, quads.wgsl)
//! against the CPU reference renderer and against the tiled compute passes
//! (`PointMethod::Tiles`): the star scenes of tests/parity.rs (fisheye,
//! equirect, cube map, a planet's glare disk, the moonlit night with the
//! Moon up). Quads vs CPU: median relative luminance difference ≤ 2 %, 99th
//! percentile ≤ 10 %, PSNR ≥ 35 dB of the developed images, the 200
//! brightest star peaks at the same pixels. Quads vs tiles: both evaluate
//! the same WGSL footprint function on the same records, so per pixel they
//! agree to f32 rounding (the quads add each footprint / Ω by blending,
//! the tiles divide the sum): relative luminance difference ≤ 1e-6 with
//! an rgba32float target; ≤ 1 % with rgba16float (11-bit significand)
//! above 10⁻⁸ × the brightest pixel.
//! Banded frames (`set_max_band_bytes`) give the same image.

use glam::DVec3;
use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::LutConfig;
use himmel_skymodel::spectrum::luminance;
use himmel_skymodel::{Effect, HdrImage, Projection, Scene, SkyRenderer, SkyState};
use himmel_wgpu::{PointMethod, WgpuRenderer};

mod wgpu_common;
use wgpu_common::{assert_parity, gpu, peaks, percentile, rel_diffs};

fn scene(utc: &str, p: Projection, w: u32, h: u32) -> Scene {
    let mut s = Scene::default();
    s.time.utc = utc.into();
    s.observer.lat_deg = 48.14;
    s.observer.lon_deg = 11.58;
    s.effects = vec![Effect::Stars, Effect::Planets, Effect::Atmosphere];
    s.camera.projection = p;
    s.camera.width = w;
    s.camera.height = h;
    s.lut = LutConfig::small();
    s
}

/// The wgpu image of `s` with `method`, in bands of `band_rows` rows when
/// given; checks that the stars' and planets' passes ran and were timed.
fn render(s: &Scene, state: &SkyState, method: PointMethod, band_rows: Option<u64>) -> HdrImage {
    render_on(&mut gpu(), s, state, method, band_rows)
}

/// [`render`] on a renderer already locked.
fn render_on(
    r: &mut WgpuRenderer,
    s: &Scene,
    state: &SkyState,
    method: PointMethod,
    band_rows: Option<u64>,
) -> HdrImage {
    r.set_point_method(method);
    r.set_max_band_bytes(band_rows.map(|n| n * s.camera.image_size().0 as u64 * 16));
    let drawn = r.render_frame(s, state).map(|f| f.points);
    let out = r.render(s, state);
    r.set_max_band_bytes(None);
    let default = PointMethod::default_for(r.adapter_info().device_type);
    r.set_point_method(default);
    assert_eq!(drawn.unwrap(), Some(method));
    let out = out.unwrap();
    for n in ["stars", "planets"] {
        let p = out.passes.iter().find(|p| p.name == n).unwrap();
        assert!(p.ran && p.ms.is_some_and(|t| t >= 0.0), "{p:?}");
    }
    out.image
}

/// The 200 brightest peaks (at least `k` × the median, at least `min` of
/// them) of the CPU image are peaks of the quads image at the same pixel.
fn same_peaks(name: &str, c: &HdrImage, g: &HdrImage, k: f32, min: usize) {
    let pc = peaks(c, k);
    let pg = peaks(g, k);
    assert!(pc.len() >= min, "{name}: {} star peaks", pc.len());
    let n = pc.len().min(200);
    let same = pc
        .iter()
        .take(200)
        .filter(|&&(i, j, _)| pg.iter().any(|q| q.0 == i && q.1 == j))
        .count();
    eprintln!("{name}: {same}/{n} brightest CPU peaks at the same pixel (quads)");
    assert_eq!(same, n, "{name}");
}

/// The largest per-pixel relative difference of luminance,
/// |Y_a − Y_b| / max(Y_a, Y_b), over the pixels with any light.
fn max_rel(a: &HdrImage, b: &HdrImage) -> f64 {
    max_rel_above(a, b, 0.0)
}

/// [`max_rel`] with the denominator at least `floor` × the brightest
/// pixel's luminance.
fn max_rel_above(a: &HdrImage, b: &HdrImage, floor: f64) -> f64 {
    let peak = a
        .pixels
        .iter()
        .map(|p| luminance(*p) as f64)
        .fold(0.0, f64::max);
    let mut m = 0.0f64;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        let (x, y) = (luminance(*p) as f64, luminance(*q) as f64);
        let s = x.abs().max(y.abs()).max(floor * peak);
        if s > 0.0 {
            m = m.max((x - y).abs() / s);
        }
    }
    m
}

/// Quads vs CPU, quads vs tiles, quads banded (`band_rows`) vs unbanded;
/// peaks of at least `k` × the median, `min` of them. Returns the CPU and
/// quads images.
fn compare(name: &str, s: &Scene, k: f32, min: usize, band_rows: u64) -> (HdrImage, HdrImage) {
    let state = SkyState::at(s).unwrap();
    let c = CpuRenderer::new(None).render(s, &state).unwrap().image;
    let q = render(s, &state, PointMethod::Quads, None);
    let t = render(s, &state, PointMethod::Tiles, None);
    assert_parity(&format!("{name}: quads vs CPU"), &c, &q);
    let qt = max_rel(&q, &t);
    let format = gpu().quad_format();
    eprintln!("{name}: quads vs tiles max relative {qt:.2e} ({format:?})");
    same_peaks(name, &c, &q, k, min);
    let (bound, floor) = if format == wgpu::TextureFormat::Rgba32Float {
        (1e-6, 0.0)
    } else {
        (1e-2, 1e-8)
    };
    let qt = max_rel_above(&t, &q, floor);
    assert!(qt <= bound, "{name}: quads vs tiles {qt:e} > {bound:e}");
    // Banded frames: the same image.
    let banded = render(s, &state, PointMethod::Quads, Some(band_rows));
    let qb = max_rel_above(&q, &banded, floor);
    assert!(qb <= bound, "{name}: banded quads vs quads {qb:e}");
    (c, q)
}

fn night(p: Projection, w: u32, h: u32) -> Scene {
    let s = scene("2024-01-15T19:30:00Z", p, w, h);
    let state = SkyState::at(&s).unwrap();
    assert!(state.sun.alt_deg < -18.0, "{}", state.sun.alt_deg);
    s
}

#[test]
fn quads_night_fisheye() {
    let s = night(Projection::Fisheye, 256, 256);
    compare("quads: night, fisheye", &s, 20.0, 50, 7);
}

/// Equirect: footprints across the 0°/360° seam (one record per wrap), the
/// poles' rows, stars at the horizon (the ground check).
#[test]
fn quads_night_equirect() {
    let s = night(Projection::Equirect, 512, 256);
    compare("quads: night, equirect", &s, 20.0, 50, 7);
}

/// Cube map: a footprint's quad is clipped to its face.
#[test]
fn quads_night_cube_map() {
    let s = night(Projection::Cubemap, 96, 96);
    compare("quads: night, cube map (6×96²)", &s, 20.0, 50, 5);
}

/// The brightest planet's glare disk (radius > 2 px): the quad covers it.
#[test]
fn quads_planet_glare_perspective() {
    let mut s = scene("2024-01-15T19:30:00Z", Projection::Perspective, 192, 128);
    let state = SkyState::at(&s).unwrap();
    let p = state
        .night
        .planets
        .iter()
        .filter(|p| p.dir.z > 0.2)
        .max_by(|a, b| a.lux.total_cmp(&b.lux))
        .copied()
        .expect("a planet well above the horizon");
    s.camera.yaw_deg = (p.dir.x as f64).atan2(p.dir.y as f64).to_degrees();
    s.camera.pitch_deg = (p.dir.z as f64).asin().to_degrees();
    s.camera.fov_deg = 8.0;
    let frame = CpuRenderer::new(None)
        .plan(&s, &state)
        .unwrap()
        .night
        .expect("night passes planned");
    let plans = frame.splat_plans(&s, &frame.planets);
    assert!(plans.iter().any(|(p, _)| p.glare_r_px > 2.0), "no glare");
    let (c, q) = compare("quads: planet glare, perspective 8°", &s, 20.0, 1, 5);
    // The glare disk's light: Σ luminance within its radius + 1 px.
    let (px, py) = s
        .camera
        .dir_to_pixel(DVec3::from_array([
            p.dir.x as f64,
            p.dir.y as f64,
            p.dir.z as f64,
        ]))
        .expect("the planet is in view");
    let rg = plans
        .iter()
        .map(|(p, _)| p.glare_r_px)
        .fold(0.0f32, f32::max) as f64;
    let near = |img: &HdrImage| -> f64 {
        let mut sum = 0.0;
        for (i, v) in img.pixels.iter().enumerate() {
            let (x, y) = ((i % img.width) as f64 + 0.5, (i / img.width) as f64 + 0.5);
            if (x - px).hypot(y - py) <= rg + 1.0 {
                sum += luminance(*v) as f64;
            }
        }
        sum
    };
    let (ec, eq) = (near(&c), near(&q));
    eprintln!("planet glare: Σ Y within {rg:.1} + 1 px CPU {ec:.4e}, quads {eq:.4e}");
    assert!((eq / ec - 1.0).abs() < 0.01, "glare {eq} vs {ec}");
}

/// The moonlit night with the full Moon 40° up: the Moon pass after the
/// stars replaces what the quads drew by its coverage (pass order).
#[test]
fn quads_moonlit_night_moon_up_fisheye() {
    let mut s = scene("2024-01-25T20:00:00Z", Projection::Fisheye, 256, 256);
    s.effects = vec![
        Effect::Milkyway,
        Effect::Stars,
        Effect::Planets,
        Effect::Moon,
        Effect::Atmosphere,
    ];
    let state = SkyState::at(&s).unwrap();
    assert!(state.runs(Effect::Moon), "{:?}", state.moon.alt_deg);
    compare("quads: moonlit night, Moon up, fisheye", &s, 1.3, 25, 5);
}

/// The rgba16float quad target (adapters without `FLOAT32_BLENDABLE`):
/// within 1 % of the tiles per pixel in luminance above 10⁻⁸ × the
/// brightest pixel (11-bit significand, one rounding per blended
/// footprint, the target scaled by `quad_scale`), the CPU parity figures
/// hold; other formats are refused.
#[test]
fn quads_half_float_target() {
    let s = night(Projection::Fisheye, 192, 192);
    let state = SkyState::at(&s).unwrap();
    // The lock is held throughout: other tests never see the half target.
    let mut r = gpu();
    let t = render_on(&mut r, &s, &state, PointMethod::Tiles, None);
    let before = r.quad_format();
    r.set_quad_format(wgpu::TextureFormat::Rgba16Float).unwrap();
    let q = render_on(&mut r, &s, &state, PointMethod::Quads, None);
    r.set_quad_format(before).unwrap();
    let full = (before == wgpu::TextureFormat::Rgba32Float)
        .then(|| render_on(&mut r, &s, &state, PointMethod::Quads, None));
    assert!(r.set_quad_format(wgpu::TextureFormat::Rgba8Unorm).is_err());
    drop(r);
    let qt = max_rel(&q, &t);
    let qt6 = max_rel_above(&t, &q, 1e-6);
    let qt8 = max_rel_above(&t, &q, 1e-8);
    eprintln!("rgba16float vs tiles above 1e-6 × the peak: {qt6:.2e}, above 1e-8: {qt8:.2e}");
    let c = CpuRenderer::new(None).render(&s, &state).unwrap().image;
    let d = rel_diffs(&c, &q);
    let (med, p99) = (percentile(&d, 0.5), percentile(&d, 0.99));
    eprintln!(
        "quads rgba16float: vs tiles max relative {qt:.2e}; vs CPU median {:.4} %, p99 {:.4} %",
        med * 100.0,
        p99 * 100.0
    );
    // Above 10⁻⁸ × the brightest pixel (fainter light falls into the
    // format's subnormals even after `quad_scale`).
    assert!(qt8 <= 1e-2, "rgba16float quads vs tiles {qt8:e}");
    // The half-float target does round: it differs from the full one.
    if let Some(f) = full {
        assert!(
            max_rel(&f, &q) > 0.0,
            "rgba16float drew the rgba32float image"
        );
    }
    assert!(med <= 0.02 && p99 <= 0.10, "{med} {p99}");
    same_peaks("quads rgba16float", &c, &q, 20.0, 50);
}
