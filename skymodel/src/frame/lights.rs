//! The lights a 3D world receives from the sky of one instant
//! (`shared/spec/world.md`), all derived from the same [`SkyState`] and
//! LUTs as the sky itself, none set by hand:
//!
//! * [`DirectLight`] — the Sun, and on a moonlit night the Moon, as
//!   directional lights: the disk's illuminance outside the atmosphere ×
//!   the spectral transmittance at the observer (the Earth's shadow near
//!   the horizon included) × the visible fraction of the disk (solar
//!   eclipses; lunar-eclipse shading is in the Moon's illuminance);
//! * [`sky_horizontal_rgb`] — the sky dome's illuminance on a horizontal
//!   plane (no Sun or Moon disk);
//! * [`AerialPerspective`] — in-scattered radiance and transmittance
//!   between the camera and each point of the world, from the atmosphere
//!   LUTs (Hillaire 2020 §5.5), on a grid of view directions × distances.

use glam::{DVec3, Vec3};

use crate::atmosphere::{aerial_perspective, AtmosphereLuts};
use crate::moon::lunar_reflectance_spectrum;
use crate::scene::{Effect, Scene};
use crate::spectrum::{BandWeights, Spectrum};
use crate::state::SkyState;

use super::sky_light::{SkyInputs, SkyLight};

/// Luminance of linear sRGB (conventions.md).
pub fn luminance(rgb: [f64; 3]) -> f64 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// A directional light (the Sun or the Moon) at the observer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DirectLight {
    /// Unit vector towards the light, ENU (refracted apparent place).
    pub dir_enu: DVec3,
    /// Illuminance at normal incidence after the atmosphere, linear sRGB
    /// with Y = lux.
    pub rgb: [f64; 3],
    /// The light's true angular radius, radians (its penumbra).
    pub angular_radius: f64,
}

impl DirectLight {
    /// Illuminance at normal incidence, lux.
    pub fn lux(&self) -> f64 {
        luminance(self.rgb)
    }

    /// The direction in the world frame (x East, y Up, z South).
    pub fn dir_world(&self) -> DVec3 {
        crate::projection::scene_from_enu(self.dir_enu)
    }

    /// Refracted altitude, radians.
    pub fn altitude(&self) -> f64 {
        self.dir_enu.z.clamp(-1.0, 1.0).asin()
    }
}

/// The Sun and the Moon as directional lights of one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DirectLights {
    /// The Sun, when the scene asks for it and its disk is above the horizon.
    pub sun: Option<DirectLight>,
    /// The Moon, when it lights the sky ([`crate::moon::moonlight_scale`]:
    /// the Sun below the horizon, the Moon above −6°) and the scene asks for it.
    pub moon: Option<DirectLight>,
}

fn transmitted_rgb(
    luts: Option<&AtmosphereLuts>,
    r0: f32,
    dir: Vec3,
    spectrum: Spectrum,
) -> [f64; 3] {
    let t = luts.map_or(Spectrum::ONE, |l| l.sun_transmittance(r0, dir.z));
    let rgb = BandWeights::solar().to_rgb(&(spectrum * t));
    rgb.map(|c| c.max(0.0) as f64)
}

impl DirectLights {
    /// The lights of `state`, through the atmosphere of `luts` seen from
    /// radius `r0` (km); without LUTs (no atmosphere pass) the lights are
    /// not extinguished.
    pub fn new(
        scene: &Scene,
        state: &SkyState,
        luts: Option<&AtmosphereLuts>,
        r0: f32,
        inputs: Option<&SkyInputs>,
    ) -> DirectLights {
        let sun = &state.sun;
        let sun_light = (scene.wants(Effect::Sun)
            && sun.alt_refracted_deg + sun.angular_radius.to_degrees() > 0.0)
            .then(|| {
                let dir = sun.dir().as_vec3().normalize();
                let scale = (sun.irradiance_scale * sun.visible_fraction) as f32;
                DirectLight {
                    dir_enu: sun.dir().normalize(),
                    rgb: transmitted_rgb(luts, r0, dir, Spectrum::splat(scale)),
                    angular_radius: sun.angular_radius,
                }
            });
        let moon_scale = match inputs {
            Some(i) => i.moon.map(|(m, _)| m.irradiance_scale as f64),
            None => {
                let pole = DVec3::from_array(state.celestial_pole).as_vec3();
                crate::moon::moonlight_scale(scene, sun, &state.moon, pole)
            }
        };
        let moon_light = moon_scale
            .filter(|_| state.moon.alt_refracted_deg > 0.0)
            .map(|scale| {
                let dir = state.moon.dir().as_vec3().normalize();
                let spectrum = lunar_reflectance_spectrum() * scale as f32;
                DirectLight {
                    dir_enu: state.moon.dir().normalize(),
                    rgb: transmitted_rgb(luts, r0, dir, spectrum),
                    angular_radius: state.moon.angular_radius,
                }
            });
        DirectLights {
            sun: sun_light,
            moon: moon_light,
        }
    }
}

/// What the observer's surroundings receive at one instant (`--stats`
/// `sun.direct_*`, `moon.direct_*`, `sky.horizontal_*`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ObserverLights {
    /// The Sun and the Moon as directional lights.
    pub direct: DirectLights,
    /// The sky dome's horizontal illuminance, linear sRGB with Y = lux
    /// (zero without the atmosphere pass).
    pub sky_horizontal_rgb: [f64; 3],
}

