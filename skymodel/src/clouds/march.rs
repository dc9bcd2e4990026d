//! Lighting the cloud fields: the view ray's march through the low layer
//! ([`march_low`]), its optical depth alone ([`optical_depth_low`], also
//! the cloud shadow of the direct beam), and the thin high layer
//! ([`shade_high`]).
//!
//! Geometry: the Earth is a sphere of radius `r_ground`; the observer
//! stands at radius `r_observer` on its local vertical (z); a point at
//! distance t along the unit view direction v is P = (0, 0, r₀) + t v,
//! its altitude |P| − r_ground and its horizontal position (v_x t, v_y t)
//! (the noise is planar; over a 4 km patch the two differ by < 1 m).
//!
//! The low layer's march (Hillaire 2016, "Physically based sky,
//! atmosphere and cloud rendering in Frostbite", §5): per step of length
//! Δt with extinction σ (σ_s = σ, albedo 1) the scattered source S is
//! integrated analytically over the step,
//!
//! ```text
//! L += T · S · (1 − e^{−σΔt}),   T ← T · e^{−σΔt},
//! ```
//!
//! and S sums, for each light of irradiance E in direction l, the single
//! scattering p(θ) E e^{−τ_l} (τ_l the optical depth towards the light, a
//! short march of `light_steps` steps to the top of the layer), the light
//! scattered more than once ([`MultipleScattering`]) and the sky's ambient
//! light. Two models of the multiple scattering:
//!
//! * [`MultipleScattering::Diffusion`] (the default): the column through
//!   the point along the light is taken as a plane-parallel slab lit at
//!   the light's zenith angle, or along the cloud's surface where a dense
//!   cloud's flank faces the light ([`slab_cosine`], the density's
//!   gradient), and the diffuse light in it is the Eddington (diffusion)
//!   solution of that slab ([`diffuse_source`]); it needs a second short
//!   march, away from the light (τ_b, ended at the first gap:
//!   [`optical_depth_connected`]), and makes the thick cloud's base as
//!   bright as a path tracer finds it and the thin edges no brighter than
//!   their single scattering; the light scattered a few times into the
//!   droplets' forward peak, which diffusion spreads over all directions,
//!   is added back along the beam ([`forward_lobes`]); by default half
//!   of the diffuse light comes instead from a 3D solve of the diffusion
//!   equations over the layer ([`super::diffusion_grid`],
//!   [`march_low_with_grids`]), which sees the light a column cannot;
//! * [`MultipleScattering::Octaves`]: Wrenninge's (2013) octaves
//!   (Hillaire 2016), `S = Σ_{i<N} bⁱ · p(cos θ; cⁱ g) · E · e^{−aⁱ τ_l}`,
//!   one light march, cheaper, but blind to the Sun's altitude and to how
//!   much cloud surrounds the point (the thin edges too bright, a low Sun
//!   too bright; `tests/tests/cloud_mitsuba.rs` measures both).
//!
//! The phase function is a two-lobe Henyey–Greenstein
//! mix ([`CloudPhase`]), a forward lobe for the droplets' diffraction peak
//! and a weak backward lobe (glory side).

use glam::{Vec2, Vec3};

use super::diffusion_grid::DiffusionGrid;
use super::field::{HighField, LowField};
use crate::atmosphere::medium::{henyey_greenstein_phase, safe_sqrt};

/// The two-lobe Henyey–Greenstein phase function of cloud droplets:
/// w · HG(g_forward) + (1 − w) · HG(g_back), sr⁻¹.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CloudPhase {
    /// Asymmetry of the forward lobe.
    pub g_forward: f32,
    /// Asymmetry of the backward lobe.
    pub g_back: f32,
    /// Weight of the forward lobe.
    pub w_forward: f32,
}

/// The droplets' phase function used by both layers (mean cosine
/// 0.8 · 0.8 + 0.2 · (−0.3) = 0.58).
pub const CLOUD_PHASE: CloudPhase = CloudPhase {
    g_forward: 0.8,
    g_back: -0.3,
    w_forward: 0.8,
};

