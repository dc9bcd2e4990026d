//! The brute-force reference integrator: no LUTs, many scattering orders.
//!
//! Single scattering is a deterministic ray march of the view ray (fine
//! quadratic steps) with the Sun's transmittance ray-marched at every
//! sample. Orders two and higher are a Monte-Carlo path tracer in the same
//! medium: at each vertex a scattering point is drawn along the current
//! ray with probability proportional to the extinction at 550 nm (ray-marched
//! optical depth, "forced scattering"), the Sun is sampled explicitly
//! (next-event estimation with ray-marched transmittance and the same soft
//! Earth shadow), and the path continues in a direction drawn from the
//! phase function (Rayleigh: uniform sphere weighted by the phase;
//! Cornette–Shanks: Henyey–Greenstein importance sampling weighted by the
//! ratio) or, on the ground, a cosine-weighted Lambertian bounce. Paths
//! end by Russian roulette after four orders or at `max_orders`.
//!
//! This is slow (milliseconds per direction) and serves only the tests and
//! the accuracy table.

use glam::Vec3;

use super::lut::{column_densities, integrate_segment, optical_depth};
use super::medium::{
    cornette_shanks_phase, henyey_greenstein_phase, rayleigh_phase, safe_sqrt, Medium,
};
use crate::spectrum::{Spectrum, BANDS};

/// Settings of the reference integrator.
#[derive(Debug, Clone, Copy)]
pub struct ReferenceConfig {
    /// Steps along the view ray for single scattering.
    pub view_steps: usize,
    /// Steps along each ray towards the Sun.
    pub sun_steps: usize,
    /// Monte-Carlo paths per direction for orders ≥ 2 (0 = single scattering only).
    pub paths: usize,
    /// Highest scattering order followed.
    pub max_orders: usize,
    /// Steps for the optical-depth table along each path segment.
    pub segment_steps: usize,
    /// Random seed.
    pub seed: u64,
    /// Lowest order the Monte-Carlo part counts (2 normally; 1 checks the
    /// path tracer against the deterministic single scattering).
    pub mc_min_order: usize,
}

impl Default for ReferenceConfig {
    fn default() -> Self {
        ReferenceConfig {
            view_steps: 400,
            sun_steps: 120,
            paths: 2000,
            max_orders: 40,
            segment_steps: 96,
            seed: 0x5eed,
            mc_min_order: 2,
        }
    }
}

/// PCG32 random numbers (O'Neill 2014).
#[derive(Debug, Clone)]
pub struct Pcg32 {
    state: u64,
}

impl Pcg32 {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        let mut p = Pcg32 {
            state: seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407),
        };
        p.next_u32();
        p
    }
    /// Next 32 random bits.
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }
    /// Uniform in [0, 1).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}

/// Transmittance from `p` towards `sun` to space, ray-marched, times the
/// soft Earth shadow.
pub fn sun_transmittance_marched(m: &Medium, p: Vec3, sun: Vec3, steps: usize) -> Spectrum {
    let r = p.length();
    let mu = p.dot(sun) / r;
    let vis = m.sun_visibility(r, mu);
    if vis <= 0.0 {
        return Spectrum::ZERO;
    }
    let len = m.distance_to_top(r, mu);
    optical_depth(m, column_densities(m, r, mu, len, steps)).exp_neg() * vis
}

/// An orthonormal basis around `n`.
fn basis(n: Vec3) -> (Vec3, Vec3) {
    let a = if n.x.abs() > 0.9 { Vec3::Y } else { Vec3::X };
    let t = n.cross(a).normalize();
    (t, n.cross(t))
}

fn sample_hg(g: f32, dir: Vec3, rng: &mut Pcg32) -> Vec3 {
    let xi = rng.next_f32();
    let cos = if g.abs() < 1e-3 {
        1.0 - 2.0 * xi
    } else {
        let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * xi);
        ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
    };
    let sin = safe_sqrt(1.0 - cos * cos);
    let phi = std::f32::consts::TAU * rng.next_f32();
    let (t, b) = basis(dir);
    (dir * cos + t * (sin * phi.cos()) + b * (sin * phi.sin())).normalize()
}

fn sample_sphere(rng: &mut Pcg32) -> Vec3 {
    let z = 1.0 - 2.0 * rng.next_f32();
    let s = safe_sqrt(1.0 - z * z);
    let phi = std::f32::consts::TAU * rng.next_f32();
    Vec3::new(s * phi.cos(), s * phi.sin(), z)
}

