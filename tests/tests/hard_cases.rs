//! The hard cases of the astronomy core: observers at the poles and on the
//! antimeridian, J2000.0, the ends of the DE421 era, both sides of a leap
//! second, the Moon at the zenith and the nadir, and years far from 2000.

use himmel_astro::units::DEG;
use himmel_astro::{Body, Instant, Observer, Precision, Sky, UtcDateTime};
use himmel_tests::{body_errors, load, parse_fixture_utc, separation_arcsec};

#[test]
fn hard_case_records_match_de421() {
    let recs = load("de421_hard_cases.json");
    for p in [Precision::Standard, Precision::High] {
        for body in Body::ALL {
            let e = body_errors(&recs, body, p, false);
            for (r, (geo, topo)) in recs.iter().zip(e.geo_arcsec.iter().zip(&e.topo_arcsec)) {
                let label = r.label.as_deref().unwrap_or("?");
                let bound = match (body, p) {
                    (Body::Moon, Precision::Standard) => 20.0,
                    (_, Precision::High) => 2.0,
                    _ => 6.0,
                };
                assert!(
                    *geo <= bound,
                    "{label} {} {}: {geo}″",
                    p.name(),
                    body.name()
                );
                // At a pole azimuth is degenerate, so compare altitudes there.
                let topo = if r.lat.abs() > 89.999 {
                    let sky = Sky::new(p, &r.instant());
                    let t = sky.topocentric(body, &r.observer()).unwrap();
                    (t.alt_deg() - r.bodies.get(body).alt_deg).abs() * 3600.0
                } else {
                    *topo
                };
                assert!(
                    topo <= 1.5 * geo + 0.5,
                    "{label} {} {}: topo {topo}″ geo {geo}″",
                    p.name(),
                    body.name()
                );
            }
        }
    }
}

#[test]
fn moon_at_zenith_and_nadir() {
    let recs = load("de421_hard_cases.json");
    let mut seen = 0;
    for r in recs
        .iter()
        .filter(|r| r.label.as_deref().unwrap_or("").starts_with("Moon at"))
    {
        let sky = Sky::new(Precision::High, &r.instant());
        let t = sky.topocentric(Body::Moon, &r.observer()).unwrap();
        let want = r.bodies.moon.alt_deg;
        assert!(t.alt_deg().is_finite() && t.az_deg().is_finite());
        assert!(
            (t.alt_deg() - want).abs() * 3600.0 < 2.0,
            "{:?}: {} vs {want}",
            r.label,
            t.alt_deg()
        );
        assert!(t.alt_refracted_deg().is_finite() && t.parallactic_angle_deg().is_finite());
        seen += 1;
    }
    assert_eq!(seen, 8);
}

#[test]
fn both_sides_of_a_leap_second() {
    let recs = load("de421_hard_cases.json");
    let leap: Vec<_> = recs
        .iter()
        .filter(|r| r.label.as_deref().unwrap_or("").contains("leap second"))
        .collect();
    assert_eq!(leap.len(), 3);
    let mut prev_tt = None;
    for r in leap {
        let utc = parse_fixture_utc(r.utc.as_deref().unwrap());
        let t = Instant::from_utc(&utc).unwrap();
        // TT from the leap-second table is exact: compare with Skyfield to 10 µs.
        assert!((t.jd_tt - r.jd_tt).abs() * 86400.0 < 1e-5, "{:?}", r.label);
        if let Some(p) = prev_tt {
            let step: f64 = (t.jd_tt - p) * 86400.0;
            assert!(
                (step - 1.0).abs() < 1e-5,
                "TT step {step} s across the leap second"
            );
        }
        prev_tt = Some(t.jd_tt);
        let sky = Sky::new(Precision::High, &t);
        let m = sky.apparent(Body::Moon).unwrap();
        let err = separation_arcsec(
            m.ra / DEG,
            m.dec / DEG,
            r.bodies.moon.ra_deg,
            r.bodies.moon.dec_deg,
        );
        assert!(err < 1.0, "{:?}: {err}″", r.label);
    }
}

/// Years −2000 and +3000: every tier gives finite positions that move
/// smoothly (the second difference over one-hour steps stays tiny).
#[test]
fn far_years_are_finite_and_continuous() {
    let obs = Observer::new(-33.9, 151.2, 10.0).unwrap();
    for year in [-2000, 3000] {
        let t0 = Instant::from_utc(&UtcDateTime::new(year, 6, 15, 0, 0, 0.0).unwrap()).unwrap();
        assert!(t0.delta_t().is_finite());
        for p in Precision::ALL {
            for body in Body::ALL {
                let pos: Vec<_> = (0..4)
                    .map(|h| {
                        let t = Instant::from_tt(t0.jd_tt + h as f64 / 24.0);
                        let sky = Sky::new(p, &t);
                        let a = sky.apparent(body).unwrap();
                        let topo = sky.topocentric(body, &obs).unwrap();
                        assert!(a.ra.is_finite() && a.dec.is_finite() && a.distance_km > 0.0);
                        assert!(topo.alt.is_finite() && topo.az.is_finite());
                        (a.ra / DEG, a.dec / DEG)
                    })
                    .collect();
                for w in pos.windows(3) {
                    let d1 = separation_arcsec(w[0].0, w[0].1, w[1].0, w[1].1);
                    let d2 = separation_arcsec(w[1].0, w[1].1, w[2].0, w[2].1);
                    // The Moon moves ~0.5°/h; a jump would show as a step change.
                    assert!(
                        (d1 - d2).abs() < 30.0,
                        "{year} {} {}: {d1} vs {d2}",
                        p.name(),
                        body.name()
                    );
                }
            }
        }
    }
}

#[test]
fn observers_at_the_poles_and_the_antimeridian_agree_with_their_twins() {
    // +180° and −180° are the same meridian.
    let t = Instant::from_tt(2451545.25);
    let sky = Sky::new(Precision::Standard, &t);
    for body in Body::ALL {
        let a = sky
            .topocentric(body, &Observer::new(10.0, 180.0, 0.0).unwrap())
            .unwrap();
        let b = sky
            .topocentric(body, &Observer::new(10.0, -180.0, 0.0).unwrap())
            .unwrap();
        assert!(separation_arcsec(a.az_deg(), a.alt_deg(), b.az_deg(), b.alt_deg()) < 1e-6);
        // 360-wrapped input.
        let c = sky
            .topocentric(body, &Observer::new(10.0, 540.0 - 360.0, 0.0).unwrap())
            .unwrap();
        assert!(separation_arcsec(a.az_deg(), a.alt_deg(), c.az_deg(), c.alt_deg()) < 1e-6);
        // At a pole the altitude equals the topocentric declination.
        let n = sky
            .topocentric(body, &Observer::new(90.0, 0.0, 0.0).unwrap())
            .unwrap();
        assert!(
            (n.alt - n.dec).abs() / DEG * 3600.0 < 1e-6,
            "{}",
            body.name()
        );
        assert!(n.az_deg().is_finite() && (0.0..360.0).contains(&n.az_deg()));
    }
    assert!(Observer::new(90.0001, 0.0, 0.0).is_err());
    assert!(Observer::new(f64::NAN, 0.0, 0.0).is_err());
}
