//! The Moon pass: photometry against the observed lunar phase curve,
//! position, size, phase and bright-limb direction measured on the image
//! against the ephemeris, hard cases, lunar and solar eclipses, culling.

use himmel_astro::{Body, Instant, Precision, Sky, UtcDateTime};
use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::LutConfig;
use himmel_skymodel::spectrum::luminance;
use himmel_skymodel::{Effect, Projection, Scene, SkyRenderer, SkyState};

fn utc(s: &str) -> UtcDateTime {
    himmel_astro::time::parse_rfc3339(s).unwrap()
}

fn fmt(t: &UtcDateTime) -> String {
    format!(
        "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}Z",
        t.year, t.month, t.day, t.hour, t.minute, t.second as u32
    )
}

/// A site where the Moon stands about 60° high, 25° west of the meridian.
fn site_for(t: &UtcDateTime) -> (f64, f64) {
    let i = Instant::from_utc(t).unwrap();
    let sky = Sky::new(Precision::Standard, &i);
    let m = sky.apparent(Body::Moon).unwrap();
    let lon = (m.ra - sky.epoch().gast()).to_degrees() + 25.0;
    let lon = (lon + 540.0).rem_euclid(360.0) - 180.0;
    let lat = (m.dec.to_degrees() - 25.0).clamp(-89.0, 89.0);
    (lat, lon)
}

/// A perspective scene with a 1° field centred on the Moon's apparent place.
fn moon_scene(t: &str, lat: f64, lon: f64, size: u32, effects: Vec<Effect>) -> (Scene, SkyState) {
    let mut s = Scene::default();
    s.time.utc = t.into();
    s.observer.lat_deg = lat;
    s.observer.lon_deg = lon;
    s.effects = effects;
    s.lut = LutConfig::small();
    s.camera.projection = Projection::Perspective;
    s.camera.width = size;
    s.camera.height = size;
    s.camera.fov_deg = 1.0;
    let st = SkyState::at(&s).unwrap();
    s.camera.yaw_deg = st.moon.az_deg;
    s.camera.pitch_deg = st.moon.alt_refracted_deg;
    let st = SkyState::at(&s).unwrap();
    (s, st)
}

fn render(s: &Scene, st: &SkyState) -> himmel_skymodel::RenderOutput {
    CpuRenderer::new(None).render(s, st).unwrap()
}

/// Σ L Ω over a perspective image, lux.
fn illuminance(s: &Scene, img: &himmel_skymodel::HdrImage) -> f64 {
    let t = (s.camera.fov_deg.to_radians() / 2.0).tan();
    let h = img.height as f64;
    let px = 2.0 * t / h;
    let mut e = 0.0;
    for (i, p) in img.pixels.iter().enumerate() {
        let nx = ((i % img.width) as f64 + 0.5 - img.width as f64 / 2.0) * px;
        let ny = ((i / img.width) as f64 + 0.5 - h / 2.0) * px;
        e += luminance(*p) as f64 * px * px / (1.0 + nx * nx + ny * ny).powf(1.5);
    }
    e
}

/// Instants (1-hour steps from 2024-01-01) whose topocentric-free
/// geocentric phase angle is within 0.5° of `target`, waxing and waning.
fn dates_with_phase(target: f64) -> Vec<String> {
    let mut out = Vec::new();
    let (mut waxing_done, mut waning_done) = (false, false);
    let start = utc("2024-01-01T00:00:00Z");
    let i0 = Instant::from_utc(&start).unwrap();
    for k in 0..24 * 60 {
        let i = Instant::from_tt_ut1(i0.jd_tt + k as f64 / 24.0, i0.jd_ut1 + k as f64 / 24.0);
        let sky = Sky::new(Precision::Standard, &i);
        let ph = sky.moon_physical().unwrap();
        let p = ph.phase_angle.to_degrees();
        if (p - target).abs() > 0.5 {
            continue;
        }
        let s = sky.apparent(Body::Sun).unwrap();
        let m = sky.apparent(Body::Moon).unwrap();
        let waxing = (m.ecl_lon - s.ecl_lon).rem_euclid(std::f64::consts::TAU) < std::f64::consts::PI;
        if waxing && !waxing_done {
            waxing_done = true;
            out.push(fmt(&i.to_utc()));
        } else if !waxing && !waning_done {
            waning_done = true;
            out.push(fmt(&i.to_utc()));
        }
        if waxing_done && waning_done {
            break;
        }
    }
    out
}

#[test]
fn photometry_follows_the_lunar_phase_curve() {
    for target in [5.0, 15.0, 30.0, 60.0, 90.0, 120.0] {
        let dates = dates_with_phase(target);
        assert!(!dates.is_empty(), "no date with phase {target}");
        for d in dates {
            let (lat, lon) = site_for(&utc(&d));
            let (s, st) = moon_scene(&d, lat, lon, 256, vec![Effect::Moon]);
            let out = render(&s, &st);
            let e = illuminance(&s, &out.image);
            let want = st.moon.illuminance_lux;
            eprintln!(
                "{d} phase {:.1}° E {e:.4e} lx, curve {want:.4e} lx, ratio {:.3}",
                st.moon.phase_angle_topo.to_degrees(),
                e / want
            );
            assert!((e / want - 1.0).abs() < 0.15, "{d}: {e} vs {want}");
        }
    }
}
