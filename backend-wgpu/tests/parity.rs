//! Parity of the wgpu backend with the CPU reference renderer (issue 7):
//! the same scenes through both backends at 256 px; per valid pixel the
//! relative luminance difference (median ≤ 2 %, 99th percentile ≤ 10 %),
//! and the tone-mapped 8-bit images (camera model, auto exposure) with
//! PSNR ≥ 35 dB. Runs on any adapter (lavapipe in CI).

use glam::DVec3;
use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::LutConfig;
use himmel_skymodel::spectrum::luminance;
use himmel_skymodel::{Effect, HdrImage, Projection, Scene, SkyRenderer, SkyState};

mod common;
use common::{assert_parity, gpu, peaks, rel_diffs};

fn scene(utc: &str, p: Projection, w: u32, h: u32) -> Scene {
    let mut s = Scene::default();
    s.time.utc = utc.into();
    s.observer.lat_deg = 48.14;
    s.observer.lon_deg = 11.58;
    s.effects = vec![Effect::Atmosphere, Effect::Sun];
    s.camera.projection = p;
    s.camera.width = w;
    s.camera.height = h;
    s.lut = LutConfig::small();
    s
}

/// Renders `s` through both backends (the wgpu one with its sky view on
/// the GPU and, uploaded, from the CPU), checks the parity figures and
/// returns the CPU image and the GPU-sky-view image.
fn parity(name: &str, s: &Scene) -> (HdrImage, HdrImage) {
    let state = SkyState::at(s).unwrap();
    let cpu = CpuRenderer::new(None).render(s, &state).unwrap();
    let c = cpu.image;
    let mut first = None;
    for on_gpu in [false, true] {
        let gpu_out = {
            let mut r = gpu();
            r.set_sky_view_on_gpu(on_gpu);
            let out = r.render(s, &state);
            r.set_sky_view_on_gpu(true);
            out.unwrap()
        };
        let g = gpu_out.image;
        let mode = if on_gpu {
            "GPU sky view"
        } else {
            "CPU sky view"
        };
        let label = format!(
            "{name} ({mode}), Sun alt {:.2}°",
            state.sun.alt_refracted_deg
        );
        assert_parity(&label, &c, &g);
        // The passes that ran have times.
        // (`moon-eclipse` is part of the Moon pass and has no time of its own.)
        for p in gpu_out
            .passes
            .iter()
            .filter(|p| p.ran && p.name != "moon-eclipse")
        {
            assert!(p.ms.is_some_and(|t| t >= 0.0), "{name}: {}", p.name);
        }
        first = Some(g);
    }
    (c, first.unwrap())
}

/// Σ luminance over the pixels within `r` px of the Sun's place.
fn sun_sum(img: &HdrImage, s: &Scene, state: &SkyState, r: f64) -> f64 {
    let (sx, sy) = s
        .camera
        .dir_to_pixel(DVec3::from_array(state.sun.enu))
        .unwrap();
    let mut sum = 0.0;
    for (i, p) in img.pixels.iter().enumerate() {
        let (x, y) = ((i % img.width) as f64 + 0.5, (i / img.width) as f64 + 0.5);
        if (x - sx).hypot(y - sy) <= r {
            sum += luminance(*p) as f64;
        }
    }
    sum
}

#[test]
fn noon_fisheye() {
    let s = scene("2024-06-21T11:15:00Z", Projection::Fisheye, 256, 256);
    let state = SkyState::at(&s).unwrap();
    assert!(state.sun.alt_deg > 60.0);
    let (c, g) = parity("noon fisheye", &s);
    // The Sun's disk itself (sub-pixel at this size) carries the same energy.
    let (ec, eg) = (sun_sum(&c, &s, &state, 3.0), sun_sum(&g, &s, &state, 3.0));
    assert!((eg / ec - 1.0).abs() < 0.01, "Sun {eg} vs {ec}");
    // CPU-clock timing (one submission per pass) renders the same image.
    let mut r = gpu();
    r.set_timestamps(false);
    assert_eq!(r.timing(), himmel_wgpu::Timing::Cpu);
    let out = r.render(&s, &state);
    r.set_timestamps(true);
    let out = out.unwrap();
    assert_eq!(out.image, g);
    assert!(out.passes.iter().filter(|p| p.ran).all(|p| p.ms.is_some()));
}

#[test]
fn sunset_equirect_with_a_large_sun() {
    let mut s = scene("2024-06-21T19:12:00Z", Projection::Equirect, 512, 256);
    s.sun_scale = 8.0;
    let state = SkyState::at(&s).unwrap();
    assert!(
        (-0.5..2.0).contains(&state.sun.alt_refracted_deg),
        "{}",
        state.sun.alt_refracted_deg
    );
    let (c, g) = parity("sunset equirect, sun_scale 8", &s);
    let (ec, eg) = (sun_sum(&c, &s, &state, 6.0), sun_sum(&g, &s, &state, 6.0));
    assert!(ec > 0.0);
    assert!((eg / ec - 1.0).abs() < 0.02, "Sun {eg} vs {ec}");
    // Rendered in bands of 7 rows (as frames beyond the adapter's buffer
    // limits are), the image is the same; also with CPU-clock timing.
    for timestamps in [true, false] {
        let mut r = gpu();
        r.set_max_band_bytes(Some(512 * 16 * 7));
        r.set_timestamps(timestamps);
        let out = r.render(&s, &state);
        r.set_max_band_bytes(None);
        r.set_timestamps(true);
        let out = out.unwrap();
        assert_eq!(out.image, g, "banded, timestamps {timestamps}");
        assert!(out.passes.iter().filter(|p| p.ran).all(|p| p.ms.is_some()));
    }
}

