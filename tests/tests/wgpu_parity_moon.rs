//! Parity of the wgpu backend with the CPU reference renderer, the Moon
//! and eclipses: the moonlit sky, the lunar disk (close-up, low and
//! refracted, rising), a lunar and a solar eclipse with its corona, and the
//! Moon pass's dispatch rectangle. Figures as in `wgpu_parity_sky.rs`
//! (median ≤ 2 %, p99 ≤ 10 %, PSNR ≥ 35 dB). Runs on any adapter (lavapipe
//! in CI).
use glam::DVec3;
use himmel_cpu::CpuRenderer;
use himmel_skymodel::spectrum::luminance;
use himmel_skymodel::{Effect, HdrImage, Projection, Scene, SkyRenderer, SkyState};

mod wgpu_common;
use wgpu_common::*;

/// A moonlit night with the Moon just below the horizon (−6° < alt < 0°,
/// three days after full Moon, Sun −24°): the Moon pass does not run but
/// its light is in the sky (cpu lib.rs `SkyLight`: a second sky view lit
/// from the Moon). The moonlit sky carries most of the light.
fn moonlit_below_horizon(p: Projection, w: u32, h: u32) {
    let mut s = scene("2024-01-28T18:35:00Z", p, w, h);
    s.effects = vec![Effect::Moon, Effect::Atmosphere];
    let state = SkyState::at(&s).unwrap();
    assert!(state.sun.alt_refracted_deg < -18.0, "{}", state.sun.alt_deg);
    let m = state.moon.alt_refracted_deg;
    assert!((-6.0..0.0).contains(&m), "Moon {m}");
    assert!(!state.runs(Effect::Moon));
    let pole = DVec3::from_array(state.celestial_pole).as_vec3();
    assert!(himmel_skymodel::moon::moonlight_scale(&s, &state.sun, &state.moon, pole).is_some());
    let name = format!("moonlit night, Moon {m:.1}°, {p:?}");
    let (_, g) = parity(&name, &s);
    // Without the Moon in the scene there is no moonlit sky: much darker.
    let mut s2 = s.clone();
    s2.effects = vec![Effect::Atmosphere];
    let state2 = SkyState::at(&s2).unwrap();
    let without = gpu().render(&s2, &state2).unwrap().image;
    let sum = |img: &HdrImage| -> f64 { img.pixels.iter().map(|p| luminance(*p) as f64).sum() };
    assert!(
        sum(&g) > 10.0 * sum(&without),
        "{} vs {}",
        sum(&g),
        sum(&without)
    );
}

#[test]
fn moonlit_night_moon_below_horizon_fisheye() {
    moonlit_below_horizon(Projection::Fisheye, 128, 128);
}

#[test]
fn moonlit_night_moon_below_horizon_equirect() {
    moonlit_below_horizon(Projection::Equirect, 256, 128);
}

/// Mean linear luminance over the pixels of a perspective image within
/// 0.95 of the Moon's drawn radius of its centre, and their number.
fn moon_disk_mean(s: &Scene, state: &SkyState, img: &HdrImage) -> (f64, usize) {
    let (cx, cy) = s
        .camera
        .dir_to_pixel(DVec3::from_array(state.moon.enu))
        .expect("the Moon in the frame");
    let t = (s.camera.fov_deg.to_radians() / 2.0).tan();
    let r = (state.moon.angular_radius * s.moon_scale).tan() / (2.0 * t / img.height as f64);
    let (mut sum, mut n) = (0.0, 0usize);
    for (i, p) in img.pixels.iter().enumerate() {
        let (x, y) = ((i % img.width) as f64 + 0.5, (i / img.width) as f64 + 0.5);
        if (x - cx).hypot(y - cy) < 0.95 * r {
            sum += luminance(*p) as f64;
            n += 1;
        }
    }
    (sum / n.max(1) as f64, n)
}

/// The Moon pass ran on the GPU with a time, as on the CPU; the
/// `moon-eclipse` entry says whether the eclipse shading ran.
fn moon_ran(s: &Scene, state: &SkyState, eclipse: bool) {
    let out = gpu().render(s, state).unwrap();
    let m = out.passes.iter().find(|p| p.name == "moon").unwrap();
    assert!(m.ran && m.ms.is_some(), "{m:?}");
    let e = out
        .passes
        .iter()
        .find(|p| p.name == "moon-eclipse")
        .unwrap();
    assert_eq!(e.ran, eclipse, "{e:?}");
    assert_eq!(e.reason.is_none(), eclipse, "{e:?}");
}