impl CloudPhase {
    /// The phase function at `cos_theta` with both asymmetries scaled by
    /// `k` (Wrenninge's octave eccentricity), sr⁻¹.
    #[inline]
    pub fn eval(&self, cos_theta: f32, k: f32) -> f32 {
        self.w_forward * henyey_greenstein_phase(self.g_forward * k, cos_theta)
            + (1.0 - self.w_forward) * henyey_greenstein_phase(self.g_back * k, cos_theta)
    }
}

/// Wrenninge's multiple-scattering octaves: extinction factor a,
/// contribution b, eccentricity c, and their count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Octaves {
    /// Extinction factor per octave (a).
    pub a: f32,
    /// Contribution per octave (b).
    pub b: f32,
    /// Phase eccentricity per octave (c).
    pub c: f32,
    /// Number of octaves (1 = single scattering).
    pub n: u32,
}

/// The octaves both backends use (compared with Mitsuba's path traced
/// multiple scattering in `tests/tests/cloud_mitsuba.rs`).
pub const OCTAVES: Octaves = Octaves {
    a: 0.25,
    b: 0.5,
    c: 0.5,
    n: 6,
};

/// The diffusion model of the multiple scattering ([`diffuse_source`],
/// [`slab_cosine`], [`optical_depth_connected`], [`forward_lobes`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Diffusion {
    /// Mean cosine of the phase function (the transport scaling 1 − g).
    pub g: f32,
    /// Scale of the diffuse source: the independent column underestimates
    /// the light a 3D cloud lets through its sides and thin parts. This,
    /// `gap_density` and `surface_weight` are what matches Mitsuba's
    /// path-traced cumulus at Sun altitudes of 20° and 60° on a second
    /// field (seed 7, `tests/fixtures/cloud_ref/seed7/`), not the one the
    /// test's goal is measured on (`tests/tests/cloud_mitsuba.rs`).
    pub gain: f32,
    /// Normalised density below which the column away from the light
    /// ends ([`optical_depth_connected`]: the slab is the piece of cloud
    /// the point belongs to, not the clouds beyond a gap).
    pub gap_density: f32,
    /// Step of the density gradient's finite differences, in noise cells
    /// ([`slab_cosine`]).
    pub surface_step: f32,
    /// Weight of the cloud's surface orientation per normalised density
    /// ([`slab_cosine`]: dense cloud has a surface, a wisp's gradient is
    /// noise).
    pub surface_weight: f32,
    /// Orders of scattering whose forward lobe is kept ([`forward_lobes`],
    /// at most [`MAX_FORWARD_ORDERS`]; 0: none).
    pub forward_orders: u32,
}

/// The most orders [`forward_lobes`] keeps.
pub const MAX_FORWARD_ORDERS: usize = 4;

/// The diffusion model both backends use by default.
pub const DIFFUSION: Diffusion = Diffusion {
    g: CLOUD_PHASE.w_forward * CLOUD_PHASE.g_forward
        + (1.0 - CLOUD_PHASE.w_forward) * CLOUD_PHASE.g_back,
    gain: 1.3,
    gap_density: 0.1,
    surface_step: 0.05,
    surface_weight: 2.0,
    forward_orders: 2,
};

/// How the light scattered more than once is approximated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MultipleScattering {
    /// Wrenninge's octaves: one light march per step.
    Octaves(Octaves),
    /// The slab diffusion solution: two light marches per step.
    Diffusion(Diffusion),
}

/// The multiple-scattering model of the frame's cloud pass.
pub const MULTIPLE_SCATTERING: MultipleScattering = MultipleScattering::Diffusion(DIFFUSION);

