//! Criterion benchmarks: himmel's tiers against the peer crate `astro`
//! (astro-rust) on the same instants, in the same run.
//!
//! `cargo bench -p himmel-tests --bench positions`

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use himmel_astro::{moon, Body, Ephemeris, Epoch, Instant, Precision, Tiered};
use himmel_tests::peer;

fn instants() -> Vec<Instant> {
    // 64 instants spread over 1900–2050.
    (0..64)
        .map(|i| Instant::from_tt(2_415_020.5 + i as f64 * 856.3))
        .collect()
}

fn lunar_theory(c: &mut Criterion) {
    let ts: Vec<_> = instants()
        .iter()
        .map(|t| (t.centuries_tt(), t.jd_tt))
        .collect();
    let mut g = c.benchmark_group("moon theory (64 instants)");
    g.bench_function("himmel meeus47 (standard)", |b| {
        b.iter(|| {
            ts.iter().for_each(|(t, _)| {
                black_box(moon::meeus47(black_box(*t)));
            })
        })
    });
    g.bench_function("himmel low", |b| {
        b.iter(|| {
            ts.iter().for_each(|(t, _)| {
                black_box(moon::low(black_box(*t)));
            })
        })
    });
    g.bench_function("himmel de421 (high)", |b| {
        b.iter(|| {
            ts.iter().for_each(|(_, j)| {
                black_box(moon::de421(black_box(*j)));
            })
        })
    });
    g.bench_function("astro-rust lunar::geocent_ecl_pos", |b| {
        b.iter(|| {
            ts.iter().for_each(|(_, j)| {
                black_box(peer::raw_position(Body::Moon, black_box(*j)));
            })
        })
    });
    g.finish();
}

fn apparent_places(c: &mut Criterion) {
    let ins = instants();
    let mut g = c.benchmark_group("apparent place incl. epoch (64 instants)");
    for body in [Body::Sun, Body::Moon, Body::Mars] {
        for p in Precision::ALL {
            let eph = Tiered(p);
            g.bench_function(format!("himmel {} {}", p.name(), body.name()), |b| {
                b.iter(|| {
                    for t in &ins {
                        let e = Epoch::new(black_box(t), p.nutation_model());
                        black_box(eph.apparent(body, &e).ok());
                    }
                })
            });
        }
        g.bench_function(format!("astro-rust {}", body.name()), |b| {
            b.iter(|| {
                ins.iter().for_each(|t| {
                    black_box(peer::apparent_radec(body, black_box(t.jd_tt)));
                })
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).measurement_time(std::time::Duration::from_secs(2));
    targets = lunar_theory, apparent_places
}
criterion_main!(benches);
