//! Criterion benchmarks of the wgpu backend against the CPU backend in the
//! same run (issue 7 acceptance figures), atmosphere + Sun, fisheye, LUTs
//! in memory (after precompute):
//!
//! * `wgpu_frame` — one frame left on the GPU (sky-view LUT in a compute
//!   shader, atmosphere, Sun, store), no read-back;
//! * `wgpu_frame_cpu_sky_view` — the same with the sky view computed on the
//!   CPU and uploaded;
//! * `wgpu_frame_readback` — `wgpu_frame` plus the copy back into an `HdrImage`;
//! * `cpu_frame` — the CPU renderer, all cores.
//!
//! In the group `night` (stars + planets + atmosphere on a dark night,
//! 1920×1080 fisheye, LUTs in memory), one frame left on the GPU with the
//! point sources drawn as
//!
//! * `wgpu_quads` — instanced quads (`PointMethod::Quads`, the default on
//!   hardware GPUs);
//! * `wgpu_tiles` — the tiled compute passes (`PointMethod::Tiles`, the
//!   default on software adapters);
//!
//! and `cpu_frame`, the CPU renderer; the per-pass times of both methods
//! are printed after the group.
//!
//! and, in the group `precompute`, the parameter-dependent LUTs at the
//! default `LutConfig` (transmittance pair 256×64, Ψ_ms 48², 64
//! directions):
//!
//! * `gpu_luts` — the LUT compute shaders (luts.wgsl) submitted and
//!   awaited;
//! * `gpu_luts_readback` — the same plus the read-back into an
//!   `AtmosphereLuts` (what a frame with `LutSource::Gpu` pays on a
//!   parameter change);
//! * `cpu_luts_upload` — `himmel_cpu::precompute` (all cores) plus the
//!   upload (what `LutSource::Cpu` pays without a cache hit);
//! * `disk_cache_load` — `himmel_skymodel::frame::luts::load` of the same LUTs (what
//!   `LutSource::Cpu` pays on a disk-cache hit, before the upload).
//!
//! `cargo bench -p himmel-tests --bench wgpu_render` (on lavapipe without a GPU).

use criterion::{criterion_group, criterion_main, Criterion};
use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::{AtmosphereParams, LutConfig};
use himmel_skymodel::{Effect, Projection, Scene, SkyRenderer, SkyState};
use himmel_wgpu::{luts, LutSource, PointMethod, WgpuRenderer};

fn scene(w: u32, h: u32) -> Scene {
    let mut s = Scene::default();
    s.time.utc = "2024-06-21T17:30:00Z".into();
    s.effects = vec![Effect::Atmosphere, Effect::Sun];
    s.camera.projection = Projection::Fisheye;
    s.camera.width = w;
    s.camera.height = h;
    s
}

fn benches(c: &mut Criterion) {
    let mut gpu = match WgpuRenderer::new(None) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("skipping the wgpu benchmarks: {e}");
            return;
        }
    };
    let info = gpu.adapter_info();
    eprintln!(
        "adapter: {} ({:?}, {:?}), timing: {}",
        info.name,
        info.backend,
        info.device_type,
        gpu.timing().name()
    );
    precompute(c, &mut gpu);
    night(c, &mut gpu);
    let mut cpu = CpuRenderer::new(None);
    for (w, h) in [(1024u32, 1024u32), (1920, 1080)] {
        let s = scene(w, h);
        let state = SkyState::at(&s).unwrap();
        gpu.render(&s, &state).unwrap();
        cpu.render(&s, &state).unwrap();
        let mut g = c.benchmark_group(format!("{w}x{h}"));
        g.sample_size(10);
        g.bench_function("wgpu_frame", |b| {
            b.iter(|| gpu.render_frame(&s, &state).unwrap())
        });
        gpu.set_sky_view_on_gpu(false);
        g.bench_function("wgpu_frame_cpu_sky_view", |b| {
            b.iter(|| gpu.render_frame(&s, &state).unwrap())
        });
        gpu.set_sky_view_on_gpu(true);
        g.bench_function("wgpu_frame_readback", |b| {
            b.iter(|| gpu.render(&s, &state).unwrap())
        });
        g.bench_function("cpu_frame", |b| b.iter(|| cpu.render(&s, &state).unwrap()));
        g.finish();
        let out = gpu.render(&s, &state).unwrap();
        for p in out.passes.iter().filter(|p| p.ran) {
            eprintln!(
                "{w}x{h} wgpu pass {}: {:.2} ms",
                p.name,
                p.ms.unwrap_or(0.0)
            );
        }
        eprintln!("{w}x{h} wgpu sky view (GPU): {:.2} ms", out.sky_view_ms);
    }
}

