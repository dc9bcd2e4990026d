//! CPU ↔ wgpu parity of the texture pass: every mapping, a cross-fade
//! between two textures of different mappings with a rotation, the
//! horizon band and the blend over the physical sky (issue 17: median
//! ≤ 2 %, p99 ≤ 10 %, PSNR ≥ 35 dB). The textures are generated here
//! and written as small EXR files.

mod wgpu_common;

use std::path::PathBuf;
use std::sync::Arc;

use glam::DVec3;
use himmel_cpu::texture_io::{write_texture, ImageLoader};
use himmel_skymodel::texture_sky::{LinearImage, Mapping};
use himmel_skymodel::texture_spec::{
    HorizonSpec, RotationMode, RotationSpec, SkyTextureSpec, TransitionSpec,
};
use himmel_skymodel::{Effect, Projection, Scene};
use wgpu_common::{gpu, parity, scene};

const NOON: &str = "2024-06-21T10:00:00Z";

/// A sky pattern with structure in azimuth and altitude (cd/m²).
fn pattern(d: DVec3, k: f64) -> [f32; 3] {
    let az = d.x.atan2(d.y);
    let alt = d.z.clamp(-1.0, 1.0).asin();
    let v = 3000.0 * (1.6 + (3.0 * az + k).sin() * alt.cos() + 0.5 * (4.0 * alt).cos());
    [v as f32, (0.8 * v) as f32, (1.2 * v + 500.0) as f32]
}

/// Writes the pattern as an EXR of `mapping` with `n` texels per tile side.
fn texture_file(name: &str, mapping: Mapping, n: u32, k: f64) -> String {
    let (w, h) = match mapping {
        Mapping::Polar => (n, n),
        Mapping::Sphere | Mapping::Paraboloid => (2 * n, n),
        Mapping::Cube | Mapping::CubeUniform => (6 * n, n),
    };
    let mut texels = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let d = mapping
                .pixel_to_dir(f64::from(i) + 0.5, f64::from(j) + 0.5, w, h)
                .unwrap();
            texels.push(pattern(d, k));
        }
    }
    let dir = std::env::temp_dir().join(format!("himmel-wgpu-texture-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path: PathBuf = dir.join(name);
    write_texture(
        &path,
        &LinearImage {
            width: w,
            height: h,
            texels,
        },
    )
    .unwrap();
    path.display().to_string()
}

fn textured(p: Projection, w: u32, h: u32, spec: SkyTextureSpec) -> Scene {
    gpu().set_texture_loader(Arc::new(ImageLoader));
    let mut s = scene(NOON, p, w, h);
    s.effects = vec![Effect::Atmosphere, Effect::Sun, Effect::Texture];
    s.sky_texture = Some(spec);
    s
}

#[test]
fn every_mapping() {
    for m in Mapping::ALL {
        let path = texture_file(&format!("{m}.exr"), m, 32, 0.0);
        let spec = SkyTextureSpec {
            path,
            mapping: m,
            keep: vec![himmel_skymodel::texture_spec::KeptPass::Sun],
            ..SkyTextureSpec::default()
        };
        let (_, g) = parity(
            &format!("texture {m}, fisheye"),
            &textured(Projection::Fisheye, 64, 64, spec.clone()),
        );
        // The texture is what is drawn: the pattern lies in 1 500 … 10 000 cd/m².
        let mut y: Vec<f32> = g
            .pixels
            .iter()
            .zip(&g.valid)
            .filter(|(_, v)| **v)
            .map(|(p, _)| himmel_skymodel::spectrum::luminance(*p))
            .collect();
        y.sort_by(f32::total_cmp);
        let median = y[y.len() / 2];
        assert!(
            (1500.0..10_000.0).contains(&median),
            "{m}: median {median} cd/m²"
        );
        if m == Mapping::CubeUniform {
            let mut s = textured(Projection::Perspective, 64, 48, spec);
            s.camera.yaw_deg = 45.0;
            s.camera.pitch_deg = 35.0;
            s.camera.fov_deg = 80.0;
            parity(
                &format!("texture {m}, perspective across a cube corner"),
                &s,
            );
        }
    }
}

#[test]
fn transition_rotation_and_horizon_band() {
    let a = texture_file("a.exr", Mapping::Sphere, 32, 0.0);
    let b = texture_file("b.exr", Mapping::Polar, 48, 1.3);
    // Half-way through a 10-minute cross-fade that began 5 minutes ago.
    let spec = SkyTextureSpec {
        path: a,
        mapping: Mapping::Sphere,
        blend: 0.7,
        rotation: RotationSpec {
            mode: RotationMode::Rate,
            azimuth_deg: 20.0,
            rate_deg_per_h: 15.0,
            reference_utc: "2024-06-21T08:00:00Z".into(),
        },
        horizon: Some(HorizonSpec {
            color_cd_m2: [4000.0, 3000.0, 2000.0],
            height_deg: 8.0,
            softness_deg: 6.0,
        }),
        transitions: vec![TransitionSpec {
            path: b,
            mapping: Some(Mapping::Polar),
            at_utc: "2024-06-21T09:55:00Z".into(),
            fade_s: 600.0,
        }],
        ..SkyTextureSpec::default()
    };
    let mut s = textured(Projection::Equirect, 96, 48, spec);
    s.effects.retain(|e| *e != Effect::Sun);
    parity(
        "texture cross-fade (sphere → polar), rate rotation, band, blend 0.7",
        &s,
    );
    let state = himmel_skymodel::SkyState::at(&s).unwrap();
    let mut cpu = himmel_cpu::CpuRenderer::new(None);
    let plan = cpu.plan(&s, &state).unwrap();
    let t = plan.texture.unwrap();
    let gains: Vec<f32> = t.layers.iter().map(|l| l.gain).collect();
    assert!(
        gains.len() == 2 && gains.iter().all(|g| (g - 0.5).abs() < 1e-5),
        "half-way through the fade: {gains:?}"
    );
}
