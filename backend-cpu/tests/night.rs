//! CPU renderer, night passes: star positions and photometry against the
//! exact star reduction of `himmel_astro::stars` (not the renderer's fast
//! path), hard cases (zenith, poles, a 0.5° field), culling at noon, and the
//! dark-sky zenith luminance.
//!
//! Reference positions: `StarReduction::topocentric` (space motion,
//! parallax, deflection, annual + diurnal aberration, precession–nutation,
//! sidereal time) + standard refraction, mapped to pixels with the fisheye
//! formula of conventions.md written out here.

use himmel_astro::frames::NutationModel;
use himmel_astro::stars::{StarReduction, StarTopocentric};
use himmel_astro::{Epoch, Instant, Observer};
use himmel_catalog::{Catalog, Star};
use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::LutConfig;
use himmel_skymodel::renderer::{HdrImage, RenderOutput};
use himmel_skymodel::spectrum::luminance;
use himmel_skymodel::{Effect, Exposure, Projection, Scene, SkyRenderer, SkyState};
use std::f64::consts::FRAC_PI_2;

const V0_LUX: f64 = 2.54e-6;

fn scene(time: &str, lat: f64, lon: f64, effects: Vec<Effect>, w: u32, p: Projection) -> Scene {
    let mut s = Scene::default();
    s.time.utc = time.into();
    s.observer.lat_deg = lat;
    s.observer.lon_deg = lon;
    s.effects = effects;
    s.camera.width = w;
    s.camera.height = w;
    s.camera.projection = p;
    s.exposure = Exposure::Ev100(-6.0);
    s.lut = LutConfig::small();
    s
}

fn render(s: &Scene) -> RenderOutput {
    let state = SkyState::at(s).unwrap();
    CpuRenderer::new(None).render(s, &state).unwrap()
}

fn reduction(time: &str) -> StarReduction {
    let utc = himmel_astro::time::parse_rfc3339(time).unwrap();
    let instant = Instant::from_utc(&utc).unwrap();
    StarReduction::new(&Epoch::new(&instant, NutationModel::Iau1980))
}

/// Continuous fisheye pixel of a refracted altitude/azimuth (conventions.md).
fn fisheye_pixel(w: usize, alt_deg: f64, az_deg: f64) -> (f64, f64) {
    let r = w as f64 / 2.0;
    let rho = (90.0 - alt_deg) / 90.0 * r;
    let az = az_deg.to_radians();
    (r - rho * az.sin(), r - rho * az.cos())
}

/// Fisheye pixel solid angle: (90°/R)² · sin z / z.
fn fisheye_omega(w: usize, x: f64, y: f64) -> f64 {
    let r = w as f64 / 2.0;
    let a = FRAC_PI_2 / r;
    let z = a * (x - r).hypot(y - r);
    if z < 1e-12 {
        a * a
    } else {
        a * a * z.sin() / z
    }
}

/// Σ L · Ω over a (2k+1)² window centred on pixel (cx, cy).
fn window_lux(img: &HdrImage, cx: f64, cy: f64, k: i64) -> f64 {
    let (ci, cj) = (cx.floor() as i64, cy.floor() as i64);
    let mut e = 0.0;
    for j in cj - k..=cj + k {
        for i in ci - k..=ci + k {
            if i < 0 || j < 0 || i >= img.width as i64 || j >= img.height as i64 {
                continue;
            }
            let p = img.pixels[j as usize * img.width + i as usize];
            e += luminance(p) as f64 * fisheye_omega(img.width, i as f64 + 0.5, j as f64 + 0.5);
        }
    }
    e
}

/// The brightest pixel within ±k of (cx, cy): its centre.
fn peak(img: &HdrImage, cx: f64, cy: f64, k: i64) -> (f64, f64) {
    let (ci, cj) = (cx.floor() as i64, cy.floor() as i64);
    let mut best = (f32::MIN, 0.0, 0.0);
    for j in cj - k..=cj + k {
        for i in ci - k..=ci + k {
            if i < 0 || j < 0 || i >= img.width as i64 || j >= img.height as i64 {
                continue;
            }
            let y = luminance(img.pixels[j as usize * img.width + i as usize]);
            if y > best.0 {
                best = (y, i as f64 + 0.5, j as f64 + 0.5);
            }
        }
    }
    (best.1, best.2)
}