fn sample_cosine(n: Vec3, rng: &mut Pcg32) -> Vec3 {
    let r = rng.next_f32().sqrt();
    let phi = std::f32::consts::TAU * rng.next_f32();
    let (t, b) = basis(n);
    let z = safe_sqrt(1.0 - r * r);
    (n * z + t * (r * phi.cos()) + b * (r * phi.sin())).normalize()
}

/// The reference sky radiance transfer factor (band radiance per unit
/// solar irradiance, sr⁻¹) seen from radius `r0` (km) in local direction
/// `view` (z up) with the Sun at local `sun`: single scattering plus, when
/// `cfg.paths > 0`, all higher orders by Monte Carlo.
pub fn radiance(m: &Medium, r0: f32, view: Vec3, sun: Vec3, cfg: &ReferenceConfig) -> Spectrum {
    let single = single_scattering(m, r0, view, sun, cfg);
    if cfg.paths == 0 {
        return single;
    }
    single + higher_orders(m, r0, view, sun, cfg)
}

/// Single scattering (plus the directly lit ground when the ray hits it).
pub fn single_scattering(
    m: &Medium,
    r0: f32,
    view: Vec3,
    sun: Vec3,
    cfg: &ReferenceConfig,
) -> Spectrum {
    let pos = Vec3::new(0.0, 0.0, r0);
    let mu = view.z;
    let (t_max, ground) = m.ray_end(r0, mu);
    let cos_theta = view.dot(sun);
    let pr = rayleigh_phase(cos_theta);
    let pm = cornette_shanks_phase(m.g, cos_theta);
    let mut tv = Spectrum::ONE;
    let mut l = Spectrum::ZERO;
    let mut t_prev = 0.0f32;
    let n = cfg.view_steps;
    for s in 0..n {
        let x = (s as f32 + 1.0) / n as f32;
        let t_next = t_max * x * x;
        let dt = t_next - t_prev;
        let t = 0.5 * (t_prev + t_next);
        t_prev = t_next;
        let p = pos + view * t;
        let d = m.densities(p.length());
        let (sr, sm) = m.scattering(d);
        let ext = m.extinction(d);
        let tsun = sun_transmittance_marched(m, p, sun, cfg.sun_steps);
        let seg = (ext * dt).exp_neg();
        l += tv * (sr * pr + sm * pm) * tsun * integrate_segment(ext, seg, dt);
        tv *= seg;
    }
    if ground {
        let pg = pos + view * t_max;
        let n = pg.normalize();
        let tsun = sun_transmittance_marched(m, pg, sun, cfg.sun_steps);
        l += tv * tsun * (n.dot(sun).max(0.0) * m.albedo / std::f32::consts::PI);
    }
    l
}

/// A segment of a path through the atmosphere with its optical-depth table
/// at the reference band (550–560 nm) and column densities.
struct Segment {
    t_max: f32,
    ground: bool,
    /// Cumulative column densities at the step boundaries.
    cols: Vec<[f32; 3]>,
    /// The column densities of the whole segment (the last of `cols`).
    total: [f32; 3],
    dt: f32,
}

const REF_BAND: usize = 4;

fn segment(m: &Medium, p: Vec3, d: Vec3, steps: usize) -> Segment {
    let r = p.length();
    let mu = p.dot(d) / r;
    let (t_max, ground) = m.ray_end(r, mu);
    let dt = t_max / steps as f32;
    let mut cols = Vec::with_capacity(steps + 1);
    let mut c = [0.0f32; 3];
    cols.push(c);
    for i in 0..steps {
        let q = p + d * ((i as f32 + 0.5) * dt);
        let dn = m.densities(q.length());
        c[0] += dn.rayleigh * dt;
        c[1] += dn.mie * dt;
        c[2] += dn.ozone * dt;
        cols.push(c);
    }
    Segment {
        t_max,
        ground,
        cols,
        total: c,
        dt,
    }
}

fn tau_ref(m: &Medium, c: [f32; 3]) -> f32 {
    m.rayleigh.0[REF_BAND] * c[0] + m.mie_extinction.0[REF_BAND] * c[1] + m.ozone.0[REF_BAND] * c[2]
}

