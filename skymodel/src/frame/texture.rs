//! The texture pass's frame ([`TextureFrame`]): which textures the
//! schedule shows at the instant and with which weights (cross-fades),
//! their gain (units), the rotation from the observer's frame into the
//! textures', the blend and the horizon band; and where the pass and the
//! kept physical passes go in the pass list ([`arrange`]).
//!
//! Per pixel with view direction d (ENU), behind it the radiance B the
//! earlier passes drew:
//!
//! ```text
//! T(d)  = Σ_layers gain_i · texture_i(R · d)            (bilinear, SkyTexture::sample)
//! T'(d) = (1 − w(h)) · T(d) + w(h) · band colour        (w = 1 − smoothstep(height, height + softness, h))
//! out   = (1 − blend) · B + blend · T'(d)
//! ```
//!
//! h is the altitude of d in degrees. The kept passes (`sky_texture.keep`)
//! are drawn after it, over the texture, extinguished by the physical
//! atmosphere as usual.

use std::sync::Arc;

use glam::{DMat3, DVec3, Vec3};

use crate::error::RenderError;
use crate::plan::{PlannedPass, SkipReason};
use crate::projection::enu_from_alt_az;
use crate::scene::Effect;
use crate::state::SkyState;
use crate::texture_sky::store::SunMask;
use crate::texture_sky::{horizontal_illuminance, Mapping, SkyTexture, TextureStore};
use crate::texture_spec::{parse_time, KeptPass, RotationMode, SkyTextureSpec, TextureUnits};

/// The Earth's rotation relative to the stars, degrees per hour of time.
pub const SIDEREAL_DEG_PER_H: f64 = 15.041_068_64;

/// One texture of the frame with its gain (units × cross-fade weight).
#[derive(Debug, Clone)]
pub struct TextureLayer {
    /// The prepared texture.
    pub texture: Arc<SkyTexture>,
    /// Radiance per texture value, cd/m² (the LDR white or 1, times the
    /// `sky` units' scale, times the cross-fade weight).
    pub gain: f32,
}

/// The horizon band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HorizonBand {
    /// Radiance, linear sRGB cd/m².
    pub color: [f32; 3],
    /// Top, degrees of altitude.
    pub height_deg: f32,
    /// Soft edge above the top, degrees.
    pub softness_deg: f32,
}

impl HorizonBand {
    /// The band's weight at altitude `h_deg`: 1 below its top, 0 above the
    /// soft edge, smoothstep between.
    pub fn weight(&self, h_deg: f32) -> f32 {
        if self.softness_deg <= 0.0 {
            return if h_deg < self.height_deg { 1.0 } else { 0.0 };
        }
        let t = ((h_deg - self.height_deg) / self.softness_deg).clamp(0.0, 1.0);
        1.0 - t * t * (3.0 - 2.0 * t)
    }
}

/// What the texture pass draws in one frame.
#[derive(Debug, Clone)]
pub struct TextureFrame {
    /// One texture, or two during a cross-fade (the earlier first).
    pub layers: Vec<TextureLayer>,
    /// Observer ENU → texture frame.
    pub rotation: DMat3,
    /// The texture's weight over what is behind it.
    pub blend: f32,
    /// The horizon band.
    pub horizon: Option<HorizonBand>,
    /// The `sky` units' scale (1 for `native`).
    pub units_scale: f64,
}