fn topo(red: &StarReduction, star: &Star, lat: f64, lon: f64) -> StarTopocentric {
    red.topocentric(&star.astrometry, &Observer::new(lat, lon, 0.0).unwrap())
}

const MUNICH: (f64, f64) = (48.14, 11.58);

#[test]
fn fifteen_brightest_stars_above_20_degrees_peak_within_one_pixel() {
    // A night render: stars over the Milky Way, through the atmosphere.
    let time = "2024-01-15T21:00:00Z";
    let s = scene(
        time,
        MUNICH.0,
        MUNICH.1,
        vec![Effect::Milkyway, Effect::Stars, Effect::Atmosphere],
        1024,
        Projection::Fisheye,
    );
    let out = render(&s);
    for p in &out.passes {
        let want = ["milkyway", "stars", "atmosphere"].contains(&p.name.as_str());
        assert_eq!(p.ran, want, "{}: {:?}", p.name, p.reason);
    }
    let red = reduction(time);
    let cat = Catalog::embedded().unwrap();
    let mut n = 0;
    let mut worst: f64 = 0.0;
    for star in cat.stars() {
        let t = topo(&red, star, MUNICH.0, MUNICH.1);
        if t.alt_deg() <= 20.0 {
            continue;
        }
        let (x, y) = fisheye_pixel(1024, t.alt_refracted_deg(), t.az_deg());
        let (px, py) = peak(&out.image, x, y, 4);
        let d = (px - x).hypot(py - y);
        eprintln!(
            "{:12} V {:5.2} alt {:6.2}° expected ({x:8.2}, {y:8.2}) peak ({px}, {py}) {d:.2} px",
            star.label(),
            star.vmag,
            t.alt_deg()
        );
        assert!(d <= 1.0, "{}: {d} px", star.label());
        worst = worst.max(d);
        n += 1;
        if n == 15 {
            break;
        }
    }
    assert_eq!(n, 15);
    eprintln!("worst peak offset {worst:.3} px");
}

#[test]
fn sirius_vega_arcturus_integrated_illuminance_within_10_percent() {
    let cat = Catalog::embedded().unwrap();
    for (time, names) in [
        ("2024-01-15T21:00:00Z", vec!["Sirius"]),
        ("2024-07-01T21:00:00Z", vec!["Vega", "Arcturus"]),
    ] {
        let s = scene(
            time,
            MUNICH.0,
            MUNICH.1,
            vec![Effect::Stars],
            1024,
            Projection::Fisheye,
        );
        let out = render(&s);
        let red = reduction(time);
        for name in names {
            let star = cat.by_name(name).unwrap();
            let t = topo(&red, star, MUNICH.0, MUNICH.1);
            assert!(t.alt_deg() > 10.0, "{name} is up");
            let (x, y) = fisheye_pixel(1024, t.alt_refracted_deg(), t.az_deg());
            let e = window_lux(&out.image, x, y, 12);
            // The other catalogue stars inside the window (e.g. ε and ζ Lyr
            // next to Vega), at their exact places.
            let (ci, cj) = (x.floor(), y.floor());
            let others: f64 = cat
                .stars()
                .iter()
                .filter(|o| o.hip != star.hip)
                .filter_map(|o| {
                    let ot = topo(&red, o, MUNICH.0, MUNICH.1);
                    let (ox, oy) = fisheye_pixel(1024, ot.alt_refracted_deg(), ot.az_deg());
                    ((ox.floor() - ci).abs() <= 12.0 && (oy.floor() - cj).abs() <= 12.0)
                        .then(|| V0_LUX * 10f64.powf(-0.4 * o.vmag))
                })
                .sum();
            let want = V0_LUX * 10f64.powf(-0.4 * star.vmag);
            eprintln!(
                "{name}: Σ L·Ω = {e:.4e} lx − other stars {others:.3e} lx; 2.54e-6 · 10^(−0.4 V) = {want:.4e} lx"
            );
            let e = e - others;
            assert!((e / want - 1.0).abs() < 0.02, "{name}: {e} vs {want}");
        }
    }
}

/// Vega's apparent place at `time` and the observer that has it at the zenith.
fn vega_zenith_observer(time: &str) -> (f64, f64) {
    let red = reduction(time);
    let vega = Catalog::embedded().unwrap().by_name("Vega").unwrap();
    let geo = red.apparent(&vega.astrometry);
    let gast = red.epoch().gast().to_degrees();
    let lon = (geo.ra_deg() - gast + 540.0).rem_euclid(360.0) - 180.0;
    (geo.dec_deg(), lon)
}