/// The diffuse (scattered at least once) light's source at a point of a
/// cloud, per unit irradiance of the light, sr⁻¹: the column through the
/// point along the light, optical depth `tau_l` towards the light and
/// `tau_b` away from it, taken as a plane-parallel slab whose light falls
/// at the cosine `mu0` to its normal ([`slab_cosine`]; its optical
/// depth across the column's times μ₀), conservative, scaled to
/// isotropic scattering by the transport depth x = (1 − g) μ₀ τ. The
/// Eddington equation of the diffuse fluence U with the direct beam as
/// its source and Marshak's conditions at both faces,
///
/// ```text
/// U'' = −3 k e^{−x/μ₁},  U − ⅔U' = 0 (x = 0),  U + ⅔U' = 0 (x = X),
/// μ₁ = (1 − g) μ₀,  k μ₁ = μ₀,
/// U(x) = −3 μ₀ μ₁ e^{−τ_l} + A x + B,
/// A = −(3 μ₀ μ₁ + 2 μ₀ + e^{−(τ_l+τ_b)} (2 μ₀ − 3 μ₀ μ₁)) / (X + 4/3),
/// B = 3 μ₀ μ₁ + 2 μ₀ + ⅔ A,
/// ```
///
/// gives the fluence and the net diffuse flux F = −U'/3 = −μ₀ e^{−τ_l} − A/3
/// along the light's travel; the light they scatter towards the viewer is
/// (U + 3 g F cos θ) / 4π, θ the angle between the view and the light
/// (the flux taken along the light: a cloud's sunlit flank reflects, its
/// base seen towards the Sun transmits forwards). It vanishes with the
/// cloud (U, F → 0 as τ_l, τ_b → 0: a thin wisp scatters once) and grows
/// linearly with depth as diffusion does.
pub fn diffuse_source(d: &Diffusion, tau_l: f32, tau_b: f32, mu0: f32, cos_theta: f32) -> f32 {
    let mu0 = mu0.max(0.05);
    let s = 1.0 - d.g;
    let mu1 = s * mu0;
    let x = s * mu0 * tau_l;
    let big_x = s * mu0 * (tau_l + tau_b);
    let beam = (-tau_l).exp();
    let through = (-(tau_l + tau_b)).exp();
    let c = 3.0 * mu0 * mu1 + 2.0 * mu0;
    let a = -(c + through * (2.0 * mu0 - 3.0 * mu0 * mu1)) / (big_x + 4.0 / 3.0);
    let b = c + 2.0 / 3.0 * a;
    let u = (-3.0 * mu0 * mu1 * beam + a * x + b).max(0.0);
    let flux = -mu0 * beam - a / 3.0;
    d.gain * (u + 3.0 * d.g * flux * cos_theta).max(0.0) / (4.0 * std::f32::consts::PI)
}

/// The extinction at the planet-centred point `p` (km⁻¹).
#[inline]
fn extinction_at(field: &LowField, shell: &Shell, p: Vec3) -> f32 {
    field.extinction(Vec2::new(p.x, p.y), p.length() - shell.r_ground)
}

/// The cosine between the light `l` and the normal of
/// [`diffuse_source`]'s slab at `pos` (planet-centred, km; extinction
/// `sigma` there): the slab is horizontal, or lies along the cloud's
/// surface where the cloud is dense. The surface's
/// outward normal n is −∇σ (forward differences `surface_step` noise
/// cells long); a flank that faces the light (n · l above the light's
/// zenith cosine μ₀) takes the light at n · l, as a low Sun lights a
/// cumulus's side almost head-on where a horizontal slab would take it
/// at grazing incidence. The normal counts with the weight
/// min(1, `surface_weight` · σ / σ_max): in a thin wisp the gradient is
/// the noise's, not a surface's. μ₀ where the field is flat.
pub fn slab_cosine(
    d: &Diffusion,
    field: &LowField,
    shell: &Shell,
    pos: Vec3,
    sigma: f32,
    l: Vec3,
) -> f32 {
    let mu0 = pos.dot(l) / pos.length();
    let h = d.surface_step / field.inv_scale;
    let grad = Vec3::new(
        extinction_at(field, shell, pos + Vec3::X * h) - sigma,
        extinction_at(field, shell, pos + Vec3::Y * h) - sigma,
        extinction_at(field, shell, pos + Vec3::Z * h) - sigma,
    );
    let len = grad.length();
    if len <= 0.0 || field.extinction_per_km <= 0.0 {
        return mu0;
    }
    let facing = (-grad / len).dot(l).max(mu0);
    let w = (d.surface_weight * sigma / field.extinction_per_km).min(1.0);
    mu0 + w * (facing - mu0)
}

