//! The LUT path's view-ray march: the scattering source at a point
//! ([`ScatterPhases`], [`MediumAt`]), one view ray marched once for every
//! Sun position ([`ViewMarch`], the sky view's rows) and the aerial
//! perspective along a ray ([`aerial_perspective`]).

use glam::Vec3;

use super::at_radius::AtRadius;
use super::lut::{integrate_segment, AtmosphereLuts};
use super::medium::{cornette_shanks_phase, rayleigh_phase, safe_sqrt};
use crate::spectrum::Spectrum;

/// The phase functions of one view ray (they depend only on the angle
/// between the view and the light).
#[derive(Debug, Clone, Copy)]
pub(super) struct ScatterPhases {
    pr: f32,
    pm: f32,
    pm_flat: f32,
}

impl ScatterPhases {
    pub(super) fn new(luts: &AtmosphereLuts, cos_theta: f32) -> Self {
        let m = &luts.medium;
        let pr = rayleigh_phase(cos_theta);
        let pm = cornette_shanks_phase(m.g, cos_theta);
        // Within the δ-scaled forward cone the aerosol phase function is
        // flattened (that light already travels in the δ-scaled beam); the
        // peak above the flat part is single scattering of the true beam.
        let cone = luts.config.forward_peak_deg.to_radians().cos();
        let pm_flat = if luts.config.forward_peak_deg > 0.0 && cos_theta > cone {
            cornette_shanks_phase(m.g, cone)
        } else {
            pm
        };
        ScatterPhases { pr, pm, pm_flat }
    }

    /// The δ-scaled extinction and the in-scattering source (single
    /// scattering of the beam plus Ψ_ms multiple scattering) at point `p`
    /// (planet-centred, km) lit from `sun`.
    #[inline]
    fn source(&self, luts: &AtmosphereLuts, p: Vec3, sun: Vec3) -> (Spectrum, Spectrum) {
        let rp = p.length();
        let mus = p.dot(sun) / rp;
        let c = MediumAt::new(luts, rp);
        (c.ext, self.lit(luts, &c, mus))
    }

    /// The in-scattering source of the medium `c` where the Sun's zenith
    /// cosine is `mus`.
    #[inline]
    fn lit(&self, luts: &AtmosphereLuts, c: &MediumAt, mus: f32) -> Spectrum {
        let ScatterPhases { pr, pm, pm_flat } = *self;
        if c.at.dark(luts, mus) {
            // No beam and no Ψ_ms: every term below is +0.
            return Spectrum::ZERO;
        }
        let tsun = c.at.scattering_sun_transmittance(luts, mus);
        let psi = c.at.multiscatter(luts, mus);
        let mut src = (c.sr * pr + c.sm * pm_flat) * tsun + c.ms * psi;
        if pm > pm_flat {
            src += c.sm * (pm - pm_flat) * c.at.sun_transmittance(luts, mus);
        }
        src
    }
}

/// The medium at radius `r` as the LUT path scatters in it: the δ-scaled
/// extinction, the Rayleigh and aerosol scattering coefficients and the
/// coefficient of the multiple-scattering term.
#[derive(Debug, Clone, Copy)]
pub(super) struct MediumAt {
    r: f32,
    /// The radius-only parts of the Sun's light there.
    at: AtRadius,
    ext: Spectrum,
    sr: Spectrum,
    sm: Spectrum,
    ms: Spectrum,
}

impl MediumAt {
    #[inline]
    fn new(luts: &AtmosphereLuts, r: f32) -> Self {
        let m = &luts.medium;
        let fwd = luts.forward;
        let dens = m.densities(r);
        let (sr, sm) = m.scattering(dens);
        MediumAt {
            r,
            at: AtRadius::new(luts, r),
            ext: m.extinction(dens) - fwd * dens.mie,
            sr,
            sm,
            ms: sr + sm - fwd * dens.mie,
        }
    }
}

/// One view ray from radius `r0` at zenith cosine `mu` marched once: each
/// step's distance, medium and weight t_v · ∫e^{−σt} dt (the view
/// transmittance to the step times the step's integral), i.e. everything
/// that does not depend on where the Sun is, so that the azimuths of a
/// sky-view row share it and only look the Sun's light up per step.
pub(super) struct ViewMarch {
    /// (distance, medium, weight) per step.
    steps: Vec<(f32, MediumAt, Spectrum)>,
    /// When the ray ends on the ground: its distance, radius and the view
    /// transmittance to it.
    ground: Option<(f32, f32, Spectrum)>,
}