#[test]
fn civil_twilight_perspective() {
    let mut s = scene("2024-06-21T19:45:00Z", Projection::Perspective, 256, 256);
    s.camera.yaw_deg = 305.0;
    s.camera.pitch_deg = 10.0;
    s.camera.fov_deg = 100.0;
    let state = SkyState::at(&s).unwrap();
    assert!(
        (-6.0..-1.0).contains(&state.sun.alt_deg),
        "{}",
        state.sun.alt_deg
    );
    parity("civil twilight perspective", &s);
}

#[test]
fn cube_map_strip_and_texture() {
    let s = scene("2024-06-21T17:30:00Z", Projection::Cubemap, 64, 64);
    parity("cube map (6×64²)", &s);
    let state = SkyState::at(&s).unwrap();
    let mut r = gpu();
    let frame = r.render_cubemap(&s, &state, 32).unwrap();
    let size = frame.texture.size();
    assert_eq!(
        (size.width, size.height, size.depth_or_array_layers),
        (32, 32, 6)
    );
    assert!(frame.cube);
    // Users bind it as a cube texture.
    let _view = frame.texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::Cube),
        ..Default::default()
    });
    let img = r.read_back(&frame).unwrap();
    assert_eq!((img.width, img.height), (192, 32));
    assert!(img.valid.iter().all(|v| *v));
}

const SAMPLE_CUBE: &str = r#"
@group(0) @binding(0) var cube: texture_cube<f32>;
@group(0) @binding(1) var nearest: sampler;
@group(0) @binding(2) var<storage, read> dirs: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x < arrayLength(&dirs)) {
        out[gid.x] = textureSampleLevel(cube, nearest, dirs[gid.x].xyz, 0.0);
    }
}
"#;

/// A user binds the cube map as `texture_cube<f32>` and samples it with
/// scene-frame directions (x East, y Up, z South): the hardware's face
/// selection returns the texel that the CPU backend renders for that
/// direction in the conventions.md strip (face order, orientation).
#[test]
fn cube_texture_samples_match_the_cpu_strip() {
    use wgpu::util::DeviceExt;
    let face = 32u32;
    let s = scene("2024-06-21T17:30:00Z", Projection::Cubemap, face, face);
    let state = SkyState::at(&s).unwrap();
    let cpu = CpuRenderer::new(None).render(&s, &state).unwrap().image;
    // Texel centres on every face, as scene-frame directions.
    let mut picks = Vec::new();
    let mut dirs: Vec<[f32; 4]> = Vec::new();
    for f in 0..6u32 {
        for &(x, y) in &[(3u32, 5u32), (16, 16), (28, 2), (9, 30), (30, 29)] {
            let px = (f * face + x) as f64 + 0.5;
            let d = s.camera.pixel_to_dir(px, y as f64 + 0.5).unwrap();
            let v = himmel_skymodel::projection::scene_from_enu(d);
            picks.push((y * 6 * face + f * face + x) as usize);
            dirs.push([v.x as f32, v.y as f32, v.z as f32, 0.0]);
        }
    }
    let mut r = gpu();
    let frame = r.render_cubemap(&s, &state, face).unwrap();
    let dev = r.device();
    let view = frame.texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::Cube),
        ..Default::default()
    });
    let sampler = dev.create_sampler(&wgpu::SamplerDescriptor::default());
    let dir_buf = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&dirs),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let size = (dirs.len() * 16) as u64;
    let out = dev.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let read = dev.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::Cube,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::NonFiltering),
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 3,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: false },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
        ],
    });
    let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Sampler(&sampler),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: dir_buf.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: out.as_entire_binding(),
            },
        ],
    });
    let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: None,
        source: wgpu::ShaderSource::Wgsl(SAMPLE_CUBE.into()),
    });
    let pl = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: None,
        layout: Some(&pl),
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let mut enc = dev.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(1, 1, 1);
    }
    enc.copy_buffer_to_buffer(&out, 0, &read, 0, size);
    r.queue().submit([enc.finish()]);
    read.slice(..).map_async(wgpu::MapMode::Read, |_| {});
    dev.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    let bytes = read.slice(..).get_mapped_range().unwrap().to_vec();
    let got: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    for (k, (&i, g)) in picks.iter().zip(got).enumerate() {
        let (yc, yg) = (luminance(cpu.pixels[i]), luminance([g[0], g[1], g[2]]));
        assert!(
            (yg / yc - 1.0).abs() < 0.01 && g[3] == 1.0,
            "face {} pick {k}: GPU cube sample {yg} vs CPU strip {yc}",
            k / 5
        );
    }
}

