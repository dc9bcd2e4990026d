//! The sky as an environment light, built on the CPU from the frame's own
//! sky cube map (the sky passes without the Sun and Moon disks, which light
//! the world as directional lights):
//!
//! * **occludable diffuse light** — the sphere is cut into cells around a
//!   set of directions (one visibility map each, [`super::shadow`]); each
//!   cell keeps the first moment of its radiance, M = ∫ L ω dω per colour
//!   channel, so that a surface of normal n facing the whole cell receives
//!   exactly n·M from it. The lighting pass sums max(0, n·M) × the cell's
//!   visibility from the surface point, so a floor under a roof or a room
//!   behind a window sees only the sky that is left open. The upper and
//!   lower hemispheres have cells of their own, so no cell straddles the
//!   horizon: a horizontal surface open to the sky receives the sky's
//!   horizontal illuminance to the cube map's quadrature.
//!
//!   The directions form `sets` interleaved sets (one per pixel of an
//!   N × N block, see shade.wgsl). The cells are the fine partition of the
//!   sphere by *all* the directions, each moment × `sets`: a pixel sums
//!   one set, an estimate of the whole sky with `sets` times the weight,
//!   and the block's average is the quadrature over every direction, with
//!   cells as small as the union's (a set's own, coarse partition would
//!   spread a bright region of the sky over the wide cell around it).
//! * **aureoles** — the sky climbs steeply towards the Sun (and the
//!   Moon): the aerosols' forward peak puts much of the sky's light within
//!   a few degrees of the disk, more than any cell of the uniform sets
//!   can resolve, and a window or a box edge cutting through that region
//!   would switch it on and off whole. So [`AUREOLE_DIRECTIONS`] extra
//!   directions in rings around each body ([`aureole_directions`]) follow
//!   the cells of the sets; the sky within [`AUREOLE_DEG`] of the body, on
//!   its side of the horizon, is cut into their cells (weight 1: every
//!   pixel sums them all).
//! * **SH9 irradiance** (Ramamoorthi & Hanrahan 2001), unoccluded, for the
//!   API and the checks;
//! * **prefiltered specular** — equirect maps of the radiance convolved
//!   with the GGX lobe at five roughnesses (split-sum, Karis 2013), and the
//!   split-sum BRDF table ([`brdf_lut`]).

// Channel loops index several arrays at once; indices read better there.
#![allow(clippy::needless_range_loop)]

use glam::Vec3;
use himmel_skymodel::projection::scene_from_enu;
use himmel_skymodel::renderer::HdrImage;
use himmel_skymodel::{Camera, Projection};
use rayon::prelude::*;

/// Roughness levels of the prefiltered maps.
pub const SPECULAR_LEVELS: usize = 5;
/// Size of each prefiltered equirect map (W × H).
pub const SPECULAR_SIZE: (usize, usize) = (64, 32);
/// Size of the split-sum BRDF table (N·V × roughness).
pub const BRDF_LUT_SIZE: usize = 32;

/// One cell of the sky's occludable light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SkyCell {
    /// The cell's direction (world frame, unit): its visibility map looks
    /// along it.
    pub dir: Vec3,
    /// ∫ L ω dω over the cell per channel (rows R, G, B), cd/m² · sr.
    pub moment: [Vec3; 3],
    /// The cell's solid angle, sr.
    pub solid_angle: f32,
    /// Its parts: `EnvLight::parts[first..first + count]`.
    pub first_part: u32,
    /// The number of its parts.
    pub parts: u32,
    /// The largest tangent of the angle between `dir` and a direction of
    /// the cell (the cone that holds it).
    pub tan_radius: f32,
    /// Whether it has parts in bands along the horizon
    /// ([`HORIZON_DEG`]): the lighting pass then looks at its parts even
    /// where its nine first lookups find it blocked (a sliver of sky under
    /// a window's top edge falls between them).
    pub horizon: bool,
}

/// A part of a sky cell: a few of its cube texels, whose visibility the
/// lighting pass reads from the cell's map where the part's rays cross
/// the cell's blockers (a parallax offset), so that a window edge cuts
/// through a cell instead of switching it whole.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellPart {
    /// The centre of the part's texels' directions ω as a step across the
    /// cell's map per metre along its direction: (ω·right, ω·up) / (ω·dir),
    /// with (right, up) the map's axes ([`super::view::light_basis`]).
    pub offset: [f32; 2],
    /// ∫ L ω dω over the part per channel, with the cell's weight.
    pub moment: [Vec3; 3],
    /// The part's extent across the map in the same units as `offset`
    /// (its texels' span and one texel; 0 for a cell in one part): the
    /// lighting pass spreads its lookups over it.
    pub extent: [f32; 2],
}