/// The m-fold convolution of [`CLOUD_PHASE`] with itself at `cos_theta`
/// (the angular spread of light scattered m times in a row without
/// leaving the line, sr⁻¹): Henyey–Greenstein lobes convolve by
/// multiplying their asymmetries, so the two-lobe mix gives the binomial
/// sum Σ_j C(m, j) w^j (1 − w)^{m−j} HG(g_f^j g_b^{m−j}); its mean cosine
/// is g^m.
pub fn phase_power(m: u32, cos_theta: f32) -> f32 {
    let p = CLOUD_PHASE;
    let mut sum = 0.0;
    let mut binom = 1.0f32;
    for j in 0..=m {
        let w = p.w_forward.powi(j as i32) * (1.0 - p.w_forward).powi((m - j) as i32);
        let g = p.g_forward.powi(j as i32) * p.g_back.powi((m - j) as i32);
        sum += binom * w * henyey_greenstein_phase(g, cos_theta);
        binom = binom * (m - j) as f32 / (j + 1) as f32;
    }
    sum
}

/// The forward lobes of the light scattered k = 1, 2, … more times
/// before it reaches the viewer, per ray (they depend on the scattering
/// angle θ alone), sr⁻¹: the diffusion solution gives the diffuse light
/// an almost isotropic angular shape, (1 + 3 g^{k+1} cos θ)/4π at order
/// k + 1, while light scattered into the droplets' forward peak keeps
/// travelling along the beam (g = 0.58: Mitsuba's cloud seen towards the
/// Sun is far brighter than single scattering and diffusion together).
/// Each entry is max(0, p^{∗(k+1)}(θ) − (1 + 3 g^{k+1} cos θ)/4π)
/// ([`phase_power`]): the part of the (k+1)-fold phase function's lobe
/// above the diffusion's, weighted per step by the Poisson probability
/// τ_l^k e^{−τ_l}/k! that the beam's light was scattered k times on its
/// way ([`forward_source`]). Only the excess is added: sideways and
/// backwards that light did not come along the beam, and the diffusion's
/// own angular term stands. Entries beyond `forward_orders` are 0.
pub fn forward_lobes(d: &Diffusion, cos_theta: f32) -> [f32; MAX_FORWARD_ORDERS] {
    let mut out = [0.0; MAX_FORWARD_ORDERS];
    let mut gk = d.g;
    for (k, o) in out
        .iter_mut()
        .enumerate()
        .take((d.forward_orders as usize).min(MAX_FORWARD_ORDERS))
    {
        gk *= d.g;
        let diffuse = (1.0 + 3.0 * gk * cos_theta) / (4.0 * std::f32::consts::PI);
        *o = (phase_power(k as u32 + 2, cos_theta) - diffuse).max(0.0);
    }
    out
}

/// The forward lobes' source at optical depth `tau_l` from the light,
/// per unit irradiance, sr⁻¹: Σ_k τ_l^k e^{−τ_l}/k! · `lobes`[k − 1]
/// ([`forward_lobes`]).
pub fn forward_source(lobes: &[f32; MAX_FORWARD_ORDERS], tau_l: f32) -> f32 {
    let mut term = (-tau_l).exp();
    let mut sum = 0.0;
    for (k, lobe) in lobes.iter().enumerate() {
        term *= tau_l / (k + 1) as f32;
        sum += term * lobe;
    }
    sum
}

/// How finely the low layer is marched and how its multiple scattering is
/// approximated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarchSettings {
    /// View-ray steps across the slab's thickness (`clouds.low.steps`).
    pub steps: u32,
    /// Steps towards each light (`clouds.low.light_steps`).
    pub light_steps: u32,
    /// The multiple-scattering model ([`MULTIPLE_SCATTERING`]).
    pub scattering: MultipleScattering,
}

/// A light at the cloud: unit ENU direction towards it and its
/// irradiance at normal incidence there (linear sRGB, Y = lux).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CloudLight {
    /// Unit vector towards the light (local frame of the observer).
    pub dir: Vec3,
    /// Irradiance at normal incidence at the cloud, linear sRGB, lux.
    pub irradiance_rgb: [f32; 3],
}

/// Where the observer stands on the spherical Earth, km.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shell {
    /// The ground's radius.
    pub r_ground: f32,
    /// The observer's radius.
    pub r_observer: f32,
}

