//! The geometry of a world frame: the camera's view and projection (the
//! sky's own perspective camera, so that the world and the sky line up
//! pixel for pixel), and the orthographic light views of the shadow maps —
//! the Sun's and Moon's cascades over the view, snapped to their texels,
//! and the fixed views over the world from which the sky's visibility is
//! sampled.

use glam::{DVec3, Mat4, Vec2, Vec3, Vec4};
use himmel_skymodel::projection::scene_from_enu;
use himmel_skymodel::Camera;
use himmel_world::Aabb;

/// Near plane of the camera, metres (reversed-Z with an infinite far plane
/// keeps depth precision at any distance).
pub const NEAR_M: f32 = 0.05;

/// The camera in the world frame (x East, y Up, z South, metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldCamera {
    /// Eye position.
    pub eye: Vec3,
    /// Unit forward, right and up vectors (world frame), the sky camera's
    /// basis ([`Camera::basis`]).
    pub forward: Vec3,
    /// See `forward`.
    pub right: Vec3,
    /// See `forward`.
    pub up: Vec3,
    /// tan(vertical fov / 2).
    pub tan_half: f32,
    /// Image width / height.
    pub aspect: f32,
    /// Image size, px.
    pub width: u32,
    /// See `width`.
    pub height: u32,
    /// The sub-pixel offset of this frame's image (px, x right, y down):
    /// a point whose centred projection is P is drawn at P + jitter
    /// (`temporal.rs`; zero without the temporal pass).
    pub jitter: Vec2,
    /// The frame's index in the temporal pass's run of frames, modulo
    /// `temporal::NOISE_PERIOD` (0 without it): the noisy passes turn their
    /// per-pixel noise with it.
    pub frame: u32,
}

/// The camera as the compute passes' uniforms begin (`ao.wgsl`,
/// `ssr.wgsl`, `temporal.wgsl`: eye, forward, right, up, each a vec4):
/// `eye.w` tan ½ fov, `forward.w` the aspect, `right.w` and `up.w` the
/// image's width and height in pixels.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CameraBlock {
    eye: [f32; 4],
    forward: [f32; 4],
    right: [f32; 4],
    up: [f32; 4],
}

impl CameraBlock {
    /// Its members as `uniforms::tests::fields!` lists them (name, offset,
    /// type), for the layout checks of the uniforms that begin with it.
    #[cfg(test)]
    pub fn layout() -> Vec<(&'static str, usize, &'static str)> {
        crate::uniforms::tests::fields!(CameraBlock, [eye, forward, right, up])
    }
}

impl WorldCamera {
    /// The uniforms' camera block.
    pub fn block(&self) -> CameraBlock {
        let v4 = |v: Vec3, w: f32| [v.x, v.y, v.z, w];
        CameraBlock {
            eye: v4(self.eye, self.tan_half),
            forward: v4(self.forward, self.aspect),
            right: v4(self.right, self.width as f32),
            up: v4(self.up, self.height as f32),
        }
    }

    /// The world camera of the scene's perspective camera.
    pub fn new(cam: &Camera) -> WorldCamera {
        let (f, r, u) = cam.basis();
        let w = |v: DVec3| scene_from_enu(v).as_vec3().normalize();
        let (width, height) = cam.image_size();
        WorldCamera {
            eye: cam.eye_m().as_vec3(),
            forward: w(f),
            right: w(r),
            up: w(u),
            tan_half: (cam.fov_deg.to_radians() / 2.0).tan() as f32,
            aspect: width as f32 / height as f32,
            width,
            height,
            jitter: Vec2::ZERO,
            frame: 0,
        }
    }

    /// The same camera without the jitter.
    pub fn unjittered(&self) -> WorldCamera {
        WorldCamera {
            jitter: Vec2::ZERO,
            ..*self
        }
    }

    /// World → view matrix (right-handed, looking down −z).
    pub fn view(&self) -> Mat4 {
        let (r, u, b) = (self.right, self.up, -self.forward);
        Mat4::from_cols(
            Vec4::new(r.x, u.x, b.x, 0.0),
            Vec4::new(r.y, u.y, b.y, 0.0),
            Vec4::new(r.z, u.z, b.z, 0.0),
            Vec4::new(-r.dot(self.eye), -u.dot(self.eye), -b.dot(self.eye), 1.0),
        )
    }