/// Texels closer to the horizon than this (degrees) are grouped in bands
/// of [`HORIZON_BAND_DEG`] of elevation: the sky's steepest gradient runs
/// across the horizon, and a window's edge seen from far inside a room
/// lets through a sliver of it thinner than a part of the grid.
pub const HORIZON_DEG: f32 = 6.0;

/// The height of a band of parts near the horizon, degrees.
pub const HORIZON_BAND_DEG: f32 = 1.0;

/// Radius of the sky around the Sun or Moon cut into the aureole's own
/// cells, degrees.
pub const AUREOLE_DEG: f32 = 10.0;

/// The aureole's rings: (radius, degrees; directions).
const AUREOLE_RINGS: [(f32, usize); 4] = [(0.0, 1), (2.0, 6), (5.0, 12), (8.5, 18)];

/// Directions of one body's aureole cells.
pub const AUREOLE_DIRECTIONS: usize = 37;

/// The directions of a body's aureole cells: the body itself and rings
/// around it ([`AUREOLE_RINGS`]), world frame, unit.
pub fn aureole_directions(body: Vec3) -> Vec<Vec3> {
    let b = body.normalize();
    // Two unit vectors across the body's direction.
    let side = if b.y.abs() < 0.9 { Vec3::Y } else { Vec3::X };
    let e1 = b.cross(side).normalize();
    let e2 = b.cross(e1);
    let mut out = Vec::with_capacity(AUREOLE_DIRECTIONS);
    for (ring, &(radius, n)) in AUREOLE_RINGS.iter().enumerate() {
        let r = radius.to_radians();
        for k in 0..n {
            // Alternate rings are turned by half a step.
            let phi = std::f32::consts::TAU * (k as f32 + 0.5 * (ring % 2) as f32) / n as f32;
            out.push((b * r.cos() + (e1 * phi.cos() + e2 * phi.sin()) * r.sin()).normalize());
        }
    }
    out
}

/// The sky's environment light of one instant.
#[derive(Debug, Clone)]
pub struct EnvLight {
    /// The occludable cells: `sets` partitions of the sphere, set after
    /// set, each upper hemisphere first.
    pub cells: Vec<SkyCell>,
    /// The number of interleaved sets the first cells form.
    pub sets: usize,
    /// The aureoles' cells after them ([`AUREOLE_DIRECTIONS`] a body).
    pub aureole_cells: usize,
    /// The cells' parts, cell after cell ([`SkyCell::first_part`]).
    pub parts: Vec<CellPart>,
    /// SH9 coefficients of the radiance, per channel (order l ≤ 2).
    pub sh9: [[f32; 9]; 3],
    /// Horizontal illuminance from the upper hemisphere, linear sRGB lux.
    pub horizontal_rgb: [f64; 3],
    /// Prefiltered radiance, [`SPECULAR_LEVELS`] equirect maps of
    /// [`SPECULAR_SIZE`] (row-major, world-frame azimuth from North through
    /// East across, zenith at the top), cd/m².
    pub specular: Vec<[f32; 3]>,
    /// The largest radiance in the cube map, cd/m².
    pub max_radiance: f32,
}

/// A cube-map texel: direction (world frame), solid angle, radiance.
fn cube_texels(cube: &HdrImage) -> Vec<(Vec3, f32, [f32; 3])> {
    let h = cube.height as u32;
    let cam = Camera {
        projection: Projection::Cubemap,
        width: h,
        height: h,
        ..Camera::default()
    };
    let mut out = Vec::with_capacity(cube.pixels.len());
    for y in 0..cube.height {
        for x in 0..cube.width {
            let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
            let Some(d) = cam.pixel_to_dir(px, py) else {
                continue;
            };
            let w = scene_from_enu(d).as_vec3().normalize();
            let sa = cam.pixel_solid_angle(px, py) as f32;
            out.push((w, sa, cube.pixels[y * cube.width + x]));
        }
    }
    out
}

/// The unit direction of an equirect texel centre (world frame): column =
/// azimuth from North (−z) through East (+x), row 0 at the zenith.
pub fn equirect_dir(i: usize, j: usize, w: usize, h: usize) -> Vec3 {
    let az = std::f32::consts::TAU * (i as f32 + 0.5) / w as f32;
    let alt = std::f32::consts::FRAC_PI_2 - std::f32::consts::PI * (j as f32 + 0.5) / h as f32;
    Vec3::new(alt.cos() * az.sin(), alt.sin(), -alt.cos() * az.cos())
}