#[test]
fn star_at_the_zenith_is_at_the_image_centre_with_its_flux() {
    let time = "2024-07-01T00:00:00Z";
    let (lat, lon) = vega_zenith_observer(time);
    let mut s = scene(time, lat, lon, vec![Effect::Stars], 65, Projection::Fisheye);
    s.stars.limit_mag = 1.0;
    let out = render(&s);
    let (px, py) = peak(&out.image, 32.5, 32.5, 5);
    assert_eq!((px, py), (32.5, 32.5));
    let vega = Catalog::embedded().unwrap().by_name("Vega").unwrap();
    let want = V0_LUX * 10f64.powf(-0.4 * vega.vmag);
    let e = window_lux(&out.image, 32.5, 32.5, 4);
    assert!((e / want - 1.0).abs() < 0.01, "{e} vs {want}");
    assert!(out
        .image
        .pixels
        .iter()
        .all(|p| p.iter().all(|v| v.is_finite())));
}

#[test]
fn observers_at_the_poles_see_every_star_above_their_horizon() {
    let time = "2024-03-20T12:00:00Z";
    let red = reduction(time);
    let cat = Catalog::embedded().unwrap();
    for lat in [90.0, -90.0] {
        let s = scene(
            time,
            lat,
            0.0,
            vec![Effect::Stars],
            128,
            Projection::Fisheye,
        );
        let out = render(&s);
        let img = &out.image;
        assert!(img.pixels.iter().all(|p| p.iter().all(|v| v.is_finite())));
        let mut e = 0.0;
        for (i, p) in img.pixels.iter().enumerate() {
            let (x, y) = ((i % 128) as f64 + 0.5, (i / 128) as f64 + 0.5);
            // Inside the horizon circle only: nothing celestial below it.
            if (x - 64.0).hypot(y - 64.0) > 64.0 {
                assert_eq!(luminance(*p), 0.0, "below the horizon at {x},{y}");
                continue;
            }
            e += luminance(*p) as f64 * fisheye_omega(128, x, y);
        }
        let want: f64 = cat
            .stars()
            .iter()
            .filter(|st| topo(&red, st, lat, 0.0).alt_refracted_deg() > 0.0)
            .map(|st| V0_LUX * 10f64.powf(-0.4 * st.vmag))
            .sum();
        eprintln!("lat {lat}: Σ L·Ω = {e:.5e} lx, Σ stars above the horizon {want:.5e} lx");
        assert!((e / want - 1.0).abs() < 0.01, "{lat}: {e} vs {want}");
    }
}

#[test]
fn half_degree_field_shows_vega_at_its_centre_with_its_flux() {
    let time = "2024-07-01T21:00:00Z";
    let red = reduction(time);
    let vega = Catalog::embedded().unwrap().by_name("Vega").unwrap();
    let t = topo(&red, vega, MUNICH.0, MUNICH.1);
    let mut s = scene(
        time,
        MUNICH.0,
        MUNICH.1,
        vec![Effect::Stars],
        64,
        Projection::Perspective,
    );
    s.camera.yaw_deg = t.az_deg();
    s.camera.pitch_deg = t.alt_refracted_deg();
    s.camera.fov_deg = 0.5;
    // No glare: the core alone shows how concentrated the star is.
    s.stars.glare = 0.0;
    let out = render(&s);
    let img = &out.image;
    let (px, py) = peak(img, 32.0, 32.0, 31);
    assert!((px - 32.0).hypot(py - 32.0) <= 1.0, "peak at {px},{py}");
    // Σ L · Ω with the pinhole's area element s² / (1 + x² + y²)^(3/2).
    let sp = 2.0 * (0.25f64).to_radians().tan() / 64.0;
    let mut e = 0.0;
    for (i, p) in img.pixels.iter().enumerate() {
        let x = ((i % 64) as f64 + 0.5 - 32.0) * sp;
        let y = ((i / 64) as f64 + 0.5 - 32.0) * sp;
        e += luminance(*p) as f64 * sp * sp / (1.0 + x * x + y * y).powf(1.5);
    }
    let want = V0_LUX * 10f64.powf(-0.4 * vega.vmag);
    assert!((e / want - 1.0).abs() < 0.01, "{e} vs {want}");
    // The same star in the 0.5° field is far brighter per pixel than in a
    // 1024² all-sky frame (≈ 0.08 cd/m² there): narrow fields show fainter stars.
    let peak_l = img
        .pixels
        .iter()
        .map(|p| luminance(*p))
        .fold(0.0f32, f32::max);
    assert!(peak_l > 1.0, "{peak_l} cd/m²");
}

