//! Cloud shadows: the transmittance of the cloud layers along the Sun's
//! or the Moon's direction from a point on or near the ground.
//!
//! Two receivers use it:
//!
//! - **the ground below the horizon of a sky render.** Its luminance is
//!   albedo/π × (E_direct sin h + E_sky) for each light
//!   ([`crate::atmosphere::SkyView::ground_direct`]); the clouds pass
//!   replaces the direct part by its shadowed value,
//!   `L' = L − L_direct (1 − T)`, with T the transmittance of both layers
//!   from the ground point that the view ray meets towards the light
//!   ([`CloudFrame::shade_ground`]). An observer on the ground sees every
//!   ground pixel at its own feet (the sky model's ground has no extent),
//!   so the whole ground takes the shadow over the observer; from a
//!   height the shadows fall where the view rays meet the ground sphere.
//!   The diffuse part (the clear sky's E_sky) is left as it is: the light
//!   of a cloudy sky's dome on the ground is not modelled (an
//!   approximation, stated in the README).
//! - **a 3D world's surfaces** (`spec/world.md`): a map of the
//!   transmittance over the world's footprint on the ground plane
//!   ([`CloudFrame::shadow_map`]), looked up by the lighting pass where a
//!   surface point's ray towards the light crosses y = 0. The clouds lie
//!   hundreds of metres above any world, so the transmittance along that
//!   ray is the same from the surface point and from its foot.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::clouds::CloudFrame;
use crate::clouds::optical_depth_ray;

/// A square map of the cloud layers' transmittance towards the lights,
/// over a square of the world's ground plane (world frame: x East, z
/// South, metres; `spec/world.md`).
#[derive(Debug, Clone, PartialEq)]
pub struct CloudShadowMap {
    /// World x and z of the square's corner (least x, least z), m.
    pub origin_m: [f32; 2],
    /// The square's side, m.
    pub size_m: f32,
    /// Texels per side.
    pub n: usize,
    /// Row-major (z rows, x columns) texel centres' transmittance towards
    /// each light of [`CloudFrame::shadow_map`]'s `lights`, in its order.
    pub texels: Vec<[f32; 2]>,
}

impl CloudFrame {
    /// The transmittance of both layers from `pos` (planet-centred km,
    /// the observer on the z axis) along the unit ENU direction `dir`.
    pub fn transmittance_towards(&self, pos: Vec3, dir: Vec3) -> f32 {
        let mut tau = 0.0;
        if let Some(f) = &self.low {
            tau += optical_depth_ray(f, &self.shell, pos, dir, self.march.steps);
        }
        if let Some(f) = &self.high {
            // The sheet's vertical optical depth where the ray crosses it,
            // over the cosine of the crossing (as the high layer's view).
            let r_layer = self.shell.r_ground + f.altitude_km;
            let r = pos.length();
            let mu = pos.dot(dir) / r;
            let disc = r * r * (mu * mu - 1.0) + r_layer * r_layer;
            if r < r_layer && disc >= 0.0 {
                let t = -r * mu + disc.sqrt();
                let p = pos + dir * t;
                let mu_l = dir.dot(p / p.length()).max(1e-3);
                tau += f.optical_depth(Vec2::new(p.x, p.y)) / mu_l;
            }
        }
        (-tau).exp()
    }

    /// The ground point (planet-centred km) seen along `view` (unit ENU,
    /// below the horizon): where the ray meets the ground sphere, or, for
    /// a ray that passes above it (an elevated observer's view between the
    /// horizontal and the dip of the horizon), the horizon's point in the
    /// view's azimuth. An observer less than a metre above the ground sees
    /// its own place.
    pub fn ground_point(&self, view: Vec3) -> Vec3 {
        let (r, rg) = (self.shell.r_observer, self.shell.r_ground);
        let eye = Vec3::new(0.0, 0.0, r);
        if r - rg < 1e-3 {
            return eye;
        }
        let mu = view.z;
        let disc = r * r * (mu * mu - 1.0) + rg * rg;
        if disc >= 0.0 && mu < 0.0 {
            return eye + view * (-r * mu - disc.sqrt());
        }
        // The tangent ray: depressed by the dip, cos(dip) = rg / r.
        let h = Vec3::new(view.x, view.y, 0.0).normalize_or(Vec3::X);
        let cos_dip = rg / r;
        let tangent = h * cos_dip - Vec3::Z * (1.0 - cos_dip * cos_dip).max(0.0).sqrt();
        eye + tangent * (r * r - rg * rg).max(0.0).sqrt()
    }

