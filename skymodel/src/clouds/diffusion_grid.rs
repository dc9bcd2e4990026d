//! A 3D estimate of the low layer's diffuse light: the diffusion (P1,
//! Eddington) equation solved on a coarse grid of cells over the cloud,
//! per light ([`DiffusionGrid::build`]), sampled by the view march and
//! blended with the column model of [`super::diffuse_source`]
//! ([`super::march_low_with_grids`], [`DiffusionGrid::diffuse`]: half
//! each by default, which is within 15 % of Mitsuba at Sun altitudes of
//! 20° and 60° where either alone is not, `tests/tests/cloud_mitsuba.rs`).
//!
//! The column model sees the cloud along one line through the point; the
//! light a low Sun puts into a cumulus's flank and lets out through its
//! base and its other flanks is 3D. Here the diffuse fluence U and flux F
//! (light scattered at least once, per unit irradiance of the light at
//! normal incidence, albedo 1, phase function of mean cosine g) obey the
//! P1 moments of the transfer equation with the attenuated direct beam
//! E_b = e^{−τ_l} travelling along ω₀ = −l as their source,
//!
//! ```text
//! ∇·F = σ E_b,    ∇U / 3 = −σ (1 − g) F + g σ E_b ω₀,
//! ```
//!
//! discretised by finite volumes on cubic cells of side h: the flux
//! through the face between cells i and j is
//! (U_i − U_j + R_i b_i + R_j b_j) / (R_i + R_j), R = 3 σ (1 − g) h / 2
//! (the half cell's resistance), b = g E_b ω₀ · n / (1 − g) (the beam's
//! forward scattering); a face towards clear air or out of the grid is
//! Marshak's vacuum condition, no diffuse light coming in: flux = U_face / 2,
//! i.e. (U_i + R_i b_i) / (2 + R_i). Cells whose optical depth σ h is
//! below `min_cell_depth` are clear (diffusion needs optical depth; a
//! wisp's light leaves it). The symmetric positive definite system is
//! solved by conjugate gradients (Jacobi preconditioned).
//!
//! A point of the view march takes U and F trilinearly from the cloudy
//! cells around it and scatters (U − 3 g F · v) / 4π towards the viewer
//! (v the view direction).
//!
//! What it costs: per light, `subsamples`³ field samples per cell for its
//! extinction, a light march per cell for E_b, and the solve (a few
//! hundred sweeps over the cells), once per Sun direction; the view
//! march then reads 8 cells per step instead of its second light march.
//! What it loses: light that leaves one cloud and enters another (a gap is
//! a vacuum), structure below a cell.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::field::LowField;
use super::march::{optical_depth_to_light, Shell};

/// How the grid is laid out and solved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSettings {
    /// Cell side, km.
    pub cell_km: f32,
    /// Half-width of the grid around the observer where the layer is
    /// unbounded, km (a patch's own half-width otherwise, if smaller).
    pub max_half_width_km: f32,
    /// Field samples per cell side for its mean extinction.
    pub subsamples: u32,
    /// Cells thinner than this optical depth (σ h) are clear.
    pub min_cell_depth: f32,
    /// Mean cosine of the phase function.
    pub g: f32,
    /// Scale of the diffuse source.
    pub gain: f32,
    /// The grid's weight against the column model of
    /// [`super::diffuse_source`] ([`DiffusionGrid::diffuse`]).
    pub weight: f32,
    /// Length of the light march's steps for the direct beam, km.
    pub beam_step_km: f32,
    /// The most steps of a beam's light march (a light near or below the
    /// horizon takes longer steps, not more).
    pub max_beam_steps: u32,
    /// Conjugate-gradient iterations at most.
    pub max_iterations: u32,
    /// Relative residual at which the solve stops.
    pub tolerance: f32,
}

/// The grid both backends use.
pub const GRID: GridSettings = GridSettings {
    cell_km: 0.2,
    max_half_width_km: 8.0,
    subsamples: 2,
    min_cell_depth: 0.1,
    g: super::march::DIFFUSION.g,
    gain: 1.0,
    weight: 0.5,
    beam_step_km: 0.1,
    max_beam_steps: 48,
    max_iterations: 600,
    tolerance: 1e-4,
};