    /// View → clip: reversed Z with an infinite far plane (depth =
    /// [`NEAR_M`] / view depth); pixel (px, py) sees the direction
    /// forward + right·nx + up·ny with nx = (px − W/2)/(H/2)·tan, as the
    /// sky's perspective projection; then moved by [`Self::jitter`].
    pub fn projection(&self) -> Mat4 {
        let (sx, sy) = (1.0 / (self.tan_half * self.aspect), 1.0 / self.tan_half);
        // x' = x + t·w in clip space shifts the image by t in NDC (y up).
        let (jx, jy) = (
            2.0 * self.jitter.x / self.width.max(1) as f32,
            -2.0 * self.jitter.y / self.height.max(1) as f32,
        );
        Mat4::from_translation(Vec3::new(jx, jy, 0.0))
            * Mat4::from_cols(
                Vec4::new(sx, 0.0, 0.0, 0.0),
                Vec4::new(0.0, sy, 0.0, 0.0),
                Vec4::new(0.0, 0.0, 0.0, -1.0),
                Vec4::new(0.0, 0.0, NEAR_M, 0.0),
            )
    }

    /// World → clip.
    pub fn view_projection(&self) -> Mat4 {
        self.projection() * self.view()
    }

    /// The eight corners of the view frustum between view depths `near`
    /// and `far` (metres along forward).
    pub fn frustum_corners(&self, near: f32, far: f32) -> [Vec3; 8] {
        let mut out = [Vec3::ZERO; 8];
        for (k, d) in [near, far].into_iter().enumerate() {
            let (h, w) = (d * self.tan_half, d * self.tan_half * self.aspect);
            for (j, (sx, sy)) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .into_iter()
                .enumerate()
            {
                out[k * 4 + j] =
                    self.eye + self.forward * d + self.right * (sx * w) + self.up * (sy * h);
            }
        }
        out
    }
}

/// An orthographic light view: world → light clip space with depth in
/// [0, 1] linear in metres along the light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightView {
    /// World → clip (x, y in [−1, 1] over the map; z in [0, 1]).
    pub matrix: Mat4,
    /// Size of one texel in the world, metres.
    pub texel_m: f32,
    /// Depth range of the map, metres (z = 1 at this distance from z = 0).
    pub depth_m: f32,
    /// The view depth (metres along the camera's forward) up to which this
    /// cascade is used (infinity for visibility maps).
    pub split_m: f32,
}

/// An orthonormal basis (right, up) perpendicular to the unit `dir`.
pub(crate) fn light_basis(dir: Vec3) -> (Vec3, Vec3) {
    let helper = if dir.y.abs() < 0.99 { Vec3::Y } else { Vec3::X };
    let right = helper.cross(dir).normalize();
    (right, dir.cross(right))
}

/// The light view towards unit `dir` (from the surface to the light) with
/// a square of half-side `half` centred on `centre` in the light's plane,
/// covering the depths of `bounds` along the light, with `res` texels a side.
/// The centre is snapped to whole texels in the light's plane, so that a
/// moving camera does not make the shadow edges shimmer.
pub fn ortho_light(dir: Vec3, centre: Vec3, half: f32, bounds: &Aabb, res: u32) -> LightView {
    let (right, up) = light_basis(dir);
    let texel = 2.0 * half / res as f32;
    let snap = |v: f32| (v / texel).round() * texel;
    let (cx, cy) = (snap(centre.dot(right)), snap(centre.dot(up)));
    // Depth along −dir (towards the ground): 0 at the highest caster.
    let corners = aabb_corners(bounds);
    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
    for c in corners {
        let d = -c.dot(dir);
        lo = lo.min(d);
        hi = hi.max(d);
    }
    let (lo, hi) = (lo - 0.5, hi + 0.5);
    let depth = (hi - lo).max(1e-3);
    // Rows: x = (p·right − cx)/half, y = (p·up − cy)/half, z = (−p·dir − lo)/depth.
    let matrix = Mat4::from_cols(
        Vec4::new(right.x / half, up.x / half, -dir.x / depth, 0.0),
        Vec4::new(right.y / half, up.y / half, -dir.y / depth, 0.0),
        Vec4::new(right.z / half, up.z / half, -dir.z / depth, 0.0),
        Vec4::new(-cx / half, -cy / half, -lo / depth, 1.0),
    );
    LightView {
        matrix,
        texel_m: texel,
        depth_m: depth,
        split_m: f32::INFINITY,
    }
}

