//! Texture-mapped skies on the CPU: the physical sky rendered as an
//! equirect EXR and drawn back as a `sphere` texture matches the physical
//! sky's own render; the masked sun; the `sky` units; image files and
//! their errors.

use std::path::PathBuf;

use glam::DVec3;
use himmel_cpu::texture_io::{read_texture, write_texture};
use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::LutConfig;
use himmel_skymodel::projection::enu_from_alt_az;
use himmel_skymodel::spectrum::luminance;
use himmel_skymodel::texture_sky::{LinearImage, Mapping, TextureError};
use himmel_skymodel::texture_spec::{SunMaskSpec, TextureUnits};
use himmel_skymodel::{
    Effect, HdrImage, Projection, RenderError, Scene, SkyRenderer, SkyState, SkyTextureSpec,
};

fn scene(effects: Vec<Effect>, p: Projection, w: u32, h: u32) -> Scene {
    let mut s = Scene::default();
    s.time.utc = "2024-06-21T10:00:00Z".into();
    s.observer.lat_deg = 48.14;
    s.observer.lon_deg = 11.58;
    s.effects = effects;
    s.camera.projection = p;
    s.camera.width = w;
    s.camera.height = h;
    s.lut = LutConfig::small();
    s
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("himmel-texture-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn render(s: &Scene) -> HdrImage {
    let state = SkyState::at(s).unwrap();
    CpuRenderer::new(None).render(s, &state).unwrap().image
}

fn with_texture(mut s: Scene, spec: SkyTextureSpec) -> Scene {
    s.effects.push(Effect::Texture);
    s.sky_texture = Some(spec);
    s
}

/// Sorted relative luminance differences over the valid pixels.
fn rel_diffs(a: &HdrImage, b: &HdrImage) -> Vec<f64> {
    let mut d: Vec<f64> = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .zip(&a.valid)
        .filter(|(_, v)| **v)
        .map(|((p, q), _)| {
            let (x, y) = (f64::from(luminance(*p)), f64::from(luminance(*q)));
            (y - x).abs() / x.max(1e-30)
        })
        .collect();
    d.sort_by(f64::total_cmp);
    d
}

/// The strong invariant: the physical sky as a 1024 × 512 equirect EXR,
/// drawn back as a `sphere` texture in its own units, is the physical
/// sky again in a fisheye and a perspective view, up to the bilinear
/// filtering of 0.35° texels.
#[test]
fn the_physical_sky_drawn_back_as_a_texture_is_the_physical_sky() {
    let pano = render(&scene(
        vec![Effect::Atmosphere],
        Projection::Equirect,
        1024,
        512,
    ));
    let path = scratch("physical.exr");
    himmel_cpu::output::write_exr(&path, &pano).unwrap();
    let spec = SkyTextureSpec {
        path: path.display().to_string(),
        mapping: Mapping::Sphere,
        ..SkyTextureSpec::default()
    };
    for (name, p, w, h) in [
        ("fisheye", Projection::Fisheye, 128, 128),
        ("perspective", Projection::Perspective, 96, 64),
    ] {
        let mut physical = scene(vec![Effect::Atmosphere], p, w, h);
        physical.camera.yaw_deg = 250.0;
        physical.camera.pitch_deg = 15.0;
        physical.camera.fov_deg = 50.0;
        let textured = with_texture(physical.clone(), spec.clone());
        let (a, b) = (render(&physical), render(&textured));
        let d = rel_diffs(&a, &b);
        let (med, p99, max) = (d[d.len() / 2], d[d.len() * 99 / 100], d[d.len() - 1]);
        println!(
            "physical sky vs its equirect drawn back, {name}: median {:.3} %, p99 {:.3} %, max {:.3} %",
            100.0 * med,
            100.0 * p99,
            100.0 * max
        );
        assert!(med < 0.005 && p99 < 0.03, "{name}: median {med}, p99 {p99}");
    }
}

/// A gradient sky with a sun of its own: 1° wide, 10⁶ cd/m², at az 100°,
/// alt 30° of the texture.
fn sky_with_sun() -> LinearImage {
    let (w, h) = (720u32, 360u32);
    let sun = enu_from_alt_az(30f64.to_radians(), 100f64.to_radians());
    let mut texels = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let d = Mapping::Sphere
                .pixel_to_dir(f64::from(i) + 0.5, f64::from(j) + 0.5, w, h)
                .unwrap();
            let base = 2000.0 + 1000.0 * d.z.max(0.0) as f32;
            let spot = if d.angle_between(sun).to_degrees() < 0.5 {
                1e6
            } else {
                0.0
            };
            texels.push([base + spot, base + spot, 1.3 * base + spot]);
        }
    }
    LinearImage {
        width: w,
        height: h,
        texels,
    }
}