#[test]
fn stars_pass_is_culled_at_noon_and_runs_at_night() {
    let mut s = scene(
        "2024-06-21T11:10:00Z",
        MUNICH.0,
        MUNICH.1,
        Effect::ALL.to_vec(),
        64,
        Projection::Fisheye,
    );
    s.exposure = Exposure::Auto;
    let out = render(&s);
    let pass = |o: &RenderOutput, n: &str| o.passes.iter().find(|p| p.name == n).unwrap().clone();
    let stars = pass(&out, "stars");
    eprintln!("noon: {:?}", stars.reason);
    assert!(!stars.ran && stars.ms.is_none());
    assert!(stars
        .reason
        .as_deref()
        .unwrap()
        .starts_with("sky background brighter than the brightest visible star"));
    for n in ["planets", "milkyway"] {
        let p = pass(&out, n);
        assert!(!p.ran, "{n}");
        assert!(
            p.reason.unwrap().starts_with("sky background brighter"),
            "{n}"
        );
    }
    s.time.utc = "2024-01-15T21:00:00Z".into();
    let out = render(&s);
    for n in ["stars", "planets", "milkyway"] {
        assert!(pass(&out, n).ran, "{n} at night");
    }
}

/// The zenith pixel's luminance of a 65×65 fisheye with the Milky Way and
/// the atmosphere at `time` for an observer whose zenith is (ra, dec) of date.
fn zenith_luminance(time: &str, ra_deg: f64, dec_deg: f64) -> f64 {
    let red = reduction(time);
    let gast = red.epoch().gast().to_degrees();
    let lon = (ra_deg - gast + 540.0).rem_euclid(360.0) - 180.0;
    let s = scene(
        time,
        dec_deg,
        lon,
        vec![Effect::Milkyway, Effect::Atmosphere],
        65,
        Projection::Fisheye,
    );
    let state = SkyState::at(&s).unwrap();
    assert!(state.sun.alt_deg < -18.0, "astronomical night");
    let out = CpuRenderer::new(None).render(&s, &state).unwrap();
    luminance(out.image.pixels[32 * 65 + 32]) as f64
}

#[test]
fn dark_sky_zenith_luminance_is_natural() {
    // North galactic pole at the zenith (α 192.9°, δ +27.1°), spring midnight.
    let pole = zenith_luminance("2024-04-15T22:00:00Z", 193.0, 27.1);
    // Cygnus (α 305°, δ +40°) at the zenith, in the Milky Way, September.
    let band = zenith_luminance("2024-09-15T21:00:00Z", 305.0, 40.0);
    eprintln!("zenith: galactic pole {pole:.3e} cd/m², Cygnus {band:.3e} cd/m²");
    assert!((2e-4 / 1.5..2e-4 * 1.5).contains(&pole), "{pole}");
    assert!(band > 1.2 * pole, "{band} vs {pole}");
    assert!(band < 1e-3);
}

#[test]
fn planets_are_drawn_with_their_magnitude() {
    // Jupiter high in the south-west from Munich, January 2024 (V ≈ −2.5).
    let time = "2024-01-15T19:00:00Z";
    let s = scene(
        time,
        MUNICH.0,
        MUNICH.1,
        vec![Effect::Planets],
        512,
        Projection::Fisheye,
    );
    let state = SkyState::at(&s).unwrap();
    let out = CpuRenderer::new(None).render(&s, &state).unwrap();
    let utc = himmel_astro::time::parse_rfc3339(time).unwrap();
    let sky = himmel_astro::Sky::new(
        himmel_astro::Precision::Standard,
        &Instant::from_utc(&utc).unwrap(),
    );
    let obs = Observer::new(MUNICH.0, MUNICH.1, 0.0).unwrap();
    let jt = sky.topocentric(himmel_astro::Body::Jupiter, &obs).unwrap();
    let mag = sky.planet_magnitude(himmel_astro::Body::Jupiter).unwrap();
    assert!(jt.alt_deg() > 20.0 && mag < -2.0);
    let (x, y) = fisheye_pixel(512, jt.alt_refracted_deg(), jt.az_deg());
    let (px, py) = peak(&out.image, x, y, 4);
    assert!((px - x).hypot(py - y) <= 1.0);
    let e = window_lux(&out.image, x, y, 12);
    let want = V0_LUX * 10f64.powf(-0.4 * mag);
    assert!((e / want - 1.0).abs() < 0.02, "{e} vs {want}");
    // Jupiter is yellowish-white: red above blue.
    let p = out.image.pixels[py as usize * 512 + px as usize];
    assert!(p[0] > p[2], "{p:?}");
}