/// The corners of a box.
pub fn aabb_corners(b: &Aabb) -> [Vec3; 8] {
    let (a, c) = (b.min, b.max);
    [
        Vec3::new(a.x, a.y, a.z),
        Vec3::new(c.x, a.y, a.z),
        Vec3::new(a.x, c.y, a.z),
        Vec3::new(c.x, c.y, a.z),
        Vec3::new(a.x, a.y, c.z),
        Vec3::new(c.x, a.y, c.z),
        Vec3::new(a.x, c.y, c.z),
        Vec3::new(c.x, c.y, c.z),
    ]
}

/// The cascades of a directional light `dir` over the camera's view of a
/// world with caster `bounds`: the view depth up to `max_m` (and no farther
/// than the farthest caster, whose shadow cannot reach farther than the
/// view) split between at most `count` cascades (`lambda` blends uniform
/// and logarithmic splits); each cascade a texel-snapped square around the
/// bounding sphere of its frustum slice, no larger than the world's own
/// extent in the light's plane. Cascades that would cover the whole world
/// anyway are merged into one.
pub fn cascades(
    cam: &WorldCamera,
    dir: Vec3,
    bounds: &Aabb,
    count: u32,
    max_m: f32,
    lambda: f32,
    res: u32,
) -> Vec<LightView> {
    let (right, up) = light_basis(dir);
    let corners = aabb_corners(bounds);
    // The world's extent in the light's plane.
    let (mut x0, mut x1, mut y0, mut y1) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN);
    let mut far = NEAR_M;
    for c in corners {
        x0 = x0.min(c.dot(right));
        x1 = x1.max(c.dot(right));
        y0 = y0.min(c.dot(up));
        y1 = y1.max(c.dot(up));
        far = far.max((c - cam.eye).dot(cam.forward));
    }
    let world_half = 0.5 * (x1 - x0).max(y1 - y0) * 1.01;
    let world_centre = right * (0.5 * (x0 + x1)) + up * (0.5 * (y0 + y1));
    let far = far.min(max_m).max(NEAR_M * 2.0);
    let n = count.max(1);
    let mut out: Vec<LightView> = Vec::new();
    let mut near = NEAR_M;
    for k in 1..=n {
        let t = k as f32 / n as f32;
        let uni = NEAR_M + (far - NEAR_M) * t;
        let log = NEAR_M * (far / NEAR_M).powf(t);
        let split = if k == n {
            far
        } else {
            lambda * log + (1.0 - lambda) * uni
        };
        let pts = cam.frustum_corners(near, split);
        let centre = pts.iter().copied().sum::<Vec3>() / 8.0;
        let radius = pts
            .iter()
            .map(|p| (*p - centre).length())
            .fold(0.0f32, f32::max);
        // Radius quantised to 1/16 of itself keeps the texel size steady as
        // the camera turns.
        let radius = (radius * 16.0).ceil() / 16.0;
        let whole_world = radius >= world_half;
        let (c, half) = if whole_world {
            (world_centre, world_half)
        } else {
            (centre, radius)
        };
        let mut v = ortho_light(dir, c, half, bounds, res);
        v.split_m = if k == n { f32::INFINITY } else { split };
        if whole_world {
            v.split_m = f32::INFINITY;
            out.push(v);
            break;
        }
        out.push(v);
        near = split;
    }
    out
}

/// `n` unit directions spread evenly over the upper (y > 0) hemisphere
/// (a Fibonacci spiral in cos θ), then, when `lower`, as many mirrored
/// into the lower hemisphere.
pub fn hemisphere_directions(n: usize, lower: bool) -> Vec<Vec3> {
    direction_sets(n, lower, 1)
}