/// A dark night (Sun −60°-ish, Moon down) with the diffuse night sky:
/// Milky Way map, faint-star floor, zodiacal light and airglow, extinguished.
fn dark_night(p: Projection, w: u32, h: u32) -> (Scene, SkyState) {
    let mut s = scene("2024-01-15T23:30:00Z", p, w, h);
    s.effects = vec![Effect::Milkyway, Effect::Atmosphere];
    let state = SkyState::at(&s).unwrap();
    assert!(state.sun.alt_deg < -18.0, "{}", state.sun.alt_deg);
    assert!(state.moon.alt_deg < -1.0, "Moon {}", state.moon.alt_deg);
    (s, state)
}

/// The Milky Way pass ran on the GPU (not culled) and carries most of the
/// light: without it the night sky is much darker.
fn milkyway_ran_and_dominates(s: &Scene, state: &SkyState, with: &HdrImage) {
    let mut r = gpu();
    let out = r.render(s, state).unwrap();
    let mw = out.passes.iter().find(|p| p.name == "milkyway").unwrap();
    assert!(mw.ran && mw.ms.is_some(), "{mw:?}");
    let mut s2 = s.clone();
    s2.effects = vec![Effect::Atmosphere];
    let state2 = SkyState::at(&s2).unwrap();
    let without = r.render(&s2, &state2).unwrap().image;
    let sum = |img: &HdrImage| -> f64 { img.pixels.iter().map(|p| luminance(*p) as f64).sum() };
    assert!(
        sum(with) > 3.0 * sum(&without),
        "{} vs {}",
        sum(with),
        sum(&without)
    );
}

#[test]
fn dark_night_milky_way_fisheye() {
    let (s, state) = dark_night(Projection::Fisheye, 128, 128);
    let (c, g) = parity("dark night, Milky Way, fisheye", &s);
    milkyway_within_one_percent(&c, &g);
    milkyway_ran_and_dominates(&s, &state, &g);
}

/// Equirect: the map's right-ascension seam, the refraction band near the
/// horizon (the sky lifted by refraction), the ground below.
#[test]
fn dark_night_milky_way_equirect() {
    let (s, state) = dark_night(Projection::Equirect, 256, 128);
    let (c, g) = parity("dark night, Milky Way, equirect", &s);
    milkyway_within_one_percent(&c, &g);
    milkyway_ran_and_dominates(&s, &state, &g);
}

/// Stars and planets on a dark night: the footprints are evaluated per
/// pixel on the GPU from the CPU's splat plans; the luminance statistics
/// hold and the star images peak at the same pixels.
fn stars_parity(name: &str, p: Projection, w: u32, h: u32) {
    let mut s = scene("2024-01-15T19:30:00Z", p, w, h);
    s.effects = vec![Effect::Stars, Effect::Planets, Effect::Atmosphere];
    let state = SkyState::at(&s).unwrap();
    assert!(state.sun.alt_deg < -18.0, "{}", state.sun.alt_deg);
    let (c, g) = parity(name, &s);
    let out = gpu().render(&s, &state).unwrap();
    for n in ["stars", "planets"] {
        let p = out.passes.iter().find(|p| p.name == n).unwrap();
        assert!(p.ran && p.ms.is_some(), "{p:?}");
    }
    same_peaks(name, &c, &g);
    // In bands of 7 rows (frames beyond the buffer limits) the tile lists
    // give the same image.
    let mut r = gpu();
    r.set_max_band_bytes(Some(w as u64 * 16 * 7));
    let banded = r.render(&s, &state);
    r.set_max_band_bytes(None);
    assert_eq!(banded.unwrap().image, out.image, "{name}: banded");
}

/// The 200 brightest star peaks of the CPU image (at least 50) are peaks
/// of the GPU image at the same pixel (0 px offset; the acceptance allows
/// 0.5 px).
fn same_peaks(name: &str, c: &HdrImage, g: &HdrImage) {
    same_peaks_above(name, c, g, 20.0, 50);
}

/// [`same_peaks`] for the peaks at least `k` × the median luminance, of
/// which there must be `min`.
fn same_peaks_above(name: &str, c: &HdrImage, g: &HdrImage, k: f32, min: usize) {
    let pc = peaks(c, k);
    let pg = peaks(g, k);
    assert!(pc.len() >= min, "{name}: {} star peaks", pc.len());
    let mut same = 0;
    for &(i, j, _) in pc.iter().take(200) {
        if pg.iter().any(|q| q.0 == i && q.1 == j) {
            same += 1;
        }
    }
    let n = pc.len().min(200);
    eprintln!(
        "{name}: {} CPU peaks, {} GPU peaks, {same}/{n} brightest at the same pixel",
        pc.len(),
        pg.len()
    );
    assert_eq!(same, n, "{name}");
}

#[test]
fn night_stars_and_planets_fisheye() {
    stars_parity(
        "night, stars + planets, fisheye",
        Projection::Fisheye,
        256,
        256,
    );
}