/// GGX normal distribution for perceptual roughness `r` (α = r²).
fn ggx_d(n_h: f32, r: f32) -> f32 {
    let a2 = (r * r).max(1e-4).powi(2);
    let d = n_h * n_h * (a2 - 1.0) + 1.0;
    a2 / (std::f32::consts::PI * d * d)
}

/// The roughness of prefiltered level `k`.
pub fn level_roughness(k: usize) -> f32 {
    k as f32 / (SPECULAR_LEVELS - 1) as f32
}

impl EnvLight {
    /// Builds the environment light from a sky cube map (6H × H strip,
    /// faces in the scene frame's order) with cells around `dirs`, which
    /// hold `sets` sets of equal size, the upper-hemisphere directions
    /// having y > 0, and the aureoles of `bodies` (unit directions towards
    /// the Sun or Moon). A texel within [`AUREOLE_DEG`] of a body on its
    /// side of the horizon belongs to the nearest of that body's aureole
    /// directions; any other to the nearest direction of its own
    /// hemisphere among all of `dirs` (dropped when its hemisphere has
    /// none), whose moment and solid angle count `sets` times (a pixel sums
    /// one set). Each cell is cut into about `parts` parts ([`CellPart`]):
    /// its texels grouped on a square grid across its direction.
    pub fn from_cube(
        cube: &HdrImage,
        dirs: &[Vec3],
        sets: usize,
        bodies: &[Vec3],
        parts: usize,
    ) -> EnvLight {
        let sets = sets.max(1);
        let weight = sets as f32;
        let texels = cube_texels(cube);
        let regular = dirs.len();
        let aureoles: Vec<Vec3> = bodies.iter().flat_map(|&b| aureole_directions(b)).collect();
        let cos_aureole = AUREOLE_DEG.to_radians().cos();
        let mut cells: Vec<SkyCell> = dirs
            .iter()
            .chain(&aureoles)
            .map(|&dir| SkyCell {
                dir,
                moment: [Vec3::ZERO; 3],
                solid_angle: 0.0,
                first_part: 0,
                parts: 0,
                tan_radius: 0.0,
                horizon: false,
            })
            .collect();
        let mut sh9 = [[0.0f32; 9]; 3];
        let mut horizontal = [0.0f64; 3];
        let mut max_radiance = 0.0f32;
        // Each texel's cell and weight (the nearest-direction search, in
        // parallel), then the sums in texel order.
        let assigned: Vec<Option<(usize, f32)>> = texels
            .par_iter()
            .map(|&(w, _, _)| {
                let up = w.y >= 0.0;
                let body = bodies
                    .iter()
                    .position(|b| (b.y >= 0.0) == up && w.dot(*b) >= cos_aureole);
                let nearest = |range: std::ops::Range<usize>| {
                    range
                        .filter(|&k| (cells[k].dir.y > 0.0) == up)
                        .max_by(|&a, &b| w.dot(cells[a].dir).total_cmp(&w.dot(cells[b].dir)))
                };
                let first = |i: usize| regular + i * AUREOLE_DIRECTIONS;
                body.and_then(|i| nearest(first(i)..first(i) + AUREOLE_DIRECTIONS))
                    .map(|k| (k, 1.0))
                    .or_else(|| nearest(0..regular).map(|k| (k, weight)))
            })
            .collect();
        for (&(w, sa, l), &best) in texels.iter().zip(&assigned) {
            max_radiance = max_radiance.max(l[0].max(l[1]).max(l[2]));
            let up = w.y >= 0.0;
            if let Some((k, f)) = best {
                let c = &mut cells[k];
                for ch in 0..3 {
                    c.moment[ch] += w * (l[ch] * sa * f);
                }
                c.solid_angle += sa * f;
            }
            let basis = sh9_basis(w);
            for ch in 0..3 {
                for (k, b) in basis.iter().enumerate() {
                    sh9[ch][k] += l[ch] * b * sa;
                }
                if up {
                    horizontal[ch] += (l[ch] * w.y * sa) as f64;
                }
            }
        }
        let parts = cut_into_parts(&mut cells, &texels, &assigned, parts, cube.height);
        let specular = prefilter(&texels, cube.height);
        EnvLight {
            cells,
            sets,
            aureole_cells: aureoles.len(),
            parts,
            sh9,
            horizontal_rgb: horizontal,
            specular,
            max_radiance,
        }
    }