impl Shell {
    /// The point at distance `t` along `view`: its horizontal position
    /// (km East, North) and altitude above the ground (km).
    #[inline]
    pub fn point(&self, view: Vec3, t: f32) -> (Vec2, f32) {
        let p = Vec3::new(0.0, 0.0, self.r_observer) + view * t;
        (
            Vec2::new(view.x * t, view.y * t),
            p.length() - self.r_ground,
        )
    }

    /// The first interval [t₀, t₁] of the ray from the observer along
    /// `view` with altitude in [`lo_km`, `hi_km`], if any.
    pub fn slab(&self, view: Vec3, lo_km: f32, hi_km: f32) -> Option<(f32, f32)> {
        self.slab_from(self.r_observer, view.z, lo_km, hi_km)
    }

    /// The same from radius `r` at zenith cosine `mu`; the ground hides
    /// what lies beyond it. A downward ray that meets the ground sphere
    /// meets it ahead (at g₀ ≥ 0; from the ground itself g₀ is 0 up to
    /// rounding, whose sign must not decide whether the cloud shows below
    /// the horizon).
    pub fn slab_from(&self, r: f32, mu: f32, lo_km: f32, hi_km: f32) -> Option<(f32, f32)> {
        let (start, end) = slab_interval(r, mu, self.r_ground + lo_km, self.r_ground + hi_km)?;
        let end = match inside_sphere(r, mu, self.r_ground) {
            Some((g0, _)) if mu < 0.0 => end.min(g0.max(0.0)),
            _ => end,
        };
        (end > start).then_some((start, end))
    }
}

/// The ray's interval inside the sphere of radius `r` from radius `r0`
/// at zenith cosine `mu` (may start behind the origin).
pub(crate) fn inside_sphere(r0: f32, mu: f32, r: f32) -> Option<(f32, f32)> {
    let disc = r0 * r0 * (mu * mu - 1.0) + r * r;
    (disc >= 0.0).then(|| {
        let s = safe_sqrt(disc);
        (-r0 * mu - s, -r0 * mu + s)
    })
}

/// The first interval at t ≥ 0 of the ray from radius `r0` at zenith
/// cosine `mu` inside the spherical shell between radii `r_lo` < `r_hi`.
pub fn slab_interval(r0: f32, mu: f32, r_lo: f32, r_hi: f32) -> Option<(f32, f32)> {
    let (o0, o1) = inside_sphere(r0, mu, r_hi)?;
    let mut start = o0.max(0.0);
    let mut end = o1;
    if end <= start {
        return None;
    }
    if let Some((i0, i1)) = inside_sphere(r0, mu, r_lo) {
        if i0 <= start && start < i1 {
            // Inside the inner sphere: the shell begins where the ray leaves it.
            start = i1;
        } else if i0 > start {
            // The ray dives into the inner sphere ahead.
            end = end.min(i0);
        }
    }
    (end > start).then_some((start, end))
}

/// The longest stretch of a view ray through the low layer that is
/// marched, km (near the horizon the slab is hundreds of km long; beyond
/// this the cloud's contribution is lost in the haze).
pub const MAX_MARCH_KM: f32 = 120.0;

/// The result of a march: in-scattered radiance (linear sRGB, cd/m²),
/// the transmittance of the layer, and the distance at which the view
/// ray's extinction happened on average (km; for the aerial perspective).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CloudHit {
    /// In-scattered radiance, cd/m².
    pub radiance: [f32; 3],
    /// Transmittance of the layer along the ray.
    pub transmittance: f32,
    /// Extinction-weighted mean distance, km.
    pub distance_km: f32,
}

impl CloudHit {
    /// No cloud on the ray.
    pub const CLEAR: CloudHit = CloudHit {
        radiance: [0.0; 3],
        transmittance: 1.0,
        distance_km: 0.0,
    };