/// Equirect: footprints across the 0°/360° seam and the poles' rows,
/// stars at the horizon (the ground check).
#[test]
fn night_stars_and_planets_equirect() {
    stars_parity(
        "night, stars + planets, equirect",
        Projection::Equirect,
        512,
        256,
    );
}

/// A narrow perspective view on the brightest planet: its core reaches
/// white and the excess spreads over a glare disk (checked on the CPU's
/// plan), which the GPU draws the same.
#[test]
fn bright_planet_glare_perspective() {
    let mut s = scene("2024-01-15T19:30:00Z", Projection::Perspective, 192, 128);
    s.effects = vec![Effect::Stars, Effect::Planets, Effect::Atmosphere];
    let state = SkyState::at(&s).unwrap();
    let brightest = state
        .night
        .planets
        .iter()
        .filter(|p| p.dir.z > 0.2)
        .max_by(|a, b| a.lux.total_cmp(&b.lux))
        .copied()
        .expect("a planet well above the horizon");
    s.camera.yaw_deg = (brightest.dir.x as f64)
        .atan2(brightest.dir.y as f64)
        .to_degrees();
    s.camera.pitch_deg = (brightest.dir.z as f64).asin().to_degrees();
    s.camera.fov_deg = 8.0;
    let frame = CpuRenderer::new(None)
        .plan(&s, &state)
        .unwrap()
        .night
        .expect("night passes planned");
    let plans = frame.splat_plans(&s, &frame.planets);
    assert!(
        plans.iter().any(|(p, _)| p.glare_r_px > 2.0),
        "no glare: {plans:?}"
    );
    parity("bright planet glare, perspective 8°", &s);
}

/// Cube map: footprints stay on their face, as the CPU's do.
#[test]
fn night_stars_cube_map() {
    let mut s = scene("2024-01-15T19:30:00Z", Projection::Cubemap, 96, 96);
    s.effects = vec![Effect::Stars, Effect::Planets, Effect::Atmosphere];
    let (c, g) = parity("night, stars + planets, cube map (6×96²)", &s);
    same_peaks("cube map", &c, &g);
}

/// All night passes together (Milky Way, stars, planets, atmosphere).
#[test]
fn dark_night_all_night_passes() {
    let (mut s, _) = dark_night(Projection::Fisheye, 128, 128);
    s.effects = vec![
        Effect::Milkyway,
        Effect::Stars,
        Effect::Planets,
        Effect::Atmosphere,
    ];
    parity("dark night, all night passes, fisheye", &s);
}

/// The Milky Way without the atmosphere: no extinction, refraction still
/// taken off low altitudes (equirect, the horizon band).
#[test]
fn dark_night_milky_way_airless_equirect() {
    let (mut s, _) = dark_night(Projection::Equirect, 256, 128);
    s.effects = vec![Effect::Milkyway];
    let (c, g) = parity("dark night, Milky Way without atmosphere, equirect", &s);
    milkyway_within_one_percent(&c, &g);
}

/// The Milky Way pass is the CPU's formula in f32 with the same tables:
/// every pixel agrees within 1 % (the refraction near the horizon too,
/// where the map's gradient is steep).
fn milkyway_within_one_percent(c: &HdrImage, g: &HdrImage) {
    let d = rel_diffs(c, g);
    let max = d[d.len() - 1];
    assert!(max < 0.01, "max |ΔY|/Y {max}");
}

/// A moonlit night with the Moon just below the horizon (−6° < alt < 0°,
/// three days after full Moon, Sun −24°): the Moon pass does not run but
/// its light is in the sky (cpu lib.rs `SkyLight`: a second sky view lit
/// from the Moon). The moonlit sky carries most of the light.
fn moonlit_below_horizon(p: Projection, w: u32, h: u32) {
    let mut s = scene("2024-01-28T18:35:00Z", p, w, h);
    s.effects = vec![Effect::Moon, Effect::Atmosphere];
    let state = SkyState::at(&s).unwrap();
    assert!(state.sun.alt_refracted_deg < -18.0, "{}", state.sun.alt_deg);
    let m = state.moon.alt_refracted_deg;
    assert!((-6.0..0.0).contains(&m), "Moon {m}");
    assert!(!state.runs(Effect::Moon));
    let pole = DVec3::from_array(state.celestial_pole).as_vec3();
    assert!(himmel_skymodel::moon::moonlight_scale(&s, &state.sun, &state.moon, pole).is_some());
    let name = format!("moonlit night, Moon {m:.1}°, {p:?}");
    let (_, g) = parity(&name, &s);
    // Without the Moon in the scene there is no moonlit sky: much darker.
    let mut s2 = s.clone();
    s2.effects = vec![Effect::Atmosphere];
    let state2 = SkyState::at(&s2).unwrap();
    let without = gpu().render(&s2, &state2).unwrap().image;
    let sum = |img: &HdrImage| -> f64 { img.pixels.iter().map(|p| luminance(*p) as f64).sum() };
    assert!(
        sum(&g) > 10.0 * sum(&without),
        "{} vs {}",
        sum(&g),
        sum(&without)
    );
}

