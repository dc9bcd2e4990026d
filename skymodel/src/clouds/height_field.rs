//! The low layer's cheap tier (`clouds.low.tier = "heightfield"`): the
//! seed thesis's height-field clouds after Dubé (2005, "Realistic cloud
//! rendering on modern GPUs").
//!
//! Once per frame the 3D density field is reduced to 2D maps over a square
//! around the observer ([`HeightField::build`]): per column (x, y) the
//! altitudes of the cloud's bottom and top (the lowest and highest of
//! [`COLUMN_SAMPLES`] samples through the slab whose extinction is above
//! 0, widened by half a sample) and the column's vertical optical depth
//! τ_v = ∫ σ dz, kept as the mean extinction σ̄ = τ_v / (top − bottom)
//! of the column's cloud. The cloud is then the volume between the two
//! height fields, of extinction σ̄ per column: every column keeps its
//! vertical optical depth, its interior structure is lost.
//!
//! A ray is intersected with that volume by a few probes
//! ([`HeightField::segment_depth`]): a probe is a straight segment of the
//! ray, its optical depth σ̄ times the length of the segment between the
//! bottom and the top of the column under the segment's midpoint
//! (bilinear over the four nearest columns: each column's own overlap,
//! weighted), so a probe many times longer than the cloud's thickness
//! still sees the thickness it traverses. The view ray takes `steps` / 4
//! probes across the slab (more on slant paths, as the volumetric march;
//! [`PROBE_DIVISOR`]).
//!
//! Lighting. Per light of the frame the maps also hold, per column, the
//! optical depth towards the light τ_l and away from it τ_b (the piece of
//! cloud beyond, ending at the first gap) at [`LIGHT_LEVELS`] altitudes
//! from the column's bottom to its top, each probed through the
//! height-field volume (`light_steps` probes) when the maps are built (a
//! slant light ray crosses many columns, so τ_l is far from linear in
//! altitude); a view probe takes them interpolated piecewise linearly in
//! altitude (bilinear over the nearest columns with cloud). Its source is the
//! volumetric tier's: single scattering through τ_l and the
//! multiple-scattering model of the march settings (the diffusion slab of
//! [`super::diffuse_source`] at the light's zenith cosine, plus the
//! forward lobes; or the octaves), and the sky's ambient light. There is
//! no surface orientation (a column's top is flat to it).
//!
//! The maps' texels: over a patch (`extent_km`) a regular grid of
//! 1/[`TEXELS_PER_CELL`] of a noise cell (coarser if the patch needs more
//! than [`MAX_MAP_TEXELS`] per side); over an unbounded layer a grid warped
//! per axis, x = a w / (1 − |w|) for w in (−1, 1), a =
//! [`MAX_MAP_TEXELS`]/2 texels of 1/[`TEXELS_PER_CELL`] cell: fine above
//! the observer, a texel (|x| + a)²/a² times wider at distance |x| (4×
//! at a, 16× at 3a), where a distant cloud covers a few pixels, and the
//! whole plane covered.
//!
//! What it costs: [`COLUMN_SAMPLES`] field samples per column (at most
//! [`MAX_MAP_TEXELS`]² columns) and 2 × [`LIGHT_LEVELS`] short probe
//! marches per column and light, once per frame; a pixel then reads the
//! maps (4 columns per probe) and evaluates no noise and marches no light
//! ray, where the volumetric march evaluates the 4-octave noise about 16
//! times per step (`cargo bench -p himmel-tests --bench clouds`: 22×
//! cheaper per ray).
//! What it loses: the column's vertical structure (two pieces of cloud
//! above each other are one), the flanks' orientation, and detail below
//! a texel. The cloud shadows on the ground keep the volumetric march
//! ([`super::optical_depth_ray`]).

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::field::LowField;
use super::march::{
    diffuse_source, forward_lobes, forward_source, inside_sphere, step_count, CloudHit, CloudLight,
    MarchSettings, MultipleScattering, Octaves, Shell, CLOUD_PHASE, MAX_FORWARD_ORDERS,
    MAX_MARCH_KM, OCTAVES,
};