    /// Adds a segment of optical depth `tau` at `t` km along the ray whose
    /// source is `src` plus `ambient` × (0.4 + 0.6 `h`), `h` the height's
    /// fraction of the slab (the sky's light weaker low in the cloud);
    /// `distance_km` sums here until [`CloudHit::finish`]. Whether the
    /// ray's light is spent (transmittance below 10⁻⁴).
    pub(crate) fn add(
        &mut self,
        tau: f32,
        t: f32,
        src: [f32; 3],
        ambient: [f32; 3],
        h: f32,
    ) -> bool {
        let amb = 0.4 + 0.6 * h;
        let seg = (-tau).exp();
        let w = self.transmittance * (1.0 - seg);
        for c in 0..3 {
            self.radiance[c] += w * (src[c] + ambient[c] * amb);
        }
        self.distance_km += w * t;
        self.transmittance *= seg;
        self.transmittance < 1e-4
    }

    /// The hit with its extinction-weighted mean distance (`t0` where
    /// nothing was extinguished).
    pub(crate) fn finish(mut self, t0: f32) -> CloudHit {
        let ext = 1.0 - self.transmittance;
        self.distance_km = if ext > 0.0 {
            self.distance_km / ext
        } else {
            t0
        };
        self
    }
}

/// Steps of a march over `len` km where `steps` span the slab's
/// `thickness` (longer slant paths get more steps, up to 4 × `steps`).
pub(crate) fn step_count(len: f32, thickness: f32, steps: u32) -> u32 {
    let dt = thickness / steps as f32;
    ((len / dt).ceil() as u32).clamp(1, 4 * steps)
}

/// Optical depth of the low layer from the point at `t` along `view`
/// towards the unit direction `l`, marched in `n` equal steps to the top
/// of the layer (`f32::INFINITY` when the ray meets the ground first).
pub fn optical_depth_to_light(field: &LowField, shell: &Shell, pos: Vec3, l: Vec3, n: u32) -> f32 {
    let r = pos.length();
    let mu = pos.dot(l) / r;
    let Some((_, d)) = inside_sphere(r, mu, shell.r_ground + field.top_km) else {
        return 0.0;
    };
    let d = d.max(0.0);
    let ds = d / n as f32;
    let mut tau = 0.0;
    for k in 0..n {
        let p = pos + l * ((k as f32 + 0.5) * ds);
        tau += field.extinction(Vec2::new(p.x, p.y), p.length() - shell.r_ground) * ds;
    }
    tau
}

/// Marches the view ray `view` (unit, observer frame) through the low
/// layer as `settings` say (at most 8 octaves), `ambient` the isotropic sky radiance above the layer
/// (linear sRGB, cd/m²; a linear height gradient scales it from 0.4 at
/// the base to 1 at the top, the light the cloud hides from its own base).
pub fn march_low(
    field: &LowField,
    shell: &Shell,
    view: Vec3,
    lights: &[CloudLight],
    ambient: [f32; 3],
    settings: &MarchSettings,
) -> CloudHit {
    march_low_with_grids(field, shell, view, lights, ambient, settings, &[])
}