/// Why a grid cannot be built.
#[derive(Debug, Clone, PartialEq)]
pub enum GridError {
    /// A setting is out of range.
    Setting(&'static str),
    /// The grid would have this many cells, more than [`MAX_CELLS`].
    TooLarge(usize),
}

impl std::fmt::Display for GridError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GridError::Setting(s) => write!(f, "invalid diffusion grid setting: {s}"),
            GridError::TooLarge(n) => {
                write!(
                    f,
                    "diffusion grid of {n} cells exceeds the limit {MAX_CELLS}"
                )
            }
        }
    }
}

impl std::error::Error for GridError {}

/// Cells over which the grid's weight falls to 0 at its edge over an
/// unbounded layer ([`DiffusionGrid::fade_km`]).
pub const FADE_CELLS: f32 = 8.0;

/// The most cells a grid may have.
pub const MAX_CELLS: usize = 1 << 23;

/// The solved grid of one light.
#[derive(Debug, Clone, PartialEq)]
pub struct DiffusionGrid {
    /// Unit direction towards the light.
    pub light: Vec3,
    /// Corner of the grid: x, y (km East, North) and altitude, km.
    pub origin: Vec3,
    /// Cell side, km.
    pub cell_km: f32,
    /// Cells along x, y, z.
    pub dims: [usize; 3],
    /// Per cell: U, F_x, F_y, F_z (per unit irradiance, × gain); all 0 in
    /// a clear cell.
    pub cells: Vec<[f32; 4]>,
    /// Per cell: whether it is cloud.
    pub cloudy: Vec<bool>,
    /// Conjugate-gradient iterations the solve took.
    pub iterations: u32,
    /// The beam's light the cloud scattered, Σ σ E_b h³ over the cells
    /// (km², per unit irradiance; before the gain).
    pub scattered: f32,
    /// The diffuse light leaving the cloud through faces towards clear
    /// air, Σ flux × h² (km²; equals [`Self::scattered`] once solved).
    pub escaped: f32,
    /// Mean cosine of the phase function (the flux's weight).
    pub g: f32,
    /// The grid's weight against the column model ([`Self::diffuse`]).
    pub weight: f32,
    /// Half-width of the square the grid covers around the observer, km.
    pub half_width_km: f32,
    /// The field's wind offset the grid was built or moved for, km.
    pub offset_km: Vec2,
    /// Over an unbounded layer, the width of the band inside the grid's
    /// edge over which the weight falls to 0 (the grid's sides are no
    /// real cloud edge), km; 0 over a patch the grid covers.
    pub fade_km: f32,
}

/// The six neighbours' offsets and unit normals.
const FACES: [([i64; 3], Vec3); 6] = [
    ([-1, 0, 0], Vec3::NEG_X),
    ([1, 0, 0], Vec3::X),
    ([0, -1, 0], Vec3::NEG_Y),
    ([0, 1, 0], Vec3::Y),
    ([0, 0, -1], Vec3::NEG_Z),
    ([0, 0, 1], Vec3::Z),
];

/// The system of the solve: per cell its resistance R, its beam term
/// magnitude E_b g/(1 − g) and its source σ E_b h.
struct System {
    dims: [usize; 3],
    cloudy: Vec<bool>,
    r: Vec<f32>,
    beam: Vec<f32>,
    source: Vec<f32>,
    omega0: Vec3,
}

impl System {
    fn neighbour(&self, i: usize, off: [i64; 3]) -> Option<usize> {
        let [nx, ny, nz] = self.dims;
        let (x, y, z) = (i % nx, (i / nx) % ny, i / (nx * ny));
        let q = [x as i64 + off[0], y as i64 + off[1], z as i64 + off[2]];
        if q[0] < 0 || q[1] < 0 || q[2] < 0 {
            return None;
        }
        let q = [q[0] as usize, q[1] as usize, q[2] as usize];
        if q[0] >= nx || q[1] >= ny || q[2] >= nz {
            return None;
        }
        let j = q[0] + nx * (q[1] + ny * q[2]);
        self.cloudy[j].then_some(j)
    }

    /// b of cell `i` through the face of normal `n`.
    fn b(&self, i: usize, n: Vec3) -> f32 {
        self.beam[i] * self.omega0.dot(n)
    }