/// Samples of the field through the slab per column of the maps.
pub const COLUMN_SAMPLES: u32 = 16;
/// Map texels per noise cell (the finest of the 4 octaves is 1/8 cell).
pub const TEXELS_PER_CELL: f32 = 32.0;
/// The most texels along a side of the maps.
pub const MAX_MAP_TEXELS: u32 = 256;
/// Altitudes per column, bottom to top, of the light maps.
pub const LIGHT_LEVELS: usize = 4;
/// The view ray's probes are the volumetric march's `steps` / this.
pub const PROBE_DIVISOR: u32 = 4;

/// The maps of one frame: per column, bottom and top altitude of the
/// cloud (km above the ground), its mean extinction (km⁻¹) and its
/// vertical optical depth, on an `n` × `n` grid of texels centred on the
/// observer (x East fastest, then y North); per light, the optical depths
/// towards and away from it from each column's bottom and top.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightField {
    /// Texels per side.
    pub n: u32,
    /// Half-width of the square a regular grid covers, km (a patch's).
    pub half_width_km: f32,
    /// Width of a regular grid's texel, km.
    pub texel_km: f32,
    /// The warp's distance a of an unbounded layer's grid, km (0: regular).
    pub warp_km: f32,
    /// [bottom km, top km, mean extinction km⁻¹, vertical optical depth]
    /// per column.
    pub columns: Vec<[f32; 4]>,
    /// Unit directions of the lights whose maps follow.
    pub light_dirs: Vec<Vec3>,
    /// Per light (2 `n`² entries each, in [`Self::light_dirs`]' order),
    /// per column: τ_l, then τ_b, at the [`LIGHT_LEVELS`] altitudes
    /// bottom + (top − bottom) · m / 3.
    pub light_columns: Vec<[f32; LIGHT_LEVELS]>,
}

/// A column without cloud.
const CLEAR_COLUMN: [f32; 4] = [0.0, 0.0, 0.0, 0.0];

/// The column of `field` at `xy`: bottom, top, mean extinction and
/// vertical optical depth ([`COLUMN_SAMPLES`] samples at the centres of
/// equal slices of the slab).
pub fn column(field: &LowField, xy: Vec2) -> [f32; 4] {
    let dz = field.thickness_km() / COLUMN_SAMPLES as f32;
    let (mut lo, mut hi, mut tau) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f32);
    for k in 0..COLUMN_SAMPLES {
        let h = field.base_km + (k as f32 + 0.5) * dz;
        let sigma = field.extinction(xy, h);
        if sigma > 0.0 {
            lo = lo.min(h - 0.5 * dz);
            hi = hi.max(h + 0.5 * dz);
            tau += sigma * dz;
        }
    }
    if tau > 0.0 && hi > lo {
        [lo, hi, tau / (hi - lo), tau]
    } else {
        CLEAR_COLUMN
    }
}

/// The optical depth of `column` over a straight segment `len` km long
/// from altitude `h0` to `h1`: its mean extinction times the part of the
/// segment between the column's bottom and top (the altitude is linear
/// along the segment).
#[inline]
pub fn column_depth(column: [f32; 4], h0: f32, h1: f32, len: f32) -> f32 {
    let [bottom, top, sigma, _] = column;
    if sigma <= 0.0 {
        return 0.0;
    }
    let (lo, hi) = (h0.min(h1), h0.max(h1));
    let inside = if hi - lo > 1e-6 {
        ((hi.min(top) - lo.max(bottom)) / (hi - lo)).max(0.0)
    } else if (bottom..=top).contains(&lo) {
        1.0
    } else {
        0.0
    };
    sigma * len * inside
}

