//! CPU renderer: Sun disk position and energy, pass plan, cache.

use glam::DVec3;
use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::{AtmosphereParams, LutConfig};
use himmel_skymodel::frame::luts as cache;
use himmel_skymodel::{Effect, Projection, Scene, SkyRenderer, SkyState};

fn scene(effects: Vec<Effect>, w: u32, h: u32, p: Projection) -> Scene {
    let mut s = Scene::default();
    s.time.utc = "2024-06-21T07:30:00Z".into();
    s.observer.lat_deg = 48.14;
    s.observer.lon_deg = 11.58;
    s.effects = effects;
    s.camera.width = w;
    s.camera.height = h;
    s.camera.projection = p;
    s.lut = LutConfig::small();
    s
}

#[test]
fn sun_disk_position_and_illuminance_in_equirect() {
    let s = scene(vec![Effect::Sun], 2048, 1024, Projection::Equirect);
    let state = SkyState::at(&s).unwrap();
    let out = CpuRenderer::new(None).render(&s, &state).unwrap();
    let img = &out.image;
    let (w, h) = (img.width as f64, img.height as f64);
    // Σ L · Ω over the image (equirect pixel solid angle: Δaz · Δ sin(alt)).
    let mut e = 0.0f64;
    let (mut cx, mut cy, mut sw) = (0.0, 0.0, 0.0);
    for (i, p) in img.pixels.iter().enumerate() {
        let y = himmel_skymodel::spectrum::luminance(*p) as f64;
        if y <= 0.0 {
            continue;
        }
        let (px, py) = ((i % img.width) as f64, (i / img.width) as f64);
        let alt_top = std::f64::consts::FRAC_PI_2 - std::f64::consts::PI * py / h;
        let alt_bot = std::f64::consts::FRAC_PI_2 - std::f64::consts::PI * (py + 1.0) / h;
        let omega = std::f64::consts::TAU / w * (alt_top.sin() - alt_bot.sin());
        e += y * omega;
        cx += y * omega * (px + 0.5);
        cy += y * omega * (py + 0.5);
        sw += y * omega;
    }
    let want = state.sun.illuminance_lux;
    eprintln!("Σ L·Ω = {e:.0} lx, E☉(d) = {want:.0} lx");
    assert!((e / want - 1.0).abs() < 0.02, "{e} lx vs {want} lx");
    assert!((120_000.0..136_000.0).contains(&want));
    // Centroid within 1 px of the refracted apparent place.
    let (sx, sy) = s
        .camera
        .dir_to_pixel(DVec3::from_array(state.sun.enu))
        .unwrap();
    let (cx, cy) = (cx / sw, cy / sw);
    eprintln!("centroid ({cx:.3}, {cy:.3}) px, refracted apparent place ({sx:.3}, {sy:.3}) px");
    assert!(
        (cx - sx).hypot(cy - sy) < 1.0,
        "centroid {cx},{cy} vs {sx},{sy}"
    );
    assert!(state.sun.alt_refracted_deg > state.sun.alt_deg);
}

#[test]
fn atmosphere_only_runs_one_pass_and_says_why_not_the_others() {
    let s = scene(vec![Effect::Atmosphere], 64, 64, Projection::Fisheye);
    let state = SkyState::at(&s).unwrap();
    let out = CpuRenderer::new(None).render(&s, &state).unwrap();
    assert_eq!(out.passes.len(), Effect::ALL.len());
    for p in &out.passes {
        if p.name == "atmosphere" {
            assert!(p.ran && p.ms.is_some());
        } else {
            assert!(!p.ran && p.ms.is_none());
            assert_eq!(p.reason.as_deref(), Some("not requested"), "{}", p.name);
        }
    }
    assert!(out
        .image
        .pixels
        .iter()
        .all(|p| p.iter().all(|v| v.is_finite())));
}

#[test]
fn clouds_without_a_layer_are_reported_and_later_effects_not_available() {
    let mut s = scene(
        vec![Effect::Clouds, Effect::Gi],
        16,
        16,
        Projection::Fisheye,
    );
    let state = SkyState::at(&s).unwrap();
    let out = CpuRenderer::new(None).render(&s, &state).unwrap();
    let clouds = out.passes.iter().find(|p| p.name == "clouds").unwrap();
    assert!(
        !clouds.ran
            && clouds
                .reason
                .as_deref()
                .unwrap()
                .starts_with("no cloud layer in the scene")
    );
    let gi = out.passes.iter().find(|p| p.name == "gi").unwrap();
    assert!(!gi.ran && gi.reason.as_deref().unwrap().starts_with("not available"));
    // With a layer the pass runs.
    s.clouds.low.coverage = 0.6;
    let state = SkyState::at(&s).unwrap();
    let out = CpuRenderer::new(None).render(&s, &state).unwrap();
    assert!(out.passes.iter().any(|p| p.name == "clouds" && p.ran));
}