impl ViewMarch {
    pub(super) fn new(luts: &AtmosphereLuts, r0: f32, mu: f32, steps: usize) -> Self {
        let m = &luts.medium;
        // The ray in its vertical plane (the radius of a point does not
        // depend on the azimuth).
        let pos = Vec3::new(0.0, 0.0, r0);
        let view = Vec3::new(safe_sqrt(1.0 - mu * mu), 0.0, mu);
        let (t_max, ground) = m.ray_end(r0, mu);
        // Fewer steps on short rays: `steps` for the horizontal ray, scaled
        // by √(length / horizontal length), at least 20 (Hillaire 2020 §5
        // also scales the sample count with the ray length).
        let t_h = m.distance_to_top(r0, 0.0).max(1e-3);
        let n = ((steps as f32 * (t_max / t_h).sqrt()).ceil() as usize).clamp(steps.min(20), steps);
        let mut tv = Spectrum::ONE;
        let mut t_prev = 0.0f32;
        let mut out = Vec::with_capacity(n);
        for s in 0..n {
            // Quadratic spacing: short steps near the observer, where the
            // air is densest along near-horizontal rays.
            let x = (s as f32 + 1.0) / n as f32;
            let t_next = t_max * x * x;
            let dt = t_next - t_prev;
            let t = 0.5 * (t_prev + t_next);
            t_prev = t_next;
            let c = MediumAt::new(luts, (pos + view * t).length());
            let seg = (c.ext * dt).exp_neg();
            out.push((t, c, tv * integrate_segment(c.ext, seg, dt)));
            tv *= seg;
        }
        ViewMarch {
            steps: out,
            ground: ground.then(|| (t_max, (pos + view * t_max).length(), tv)),
        }
    }

    /// Whether [`Self::transfer`] is +0 in every band for every Sun at
    /// angle `cos_theta ≤ cos_theta_max` from the view with local zenith
    /// cosine `sun_z`: every step's source is dark ([`AtRadius::dark`]) and
    /// the Sun is below the ground point's horizon at the greatest angle.
    /// Both tests are monotone in the Sun's zenith cosine at a point,
    /// which grows with `cos_theta` (t ≥ 0, r > 0), so the greatest angle
    /// decides for all.
    pub(super) fn dark(
        &self,
        luts: &AtmosphereLuts,
        r0: f32,
        cos_theta_max: f32,
        sun_z: f32,
    ) -> bool {
        let mu_sun = |t: f32, r: f32| (r0 * sun_z + t * cos_theta_max) / r;
        self.steps
            .iter()
            .all(|(t, c, _)| c.at.dark(luts, mu_sun(*t, c.r)))
            && self.ground.map_or(true, |(t_max, rg, _)| {
                luts.medium.sun_visibility(rg, mu_sun(t_max, rg)) <= 0.0
            })
    }

    /// The radiance transfer factor of the ray for a Sun at angle
    /// `cos_theta` from the view direction with local zenith cosine
    /// `sun_z`, seen from radius `r0`.
    pub(super) fn transfer(
        &self,
        luts: &AtmosphereLuts,
        r0: f32,
        cos_theta: f32,
        sun_z: f32,
    ) -> Spectrum {
        let phases = ScatterPhases::new(luts, cos_theta);
        // p · sun for p = (0, 0, r0) + t · view.
        let mu_sun = |t: f32, r: f32| (r0 * sun_z + t * cos_theta) / r;
        let mut l = Spectrum::ZERO;
        for (t, c, weight) in &self.steps {
            l += *weight * phases.lit(luts, c, mu_sun(*t, c.r));
        }
        if let Some((t_max, rg, tv)) = self.ground {
            let mug = mu_sun(t_max, rg);
            let tsun = luts.scattering_sun_transmittance(rg, mug);
            l += tv * tsun * (mug.max(0.0) * luts.medium.albedo / std::f32::consts::PI);
        }
        l
    }
}

/// Aerial perspective along one view ray: the in-scattered radiance
/// transfer (band radiance per unit solar irradiance, sr⁻¹) and the
/// transmittance from the observer at radius `r0` (km) in local direction
/// `view` (z up) to each distance of `ends` (km, ascending), with the light
/// at `sun`. The same integrand as the sky view ([`SkyView::transfer`]),
/// marched in `steps_per_end` equal steps per interval between ends and
/// clipped where the ray meets the ground or leaves the atmosphere
/// (Hillaire 2020 §5.5 computes this per froxel).
pub fn aerial_perspective(
    luts: &AtmosphereLuts,
    r0: f32,
    view: Vec3,
    sun: Vec3,
    ends: &[f32],
    steps_per_end: usize,
) -> Vec<(Spectrum, Spectrum)> {
    let pos = Vec3::new(0.0, 0.0, r0);
    let (t_max, _) = luts.medium.ray_end(r0, view.z);
    let phases = ScatterPhases::new(luts, view.dot(sun));
    let mut tv = Spectrum::ONE;
    let mut l = Spectrum::ZERO;
    let mut t0 = 0.0f32;
    let n = steps_per_end.max(1);
    ends.iter()
        .map(|&end| {
            let t1 = end.clamp(t0, t_max.max(t0));
            let dt = (t1 - t0) / n as f32;
            for s in 0..n {
                if dt <= 0.0 {
                    break;
                }
                let t = t0 + (s as f32 + 0.5) * dt;
                let (ext, src) = phases.source(luts, pos + view * t, sun);
                let seg = (ext * dt).exp_neg();
                l += tv * src * integrate_segment(ext, seg, dt);
                tv *= seg;
            }
            t0 = t1;
            (l, tv)
        })
        .collect()
}