impl TextureFrame {
    /// The frame of `spec` at `state`: its textures from `store` (decoded,
    /// checked and prepared once); `sky_lux` is the physical sky's
    /// horizontal illuminance (needed by the `sky` units).
    pub fn prepare(
        spec: &SkyTextureSpec,
        state: &SkyState,
        store: &mut TextureStore,
        sky_lux: Option<f64>,
    ) -> Result<TextureFrame, RenderError> {
        let mask = spec.sun_mask.as_ref().map(|m| SunMask {
            dir: m
                .direction
                .map(|d| enu_from_alt_az(d.alt_deg.to_radians(), d.az_deg.to_radians())),
            radius: m.radius_deg.to_radians(),
        });
        let mut layers = Vec::new();
        for (path, mapping, weight) in schedule(spec, state.jd_tt)? {
            let (texture, hdr) = store
                .prepared(&path, mapping, mask)
                .map_err(RenderError::Texture)?;
            let unit = if hdr {
                1.0
            } else {
                spec.ldr_white_cd_m2 as f32
            };
            layers.push(TextureLayer {
                texture,
                gain: unit * weight,
            });
        }
        let rotation = rotation(spec, state)?;
        let horizon = spec.horizon.as_ref().map(|h| HorizonBand {
            color: h.color_cd_m2.map(|c| c as f32),
            height_deg: h.height_deg as f32,
            softness_deg: h.softness_deg as f32,
        });
        let mut frame = TextureFrame {
            layers,
            rotation,
            blend: spec.blend as f32,
            horizon,
            units_scale: 1.0,
        };
        if spec.units == TextureUnits::Sky {
            let sky = sky_lux.ok_or_else(|| {
                RenderError::Scene(crate::scene::SceneError::new(
                    "sky_texture.units",
                    "'sky' scales the texture to the physical sky's horizontal illuminance and needs the atmosphere effect",
                ))
            })?;
            let tex = horizontal_illuminance(|d| frame.texture(d));
            if tex > 0.0 {
                frame.units_scale = sky / tex;
                for l in &mut frame.layers {
                    l.gain *= frame.units_scale as f32;
                }
            }
        }
        Ok(frame)
    }

    /// The textures' radiance towards observer direction `d` (before the
    /// horizon band).
    pub fn texture(&self, d: DVec3) -> [f32; 3] {
        let t = self.rotation * d;
        let mut out = [0.0f32; 3];
        for l in &self.layers {
            let c = l.texture.sample(t);
            for k in 0..3 {
                out[k] += l.gain * c[k];
            }
        }
        out
    }

    /// The pass's result over `behind` towards `d` (module docs).
    pub fn over(&self, behind: [f32; 3], d: Vec3) -> [f32; 3] {
        let mut t = self.texture(d.as_dvec3());
        if let Some(h) = &self.horizon {
            let w = h.weight(d.z.clamp(-1.0, 1.0).asin().to_degrees());
            t = std::array::from_fn(|k| (1.0 - w) * t[k] + w * h.color[k]);
        }
        let a = self.blend;
        std::array::from_fn(|k| (1.0 - a) * behind[k] + a * t[k])
    }
}

/// The textures shown at Julian date (TT) `jd` with their cross-fade
/// weights: the last transition that has begun (or the first texture)
/// and, while its fade lasts, the one before it.
pub fn schedule(
    spec: &SkyTextureSpec,
    jd: f64,
) -> Result<Vec<(String, Mapping, f32)>, RenderError> {
    let mut shown = vec![(spec.path.clone(), spec.mapping, 1.0f32)];
    for (k, t) in spec.transitions.iter().enumerate() {
        let field = format!("sky_texture.transitions[{k}].at_utc");
        let start = parse_time(&field, &t.at_utc).map_err(RenderError::Scene)?;
        if jd < start {
            break;
        }
        let s = if t.fade_s > 0.0 {
            (((jd - start) * 86_400.0) / t.fade_s).clamp(0.0, 1.0) as f32
        } else {
            1.0
        };
        let prev = shown.pop().map(|(p, m, _)| (p, m));
        shown.clear();
        if let (Some((p, m)), true) = (prev, s < 1.0) {
            shown.push((p, m, 1.0 - s));
        }
        shown.push((t.path.clone(), t.mapping.unwrap_or(spec.mapping), s));
    }
    Ok(shown)
}