#[test]
fn every_projection_renders_finite_pixels() {
    for p in [
        Projection::Fisheye,
        Projection::Equirect,
        Projection::Perspective,
        Projection::Cubemap,
    ] {
        let s = scene(vec![Effect::Atmosphere, Effect::Sun], 48, 32, p);
        let state = SkyState::at(&s).unwrap();
        let out = CpuRenderer::new(None).render(&s, &state).unwrap();
        let (w, h) = s.camera.image_size();
        assert_eq!(out.image.pixels.len(), (w * h) as usize);
        assert!(
            out.image
                .pixels
                .iter()
                .all(|p| p.iter().all(|v| v.is_finite())),
            "{p:?}"
        );
    }
}

#[test]
fn cache_round_trip_and_key_changes_with_parameters() {
    let dir = std::env::temp_dir().join(format!("himmel-cache-test-{}", std::process::id()));
    let params = AtmosphereParams::default();
    let cfg = LutConfig::small();
    let luts = himmel_cpu::precompute(&params, &cfg, false);
    cache::store(&dir, &luts).unwrap();
    let back = cache::load(&dir, &params, &cfg).unwrap();
    assert_eq!(back.transmittance, luts.transmittance);
    assert_eq!(back.scattering_transmittance, luts.scattering_transmittance);
    assert_eq!(back.multiscatter, luts.multiscatter);
    let mut p2 = params.clone();
    p2.aerosol_density = 2.0;
    assert_ne!(cache::cache_key(&params, &cfg), cache::cache_key(&p2, &cfg));
    assert!(cache::load(&dir, &p2, &cfg).is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A damaged LUT cache file — texels changed to other finite values,
/// truncated, or of another format version — is never used: the renderer
/// recomputes the LUTs (`lut_source` `computed`), replaces the file, and
/// renders the same image as with a clean cache.
#[test]
fn a_damaged_cache_file_is_recomputed_and_the_image_is_unchanged() {
    let dir = std::env::temp_dir().join(format!("himmel-damaged-cache-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut s = scene(
        vec![Effect::Atmosphere, Effect::Sun],
        64,
        64,
        Projection::Fisheye,
    );
    s.lut = LutConfig::small();
    let state = SkyState::at(&s).unwrap();
    let clean = CpuRenderer::new(Some(dir.clone()))
        .render(&s, &state)
        .unwrap();
    assert_eq!(clean.lut_source.name(), "computed");
    let path = cache::cache_path(&dir, &s.atmosphere, &s.lut);
    let intact = std::fs::read(&path).unwrap();
    let from_disk = CpuRenderer::new(Some(dir.clone()))
        .render(&s, &state)
        .unwrap();
    assert_eq!(from_disk.lut_source.name(), "disk-cache");
    assert_eq!(from_disk.image, clean.image);
    type Damage = fn(&mut Vec<u8>);
    let damages: [(&str, Damage); 3] = [
        ("1000 texels altered", |b| {
            for k in 0..1000 {
                let at = 12 + 4 * (k * 131 % ((b.len() - 12) / 4));
                let v = f32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]]);
                b[at..at + 4].copy_from_slice(&(v * 0.9).to_le_bytes());
            }
        }),
        ("truncated", |b| b.truncate(b.len() - 400)),
        ("format version 4", |b| b[..8].copy_from_slice(b"HMLUT004")),
    ];
    for (what, damage) in damages {
        let mut bytes = intact.clone();
        damage(&mut bytes);
        std::fs::write(&path, &bytes).unwrap();
        let out = CpuRenderer::new(Some(dir.clone()))
            .render(&s, &state)
            .unwrap();
        assert_eq!(out.lut_source.name(), "computed", "{what}");
        assert_eq!(out.image, clean.image, "{what}: image differs");
        assert_eq!(
            std::fs::read(&path).unwrap(),
            intact,
            "{what}: file not replaced"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn fast_directions_equal_the_projection_definition() {
    for p in [
        Projection::Fisheye,
        Projection::Equirect,
        Projection::Perspective,
    ] {
        let s = scene(vec![], 90, 60, p);
        let dirs = himmel_cpu::directions(&s.camera);
        for (i, d) in dirs.iter().enumerate() {
            let (x, y) = ((i % 90) as f64 + 0.5, (i / 90) as f64 + 0.5);
            let want = s.camera.pixel_to_dir(x, y);
            match (d, want) {
                (Some(d), Some(wv)) => assert!((d.as_dvec3() - wv).length() < 1e-5, "{p:?} {i}"),
                (None, None) => {}
                _ => panic!("{p:?} {i}: {d:?} vs {want:?}"),
            }
        }
    }
}