/// A moonlit night with the full Moon 40° high over Munich (phase 5°, Sun
/// −39°): the Moon (a sub-pixel disk, supersampled 8 × 8), the moonlit sky,
/// stars, planets and the Milky Way, fisheye.
#[test]
fn moonlit_night_full_moon_up_fisheye() {
    let mut s = scene("2024-01-25T20:00:00Z", Projection::Fisheye, 256, 256);
    s.effects = vec![
        Effect::Milkyway,
        Effect::Stars,
        Effect::Planets,
        Effect::Moon,
        Effect::Atmosphere,
    ];
    let state = SkyState::at(&s).unwrap();
    assert!(
        (38.0..43.0).contains(&state.moon.alt_deg),
        "{}",
        state.moon.alt_deg
    );
    assert!(state.moon.phase_angle_topo.to_degrees() < 8.0);
    let (c, g) = parity("moonlit night, full Moon 40°, fisheye", &s);
    moon_ran(&s, &state, false);
    // The brighter stars still show in the moonlit sky (the 31 peaks above
    // 1.3 × the median sky; the Moon is one), at the same pixels.
    same_peaks_above("moonlit night", &c, &g, 1.3, 25);
    // The disk (supersampled, a fraction of a pixel) carries the same light.
    let (mx, my) = s
        .camera
        .dir_to_pixel(DVec3::from_array(state.moon.enu))
        .unwrap();
    let near = |img: &HdrImage| -> f64 {
        let mut sum = 0.0;
        for (i, p) in img.pixels.iter().enumerate() {
            let (x, y) = ((i % img.width) as f64 + 0.5, (i / img.width) as f64 + 0.5);
            if (x - mx).hypot(y - my) <= 2.0 {
                sum += luminance(*p) as f64;
            }
        }
        sum
    };
    let (ec, eg) = (near(&c), near(&g));
    eprintln!("moonlit night: Σ Y within 2 px of the Moon CPU {ec:.4e}, GPU {eg:.4e}");
    assert!((eg / ec - 1.0).abs() < 0.01, "Moon {eg} vs {ec}");
    // Rendered in bands of 5 rows, the image is the same.
    let mut r = gpu();
    r.set_max_band_bytes(Some(256 * 16 * 5));
    let banded = r.render(&s, &state);
    r.set_max_band_bytes(None);
    assert_eq!(banded.unwrap().image, g, "banded");
}

/// The total lunar eclipse of 2025-03-14 at greatest eclipse (06:58:43
/// UTC, NASA/Espenak) from 22.3° S, 77.2° W, where the Moon stands 54°
/// high: the red umbra from the CPU's eclipse table, 1° perspective with
/// the stars and the atmosphere.
#[test]
fn lunar_eclipse_2025_03_14_perspective() {
    let mut s = scene("2025-03-14T06:58:43Z", Projection::Perspective, 192, 192);
    s.observer.lat_deg = -22.3;
    s.observer.lon_deg = -77.2;
    s.effects = vec![Effect::Stars, Effect::Moon, Effect::Atmosphere];
    s.camera.fov_deg = 1.0;
    let state = SkyState::at(&s).unwrap();
    s.camera.yaw_deg = state.moon.az_deg;
    s.camera.pitch_deg = state.moon.alt_refracted_deg;
    let state = SkyState::at(&s).unwrap();
    assert!(state.moon.alt_deg > 50.0, "{}", state.moon.alt_deg);
    assert!(state.moon.eclipse.is_some());
    let (c, g) = parity("lunar eclipse 2025-03-14, 1° perspective", &s);
    moon_ran(&s, &state, true);
    let (mc, n) = moon_disk_mean(&s, &state, &c);
    let (mg, _) = moon_disk_mean(&s, &state, &g);
    eprintln!("lunar eclipse: disk mean Y CPU {mc:.4e}, GPU {mg:.4e} cd/m² ({n} px)");
    assert!(n > 5_000);
    assert!((mg / mc - 1.0).abs() < 0.01, "{mg} vs {mc}");
}