#[test]
fn scintillation_is_deterministic_per_seed() {
    let time = "2024-01-15T21:00:00Z";
    let mut s = scene(
        time,
        MUNICH.0,
        MUNICH.1,
        vec![Effect::Stars],
        96,
        Projection::Fisheye,
    );
    s.stars.scintillation = true;
    s.stars.seed = 1;
    let a = render(&s).image.pixels;
    let b = render(&s).image.pixels;
    assert_eq!(a, b);
    s.stars.seed = 2;
    let c = render(&s).image.pixels;
    assert_ne!(a, c);
    s.stars.scintillation = false;
    let d = render(&s).image.pixels;
    // Twinkling changes single stars by tens of per cent but leaves the
    // total flux of thousands of stars nearly unchanged (unit-mean noise).
    let total = |p: &[[f32; 3]]| p.iter().map(|q| luminance(*q) as f64).sum::<f64>();
    assert!((total(&a) / total(&d) - 1.0).abs() < 0.1);
}

#[test]
fn auto_exposure_estimate_before_rendering_matches_the_metering() {
    // Noon, sunset, civil and nautical twilight, night (Munich, 21 June 2024).
    for time in [
        "2024-06-21T11:10:00Z",
        "2024-06-21T19:05:00Z",
        "2024-06-21T19:45:00Z",
        "2024-06-21T20:30:00Z",
        "2024-06-21T23:00:00Z",
    ] {
        let mut s = scene(
            time,
            MUNICH.0,
            MUNICH.1,
            Effect::ALL.to_vec(),
            128,
            Projection::Fisheye,
        );
        s.exposure = Exposure::Auto;
        let state = SkyState::at(&s).unwrap();
        let mut r = CpuRenderer::new(None);
        let out = r.render(&s, &state).unwrap();
        let metered = himmel_skymodel::camera::meter_ev100(&out.image.pixels, &out.image.valid);
        let frame = r.plan(&s, &state).unwrap().night.unwrap();
        let ran: Vec<_> = out
            .passes
            .iter()
            .filter(|p| p.ran)
            .map(|p| p.name.clone())
            .collect();
        eprintln!(
            "{time}: estimated EV100 {:.2}, metered {metered:.2}; ran {ran:?}",
            frame.ev100
        );
        assert!((frame.ev100 - metered).abs() < 0.25, "{time}");
    }
}

#[test]
fn band_parallel_splats_equal_a_serial_splat() {
    use himmel_skymodel::night::white_luminance;
    use himmel_skymodel::stars::{splat, Psf, SplatScratch};
    let s = scene(
        "2024-01-15T21:00:00Z",
        MUNICH.0,
        MUNICH.1,
        vec![Effect::Stars],
        300,
        Projection::Fisheye,
    );
    let out = render(&s);
    let state = SkyState::at(&s).unwrap();
    let psf = Psf {
        core_px: s.stars.core_px as f32,
        glare: s.stars.glare as f32,
        white_cd_m2: white_luminance(-6.0),
    };
    let mut serial = vec![[0.0f32; 3]; 300 * 300];
    let mut scratch = SplatScratch::default();
    for p in state.night.stars(&s) {
        splat(
            &mut serial,
            &s.camera,
            p.dir,
            p.lux,
            p.rgb,
            &psf,
            &mut scratch,
        );
    }
    let peak = serial.iter().map(|p| luminance(*p)).fold(0.0f32, f32::max);
    for (a, b) in out.image.pixels.iter().zip(&serial) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() <= 1e-5 * peak, "{a:?} vs {b:?}");
        }
    }
}