#[test]
fn moonlit_night_moon_below_horizon_fisheye() {
    moonlit_below_horizon(Projection::Fisheye, 128, 128);
}

#[test]
fn moonlit_night_moon_below_horizon_equirect() {
    moonlit_below_horizon(Projection::Equirect, 256, 128);
}

/// Mean linear luminance over the pixels of a perspective image within
/// 0.95 of the Moon's drawn radius of its centre, and their number.
fn moon_disk_mean(s: &Scene, state: &SkyState, img: &HdrImage) -> (f64, usize) {
    let (cx, cy) = s
        .camera
        .dir_to_pixel(DVec3::from_array(state.moon.enu))
        .expect("the Moon in the frame");
    let t = (s.camera.fov_deg.to_radians() / 2.0).tan();
    let r = (state.moon.angular_radius * s.moon_scale).tan() / (2.0 * t / img.height as f64);
    let (mut sum, mut n) = (0.0, 0usize);
    for (i, p) in img.pixels.iter().enumerate() {
        let (x, y) = ((i % img.width) as f64 + 0.5, (i / img.width) as f64 + 0.5);
        if (x - cx).hypot(y - cy) < 0.95 * r {
            sum += luminance(*p) as f64;
            n += 1;
        }
    }
    (sum / n.max(1) as f64, n)
}

/// The Moon pass ran on the GPU with a time, as on the CPU; the
/// `moon-eclipse` entry says whether the eclipse shading ran.
fn moon_ran(s: &Scene, state: &SkyState, eclipse: bool) {
    let out = gpu().render(s, state).unwrap();
    let m = out.passes.iter().find(|p| p.name == "moon").unwrap();
    assert!(m.ran && m.ms.is_some(), "{m:?}");
    let e = out
        .passes
        .iter()
        .find(|p| p.name == "moon-eclipse")
        .unwrap();
    assert_eq!(e.ran, eclipse, "{e:?}");
    assert_eq!(e.reason.is_none(), eclipse, "{e:?}");
}

/// A moonlit night with the full Moon 40° high over Munich (phase 5°, Sun
/// −39°): the Moon (a sub-pixel disk, supersampled 8 × 8), the moonlit sky,
/// stars, planets and the Milky Way, fisheye.
#[test]
fn moonlit_night_full_moon_up_fisheye() {
    let mut s = scene("2024-01-25T20:00:00Z", Projection::Fisheye, 256, 256);
    s.effects = vec![
        Effect::Milkyway,
        Effect::Stars,
        Effect::Planets,
        Effect::Moon,
        Effect::Atmosphere,
    ];
    let state = SkyState::at(&s).unwrap();
    assert!(
        (38.0..43.0).contains(&state.moon.alt_deg),
        "{}",
        state.moon.alt_deg
    );
    assert!(state.moon.phase_angle_topo.to_degrees() < 8.0);
    let (c, g) = parity("moonlit night, full Moon 40°, fisheye", &s);
    moon_ran(&s, &state, false);
    // The brighter stars still show in the moonlit sky (the 31 peaks above
    // 1.3 × the median sky; the Moon is one), at the same pixels.
    same_peaks_above("moonlit night", &c, &g, 1.3, 25);
    // The disk (supersampled, a fraction of a pixel) carries the same light.
    let (mx, my) = s
        .camera
        .dir_to_pixel(DVec3::from_array(state.moon.enu))
        .unwrap();
    let near = |img: &HdrImage| -> f64 {
        let mut sum = 0.0;
        for (i, p) in img.pixels.iter().enumerate() {
            let (x, y) = ((i % img.width) as f64 + 0.5, (i / img.width) as f64 + 0.5);
            if (x - mx).hypot(y - my) <= 2.0 {
                sum += luminance(*p) as f64;
            }
        }
        sum
    };
    let (ec, eg) = (near(&c), near(&g));
    eprintln!("moonlit night: Σ Y within 2 px of the Moon CPU {ec:.4e}, GPU {eg:.4e}");
    assert!((eg / ec - 1.0).abs() < 0.01, "Moon {eg} vs {ec}");
    // Rendered in bands of 5 rows, the image is the same.
    let mut r = gpu();
    r.set_max_band_bytes(Some(256 * 16 * 5));
    let banded = r.render(&s, &state);
    r.set_max_band_bytes(None);
    assert_eq!(banded.unwrap().image, g, "banded");
}

