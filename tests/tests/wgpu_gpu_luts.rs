//! The atmosphere LUTs computed by the WGSL compute shaders (luts.wgsl)
//! against the CPU precompute (`himmel_cpu::precompute`), texel by texel,
//! and frame parity of the wgpu backend with GPU LUTs against the CPU
//! renderer (the metrics of tests/parity.rs). Runs on any adapter
//! (lavapipe in CI).
//!
//! The bound. Both sides evaluate the same f32 expressions, but a shader
//! compiler may fuse multiply-adds (and a GPU's sqrt/exp may differ by an
//! ulp), so a sample's radius r_i = √(t² + 2rμt + r²) with r ≈ 6400 km can
//! differ by one ulp of r² (4 km²): δr = ulp(r²)/(2r) ≈ 0.31 m, which
//! changes the aerosol density e^{−h/H_M} (H_M = 1.2 km) by
//! κ = δr/H_M ≈ 2.6e-4 relative. An optical depth τ may therefore differ by
//! a few κ·τ (we allow 3κ) plus the rounding of T = e^{−τ} near 1 (f32 ε),
//! and T itself by τ·3κ relative: with the values compared (T ≥ 1e-6 of
//! the table's maximum, τ ≤ ln 10⁶ ≈ 13.8) at most 1.1e-2. Ψ_ms integrates
//! the Sun's transmittance over paths of the same optical depths, so the
//! same bound holds for it. The 99th percentiles (τ ≲ 1 for most texels)
//! must stay below 1e-3.

use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::{AtmosphereLuts, AtmosphereParams, Lut2, LutConfig, Medium};
use himmel_skymodel::spectrum::Spectrum;
use himmel_skymodel::{Effect, Projection, Scene, SkyRenderer, SkyState};
use himmel_wgpu::luts::{self, LutPipelines};
use himmel_wgpu::LutSource;

mod wgpu_common;
use wgpu_common::{assert_parity, gpu, percentile};

/// κ of the module documentation: the relative aerosol-density change of
/// one ulp of r² at the ground.
fn kappa(m: &Medium) -> f32 {
    let r2 = m.bottom * m.bottom;
    let ulp = f32::from_bits(r2.to_bits() + 1) - r2;
    ulp / (2.0 * m.bottom) * m.inv_h_m
}

/// Sorted relative differences |g − c| / c of every band of every texel
/// with c ≥ 1e-6 × the table's largest value; fails on a non-finite GPU
/// value or a smaller one off by more than that floor.
fn rel_diffs(label: &str, c: &Lut2<Spectrum>, g: &Lut2<Spectrum>) -> Vec<f64> {
    assert_eq!((c.w, c.h, c.data.len()), (g.w, g.h, g.data.len()));
    let floor = 1e-6 * c.data.iter().map(|s| s.max_value()).fold(0.0f32, f32::max);
    let mut d = Vec::new();
    for (a, b) in c.data.iter().zip(&g.data) {
        for (x, y) in a.0.iter().zip(&b.0) {
            assert!(y.is_finite(), "{label}: non-finite GPU texel");
            if *x >= floor {
                d.push(((y - x).abs() / x) as f64);
            } else {
                assert!((y - x).abs() <= floor, "{label}: {y} vs {x}");
            }
        }
    }
    d.sort_by(|a, b| a.total_cmp(b));
    d
}