impl HeightField {
    /// The maps of `field` for this frame and the lights `light_dirs` (unit,
    /// towards each), the light probes `light_steps` each, the gaps as the
    /// diffusion model of `settings` says.
    pub fn build(
        field: &LowField,
        shell: &Shell,
        light_dirs: &[Vec3],
        settings: &MarchSettings,
    ) -> HeightField {
        let fine = 1.0 / (field.inv_scale * TEXELS_PER_CELL);
        let (n, half_width_km, texel_km, warp_km) = if field.half_extent_km.is_finite() {
            let half = field.half_extent_km;
            let texel = fine.max(2.0 * half / MAX_MAP_TEXELS as f32);
            let n = ((2.0 * half / texel).ceil() as u32).clamp(1, MAX_MAP_TEXELS);
            (n, 0.5 * n as f32 * texel, texel, 0.0)
        } else {
            let n = MAX_MAP_TEXELS;
            (n, f32::INFINITY, fine, 0.5 * n as f32 * fine)
        };
        let mut hf = HeightField {
            n,
            half_width_km,
            texel_km,
            warp_km,
            columns: vec![CLEAR_COLUMN; (n * n) as usize],
            light_dirs: light_dirs.to_vec(),
            light_columns: vec![[0.0; LIGHT_LEVELS]; 2 * light_dirs.len() * (n * n) as usize],
        };
        let centres: Vec<f32> = (0..n).map(|i| hf.texel_centre(i)).collect();
        hf.columns
            .par_chunks_mut(n as usize)
            .enumerate()
            .for_each(|(j, row)| {
                for (i, c) in row.iter_mut().enumerate() {
                    *c = column(field, Vec2::new(centres[i], centres[j]));
                }
            });
        let gap = match settings.scattering {
            MultipleScattering::Diffusion(d) => d.gap_density * field.extinction_per_km,
            MultipleScattering::Octaves(_) => 0.0,
        };
        let mut light_columns = std::mem::take(&mut hf.light_columns);
        for (k, chunk) in light_columns.chunks_mut(2 * (n * n) as usize).enumerate() {
            let l = light_dirs[k];
            chunk.par_chunks_mut(2).enumerate().for_each(|(idx, out)| {
                let c = hf.columns[idx];
                if c[2] <= 0.0 {
                    return;
                }
                let xy = Vec2::new(centres[idx % n as usize], centres[idx / n as usize]);
                let at = |h: f32| {
                    let r = shell.r_ground + h;
                    Vec3::new(xy.x, xy.y, (r * r - xy.length_squared()).max(0.0).sqrt())
                };
                let steps = settings.light_steps;
                let towards = |h: f32| hf.depth_to_light(field, shell, at(h), l, steps);
                let away = |h: f32| hf.depth_connected(field, shell, at(h), -l, steps, gap);
                for m in 0..LIGHT_LEVELS {
                    let h = c[0] + (c[1] - c[0]) * m as f32 / (LIGHT_LEVELS - 1) as f32;
                    out[0][m] = towards(h);
                    out[1][m] = away(h);
                }
            });
        }
        hf.light_columns = light_columns;
        hf
    }

    /// The horizontal coordinate (km) of the centre of texel `i` along an
    /// axis.
    pub fn texel_centre(&self, i: u32) -> f32 {
        if self.warp_km > 0.0 {
            let w = (i as f32 + 0.5) * 2.0 / self.n as f32 - 1.0;
            self.warp_km * w / (1.0 - w.abs())
        } else {
            -self.half_width_km + (i as f32 + 0.5) * self.texel_km
        }
    }

    /// The continuous texel coordinate of `x` km along an axis (texel i's
    /// centre at i).
    pub fn texel_coordinate(&self, x: f32) -> f32 {
        if self.warp_km > 0.0 {
            let w = x / (x.abs() + self.warp_km);
            (w + 1.0) * 0.5 * self.n as f32 - 0.5
        } else {
            (x + self.half_width_km) / self.texel_km - 0.5
        }
    }

    /// The four texels around `xy` and their bilinear weights.
    fn corners(&self, xy: Vec2) -> [((i32, i32), f32); 4] {
        let u = Vec2::new(self.texel_coordinate(xy.x), self.texel_coordinate(xy.y));
        let (fi, fj) = (u.x.floor(), u.y.floor());
        let (fx, fy) = (u.x - fi, u.y - fj);
        let (i, j) = (fi as i32, fj as i32);
        [
            ((i, j), (1.0 - fx) * (1.0 - fy)),
            ((i + 1, j), fx * (1.0 - fy)),
            ((i, j + 1), (1.0 - fx) * fy),
            ((i + 1, j + 1), fx * fy),
        ]
    }