    /// `px` (a ground pixel's radiance, cd/m², seen along `view` below
    /// the horizon) with each light's direct part shadowed by the clouds
    /// between the ground point and the light (none above the horizon,
    /// or without the atmosphere pass, which alone draws the ground). An
    /// elevated observer's rays between the horizontal and the dip of the
    /// horizon, which meet no ground short of the horizon hundreds of
    /// kilometres away (beyond the layer's longest march,
    /// [`crate::clouds::march::MAX_MARCH_KM`]), are left unshadowed.
    pub fn shade_ground(&self, view: Vec3, px: [f32; 3]) -> [f32; 3] {
        if view.z >= 0.0 || self.ground_direct.is_empty() {
            return px;
        }
        let (r, rg) = (self.shell.r_observer, self.shell.r_ground);
        let flat = r - rg < 1e-3;
        if !flat && r * r * (view.z * view.z - 1.0) + rg * rg < 0.0 {
            return px;
        }
        let p = self.ground_point(view);
        let mut out = px;
        for (k, g) in self.ground_direct.iter().enumerate() {
            let t = match self.ground_at_observer.get(k) {
                Some(&t) if flat => t,
                _ => self.transmittance_towards(p, g.dir),
            };
            for c in 0..3 {
                out[c] = (out[c] - g.rgb[c] * (1.0 - t)).max(0.0);
            }
        }
        out
    }