    /// The outward diffuse flux of cloudy cell `i` through each face
    /// given the fluence `u`.
    fn face_fluxes(&self, i: usize, u: &[f32]) -> [f32; 6] {
        let mut out = [0.0; 6];
        for (o, (off, n)) in out.iter_mut().zip(FACES) {
            let ri = self.r[i];
            *o = match self.neighbour(i, off) {
                Some(j) => {
                    let rj = self.r[j];
                    (u[i] - u[j] + ri * self.b(i, n) + rj * self.b(j, n)) / (ri + rj)
                }
                None => (u[i] + ri * self.b(i, n)) / (2.0 + ri),
            };
        }
        out
    }

    /// (A u)_i and the diagonal A_ii of the linear part of the balance.
    fn apply(&self, u: &[f32], out: &mut [f32]) {
        out.par_iter_mut().enumerate().for_each(|(i, o)| {
            if !self.cloudy[i] {
                *o = 0.0;
                return;
            }
            let ri = self.r[i];
            let mut s = 0.0;
            for (off, _) in FACES {
                s += match self.neighbour(i, off) {
                    Some(j) => (u[i] - u[j]) / (ri + self.r[j]),
                    None => u[i] / (2.0 + ri),
                };
            }
            *o = s;
        });
    }

    fn diagonal(&self, i: usize) -> f32 {
        let ri = self.r[i];
        FACES
            .iter()
            .map(|&(off, _)| match self.neighbour(i, off) {
                Some(j) => 1.0 / (ri + self.r[j]),
                None => 1.0 / (2.0 + ri),
            })
            .sum()
    }

    /// The right-hand side: the source less the beam terms of the faces.
    fn rhs(&self) -> Vec<f32> {
        (0..self.r.len())
            .into_par_iter()
            .map(|i| {
                if !self.cloudy[i] {
                    return 0.0;
                }
                let ri = self.r[i];
                let mut s = self.source[i];
                for (off, n) in FACES {
                    s -= match self.neighbour(i, off) {
                        Some(j) => {
                            let rj = self.r[j];
                            (ri * self.b(i, n) + rj * self.b(j, n)) / (ri + rj)
                        }
                        None => ri * self.b(i, n) / (2.0 + ri),
                    };
                }
                s
            })
            .collect()
    }
}

fn dot(a: &[f32], b: &[f32]) -> f64 {
    a.par_iter()
        .zip(b)
        .map(|(x, y)| *x as f64 * *y as f64)
        .sum()
}

/// Conjugate gradients on `sys` (Jacobi preconditioned): the fluence and
/// the iterations taken.
fn solve(sys: &System, max_iterations: u32, tolerance: f32) -> (Vec<f32>, u32) {
    let n = sys.r.len();
    let b = sys.rhs();
    let inv_diag: Vec<f32> = (0..n)
        .into_par_iter()
        .map(|i| {
            if sys.cloudy[i] {
                1.0 / sys.diagonal(i)
            } else {
                0.0
            }
        })
        .collect();
    let mut x = vec![0.0f32; n];
    let mut r = b.clone();
    let mut z: Vec<f32> = r.iter().zip(&inv_diag).map(|(a, d)| a * d).collect();
    let mut p = z.clone();
    let mut ap = vec![0.0f32; n];
    let mut rz = dot(&r, &z);
    let b_norm = dot(&b, &b).sqrt();
    if b_norm <= 0.0 {
        return (x, 0);
    }
    for it in 0..max_iterations {
        sys.apply(&p, &mut ap);
        let pap = dot(&p, &ap);
        if pap <= 0.0 {
            return (x, it);
        }
        let alpha = (rz / pap) as f32;
        x.par_iter_mut()
            .zip(r.par_iter_mut())
            .zip(p.par_iter().zip(&ap))
            .for_each(|((xi, ri), (pi, api))| {
                *xi += alpha * pi;
                *ri -= alpha * api;
            });
        if dot(&r, &r).sqrt() <= tolerance as f64 * b_norm {
            return (x, it + 1);
        }
        z.par_iter_mut()
            .zip(r.par_iter().zip(&inv_diag))
            .for_each(|(zi, (ri, di))| *zi = ri * di);
        let rz_new = dot(&r, &z);
        let beta = (rz_new / rz) as f32;
        rz = rz_new;
        p.par_iter_mut()
            .zip(&z)
            .for_each(|(pi, zi)| *pi = zi + beta * *pi);
    }
    (x, max_iterations)
}

