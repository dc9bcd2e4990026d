//! The procedural test worlds the lighting passes are judged on (world
//! frame: x East, y Up, z South, metres, the ground at y = 0). Every
//! surface is a closed, outward-facing box or an arch panel, so the worlds
//! are watertight where they should be (the sun room) and their areas are
//! exact (tests).
//!
//! * [`plane_and_boxes`] — a 40 m × 40 m ground, three boxes and a 2 m pole
//!   (the shadow tests: direction and length);
//! * [`glossy_plane_and_boxes`] — the same with a polished metal floor
//!   (the screen-space reflection tests);
//! * [`sun_room`] — a closed 6 m × 3 m × 5 m room whose only opening is a
//!   2 m × 1.5 m window in the south wall (the seed GI thesis' indoor case:
//!   the floor and walls see the sky only through it);
//! * [`atrium`] — a 20 m × 20 m courtyard ringed by a colonnade of
//!   semicircular arches under a covered walk and 8 m outer walls (the role
//!   Crytek Sponza plays in the seeds; Sponza itself is not obtainable here).

use glam::Vec3;

use crate::{Material, Mesh, World};

/// Builds a world one material at a time.
#[derive(Debug, Default, Clone)]
pub struct Builder {
    world: World,
}

impl Builder {
    /// Adds a material; returns its index.
    pub fn material(&mut self, m: Material) -> usize {
        self.world.materials.push(m);
        self.world.materials.len() - 1
    }

    fn mesh(&mut self, material: usize) -> &mut Mesh {
        if let Some(i) = self
            .world
            .meshes
            .iter()
            .position(|m| m.material == material)
        {
            return &mut self.world.meshes[i];
        }
        self.world.meshes.push(Mesh {
            positions: Vec::new(),
            normals: Vec::new(),
            uvs: Vec::new(),
            indices: Vec::new(),
            material,
        });
        let n = self.world.meshes.len() - 1;
        &mut self.world.meshes[n]
    }

    /// A planar quad a → b → c → d (counter-clockwise seen from its front,
    /// where its normal points), texture coordinates in metres along a→b
    /// and a→d.
    pub fn quad(&mut self, material: usize, [a, b, c, d]: [Vec3; 4]) {
        let n = (b - a).cross(d - a).normalize_or(Vec3::Y);
        let (u, v) = ((b - a).length(), (d - a).length());
        let m = self.mesh(material);
        let base = m.positions.len() as u32;
        for (p, uv) in [(a, [0.0, 0.0]), (b, [u, 0.0]), (c, [u, v]), (d, [0.0, v])] {
            m.positions.push(p.to_array());
            m.normals.push(n.to_array());
            m.uvs.push(uv);
        }
        m.indices
            .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }

    /// An axis-aligned box from `min` to `max`, faces outward.
    pub fn cuboid(&mut self, material: usize, min: Vec3, max: Vec3) {
        let (x0, y0, z0) = (min.x, min.y, min.z);
        let (x1, y1, z1) = (max.x, max.y, max.z);
        let v = Vec3::new;
        // +x, −x, +y, −y, +z, −z, each counter-clockwise from outside.
        self.quad(
            material,
            [v(x1, y0, z1), v(x1, y0, z0), v(x1, y1, z0), v(x1, y1, z1)],
        );
        self.quad(
            material,
            [v(x0, y0, z0), v(x0, y0, z1), v(x0, y1, z1), v(x0, y1, z0)],
        );
        self.quad(
            material,
            [v(x0, y1, z1), v(x1, y1, z1), v(x1, y1, z0), v(x0, y1, z0)],
        );
        self.quad(
            material,
            [v(x0, y0, z0), v(x1, y0, z0), v(x1, y0, z1), v(x0, y0, z1)],
        );
        self.quad(
            material,
            [v(x0, y0, z1), v(x1, y0, z1), v(x1, y1, z1), v(x0, y1, z1)],
        );
        self.quad(
            material,
            [v(x1, y0, z0), v(x0, y0, z0), v(x0, y1, z0), v(x1, y1, z0)],
        );
    }

    /// A semicircular arch spanning `width` along the unit horizontal
    /// `along`, springing at height `spring` from `start` (the left foot on
    /// the ground line), `depth` deep towards `out` (unit, horizontal), up
    /// to the lintel height `top`: its two faces (the spandrels between the
    /// lintel and the curve) and the soffit under the curve, in `n` segments.
    #[allow(clippy::too_many_arguments)]
    pub fn arch(
        &mut self,
        material: usize,
        start: Vec3,
        along: Vec3,
        out: Vec3,
        width: f32,
        depth: f32,
        spring: f32,
        top: f32,
        n: usize,
    ) {
        let r = width / 2.0;
        let centre = start + along * r + Vec3::Y * spring;
        let arc = |k: usize| {
            let t = std::f32::consts::PI * (1.0 - k as f32 / n as f32);
            centre + along * (r * t.cos()) + Vec3::Y * (r * t.sin())
        };
        let lift = |p: Vec3| Vec3::new(p.x, start.y + top, p.z);
        for k in 0..n {
            let (a, b) = (arc(k), arc(k + 1));
            // Front face (towards −out) and back face (towards +out).
            self.quad(material, [a, b, lift(b), lift(a)]);
            let (ad, bd) = (a + out * depth, b + out * depth);
            self.quad(material, [bd, ad, lift(ad), lift(bd)]);
            // The soffit faces down and inwards, towards the arch's centre.
            self.quad(material, [b, a, ad, bd]);
        }
    }

