//! Where the chart overlay goes: the constellation figures as polylines in
//! image pixels, and the labels' anchors ([`crate::overlay_spec`] is the
//! scene key; the output stage draws them into the 8-bit image).
//!
//! **Positions.** The figures' vertices are stars (d3-celestial's
//! `constellations.lines.json`, J2000). Each vertex is matched once per
//! process to the catalogue star at that place (within
//! [`VERTEX_MATCH_DEG`]) and then follows exactly the stars pass's path:
//! the fast-path star ([`crate::stars::CatalogueStar::fast`]: space motion,
//! aberration, precession–nutation, sidereal time) through the frame's
//! [`himmel_astro::stars::FrameRotation`], then standard refraction ([`refracted`]), then
//! [`Camera::dir_to_pixel`]. A line therefore ends where the stars pass
//! centres the star's PSF. A vertex with no catalogue star (none in the
//! embedded figures at V ≤ 6.5, but the data may change) keeps its J2000
//! place without space motion. Constellation names sit at the normalised
//! mean direction of their figure's vertices; star names at the named
//! stars brighter than `star_names_max_mag`; planet names at the planets
//! the scene renders ([`crate::night::NightSky::planets`]).
//!
//! **Lines follow the projection.** A figure's edge is a great circle
//! between two stars in the airless frame; it is sampled every
//! [`Tracer::step`] (at most 0.5°, finer for small pixels), each sample
//! refracted and projected, so that edges curve as the fisheye, equirect
//! and cube-map projections bend them. An edge is cut where its samples
//! stop being continuous in the image: below the refracted horizon (the
//! ground hides the stars there), behind a perspective camera, across the
//! equirect ±180° seam (North) and across cube-map faces; each cut is
//! found by bisection to 10⁻⁶ of a sample step, so a line stops at the
//! horizon or the seam, not a sample before it. Lines leaving the image
//! are kept (the drawing clips them); labels whose anchor is outside the
//! image are dropped.

use glam::DVec3;
use himmel_astro::stars::FastStar;
use himmel_catalog::constellations::constellation_name;
use himmel_catalog::figures::constellation_figures;
use himmel_catalog::{Catalog, CatalogError};

use crate::projection::{Camera, Projection};
use crate::refraction::refracted;
use crate::scene::Scene;
use crate::stars::catalogue;
use crate::state::SkyState;

/// Largest angle between a figure vertex and the catalogue star it is
/// matched to, degrees (d3-celestial's vertices are its stars' J2000
/// places to 10⁻⁴°).
pub const VERTEX_MATCH_DEG: f64 = 0.02;

/// The names of the planets by [`crate::stars::PointSource::id`] (1–5).
const PLANET_NAMES: [&str; 5] = ["Mercury", "Venus", "Mars", "Jupiter", "Saturn"];

/// What a label names (the drawing places each kind differently).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LabelKind {
    /// A constellation: centred on its anchor.
    Constellation,
    /// A star: beside it.
    Star,
    /// A planet: beside it.
    Planet,
}

/// A label: its text and anchor (continuous image position, px).
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    /// The name.
    pub text: String,
    /// The anchor: the constellation's centre, or the star or planet.
    pub pos: [f64; 2],
    /// What it names.
    pub kind: LabelKind,
}

/// The overlay of one frame in image pixels.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OverlayGeometry {
    /// Polylines (continuous image positions, px); each is continuous in
    /// the image and may leave it.
    pub lines: Vec<Vec<[f64; 2]>>,
    /// The figures' shown vertices (their stars, where lines end), px.
    pub vertices: Vec<[f64; 2]>,
    /// Labels whose anchors lie inside the image.
    pub labels: Vec<Label>,
}

/// A constellation figure resolved to fast-path stars.
struct Figure {
    name: &'static str,
    lines: Vec<Vec<FastStar>>,
    /// Mean ICRS direction of its vertices (unit).
    centre: DVec3,
}

/// A fixed ICRS direction as a fast-path "star" without space motion.
fn fixed(u: DVec3) -> FastStar {
    FastStar { u, w: DVec3::ZERO }
}