impl DiffusionGrid {
    /// Builds and solves the grid of `field` lit from the unit direction
    /// `light` (observer frame) with `settings`.
    pub fn build(
        field: &LowField,
        shell: &Shell,
        light: Vec3,
        settings: &GridSettings,
    ) -> Result<Self, GridError> {
        let s = settings;
        if !(s.cell_km > 0.0 && s.max_half_width_km > 0.0 && s.beam_step_km > 0.0) {
            return Err(GridError::Setting("cell, width and beam step must be > 0"));
        }
        if s.subsamples == 0 || !(0.0..1.0).contains(&s.g) || !(0.0..=1.0).contains(&s.weight) {
            return Err(GridError::Setting(
                "subsamples ≥ 1, g in [0, 1), weight in [0, 1]",
            ));
        }
        let half = field.half_extent_km.min(s.max_half_width_km);
        let unbounded = half < field.half_extent_km;
        // Over an unbounded layer the cells move with the wind's field
        // (the corner shifted by the wind offset modulo a cell, one more
        // cell per side): a translated field gives the same cells.
        let (corner, extra) = if unbounded {
            let shift = |o: f32| o.rem_euclid(s.cell_km) - s.cell_km;
            (
                Vec2::new(
                    -half + shift(field.offset_km.x),
                    -half + shift(field.offset_km.y),
                ),
                1,
            )
        } else {
            (Vec2::splat(-half), 0)
        };
        let nxy = ((2.0 * half / s.cell_km).ceil() as usize).max(1) + extra;
        let nz = ((field.thickness_km() / s.cell_km).ceil() as usize).max(1);
        let count = nxy * nxy * nz;
        if count > MAX_CELLS {
            return Err(GridError::TooLarge(count));
        }
        let h = s.cell_km;
        let origin = Vec3::new(corner.x, corner.y, field.base_km);
        let sub = s.subsamples;
        let centre = |i: usize| -> Vec3 {
            let (x, y, z) = (i % nxy, (i / nxy) % nxy, i / (nxy * nxy));
            origin + Vec3::new(x as f32 + 0.5, y as f32 + 0.5, z as f32 + 0.5) * h
        };
        let sub_offset = |m: u32| ((m as f32 + 0.5) / sub as f32 - 0.5) * h;
        let beam_at = |p: Vec3| {
            let pos = Vec3::new(p.x, p.y, shell.r_ground + p.z);
            let mu = light.z.max(1e-3);
            let steps = (((field.top_km - p.z) / mu / s.beam_step_km).ceil() as u32)
                .clamp(1, s.max_beam_steps.max(1));
            (-optical_depth_to_light(field, shell, pos, light, steps)).exp()
        };
        // Per cell: mean σ, mean σ E_b and mean E_b over its sub-samples.
        let samples: Vec<[f32; 3]> = (0..count)
            .into_par_iter()
            .map(|i| {
                let c = centre(i);
                let mut acc = [0.0f32; 3];
                for a in 0..sub {
                    for b in 0..sub {
                        for k in 0..sub {
                            let p = c + Vec3::new(sub_offset(a), sub_offset(b), sub_offset(k));
                            let sigma = field.extinction(Vec2::new(p.x, p.y), p.z);
                            if sigma > 0.0 {
                                let e = beam_at(p);
                                acc[0] += sigma;
                                acc[1] += sigma * e;
                                acc[2] += e;
                            }
                        }
                    }
                }
                acc.map(|v| v / (sub * sub * sub) as f32)
            })
            .collect();
        let sigma: Vec<f32> = samples.iter().map(|v| v[0]).collect();
        let cloudy: Vec<bool> = sigma.iter().map(|&x| x * h >= s.min_cell_depth).collect();
        let beam: Vec<f32> = samples.iter().map(|v| v[2]).collect();
        let sys = System {
            dims: [nxy, nxy, nz],
            r: sigma.iter().map(|&x| 1.5 * x * (1.0 - s.g) * h).collect(),
            source: samples.iter().map(|v| v[1] * h).collect(),
            beam: beam.iter().map(|&e| e * s.g / (1.0 - s.g)).collect(),
            cloudy,
            omega0: -light,
        };
        let (u, iterations) = solve(&sys, s.max_iterations, s.tolerance);
        let escaped: f64 = (0..count)
            .into_par_iter()
            .filter(|&i| sys.cloudy[i])
            .map(|i| {
                let f = sys.face_fluxes(i, &u);
                FACES
                    .iter()
                    .zip(f)
                    .filter(|((off, _), _)| sys.neighbour(i, *off).is_none())
                    .map(|(_, x)| x as f64)
                    .sum::<f64>()
            })
            .sum();
        let scattered: f64 = (0..count)
            .filter(|&i| sys.cloudy[i])
            .map(|i| sys.source[i] as f64)
            .sum();
        let cells = (0..count)
            .into_par_iter()
            .map(|i| {
                if !sys.cloudy[i] {
                    return [0.0; 4];
                }
                let f = sys.face_fluxes(i, &u);
                // Outward fluxes of opposite faces: F_x = (out₊ − out₋)/2.
                [
                    s.gain * u[i],
                    s.gain * 0.5 * (f[1] - f[0]),
                    s.gain * 0.5 * (f[3] - f[2]),
                    s.gain * 0.5 * (f[5] - f[4]),
                ]
            })
            .collect();
        Ok(DiffusionGrid {
            light,
            origin,
            cell_km: h,
            dims: [nxy, nxy, nz],
            cells,
            cloudy: sys.cloudy,
            iterations,
            scattered: (scattered * (h * h) as f64) as f32,
            escaped: (escaped * (h * h) as f64) as f32,
            g: s.g,
            weight: s.weight,
            half_width_km: half,
            offset_km: field.offset_km,
            fade_km: if unbounded { FADE_CELLS * h } else { 0.0 },
        })
    }

