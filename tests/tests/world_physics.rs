//! Physical checks of the wgpu world passes (issue 14, `spec/world.md`),
//! each against a number the physics fixes rather than a picture:
//!
//! * a white Lambertian plane open to the sky shows
//!   L = ρ/π · (E_dir · sin h + E_sky,h) with the frame's own illuminances;
//! * a pole's shadow points away from the Sun's azimuth and is
//!   height / tan h long;
//! * the soft shadow's penumbra is as wide as the Sun's disk seen from the
//!   shadow: distance × tan 0.53°;
//! * a closed room lit inside by an emissive patch gains no light from the
//!   sunlit sky outside (no leaks through the walls).

mod wgpu_common;
mod world_common;

use glam::{DVec3, Vec3};
use himmel_skymodel::frame::lights::luminance;
use himmel_skymodel::{Effect, RenderOutput, Scene, SkyRenderer, SkyState, WorldSpec};
use himmel_world::procedural::Builder;
use himmel_world::{Material, World};
use world_common::view::{ground_point, munich_view};

/// A scene at `time` (Munich) seeing `world` from `eye` towards `at`.
fn scene(
    time: &str,
    eye: [f64; 3],
    at: [f64; 3],
    up: [f64; 3],
    size: (u32, u32),
    fov: f64,
) -> Scene {
    let mut s = munich_view(time, eye, at, up, size, fov);
    s.effects = vec![
        Effect::Atmosphere,
        Effect::Sun,
        Effect::Moon,
        Effect::World,
        Effect::Shadows,
    ];
    s.world = Some(WorldSpec {
        gltf: "test".into(),
        ground: false,
    });
    s
}

fn render(s: &Scene, world: &World) -> (RenderOutput, SkyState) {
    let state = SkyState::at(s).unwrap();
    let mut r = wgpu_common::gpu();
    r.set_world(world);
    let out = r.render(s, &state).unwrap();
    // HIMMEL_TEST_OUT=DIR keeps each frame as a PNG for inspection.
    if let Some(dir) = std::env::var_os("HIMMEL_TEST_OUT") {
        let name = format!(
            "world_{:016x}.png",
            out.image.pixels.len() as u64 ^ (s.camera.width as u64) << 32
        );
        let settings = himmel_skymodel::camera::CameraSettings {
            exposure: s.exposure,
            night_vision: false,
            dither: false,
        };
        let _ = himmel_cpu::output::write_png(
            &std::path::Path::new(&dir).join(name),
            &out.image,
            &settings,
        );
    }
    (out, state)
}

/// A square plane of half-side `half` metres at y = 0 of linear albedo `rho`.
fn plane(b: &mut Builder, half: f32, rho: f32) {
    let m = b.material(Material::diffuse("plane", [rho; 3]));
    let v = Vec3::new;
    b.quad(
        m,
        [
            v(-half, 0.0, half),
            v(half, 0.0, half),
            v(half, 0.0, -half),
            v(-half, 0.0, -half),
        ],
    );
}

#[test]
fn lit_plane_shows_the_frames_own_illuminance() {
    let mut b = Builder::default();
    plane(&mut b, 300.0, 0.5);
    let world = b.build();
    for time in ["2024-06-21T11:00:00Z", "2024-06-21T17:30:00Z"] {
        let s = scene(
            time,
            [0.0, 2.0, 0.0],
            [0.0, 0.0, -2.0],
            [0.0, 1.0, 0.0],
            (64, 48),
            40.0,
        );
        let (out, state) = render(&s, &world);
        let sun = out.lights.direct.sun.expect("the Sun is up");
        let h = sun.altitude();
        let e = [0, 1, 2].map(|c| sun.rgb[c] * h.sin() + out.lights.sky_horizontal_rgb[c]);
        let want = luminance(e) * 0.5 / std::f64::consts::PI;
        // The central pixels (the plane at ~2.5 m).
        let img = &out.image;
        let mut sum = 0.0;
        let mut n = 0.0;
        for y in 20..28 {
            for x in 28..36 {
                sum += luminance(img.pixels[y * img.width + x].map(f64::from));
                n += 1.0;
            }
        }
        let got = sum / n;
        eprintln!("lit plane at {time}: {got:.1} cd/m² vs {want:.1} cd/m²");
        assert!(
            (got / want - 1.0).abs() < 0.01,
            "{time} (Sun at {:.1}°): plane {got:.1} cd/m² vs ρ/π·(E_dir sin h + E_sky) = {want:.1}",
            state.sun.alt_refracted_deg
        );
    }
}

