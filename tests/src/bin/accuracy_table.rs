//! Prints the accuracy-vs-cost table of the astronomy core: for each tier
//! and body, the great-circle error of the apparent geocentric place against
//! JPL DE421 (600 random instants 1900–2050, same TT; fixtures from
//! `tools/gen_fixtures.py`) and the cost of one call, with the peer crate
//! `astro` (astro-rust) measured in the same run on the same instants.
//!
//! Run: `cargo run -p himmel-tests --release --bin accuracy-table`
//! (timings are wall-clock means over many calls on this machine; the
//! criterion benchmark `cargo bench -p himmel-tests` gives the same
//! comparison with confidence intervals).

use std::hint::black_box;
use std::time::Instant as Clock;

use himmel_astro::units::DEG;
use himmel_astro::{moon, Body, Ephemeris, Epoch, Precision, Tiered};
use himmel_tests::{load, peer, separation_arcsec, Stats};

fn time_ns<F: FnMut()>(calls: usize, mut f: F) -> f64 {
    // Warm up, then take the best of five rounds to damp scheduler noise.
    f();
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let t = Clock::now();
        f();
        best = best.min(t.elapsed().as_nanos() as f64 / calls as f64);
    }
    best
}

fn main() {
    let recs = load("de421_same_tt.json");
    let instants: Vec<_> = recs.iter().map(|r| r.instant()).collect();
    println!(
        "Apparent geocentric place vs JPL DE421 ({} instants 1900–2050, same TT); cost per call on this machine\n",
        recs.len()
    );
    println!(
        "| provider | body | median (″) | p95 (″) | max (″) | ns / call |\n|---|---|---:|---:|---:|---:|"
    );
    for p in Precision::ALL {
        let eph = Tiered(p);
        let epochs: Vec<Epoch> = instants
            .iter()
            .map(|t| Epoch::new(t, p.nutation_model()))
            .collect();
        for body in Body::ALL {
            let errs: Vec<f64> = recs
                .iter()
                .zip(&epochs)
                .map(|(r, e)| {
                    let a = eph.apparent(body, e).expect("tiered bodies are available");
                    let w = r.bodies.get(body);
                    separation_arcsec(a.ra / DEG, a.dec / DEG, w.ra_deg, w.dec_deg)
                })
                .collect();
            let s = Stats::of(&errs);
            // Cost of a fresh instant: the epoch (nutation, sidereal time) plus the body.
            let ns = time_ns(instants.len(), || {
                for t in &instants {
                    let e = Epoch::new(black_box(t), p.nutation_model());
                    black_box(eph.apparent(body, &e).ok());
                }
            });
            println!(
                "| himmel {} | {} | {:.3} | {:.3} | {:.3} | {:.0} |",
                p.name(),
                body.name(),
                s.median,
                s.p95,
                s.max,
                ns
            );
        }
    }
    for body in Body::ALL {
        let errs: Vec<f64> = recs
            .iter()
            .map(|r| {
                let (ra, dec) = peer::apparent_radec(body, r.jd_tt);
                let w = r.bodies.get(body);
                separation_arcsec(ra / DEG, dec / DEG, w.ra_deg, w.dec_deg)
            })
            .collect();
        let s = Stats::of(&errs);
        let ns = time_ns(recs.len(), || {
            for r in &recs {
                black_box(peer::apparent_radec(body, black_box(r.jd_tt)));
            }
        });
        println!(
            "| astro-rust 2.0 | {} | {:.3} | {:.3} | {:.3} | {:.0} |",
            body.name(),
            s.median,
            s.p95,
            s.max,
            ns
        );
    }

    println!("\nLunar theory alone (geocentric ecliptic of date, no nutation), ns per call:\n");
    println!("| theory | ns / call |\n|---|---:|");
    let ts: Vec<f64> = instants.iter().map(|t| t.centuries_tt()).collect();
    let jds: Vec<f64> = instants.iter().map(|t| t.jd_tt).collect();
    let row = |name: &str, ns: f64| println!("| {name} | {ns:.0} |");
    row(
        "himmel moon::low",
        time_ns(ts.len(), || {
            ts.iter().for_each(|t| {
                black_box(moon::low(black_box(*t)));
            })
        }),
    );
    row(
        "himmel moon::meeus47",
        time_ns(ts.len(), || {
            ts.iter().for_each(|t| {
                black_box(moon::meeus47(black_box(*t)));
            })
        }),
    );
    row(
        "himmel moon::de421",
        time_ns(jds.len(), || {
            jds.iter().for_each(|j| {
                black_box(moon::de421(black_box(*j)));
            })
        }),
    );
    row(
        "astro-rust lunar::geocent_ecl_pos",
        time_ns(jds.len(), || {
            jds.iter().for_each(|j| {
                black_box(peer::raw_position(Body::Moon, black_box(*j)));
            })
        }),
    );
}