/// The figures with each vertex matched to its catalogue star (once per
/// process).
fn figures() -> Result<&'static [Figure], CatalogError> {
    static CELL: std::sync::OnceLock<Result<Vec<Figure>, CatalogError>> =
        std::sync::OnceLock::new();
    CELL.get_or_init(|| {
        let stars = catalogue(6.5);
        let cos_match = VERTEX_MATCH_DEG.to_radians().cos();
        let resolve = |v: DVec3| {
            stars
                .iter()
                .map(|s| (s.fast.u.dot(v), s))
                .filter(|(c, _)| *c >= cos_match)
                .max_by(|a, b| a.0.total_cmp(&b.0))
                .map_or(fixed(v), |(_, s)| s.fast)
        };
        let figs = constellation_figures()?;
        Ok(figs
            .iter()
            .map(|f| {
                let lines: Vec<Vec<FastStar>> = f
                    .lines
                    .iter()
                    .map(|l| l.unit_vectors().into_iter().map(resolve).collect())
                    .collect();
                let sum: DVec3 = lines.iter().flatten().map(|s| s.u).sum();
                Figure {
                    name: constellation_name(&f.abbreviation).unwrap_or("?"),
                    lines,
                    centre: sum.normalize_or_zero(),
                }
            })
            .collect())
    })
    .as_ref()
    .map(Vec::as_slice)
    .map_err(Clone::clone)
}

impl OverlayGeometry {
    /// The overlay of `scene.overlay` for the frame of `state` (empty when
    /// the scene asks for none).
    pub fn build(scene: &Scene, state: &SkyState) -> Result<OverlayGeometry, CatalogError> {
        let spec = &scene.overlay;
        let cam = &scene.camera;
        let frame = &state.night.star_frame;
        let mut out = OverlayGeometry::default();
        if spec.constellations {
            let mut tracer = Tracer::new(cam);
            for f in figures()? {
                for line in &f.lines {
                    for pair in line.windows(2) {
                        tracer.edge(frame.enu(&pair[0]), frame.enu(&pair[1]));
                    }
                    tracer.finish_line();
                    let shown = line.iter().filter_map(|v| tracer.land(frame.enu(v)));
                    out.vertices.extend(shown.map(|l| l.px));
                }
            }
            out.lines = tracer.lines;
        }
        if spec.labels {
            let (w, h) = cam.image_size();
            let mut label = |text: &str, dir: DVec3, kind| {
                let shown = dir.z >= 0.0;
                if let Some((x, y)) = cam.dir_to_pixel(dir).filter(|_| shown) {
                    if (0.0..w as f64).contains(&x) && (0.0..h as f64).contains(&y) {
                        out.labels.push(Label {
                            text: text.into(),
                            pos: [x, y],
                            kind,
                        });
                    }
                }
            };
            for f in figures()? {
                label(
                    f.name,
                    refracted(frame.enu(&fixed(f.centre))),
                    LabelKind::Constellation,
                );
            }
            let cat = Catalog::embedded()?;
            for (s, c) in cat.stars().iter().zip(catalogue(6.5)) {
                if s.vmag > spec.star_names_max_mag {
                    break;
                }
                if let (Some(name), true) = (&s.name, s.hip == c.hip) {
                    label(name, refracted(frame.enu(&c.fast)), LabelKind::Star);
                }
            }
            for p in &state.night.planets {
                let name = PLANET_NAMES.get((p.id as usize).wrapping_sub(1));
                if let Some(name) = name {
                    label(name, p.dir.as_dvec3(), LabelKind::Planet);
                }
            }
        }
        Ok(out)
    }
}

/// Projects great-circle edges into continuous image polylines (see the
/// module documentation).
struct Tracer<'a> {
    cam: &'a Camera,
    /// Image width, px (the equirect seam test).
    width: f64,
    /// Farthest a kept point may lie from the image, px (a perspective
    /// camera sends directions near 90° off its axis towards infinity).
    reach: f64,
    /// Largest angle between samples, radians.
    step: f64,
    lines: Vec<Vec<[f64; 2]>>,
    current: Vec<[f64; 2]>,
}

/// Where a sample lands: its pixel and the part of the image it is in
/// (the cube map's face; 0 elsewhere).
#[derive(Debug, Clone, Copy)]
struct Landing {
    px: [f64; 2],
    chart: i64,
}

impl<'a> Tracer<'a> {
    fn new(cam: &'a Camera) -> Self {
        let (w, h) = cam.image_size();
        Tracer {
            cam,
            width: w as f64,
            reach: 50.0 * (w as f64 + h as f64),
            step: (0.5f64.to_radians()).min(2.0 * cam.max_pixel_angle()),
            lines: Vec::new(),
            current: Vec::new(),
        }
    }