/// Totality at Dallas, 2024-04-08 18:42:39 UTC: the Sun's sub-samples
/// behind the Moon are skipped and the corona drawn around the black disk
/// (2.5° perspective on the Sun); and the whole sky in a fisheye.
#[test]
fn solar_eclipse_totality_dallas() {
    let mut s = scene("2024-04-08T18:42:39Z", Projection::Perspective, 160, 160);
    s.observer.lat_deg = 32.7767;
    s.observer.lon_deg = -96.797;
    s.effects = vec![Effect::Moon, Effect::Sun, Effect::Atmosphere];
    s.camera.fov_deg = 2.5;
    let state = SkyState::at(&s).unwrap();
    s.camera.yaw_deg = state.sun.az_deg;
    s.camera.pitch_deg = state.sun.alt_refracted_deg;
    let state = SkyState::at(&s).unwrap();
    assert!(state.sun.visible_fraction < 1e-3);
    let (c, g) = parity("solar eclipse totality, Dallas, 2.5° perspective", &s);
    moon_ran(&s, &state, false);
    // The corona carries the frame's light (the Sun is hidden): Σ Y.
    let sum = |img: &HdrImage| -> f64 { img.pixels.iter().map(|p| luminance(*p) as f64).sum() };
    eprintln!("totality: Σ Y CPU {:.4e}, GPU {:.4e}", sum(&c), sum(&g));
    assert!((sum(&g) / sum(&c) - 1.0).abs() < 0.01);
    // In bands of 7 rows (the Sun's, the corona's and the Moon's
    // rectangles split across bands), the image is the same; the corona's
    // dispatch counts in the Sun pass's time.
    let banded = {
        let mut r = gpu();
        r.set_max_band_bytes(Some(160 * 16 * 7));
        let out = r.render(&s, &state);
        r.set_max_band_bytes(None);
        out.unwrap()
    };
    assert_eq!(banded.image, g, "banded");
    let ran: Vec<_> = banded
        .passes
        .iter()
        .filter(|p| p.ran)
        .map(|p| (p.name.as_str(), p.ms.is_some()))
        .collect();
    assert_eq!(ran, [("moon", true), ("sun", true), ("atmosphere", true)]);
    let mut f = s.clone();
    f.camera.projection = Projection::Fisheye;
    f.camera.width = 128;
    f.camera.height = 128;
    parity("solar eclipse totality, Dallas, fisheye", &f);
    // The partial phase twelve minutes earlier: the photosphere's crescent
    // beside the Moon's limb (the Sun's sub-samples behind the Moon skipped).
    let mut p = s.clone();
    p.time.utc = "2024-04-08T18:30:00Z".into();
    let st = SkyState::at(&p).unwrap();
    assert!((0.05..0.5).contains(&st.sun.visible_fraction));
    p.camera.yaw_deg = st.sun.az_deg;
    p.camera.pitch_deg = st.sun.alt_refracted_deg;
    let st = SkyState::at(&p).unwrap();
    let (c, g) = parity(
        "solar eclipse partial phase, Dallas 18:30, 2.5° perspective",
        &p,
    );
    let (ec, eg) = (sun_sum(&c, &p, &st, 30.0), sun_sum(&g, &p, &st, 30.0));
    eprintln!("partial phase: Σ Y within 30 px of the Sun CPU {ec:.4e}, GPU {eg:.4e}");
    assert!((eg / ec - 1.0).abs() < 0.01, "{eg} vs {ec}");
}

/// A 1° close-up of the waxing gibbous Moon (phase 57°, 65° high over
/// Munich) at 256 × 256: terminator relief from the normal map, the albedo
/// map, the analytic limb; the mean over the disk agrees within 1 %.
#[test]
fn moon_close_up_perspective() {
    let mut s = scene("2024-01-20T19:00:00Z", Projection::Perspective, 256, 256);
    s.effects = vec![Effect::Moon, Effect::Atmosphere];
    s.camera.fov_deg = 1.0;
    let state = SkyState::at(&s).unwrap();
    s.camera.yaw_deg = state.moon.az_deg;
    s.camera.pitch_deg = state.moon.alt_refracted_deg;
    let state = SkyState::at(&s).unwrap();
    let phase = state.moon.phase_angle_topo.to_degrees();
    assert!((50.0..65.0).contains(&phase), "{phase}");
    let (c, g) = parity("Moon close-up, phase 57°, 1° perspective", &s);
    moon_ran(&s, &state, false);
    let (mc, n) = moon_disk_mean(&s, &state, &c);
    let (mg, _) = moon_disk_mean(&s, &state, &g);
    eprintln!("close-up: disk mean Y CPU {mc:.2} GPU {mg:.2} cd/m² ({n} px)");
    assert!(n > 10_000);
    assert!((mg / mc - 1.0).abs() < 0.01, "{mg} vs {mc}");
    // In bands of 9 rows (the disk's rectangle split across bands) and
    // with CPU-clock timing, the image is the same.
    let mut r = gpu();
    r.set_max_band_bytes(Some(256 * 16 * 9));
    r.set_timestamps(false);
    let banded = r.render(&s, &state);
    r.set_max_band_bytes(None);
    r.set_timestamps(true);
    let banded = banded.unwrap();
    assert_eq!(banded.image, g, "banded");
    let m = banded.passes.iter().find(|p| p.name == "moon").unwrap();
    assert!(m.ms.is_some(), "{m:?}");
}