    /// The optical depths towards and away from light `k` of the maps
    /// at `xy` and altitude `h_km`: each column's interpolated piecewise
    /// linearly in altitude between its levels, weighted bilinearly over
    /// the nearest columns with cloud.
    pub fn light_depths(&self, k: usize, xy: Vec2, h_km: f32) -> (f32, f32) {
        let nn = (self.n * self.n) as usize;
        let (mut tl, mut tb, mut wsum) = (0.0, 0.0, 0.0);
        for ((i, j), w) in self.corners(xy) {
            let c = self.texel(i, j);
            if c[2] <= 0.0 || w <= 0.0 {
                continue;
            }
            let at = 2 * (k * nn + (j * self.n as i32 + i) as usize);
            let top = (LIGHT_LEVELS - 1) as f32;
            let f = ((h_km - c[0]) / (c[1] - c[0])).clamp(0.0, 1.0) * top;
            let m = (f.floor() as usize).min(LIGHT_LEVELS - 2);
            let r = f - m as f32;
            let lerp = |d: [f32; LIGHT_LEVELS]| d[m] + r * (d[m + 1] - d[m]);
            tl += w * lerp(self.light_columns[at]);
            tb += w * lerp(self.light_columns[at + 1]);
            wsum += w;
        }
        if wsum > 0.0 {
            (tl / wsum, tb / wsum)
        } else {
            (0.0, 0.0)
        }
    }

    /// The column of texel (i, j); clear outside the maps.
    #[inline]
    fn texel(&self, i: i32, j: i32) -> [f32; 4] {
        let n = self.n as i32;
        if i < 0 || j < 0 || i >= n || j >= n {
            return CLEAR_COLUMN;
        }
        self.columns[(j * n + i) as usize]
    }

    /// The optical depth of the height-field volume over the segment
    /// `len` km long from altitude `h0` to `h1` whose midpoint lies at
    /// `xy` (km East, North of the observer): [`column_depth`] of the four
    /// columns nearest `xy`, weighted bilinearly.
    pub fn segment_depth(&self, xy: Vec2, h0: f32, h1: f32, len: f32) -> f32 {
        self.corners(xy)
            .iter()
            .map(|&((i, j), w)| w * column_depth(self.texel(i, j), h0, h1, len))
            .sum()
    }

    /// The optical depth over `n` equal probes of the straight ray from
    /// `pos` (planet-centred, km) along the unit `dir` between distances
    /// `t0` and `t1`; with `gap` the sum ends at the first probe whose
    /// mean extinction is at most `gap` (the piece of cloud `pos`
    /// belongs to).
    fn ray_depth(
        &self,
        shell: &Shell,
        ray: (Vec3, Vec3),
        (t0, t1): (f32, f32),
        n: u32,
        gap: Option<f32>,
    ) -> f32 {
        let (pos, dir) = ray;
        let ds = (t1 - t0) / n as f32;
        let height = |t: f32| (pos + dir * t).length() - shell.r_ground;
        let mut tau = 0.0;
        for k in 0..n {
            let ta = t0 + k as f32 * ds;
            let mid = pos + dir * (ta + 0.5 * ds);
            let d = self.segment_depth(Vec2::new(mid.x, mid.y), height(ta), height(ta + ds), ds);
            if gap.is_some_and(|g| d <= g * ds) {
                break;
            }
            tau += d;
        }
        tau
    }

    /// The optical depth from `pos` towards the unit `l` to the top of the
    /// layer, in `n` probes.
    pub fn depth_to_light(
        &self,
        field: &LowField,
        shell: &Shell,
        pos: Vec3,
        l: Vec3,
        n: u32,
    ) -> f32 {
        let r = pos.length();
        let Some((_, d)) = inside_sphere(r, pos.dot(l) / r, shell.r_ground + field.top_km) else {
            return 0.0;
        };
        self.ray_depth(shell, (pos, l), (0.0, d.max(0.0)), n, None)
    }

