//! Clouds: a volumetric low layer (cumulus, stratocumulus, stratus) and a
//! thin high layer (cirrus), in absolute units, lit by the Sun and the
//! Moon through the atmosphere and by the sky.
//!
//! * [`noise`] — hash-based value noise and fBm, periodic, identical in
//!   WGSL;
//! * [`field`] — the density fields: [`LowField`] (3D extinction, km⁻¹)
//!   and [`HighField`] (2D vertical optical depth);
//! * [`height_field`] — the cheap tier of the low layer: the field
//!   reduced to per-column bottom, top and mean extinction maps, rays
//!   intersected with that volume by a few probes (Dubé 2005);
//! * [`diffusion_grid`] — the low layer's diffuse light solved in 3D (P1
//!   equations on a coarse grid, once per light), blended with the
//!   column model by the view march;
//! * [`march`] — the view ray's march through the low layer with
//!   self-shadowing and Wrenninge's multiple-scattering octaves, the
//!   optical depth of a ray (the direct Sun's transmittance), and the high
//!   layer's single scattering.
//!
//! The frame's constants (the lights' irradiance at the cloud after the
//! atmosphere's transmittance, the sky's ambient radiance, the aerial
//! perspective in front of the cloud) and the composition over the sky
//! are [`crate::frame::CloudFrame`]. The model is checked against Mitsuba
//! 3's path tracer on the same density field (`tools/cloud_reference.py`,
//! `tests/tests/cloud_mitsuba.rs`).

pub mod diffusion_grid;
pub mod field;
pub mod height_field;
pub mod march;
pub mod noise;

