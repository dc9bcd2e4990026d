//! The cloud models' cost per ray (`cargo bench -p himmel-tests --bench
//! clouds`): the low layer's march (default cumulus at coverage 0.6, 64
//! steps per slab, 6 light steps) with each multiple-scattering model
//! (the diffusion solution, two light marches per step; Wrenninge's six
//! octaves, one), the height-field tier's probes through its maps and the
//! maps' build (once per frame; `clouds.low.tier = "heightfield"`), and
//! the high layer's shading, over a fan of 256 view rays above 20°
//! altitude; the default diffusion model's 3D grid (its build, once per
//! light and frame, over the unbounded layer's 16 km square) and the march
//! that reads it.

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use himmel_skymodel::clouds::{
    march_height_field, march_low, march_low_with_grids, shade_high, CloudLight, DiffusionGrid,
    HeightField, HighField, LowField, MarchSettings, MultipleScattering, Shell, DIFFUSION, GRID,
    OCTAVES,
};
use himmel_skymodel::scene::{HighCloudSpec, LowCloudSpec};

fn rays() -> Vec<Vec3> {
    (0..256)
        .map(|i| {
            let az = i as f32 * 0.618 * std::f32::consts::TAU;
            let alt = (20.0 + 70.0 * (i as f32 / 256.0)).to_radians();
            Vec3::new(alt.cos() * az.sin(), alt.cos() * az.cos(), alt.sin())
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let shell = Shell {
        r_ground: 6360.0,
        r_observer: 6360.0,
    };
    let low = LowField::new(
        &LowCloudSpec {
            coverage: 0.6,
            ..LowCloudSpec::default()
        },
        0.0,
    );
    let high = HighField::new(
        &HighCloudSpec {
            coverage: 0.6,
            ..HighCloudSpec::default()
        },
        0.0,
    );
    let lights = [CloudLight {
        dir: Vec3::new(0.3, -0.5, 0.81).normalize(),
        irradiance_rgb: [1.0e5; 3],
    }];
    let rays = rays();
    for (name, scattering) in [
        ("diffusion", MultipleScattering::Diffusion(DIFFUSION)),
        ("octaves", MultipleScattering::Octaves(OCTAVES)),
    ] {
        let settings = MarchSettings {
            steps: 64,
            light_steps: 6,
            scattering,
        };
        c.bench_function(&format!("clouds/low_march_256_rays_{name}"), |b| {
            b.iter(|| {
                rays.iter()
                    .map(|&v| {
                        march_low(&low, &shell, v, &lights, [1.0e3; 3], &settings).transmittance
                    })
                    .sum::<f32>()
            })
        });
    }
    let settings = MarchSettings {
        steps: 64,
        light_steps: 6,
        scattering: MultipleScattering::Diffusion(DIFFUSION),
    };
    let dirs = [lights[0].dir];
    c.bench_function("clouds/diffusion_grid_build", |b| {
        b.iter(|| {
            DiffusionGrid::build(&low, &shell, dirs[0], &GRID)
                .map(|g| g.iterations)
                .unwrap_or(0)
        })
    });
    if let Ok(grid) = DiffusionGrid::build(&low, &shell, dirs[0], &GRID) {
        let grids = [grid];
        c.bench_function("clouds/low_march_256_rays_diffusion_grid", |b| {
            b.iter(|| {
                rays.iter()
                    .map(|&v| {
                        march_low_with_grids(
                            &low, &shell, v, &lights, [1.0e3; 3], &settings, &grids,
                        )
                        .transmittance
                    })
                    .sum::<f32>()
            })
        });
    }
    c.bench_function("clouds/height_field_maps_build", |b| {
        b.iter(|| HeightField::build(&low, &shell, &dirs, &settings).n)
    });
    let hf = HeightField::build(&low, &shell, &dirs, &settings);
    c.bench_function("clouds/height_field_256_rays_diffusion", |b| {
        b.iter(|| {
            rays.iter()
                .map(|&v| {
                    march_height_field(&hf, &low, &shell, v, &lights, [1.0e3; 3], &settings)
                        .transmittance
                })
                .sum::<f32>()
        })
    });
    c.bench_function("clouds/high_shade_256_rays", |b| {
        b.iter(|| {
            rays.iter()
                .map(|&v| shade_high(&high, &shell, v, &lights, [1.0e3; 3]).transmittance)
                .sum::<f32>()
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