/// The total lunar eclipse of 2025-03-14 at greatest eclipse (06:58:43
/// UTC, NASA/Espenak) from 22.3° S, 77.2° W, where the Moon stands 54°
/// high: the red umbra from the CPU's eclipse table, 1° perspective with
/// the stars and the atmosphere.
#[test]
fn lunar_eclipse_2025_03_14_perspective() {
    let mut s = scene("2025-03-14T06:58:43Z", Projection::Perspective, 192, 192);
    s.observer.lat_deg = -22.3;
    s.observer.lon_deg = -77.2;
    s.effects = vec![Effect::Stars, Effect::Moon, Effect::Atmosphere];
    s.camera.fov_deg = 1.0;
    let state = SkyState::at(&s).unwrap();
    s.camera.yaw_deg = state.moon.az_deg;
    s.camera.pitch_deg = state.moon.alt_refracted_deg;
    let state = SkyState::at(&s).unwrap();
    assert!(state.moon.alt_deg > 50.0, "{}", state.moon.alt_deg);
    assert!(state.moon.eclipse.is_some());
    let (c, g) = parity("lunar eclipse 2025-03-14, 1° perspective", &s);
    moon_ran(&s, &state, true);
    let (mc, n) = moon_disk_mean(&s, &state, &c);
    let (mg, _) = moon_disk_mean(&s, &state, &g);
    eprintln!("lunar eclipse: disk mean Y CPU {mc:.4e}, GPU {mg:.4e} cd/m² ({n} px)");
    assert!(n > 5_000);
    assert!((mg / mc - 1.0).abs() < 0.01, "{mg} vs {mc}");
}

/// Totality at Dallas, 2024-04-08 18:42:39 UTC: the Sun's sub-samples
/// behind the Moon are skipped and the corona drawn around the black disk
/// (2.5° perspective on the Sun); and the whole sky in a fisheye.
#[test]
fn solar_eclipse_totality_dallas() {
    let mut s = scene("2024-04-08T18:42:39Z", Projection::Perspective, 160, 160);
    s.observer.lat_deg = 32.7767;
    s.observer.lon_deg = -96.797;
    s.effects = vec![Effect::Moon, Effect::Sun, Effect::Atmosphere];
    s.camera.fov_deg = 2.5;
    let state = SkyState::at(&s).unwrap();
    s.camera.yaw_deg = state.sun.az_deg;
    s.camera.pitch_deg = state.sun.alt_refracted_deg;
    let state = SkyState::at(&s).unwrap();
    assert!(state.sun.visible_fraction < 1e-3);
    let (c, g) = parity("solar eclipse totality, Dallas, 2.5° perspective", &s);
    moon_ran(&s, &state, false);
    // The corona carries the frame's light (the Sun is hidden): Σ Y.
    let sum = |img: &HdrImage| -> f64 { img.pixels.iter().map(|p| luminance(*p) as f64).sum() };
    eprintln!("totality: Σ Y CPU {:.4e}, GPU {:.4e}", sum(&c), sum(&g));
    assert!((sum(&g) / sum(&c) - 1.0).abs() < 0.01);
    // In bands of 7 rows (the Sun's, the corona's and the Moon's
    // rectangles split across bands), the image is the same; the corona's
    // dispatch counts in the Sun pass's time.
    let banded = {
        let mut r = gpu();
        r.set_max_band_bytes(Some(160 * 16 * 7));
        let out = r.render(&s, &state);
        r.set_max_band_bytes(None);
        out.unwrap()
    };
    assert_eq!(banded.image, g, "banded");
    let ran: Vec<_> = banded
        .passes
        .iter()
        .filter(|p| p.ran)
        .map(|p| (p.name.as_str(), p.ms.is_some()))
        .collect();
    assert_eq!(ran, [("moon", true), ("sun", true), ("atmosphere", true)]);
    let mut f = s.clone();
    f.camera.projection = Projection::Fisheye;
    f.camera.width = 128;
    f.camera.height = 128;
    parity("solar eclipse totality, Dallas, fisheye", &f);
    // The partial phase twelve minutes earlier: the photosphere's crescent
    // beside the Moon's limb (the Sun's sub-samples behind the Moon skipped).
    let mut p = s.clone();
    p.time.utc = "2024-04-08T18:30:00Z".into();
    let st = SkyState::at(&p).unwrap();
    assert!((0.05..0.5).contains(&st.sun.visible_fraction));
    p.camera.yaw_deg = st.sun.az_deg;
    p.camera.pitch_deg = st.sun.alt_refracted_deg;
    let st = SkyState::at(&p).unwrap();
    let (c, g) = parity(
        "solar eclipse partial phase, Dallas 18:30, 2.5° perspective",
        &p,
    );
    let (ec, eg) = (sun_sum(&c, &p, &st, 30.0), sun_sum(&g, &p, &st, 30.0));
    eprintln!("partial phase: Σ Y within 30 px of the Sun CPU {ec:.4e}, GPU {eg:.4e}");
    assert!((eg / ec - 1.0).abs() < 0.01, "{eg} vs {ec}");
}