    /// Unoccluded irradiance on a surface of unit normal `n` from the SH9
    /// coefficients (cosine lobe convolution), linear sRGB lux.
    pub fn sh9_irradiance(&self, n: Vec3) -> [f32; 3] {
        let a = [
            std::f32::consts::PI,
            2.0 * std::f32::consts::PI / 3.0,
            2.0 * std::f32::consts::PI / 3.0,
            2.0 * std::f32::consts::PI / 3.0,
            std::f32::consts::PI / 4.0,
            std::f32::consts::PI / 4.0,
            std::f32::consts::PI / 4.0,
            std::f32::consts::PI / 4.0,
            std::f32::consts::PI / 4.0,
        ];
        let b = sh9_basis(n);
        [0, 1, 2].map(|ch| {
            (0..9)
                .map(|k| a[k] * self.sh9[ch][k] * b[k])
                .sum::<f32>()
                .max(0.0)
        })
    }

    /// Irradiance on a surface of unit normal `n` that sees every cell
    /// whose visibility is given by `visible`, averaged over the sets (what
    /// the lighting pass's N × N block gives), linear sRGB lux.
    pub fn cell_irradiance(&self, n: Vec3, visible: impl Fn(usize) -> f32) -> [f32; 3] {
        let mut e = [0.0f32; 3];
        for (k, c) in self.cells.iter().enumerate() {
            let v = visible(k);
            // The sets' cells count once per set, the aureoles' in every
            // set: weight them as the block's average does.
            let f = if k < self.cells.len() - self.aureole_cells {
                1.0 / self.sets as f32
            } else {
                1.0
            };
            let parts = &self.parts[c.first_part as usize..(c.first_part + c.parts) as usize];
            for ch in 0..3 {
                let part_sum: f32 = parts.iter().map(|p| n.dot(p.moment[ch]).max(0.0)).sum();
                e[ch] += f * v * part_sum;
            }
        }
        e
    }
}

/// Cuts each cell into parts: its texels (`assigned` to it with their
/// weight) grouped on a square grid in the plane across the cell's
/// direction, of about `per_cell` squares over the cell's solid angle, but
/// within [`HORIZON_DEG`] of the horizon in bands of [`HORIZON_BAND_DEG`]
/// of elevation across the grid's columns (one part a cell, along its
/// direction, when `per_cell` ≤ 1). `face`: the cube's face size, texels.
/// Fills the cells' part ranges, cone radii and horizon flags; returns the
/// parts, cell after cell.
fn cut_into_parts(
    cells: &mut [SkyCell],
    texels: &[(Vec3, f32, [f32; 3])],
    assigned: &[Option<(usize, f32)>],
    per_cell: usize,
    face: usize,
) -> Vec<CellPart> {
    struct Acc {
        lo: [f32; 2],
        hi: [f32; 2],
        along: f32,
        moment: [Vec3; 3],
    }
    // A cube texel's side, tangent units at its face's centre.
    let texel_tan = 2.0 / face.max(1) as f32;
    let bases: Vec<(Vec3, Vec3)> = cells
        .iter()
        .map(|c| super::view::light_basis(c.dir))
        .collect();
    // The cells' own solid angles (without the sets' weight) set the grid.
    let mut own = vec![0.0f32; cells.len()];
    for (&(_, sa, _), best) in texels.iter().zip(assigned) {
        if let Some((k, _)) = *best {
            own[k] += sa;
        }
    }
    let mut groups: std::collections::BTreeMap<(usize, i32, i32), Acc> = Default::default();
    for (&(w, sa, l), best) in texels.iter().zip(assigned) {
        let Some((k, f)) = *best else {
            continue;
        };
        let c = &mut cells[k];
        let (right, up) = bases[k];
        let along = w.dot(c.dir).max(0.05);
        let ab = [w.dot(right) / along, w.dot(up) / along];
        c.tan_radius = c.tan_radius.max(ab[0].hypot(ab[1]));
        let elevation = w.y.clamp(-1.0, 1.0).asin().to_degrees();
        let key = if per_cell <= 1 {
            (k, 0, 0)
        } else {
            let pitch = (own[k] / per_cell as f32).sqrt().max(1e-6);
            let column = (ab[0] / pitch).floor() as i32;
            if elevation.abs() < HORIZON_DEG {
                c.horizon = true;
                // Bands along the horizon (keys apart from the grid's).
                let band = (elevation / HORIZON_BAND_DEG).floor() as i32;
                (k, column, i32::MIN / 2 + band)
            } else {
                (k, column, (ab[1] / pitch).floor() as i32)
            }
        };
        let g = groups.entry(key).or_insert(Acc {
            lo: [f32::INFINITY; 2],
            hi: [f32::NEG_INFINITY; 2],
            along: 1.0,
            moment: [Vec3::ZERO; 3],
        });
        for i in 0..2 {
            g.lo[i] = g.lo[i].min(ab[i]);
            g.hi[i] = g.hi[i].max(ab[i]);
        }
        g.along = g.along.min(along);
        for ch in 0..3 {
            g.moment[ch] += w * (l[ch] * sa * f);
        }
    }
    let mut parts = Vec::with_capacity(groups.len());
    for ((k, _, _), g) in groups {
        let c = &mut cells[k];
        if c.parts == 0 {
            c.first_part = parts.len() as u32;
        }
        c.parts += 1;
        // One part a cell is looked up along the cell's own direction,
        // where its map is exact.
        let (offset, extent) = if per_cell <= 1 {
            ([0.0; 2], [0.0; 2])
        } else {
            // The texels' span and one texel (at its steepest in the
            // cell's map).
            let t = texel_tan / (g.along * g.along);
            (
                [0.5 * (g.lo[0] + g.hi[0]), 0.5 * (g.lo[1] + g.hi[1])],
                [g.hi[0] - g.lo[0] + t, g.hi[1] - g.lo[1] + t],
            )
        };
        parts.push(CellPart {
            offset,
            moment: g.moment,
            extent,
        });
    }
    parts
}