/// A low Moon (4° high) drawn with the differential refraction across its
/// disk (moon.rs `unrefract`, tabulated for the GPU), 2° perspective.
#[test]
fn low_moon_flattened_by_refraction() {
    let mut s = scene("2024-01-20T12:00:00Z", Projection::Perspective, 192, 192);
    s.effects = vec![Effect::Moon, Effect::Atmosphere];
    s.camera.fov_deg = 2.0;
    // The hour when the Moon rises through 4° at Munich.
    let mut state = SkyState::at(&s).unwrap();
    for m in 0..(24 * 12) {
        s.time.utc = format!("2024-01-20T{:02}:{:02}:00Z", m / 12, (m % 12) * 5);
        state = SkyState::at(&s).unwrap();
        if (3.0..5.0).contains(&state.moon.alt_refracted_deg) {
            break;
        }
    }
    assert!((3.0..5.0).contains(&state.moon.alt_refracted_deg));
    s.camera.yaw_deg = state.moon.az_deg;
    s.camera.pitch_deg = state.moon.alt_refracted_deg;
    let state = SkyState::at(&s).unwrap();
    let (c, g) = parity("low Moon (refraction), 2° perspective", &s);
    moon_ran(&s, &state, false);
    let (mc, _) = moon_disk_mean(&s, &state, &c);
    let (mg, _) = moon_disk_mean(&s, &state, &g);
    assert!((mg / mc - 1.0).abs() < 0.01, "{mg} vs {mc}");
    // The same Moon as a supersampled disk of a 256² fisheye (un-refracted
    // sub-samples), alone: the same light.
    let mut f = s.clone();
    f.camera.projection = Projection::Fisheye;
    f.camera.width = 256;
    f.camera.height = 256;
    f.effects = vec![Effect::Moon];
    let (c, g) = parity("low Moon (refraction), fisheye, Moon alone", &f);
    let sum = |img: &HdrImage| -> f64 { img.pixels.iter().map(|p| luminance(*p) as f64).sum() };
    assert!(sum(&c) > 0.0);
    assert!(
        (sum(&g) / sum(&c) - 1.0).abs() < 1e-3,
        "{} vs {}",
        sum(&g),
        sum(&c)
    );
}

/// The moonlit night of `moonlit_night_full_moon_up_fisheye` as a cube map
/// (6 × 64²: the Moon's sub-samples on its face) and as an equirect image
/// with the Moon drawn 12 × its size (`moon_scale`: the analytic limb, 26 px
/// across, with stars and the Milky Way behind it).
#[test]
fn moonlit_night_cube_map_and_large_moon_equirect() {
    let mut s = scene("2024-01-25T20:00:00Z", Projection::Cubemap, 64, 64);
    s.effects = vec![
        Effect::Milkyway,
        Effect::Stars,
        Effect::Planets,
        Effect::Moon,
        Effect::Atmosphere,
    ];
    let state = SkyState::at(&s).unwrap();
    parity("moonlit night, full Moon 40°, cube map (6×64²)", &s);
    moon_ran(&s, &state, false);
    let mut e = s.clone();
    e.camera.projection = Projection::Equirect;
    e.camera.width = 512;
    e.camera.height = 256;
    e.moon_scale = 12.0;
    let state = SkyState::at(&e).unwrap();
    let (c, g) = parity("moonlit night, Moon × 12, equirect 512×256", &e);
    moon_ran(&e, &state, false);
    // The disk replaces what is behind it: its pixels are the Moon's.
    let (mx, my) = e
        .camera
        .dir_to_pixel(DVec3::from_array(state.moon.enu))
        .unwrap();
    let at = |img: &HdrImage| luminance(img.pixels[my as usize * 512 + mx as usize]) as f64;
    eprintln!(
        "Moon × 12: centre pixel CPU {:.1} GPU {:.1} cd/m²",
        at(&c),
        at(&g)
    );
    assert!(at(&c) > 1000.0 && (at(&g) / at(&c) - 1.0).abs() < 1e-3);
}

