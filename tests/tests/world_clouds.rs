//! Clouds over a 3D world (issue 18, `spec/world.md`): the Sun's light on
//! the world passes through the cloud layers, and a cloudy sky lights it
//! with its clouds.
//!
//! * The Sun's share of a white plane's luminance (the frame with the
//!   Sun minus the frame without it) under cumulus, over the same share
//!   under a clear sky, is the clouds' transmittance towards the Sun from
//!   that point of the plane (`CloudFrame::transmittance_towards`, the
//!   sky model's own march), pixel by pixel;
//! * the environment light is rebuilt when the clouds move (the wind) and
//!   kept when nothing changed, with its reason in `--stats`.
//!
//! `cargo test -p himmel-tests --test world_clouds -- --nocapture` prints
//! the figures.

mod wgpu_common;
mod world_common;

use glam::Vec3;
use himmel_skymodel::frame::lights::luminance;
use himmel_skymodel::frame::CloudFrame;
use himmel_skymodel::scene::LowCloudKind;
use himmel_skymodel::{Effect, RenderOutput, Scene, SkyRenderer, SkyState, WorldSpec};
use himmel_world::procedural::Builder;
use himmel_world::{Material, World};
use world_common::view::{ground_point, munich_view};

/// A white (ρ = 0.5) plane 3 km across seen from 1.2 km straight above, at
/// noon in Munich, with cumulus (coverage 0.65) when `clouds`, the Sun's light when `sun`.
fn scene(clouds: bool, sun: bool) -> Scene {
    let mut s = munich_view(
        "2024-06-21T11:00:00Z",
        [0.0, 1200.0, 0.0],
        [0.0; 3],
        [0.0, 0.0, -1.0],
        (64, 64),
        90.0,
    );
    s.effects = vec![Effect::Atmosphere, Effect::World];
    if sun {
        s.effects.push(Effect::Sun);
    }
    if clouds {
        s.effects.push(Effect::Clouds);
        s.clouds.low.coverage = 0.65;
        s.clouds.low.kind = LowCloudKind::Cumulus;
    }
    s.world = Some(WorldSpec {
        gltf: "test".into(),
        ground: false,
    });
    s
}

fn plane() -> World {
    let mut b = Builder::default();
    let m = b.material(Material::diffuse("plane", [0.5; 3]));
    let (h, v) = (1500.0, Vec3::new);
    b.quad(
        m,
        [v(-h, 0.0, h), v(h, 0.0, h), v(h, 0.0, -h), v(-h, 0.0, -h)],
    );
    b.build()
}

fn render(r: &mut himmel_wgpu::WgpuRenderer, s: &Scene) -> RenderOutput {
    let state = SkyState::at(s).expect("state");
    r.render(s, &state).expect("render")
}

#[test]
fn cloud_shadows_fall_on_the_world() {
    let world = plane();
    let mut r = wgpu_common::gpu();
    r.set_world(&world);
    let [cs, cn, ks, kn] = [(true, true), (true, false), (false, true), (false, false)]
        .map(|(c, s)| render(&mut r, &scene(c, s)));
    let stat = cs
        .passes
        .iter()
        .find(|p| p.name == "world/cloud-shadows")
        .expect("a cloud-shadows entry");
    assert!(stat.ran && stat.ms.is_some(), "{stat:?}");
    assert!(!kn.passes.iter().any(|p| p.name == "world/cloud-shadows"));
    // The sky model's transmittance towards the Sun from the plane.
    let s = scene(true, true);
    let state = SkyState::at(&s).expect("state");
    let clouds = CloudFrame::prepare(&s, &state, None, None, None, &mut Default::default());
    let sun = state.sun.dir().as_vec3().normalize();
    let w = s.camera.width as usize;
    let y = |o: &RenderOutput, i: usize| luminance(o.image.pixels[i].map(f64::from));
    let (mut n, mut sum_err, mut worst) = (0usize, 0.0f64, 0.0f64);
    let (mut lo, mut hi) = (1.0f64, 0.0f64);
    for py in 2..62 {
        for px in 2..62 {
            let Some(p) = ground_point(&s, px, py) else {
                continue;
            };
            let i = py * w + px;
            let clear = y(&ks, i) - y(&kn, i);
            let cloudy = y(&cs, i) - y(&cn, i);
            assert!(clear > 0.0, "the Sun lights the plane");
            let got = cloudy / clear;
            // World (x East, z South) → the clouds' ENU km.
            let pos = Vec3::new(
                p.x as f32 * 1e-3,
                -p.z as f32 * 1e-3,
                clouds.shell.r_observer,
            );
            let want = clouds.transmittance_towards(pos, sun) as f64;
            let err = (got - want).abs();
            sum_err += err;
            worst = worst.max(err);
            lo = lo.min(want);
            hi = hi.max(want);
            n += 1;
        }
    }
    let mean = sum_err / n as f64;
    println!(
        "cloud shadows on a plane ({n} pixels, T {lo:.3}–{hi:.3}): mean |ΔT| {mean:.4}, worst {worst:.4}"
    );
    // The scene must show sun and shadow for the test to mean anything.
    assert!(lo < 0.3 && hi > 0.7, "T {lo}–{hi}");
    // The map's 25 m bilinear texels against the exact march per pixel.
    assert!(mean < 0.005, "mean |ΔT| {mean}");
    assert!(worst < 0.05, "worst |ΔT| {worst}");
}

#[test]
fn the_sky_light_follows_the_clouds() {
    let world = plane();
    let mut r = wgpu_common::gpu();
    r.set_world(&world);
    let sky = |o: &RenderOutput| {
        o.passes
            .iter()
            .find(|p| p.name == "world/sky-light")
            .cloned()
            .expect("a sky-light entry")
    };
    let mut s = scene(true, true);
    let first = render(&mut r, &s);
    assert!(sky(&first).ran);
    let again = render(&mut r, &s);
    let kept = sky(&again);
    assert!(!kept.ran && kept.reason.is_some_and(|w| w.starts_with("reused")));
    // One second later the Sun has moved 0.004° (within the reuse
    // tolerance) but the wind has moved the clouds 5 m: rebuilt.
    s.time.utc = "2024-06-21T11:00:01Z".into();
    let moved = render(&mut r, &s);
    assert!(sky(&moved).ran, "{:?}", sky(&moved));
    // The clouds are in the sky that lights the world: the plane without
    // the Sun under a closed deck of stratus and under a clear sky.
    let mut overcast = scene(true, false);
    overcast.clouds.low.coverage = 1.0;
    overcast.clouds.low.kind = LowCloudKind::Stratus;
    let dark = render(&mut r, &overcast);
    let clear = render(&mut r, &scene(false, false));
    let c = 32 * 64 + 32;
    let (yd, yc) = (
        luminance(dark.image.pixels[c].map(f64::from)),
        luminance(clear.image.pixels[c].map(f64::from)),
    );
    println!("sky-lit plane: clear sky {yc:.1} cd/m², overcast stratus {yd:.1} cd/m²");
    assert!(yd != yc && yd > 0.0, "{yd} {yc}");
}