/// A 1° close-up of the waxing gibbous Moon (phase 57°, 65° high over
/// Munich) at 256 × 256: terminator relief from the normal map, the albedo
/// map, the analytic limb; the mean over the disk agrees within 1 %.
#[test]
fn moon_close_up_perspective() {
    let mut s = scene("2024-01-20T19:00:00Z", Projection::Perspective, 256, 256);
    s.effects = vec![Effect::Moon, Effect::Atmosphere];
    s.camera.fov_deg = 1.0;
    let state = SkyState::at(&s).unwrap();
    s.camera.yaw_deg = state.moon.az_deg;
    s.camera.pitch_deg = state.moon.alt_refracted_deg;
    let state = SkyState::at(&s).unwrap();
    let phase = state.moon.phase_angle_topo.to_degrees();
    assert!((50.0..65.0).contains(&phase), "{phase}");
    let (c, g) = parity("Moon close-up, phase 57°, 1° perspective", &s);
    moon_ran(&s, &state, false);
    let (mc, n) = moon_disk_mean(&s, &state, &c);
    let (mg, _) = moon_disk_mean(&s, &state, &g);
    eprintln!("close-up: disk mean Y CPU {mc:.2} GPU {mg:.2} cd/m² ({n} px)");
    assert!(n > 10_000);
    assert!((mg / mc - 1.0).abs() < 0.01, "{mg} vs {mc}");
    // In bands of 9 rows (the disk's rectangle split across bands) and
    // with CPU-clock timing, the image is the same.
    let mut r = gpu();
    r.set_max_band_bytes(Some(256 * 16 * 9));
    r.set_timestamps(false);
    let banded = r.render(&s, &state);
    r.set_max_band_bytes(None);
    r.set_timestamps(true);
    let banded = banded.unwrap();
    assert_eq!(banded.image, g, "banded");
    let m = banded.passes.iter().find(|p| p.name == "moon").unwrap();
    assert!(m.ms.is_some(), "{m:?}");
}

/// A low Moon (4° high) drawn with the differential refraction across its
/// disk (moon.rs `unrefract`, tabulated for the GPU), 2° perspective.
#[test]
fn low_moon_flattened_by_refraction() {
    let mut s = scene("2024-01-20T12:00:00Z", Projection::Perspective, 192, 192);
    s.effects = vec![Effect::Moon, Effect::Atmosphere];
    s.camera.fov_deg = 2.0;
    // The hour when the Moon rises through 4° at Munich.
    let mut state = SkyState::at(&s).unwrap();
    for m in 0..(24 * 12) {
        s.time.utc = format!("2024-01-20T{:02}:{:02}:00Z", m / 12, (m % 12) * 5);
        state = SkyState::at(&s).unwrap();
        if (3.0..5.0).contains(&state.moon.alt_refracted_deg) {
            break;
        }
    }
    assert!((3.0..5.0).contains(&state.moon.alt_refracted_deg));
    s.camera.yaw_deg = state.moon.az_deg;
    s.camera.pitch_deg = state.moon.alt_refracted_deg;
    let state = SkyState::at(&s).unwrap();
    let (c, g) = parity("low Moon (refraction), 2° perspective", &s);
    moon_ran(&s, &state, false);
    let (mc, _) = moon_disk_mean(&s, &state, &c);
    let (mg, _) = moon_disk_mean(&s, &state, &g);
    assert!((mg / mc - 1.0).abs() < 0.01, "{mg} vs {mc}");
    // The same Moon as a supersampled disk of a 256² fisheye (un-refracted
    // sub-samples), alone: the same light.
    let mut f = s.clone();
    f.camera.projection = Projection::Fisheye;
    f.camera.width = 256;
    f.camera.height = 256;
    f.effects = vec![Effect::Moon];
    let (c, g) = parity("low Moon (refraction), fisheye, Moon alone", &f);
    let sum = |img: &HdrImage| -> f64 { img.pixels.iter().map(|p| luminance(*p) as f64).sum() };
    assert!(sum(&c) > 0.0);
    assert!(
        (sum(&g) / sum(&c) - 1.0).abs() < 1e-3,
        "{} vs {}",
        sum(&g),
        sum(&c)
    );
}

/// The moonlit night of `moonlit_night_full_moon_up_fisheye` as a cube map
/// (6 × 64²: the Moon's sub-samples on its face) and as an equirect image
/// with the Moon drawn 12 × its size (`moon_scale`: the analytic limb, 26 px
/// across, with stars and the Milky Way behind it).
#[test]
fn moonlit_night_cube_map_and_large_moon_equirect() {
    let mut s = scene("2024-01-25T20:00:00Z", Projection::Cubemap, 64, 64);
    s.effects = vec![
        Effect::Milkyway,
        Effect::Stars,
        Effect::Planets,
        Effect::Moon,
        Effect::Atmosphere,
    ];
    let state = SkyState::at(&s).unwrap();
    parity("moonlit night, full Moon 40°, cube map (6×64²)", &s);
    moon_ran(&s, &state, false);
    let mut e = s.clone();
    e.camera.projection = Projection::Equirect;
    e.camera.width = 512;
    e.camera.height = 256;
    e.moon_scale = 12.0;
    let state = SkyState::at(&e).unwrap();
    let (c, g) = parity("moonlit night, Moon × 12, equirect 512×256", &e);
    moon_ran(&e, &state, false);
    // The disk replaces what is behind it: its pixels are the Moon's.
    let (mx, my) = e
        .camera
        .dir_to_pixel(DVec3::from_array(state.moon.enu))
        .unwrap();
    let at = |img: &HdrImage| luminance(img.pixels[my as usize * 512 + mx as usize]) as f64;
    eprintln!(
        "Moon × 12: centre pixel CPU {:.1} GPU {:.1} cd/m²",
        at(&c),
        at(&g)
    );
    assert!(at(&c) > 1000.0 && (at(&g) / at(&c) - 1.0).abs() < 1e-3);
}

