//! Criterion benchmarks of the event searches (issue 3 speed targets):
//! all lunar eclipses 1900–2050 (< 1 s) and a year of daily Sun and Moon
//! rise/set/transit for one site (< 0.2 s), standard precision; the local
//! solar eclipse search also at the CLI default (DE421 Moon) and high.
//!
//! `cargo bench -p himmel-tests --bench events`

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use himmel_astro::events::lunar_eclipse::lunar_eclipses;
use himmel_astro::events::phases::phases;
use himmel_astro::events::riseset::rise_set_transit;
use himmel_astro::events::solar_eclipse::{
    local_solar_eclipses, local_solar_eclipses_preferring_de421, solar_eclipses,
};
use himmel_astro::time::days_in_month;
use himmel_astro::{Body, Instant, Observer, Precision, Tiered, UtcDateTime};

const EPH: Tiered = Tiered(Precision::Standard);

fn utc(y: i32) -> Instant {
    Instant::from_utc(&UtcDateTime::new(y, 1, 1, 0, 0, 0.0).unwrap()).unwrap()
}

fn searches(c: &mut Criterion) {
    let mut g = c.benchmark_group("events");
    g.bench_function("all lunar eclipses 1900-2050", |b| {
        b.iter(|| {
            let n = lunar_eclipses(EPH, &utc(1900), &utc(2051))
                .unwrap()
                .map(Result::unwrap)
                .count();
            black_box(n)
        })
    });
    let berlin = Observer::new(52.52, 13.405, 0.0).unwrap();
    g.bench_function(
        "a year of daily Sun and Moon rise/set/transit (Berlin)",
        |b| {
            b.iter(|| {
                let mut n = 0;
                for m in 1..=12u8 {
                    for d in 1..=days_in_month(2024, m) {
                        for body in [Body::Sun, Body::Moon] {
                            n += rise_set_transit(&EPH, body, &berlin, 2024, m, d)
                                .unwrap()
                                .events()
                                .len();
                        }
                    }
                }
                black_box(n)
            })
        },
    );
    g.bench_function("Moon phases 1990-2030", |b| {
        b.iter(|| black_box(phases(EPH, &utc(1990), &utc(2031)).unwrap().count()))
    });
    g.bench_function("all solar eclipses 1900-2050", |b| {
        b.iter(|| black_box(solar_eclipses(EPH, &utc(1900), &utc(2051)).unwrap().count()))
    });
    g.bench_function("local solar eclipses 2000-2050 (Berlin)", |b| {
        b.iter(|| {
            black_box(
                local_solar_eclipses(EPH, &berlin, &utc(2000), &utc(2051))
                    .unwrap()
                    .count(),
            )
        })
    });
    // The `himmel eclipses --kind solar --local` default: DE421 Moon (high
    // tier) for the local circumstances, standard for the global scan.
    g.bench_function(
        "local solar eclipses 2000-2050 (Berlin), default: DE421 Moon",
        |b| {
            b.iter(|| {
                black_box(
                    local_solar_eclipses_preferring_de421(EPH, &berlin, &utc(2000), &utc(2051))
                        .unwrap()
                        .count(),
                )
            })
        },
    );
    g.bench_function("local solar eclipses 2000-2050 (Berlin), high", |b| {
        b.iter(|| {
            black_box(
                local_solar_eclipses(Tiered(Precision::High), &berlin, &utc(2000), &utc(2051))
                    .unwrap()
                    .count(),
            )
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).measurement_time(std::time::Duration::from_secs(5));
    targets = searches
}
criterion_main!(benches);