/// The shadow of a 5 m pole on a white plane seen from straight above.
#[test]
fn pole_shadow_points_away_from_the_sun_with_its_length() {
    let mut b = Builder::default();
    plane(&mut b, 100.0, 0.8);
    let m = b.material(Material::diffuse("pole", [0.8; 3]));
    let height = 5.0f32;
    b.cuboid(
        m,
        Vec3::new(-0.05, 0.0, -0.05),
        Vec3::new(0.05, height, 0.05),
    );
    let world = b.build();
    let time = "2024-06-21T15:00:00Z";
    let s0 = scene(
        time,
        [0.0, 30.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, -1.0],
        (8, 8),
        45.0,
    );
    let st = SkyState::at(&s0).unwrap();
    let alt = st.sun.alt_refracted_deg.to_radians();
    let az = st.sun.az_deg.to_radians();
    let want_len = height as f64 / alt.tan();
    // Away from the Sun (world frame: x East, z South).
    let away = DVec3::new(-az.sin(), 0.0, az.cos());
    // Looking down on the middle of the shadow, North (−z) up in the image.
    let mid = away * (want_len / 2.0);
    let (w, h) = (640u32, 640u32);
    let s = scene(
        time,
        (mid + DVec3::Y * 12.0).to_array(),
        mid.to_array(),
        [0.0, 0.0, -1.0],
        (w, h),
        35.0,
    );
    let (out, _) = render(&s, &world);
    let img = &out.image;
    let mut ys: Vec<f64> = img
        .pixels
        .iter()
        .map(|p| luminance(p.map(f64::from)))
        .collect();
    ys.sort_by(f64::total_cmp);
    let lit = ys[ys.len() / 2];
    // The umbra keeps the sky's light: the depth of a full shadow is the
    // Sun's share of the plane's illuminance.
    let sun = out.lights.direct.sun.expect("the Sun is up");
    let e_sun = luminance(sun.rgb) * alt.sin();
    let depth = e_sun / (e_sun + luminance(out.lights.sky_horizontal_rgb));
    // The shadow's darkness integrated across its width, in 1 cm bins along
    // `away`: the local width of the shadow (m) — 0.1 m along the pole's
    // image, falling to 0 at the tip.
    let bin = 0.01;
    let n = (want_len * 1.5 / bin) as usize;
    let mut width = vec![0.0f64; n];
    let (mut sx, mut sz, mut mass) = (0.0, 0.0, 0.0);
    let across = DVec3::new(away.z, 0.0, -away.x);
    for y in 0..h as usize {
        for x in 0..w as usize {
            let Some(p) = ground_point(&s, x, y) else {
                continue;
            };
            let l = luminance(img.pixels[y * w as usize + x].map(f64::from));
            let dark = ((lit - l) / (lit * depth)).clamp(0.0, 1.0);
            if dark < 0.05 {
                continue;
            }
            // The pixel's footprint on the ground, m².
            let fp = footprint(&s, x, y);
            let along = p.dot(away);
            if p.dot(across).abs() < 0.5 && along > 0.0 && ((along / bin) as usize) < n {
                width[(along / bin) as usize] += dark * fp / bin;
            }
            sx += p.x * dark;
            sz += p.z * dark;
            mass += dark;
        }
    }
    // Azimuth of the shadow's centroid, from North through East.
    let shadow_az = sx.atan2(-sz);
    let mut diff = (shadow_az - (az + std::f64::consts::PI))
        .to_degrees()
        .rem_euclid(360.0);
    if diff > 180.0 {
        diff -= 360.0;
    }
    assert!(mass > 100.0, "no shadow found");
    assert!(diff.abs() < 0.5, "shadow azimuth off by {diff:.3}°");
    // The length: where the width falls to half its value along the pole.
    let body: Vec<f64> = width[(1.0 / bin) as usize..((want_len - 1.0) / bin) as usize].to_vec();
    let mut sorted = body.clone();
    sorted.sort_by(f64::total_cmp);
    let full = sorted[sorted.len() / 2];
    // The pole's square section seen across the shadow: 0.1 m × (|ax| + |az|),
    // to the shadow map's texels.
    let section = 0.1 * (across.x.abs() + across.z.abs());
    assert!(
        (full / section - 1.0).abs() < 0.15,
        "the shadow is {full:.4} m wide, not the pole's {section:.4} m"
    );
    let k = (1.0 / bin) as usize
        + width[(1.0 / bin) as usize..]
            .iter()
            .position(|&v| v < 0.5 * full)
            .expect("the shadow ends");
    let len = (k as f64) * bin;
    eprintln!(
        "pole shadow: azimuth off by {diff:.3}°, {len:.3} m vs {want_len:.3} m, width {full:.4} m"
    );
    assert!(
        (len / want_len - 1.0).abs() < 0.01,
        "shadow {len:.3} m vs height / tan h = {want_len:.3} m (Sun {:.2}°)",
        alt.to_degrees()
    );
}