    /// The landing of the airless ENU direction `d`, or `None` where the
    /// image does not show it (below the refracted horizon, behind the
    /// camera, too far outside).
    fn land(&self, d: DVec3) -> Option<Landing> {
        let r = refracted(d);
        if r.z < 0.0 {
            return None;
        }
        let (x, y) = self.cam.dir_to_pixel(r)?;
        if !(x.abs() < self.reach && y.abs() < self.reach) {
            return None;
        }
        let chart = match self.cam.projection {
            Projection::Cubemap => (x / self.cam.height.max(1) as f64).floor() as i64,
            _ => 0,
        };
        Some(Landing { px: [x, y], chart })
    }

    /// Whether a line may join `a` to `b` directly.
    fn joins(&self, a: &Landing, b: &Landing) -> bool {
        a.chart == b.chart
            && (self.cam.projection != Projection::Equirect
                || (a.px[0] - b.px[0]).abs() < self.width / 2.0)
    }

    fn finish_line(&mut self) {
        if self.current.len() >= 2 {
            self.lines.push(std::mem::take(&mut self.current));
        } else {
            self.current.clear();
        }
    }

    fn push(&mut self, p: [f64; 2]) {
        if self.current.last() != Some(&p) {
            self.current.push(p);
        }
    }

    /// The last point between `a` (t = 0) and `b` (t = 1) on the great
    /// circle that still joins `from` (the landing at `a`), by bisection.
    fn last_joining(&self, a: DVec3, b: DVec3, from: &Landing) -> Landing {
        let (mut lo, mut hi) = (0.0, 1.0);
        let mut best = *from;
        for _ in 0..20 {
            let mid = 0.5 * (lo + hi);
            match self.land(slerp(a, b, mid)).filter(|l| self.joins(from, l)) {
                Some(l) => {
                    best = l;
                    lo = mid;
                }
                None => hi = mid,
            }
        }
        best
    }

    /// Adds the edge between the airless ENU directions `a` and `b`.
    fn edge(&mut self, a: DVec3, b: DVec3) {
        let angle = a.dot(b).clamp(-1.0, 1.0).acos();
        let n = ((angle / self.step).ceil() as usize).clamp(1, 100_000);
        let mut prev = (a, self.land(a));
        if let Some(l) = prev.1 {
            if self.current.last() != Some(&l.px) {
                self.finish_line();
            }
            self.push(l.px);
        } else {
            self.finish_line();
        }
        for i in 1..=n {
            let d = slerp(a, b, i as f64 / n as f64);
            let here = self.land(d);
            match (prev.1, here) {
                (Some(p), Some(h)) if self.joins(&p, &h) => self.push(h.px),
                (p, h) => {
                    if let Some(p) = p {
                        let end = self.last_joining(prev.0, d, &p);
                        self.push(end.px);
                    }
                    self.finish_line();
                    if let Some(h) = h {
                        let start = self.last_joining(d, prev.0, &h);
                        self.push(start.px);
                        self.push(h.px);
                    }
                }
            }
            prev = (d, here);
        }
    }
}