/// The nine real SH basis functions (l ≤ 2) at unit `d`.
pub fn sh9_basis(d: Vec3) -> [f32; 9] {
    let (x, y, z) = (d.x, d.y, d.z);
    [
        0.282_095,
        0.488_603 * y,
        0.488_603 * z,
        0.488_603 * x,
        1.092_548 * x * y,
        1.092_548 * y * z,
        0.315_392 * (3.0 * z * z - 1.0),
        1.092_548 * x * z,
        0.546_274 * (x * x - y * y),
    ]
}

/// The prefiltered maps: for each level's roughness r and output direction
/// R (taken as normal and view, the split-sum assumption), Σ L D(n·h) (n·ω)
/// / Σ D (n·ω) over a 16²-per-face reduction of the cube map; level 0 is
/// the radiance under a ≈ 3° lobe over a 32²-per-face reduction.
fn prefilter(texels: &[(Vec3, f32, [f32; 3])], face: usize) -> Vec<[f32; 3]> {
    // Reduce the cube to ≤ 32 × 32 per face for the mirror level and
    // ≤ 16 × 16 for the rough ones: merge texels by block.
    let fine = reduce(texels, face, (face / 32).max(1));
    let reduced = reduce(texels, face, (face / 16).max(1));
    let (w, h) = SPECULAR_SIZE;
    // A lobe's weight below e⁻²⁰ of its peak is left out: the mirror
    // level's lobe ends within 1 − cos = 0.03 (14°).
    let mirror_cut = 1.0 - 20.0 * 1.5e-3;
    (0..SPECULAR_LEVELS * w * h)
        .into_par_iter()
        .map(|idx| {
            let (level, texel) = (idx / (w * h), idx % (w * h));
            let r = level_roughness(level).max(0.08);
            let n = equirect_dir(texel % w, texel / w, w, h);
            let (mut acc, mut wsum) = ([0.0f32; 3], 0.0f32);
            let src: &[(Vec3, f32, [f32; 3])] = if level == 0 { &fine } else { &reduced };
            for &(d, sa, l) in src {
                let c = n.dot(d);
                if c <= 0.0 || (level == 0 && c < mirror_cut) {
                    continue;
                }
                let wgt = if level == 0 {
                    // A narrow lobe (≈ 3°) for the mirror level.
                    (-(1.0 - c) / 1.5e-3).exp() * sa
                } else {
                    let hv = (n + d).normalize();
                    ggx_d(n.dot(hv), r) * c * sa
                };
                for ch in 0..3 {
                    acc[ch] += l[ch] * wgt;
                }
                wsum += wgt;
            }
            if wsum > 0.0 {
                acc.map(|a| a / wsum)
            } else {
                [0.0; 3]
            }
        })
        .collect()
}