    /// This grid moved with the wind to `field`'s offset, where that is the
    /// grid [`Self::build`] would give for `field` and the same light: over
    /// an unbounded layer the cells are the field's own lattice, so while
    /// the offset stays within the same lattice step the cells hold the
    /// same cloud and only the corner moves; over a patch the grid stays
    /// put, so only an unchanged offset keeps it. `None`: build anew.
    pub fn follow(&self, field: &LowField) -> Option<DiffusionGrid> {
        let h = self.cell_km;
        if self.fade_km == 0.0 {
            return (field.offset_km == self.offset_km).then(|| self.clone());
        }
        let step = |o: Vec2| ((o.x / h).floor(), (o.y / h).floor());
        if step(field.offset_km) != step(self.offset_km) {
            return None;
        }
        let shift = |o: f32| o.rem_euclid(h) - h;
        let corner = Vec2::new(
            -self.half_width_km + shift(field.offset_km.x),
            -self.half_width_km + shift(field.offset_km.y),
        );
        let mut g = self.clone();
        g.origin = Vec3::new(corner.x, corner.y, self.origin.z);
        g.offset_km = field.offset_km;
        Some(g)
    }

    /// U and F at horizontal position `xy` (km) and altitude `h_km`:
    /// trilinear over the cloudy cells around it, weights renormalised;
    /// `None` outside the grid or with no cloudy cell around.
    pub fn sample(&self, xy: Vec2, h_km: f32) -> Option<(f32, Vec3)> {
        let q = (Vec3::new(xy.x, xy.y, h_km) - self.origin) / self.cell_km - Vec3::splat(0.5);
        let [nx, ny, nz] = self.dims;
        let base = q.floor();
        let fr = q - base;
        let mut acc = [0.0f32; 4];
        let mut wsum = 0.0;
        for corner in 0..8 {
            let d = [corner & 1, (corner >> 1) & 1, (corner >> 2) & 1];
            let c = [
                base.x as i64 + d[0] as i64,
                base.y as i64 + d[1] as i64,
                base.z as i64 + d[2] as i64,
            ];
            if c.iter().any(|&v| v < 0) {
                continue;
            }
            let c = [c[0] as usize, c[1] as usize, c[2] as usize];
            if c[0] >= nx || c[1] >= ny || c[2] >= nz {
                continue;
            }
            let i = c[0] + nx * (c[1] + ny * c[2]);
            if !self.cloudy[i] {
                continue;
            }
            let w = [fr.x, fr.y, fr.z]
                .iter()
                .zip(d)
                .map(|(f, dd)| if dd == 1 { *f } else { 1.0 - f })
                .product::<f32>();
            for (a, v) in acc.iter_mut().zip(self.cells[i]) {
                *a += w * v;
            }
            wsum += w;
        }
        (wsum > 1e-6).then(|| (acc[0] / wsum, Vec3::new(acc[1], acc[2], acc[3]) / wsum))
    }