/// The `night` group (see the module documentation).
fn night(c: &mut Criterion, gpu: &mut WgpuRenderer) {
    let mut s = scene(1920, 1080);
    s.time.utc = "2024-01-15T19:30:00Z".into();
    s.observer.lat_deg = 48.14;
    s.observer.lon_deg = 11.58;
    s.effects = vec![Effect::Stars, Effect::Planets, Effect::Atmosphere];
    let state = SkyState::at(&s).unwrap();
    let mut cpu = CpuRenderer::new(None);
    cpu.render(&s, &state).unwrap();
    let before = gpu.point_method();
    let mut g = c.benchmark_group("night");
    g.sample_size(10);
    for m in [PointMethod::Quads, PointMethod::Tiles] {
        gpu.set_point_method(m);
        gpu.render(&s, &state).unwrap();
        g.bench_function(format!("wgpu_{}", m.name()), |b| {
            b.iter(|| gpu.render_frame(&s, &state).unwrap())
        });
    }
    g.bench_function("cpu_frame", |b| b.iter(|| cpu.render(&s, &state).unwrap()));
    g.finish();
    // Per-pass times from timestamps and from the CPU clock around each
    // awaited pass (lavapipe's timestamps do not follow its deferred
    // rasterisation: with the quads' render passes in the submission the
    // atmosphere's compute work is attributed elsewhere).
    for ts in [true, false] {
        gpu.set_timestamps(ts);
        for m in [PointMethod::Quads, PointMethod::Tiles] {
            gpu.set_point_method(m);
            let f = gpu.render_frame(&s, &state).unwrap();
            for p in f.passes.iter().filter(|p| p.ran) {
                eprintln!(
                    "night 1920x1080 {} ({}): pass {}: {:.2} ms",
                    m.name(),
                    gpu.timing().name(),
                    p.name,
                    p.ms.unwrap_or(0.0)
                );
            }
        }
    }
    gpu.set_timestamps(true);
    gpu.set_point_method(before);
}

/// The `precompute` group (see the module documentation).
fn precompute(c: &mut Criterion, gpu: &mut WgpuRenderer) {
    let params = AtmosphereParams::default();
    let config = LutConfig::default();
    let before = gpu.lut_source();
    let pipelines = luts::LutPipelines::new(gpu.device());
    let mut g = c.benchmark_group("precompute");
    g.sample_size(10);
    g.bench_function("gpu_luts", |b| {
        b.iter(|| {
            let bufs =
                luts::dispatch(gpu.device(), gpu.queue(), &pipelines, &params, &config).unwrap();
            gpu.device()
                .poll(wgpu::PollType::wait_indefinitely())
                .unwrap();
            bufs
        })
    });
    gpu.set_lut_source(LutSource::Gpu);
    g.bench_function("gpu_luts_readback", |b| {
        b.iter(|| gpu.precompute_luts(&params, &config).unwrap())
    });
    gpu.set_lut_source(LutSource::Cpu);
    g.bench_function("cpu_luts_upload", |b| {
        b.iter(|| gpu.precompute_luts(&params, &config).unwrap())
    });
    let dir = std::env::temp_dir().join(format!("himmel-bench-luts-{}", std::process::id()));
    let stored = himmel_cpu::precompute(&params, &config, false);
    if himmel_skymodel::frame::luts::store(&dir, &stored).is_ok() {
        g.bench_function("disk_cache_load", |b| {
            b.iter(|| himmel_skymodel::frame::luts::load(&dir, &params, &config).unwrap())
        });
    }
    let _ = std::fs::remove_dir_all(&dir);
    g.finish();
    gpu.set_lut_source(before);
}

criterion_group!(wgpu_render, benches);
criterion_main!(wgpu_render);