/// The sky dome's illuminance on a horizontal plane, linear sRGB with
/// Y = lux: ∫ L(ω) sin e dω over the upper hemisphere, the sunlit and the
/// moonlit sky together (a 256 × 64 quadrature in azimuth × √elevation,
/// which follows the sky-view LUT's packing near the horizon).
pub fn sky_horizontal_rgb(sky: &SkyLight) -> [f64; 3] {
    let (na, ne) = (256usize, 64usize);
    let mut e = [0.0f64; 3];
    for j in 0..ne {
        let (x0, x1) = (j as f64 / ne as f64, (j + 1) as f64 / ne as f64);
        let (e0, e1) = (
            x0 * x0 * std::f64::consts::FRAC_PI_2,
            x1 * x1 * std::f64::consts::FRAC_PI_2,
        );
        // ∫ sin e cos e de over the ring, per unit azimuth.
        let w = 0.5 * (e1.sin().powi(2) - e0.sin().powi(2));
        let em = 0.5 * (e0 + e1);
        for i in 0..na {
            let az = (i as f64 + 0.5) / na as f64 * std::f64::consts::TAU;
            let d = Vec3::new(
                (em.cos() * az.sin()) as f32,
                (em.cos() * az.cos()) as f32,
                em.sin() as f32,
            );
            let l = sky.radiance(d);
            for c in 0..3 {
                e[c] += l[c] as f64 * w * std::f64::consts::TAU / na as f64;
            }
        }
    }
    e
}

/// Steps of the aerial perspective's march between two distances
/// (`atmosphere::aerial_perspective`).
pub const AERIAL_STEPS: usize = 4;

/// Aerial perspective on a grid over the camera's view: for each of
/// `dirs` (ENU, unit) and each distance of `distances_m`, the in-scattered
/// radiance (linear sRGB, cd/m²; the sunlit and the moonlit air) and the
/// transmittance (linear sRGB weights of the solar spectrum).
#[derive(Debug, Clone)]
pub struct AerialPerspective {
    /// Distances of the slices, metres, ascending.
    pub distances_m: Vec<f32>,
    /// Per direction (outer) and slice (inner): in-scattered radiance,
    /// cd/m², and its transmittance in the alpha-free second triple.
    pub table: Vec<([f32; 3], [f32; 3])>,
}

impl AerialPerspective {
    /// Marches every direction of `dirs` through the atmosphere of `luts`
    /// from radius `r0` (km), lit as in `inputs`.
    pub fn compute(
        luts: &AtmosphereLuts,
        inputs: &SkyInputs,
        r0: f32,
        dirs: &[Vec3],
        distances_m: &[f32],
    ) -> AerialPerspective {
        let w = BandWeights::solar();
        let white = w.to_rgb(&Spectrum::ONE);
        let ends: Vec<f32> = distances_m.iter().map(|d| d / 1000.0).collect();
        let mut lights = vec![(inputs.sun_dir, inputs.sun.irradiance_scale)];
        if let Some((m, dir)) = inputs.moon {
            lights.push((dir, m.irradiance_scale));
        }
        let mut table = Vec::with_capacity(dirs.len() * ends.len());
        for &d in dirs {
            let mut rows: Vec<([f32; 3], [f32; 3])> = vec![([0.0; 3], [1.0; 3]); ends.len()];
            for (k, &(light, scale)) in lights.iter().enumerate() {
                let segs = aerial_perspective(luts, r0, d, light, &ends, AERIAL_STEPS);
                for (row, (l, t)) in rows.iter_mut().zip(segs) {
                    let lr = w.to_rgb(&l);
                    for c in 0..3 {
                        row.0[c] += lr[c].max(0.0) * scale;
                    }
                    if k == 0 {
                        let tr = w.to_rgb(&t);
                        row.1 = [0, 1, 2].map(|c| (tr[c] / white[c]).clamp(0.0, 1.0));
                    }
                }
            }
            table.extend(rows);
        }
        AerialPerspective {
            distances_m: distances_m.to_vec(),
            table,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atmosphere::{AtmosphereParams, LutConfig, SkyViewInput};

    fn luts() -> AtmosphereLuts {
        AtmosphereLuts::compute(&AtmosphereParams::default(), &LutConfig::small())
    }

    /// The transmittance falls with distance, the in-scattering grows, and
    /// over a long horizontal path the in-scattering approaches the sky's
    /// horizon radiance (the path then is the sky's own line of sight).
    #[test]
    fn aerial_perspective_grows_towards_the_horizon_sky() {
        let l = luts();
        let r0 = l.medium.bottom;
        let sun_dir = Vec3::new(0.0, 0.6, 0.8);
        let input = SkyViewInput {
            observer_altitude_km: 0.0,
            sun_sin_elevation: 0.8,
            irradiance_scale: 1.0,
        };
        let inputs = SkyInputs {
            sun: input,
            sun_dir,
            moon: None,
        };
        let view = Vec3::new(1.0, 0.0, 0.0);
        let d = [10.0, 1000.0, 10_000.0, 400_000.0];
        let ap = AerialPerspective::compute(&l, &inputs, r0, &[view], &d);
        let y = |k: usize| luminance(ap.table[k].0.map(f64::from));
        let t = |k: usize| ap.table[k].1[1];
        assert!(t(0) > 0.999 && t(0) < 1.0, "{}", t(0));
        assert!(t(1) < t(0) && t(2) < t(1) && t(3) < 0.05);
        assert!(y(0) < y(1) && y(1) < y(2) && y(2) < y(3));
        let sky = crate::atmosphere::SkyView::compute(&l, &input);
        let horizon = luminance(sky.radiance(view, sun_dir).map(f64::from));
        assert!((y(3) / horizon - 1.0).abs() < 0.05, "{} vs {horizon}", y(3));
    }
}