pub use diffusion_grid::{DiffusionGrid, GridError, GridSettings, GRID};
pub use field::{HighField, LowField};
pub use height_field::{march_height_field, HeightField};
pub use march::{
    diffuse_source, forward_lobes, forward_source, march_low, march_low_with_grids,
    optical_depth_connected, optical_depth_low, optical_depth_ray, optical_depth_through,
    optical_depth_to_light, phase_power, shade_high, slab_cosine, CloudHit, CloudLight, CloudPhase,
    Diffusion, MarchSettings, MultipleScattering, Octaves, Shell, CLOUD_PHASE, DIFFUSION,
    MAX_FORWARD_ORDERS, MULTIPLE_SCATTERING, OCTAVES,
};

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::march::slab_interval;
    use super::*;
    use crate::cloud_spec::{HighCloudSpec, LowCloudSpec};

    const RG: f32 = 6360.0;
    const SETTINGS: MarchSettings = MarchSettings {
        steps: 64,
        light_steps: 6,
        scattering: MULTIPLE_SCATTERING,
    };

    fn shell() -> Shell {
        Shell {
            r_ground: RG,
            r_observer: RG,
        }
    }

    #[test]
    fn slab_intervals_from_below_inside_and_above() {
        // From the ground straight up: base to top.
        let (a, b) = slab_interval(RG, 1.0, RG + 1.0, RG + 2.0).unwrap();
        assert!((a - 1.0).abs() < 1e-3 && (b - 2.0).abs() < 1e-3, "{a} {b}");
        // From the ground down: the ground hides the far side.
        assert!(shell()
            .slab(Vec3::new(0.0, 0.98, -0.2).normalize(), 1.0, 2.0)
            .is_none());
        // Inside the slab looking down: to the base.
        let (a, b) = slab_interval(RG + 1.5, -1.0, RG + 1.0, RG + 2.0).unwrap();
        assert!(a == 0.0 && (b - 0.5).abs() < 1e-3, "{a} {b}");
        // Above looking down: top to base.
        let (a, b) = slab_interval(RG + 3.0, -1.0, RG + 1.0, RG + 2.0).unwrap();
        assert!((a - 1.0).abs() < 1e-3 && (b - 2.0).abs() < 1e-3, "{a} {b}");
        // The horizontal ray from the ground: a long, finite slant path.
        let (a, b) = slab_interval(RG, 0.0, RG + 1.0, RG + 2.0).unwrap();
        let expect = |h: f32| ((RG + h).powi(2) - RG * RG).sqrt();
        assert!((a / expect(1.0) - 1.0).abs() < 1e-3 && (b / expect(2.0) - 1.0).abs() < 1e-3);
    }

    fn field() -> LowField {
        LowField::new(
            &LowCloudSpec {
                coverage: 0.7,
                ..LowCloudSpec::default()
            },
            0.0,
        )
    }

    /// The march's transmittance is e^{−τ} of the same ray's optical depth,
    /// the radiance is linear in the light, and without light there is none.
    #[test]
    fn march_is_consistent_and_linear() {
        let f = field();
        let sh = shell();
        let sun = Vec3::new(0.3, 0.2, 0.93).normalize();
        let light = |e: f32| {
            [CloudLight {
                dir: sun,
                irradiance_rgb: [e, e, e],
            }]
        };
        let mut seen = 0;
        for i in 0..40 {
            let a = i as f32 * 0.157;
            let v = Vec3::new(a.cos() * 0.5, a.sin() * 0.5, 0.8).normalize();
            let h1 = march_low(&f, &sh, v, &light(1.0), [0.0; 3], &SETTINGS);
            let h2 = march_low(&f, &sh, v, &light(2.0), [0.0; 3], &SETTINGS);
            let h0 = march_low(&f, &sh, v, &light(0.0), [0.0; 3], &SETTINGS);
            let tau = optical_depth_low(&f, &sh, v, 64);
            if h1.transmittance > 1e-3 {
                assert!((h1.transmittance - (-tau).exp()).abs() < 1e-3);
            }
            assert!((h2.radiance[1] - 2.0 * h1.radiance[1]).abs() <= 1e-4 * h2.radiance[1]);
            assert_eq!(h0.radiance, [0.0; 3]);
            // Energy: a white cloud lit by E never exceeds the radiance of
            // a perfect diffuse reflector times the forward peak's gain.
            assert!(h1.radiance[1] >= 0.0 && h1.radiance[1].is_finite());
            seen += (h1.transmittance < 0.9) as u32;
        }
        assert!(seen > 5, "the rays should meet clouds: {seen}");
    }

    /// The diffuse source vanishes with the cloud (a thin wisp scatters
    /// once), grows into a thick cloud and fades towards the face away
    /// from the light, and stays finite and non-negative for every light
    /// angle and depth.
    #[test]
    fn diffuse_source_limits() {
        let d = DIFFUSION;
        assert!(diffuse_source(&d, 1e-4, 1e-4, 0.8, 0.5) < 1e-3);
        assert!(diffuse_source(&d, 0.0, 0.0, 0.8, 0.5) < 1e-6);
        // In a thick slab lit from above, the fluence falls from the lit
        // face's neighbourhood to the far face.
        let total = 40.0;
        let near = diffuse_source(&d, 2.0, total - 2.0, 1.0, 0.0);
        let far = diffuse_source(&d, total - 0.1, 0.1, 1.0, 0.0);
        assert!(near > 3.0 * far && far > 0.0, "{near} {far}");
        // Seen towards the light from below, the transmitted light is
        // brighter than seen away from it (the net flux goes forwards).
        let fwd = diffuse_source(&d, total - 0.5, 0.5, 1.0, 1.0);
        let back = diffuse_source(&d, total - 0.5, 0.5, 1.0, -1.0);
        assert!(fwd > back, "{fwd} {back}");
        for &mu in &[-0.5f32, 0.0, 1e-6, 0.05, 0.3, 1.0] {
            for &t in &[0.0f32, 1e-3, 1.0, 30.0, 1e4] {
                for &c in &[-1.0f32, 0.0, 1.0] {
                    let v = diffuse_source(&d, t, 0.5 * t, mu, c);
                    assert!(v.is_finite() && v >= 0.0, "{mu} {t} {c}: {v}");
                }
            }
        }
    }

    /// The m-fold convolved phase function is normalised with mean cosine
    /// g^m; the forward lobes are large towards the light, small
    /// sideways and backwards, and weigh nothing outside a cloud
    /// (τ = 0) and in its depths.
    #[test]
    fn forward_lobes_and_phase_powers() {
        for m in [1u32, 2, 3] {
            let n = 40_000;
            let (mut s0, mut s1) = (0.0f64, 0.0f64);
            for i in 0..n {
                let mu = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                let p = phase_power(m, mu as f32) as f64 * 2.0 / n as f64;
                s0 += p;
                s1 += p * mu;
            }
            let tau = 2.0 * std::f64::consts::PI;
            assert!((s0 * tau - 1.0).abs() < 2e-3, "{m}: {}", s0 * tau);
            let g = (DIFFUSION.g as f64).powi(m as i32);
            assert!((s1 * tau - g).abs() < 2e-3, "{m}: {} vs {g}", s1 * tau);
        }
        assert!((phase_power(1, 0.3) - CLOUD_PHASE.eval(0.3, 1.0)).abs() < 1e-6);
        let fwd = forward_lobes(&DIFFUSION, 1.0);
        assert!(fwd[0] > 0.3 && fwd[1] > 0.0 && fwd[2] == 0.0, "{fwd:?}");
        let side = forward_lobes(&DIFFUSION, 0.0);
        let back = forward_lobes(&DIFFUSION, -0.5);
        assert!(
            side[0] < 0.02 * fwd[0] && back[0] < 0.02 * fwd[0],
            "{side:?} {back:?}"
        );
        let none = Diffusion {
            forward_orders: 0,
            ..DIFFUSION
        };
        assert_eq!(forward_lobes(&none, 1.0), [0.0; MAX_FORWARD_ORDERS]);
        assert_eq!(forward_source(&fwd, 0.0), 0.0);
        assert!(forward_source(&fwd, 1.0) > 0.1 && forward_source(&fwd, 40.0) < 1e-12);
    }

    /// The slab's cosine is the light's zenith cosine where the field is
    /// flat or empty and never below it; on a flank a low light faces
    /// it is larger. The connected column ends at the first gap.
    #[test]
    fn slab_cosine_and_connected_column() {
        let f = field();
        let sh = shell();
        let sun = Vec3::new(0.0, 0.94, 0.342);
        let up = Vec3::new(0.0, 0.0, RG + 1.8);
        assert!((slab_cosine(&DIFFUSION, &f, &sh, up, 0.0, sun) - 0.342).abs() < 1e-3);
        let mut lit = 0;
        for i in 0..400 {
            let p = Vec3::new(
                (i % 20) as f32 * 0.31,
                (i / 20) as f32 * 0.27,
                RG + f.base_km + 0.4,
            );
            let sigma = f.extinction(glam::Vec2::new(p.x, p.y), p.length() - RG);
            let mu = slab_cosine(&DIFFUSION, &f, &sh, p, sigma, sun);
            assert!((0.342 - 1e-3..=1.0 + 1e-6).contains(&mu), "{mu}");
            lit += (mu > 0.5) as u32;
            let all = optical_depth_through(&f, &sh, p, -sun, 6);
            let piece = optical_depth_connected(&f, &sh, p, -sun, 6, 3.0);
            assert!(piece <= all + 1e-4 && piece >= 0.0, "{piece} {all}");
            assert_eq!(optical_depth_connected(&f, &sh, p, -sun, 6, -1.0), all);
        }
        assert!(lit > 10, "lit flanks: {lit}");
    }

    /// In the thin limit the high layer scatters p(θ) E τ / μ_v and
    /// transmits e^{−τ/μ_v}.
    #[test]
    fn high_layer_thin_limit() {
        let spec = HighCloudSpec {
            coverage: 1.0,
            optical_depth: 1e-3,
            ..HighCloudSpec::default()
        };
        let f = HighField::new(&spec, 0.0);
        let sh = shell();
        let v = Vec3::Z;
        let sun = Vec3::new(0.0, 0.6, 0.8);
        let lights = [CloudLight {
            dir: sun,
            irradiance_rgb: [1.0; 3],
        }];
        let hit = shade_high(&f, &sh, v, &lights, [0.0; 3]);
        let tau = f.optical_depth(glam::Vec2::ZERO);
        assert!(tau > 0.0);
        let expect = CLOUD_PHASE.eval(v.dot(sun), 1.0) * tau;
        assert!(
            (hit.radiance[0] / expect - 1.0).abs() < 0.01,
            "{hit:?} {expect}"
        );
        assert!((hit.transmittance - (-tau).exp()).abs() < 1e-6);
    }

    /// The two-lobe phase function and each octave's are normalised.
    #[test]
    fn phase_is_normalised() {
        for k in [1.0, 0.5, 0.25] {
            let n = 20_000;
            let s: f64 = (0..n)
                .map(|i| {
                    let mu = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                    CLOUD_PHASE.eval(mu as f32, k) as f64 * 2.0 / n as f64
                })
                .sum::<f64>()
                * 2.0
                * std::f64::consts::PI;
            assert!((s - 1.0).abs() < 1e-3, "{k}: {s}");
        }
    }
}