/// Merges k × k blocks of texels of each face (power-weighted direction,
/// summed solid angle, mean radiance).
fn reduce(texels: &[(Vec3, f32, [f32; 3])], face: usize, k: usize) -> Vec<(Vec3, f32, [f32; 3])> {
    let n = face.div_ceil(k);
    let mut cells = vec![(Vec3::ZERO, 0.0f32, [0.0f32; 3]); 6 * n * n];
    let width = 6 * face;
    for (idx, &(d, sa, l)) in texels.iter().enumerate() {
        let (x, y) = (idx % width, idx / width);
        let (f, fx) = (x / face, x % face);
        let c = &mut cells[f * n * n + (y / k) * n + fx / k];
        c.0 += d * sa;
        c.1 += sa;
        for ch in 0..3 {
            c.2[ch] += l[ch] * sa;
        }
    }
    cells
        .into_iter()
        .filter(|c| c.1 > 0.0)
        .map(|(d, sa, l)| (d.normalize(), sa, l.map(|v| v / sa)))
        .collect()
}

/// The split-sum BRDF table (Karis 2013): for N·V (across) and perceptual
/// roughness (down), the scale A and bias B of F0 in ∫ f cos dω = F0·A + B
/// for GGX with the height-correlated Smith term, by importance sampling
/// (256 Hammersley samples per entry).
pub fn brdf_lut() -> Vec<[f32; 2]> {
    let n = BRDF_LUT_SIZE;
    let mut out = Vec::with_capacity(n * n);
    for j in 0..n {
        let r = ((j as f32 + 0.5) / n as f32).max(0.02);
        let a = r * r;
        for i in 0..n {
            let nv = ((i as f32 + 0.5) / n as f32).max(1e-3);
            let v = Vec3::new((1.0 - nv * nv).sqrt(), 0.0, nv);
            let (mut sa, mut sb) = (0.0f32, 0.0f32);
            let samples = 256u32;
            for s in 0..samples {
                let (u1, u2) = (
                    (s as f32 + 0.5) / samples as f32,
                    s.reverse_bits() as f32 / 4_294_967_296.0,
                );
                let phi = std::f32::consts::TAU * u2;
                let ct = ((1.0 - u1) / (1.0 + (a * a - 1.0) * u1)).sqrt();
                let st = (1.0 - ct * ct).max(0.0).sqrt();
                let hv = Vec3::new(st * phi.cos(), st * phi.sin(), ct);
                let l = 2.0 * v.dot(hv) * hv - v;
                let (nl, nh, vh) = (l.z, hv.z, v.dot(hv));
                if nl <= 0.0 {
                    continue;
                }
                let g = smith_g2(nv, nl, a);
                let gv = g * vh / (nh * nv);
                let fc = (1.0 - vh).powi(5);
                sa += (1.0 - fc) * gv;
                sb += fc * gv;
            }
            out.push([sa / samples as f32, sb / samples as f32]);
        }
    }
    out
}