/// `sets` interleaved sets of [`hemisphere_directions`], set after set:
/// set s shifts the spiral by (s + ½)/sets of a stratum in cos θ and turns
/// it by s/sets of a turn, so that together the sets sample the sphere
/// `sets` times more finely than each alone.
pub fn direction_sets(n: usize, lower: bool, sets: usize) -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5.0f32.sqrt());
    let mut out = Vec::with_capacity(n * sets * 2);
    for s in 0..sets.max(1) {
        let shift = (s as f32 + 0.5) / sets.max(1) as f32;
        let turn = std::f32::consts::TAU * s as f32 / sets.max(1) as f32;
        let upper: Vec<Vec3> = (0..n)
            .map(|i| {
                let y = 1.0 - (i as f32 + shift) / n as f32;
                let r = (1.0 - y * y).max(0.0).sqrt();
                let phi = golden * i as f32 + turn;
                Vec3::new(r * phi.cos(), y, r * phi.sin())
            })
            .collect();
        let mirrored: Vec<Vec3> = upper.iter().map(|d| Vec3::new(d.x, -d.y, d.z)).collect();
        out.extend(upper);
        if lower {
            out.extend(mirrored);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use himmel_skymodel::Projection;

    fn camera() -> Camera {
        Camera {
            projection: Projection::Perspective,
            width: 320,
            height: 180,
            fov_deg: 60.0,
            position_m: Some([1.0, 1.7, 4.0]),
            look_at_m: Some([-2.0, 0.5, -3.0]),
            ..Camera::default()
        }
    }

    /// A world point projects to the pixel whose sky direction points at it.
    #[test]
    fn projection_matches_the_sky_camera() {
        let cam = camera();
        let wc = WorldCamera::new(&cam);
        let vp = wc.view_projection();
        for p in [
            Vec3::new(-2.0, 0.5, -3.0),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(-5.0, 3.0, -1.0),
        ] {
            let c = vp * p.extend(1.0);
            let ndc = c.truncate() / c.w;
            let px = (ndc.x + 1.0) * 0.5 * 320.0;
            let py = (1.0 - ndc.y) * 0.5 * 180.0;
            let dir = cam.pixel_to_dir(px as f64, py as f64).unwrap();
            let want =
                himmel_skymodel::projection::enu_from_scene((p - wc.eye).as_dvec3()).normalize();
            assert!(dir.dot(want) > 1.0 - 1e-9, "{p}: {dir} vs {want}");
            let depth = (p - wc.eye).dot(wc.forward);
            assert!((ndc.z - NEAR_M / depth).abs() < 1e-6);
        }
    }

    /// Every corner of the world falls inside the light view of the whole
    /// world, with depth in [0, 1]; snapping keeps texel alignment.
    #[test]
    fn light_views_cover_the_world() {
        let b = Aabb {
            min: Vec3::new(-20.0, 0.0, -20.0),
            max: Vec3::new(20.0, 3.0, 20.0),
        };
        let dir = Vec3::new(0.3, 0.5, 0.8).normalize();
        let cam = WorldCamera::new(&camera());
        let cs = cascades(&cam, dir, &b, 3, 500.0, 0.75, 1024);
        let last = cs.last().unwrap();
        for c in aabb_corners(&b) {
            let p = last.matrix * c.extend(1.0);
            assert!(p.x.abs() <= 1.0 + 1e-4 && p.y.abs() <= 1.0 + 1e-4, "{p}");
            assert!((0.0..=1.0).contains(&p.z), "{p}");
        }
        assert!(cs.windows(2).all(|w| w[0].texel_m <= w[1].texel_m));
        // A small world needs fewer cascades than asked for: the first one
        // that would cover it whole ends the list.
        let small = Aabb {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        };
        let cs = cascades(&cam, dir, &small, 4, 500.0, 0.75, 1024);
        assert!(cs.len() < 4, "{}", cs.len());
        assert_eq!(cs.last().unwrap().split_m, f32::INFINITY);
    }

    #[test]
    fn hemisphere_directions_are_unit_and_balanced() {
        let d = hemisphere_directions(80, true);
        assert_eq!(d.len(), 160);
        assert!(d.iter().all(|v| (v.length() - 1.0).abs() < 1e-5));
        let mean: Vec3 = d[..80].iter().copied().sum::<Vec3>() / 80.0;
        // Uniform over the hemisphere: mean y = 1/2, mean x, z ≈ 0.
        assert!(
            (mean.y - 0.5).abs() < 0.01 && mean.x.abs() < 0.02 && mean.z.abs() < 0.02,
            "{mean}"
        );
    }
}