#[test]
fn the_masked_sun_is_replaced_by_the_ephemeris_sun() {
    let path = scratch("sun.exr");
    write_texture(&path, &sky_with_sun()).unwrap();
    let spec = SkyTextureSpec {
        path: path.display().to_string(),
        keep: vec![himmel_skymodel::texture_spec::KeptPass::Sun],
        sun_mask: Some(SunMaskSpec::default()),
        ..SkyTextureSpec::default()
    };
    let s = with_texture(
        scene(
            vec![Effect::Atmosphere, Effect::Sun],
            Projection::Fisheye,
            256,
            256,
        ),
        spec,
    );
    let state = SkyState::at(&s).unwrap();
    let img = render(&s);
    let y = |x: f64, yy: f64| luminance(img.pixels[yy as usize * img.width + x as usize]);
    // The texture's sun is gone: at its place, the gradient (≤ 3 000 cd/m²).
    let own = enu_from_alt_az(30f64.to_radians(), 100f64.to_radians());
    let (ox, oy) = s.camera.dir_to_pixel(own).unwrap();
    for (dx, dy) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (-1.0, -1.0)] {
        let v = y(ox + dx, oy + dy);
        assert!(
            (1000.0..3500.0).contains(&v),
            "texture sun still drawn: {v} cd/m²"
        );
    }
    // The drawn disk: the luminance-weighted centroid of the pixels above
    // 10⁶ cd/m² (the texture's sky is ≤ 3 000) at the ephemeris Sun.
    let (mut cx, mut cy, mut sw) = (0.0, 0.0, 0.0);
    for (i, p) in img.pixels.iter().enumerate() {
        let v = f64::from(luminance(*p));
        if v > 1e6 {
            cx += v * ((i % img.width) as f64 + 0.5);
            cy += v * ((i / img.width) as f64 + 0.5);
            sw += v;
        }
    }
    assert!(sw > 0.0, "no Sun disk drawn");
    let (sx, sy) = s
        .camera
        .dir_to_pixel(DVec3::from_array(state.sun.enu))
        .unwrap();
    let off = (cx / sw - sx).hypot(cy / sw - sy);
    println!("drawn Sun disk {off:.3} px from the ephemeris Sun");
    assert!(off <= 1.0, "{off} px");
}

#[test]
fn sky_units_match_the_physical_sky_illuminance() {
    let path = scratch("grey.exr");
    let grey = LinearImage {
        width: 64,
        height: 32,
        texels: vec![[1.0, 1.0, 1.0]; 64 * 32],
    };
    write_texture(&path, &grey).unwrap();
    let spec = SkyTextureSpec {
        path: path.display().to_string(),
        units: TextureUnits::Sky,
        ..SkyTextureSpec::default()
    };
    let s = with_texture(
        scene(vec![Effect::Atmosphere], Projection::Fisheye, 32, 32),
        spec,
    );
    let state = SkyState::at(&s).unwrap();
    let mut r = CpuRenderer::new(None);
    let out = r.render(&s, &state).unwrap();
    let plan = r.plan(&s, &state).unwrap();
    let t = plan.texture.unwrap();
    let sky = himmel_skymodel::frame::lights::luminance(out.lights.sky_horizontal_rgb);
    // A uniform unit texture has E = π; its gain is the sky's E / π.
    let want = sky / std::f64::consts::PI;
    let got = f64::from(t.layers[0].gain);
    println!("sky units: gain {got:.2} cd/m² vs E_sky/π {want:.2}");
    assert!((got / want - 1.0).abs() < 1e-3, "{got} vs {want}");
}

#[test]
fn image_files_decode_and_errors_name_the_file() {
    // An 8-bit sRGB PNG: 128 → linear 0.21586.
    let png = scratch("mid.png");
    image::RgbImage::from_pixel(12, 6, image::Rgb([128, 128, 128]))
        .save(&png)
        .unwrap();
    let d = read_texture(&png).unwrap();
    assert!(!d.hdr);
    assert!(
        (d.image.texels[0][0] - 0.215_861).abs() < 1e-5,
        "{:?}",
        d.image.texels[0]
    );
    // EXR keeps its linear values.
    let exr = scratch("hdr.exr");
    let img = LinearImage {
        width: 4,
        height: 2,
        texels: vec![[12_345.0, 0.5, 2.0]; 8],
    };
    write_texture(&exr, &img).unwrap();
    let d = read_texture(&exr).unwrap();
    assert!(d.hdr);
    assert_eq!(d.image, img);
    // Missing and corrupt files.
    let missing = scratch("missing.exr");
    let e = read_texture(&missing).unwrap_err();
    assert!(
        matches!(e, TextureError::File { .. }) && e.to_string().contains("missing.exr"),
        "{e}"
    );
    let bad = scratch("garbage.png");
    std::fs::write(&bad, b"\x89PNG\r\n\x1a\nnot really").unwrap();
    let e = read_texture(&bad).unwrap_err();
    assert!(e.to_string().contains("garbage.png"), "{e}");
    // A cube strip of the wrong aspect fails the render, naming the file.
    let strip = scratch("strip.exr");
    write_texture(
        &strip,
        &LinearImage {
            width: 50,
            height: 10,
            texels: vec![[1.0; 3]; 500],
        },
    )
    .unwrap();
    let spec = SkyTextureSpec {
        path: strip.display().to_string(),
        mapping: Mapping::Cube,
        ..SkyTextureSpec::default()
    };
    let s = with_texture(scene(vec![], Projection::Fisheye, 16, 16), spec);
    let state = SkyState::at(&s).unwrap();
    let e = CpuRenderer::new(None).render(&s, &state).unwrap_err();
    assert!(
        matches!(e, RenderError::Texture(TextureError::Size { .. })),
        "{e}"
    );
    assert!(
        e.to_string().contains("strip.exr") && e.to_string().contains("6N × N"),
        "{e}"
    );
}