    /// The world built.
    pub fn build(self) -> World {
        self.world
    }
}

/// A 40 m × 40 m ground slab (top at y = 0), three boxes and a 2 m pole of
/// 0.1 m × 0.1 m section at the origin: white ground (albedo 0.8), grey
/// boxes (0.5), a white pole.
pub fn plane_and_boxes() -> World {
    let mut b = Builder::default();
    let ground = b.material(Material::diffuse("ground", [0.8; 3]));
    let grey = b.material(Material::diffuse("box", [0.5; 3]));
    let white = b.material(Material::diffuse("pole", [0.8; 3]));
    let v = Vec3::new;
    b.quad(
        ground,
        [
            v(-20.0, 0.0, 20.0),
            v(20.0, 0.0, 20.0),
            v(20.0, 0.0, -20.0),
            v(-20.0, 0.0, -20.0),
        ],
    );
    b.cuboid(grey, v(3.0, 0.0, -2.0), v(4.0, 1.0, -1.0));
    b.cuboid(grey, v(-5.0, 0.0, -6.0), v(-3.0, 3.0, -5.0));
    b.cuboid(grey, v(2.0, 0.0, 4.0), v(3.0, 0.5, 6.0));
    b.cuboid(white, v(-0.05, 0.0, -0.05), v(0.05, 2.0, 0.05));
    b.build()
}

/// [`plane_and_boxes`] with a polished metal floor: base colour 0.9,
/// metallic 1 and perceptual roughness `roughness` (GGX α = roughness²),
/// in which the boxes and the pole reflect.
pub fn glossy_plane_and_boxes(roughness: f32) -> World {
    let mut w = plane_and_boxes();
    if let Some(m) = w.materials.first_mut() {
        *m = Material {
            name: Some("metal floor".into()),
            base_color: [0.9, 0.9, 0.9, 1.0],
            metallic: 1.0,
            roughness,
            ..Material::default()
        };
    }
    w
}

/// The sun room's inner size (x, y, z), metres.
pub const SUN_ROOM: [f32; 3] = [6.0, 3.0, 5.0];
/// The sun room's south window: width, height, sill height, metres
/// (centred in the south wall).
pub const SUN_ROOM_WINDOW: [f32; 3] = [2.0, 1.5, 0.8];

/// A closed room of [`SUN_ROOM`] inside (x −3…3, y 0…3, z −2.5…2.5; walls
/// 0.2 m thick) whose only opening is the south window
/// ([`SUN_ROOM_WINDOW`], in the wall at z = +2.5 … +2.7): white walls and
/// ceiling (albedo 0.7), a wooden floor (0.35, 0.25, 0.15).
pub fn sun_room() -> World {
    let mut b = Builder::default();
    let wall = b.material(Material::diffuse("wall", [0.7; 3]));
    let floor = b.material(Material::diffuse("floor", [0.35, 0.25, 0.15]));
    let [sx, sy, sz] = SUN_ROOM;
    let (hx, hz, t) = (sx / 2.0, sz / 2.0, 0.2);
    let v = Vec3::new;
    b.cuboid(floor, v(-hx - t, -t, -hz - t), v(hx + t, 0.0, hz + t));
    b.cuboid(wall, v(-hx - t, sy, -hz - t), v(hx + t, sy + t, hz + t));
    b.cuboid(wall, v(-hx - t, 0.0, -hz - t), v(-hx, sy, hz + t));
    b.cuboid(wall, v(hx, 0.0, -hz - t), v(hx + t, sy, hz + t));
    b.cuboid(wall, v(-hx, 0.0, -hz - t), v(hx, sy, -hz));
    // The south wall around the window.
    let [ww, wh, sill] = SUN_ROOM_WINDOW;
    let (z0, z1) = (hz, hz + t);
    b.cuboid(wall, v(-hx, 0.0, z0), v(-ww / 2.0, sy, z1));
    b.cuboid(wall, v(ww / 2.0, 0.0, z0), v(hx, sy, z1));
    b.cuboid(wall, v(-ww / 2.0, 0.0, z0), v(ww / 2.0, sill, z1));
    b.cuboid(wall, v(-ww / 2.0, sill + wh, z0), v(ww / 2.0, sy, z1));
    b.build()
}

/// The atrium's courtyard half-width (m), bay width (m), column section
/// (m), arch springing height and lintel height (m), outer wall height (m).
pub const ATRIUM: [f32; 6] = [10.0, 2.5, 0.4, 2.5, 4.2, 8.0];