    /// The optical depth of the layer along the ray from `pos` in the unit
    /// direction `dir` to where it leaves the layer, probed like the view
    /// ray of [`march_height_field`] (the transmittance of the direct Sun
    /// through the height-field volume when `dir` points at the Sun).
    pub fn depth_ray(
        &self,
        field: &LowField,
        shell: &Shell,
        pos: Vec3,
        dir: Vec3,
        steps: u32,
    ) -> f32 {
        let r = pos.length();
        let Some((t0, t1)) = shell.slab_from(r, pos.dot(dir) / r, field.base_km, field.top_km)
        else {
            return 0.0;
        };
        let t1 = t1.min(t0 + MAX_MARCH_KM);
        let probes = (steps / PROBE_DIVISOR).max(4);
        let n = step_count(t1 - t0, field.thickness_km(), probes);
        self.ray_depth(shell, (pos, dir), (t0, t1), n, None)
    }

    /// The optical depth of the piece of cloud at `pos` along the unit
    /// `dir` (towards where the ray leaves the layer, ending at the first
    /// probe of mean extinction at most `gap` km⁻¹), in `n` probes.
    pub fn depth_connected(
        &self,
        field: &LowField,
        shell: &Shell,
        pos: Vec3,
        dir: Vec3,
        n: u32,
        gap: f32,
    ) -> f32 {
        let r = pos.length();
        let Some((t0, t1)) = shell.slab_from(r, pos.dot(dir) / r, field.base_km, field.top_km)
        else {
            return 0.0;
        };
        self.ray_depth(shell, (pos, dir), (t0, t1), n, Some(gap))
    }
}

/// The light scattered towards the viewer per unit irradiance at a
/// probe, sr⁻¹: single scattering (or the octaves) through `tau`, plus,
/// with the diffusion model, the diffuse source of the column (`tau_b`
/// away from the light, light at the zenith cosine `mu0`) and the forward
/// lobes ([`super::march_low`]'s source without the surface's
/// orientation).
#[allow(clippy::too_many_arguments)]
fn probe_source(
    settings: &MarchSettings,
    octaves: Octaves,
    lobes: &[f32; MAX_FORWARD_ORDERS],
    cos_theta: f32,
    tau: f32,
    tau_b: f32,
    mu0: f32,
) -> f32 {
    let mut f = 0.0;
    let (mut ai, mut bi, mut k) = (1.0f32, 1.0f32, 1.0f32);
    for _ in 0..octaves.n.clamp(1, 8) {
        f += bi * CLOUD_PHASE.eval(cos_theta, k) * (-ai * tau).exp();
        ai *= octaves.a;
        bi *= octaves.b;
        k *= octaves.c;
    }
    if let MultipleScattering::Diffusion(d) = settings.scattering {
        f += diffuse_source(&d, tau, tau_b, mu0, cos_theta);
        f += forward_source(lobes, tau);
    }
    f
}

