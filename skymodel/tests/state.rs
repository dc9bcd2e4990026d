//! `SkyState::at`: the Sun's refracted apparent direction, size and
//! illuminance, and the pass plan.

use himmel_skymodel::{Effect, Scene, SkyState};

fn scene(utc: &str, effects: Vec<Effect>) -> Scene {
    let mut s = Scene::default();
    s.time.utc = utc.into();
    s.observer.lat_deg = 48.14;
    s.observer.lon_deg = 11.58;
    s.effects = effects;
    s
}

#[test]
fn sun_state_at_perihelion_noon() {
    // 2024-01-03 ≈ perihelion (0.98333 AU): illuminance (1/0.98333)² × 1 AU value.
    let st = SkyState::at(&scene("2024-01-03T11:20:00Z", vec![Effect::Sun])).unwrap();
    let d_au = st.sun.distance_km / 149_597_870.7;
    assert!((d_au - 0.9833).abs() < 0.001, "{d_au}");
    assert!((st.sun.irradiance_scale - 1.0 / (d_au * d_au)).abs() < 1e-9);
    // Semidiameter 16′16″ at perihelion (Astronomical Almanac 2024).
    let sd_arcmin = st.sun.angular_radius.to_degrees() * 60.0;
    assert!((sd_arcmin - 16.27).abs() < 0.02, "{sd_arcmin}");
    // ENU unit vector at the refracted altitude and the azimuth.
    let v = st.sun.enu;
    let alt = v[2].asin().to_degrees();
    let az = v[0].atan2(v[1]).to_degrees().rem_euclid(360.0);
    assert!((alt - st.sun.alt_refracted_deg).abs() < 1e-9);
    assert!((az - st.sun.az_deg).abs() < 1e-9);
    assert!(st.sun.alt_refracted_deg > st.sun.alt_deg);
    assert!(st.runs(Effect::Sun));
}

#[test]
fn pass_plan_reasons() {
    let st = SkyState::at(&scene(
        "2024-01-03T23:00:00Z",
        vec![Effect::Sun, Effect::Atmosphere, Effect::Clouds],
    ))
    .unwrap();
    let reason = |e: Effect| {
        st.passes
            .iter()
            .find(|p| p.effect == e)
            .unwrap()
            .reason
            .as_ref()
            .map(ToString::to_string)
    };
    assert_eq!(
        reason(Effect::Sun).as_deref(),
        Some("the Sun's disk is below the horizon")
    );
    assert_eq!(reason(Effect::Atmosphere), None);
    // A scene without a cloud layer plans no clouds pass, and says why.
    assert!(reason(Effect::Clouds)
        .unwrap()
        .starts_with("no cloud layer in the scene"));
    assert_eq!(reason(Effect::Moon).as_deref(), Some("not requested"));
    assert_eq!(st.passes.len(), Effect::ALL.len());
}

#[test]
fn bad_time_and_poles() {
    let e = SkyState::at(&scene("yesterday", vec![])).unwrap_err();
    assert_eq!(e.field, "time.utc");
    for lat in [90.0, -90.0] {
        let mut s = scene("2024-06-21T12:00:00Z", vec![Effect::Sun]);
        s.observer.lat_deg = lat;
        let st = SkyState::at(&s).unwrap();
        assert!(st.sun.enu.iter().all(|v| v.is_finite()));
    }
}