/// Compares the three LUTs; returns (max, p99) of the relative differences
/// per LUT after asserting the bounds of the module documentation.
fn compare(name: &str, cpu: &AtmosphereLuts, gpu: &AtmosphereLuts) -> [(f64, f64); 3] {
    let k = kappa(&cpu.medium);
    assert!((2e-4..3e-4).contains(&k), "κ {k}");
    // Optical depths: |Δτ| ≤ 2ε + 3κτ on every band of every texel.
    for (label, c, g) in [
        ("T", &cpu.transmittance, &gpu.transmittance),
        (
            "T_s",
            &cpu.scattering_transmittance,
            &gpu.scattering_transmittance,
        ),
    ] {
        let mut worst = 0.0f32;
        for (a, b) in c.data.iter().zip(&g.data) {
            for (x, y) in a.0.iter().zip(&b.0) {
                // Below 1e-30 (τ > 69) the GPU may flush to zero.
                if *x < 1e-30 {
                    assert!(*y < 1e-29, "{name}: {y} vs {x}");
                    continue;
                }
                let (tx, ty) = (-x.ln(), -y.ln());
                let allowed = 2.0 * f32::EPSILON + 3.0 * k * tx;
                worst = worst.max((ty - tx).abs() / allowed);
            }
        }
        eprintln!("{name} {label}: worst |Δτ| / (2ε + 3κτ) = {worst:.3}");
        assert!(worst <= 1.0, "{name} {label}: τ off by {worst} × the bound");
    }
    let bound = 3.0 * k * 1e6f32.ln() + 2.0 * f32::EPSILON;
    let mut out = [(0.0, 0.0); 3];
    for (i, (label, c, g)) in [
        ("transmittance", &cpu.transmittance, &gpu.transmittance),
        (
            "scattering transmittance",
            &cpu.scattering_transmittance,
            &gpu.scattering_transmittance,
        ),
        ("multiple scattering", &cpu.multiscatter, &gpu.multiscatter),
    ]
    .into_iter()
    .enumerate()
    {
        let d = rel_diffs(label, c, g);
        let (max, p99) = (d[d.len() - 1], percentile(&d, 0.99));
        eprintln!(
            "{name} {label} ({}×{}, {} values): max relative difference {max:.2e}, p99 {p99:.2e}",
            c.w,
            c.h,
            d.len()
        );
        assert!(max <= bound as f64, "{name} {label}: max {max} > {bound}");
        assert!(p99 <= 1e-3, "{name} {label}: p99 {p99}");
        out[i] = (max, p99);
    }
    out
}

fn gpu_luts(params: &AtmosphereParams, config: &LutConfig) -> AtmosphereLuts {
    let r = gpu();
    let p = LutPipelines::new(r.device());
    luts::compute(r.device(), r.queue(), &p, params, config)
        .expect("GPU LUTs")
        .1
}

#[test]
fn gpu_luts_match_the_cpu_precompute_at_the_default_config() {
    let params = AtmosphereParams::default();
    let config = LutConfig::default();
    let c = himmel_cpu::precompute(&params, &config, false);
    let g = gpu_luts(&params, &config);
    compare("default config", &c, &g);
    // The parameters and configuration travel with them.
    assert_eq!((g.params, g.config), (params, config));
    assert_eq!(g.forward, c.forward);
}

/// The other branches: no forward peak, a finite number of orders, a
/// direction count that is not a square (rounded to k² as on the CPU), a
/// hazy, high-albedo atmosphere; and single scattering (Ψ = 0).
#[test]
fn gpu_luts_match_the_cpu_precompute_on_other_branches() {
    let params = AtmosphereParams {
        aerosol_density: 3.0,
        ground_albedo: 0.6,
        ozone_du: 400.0,
        ..AtmosphereParams::default()
    };
    let config = LutConfig {
        forward_peak_deg: 0.0,
        orders: 3,
        multiscatter_dirs: 50,
        multiscatter_n: 20,
        ..LutConfig::small()
    };
    let c = himmel_cpu::precompute(&params, &config, false);
    let g = gpu_luts(&params, &config);
    compare("hazy, 3 orders, no forward peak", &c, &g);
    assert_eq!(c.transmittance, c.scattering_transmittance);
    let single = LutConfig {
        orders: 1,
        ..LutConfig::small()
    };
    let g = gpu_luts(&params, &single);
    assert!(g.multiscatter.data.iter().all(|s| *s == Spectrum::ZERO));
    assert_eq!(g.multiscatter.data.len(), 16 * 16);
}