/// Observer ENU → texture frame: the texture turned by its azimuth (and
/// rate) about the zenith, or with the stars about the celestial pole
/// (`RotationMode`).
pub fn rotation(spec: &SkyTextureSpec, state: &SkyState) -> Result<DMat3, RenderError> {
    let r = &spec.rotation;
    let hours = if r.mode == RotationMode::Fixed {
        0.0
    } else {
        let t0 = parse_time("sky_texture.rotation.reference_utc", &r.reference_utc)
            .map_err(RenderError::Scene)?;
        (state.jd_tt - t0) * 24.0
    };
    let (azimuth, pole_turn) = match r.mode {
        RotationMode::Fixed => (r.azimuth_deg, 0.0),
        RotationMode::Rate => (r.azimuth_deg + r.rate_deg_per_h * hours, 0.0),
        RotationMode::Sidereal => (
            r.azimuth_deg,
            (SIDEREAL_DEG_PER_H * hours).rem_euclid(360.0),
        ),
    };
    // The texture's azimuth A shows at the observer's A + azimuth: look
    // up at −azimuth. With the stars, the texture's instant saw the star
    // now at d at R_pole(+θ) d (the sky turns by −θ about the pole).
    let az = DMat3::from_axis_angle(DVec3::Z, azimuth.rem_euclid(360.0).to_radians());
    let pole = DVec3::from_array(state.celestial_pole).normalize_or(DVec3::Z);
    let turn = DMat3::from_axis_angle(pole, pole_turn.to_radians());
    Ok(az * turn)
}

/// The effect of a kept pass.
pub fn effect_of(k: KeptPass) -> Effect {
    match k {
        KeptPass::Sun => Effect::Sun,
        KeptPass::Moon => Effect::Moon,
        KeptPass::Stars => Effect::Stars,
        KeptPass::Planets => Effect::Planets,
    }
}

