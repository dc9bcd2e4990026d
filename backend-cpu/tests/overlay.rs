//! The chart overlay against the rendered stars: the figure lines that end
//! on Betelgeuse and Rigel end within 1 px of the stars' centroids in the
//! image the stars pass rendered (fisheye and perspective), and the drawn
//! overlay covers that pixel.

use himmel_cpu::CpuRenderer;
use himmel_skymodel::atmosphere::LutConfig;
use himmel_skymodel::overlay::OverlayGeometry;
use himmel_skymodel::renderer::HdrImage;
use himmel_skymodel::spectrum::luminance;
use himmel_skymodel::{Effect, Exposure, Projection, Scene, SkyRenderer, SkyState};

/// Munich, 15 January 2024, 22:00 CET: Orion near the meridian.
fn scene(p: Projection) -> Scene {
    let mut s = Scene::default();
    s.time.utc = "2024-01-15T21:00:00Z".into();
    s.effects = vec![Effect::Stars];
    s.camera.projection = p;
    s.camera.width = 320;
    s.camera.height = 320;
    s.camera.yaw_deg = 180.0;
    s.camera.pitch_deg = 40.0;
    s.camera.fov_deg = 50.0;
    s.exposure = Exposure::Ev100(-6.0);
    // All of a star's flux in its core: the centroid is the PSF's centre.
    s.stars.glare = 0.0;
    s.lut = LutConfig::small();
    s.overlay.constellations = true;
    s
}

/// Luminance-weighted centroid (continuous px) of the 7 × 7 window around
/// the brightest pixel within 4 px of `near`.
fn centroid(img: &HdrImage, near: [f64; 2]) -> [f64; 2] {
    let (w, h) = (img.width as i64, img.height as i64);
    let y_at = |x: i64, y: i64| -> f64 {
        if x < 0 || y < 0 || x >= w || y >= h {
            return 0.0;
        }
        luminance(img.pixels[(y * w + x) as usize]) as f64
    };
    let (nx, ny) = (near[0].floor() as i64, near[1].floor() as i64);
    let mut peak = (nx, ny);
    for y in ny - 4..=ny + 4 {
        for x in nx - 4..=nx + 4 {
            if y_at(x, y) > y_at(peak.0, peak.1) {
                peak = (x, y);
            }
        }
    }
    let (mut sx, mut sy, mut s) = (0.0, 0.0, 0.0);
    for y in peak.1 - 3..=peak.1 + 3 {
        for x in peak.0 - 3..=peak.0 + 3 {
            let l = y_at(x, y);
            sx += l * (x as f64 + 0.5);
            sy += l * (y as f64 + 0.5);
            s += l;
        }
    }
    assert!(s > 0.0, "no star near {near:?}");
    [sx / s, sy / s]
}

#[test]
fn figure_lines_end_on_the_rendered_stars() {
    let cat = himmel_catalog::Catalog::embedded().unwrap();
    for p in [Projection::Fisheye, Projection::Perspective] {
        let s = scene(p);
        let state = SkyState::at(&s).unwrap();
        let out = CpuRenderer::new(None).render(&s, &state).unwrap();
        let g = OverlayGeometry::build(&s, &state).unwrap();
        let (w, h) = (out.image.width, out.image.height);
        let mut canvas = vec![0u8; w * h * 3];
        himmel_cpu::overlay::draw(&mut canvas, w, h, &g, &s.overlay).unwrap();
        for name in ["Betelgeuse", "Rigel"] {
            let star = cat.by_name(name).unwrap();
            // Where the stars pass put it: the exact reduction's place is
            // not needed, only the rendered star's centroid.
            let approx = state
                .night
                .star_frame
                .enu(&himmel_astro::stars::FastStar::new(
                    &star.astrometry,
                    himmel_astro::units::J2000,
                ));
            let (ax, ay) = s
                .camera
                .dir_to_pixel(himmel_skymodel::refraction::refracted(approx))
                .unwrap();
            let c = centroid(&out.image, [ax, ay]);
            let (d, v) = g
                .vertices
                .iter()
                .map(|v| ((v[0] - c[0]).hypot(v[1] - c[1]), *v))
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .unwrap();
            println!(
                "{p:?} {name}: centroid ({:.3}, {:.3}), line end ({:.3}, {:.3}): {d:.3} px",
                c[0], c[1], v[0], v[1]
            );
            assert!(d <= 1.0, "{p:?} {name}: the lines end {d} px from the star");
            // A line reaches that vertex, and the drawn overlay covers it.
            assert!(g.lines.iter().flatten().any(|q| q == &v));
            let (vx, vy) = (v[0] as usize, v[1] as usize);
            let drawn = (vy - 1..=vy + 1)
                .flat_map(|y| (vx - 1..=vx + 1).map(move |x| (x, y)))
                .map(|(x, y)| canvas[(y * w + x) * 3 + 2])
                .max();
            assert!(
                drawn > Some(128),
                "{p:?} {name}: the overlay is not drawn at its end ({drawn:?})"
            );
        }
    }
}