/// The point a fraction `t` of the way from unit vector `a` to `b` along
/// their great circle.
fn slerp(a: DVec3, b: DVec3, t: f64) -> DVec3 {
    let angle = a.dot(b).clamp(-1.0, 1.0).acos();
    if angle < 1e-12 {
        return a;
    }
    let s = angle.sin();
    (a * ((1.0 - t) * angle).sin() / s + b * (t * angle).sin() / s).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn orion_scene(projection: Projection) -> (Scene, SkyState) {
        let mut s = Scene::default();
        s.time.utc = "2024-01-15T21:00:00Z".into();
        s.camera.projection = projection;
        s.camera.width = 256;
        s.camera.height = if projection == Projection::Equirect {
            128
        } else {
            256
        };
        s.camera.yaw_deg = 180.0;
        s.camera.pitch_deg = 30.0;
        s.camera.fov_deg = 60.0;
        s.overlay.constellations = true;
        s.overlay.labels = true;
        let state = SkyState::at(&s).unwrap();
        (s, state)
    }

    /// Every figure vertex found its catalogue star.
    #[test]
    fn every_vertex_is_a_catalogue_star() {
        let figs = figures().unwrap();
        assert_eq!(figs.len(), 89);
        let stars = catalogue(6.5);
        let n = figs.iter().flat_map(|f| f.lines.iter().flatten()).count();
        let matched = figs
            .iter()
            .flat_map(|f| f.lines.iter().flatten())
            .filter(|v| stars.iter().any(|s| s.fast == **v))
            .count();
        assert!(n > 600, "{n} vertices");
        assert_eq!(matched, n);
    }

    /// In every projection: each polyline point lies on the visible sky
    /// (its pixel maps back to a direction at or above the horizon, within
    /// a pixel's angle), no step of a polyline jumps across the equirect
    /// seam or a cube face, and the named stars of Orion are labelled.
    #[test]
    fn lines_stay_on_the_visible_sky_in_every_projection() {
        for p in [
            Projection::Fisheye,
            Projection::Equirect,
            Projection::Perspective,
            Projection::Cubemap,
        ] {
            let (s, state) = orion_scene(p);
            let g = OverlayGeometry::build(&s, &state).unwrap();
            let cam = &s.camera;
            let (w, h) = cam.image_size();
            assert!(g.lines.len() > 10, "{p:?}: {} lines", g.lines.len());
            let tol = cam.max_pixel_angle();
            let mut inside = 0;
            for line in &g.lines {
                for q in line.windows(2) {
                    if p == Projection::Equirect {
                        let dx = (q[1][0] - q[0][0]).abs();
                        assert!(dx < w as f64 / 2.0, "a step of {dx} px across the seam");
                    }
                    if p == Projection::Cubemap {
                        let face = |x: f64| (x / h as f64).floor().clamp(0.0, 5.0);
                        let (fa, fb) = (face(q[0][0]), face(q[1][0]));
                        let on_edge = |x: f64| (x / h as f64 - (x / h as f64).round()).abs() < 1e-3;
                        assert!(fa == fb || on_edge(q[0][0]) || on_edge(q[1][0]), "{q:?}");
                    }
                }
                for pt in line {
                    let in_img =
                        (0.0..w as f64).contains(&pt[0]) && (0.0..h as f64).contains(&pt[1]);
                    if in_img {
                        inside += 1;
                        let d = cam.pixel_to_dir(pt[0], pt[1]).unwrap();
                        assert!(d.z > -tol, "{p:?}: a point below the horizon {d}");
                    }
                }
            }
            assert!(inside > 100, "{p:?}: {inside} points in the image");
            let names: Vec<&str> = g.labels.iter().map(|l| l.text.as_str()).collect();
            for want in ["Orion", "Betelgeuse", "Rigel", "Jupiter"] {
                if p == Projection::Perspective && want == "Jupiter" {
                    continue; // Jupiter stands in the south-west, outside the 60° view
                }
                assert!(
                    names.contains(&want),
                    "{p:?}: {want} missing from {names:?}"
                );
            }
        }
    }

    /// A long edge curves in the fisheye: its samples leave the straight
    /// chord between its ends (a great circle away from the zenith is no
    /// straight line in an azimuthal equidistant projection).
    #[test]
    fn long_edges_curve_in_the_fisheye() {
        let (s, _) = orion_scene(Projection::Fisheye);
        let mut t = Tracer::new(&s.camera);
        // Two points 40° apart at 20° altitude, due East and due South.
        let a = crate::projection::enu_from_alt_az(0.35, 1.6);
        let b = crate::projection::enu_from_alt_az(0.35, 2.3);
        t.edge(a, b);
        t.finish_line();
        assert_eq!(t.lines.len(), 1);
        let l = &t.lines[0];
        let (p, q) = (l[0], l[l.len() - 1]);
        let off = l
            .iter()
            .map(|m| {
                let (ux, uy) = (q[0] - p[0], q[1] - p[1]);
                ((m[0] - p[0]) * uy - (m[1] - p[1]) * ux).abs() / ux.hypot(uy)
            })
            .fold(0.0, f64::max);
        assert!(off > 2.0, "the line stays within {off} px of its chord");
    }

    /// An edge that dips below the horizon stops at it: its last point
    /// lies within a thousandth of a degree of the refracted horizon.
    #[test]
    fn edges_stop_at_the_horizon() {
        let (s, _) = orion_scene(Projection::Equirect);
        let mut t = Tracer::new(&s.camera);
        let a = crate::projection::enu_from_alt_az(0.1, 3.0);
        let b = crate::projection::enu_from_alt_az(-0.1, 3.0);
        t.edge(a, b);
        t.finish_line();
        let l = &t.lines[0];
        let end = l[l.len() - 1];
        let d = s.camera.pixel_to_dir(end[0], end[1]).unwrap();
        assert!(
            d.z.abs() < 2e-5,
            "ends at altitude {}°",
            d.z.asin().to_degrees()
        );
    }

    #[test]
    fn nothing_is_built_when_off() {
        let (mut s, state) = orion_scene(Projection::Fisheye);
        s.overlay.constellations = false;
        s.overlay.labels = false;
        assert_eq!(
            OverlayGeometry::build(&s, &state).unwrap(),
            OverlayGeometry::default()
        );
    }
}