    /// The layers' transmittance towards `lights` (at most two unit
    /// directions in the world frame, towards the light) over the square
    /// of side `size_m` with least corner `origin_m` (world x, z) on the
    /// ground plane, `n` × `n` texels (a light not above the horizon gets
    /// 0: it lights nothing).
    pub fn shadow_map(
        &self,
        lights: &[Vec3],
        origin_m: [f32; 2],
        size_m: f32,
        n: usize,
    ) -> CloudShadowMap {
        let n = n.max(1);
        let texel = size_m / n as f32;
        // World (x, y, z) = (East, Up, South): ENU (x, −z, y).
        let enu: Vec<Vec3> = lights
            .iter()
            .take(2)
            .map(|l| Vec3::new(l.x, -l.z, l.y).normalize_or_zero())
            .collect();
        let texels = (0..n * n)
            .into_par_iter()
            .map(|i| {
                let x = origin_m[0] + ((i % n) as f32 + 0.5) * texel;
                let z = origin_m[1] + ((i / n) as f32 + 0.5) * texel;
                let pos = Vec3::new(x * 1e-3, -z * 1e-3, self.shell.r_observer);
                let mut t = [0.0f32; 2];
                for (k, d) in enu.iter().enumerate() {
                    if d.z > 0.0 {
                        t[k] = self.transmittance_towards(pos, *d);
                    }
                }
                t
            })
            .collect();
        CloudShadowMap {
            origin_m,
            size_m,
            n,
            texels,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clouds::optical_depth_low;
    use crate::scene::{Effect, Scene};
    use crate::state::SkyState;

    fn frame(coverage: f64, elevation_m: f64) -> CloudFrame {
        let mut s = Scene::default();
        s.time.utc = "2024-06-21T11:00:00Z".into();
        s.observer.elevation_m = elevation_m;
        s.effects = vec![Effect::Clouds];
        s.clouds.low.coverage = coverage;
        let state = SkyState::at(&s).expect("state");
        CloudFrame::prepare(&s, &state, None, None, None, &mut Default::default())
    }

    /// From the observer, the transmittance towards a direction is the
    /// view march's e^{−τ} through the low layer (the direct Sun's).
    #[test]
    fn transmittance_from_the_observer_is_the_view_rays() {
        let f = frame(0.6, 0.0);
        let low = f.low.as_ref().expect("low layer");
        let eye = Vec3::new(0.0, 0.0, f.shell.r_observer);
        for i in 0..20 {
            let a = i as f32 * 0.31;
            let d = Vec3::new(a.cos() * 0.5, a.sin() * 0.5, 0.8).normalize();
            let want = (-optical_depth_low(low, &f.shell, d, f.march.steps)).exp();
            let got = f.transmittance_towards(eye, d);
            assert!((got - want).abs() < 1e-6, "{got} {want}");
        }
    }

    /// A light below the horizon leaves the map dark; a clear sky leaves
    /// it at 1; a cloudy sky casts shadows of every depth between.
    #[test]
    fn the_map_spans_sun_and_shadow() {
        let f = frame(0.5, 0.0);
        let sun = Vec3::new(0.3, 0.8, -0.5).normalize();
        let below = Vec3::new(0.3, -0.2, 0.5).normalize();
        let m = f.shadow_map(&[sun, below], [-2000.0, -2000.0], 4000.0, 24);
        assert_eq!(m.texels.len(), 24 * 24);
        assert!(m.texels.iter().all(|t| t[1] == 0.0));
        let (lo, hi) = m
            .texels
            .iter()
            .fold((1f32, 0f32), |(a, b), t| (a.min(t[0]), b.max(t[0])));
        assert!(lo < 0.1 && hi > 0.9, "{lo} {hi}");
        let clear = frame(0.0, 0.0).shadow_map(&[sun], [0.0, 0.0], 100.0, 4);
        assert!(clear.texels.iter().all(|t| t[0] == 1.0));
    }

    /// The map's texel is the transmittance from its centre, the world's
    /// South (+z) being the ENU −y.
    #[test]
    fn the_map_follows_the_world_frame() {
        let f = frame(0.6, 0.0);
        let sun_world = Vec3::new(0.2, 0.9, 0.3).normalize();
        let m = f.shadow_map(&[sun_world], [100.0, 300.0], 800.0, 8);
        let (i, j) = (5usize, 2usize);
        let (x, z) = (100.0 + 550.0, 300.0 + 250.0);
        let pos = Vec3::new(x * 1e-3, -z * 1e-3, f.shell.r_observer);
        let enu = Vec3::new(sun_world.x, -sun_world.z, sun_world.y);
        let want = f.transmittance_towards(pos, enu);
        assert!((m.texels[j * 8 + i][0] - want).abs() < 1e-6);
    }

    /// From a height, a ground pixel's point lies on the ground sphere
    /// along the view ray; on the ground, at the observer's feet.
    #[test]
    fn ground_points() {
        let f = frame(0.5, 2000.0);
        let v = Vec3::new(0.6, 0.0, -0.8);
        let p = f.ground_point(v);
        assert!((p.length() - f.shell.r_ground).abs() < 1e-3, "{p}");
        // 2 km at 53° below the horizontal: about 2.5 km away.
        assert!((p.x - 1.5).abs() < 0.01, "{p}");
        // Just below the horizontal the ray passes over the ground: the
        // horizon, √(2 R h) ≈ 159.5 km away.
        let g = f.ground_point(Vec3::new(1.0, 0.0, -1e-4).normalize());
        assert!((g.length() - f.shell.r_ground).abs() < 1e-2, "{g}");
        assert!((g.x - 159.5).abs() < 0.5 && g.y.abs() < 1e-3, "{g}");
        let flat = frame(0.5, 0.0);
        assert_eq!(
            flat.ground_point(v),
            Vec3::new(0.0, 0.0, flat.shell.r_observer)
        );
    }
}