/// The view ray `view` through the height-field volume `hf` of `field`
/// (the volumetric [`super::march_low`]'s contract: lights at the cloud,
/// the sky's isotropic `ambient` radiance, linear sRGB, cd/m²). Light k
/// takes its optical depths from the maps when they were built for its
/// direction (`hf.light_dirs[k]`), else probes them through the volume.
pub fn march_height_field(
    hf: &HeightField,
    field: &LowField,
    shell: &Shell,
    view: Vec3,
    lights: &[CloudLight],
    ambient: [f32; 3],
    settings: &MarchSettings,
) -> CloudHit {
    let Some((t0, t1)) = shell.slab(view, field.base_km, field.top_km) else {
        return CloudHit::CLEAR;
    };
    let t1 = t1.min(t0 + MAX_MARCH_KM);
    let probes = (settings.steps / PROBE_DIVISOR).max(4);
    let n = step_count(t1 - t0, field.thickness_km(), probes);
    let dt = (t1 - t0) / n as f32;
    let origin = Vec3::new(0.0, 0.0, shell.r_observer);
    let height = |t: f32| (origin + view * t).length() - shell.r_ground;
    let (octaves, gap) = match settings.scattering {
        MultipleScattering::Octaves(o) => (o, 0.0),
        MultipleScattering::Diffusion(d) => (
            Octaves { n: 1, ..OCTAVES },
            d.gap_density * field.extinction_per_km,
        ),
    };
    let lobes: Vec<[f32; MAX_FORWARD_ORDERS]> = lights
        .iter()
        .map(|lt| match settings.scattering {
            MultipleScattering::Diffusion(d) => forward_lobes(&d, view.dot(lt.dir)),
            MultipleScattering::Octaves(_) => [0.0; MAX_FORWARD_ORDERS],
        })
        .collect();
    let mut hit = CloudHit::CLEAR;
    for s in 0..n {
        let ta = t0 + s as f32 * dt;
        let t = ta + 0.5 * dt;
        let pos = origin + view * t;
        let tau_seg = hf.segment_depth(Vec2::new(pos.x, pos.y), height(ta), height(ta + dt), dt);
        if tau_seg <= 0.0 {
            continue;
        }
        let mut src = [0.0f32; 3];
        for (k, (lt, lobes)) in lights.iter().zip(&lobes).enumerate() {
            let (tau, tau_b) = if hf
                .light_dirs
                .get(k)
                .is_some_and(|d| d.dot(lt.dir) > 0.999_999)
            {
                hf.light_depths(k, Vec2::new(pos.x, pos.y), height(t))
            } else {
                let n = settings.light_steps;
                (
                    hf.depth_to_light(field, shell, pos, lt.dir, n),
                    hf.depth_connected(field, shell, pos, -lt.dir, n, gap),
                )
            };
            let mu0 = pos.dot(lt.dir) / pos.length();
            let f = probe_source(settings, octaves, lobes, view.dot(lt.dir), tau, tau_b, mu0);
            for c in 0..3 {
                src[c] += f * lt.irradiance_rgb[c];
            }
        }
        let hf_frac = ((height(t) - field.base_km) / field.thickness_km()).clamp(0.0, 1.0);
        if hit.add(tau_seg, t, src, ambient, hf_frac) {
            break;
        }
    }
    hit.finish(t0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clouds::{march_low, optical_depth_low, MULTIPLE_SCATTERING};
    use crate::scene::LowCloudSpec;

    const RG: f32 = 6360.0;
    const SHELL: Shell = Shell {
        r_ground: RG,
        r_observer: RG,
    };
    const SETTINGS: MarchSettings = MarchSettings {
        steps: 64,
        light_steps: 6,
        scattering: MULTIPLE_SCATTERING,
    };

    fn field(extent_km: f64) -> LowField {
        LowField::new(
            &LowCloudSpec {
                coverage: 0.6,
                base_km: 1.0,
                top_km: 2.0,
                extinction_per_km: 20.0,
                scale_km: 1.5,
                extent_km,
                ..LowCloudSpec::default()
            },
            0.0,
        )
    }

    #[test]
    fn a_column_keeps_its_vertical_optical_depth() {
        let f = field(2.0);
        let mut seen = 0;
        for i in 0..50 {
            let xy = Vec2::new(-1.8 + 0.071 * i as f32, 0.9 - 0.037 * i as f32);
            let c = column(&f, xy);
            let dz = f.thickness_km() / 512.0;
            let fine: f32 = (0..512)
                .map(|k| f.extinction(xy, f.base_km + (k as f32 + 0.5) * dz) * dz)
                .sum();
            assert!((c[3] - fine).abs() <= 0.05 * fine + 0.05, "{c:?} {fine}");
            if c[3] > 0.0 {
                assert!(
                    c[0] >= f.base_km && c[1] <= f.top_km && c[0] < c[1],
                    "{c:?}"
                );
                let vertical = column_depth(c, f.base_km - 0.1, f.top_km + 0.1, 1.2);
                assert!(
                    (vertical - c[3]).abs() < 1e-3 * c[3].max(1.0),
                    "{vertical} {c:?}"
                );
                seen += 1;
            }
        }
        assert!(seen > 10, "{seen}");
    }

    #[test]
    fn segments_see_the_thickness_they_traverse() {
        let c = [1.2, 1.6, 10.0, 4.0];
        assert!((column_depth(c, 1.0, 2.0, 1.0) - 4.0).abs() < 1e-5);
        assert!((column_depth(c, 1.4, 2.0, 3.0) - 10.0 * 3.0 / 3.0).abs() < 1e-4);
        assert_eq!(column_depth(c, 1.7, 2.0, 1.0), 0.0);
        assert_eq!(column_depth(c, 1.3, 1.3, 0.5), 5.0);
        assert_eq!(column_depth(CLEAR_COLUMN, 1.0, 2.0, 1.0), 0.0);
    }

    /// The maps' transmittance of zenith-ish rays follows the volumetric
    /// march's, and the height-field march is finite, linear in the light
    /// and dark without it.
    #[test]
    fn the_height_field_march_follows_the_volume() {
        let f = field(2.0);
        let sun = Vec3::new(0.3, -0.5, 0.8).normalize();
        let hf = HeightField::build(&f, &SHELL, &[sun], &SETTINGS);
        assert!(hf.n > 32 && hf.n <= MAX_MAP_TEXELS, "{}", hf.n);
        let probed = HeightField::build(&f, &SHELL, &[], &SETTINGS);
        let light = |e: f32| {
            [CloudLight {
                dir: sun,
                irradiance_rgb: [e; 3],
            }]
        };
        let (mut mapped, mut marched) = (0.0f32, 0.0f32);
        let (mut err, mut sum, mut lit) = (0.0f32, 0.0f32, 0);
        for i in 0..80 {
            let a = i as f32 * 0.37;
            let v = Vec3::new(a.cos() * 0.3, a.sin() * 0.3, 0.95).normalize();
            let h1 = march_height_field(&hf, &f, &SHELL, v, &light(1.0), [0.0; 3], &SETTINGS);
            let h2 = march_height_field(&hf, &f, &SHELL, v, &light(2.0), [0.0; 3], &SETTINGS);
            let h0 = march_height_field(&hf, &f, &SHELL, v, &light(0.0), [0.0; 3], &SETTINGS);
            assert_eq!(h0.radiance, [0.0; 3]);
            assert!((h2.radiance[1] - 2.0 * h1.radiance[1]).abs() <= 1e-4 * h2.radiance[1]);
            assert!(h1.radiance[1].is_finite() && h1.radiance[1] >= 0.0);
            let t = (-optical_depth_low(&f, &SHELL, v, 64)).exp();
            err += (h1.transmittance - t).abs();
            sum += 1.0 - t;
            let vol = march_low(&f, &SHELL, v, &light(1.0), [0.0; 3], &SETTINGS);
            lit += (h1.radiance[1] > 0.0 && vol.radiance[1] > 0.0) as u32;
            let p = march_height_field(&probed, &f, &SHELL, v, &light(1.0), [0.0; 3], &SETTINGS);
            mapped += h1.radiance[1];
            marched += p.radiance[1];
        }
        assert!(err < 0.15 * sum, "{err} vs {sum}");
        assert!(lit > 20, "{lit}");
        // The light maps stand in for the probes towards the light.
        assert!(
            (mapped / marched - 1.0).abs() < 0.15,
            "{mapped} vs {marched}"
        );
    }

    #[test]
    fn an_unbounded_layer_gets_a_warped_grid() {
        let f = field(0.0);
        assert!(!f.half_extent_km.is_finite());
        let hf = HeightField::build(&f, &SHELL, &[Vec3::Z], &SETTINGS);
        assert_eq!(hf.n, MAX_MAP_TEXELS);
        assert!(hf.warp_km > 0.0);
        let fine = 1.0 / (f.inv_scale * TEXELS_PER_CELL);
        let mid = hf.n / 2;
        let w0 = hf.texel_centre(mid) - hf.texel_centre(mid - 1);
        assert!((w0 / fine - 1.0).abs() < 0.05, "{w0} vs {fine}");
        for i in [0, 3, mid - 7, mid, hf.n - 1] {
            let x = hf.texel_centre(i);
            assert!((hf.texel_coordinate(x) - i as f32).abs() < 1e-2, "{i} {x}");
        }
        assert!(
            hf.texel_centre(hf.n - 1) > MAX_MARCH_KM,
            "{}",
            hf.texel_centre(hf.n - 1)
        );
        let thick = hf.columns.iter().filter(|c| c[3] > 0.0).count();
        assert!(thick > 100, "{thick}");
    }
}