/// The ground area seen by pixel (x, y), m².
fn footprint(s: &Scene, x: usize, y: usize) -> f64 {
    let p = |dx: f64, dy: f64| {
        let d = s.camera.pixel_to_dir(x as f64 + dx, y as f64 + dy).unwrap();
        let d = himmel_skymodel::projection::scene_from_enu(d);
        let eye = s.camera.eye_m();
        eye + d * (-eye.y / d.y)
    };
    let (a, b, c) = (p(0.0, 0.0), p(1.0, 0.0), p(0.0, 1.0));
    (b - a).cross(c - a).length()
}

/// Fraction of a uniform disk of unit radius beyond offset x (the light
/// blocked by a straight edge at x), for x in [−1, 1].
fn disk_fraction(x: f64) -> f64 {
    let x = x.clamp(-1.0, 1.0);
    (x.acos() - x * (1.0 - x * x).sqrt()) / std::f64::consts::PI
}

/// x where `disk_fraction` equals `f` (bisection).
fn disk_offset(f: f64) -> f64 {
    let (mut lo, mut hi) = (-1.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if disk_fraction(mid) > f {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn soft_penumbra_is_as_wide_as_the_suns_disk() {
    // A 12 m roof slab at 10 m; the Sun high in the south-west: the
    // shadow's side edge runs along the Sun's azimuth and its penumbra,
    // across it, is (distance along the ray) × the Sun's diameter.
    let mut b = Builder::default();
    plane(&mut b, 100.0, 0.8);
    let m = b.material(Material::diffuse("roof", [0.8; 3]));
    let roof_h = 10.0f32;
    b.cuboid(
        m,
        Vec3::new(-6.0, roof_h, -6.0),
        Vec3::new(6.0, roof_h + 0.2, 6.0),
    );
    let world = b.build();
    let s0 = scene(
        "2024-06-21T11:00:00Z",
        [0.0, 5.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, -1.0],
        (64, 64),
        10.0,
    );
    let state = SkyState::at(&s0).unwrap();
    let alt = state.sun.alt_refracted_deg.to_radians();
    let az = state.sun.az_deg.to_radians();
    // Horizontal unit vectors along and across the Sun's azimuth (world).
    let along = DVec3::new(az.sin(), 0.0, -az.cos());
    let across = DVec3::new(along.z, 0.0, -along.x);
    // The roof's shadow is shifted away from the Sun by h / tan(alt); find
    // a point of its side edge: the shadow of the roof corner edge. Rather
    // than intersect analytically, scan across at the shadow's middle.
    let shift = -along * (roof_h as f64 / alt.tan());
    let centre = shift;
    // The side edge of the shadow nearest `across`: the roof's half width
    // projected on `across` (the roof is square; its edges are axis-aligned,
    // so the side edge is a slanted line in general — use a profile
    // perpendicular to the x or z edge closest to `across`).
    let (edge_axis, edge_dir) = if across.x.abs() > across.z.abs() {
        (DVec3::X * across.x.signum(), DVec3::Z)
    } else {
        (DVec3::Z * across.z.signum(), DVec3::X)
    };
    let _ = edge_dir;
    let edge_point = centre + edge_axis * 6.0;
    let eye = edge_point + DVec3::Y * 3.0;
    let mut s = scene(
        "2024-06-21T11:00:00Z",
        eye.to_array(),
        edge_point.to_array(),
        [0.0, 0.0, -1.0],
        (400, 400),
        20.0,
    );
    s.lighting.shadows.resolution = 4096;
    let (out, _) = render(&s, &world);
    // Profile along edge_axis through the image centre: luminance vs
    // offset (m), averaged over the 40 middle rows or columns.
    let img = &out.image;
    let n = 400usize;
    let mut prof: Vec<(f64, f64)> = Vec::new();
    for i in 0..n {
        let mut acc = 0.0;
        let mut off = 0.0;
        for j in 180..220 {
            let (x, y) = if edge_axis.x != 0.0 { (i, j) } else { (j, i) };
            let p = ground_point(&s, x, y).unwrap();
            off += (p - edge_point).dot(edge_axis);
            acc += luminance(img.pixels[y * n + x].map(f64::from));
        }
        prof.push((off / 40.0, acc / 40.0));
    }
    prof.sort_by(|a, b| a.0.total_cmp(&b.0));
    let umbra = prof.first().unwrap().1.min(prof.last().unwrap().1);
    let lit = prof.first().unwrap().1.max(prof.last().unwrap().1);
    let at = |f: f64| {
        let level = umbra + f * (lit - umbra);
        let k = prof
            .windows(2)
            .position(|w| (w[0].1 - level) * (w[1].1 - level) <= 0.0)
            .expect("the profile crosses the level");
        let (a, b) = (prof[k], prof[k + 1]);
        a.0 + (level - a.1) / (b.1 - a.1) * (b.0 - a.0)
    };
    let w1090 = (at(0.9) - at(0.1)).abs();
    // The penumbra's full width W for a uniform disk: its 10–90 % width is
    // W/2 × |x(0.1) − x(0.9)|.
    let k = (disk_offset(0.1) - disk_offset(0.9)).abs() / 2.0;
    let width = w1090 / k;
    // The edge of the roof is at distance roof_h / sin(alt) along the ray;
    // the profile runs along an axis at angle φ to the true
    // across-the-ray direction: the penumbra on the ground widens by 1/|cos φ|
    // in the along-axis direction and by 1/sin(alt) where it is along the ray.
    let d = roof_h as f64 / alt.sin();
    let theta = 2.0 * state.sun.angular_radius;
    // Ground footprint of the penumbra across an edge with horizontal
    // normal e: W_ground = d·θ·|(e·across)| + d·θ/sin(alt)·|(e·along)| — the
    // disk's image on the ground is an ellipse with semi-axes d·θ/2 across
    // and d·θ/(2 sin alt) along the azimuth; its extent along e:
    let (ea, el) = (edge_axis.dot(across), edge_axis.dot(along));
    let want = d * theta.tan() * (ea * ea + (el / alt.sin()).powi(2)).sqrt();
    eprintln!("penumbra: {width:.4} m measured, {want:.4} m expected (d = {d:.2} m)");
    assert!(
        (width / want - 1.0).abs() < 0.2,
        "penumbra {:.4} m vs {:.4} m (distance {d:.2} m × tan 0.53°, projected)",
        width,
        want
    );
}

#[test]
fn closed_room_gains_no_light_from_the_sunlit_sky() {
    // A closed white box (0.2 m walls) with an emissive patch inside; the
    // Sun high outside.
    let mut b = Builder::default();
    let wall = b.material(Material::diffuse("wall", [1.0; 3]));
    let lamp = b.material(Material {
        emissive: [100.0, 100.0, 100.0],
        ..Material::diffuse("lamp", [0.0; 3])
    });
    let v = Vec3::new;
    let (x, y, z, t) = (3.0, 3.0, 3.0, 0.2);
    b.cuboid(wall, v(-x - t, -t, -z - t), v(x + t, 0.0, z + t));
    b.cuboid(wall, v(-x - t, y, -z - t), v(x + t, y + t, z + t));
    b.cuboid(wall, v(-x - t, 0.0, -z - t), v(-x, y, z + t));
    b.cuboid(wall, v(x, 0.0, -z - t), v(x + t, y, z + t));
    b.cuboid(wall, v(-x, 0.0, -z - t), v(x, y, -z));
    b.cuboid(wall, v(-x, 0.0, z), v(x, y, z + t));
    // The box alone, then with the lamp.
    let bare = b.clone().build();
    b.quad(
        lamp,
        [
            v(-0.5, 2.99, -0.5),
            v(0.5, 2.99, -0.5),
            v(0.5, 2.99, 0.5),
            v(-0.5, 2.99, 0.5),
        ],
    );
    let lit = b.build();
    let mut s = scene(
        "2024-06-21T11:00:00Z",
        [0.0, 1.5, 2.5],
        [0.0, 1.5, -3.0],
        [0.0, 1.0, 0.0],
        (96, 64),
        90.0,
    );
    // One part a cell (each looked up along its cell's direction): nothing
    // leaks. The default parts are looked up with a parallax that a
    // single depth layer cannot always follow: a ray that tilts into a
    // ceiling the map sees edge-on counts as open where it passes the
    // far wall. That leak (2.2 × 10⁻⁴ here, in the room's upper corners)
    // is bounded at 5 × 10⁻⁴ of what a white surface open to the whole sky
    // receives; a closed interior lit by lamps wants `parts` 1.
    for (parts, world) in [(1, &bare), (16, &bare), (1, &lit), (16, &lit)] {
        s.lighting.sky.parts = parts;
        let (out, _) = render(&s, world);
        let open_sky = luminance(out.lights.sky_horizontal_rgb) / std::f64::consts::PI;
        let bound = if parts == 1 { 1e-3 } else { 5e-4 * open_sky };
        let mut lamp_px = 0;
        let mut leak = 0.0f64;
        for p in &out.image.pixels {
            let l = luminance(p.map(f64::from));
            if l > 50.0 {
                // Only the lamp itself, at its emitted radiance.
                assert!((l / 100.0 - 1.0).abs() < 1e-3, "{l}");
                lamp_px += 1;
            } else {
                // Walls: no sunlight or skylight leaks in (world passes add
                // no light of their own beyond emission at this order).
                leak = leak.max(l);
            }
        }
        println!("parts {parts}: largest leak {leak:.2e} cd/m² (open sky {open_sky:.0} cd/m²)");
        assert!(leak < bound, "parts {parts}: leak {leak} cd/m² (≤ {bound})");
        assert_eq!(
            lamp_px > 0,
            std::ptr::eq(world, &lit),
            "the lamp is in view"
        );
    }
}