/// Puts the texture pass's neighbours in order: with `blend` 1 the
/// atmosphere, the Milky Way and every body not kept are skipped
/// ([`SkipReason::ReplacedByTexture`]); the kept passes move after the
/// texture pass (drawn over it).
pub fn arrange(passes: &mut Vec<PlannedPass>, spec: &SkyTextureSpec) {
    let replace = spec.blend >= 1.0;
    let kept = |e: Effect| spec.keep.iter().any(|k| effect_of(*k) == e);
    for p in passes.iter_mut() {
        let body = matches!(
            p.effect,
            Effect::Sun | Effect::Moon | Effect::Stars | Effect::Planets
        );
        let background = matches!(p.effect, Effect::Atmosphere | Effect::Milkyway);
        if replace && (background || (body && !kept(p.effect))) {
            p.skip(SkipReason::ReplacedByTexture);
        }
    }
    let (front, mut rest): (Vec<PlannedPass>, Vec<PlannedPass>) =
        passes.drain(..).partition(|p| kept(p.effect));
    let at = rest
        .iter()
        .position(|p| p.effect == Effect::Texture)
        .map_or(rest.len(), |i| i + 1);
    rest.splice(at..at, front);
    *passes = rest;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::PlannedPass;
    use crate::scene::Scene;
    use crate::texture_spec::{RotationSpec, TransitionSpec};

    fn state_at(utc: &str) -> SkyState {
        let mut s = Scene::default();
        s.time.utc = utc.into();
        SkyState::at(&s).unwrap()
    }

    /// With `sidereal`, a star seen now at d looks up the texture where
    /// the same star stood at the reference instant (the star frame of
    /// the exact reduction at both instants, 3 h apart).
    #[test]
    fn sidereal_rotation_keeps_a_star_photo_on_the_stars() {
        let (t0, t1) = ("2024-01-15T20:00:00Z", "2024-01-15T23:00:00Z");
        let spec = SkyTextureSpec {
            rotation: RotationSpec {
                mode: RotationMode::Sidereal,
                reference_utc: t0.into(),
                ..RotationSpec::default()
            },
            ..SkyTextureSpec::default()
        };
        let (s0, s1) = (state_at(t0), state_at(t1));
        let r = rotation(&spec, &s1).unwrap();
        for v in [
            DVec3::new(0.3, 0.5, 0.81),
            DVec3::new(-0.7, 0.2, 0.1),
            DVec3::X,
        ] {
            let v = v.normalize();
            let d0 = s0.night.star_frame.icrs_to_enu * v;
            let d1 = s1.night.star_frame.icrs_to_enu * v;
            let off = (r * d1).angle_between(d0).to_degrees();
            assert!(off < 0.05, "{v}: {off}°");
        }
        // A fixed rotation by 90° shows the texture's North in the East.
        let fixed = SkyTextureSpec {
            rotation: RotationSpec {
                azimuth_deg: 90.0,
                ..RotationSpec::default()
            },
            ..SkyTextureSpec::default()
        };
        let r = rotation(&fixed, &s1).unwrap();
        assert!((r * DVec3::X - DVec3::Y).length() < 1e-12);
    }

    #[test]
    fn the_schedule_cross_fades() {
        let spec = SkyTextureSpec {
            path: "a".into(),
            transitions: vec![
                TransitionSpec {
                    path: "b".into(),
                    mapping: Some(Mapping::Cube),
                    at_utc: "2024-01-01T12:00:00Z".into(),
                    fade_s: 3600.0,
                },
                TransitionSpec {
                    path: "c".into(),
                    mapping: None,
                    at_utc: "2024-01-01T18:00:00Z".into(),
                    fade_s: 0.0,
                },
            ],
            ..SkyTextureSpec::default()
        };
        let at = |utc: &str| {
            let jd = parse_time("t", utc).unwrap();
            schedule(&spec, jd)
                .unwrap()
                .into_iter()
                .map(|(p, m, w)| (p, m, (w * 1000.0).round() / 1000.0))
                .collect::<Vec<_>>()
        };
        assert_eq!(
            at("2024-01-01T11:00:00Z"),
            vec![("a".into(), Mapping::Sphere, 1.0)]
        );
        assert_eq!(
            at("2024-01-01T12:15:00Z"),
            vec![
                ("a".into(), Mapping::Sphere, 0.75),
                ("b".into(), Mapping::Cube, 0.25)
            ]
        );
        assert_eq!(
            at("2024-01-01T13:00:00Z"),
            vec![("b".into(), Mapping::Cube, 1.0)]
        );
        assert_eq!(
            at("2024-01-01T18:00:00Z"),
            vec![("c".into(), Mapping::Sphere, 1.0)]
        );
    }

    #[test]
    fn the_band_and_the_pass_order() {
        let band = HorizonBand {
            color: [1.0; 3],
            height_deg: 5.0,
            softness_deg: 4.0,
        };
        assert_eq!(band.weight(-10.0), 1.0);
        assert_eq!(band.weight(5.0), 1.0);
        assert!((band.weight(7.0) - 0.5).abs() < 1e-6);
        assert_eq!(band.weight(9.0), 0.0);
        let spec = SkyTextureSpec {
            keep: vec![KeptPass::Sun, KeptPass::Stars],
            ..SkyTextureSpec::default()
        };
        let mut passes: Vec<PlannedPass> = Effect::ALL
            .into_iter()
            .map(|effect| PlannedPass {
                effect,
                run: true,
                reason: None,
            })
            .collect();
        arrange(&mut passes, &spec);
        let order: Vec<(&str, bool)> = passes
            .iter()
            .take(9)
            .map(|p| (p.effect.name(), p.run))
            .collect();
        assert_eq!(
            order,
            vec![
                ("milkyway", false),
                ("planets", false),
                ("moon", false),
                ("atmosphere", false),
                ("texture", true),
                ("stars", true),
                ("sun", true),
                ("clouds", true),
                ("world", true),
            ]
        );
    }
}