/// The height-correlated Smith masking–shadowing G2 for GGX (α = `a`).
fn smith_g2(nv: f32, nl: f32, a: f32) -> f32 {
    let a2 = a * a;
    let lv = nl * (nv * nv * (1.0 - a2) + a2).sqrt();
    let ll = nv * (nl * nl * (1.0 - a2) + a2).sqrt();
    2.0 * nv * nl / (lv + ll)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::passes::lighting::view::hemisphere_directions;
    use glam::DVec3;

    fn cube(face: usize, f: impl Fn(Vec3) -> [f32; 3]) -> HdrImage {
        let cam = Camera {
            projection: Projection::Cubemap,
            width: face as u32,
            height: face as u32,
            ..Camera::default()
        };
        let (w, h) = (6 * face, face);
        let mut pixels = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let d = cam
                    .pixel_to_dir(x as f64 + 0.5, y as f64 + 0.5)
                    .unwrap_or(DVec3::Z);
                pixels.push(f(scene_from_enu(d).as_vec3()));
            }
        }
        HdrImage {
            width: w,
            height: h,
            pixels,
            valid: vec![true; w * h],
        }
    }

    /// A uniform sky of radiance L over the upper hemisphere (black below)
    /// gives π L on a horizontal surface by every route: the cells, SH9
    /// (to its ringing), and the horizontal sum.
    #[test]
    fn uniform_sky_gives_pi_l() {
        let c = cube(32, |d| {
            if d.y >= 0.0 {
                [1000.0, 1000.0, 1000.0]
            } else {
                [0.0; 3]
            }
        });
        let env = EnvLight::from_cube(&c, &hemisphere_directions(40, true), 1, &[], 16);
        // The default layout, 16 interleaved sets of 32 directions a
        // hemisphere: their average is the quadrature over all the
        // directions; each alone (one pixel of the block) estimates it to
        // its coarser sampling (within 26 % here: a pixel alone is noisy,
        // the block's average removes that spread where the surface
        // continues).
        let sets = crate::passes::lighting::view::direction_sets(32, true, 16);
        let env16 = EnvLight::from_cube(&c, &sets, 16, &[], 16);
        let e = env16.cell_irradiance(Vec3::Y, |_| 1.0);
        assert!(
            (e[1] / (std::f32::consts::PI * 1000.0) - 1.0).abs() < 2e-3,
            "{e:?}"
        );
        for s in 0..16 {
            let e = env16.cell_irradiance(Vec3::Y, |k| 16.0 * (k / 64 == s) as u8 as f32);
            assert!(
                (e[1] / (std::f32::consts::PI * 1000.0) - 1.0).abs() < 0.3,
                "set {s}: {e:?}"
            );
        }
        let want = std::f32::consts::PI * 1000.0;
        let e = env.cell_irradiance(Vec3::Y, |_| 1.0);
        assert!((e[1] / want - 1.0).abs() < 2e-3, "{e:?}");
        assert!((env.horizontal_rgb[1] as f32 / want - 1.0).abs() < 2e-3);
        // A wall sees half of the sky hemisphere: π L / 2.
        let wall = env.cell_irradiance(Vec3::X, |_| 1.0);
        assert!((wall[1] / (want / 2.0) - 1.0).abs() < 0.03, "{wall:?}");
        // SH9 of a hemisphere step rings; the horizontal value within 5 %.
        let sh = env.sh9_irradiance(Vec3::Y);
        assert!((sh[1] / want - 1.0).abs() < 0.05, "{sh:?}");
        // Nothing visible: nothing received.
        assert_eq!(env.cell_irradiance(Vec3::Y, |_| 0.0), [0.0; 3]);
        // The prefiltered maps of a uniform hemisphere are L at the zenith.
        let (w, _) = SPECULAR_SIZE;
        for level in 0..SPECULAR_LEVELS {
            let top = env.specular[level * w * SPECULAR_SIZE.1 + w / 2];
            assert!((top[1] / 1000.0 - 1.0).abs() < 0.01, "{level}: {top:?}");
        }
    }

    /// Near the horizon a cell's parts are bands of elevation: no part
    /// holds texels more than one band apart, none crosses the horizon,
    /// the cells that have them say so, and every part's extent covers its
    /// texels' directions (the lighting pass spreads its lookups over it).
    #[test]
    fn parts_follow_the_horizon() {
        let c = cube(64, |d| [100.0 + 50.0 * d.y; 3]);
        let dirs = crate::passes::lighting::view::direction_sets(64, true, 2);
        let env = EnvLight::from_cube(&c, &dirs, 2, &[], 16);
        let texels = cube_texels(&c);
        let mut banded = 0;
        for cell in &env.cells {
            let (right, up) = crate::passes::lighting::view::light_basis(cell.dir);
            let first = cell.first_part as usize;
            let parts = &env.parts[first..first + cell.parts as usize];
            // The texels of this cell (its hemisphere's nearest direction).
            let mine: Vec<Vec3> = texels
                .iter()
                .map(|t| t.0)
                .filter(|w| {
                    let up_side = w.y >= 0.0;
                    let best = env.cells[..dirs.len()]
                        .iter()
                        .filter(|o| (o.dir.y > 0.0) == up_side)
                        .max_by(|a, b| w.dot(a.dir).total_cmp(&w.dot(b.dir)));
                    best.is_some_and(|b| b.dir == cell.dir)
                })
                .collect();
            let near_horizon = mine
                .iter()
                .any(|w| w.y.asin().to_degrees().abs() < HORIZON_DEG);
            assert_eq!(cell.horizon, near_horizon, "{:?}", cell.dir);
            for w in &mine {
                let along = w.dot(cell.dir).max(0.05);
                let ab = [w.dot(right) / along, w.dot(up) / along];
                // Some part of the cell covers the texel's direction.
                assert!(
                    parts
                        .iter()
                        .any(|p| (0..2)
                            .all(|i| (ab[i] - p.offset[i]).abs() <= 0.5 * p.extent[i] + 1e-5)),
                    "{:?}: texel {w:?} outside every part",
                    cell.dir
                );
            }
            for p in parts {
                // A part's span in elevation (its extent, up, less one
                // texel) near the horizon: one band.
                let centre = (cell.dir + right * p.offset[0] + up * p.offset[1]).normalize();
                if centre.y.asin().to_degrees().abs() < HORIZON_DEG - 2.0 {
                    banded += 1;
                    let span = (p.extent[1] - 2.0 / 64.0 / 0.9).max(0.0);
                    assert!(
                        span.atan().to_degrees() <= HORIZON_BAND_DEG + 0.2,
                        "{:?}: a part {} deg tall at the horizon",
                        cell.dir,
                        span.atan().to_degrees()
                    );
                }
            }
        }
        assert!(banded > 0);
    }

    /// A bright spot (a low Sun's aureole) stays where it is: a surface
    /// facing it receives, averaged over the sets, the irradiance of the
    /// whole sky to 1 %, and a surface it lies behind receives none of
    /// it (a set's own coarse partition would spread the spot over its
    /// wide cell, in front of both).
    #[test]
    fn a_bright_spot_stays_in_its_own_cell() {
        let body = Vec3::new(0.0, 0.2, -1.0).normalize();
        let spot = 3f32.to_radians();
        let c = cube(128, |d| {
            let v = if d.dot(body) >= spot.cos() {
                1.0e5
            } else {
                100.0
            };
            if d.y >= 0.0 {
                [v; 3]
            } else {
                [0.0; 3]
            }
        });
        let dirs = crate::passes::lighting::view::direction_sets(32, true, 16);
        let env = EnvLight::from_cube(&c, &dirs, 16, &[], 16);
        let exact = |n: Vec3| -> f32 {
            cube_texels(&c)
                .iter()
                .map(|t| t.2[1] * t.1 * n.dot(t.0).max(0.0))
                .sum()
        };
        // With the spot's body given, its aureole cells take the spot.
        let with_aureole = EnvLight::from_cube(&c, &dirs, 16, &[body], 16);
        assert_eq!(with_aureole.aureole_cells, AUREOLE_DIRECTIONS);
        for n in [
            Vec3::new(0.0, 0.6, -0.8),
            Vec3::Y,
            // The spot lies 5° behind this surface's plane (2° beyond its
            // edge).
            {
                let perp = Vec3::new(0.0, -body.z, body.y);
                let a = 95f32.to_radians();
                (body * a.cos() + perp * a.sin()).normalize()
            },
        ] {
            let want = exact(n);
            for env in [&env, &with_aureole] {
                let e = env.cell_irradiance(n, |_| 1.0)[1];
                assert!((e / want - 1.0).abs() < 0.01, "{n}: {e} vs {want}");
            }
        }
    }

    /// The aureole's directions: the body first, then rings at their radii.
    #[test]
    fn aureole_rings_surround_the_body() {
        for body in [
            Vec3::new(0.3, 0.1, -0.9),
            Vec3::Y,
            Vec3::new(0.0, -0.2, 1.0),
        ] {
            let d = aureole_directions(body);
            assert_eq!(d.len(), AUREOLE_DIRECTIONS);
            let mut k = 0;
            for &(radius, n) in &AUREOLE_RINGS {
                for v in &d[k..k + n] {
                    let angle = v.dot(body.normalize()).clamp(-1.0, 1.0).acos().to_degrees();
                    assert!((v.length() - 1.0).abs() < 1e-5 && (angle - radius).abs() < 0.01);
                }
                k += n;
            }
        }
    }

    /// The BRDF table's A + B is the directional albedo of GGX with white
    /// F0: ≤ 1 (to the quadrature), near 1 for smooth surfaces seen head-on.
    #[test]
    fn brdf_table_is_energy_bounded() {
        let t = brdf_lut();
        let n = BRDF_LUT_SIZE;
        // ≤ 1 to the quadrature (256 Hammersley samples: within 1 %) from
        // N·V = 0.1 on; nearer grazing the estimator's 1/(N·V) weight
        // leaves a few per cent.
        for (k, v) in t.iter().enumerate().filter(|(k, _)| k % n >= n / 10) {
            assert!(
                v[0] >= 0.0 && v[1] >= 0.0 && v[0] + v[1] <= 1.0 + 1e-2,
                "N·V column {}, roughness row {}: {v:?}",
                k % n,
                k / n
            );
        }
        let smooth_head_on = t[n - 1];
        assert!(
            smooth_head_on[0] + smooth_head_on[1] > 0.95,
            "{smooth_head_on:?}"
        );
    }
}