    /// The diffuse source towards the viewer looking along `view` at
    /// `xy`, `h_km`, per unit irradiance, sr⁻¹: (U − 3 g F · v) / 4π.
    pub fn source(&self, xy: Vec2, h_km: f32, view: Vec3) -> Option<f32> {
        self.sample(xy, h_km)
            .map(|(u, f)| (u - 3.0 * self.g * f.dot(view)).max(0.0) / (4.0 * std::f32::consts::PI))
    }

    /// The diffuse source the view march uses at `xy`, `h_km` given the
    /// column model's `column` there ([`super::diffuse_source`]):
    /// [`Self::weight`] × the grid's [`Self::source`] + (1 − weight) ×
    /// `column`; `column` where the grid has no cloud.
    pub fn diffuse(&self, column: f32, xy: Vec2, h_km: f32, view: Vec3) -> f32 {
        let w = self.weight_at(xy);
        if w <= 0.0 {
            return column;
        }
        match self.source(xy, h_km, view) {
            Some(grid) => w * grid + (1.0 - w) * column,
            None => column,
        }
    }

    /// [`Self::weight`] at `xy`, faded to 0 over [`Self::fade_km`] inside
    /// the grid's edge.
    pub fn weight_at(&self, xy: Vec2) -> f32 {
        if self.fade_km <= 0.0 {
            return self.weight;
        }
        let half = self.half_width_km;
        let inside = half - xy.x.abs().max(xy.y.abs());
        self.weight * (inside / self.fade_km).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud_spec::LowCloudSpec;

    const SHELL: Shell = Shell {
        r_ground: 6360.0,
        r_observer: 6360.0,
    };

    fn field() -> LowField {
        LowField::new(
            &LowCloudSpec {
                coverage: 0.6,
                extent_km: 2.0,
                base_km: 1.0,
                top_km: 2.0,
                extinction_per_km: 20.0,
                scale_km: 1.5,
                seed: 3,
                ..LowCloudSpec::default()
            },
            0.0,
        )
    }

    fn grid(light: Vec3) -> DiffusionGrid {
        let settings = GridSettings {
            cell_km: 0.2,
            tolerance: 1e-6,
            ..GRID
        };
        DiffusionGrid::build(&field(), &SHELL, light, &settings).unwrap()
    }

    /// The solve conserves energy: the diffuse light leaving the cloud
    /// through its faces to clear air equals the beam's light the cloud
    /// scattered (albedo 1), each cell's balance summed.
    #[test]
    fn what_the_beam_puts_in_leaves_through_the_faces() {
        let light = Vec3::new(0.3, 0.2, 0.5).normalize();
        let f = field();
        let settings = GridSettings {
            cell_km: 0.2,
            tolerance: 1e-7,
            max_iterations: 2000,
            gain: 1.0,
            ..GRID
        };
        let g = DiffusionGrid::build(&f, &SHELL, light, &settings).unwrap();
        assert!(g.cloudy.iter().filter(|&&c| c).count() > 20);
        assert!(g.iterations < settings.max_iterations, "{}", g.iterations);
        assert!(g.scattered > 0.0);
        let balance = g.escaped / g.scattered;
        assert!((balance - 1.0).abs() < 1e-3, "{balance}");
        assert!(g.cells.iter().all(|c| c[0] >= -1e-4), "negative fluence");
    }

    /// A brighter beam (the light higher, a shorter path through the
    /// cloud) gives more diffuse light overall.
    #[test]
    fn a_higher_light_lights_the_cloud_more() {
        let total = |alt: f32| -> f32 {
            let l = Vec3::new(alt.cos(), 0.0, alt.sin());
            grid(l).cells.iter().map(|c| c[0]).sum()
        };
        let (low, high) = (total(0.35), total(1.2));
        assert!(high > low, "{low} {high}");
    }

    /// Over an unbounded layer the cells move with the field: the wind
    /// carrying it 1.234 km gives the same diffuse light 1.234 km
    /// downwind (away from the grid's edges).
    #[test]
    fn the_cells_follow_the_wind() {
        let mut f = field();
        f.half_extent_km = f32::INFINITY;
        let settings = GridSettings {
            cell_km: 0.2,
            max_half_width_km: 4.0,
            ..GRID
        };
        let light = Vec3::new(0.5, 0.2, 0.6).normalize();
        let a = DiffusionGrid::build(&f, &SHELL, light, &settings).unwrap();
        let shift = Vec2::new(1.234, -0.567);
        f.offset_km += shift;
        let b = DiffusionGrid::build(&f, &SHELL, light, &settings).unwrap();
        let (mut n, mut worst) = (0, 0.0f32);
        for i in 0..20 {
            for j in 0..20 {
                for k in 0..5 {
                    let xy = Vec2::new(-1.5 + 0.09 * i as f32, -0.8 + 0.09 * j as f32);
                    let h = 1.1 + 0.2 * k as f32;
                    if let (Some((ua, _)), Some((ub, _))) =
                        (a.sample(xy, h), b.sample(xy + shift, h))
                    {
                        n += 1;
                        worst = worst.max((ua - ub).abs() / ua.max(ub).max(1e-3));
                    }
                }
            }
        }
        assert!(n > 50, "{n}");
        assert!(worst < 0.05, "{worst}");
    }

    /// A grid moved with the wind within a lattice step is the grid a
    /// build gives there (the same cells, the same solve); a step further,
    /// or any move of a patch, asks for a build.
    #[test]
    fn a_grid_follows_the_wind_within_a_cell() {
        let mut f = field();
        f.half_extent_km = f32::INFINITY;
        let settings = GridSettings {
            cell_km: 0.2,
            max_half_width_km: 2.0,
            ..GRID
        };
        let light = Vec3::new(0.5, 0.2, 0.6).normalize();
        f.offset_km = Vec2::new(0.41, 0.83);
        let a = DiffusionGrid::build(&f, &SHELL, light, &settings).unwrap();
        f.offset_km = Vec2::new(0.47, 0.89);
        let moved = a.follow(&f).unwrap();
        let built = DiffusionGrid::build(&f, &SHELL, light, &settings).unwrap();
        assert!(
            (moved.origin - built.origin).length() < 1e-5,
            "{:?} vs {:?}",
            moved.origin,
            built.origin
        );
        assert_eq!(moved.dims, built.dims);
        // The same cells up to the float rounding of their sample points
        // and the solve's parallel sums.
        let worst = moved
            .cells
            .iter()
            .zip(&built.cells)
            .map(|(a, b)| (a[0] - b[0]).abs())
            .fold(0.0f32, f32::max);
        let peak = built.cells.iter().map(|c| c[0]).fold(0.0f32, f32::max);
        assert!(peak > 0.1 && worst < 1e-3 * peak, "{worst} of {peak}");
        f.offset_km = Vec2::new(0.61, 0.83);
        assert!(a.follow(&f).is_none());
        let mut patch = field();
        let p = DiffusionGrid::build(&patch, &SHELL, light, &settings).unwrap();
        assert_eq!(p.follow(&patch).as_ref(), Some(&p));
        patch.offset_km += Vec2::new(0.01, 0.0);
        assert!(p.follow(&patch).is_none());
    }

    #[test]
    fn sampling_outside_the_cloud_is_none_and_settings_are_checked() {
        let g = grid(Vec3::Z);
        assert!(g.sample(Vec2::new(5.0, 5.0), 1.3).is_none());
        assert!(g.sample(Vec2::ZERO, 0.5).is_none());
        assert_eq!(g.diffuse(0.25, Vec2::new(5.0, 5.0), 1.3, Vec3::Z), 0.25);
        let bad = GridSettings {
            cell_km: 0.0,
            ..GRID
        };
        assert!(matches!(
            DiffusionGrid::build(&field(), &SHELL, Vec3::Z, &bad),
            Err(GridError::Setting(_))
        ));
        let huge = GridSettings {
            cell_km: 1e-3,
            ..GRID
        };
        assert!(matches!(
            DiffusionGrid::build(&field(), &SHELL, Vec3::Z, &huge),
            Err(GridError::TooLarge(_))
        ));
    }
}
