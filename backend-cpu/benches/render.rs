//! Criterion benchmarks of the CPU renderer (issue acceptance figures):
//!
//! * `precompute_default` — the parameter-dependent LUTs for the default
//!   atmosphere (transmittance + multiple scattering), all cores;
//! * `parameter_change_render_1920x1080` — a new aerosol density: precompute,
//!   sky view and a full 1920×1080 fisheye frame with atmosphere + Sun;
//! * `frame_1920x1080_fisheye` — one frame with the LUTs in memory (the
//!   per-frame sky-view LUT and every pixel);
//! * `stars_pass_1920x1080` — the stars pass alone (8 874 catalogue stars:
//!   positions, refraction, extinction, PSF splats) at night, fisheye;
//! * `milkyway_pass_1920x1080` — the Milky Way / night-sky light pass alone.
//!
//! `cargo bench -p himmel-cpu --bench render`

use criterion::{criterion_group, criterion_main, Criterion};
use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::{AtmosphereParams, LutConfig};
use himmel_skymodel::{Effect, Projection, Scene, SkyRenderer, SkyState};

fn scene() -> Scene {
    let mut s = Scene::default();
    s.time.utc = "2024-06-21T17:30:00Z".into();
    s.effects = vec![Effect::Atmosphere, Effect::Sun];
    s.camera.projection = Projection::Fisheye;
    s.camera.width = 1920;
    s.camera.height = 1080;
    s
}

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("cpu");
    g.sample_size(10);
    g.bench_function("precompute_default", |b| {
        b.iter(|| {
            himmel_cpu::precompute(&AtmosphereParams::default(), &LutConfig::default(), false)
        })
    });
    let s = scene();
    let state = SkyState::at(&s).unwrap();
    let mut r = CpuRenderer::new(None);
    let mut k = 0u32;
    g.bench_function("parameter_change_render_1920x1080", |b| {
        b.iter(|| {
            k += 1;
            let mut s2 = s.clone();
            s2.atmosphere.aerosol_density = 1.0 + (k % 1000) as f64 * 1e-3;
            r.render(&s2, &state).unwrap()
        })
    });
    let mut r = CpuRenderer::new(None);
    r.render(&s, &state).unwrap();
    g.bench_function("frame_1920x1080_fisheye", |b| {
        b.iter(|| r.render(&s, &state).unwrap())
    });
    let mut night = scene();
    night.time.utc = "2024-01-15T21:00:00Z".into();
    night.effects = vec![Effect::Stars, Effect::Milkyway];
    night.exposure = himmel_skymodel::Exposure::Ev100(-6.0);
    let nstate = SkyState::at(&night).unwrap();
    let dirs = himmel_cpu::directions(&night.camera);
    let frame = r.plan(&night, &nstate).unwrap().night.unwrap();
    use himmel_cpu::night_pass;
    use himmel_skymodel::frame::night::star_sources;
    let mut pixels = vec![[0.0f32; 3]; dirs.len()];
    g.bench_function("stars_pass_1920x1080", |b| {
        // The stars above the horizon (as the frame plan finds them) and their splats.
        b.iter(|| {
            night_pass::splat_all(&frame, &mut pixels, &night, &star_sources(&night, &nstate))
        })
    });
    g.bench_function("milkyway_pass_1920x1080", |b| {
        b.iter(|| night_pass::milkyway(&frame, &mut pixels, &dirs))
    });
    g.finish();
}

criterion_group!(cpu, benches);
criterion_main!(cpu);
