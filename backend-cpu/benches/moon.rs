//! Criterion benchmark of the Moon pass (issue 6 acceptance: ≤ 60 ms at
//! 1920×1080 with a 1° field of view, the Moon filling the frame):
//!
//! * `moon_pass_1920x1080_fov1` — the pass alone (shader set-up + every
//!   pixel of the disk's bounding box), pixel directions precomputed;
//! * `moon_pass_eclipse_1920x1080_fov1` — the same during the lunar eclipse
//!   of 2025-03-14 (adds the per-frame eclipse table).
//!
//! `cargo bench -p himmel-cpu --bench moon`

use criterion::{criterion_group, criterion_main, Criterion};
use himmel_skymodel::{Effect, Projection, Scene, SkyState};

fn scene(t: &str) -> (Scene, SkyState) {
    let mut s = Scene::default();
    s.time.utc = t.into();
    s.observer.lat_deg = 19.43;
    s.observer.lon_deg = -99.13;
    s.effects = vec![Effect::Moon];
    s.camera.projection = Projection::Perspective;
    s.camera.width = 1920;
    s.camera.height = 1080;
    s.camera.fov_deg = 1.0;
    let st = SkyState::at(&s).unwrap();
    s.camera.yaw_deg = st.moon.az_deg;
    s.camera.pitch_deg = st.moon.alt_refracted_deg;
    let st = SkyState::at(&s).unwrap();
    (s, st)
}

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("cpu");
    g.sample_size(20);
    for (name, t) in [
        ("moon_pass_1920x1080_fov1", "2025-03-14T03:58:43Z"),
        ("moon_pass_eclipse_1920x1080_fov1", "2025-03-14T06:58:43Z"),
    ] {
        let (s, st) = scene(t);
        let dirs = himmel_cpu::directions(&s.camera);
        let mut pixels = vec![[0.0f32; 3]; dirs.len()];
        g.bench_function(name, |b| {
            b.iter(|| {
                // The Moon's frame (shader constants and tables) and the pass.
                let frame = himmel_skymodel::frame::MoonFrame::new(&s, &st, None, 0.0);
                himmel_cpu::moon_pass::render(&mut pixels, &dirs, 1920, &s.camera, &frame)
            })
        });
    }
    g.finish();
}

criterion_group!(moon, benches);
criterion_main!(moon);