/// Every pixel the CPU's Moon pass draws lies in the rectangle the GPU's
/// Moon pass is dispatched over (`moon_uniforms`), in all projections:
/// a perspective close-up, a supersampled fisheye disk, an equirect disk
/// × 12, a cube map and a low, refracted Moon.
#[test]
fn moon_rectangle_holds_every_drawn_pixel() {
    let close = |p: Projection, w: u32, h: u32, fov: f64, scale: f64, utc: &str| {
        let mut s = scene(utc, p, w, h);
        s.effects = vec![Effect::Moon];
        s.moon_scale = scale;
        s.camera.fov_deg = fov;
        let st = SkyState::at(&s).unwrap();
        s.camera.yaw_deg = st.moon.az_deg + 0.2 * fov;
        s.camera.pitch_deg = st.moon.alt_refracted_deg;
        s
    };
    let scenes = [
        close(
            Projection::Perspective,
            160,
            120,
            1.0,
            1.0,
            "2024-01-20T19:00:00Z",
        ),
        close(
            Projection::Fisheye,
            128,
            128,
            90.0,
            1.0,
            "2024-01-25T20:00:00Z",
        ),
        close(
            Projection::Equirect,
            256,
            128,
            90.0,
            12.0,
            "2024-01-25T20:00:00Z",
        ),
        close(
            Projection::Cubemap,
            48,
            48,
            90.0,
            4.0,
            "2024-01-25T20:00:00Z",
        ),
        close(
            Projection::Perspective,
            128,
            128,
            2.0,
            1.0,
            "2024-01-20T11:40:00Z",
        ),
    ];
    for s in &scenes {
        let state = SkyState::at(s).unwrap();
        let img = CpuRenderer::new(None).render(s, &state).unwrap().image;
        let rect = himmel_skymodel::frame::MoonFrame::new(s, &state, None, 0.0).rect;
        let [x0, y0, x1, y1] = rect;
        let mut drawn = 0;
        for (i, p) in img.pixels.iter().enumerate() {
            if luminance(*p) > 0.0 {
                drawn += 1;
                let (x, y) = ((i % img.width) as u32, (i / img.width) as u32);
                assert!(
                    (x0..x1).contains(&x) && (y0..y1).contains(&y),
                    "{:?}: ({x}, {y}) outside {:?}",
                    s.camera.projection,
                    rect
                );
            }
        }
        assert!(drawn > 0, "{:?}: no Moon", s.camera.projection);
        eprintln!(
            "{:?}: {drawn} Moon pixels in a {}×{} rectangle (Moon {:.1}° up)",
            s.camera.projection,
            x1 - x0,
            y1 - y0,
            state.moon.alt_refracted_deg
        );
    }
}

/// The Moon rising through the horizon at night (2024-01-27, Munich, Sun
/// −18°, phase 22°; refracted altitude of the centre within ±0.15°): the
/// ground hides the lower half, the refraction is strongest, the extinction
/// steepest across the disk; 2° perspective.
#[test]
fn moon_on_the_horizon() {
    let mut s = scene("2024-01-27T17:45:00Z", Projection::Perspective, 192, 192);
    s.effects = vec![Effect::Moon, Effect::Atmosphere];
    s.camera.fov_deg = 2.0;
    let mut state = SkyState::at(&s).unwrap();
    for m in 45..60 {
        s.time.utc = format!("2024-01-27T17:{m:02}:00Z");
        state = SkyState::at(&s).unwrap();
        if state.moon.alt_refracted_deg > -0.15 {
            break;
        }
    }
    let alt = state.moon.alt_refracted_deg;
    assert!((-0.15..0.15).contains(&alt), "{alt}");
    assert!(state.sun.alt_deg < -12.0);
    s.camera.yaw_deg = state.moon.az_deg;
    s.camera.pitch_deg = alt;
    let state = SkyState::at(&s).unwrap();
    let (c, g) = parity(
        &format!("Moon on the horizon ({alt:.2}°), 2° perspective"),
        &s,
    );
    moon_ran(&s, &state, false);
    // The upper part of the disk is drawn and outshines the sky beside it
    // (the mean over the disk includes the ground below the horizon).
    let (mc, n) = moon_disk_mean(&s, &state, &c);
    let (mg, _) = moon_disk_mean(&s, &state, &g);
    let sky = luminance(c.pixels[96 * 192 + 5]) as f64;
    eprintln!("horizon: disk mean Y CPU {mc:.4} GPU {mg:.4} cd/m² ({n} px), sky beside {sky:.4}");
    assert!(mc > 5.0 * sky, "{mc} vs sky {sky}");
    assert!((mg / mc - 1.0).abs() < 0.01, "{mg} vs {mc}");
}
