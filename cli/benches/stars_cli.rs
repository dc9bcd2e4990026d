//! End-to-end cost of `himmel stars --limit-mag 6.5 --format json` for one
//! instant: process start, catalogue decode, reduction of 8 874 stars, JSON
//! output (to a null sink). `cargo bench -p himmel-cli --bench stars_cli`.

use std::process::{Command, Stdio};

use criterion::{criterion_group, criterion_main, Criterion};

fn run(format: &str) {
    let status = Command::new(env!("CARGO_BIN_EXE_himmel"))
        .args([
            "stars",
            "--time",
            "2024-01-15T21:00:00Z",
            "--lat",
            "52.5",
            "--lon",
            "13.4",
            "--limit-mag",
            "6.5",
            "--format",
            format,
        ])
        .stdout(Stdio::null())
        .status()
        .expect("run himmel");
    assert!(status.success());
}

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("himmel stars --limit-mag 6.5");
    g.sample_size(30);
    g.bench_function("json", |b| b.iter(|| run("json")));
    g.bench_function("table", |b| b.iter(|| run("table")));
    g.finish();
}

criterion_group!(stars_cli, benches);
criterion_main!(stars_cli);