/// [`march_low`] with the diffuse light of the diffusion model taken from
/// `grids` (one per light, in `lights`' order, [`DiffusionGrid`]) where
/// they cover the point; the column model elsewhere and for the lights
/// beyond `grids`' length.
pub fn march_low_with_grids(
    field: &LowField,
    shell: &Shell,
    view: Vec3,
    lights: &[CloudLight],
    ambient: [f32; 3],
    settings: &MarchSettings,
    grids: &[DiffusionGrid],
) -> CloudHit {
    let MarchSettings {
        steps,
        light_steps,
        scattering,
    } = *settings;
    let octaves = match scattering {
        MultipleScattering::Octaves(o) => o,
        MultipleScattering::Diffusion(_) => Octaves { n: 1, ..OCTAVES },
    };
    let n_oct = octaves.n.clamp(1, 8) as usize;
    let Some((t0, t1)) = shell.slab(view, field.base_km, field.top_km) else {
        return CloudHit::CLEAR;
    };
    let t1 = t1.min(t0 + MAX_MARCH_KM);
    let n = step_count(t1 - t0, field.thickness_km(), steps);
    let dt = (t1 - t0) / n as f32;
    let origin = Vec3::new(0.0, 0.0, shell.r_observer);
    let phases: Vec<[f32; 8]> = lights
        .iter()
        .map(|lt| {
            let cos = view.dot(lt.dir);
            let mut p = [0.0f32; 8];
            let mut k = 1.0;
            for o in p.iter_mut().take(n_oct) {
                *o = CLOUD_PHASE.eval(cos, k);
                k *= octaves.c;
            }
            p
        })
        .collect();
    let mut hit = CloudHit::CLEAR;
    let lobes: Vec<[f32; MAX_FORWARD_ORDERS]> = lights
        .iter()
        .map(|lt| match scattering {
            MultipleScattering::Diffusion(d) => forward_lobes(&d, view.dot(lt.dir)),
            MultipleScattering::Octaves(_) => [0.0; MAX_FORWARD_ORDERS],
        })
        .collect();
    for s in 0..n {
        let t = t0 + (s as f32 + 0.5) * dt;
        let (xy, h) = shell.point(view, t);
        let sigma = field.extinction(xy, h);
        if sigma <= 0.0 {
            continue;
        }
        let pos = origin + view * t;
        let mut src = [0.0f32; 3];
        for (k, ((lt, ph), lobes)) in lights.iter().zip(&phases).zip(&lobes).enumerate() {
            let tau = optical_depth_to_light(field, shell, pos, lt.dir, light_steps);
            let mut f = 0.0;
            let (mut ai, mut bi) = (1.0f32, 1.0f32);
            for p in ph.iter().take(n_oct) {
                f += bi * p * (-ai * tau).exp();
                ai *= octaves.a;
                bi *= octaves.b;
            }
            if let MultipleScattering::Diffusion(d) = scattering {
                let gap = d.gap_density * field.extinction_per_km;
                let tau_b = optical_depth_connected(field, shell, pos, -lt.dir, light_steps, gap);
                let mu = slab_cosine(&d, field, shell, pos, sigma, lt.dir);
                let column = diffuse_source(&d, tau, tau_b, mu, view.dot(lt.dir));
                f += match grids.get(k) {
                    Some(g) => g.diffuse(column, xy, h, view),
                    None => column,
                };
                f += forward_source(lobes, tau);
            }
            for c in 0..3 {
                src[c] += f * lt.irradiance_rgb[c];
            }
        }
        let hf = ((h - field.base_km) / field.thickness_km()).clamp(0.0, 1.0);
        if hit.add(sigma * dt, t, src, ambient, hf) {
            break;
        }
    }
    hit.finish(t0)
}

/// Optical depth of the low layer from `pos` (inside or outside it) along
/// the unit direction `dir` to where the ray leaves the layer (or meets
/// the ground), marched in `n` equal steps.
pub fn optical_depth_through(field: &LowField, shell: &Shell, pos: Vec3, dir: Vec3, n: u32) -> f32 {
    let r = pos.length();
    let Some((t0, t1)) = shell.slab_from(r, pos.dot(dir) / r, field.base_km, field.top_km) else {
        return 0.0;
    };
    let ds = (t1 - t0) / n as f32;
    let mut tau = 0.0;
    for k in 0..n {
        let p = pos + dir * (t0 + (k as f32 + 0.5) * ds);
        tau += field.extinction(Vec2::new(p.x, p.y), p.length() - shell.r_ground) * ds;
    }
    tau
}

/// Optical depth of the piece of cloud `pos` belongs to along the unit
/// direction `dir`: [`optical_depth_through`]'s march (`n` equal steps to
/// where the ray leaves the layer) ending at the first sample whose
/// extinction is at most `gap` km⁻¹ (a gap between clouds: beyond it the
/// diffuse light of [`diffuse_source`]'s slab escapes).
pub fn optical_depth_connected(
    field: &LowField,
    shell: &Shell,
    pos: Vec3,
    dir: Vec3,
    n: u32,
    gap: f32,
) -> f32 {
    let r = pos.length();
    let Some((t0, t1)) = shell.slab_from(r, pos.dot(dir) / r, field.base_km, field.top_km) else {
        return 0.0;
    };
    let ds = (t1 - t0) / n as f32;
    let mut tau = 0.0;
    for k in 0..n {
        let sigma = extinction_at(field, shell, pos + dir * (t0 + (k as f32 + 0.5) * ds));
        if sigma <= gap {
            break;
        }
        tau += sigma * ds;
    }
    tau
}