/// Orders ≥ 2 by Monte Carlo (see the module documentation).
pub fn higher_orders(
    m: &Medium,
    r0: f32,
    view: Vec3,
    sun: Vec3,
    cfg: &ReferenceConfig,
) -> Spectrum {
    let mut rng = Pcg32::new(
        cfg.seed
            ^ (view.x.to_bits() as u64) << 1
            ^ (view.z.to_bits() as u64) << 29
            ^ (sun.z.to_bits() as u64) << 7,
    );
    let mut sum = Spectrum::ZERO;
    let start = Vec3::new(0.0, 0.0, r0);
    for _ in 0..cfg.paths {
        let mut p = start;
        let mut d = view;
        let mut beta = Spectrum::ONE;
        for order in 1..=cfg.max_orders {
            let seg = segment(m, p, d, cfg.segment_steps);
            let tau_tot = tau_ref(m, seg.total);
            // Choose the ground or the medium when the ray ends on the ground.
            let t_ground = (-tau_tot).exp();
            let p_ground = if seg.ground {
                t_ground.clamp(0.2, 0.8)
            } else {
                0.0
            };
            if seg.ground && rng.next_f32() < p_ground {
                let pg = p + d * seg.t_max;
                let n = pg.normalize();
                let tv = optical_depth(m, seg.total).exp_neg();
                beta = beta * tv * (1.0 / p_ground);
                if order >= cfg.mc_min_order {
                    let tsun = sun_transmittance_marched(m, pg, sun, cfg.sun_steps);
                    sum += beta * tsun * (n.dot(sun).max(0.0) * m.albedo / std::f32::consts::PI);
                }
                beta = beta * m.albedo;
                p = pg + n * 1e-3;
                d = sample_cosine(n, &mut rng);
            } else {
                // Medium: t with pdf σ_ref(t)/τ_tot.
                if tau_tot <= 1e-9 {
                    break;
                }
                let target = rng.next_f32() * tau_tot;
                let mut i = 0;
                while i + 1 < seg.cols.len() && tau_ref(m, seg.cols[i + 1]) < target {
                    i += 1;
                }
                let i = i.min(seg.cols.len() - 2);
                let t0 = tau_ref(m, seg.cols[i]);
                let t1 = tau_ref(m, seg.cols[i + 1]);
                let frac = if t1 > t0 {
                    ((target - t0) / (t1 - t0)).clamp(0.0, 1.0)
                } else {
                    0.5
                };
                let t = (i as f32 + frac) * seg.dt;
                let mut col = [0.0f32; 3];
                for k in 0..3 {
                    col[k] = seg.cols[i][k] + (seg.cols[i + 1][k] - seg.cols[i][k]) * frac;
                }
                let q = p + d * t;
                let dens = m.densities(q.length());
                let (sr, sm) = m.scattering(dens);
                let ext = m.extinction(dens);
                let sig_ref = ext.0[REF_BAND].max(1e-12);
                let tv = optical_depth(m, col).exp_neg();
                let w = tau_tot / sig_ref * (1.0 - p_ground).recip();
                // Pick Rayleigh or aerosol by their scattering at the reference band.
                let pr_sel = sr.0[REF_BAND] / (sr.0[REF_BAND] + sm.0[REF_BAND]).max(1e-20);
                let rayleigh = rng.next_f32() < pr_sel;
                let (sig, psel) = if rayleigh {
                    (sr, pr_sel)
                } else {
                    (sm, 1.0 - pr_sel)
                };
                if psel <= 0.0 {
                    break;
                }
                beta = beta * tv * sig * (w / psel);
                let cos_sun = d.dot(sun);
                if order >= cfg.mc_min_order {
                    let ph = if rayleigh {
                        rayleigh_phase(cos_sun)
                    } else {
                        cornette_shanks_phase(m.g, cos_sun)
                    };
                    let tsun = sun_transmittance_marched(m, q, sun, cfg.sun_steps);
                    sum += beta * tsun * ph;
                }
                // New direction.
                let nd = if rayleigh {
                    let nd = sample_sphere(&mut rng);
                    beta = beta * (rayleigh_phase(d.dot(nd)) * 4.0 * std::f32::consts::PI);
                    nd
                } else {
                    let nd = sample_hg(m.g, d, &mut rng);
                    let c = d.dot(nd);
                    beta = beta * (cornette_shanks_phase(m.g, c) / henyey_greenstein_phase(m.g, c));
                    nd
                };
                p = q;
                d = nd;
            }
            if order >= 4 {
                let q = beta.max_value().min(0.95);
                if q <= 0.0 || rng.next_f32() >= q {
                    break;
                }
                beta = beta * (1.0 / q);
            }
            if !beta.is_finite() {
                break;
            }
        }
    }
    let mut out = sum * (1.0 / cfg.paths as f32);
    for b in 0..BANDS {
        if !out.0[b].is_finite() {
            out.0[b] = 0.0;
        }
    }
    out
}