/// Every pixel the CPU's Moon pass draws lies in the rectangle the GPU's
/// Moon pass is dispatched over (`moon_uniforms`), in all projections:
/// a perspective close-up, a supersampled fisheye disk, an equirect disk
/// × 12, a cube map and a low, refracted Moon.
#[test]
fn moon_rectangle_holds_every_drawn_pixel() {
    let close = |p: Projection, w: u32, h: u32, fov: f64, scale: f64, utc: &str| {
        let mut s = scene(utc, p, w, h);
        s.effects = vec![Effect::Moon];
        s.moon_scale = scale;
        s.camera.fov_deg = fov;
        let st = SkyState::at(&s).unwrap();
        s.camera.yaw_deg = st.moon.az_deg + 0.2 * fov;
        s.camera.pitch_deg = st.moon.alt_refracted_deg;
        s
    };
    let scenes = [
        close(
            Projection::Perspective,
            160,
            120,
            1.0,
            1.0,
            "2024-01-20T19:00:00Z",
        ),
        close(
            Projection::Fisheye,
            128,
            128,
            90.0,
            1.0,
            "2024-01-25T20:00:00Z",
        ),
        close(
            Projection::Equirect,
            256,
            128,
            90.0,
            12.0,
            "2024-01-25T20:00:00Z",
        ),
        close(
            Projection::Cubemap,
            48,
            48,
            90.0,
            4.0,
            "2024-01-25T20:00:00Z",
        ),
        close(
            Projection::Perspective,
            128,
            128,
            2.0,
            1.0,
            "2024-01-20T11:40:00Z",
        ),
    ];
    for s in &scenes {
        let state = SkyState::at(s).unwrap();
        let img = CpuRenderer::new(None).render(s, &state).unwrap().image;
        let rect = himmel_skymodel::frame::MoonFrame::new(s, &state, None, 0.0).rect;
        let [x0, y0, x1, y1] = rect;
        let mut drawn = 0;
        for (i, p) in img.pixels.iter().enumerate() {
            if luminance(*p) > 0.0 {
                drawn += 1;
                let (x, y) = ((i % img.width) as u32, (i / img.width) as u32);
                assert!(
                    (x0..x1).contains(&x) && (y0..y1).contains(&y),
                    "{:?}: ({x}, {y}) outside {:?}",
                    s.camera.projection,
                    rect
                );
            }
        }
        assert!(drawn > 0, "{:?}: no Moon", s.camera.projection);
        eprintln!(
            "{:?}: {drawn} Moon pixels in a {}×{} rectangle (Moon {:.1}° up)",
            s.camera.projection,
            x1 - x0,
            y1 - y0,
            state.moon.alt_refracted_deg
        );
    }
}

/// The Moon rising through the horizon at night (2024-01-27, Munich, Sun
/// −18°, phase 22°; refracted altitude of the centre within ±0.15°): the
/// ground hides the lower half, the refraction is strongest, the extinction
/// steepest across the disk; 2° perspective.
#[test]
fn moon_on_the_horizon() {
    let mut s = scene("2024-01-27T17:45:00Z", Projection::Perspective, 192, 192);
    s.effects = vec![Effect::Moon, Effect::Atmosphere];
    s.camera.fov_deg = 2.0;
    let mut state = SkyState::at(&s).unwrap();
    for m in 45..60 {
        s.time.utc = format!("2024-01-27T17:{m:02}:00Z");
        state = SkyState::at(&s).unwrap();
        if state.moon.alt_refracted_deg > -0.15 {
            break;
        }
    }
    let alt = state.moon.alt_refracted_deg;
    assert!((-0.15..0.15).contains(&alt), "{alt}");
    assert!(state.sun.alt_deg < -12.0);
    s.camera.yaw_deg = state.moon.az_deg;
    s.camera.pitch_deg = alt;
    let state = SkyState::at(&s).unwrap();
    let (c, g) = parity(
        &format!("Moon on the horizon ({alt:.2}°), 2° perspective"),
        &s,
    );
    moon_ran(&s, &state, false);
    // The upper part of the disk is drawn and outshines the sky beside it
    // (the mean over the disk includes the ground below the horizon).
    let (mc, n) = moon_disk_mean(&s, &state, &c);
    let (mg, _) = moon_disk_mean(&s, &state, &g);
    let sky = luminance(c.pixels[96 * 192 + 5]) as f64;
    eprintln!("horizon: disk mean Y CPU {mc:.4} GPU {mg:.4} cd/m² ({n} px), sky beside {sky:.4}");
    assert!(mc > 5.0 * sky, "{mc} vs sky {sky}");
    assert!((mg / mc - 1.0).abs() < 0.01, "{mg} vs {mc}");
}