/// A 20 m × 20 m courtyard (ground slab top at y = 0) ringed on each side
/// by a colonnade: square columns ([`ATRIUM`]) every 2.5 m carrying
/// semicircular arches under a 3 m-deep covered walk (roof slab at the
/// lintel height), backed by 8 m outer walls. Stone (albedo 0.6), a light
/// floor (0.5).
pub fn atrium() -> World {
    let mut b = Builder::default();
    let stone = b.material(Material::diffuse("stone", [0.6, 0.57, 0.52]));
    let floor = b.material(Material::diffuse("floor", [0.5; 3]));
    let [half, bay, col, spring, top, wall_h] = ATRIUM;
    let walk = 3.0;
    let outer = half + walk;
    let v = Vec3::new;
    b.cuboid(
        floor,
        v(-outer - 0.5, -0.2, -outer - 0.5),
        v(outer + 0.5, 0.0, outer + 0.5),
    );
    // Outer walls (0.5 m thick).
    b.cuboid(
        stone,
        v(-outer - 0.5, 0.0, -outer - 0.5),
        v(outer + 0.5, wall_h, -outer),
    );
    b.cuboid(
        stone,
        v(-outer - 0.5, 0.0, outer),
        v(outer + 0.5, wall_h, outer + 0.5),
    );
    b.cuboid(
        stone,
        v(-outer - 0.5, 0.0, -outer),
        v(-outer, wall_h, outer),
    );
    b.cuboid(stone, v(outer, 0.0, -outer), v(outer + 0.5, wall_h, outer));
    // The walk's roof: four slabs over the colonnade.
    let roof = |b: &mut Builder, min: Vec3, max: Vec3| b.cuboid(stone, min, max);
    roof(&mut b, v(-outer, top, -outer), v(outer, top + 0.3, -half));
    roof(&mut b, v(-outer, top, half), v(outer, top + 0.3, outer));
    roof(&mut b, v(-outer, top, -half), v(-half, top + 0.3, half));
    roof(&mut b, v(half, top, -half), v(outer, top + 0.3, half));
    // Columns and arches along each side of the courtyard: (start corner,
    // direction along the side, direction out of the courtyard).
    let bays = (2.0 * half / bay).round() as usize;
    let sides = [
        (v(-half, 0.0, -half), Vec3::X, Vec3::NEG_Z),
        (v(half, 0.0, half), Vec3::NEG_X, Vec3::Z),
        (v(half, 0.0, -half), Vec3::Z, Vec3::X),
        (v(-half, 0.0, half), Vec3::NEG_Z, Vec3::NEG_X),
    ];
    for (corner, along, out) in sides {
        for k in 0..bays {
            let c = corner + along * (k as f32 * bay);
            let (lo, hi) = (c - Vec3::splat(col / 2.0), c + Vec3::splat(col / 2.0));
            b.cuboid(stone, v(lo.x, 0.0, lo.z), v(hi.x, top, hi.z));
        }
        for k in 0..bays {
            let start = corner + along * (k as f32 * bay + col / 2.0) - out * (col / 2.0);
            b.arch(stone, start, along, out, bay - col, col, spring, top, 12);
        }
    }
    b.build()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boxes_are_closed_and_outward() {
        let mut b = Builder::default();
        let m = b.material(Material::default());
        b.cuboid(m, Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        let w = b.build();
        assert_eq!(w.triangles(), 12);
        assert!((w.area() - 2.0 * (2.0 + 3.0 + 6.0)).abs() < 1e-9);
        // Outward: each face normal points away from the centre.
        let mesh = &w.meshes[0];
        let centre = Vec3::new(0.5, 1.0, 1.5);
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            let (p, n) = (Vec3::from_array(*p), Vec3::from_array(*n));
            assert!((p - centre).dot(n) > 0.0);
        }
        // The winding agrees with the normals.
        for t in mesh.indices.chunks_exact(3) {
            let p = |i: u32| Vec3::from_array(mesh.positions[i as usize]);
            let geo = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
            assert!(geo.dot(Vec3::from_array(mesh.normals[t[0] as usize])) > 0.0);
        }
    }

    #[test]
    fn worlds_have_their_documented_extents() {
        let p = plane_and_boxes();
        let bb = p.bounds().unwrap();
        assert_eq!((bb.min.y, bb.max.y), (0.0, 3.0));
        assert_eq!((bb.min.x, bb.max.x), (-20.0, 20.0));
        let r = sun_room();
        let bb = r.bounds().unwrap();
        assert!((bb.max.y - 3.2).abs() < 1e-6 && (bb.max.z - 2.7).abs() < 1e-6);
        let a = atrium();
        let bb = a.bounds().unwrap();
        assert!((bb.max.y - 8.0).abs() < 1e-6 && (bb.max.x - 13.5).abs() < 1e-6);
        assert!(a.triangles() > 2000, "{}", a.triangles());
    }
}
