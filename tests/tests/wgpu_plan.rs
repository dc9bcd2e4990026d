//! The wgpu backend executes the frame plan without the CPU's per-pixel
//! work: a night frame (every night pass, the Moon and the atmosphere,
//! metered automatically) builds no per-pixel direction buffer and no CPU
//! sky view — the plan's metering and culling read the GPU's sky views
//! back — while the same frame on the CPU backend builds both (so the
//! counts can fail). The two backends plan the same frame: the same
//! passes run, for the same reasons.

use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::LutConfig;
use himmel_skymodel::frame::pixels::direction_buffers_built;
use himmel_skymodel::frame::sky_light::cpu_sky_views_computed;
use himmel_skymodel::{Effect, Exposure, Projection, Scene, SkyRenderer, SkyState};

mod wgpu_common;
use wgpu_common::gpu;

fn moonlit_night() -> (Scene, SkyState) {
    let mut s = Scene::default();
    s.time.utc = "2024-01-25T20:00:00Z".into();
    s.observer.lat_deg = 48.14;
    s.observer.lon_deg = 11.58;
    s.effects = vec![
        Effect::Milkyway,
        Effect::Stars,
        Effect::Planets,
        Effect::Moon,
        Effect::Atmosphere,
    ];
    s.exposure = Exposure::Auto;
    s.camera.projection = Projection::Fisheye;
    s.camera.width = 256;
    s.camera.height = 256;
    s.lut = LutConfig::small();
    let state = SkyState::at(&s).unwrap();
    (s, state)
}

#[test]
fn a_wgpu_night_frame_builds_no_cpu_directions_and_no_cpu_sky_view() {
    let (s, state) = moonlit_night();
    let mut r = gpu();
    r.set_sky_view_on_gpu(true);
    let (dirs, views) = (direction_buffers_built(), cpu_sky_views_computed());
    let g = r.render(&s, &state).unwrap();
    assert_eq!(
        direction_buffers_built() - dirs,
        0,
        "direction buffers on wgpu"
    );
    assert_eq!(cpu_sky_views_computed() - views, 0, "CPU sky views on wgpu");
    // The counts move when the CPU does this work.
    let c = CpuRenderer::new(None).render(&s, &state).unwrap();
    assert_eq!(direction_buffers_built() - dirs, 1);
    assert!(cpu_sky_views_computed() - views >= 2, "sunlit + moonlit");
    // Both backends planned the same frame.
    let summary = |p: &[himmel_skymodel::PassStat]| {
        p.iter()
            .map(|p| (p.name.clone(), p.ran))
            .collect::<Vec<_>>()
    };
    assert_eq!(summary(&g.passes), summary(&c.passes));
    let ran: Vec<&str> = g
        .passes
        .iter()
        .filter(|p| p.ran)
        .map(|p| p.name.as_str())
        .collect();
    eprintln!("moonlit night on wgpu: ran {ran:?}");
    assert!(ran.contains(&"stars") && ran.contains(&"moon") && ran.contains(&"atmosphere"));
}

/// With the sky view on the CPU (`set_sky_view_on_gpu(false)`) the wgpu
/// backend computes the CPU sky views once per frame — for the metering
/// and the upload alike — and still no direction buffer.
#[test]
fn a_cpu_sky_view_is_computed_once_per_frame() {
    let (s, state) = moonlit_night();
    let mut r = gpu();
    r.set_sky_view_on_gpu(false);
    let (dirs, views) = (direction_buffers_built(), cpu_sky_views_computed());
    let out = r.render(&s, &state);
    r.set_sky_view_on_gpu(true);
    out.unwrap();
    assert_eq!(direction_buffers_built() - dirs, 0);
    assert_eq!(
        cpu_sky_views_computed() - views,
        2,
        "sunlit + moonlit, once"
    );
}