/// Optical depth of the low layer along the whole ray from the observer
/// along `view`, marched like [`march_low`] (the transmittance of the
/// direct Sun through the layer when `view` points at the Sun).
pub fn optical_depth_low(field: &LowField, shell: &Shell, view: Vec3, steps: u32) -> f32 {
    let origin = Vec3::new(0.0, 0.0, shell.r_observer);
    optical_depth_ray(field, shell, origin, view, steps)
}

/// Optical depth of the low layer along the ray from `pos` (planet-centred,
/// km, the observer on the z axis) in the unit direction `dir`, marched
/// like [`march_low`]: `steps` steps across the slab's thickness, more on
/// slant paths (the cloud shadow of the direct beam at `pos` when `dir`
/// points at the Sun).
pub fn optical_depth_ray(field: &LowField, shell: &Shell, pos: Vec3, dir: Vec3, steps: u32) -> f32 {
    let r = pos.length();
    let Some((t0, t1)) = shell.slab_from(r, pos.dot(dir) / r, field.base_km, field.top_km) else {
        return 0.0;
    };
    let t1 = t1.min(t0 + MAX_MARCH_KM);
    let n = step_count(t1 - t0, field.thickness_km(), steps);
    let dt = (t1 - t0) / n as f32;
    (0..n)
        .map(|s| {
            let p = pos + dir * (t0 + (s as f32 + 0.5) * dt);
            field.extinction(Vec2::new(p.x, p.y), p.length() - shell.r_ground) * dt
        })
        .sum()
}

/// The thin high layer along `view`: single scattering of each light in a
/// plane-parallel sheet of vertical optical depth τ (albedo 1), seen from
/// below along cosine μ_v with the light at cosine μ_l above the sheet,
///
/// ```text
/// L = p(θ) E / μ_v · ∫₀^τ e^{−τ'/μ_l} e^{−(τ−τ')/μ_v} dτ'
///   = p(θ) E τ/μ_v · e^{−τ/μ_v} · (1 − e^{−x}) / x,  x = τ (1/μ_l − 1/μ_v),
/// ```
///
/// plus the sky's isotropic `ambient` radiance scattered by the sheet,
/// ambient · (1 − e^{−τ/μ_v}); transmittance e^{−τ/μ_v}.
pub fn shade_high(
    field: &HighField,
    shell: &Shell,
    view: Vec3,
    lights: &[CloudLight],
    ambient: [f32; 3],
) -> CloudHit {
    let r_layer = shell.r_ground + field.altitude_km;
    if shell.r_observer >= r_layer {
        return CloudHit::CLEAR;
    }
    let Some((_, t)) = inside_sphere(shell.r_observer, view.z, r_layer) else {
        return CloudHit::CLEAR;
    };
    let p = Vec3::new(0.0, 0.0, shell.r_observer) + view * t;
    let up = p / p.length();
    let mu_v = view.dot(up).max(1e-3);
    let tau = field.optical_depth(Vec2::new(view.x * t, view.y * t));
    if tau <= 0.0 {
        return CloudHit::CLEAR;
    }
    let tv = (-tau / mu_v).exp();
    let mut l = [0.0f32; 3];
    for lt in lights {
        let mu_l = lt.dir.dot(up);
        if mu_l <= 1e-3 {
            continue;
        }
        let x = tau * (1.0 / mu_l - 1.0 / mu_v);
        // (1 − e^{−x}) / x, continuous through x = 0.
        let g = if x.abs() < 1e-4 {
            1.0 - 0.5 * x
        } else {
            -(-x).exp_m1() / x
        };
        let f = CLOUD_PHASE.eval(view.dot(lt.dir), 1.0) * tau / mu_v * tv * g;
        for c in 0..3 {
            l[c] += f * lt.irradiance_rgb[c];
        }
    }
    for c in 0..3 {
        l[c] += ambient[c] * (1.0 - tv);
    }
    CloudHit {
        radiance: l,
        transmittance: tv,
        distance_km: t,
    }
}