/// A zero size is an error, not a panic or a device loss.
#[test]
fn an_empty_lut_is_an_error() {
    let r = gpu();
    let p = LutPipelines::new(r.device());
    let config = LutConfig {
        multiscatter_n: 0,
        ..LutConfig::small()
    };
    let e = luts::compute(
        r.device(),
        r.queue(),
        &p,
        &AtmosphereParams::default(),
        &config,
    )
    .unwrap_err();
    assert!(e.to_string().contains("multiscatter_n"), "{e}");
}

fn scene(utc: &str, p: Projection, w: u32, h: u32) -> Scene {
    let mut s = Scene::default();
    s.time.utc = utc.into();
    s.observer.lat_deg = 48.14;
    s.observer.lon_deg = 11.58;
    s.effects = vec![Effect::Atmosphere, Effect::Sun];
    s.camera.projection = p;
    s.camera.width = w;
    s.camera.height = h;
    s
}

/// Renders `s` on the CPU backend and on wgpu with GPU LUTs (twice: the
/// second frame reuses them) and checks the parity figures of
/// tests/parity.rs: median ≤ 2 %, p99 ≤ 10 %, PSNR ≥ 35 dB.
fn parity_with_gpu_luts(name: &str, s: &Scene) {
    let state = SkyState::at(s).unwrap();
    let c = CpuRenderer::new(None).render(s, &state).unwrap().image;
    let mut r = gpu();
    let before = r.lut_source();
    r.set_lut_source(LutSource::Gpu);
    let first = r.render(s, &state);
    let second = r.render(s, &state);
    r.set_lut_source(before);
    let (first, second) = (first.unwrap(), second.unwrap());
    assert_eq!(first.lut_source.name(), "gpu", "{name}");
    assert_eq!(second.lut_source.name(), "memory", "{name}: LUTs reused");
    assert_eq!(first.image, second.image, "{name}");
    let g = first.image;
    let label = format!(
        "{name} (GPU LUTs), Sun alt {:.2}°",
        state.sun.alt_refracted_deg
    );
    assert_parity(&label, &c, &g);
}

#[test]
fn noon_with_gpu_luts_at_the_default_config() {
    let s = scene("2024-06-21T11:15:00Z", Projection::Fisheye, 256, 256);
    let state = SkyState::at(&s).unwrap();
    assert!(state.sun.alt_deg > 60.0);
    parity_with_gpu_luts("noon fisheye, default LUTs", &s);
}

#[test]
fn civil_twilight_with_gpu_luts() {
    let mut s = scene("2024-06-21T19:45:00Z", Projection::Perspective, 256, 256);
    s.camera.yaw_deg = 305.0;
    s.camera.pitch_deg = 10.0;
    s.camera.fov_deg = 100.0;
    s.lut = LutConfig::small();
    let state = SkyState::at(&s).unwrap();
    assert!(
        (-6.0..-1.0).contains(&state.sun.alt_deg),
        "{}",
        state.sun.alt_deg
    );
    parity_with_gpu_luts("civil twilight perspective, small LUTs", &s);
}

/// Switching the source drops the LUTs held: the CPU path computes anew.
#[test]
fn switching_the_source_recomputes() {
    let mut s = scene("2024-06-21T17:30:00Z", Projection::Fisheye, 32, 32);
    s.lut = LutConfig::small();
    s.atmosphere.ozone_du = 310.0;
    let state = SkyState::at(&s).unwrap();
    let mut r = gpu();
    let before = r.lut_source();
    r.set_lut_source(LutSource::Gpu);
    let a = r.render(&s, &state).map(|o| o.lut_source);
    r.set_lut_source(LutSource::Cpu);
    let b = r.render(&s, &state).map(|o| o.lut_source);
    let b2 = r.render(&s, &state).map(|o| o.lut_source);
    r.set_lut_source(before);
    assert_eq!(a.unwrap().name(), "gpu");
    assert_eq!(b.unwrap().name(), "computed");
    assert_eq!(b2.unwrap().name(), "memory");
}
