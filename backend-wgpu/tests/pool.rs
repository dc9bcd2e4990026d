//! The per-frame buffers are kept across frames (`WgpuRenderer::pooled_buffers`):
//! a repeated frame allocates no buffer and reproduces its image bit for bit,
//! and a frame after a different one carries nothing over from it (every
//! binding covers exactly the bytes its frame wrote).

use himmel_skymodel::atmosphere::LutConfig;
use himmel_skymodel::{Effect, HdrImage, Projection, Scene, SkyRenderer, SkyState};
use himmel_wgpu::WgpuRenderer;

fn scene(utc: &str, effects: Vec<Effect>, w: u32, h: u32) -> (Scene, SkyState) {
    let mut s = Scene::default();
    s.time.utc = utc.into();
    s.observer.lat_deg = 48.14;
    s.observer.lon_deg = 11.58;
    s.effects = effects;
    s.camera.projection = Projection::Fisheye;
    s.camera.width = w;
    s.camera.height = h;
    s.lut = LutConfig::small();
    let state = SkyState::at(&s).unwrap();
    (s, state)
}

fn image(r: &mut WgpuRenderer, s: &(Scene, SkyState)) -> HdrImage {
    r.render(&s.0, &s.1).unwrap().image
}

#[test]
fn repeated_frames_reuse_their_buffers_and_nothing_leaks_between_scenes() {
    let mut r = WgpuRenderer::new(None).expect("a wgpu adapter (lavapipe in CI)");
    // A moonlit night with every point pass (Moon 40° up, stars, planets,
    // Milky Way) and a noon frame with only the atmosphere and the Sun.
    let night = scene(
        "2024-01-25T20:00:00Z",
        vec![
            Effect::Milkyway,
            Effect::Stars,
            Effect::Planets,
            Effect::Moon,
            Effect::Atmosphere,
        ],
        128,
        128,
    );
    let noon = scene(
        "2024-06-21T11:00:00Z",
        vec![Effect::Atmosphere, Effect::Sun],
        96,
        96,
    );
    assert!(night.1.moon.alt_deg > 30.0 && night.1.sun.alt_deg < -18.0);

    let a = image(&mut r, &night);
    let n = r.pooled_buffers();
    assert!(n >= 8, "{n} pooled buffers");
    let a2 = image(&mut r, &night);
    assert_eq!(r.pooled_buffers(), n, "a repeated frame allocated buffers");
    assert_eq!(a, a2, "a repeated frame differs");

    // Noon after the night, against noon from a renderer that never drew
    // the night: the smaller point lists, the absent Moon and Milky Way
    // leave no trace.
    let b = image(&mut r, &noon);
    // (noon adds at most its dummy Milky Way map's slot)
    let n_both = r.pooled_buffers();
    assert!(n_both <= n + 1, "{n_both} after noon, {n} after the night");
    let mut fresh = WgpuRenderer::new(None).unwrap();
    assert_eq!(b, image(&mut fresh, &noon), "noon after a night differs");
    // And the night after noon is the night again.
    assert_eq!(image(&mut r, &night), a, "night after noon differs");
    assert_eq!(
        r.pooled_buffers(),
        n_both,
        "no new slot for scenes seen before"
    );
}
