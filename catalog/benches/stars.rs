//! Costs of the star pipeline: decoding the embedded table, the exact
//! reduction of every V ≤ 6.5 star for one instant, and one frame of the
//! fast path. `cargo bench -p himmel-catalog --bench stars`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use himmel_astro::frames::NutationModel;
use himmel_astro::stars::StarReduction;
use himmel_astro::{Epoch, Instant, Observer};
use himmel_catalog::{Catalog, StarField};

fn benches(c: &mut Criterion) {
    let bytes = include_bytes!("../data/stars.bin");
    c.bench_function("decode embedded catalogue (8874 stars)", |b| {
        b.iter(|| Catalog::from_bytes(black_box(bytes)).unwrap())
    });
    let cat = Catalog::embedded().unwrap();
    let obs = Observer::new(52.5, 13.4, 40.0).unwrap();
    let instant = Instant::from_tt(2_460_325.4);
    c.bench_function("exact apparent + topocentric, all V<=6.5 stars", |b| {
        b.iter(|| {
            let epoch = Epoch::new(&instant, NutationModel::Iau1980);
            let red = StarReduction::new(&epoch);
            let mut acc = 0.0;
            for s in cat.brighter_than(6.5) {
                let (geo, topo) = red.geocentric_and_topocentric(&s.astrometry, &obs);
                acc += geo.ra + topo.alt;
            }
            acc
        })
    });
    let field = StarField::new(cat.stars(), 2_460_000.5, 365.25).unwrap();
    c.bench_function("fast path frame, all V<=6.5 stars", |b| {
        b.iter(|| {
            let epoch = Epoch::new(&instant, NutationModel::Iau1980);
            let frame = field.frame(&epoch, &obs);
            let mut acc = glam::DVec3::ZERO;
            for s in field.stars() {
                acc += frame.enu(s);
            }
            acc
        })
    });
}

criterion_group!(stars, benches);
criterion_main!(stars);
