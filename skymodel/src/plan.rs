//! The pass plan: every effect of the scene, back to front, with whether
//! its pass runs and, when it does not, why ([`SkipReason`]).
//!
//! The plan is made in two steps. [`plan`] (called by
//! [`crate::SkyState::at`]) decides from the scene and the instant alone:
//! not requested, not available yet, the Sun's or the Moon's disk below the
//! horizon, every planet below the horizon. The frame plan
//! ([`crate::frame::FramePlan`]) then adds what depends on the image: a
//! night pass that would change no displayed value at the frame's exposure
//! is culled ([`Culled`]). No module of this crate below the frame plan
//! imports this one back except `state` and `night`, which only use its
//! types.

use serde::{Serialize, Serializer};

use crate::moon::{MoonState, MOONLIGHT_BELOW_DEG};
use crate::scene::{Effect, Scene};
use crate::stars::PointSource;
use crate::sun::SunState;

/// Why a pass does not run.
#[derive(Debug, Clone, PartialEq)]
pub enum SkipReason {
    /// The scene's `effects` do not list it.
    NotRequested,
    /// The effect has no pass in this version.
    NotAvailable(Effect),
    /// The Sun's drawn disk lies entirely below the horizon.
    SunBelowHorizon,
    /// The Moon's drawn disk lies entirely below the horizon, at this
    /// refracted altitude of its centre (degrees).
    MoonBelowHorizon {
        /// Refracted altitude of the centre, degrees.
        alt_refracted_deg: f64,
    },
    /// Mercury–Saturn are all below the horizon.
    PlanetsBelowHorizon,
    /// Invisible at the frame's exposure.
    Culled(Culled),
    /// A lighting pass of a scene without a 3D world.
    NoWorld,
    /// Shadow maps while neither the Sun nor the Moon lights the world.
    NoDirectLight,
    /// Light shafts while neither the Sun nor the Moon lights the world.
    NoShaftLight,
    /// Light shafts without fog, or in fog that does not scatter.
    NoFogScattering,
    /// Ambient occlusion without the sky's light (the atmosphere pass not
    /// requested): it multiplies nothing else.
    NoSkyLight,
    /// Screen-space reflections without the sky's light (the atmosphere
    /// pass not requested): the reflections replace the sky's specular
    /// term, which is then absent.
    NoSkyReflection,
    /// Screen-space light shafts (`mitchell`, `sousa`) whose light is far
    /// off screen ([`shaft_light_off_screen`]).
    ShaftLightOffScreen {
        /// `Sun` or `Moon`.
        light: &'static str,
        /// Its angle from the view axis, degrees.
        off_axis_deg: f64,
    },
    /// The texture pass of a scene without `sky_texture`.
    NoTexture,
    /// The clouds pass of a scene without a cloud layer (both
    /// `clouds.low.coverage` and `clouds.high.coverage` are 0).
    NoClouds,
    /// Hidden behind a sky texture that replaces the physical sky
    /// (`sky_texture.blend` 1, the pass not in `sky_texture.keep`).
    ReplacedByTexture,
    /// Hidden by an overcast sky: the cloud layers keep at most this
    /// fraction of the light in every sampled direction of the view
    /// ([`crate::frame::overcast`]).
    Overcast {
        /// The largest transmittance found.
        max_transmittance: f32,
    },
}

/// Why a night pass is invisible at the frame's exposure
/// ([`crate::night`]'s culling criterion).
#[derive(Debug, Clone, PartialEq)]
pub enum Culled {
    /// No source of this kind (`star`, `planet`) lies in the field of
    /// view above the horizon.
    NoSourceInView(&'static str),
    /// The brightest candidate's core peak does not show against the sky
    /// background (both cd/m²) at `ev100`.
    BackgroundBrighter {
        /// `star` or `planet`.
        what: &'static str,
        /// Sky background at the source, cd/m².
        background: f32,
        /// Core peak luminance, cd/m².
        peak: f32,
        /// The frame's EV100.
        ev100: f64,
    },
    /// The brightest candidate is below one display level at `ev100`.
    BelowDisplayLevel {
        /// `star` or `planet`.
        what: &'static str,
        /// Core peak luminance, cd/m².
        peak: f32,
        /// The frame's EV100.
        ev100: f64,
    },
    /// The image shows no sky above the horizon (Milky Way).
    NoSkyInView,
    /// The diffuse night light changes no sample of the sky background.
    DiffuseBackgroundBrighter {
        /// Darkest sampled background, cd/m².
        background: f32,
        /// Brightest sampled night light, cd/m².
        night_light: f32,
        /// The frame's EV100.
        ev100: f64,
    },
    /// The diffuse night light is below one display level at `ev100`.
    DiffuseBelowDisplayLevel {
        /// The frame's EV100.
        ev100: f64,
    },
}

impl std::fmt::Display for Culled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Culled::NoSourceInView(what) => {
                write!(f, "no {what} in the field of view above the horizon")
            }
            Culled::BackgroundBrighter {
                what,
                background,
                peak,
                ev100,
            } => write!(
                f,
                "sky background brighter than the brightest visible {what} (background {background:.3e} cd/m², {what} peak {peak:.3e} cd/m² at EV100 {ev100:.1})"
            ),
            Culled::BelowDisplayLevel { what, peak, ev100 } => write!(
                f,
                "the brightest {what} is below one display level at EV100 {ev100:.1} (peak {peak:.3e} cd/m²)"
            ),
            Culled::NoSkyInView => f.write_str("no sky above the horizon in the field of view"),
            Culled::DiffuseBackgroundBrighter {
                background,
                night_light,
                ev100,
            } => write!(
                f,
                "sky background brighter than the Milky Way and night-sky light (background ≥ {background:.3e} cd/m², night light ≤ {night_light:.3e} cd/m² at EV100 {ev100:.1})"
            ),
            Culled::DiffuseBelowDisplayLevel { ev100 } => write!(
                f,
                "the night-sky light is below one display level at EV100 {ev100:.1}"
            ),
        }
    }
}

impl std::fmt::Display for SkipReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SkipReason::NotRequested => f.write_str("not requested"),
            SkipReason::NotAvailable(e) => write!(
                f,
                "not available yet: the {} pass arrives with a later version",
                e.name()
            ),
            SkipReason::SunBelowHorizon => f.write_str("the Sun's disk is below the horizon"),
            SkipReason::MoonBelowHorizon { alt_refracted_deg } => {
                write!(
                    f,
                    "the Moon's disk is below the horizon (refracted altitude {alt_refracted_deg:.2}°; the moonlit sky is part of the atmosphere pass"
                )?;
                if *alt_refracted_deg < MOONLIGHT_BELOW_DEG {
                    write!(f, ", which leaves it out below {MOONLIGHT_BELOW_DEG}°")?;
                }
                f.write_str(")")
            }
            SkipReason::PlanetsBelowHorizon => f.write_str("every planet is below the horizon"),
            SkipReason::Culled(c) => c.fmt(f),
            SkipReason::NoWorld => f.write_str("no 3D world in the scene"),
            SkipReason::NoDirectLight => f.write_str(
                "neither the Sun nor the Moon lights the world (each is below the horizon or not among the effects): nothing casts a shadow",
            ),
            SkipReason::NoShaftLight => f.write_str(
                "neither the Sun nor the Moon lights the world (each is below the horizon or not among the effects): no light to scatter in the fog",
            ),
            SkipReason::NoFogScattering => f.write_str(
                "no fog scatters light (the scene has no fog, or its scattering_per_m is 0)",
            ),
            SkipReason::NoSkyLight => f.write_str(
                "no sky light to occlude (the atmosphere pass is not requested); AO multiplies only the sky's light",
            ),
            SkipReason::NoSkyReflection => f.write_str(
                "no sky light whose specular term the reflections replace (the atmosphere pass is not requested)",
            ),
            SkipReason::ShaftLightOffScreen {
                light,
                off_axis_deg,
            } => write!(
                f,
                "the {light} is far off screen for the screen-space light shafts ({off_axis_deg:.1}° from the view axis: behind the camera, or its image more than {OFF_SCREEN_WIDTHS} frame widths or heights beyond the frame)"
            ),
            SkipReason::NoTexture => f.write_str("no sky texture in the scene"),
            SkipReason::NoClouds => f.write_str(
                "no cloud layer in the scene (clouds.low.coverage and clouds.high.coverage are 0)",
            ),
            SkipReason::ReplacedByTexture => {
                f.write_str("replaced by the sky texture (blend 1; not in sky_texture.keep)")
            }
            SkipReason::Overcast { max_transmittance } => write!(
                f,
                "hidden by an overcast sky: the clouds keep at most {max_transmittance:.1e} of the light behind them in every sampled direction of the view"
            ),
        }
    }
}

impl Serialize for SkipReason {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// Whether a pass runs, and if not, why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlannedPass {
    /// The effect.
    pub effect: Effect,
    /// Whether it runs.
    pub run: bool,
    /// Why it does not run.
    pub reason: Option<SkipReason>,
}

impl PlannedPass {
    /// Marks the pass as not running, for `reason` (the first reason wins).
    pub fn skip(&mut self, reason: SkipReason) {
        if self.run {
            self.run = false;
            self.reason = Some(reason);
        }
    }
}

/// Whether the Sun or the Moon, requested and above the horizon, lights a
/// world (what shadows and light shafts need).
fn lights_the_world(scene: &Scene, sun: &SunState, moon: &MoonState) -> bool {
    (sun.alt_refracted_deg > 0.0 && scene.wants(Effect::Sun))
        || (moon.alt_refracted_deg > 0.0 && scene.wants(Effect::Moon))
}

/// The pass plan of `scene` at an instant with this Sun, Moon and these
/// planets (refracted ENU directions): every effect, back to front.
pub fn plan(
    scene: &Scene,
    sun: &SunState,
    moon: &MoonState,
    planets: &[PointSource],
) -> Vec<PlannedPass> {
    Effect::ALL
        .into_iter()
        .map(|e| {
            let reason = if !scene.wants(e) {
                Some(SkipReason::NotRequested)
            } else if !e.available() {
                Some(SkipReason::NotAvailable(e))
            } else {
                match e {
                    Effect::Sun => sun_below_horizon(scene, sun),
                    Effect::Moon => moon_below_horizon(scene, moon),
                    Effect::Planets if planets.iter().all(|s| s.dir.z < 0.0) => {
                        Some(SkipReason::PlanetsBelowHorizon)
                    }
                    e if e.is_lighting() && scene.world.is_none() => Some(SkipReason::NoWorld),
                    Effect::Texture if scene.sky_texture.is_none() => Some(SkipReason::NoTexture),
                    Effect::Clouds if !scene.clouds.has_low() && !scene.clouds.has_high() => {
                        Some(SkipReason::NoClouds)
                    }
                    Effect::Shadows if !lights_the_world(scene, sun, moon) => {
                        Some(SkipReason::NoDirectLight)
                    }
                    Effect::Godrays if !scene.fog.is_some_and(|f| f.scattering_per_m > 0.0) => {
                        Some(SkipReason::NoFogScattering)
                    }
                    Effect::Godrays if !lights_the_world(scene, sun, moon) => {
                        Some(SkipReason::NoShaftLight)
                    }
                    Effect::Ao if !scene.wants(Effect::Atmosphere) => Some(SkipReason::NoSkyLight),
                    Effect::Ssr if !scene.wants(Effect::Atmosphere) => {
                        Some(SkipReason::NoSkyReflection)
                    }
                    Effect::Godrays if scene.lighting.godrays.method.screen_space() => {
                        shaft_light_off_screen(scene, sun, moon)
                    }
                    _ => None,
                }
            };
            PlannedPass {
                effect: e,
                run: reason.is_none(),
                reason,
            }
        })
        .collect()
}

/// How far beyond the frame's edge, in frame widths (heights), a light's
/// image may lie for the screen-space light shafts to run.
pub const OFF_SCREEN_WIDTHS: f64 = 2.0;

/// Whether the light of the screen-space light shafts — the Sun when it is
/// above the horizon, else the Moon — is *far off screen* for the
/// perspective camera: behind it (at 90° or more from the view axis: its
/// image, the point the radial blur converges on, is then mirrored through
/// the frame's centre), or its image more than [`OFF_SCREEN_WIDTHS`] frame
/// widths (heights) beyond the frame's edge, where every pixel's taps
/// toward it lie at least two-thirds outside the frame (the blur has
/// nothing to gather there).
pub fn shaft_light_off_screen(
    scene: &Scene,
    sun: &SunState,
    moon: &MoonState,
) -> Option<SkipReason> {
    let (light, dir) = if sun.alt_refracted_deg > 0.0 {
        ("Sun", sun.dir())
    } else {
        ("Moon", glam::DVec3::from_array(moon.enu))
    };
    let cam = &scene.camera;
    if cam.projection != crate::Projection::Perspective {
        return None;
    }
    let (f, r, u) = cam.basis();
    let d = dir.normalize_or_zero();
    let off_axis_deg = f.dot(d).clamp(-1.0, 1.0).acos().to_degrees();
    let (w, h) = cam.image_size();
    let tan_v = (cam.fov_deg.to_radians() / 2.0).tan();
    let tan_h = tan_v * w as f64 / h.max(1) as f64;
    let reach = 1.0 + 2.0 * OFF_SCREEN_WIDTHS;
    let far = f.dot(d) <= 0.0
        || (r.dot(d) / f.dot(d) / tan_h).abs() > reach
        || (u.dot(d) / f.dot(d) / tan_v).abs() > reach;
    far.then_some(SkipReason::ShaftLightOffScreen {
        light,
        off_axis_deg,
    })
}

/// The Sun pass does not run when its drawn disk lies entirely below the
/// horizon (refracted altitude + drawn radius < 0°).
fn sun_below_horizon(scene: &Scene, sun: &SunState) -> Option<SkipReason> {
    let top = sun.alt_refracted_deg + (sun.angular_radius * scene.sun_scale).to_degrees();
    (top < 0.0).then_some(SkipReason::SunBelowHorizon)
}

/// The Moon pass does not run when the drawn disk lies entirely below the
/// horizon (refracted altitude + drawn radius < 0°). The threshold is the
/// horizon itself because the Moon pass draws only the disk (the ground
/// hides what is below the horizon); the moonlit sky belongs to the
/// atmosphere pass ([`crate::moon::moonlight_scale`], down to
/// [`MOONLIGHT_BELOW_DEG`]).
fn moon_below_horizon(scene: &Scene, moon: &MoonState) -> Option<SkipReason> {
    let top = moon.alt_refracted_deg + (moon.angular_radius * scene.moon_scale).to_degrees();
    (top < 0.0).then_some(SkipReason::MoonBelowHorizon {
        alt_refracted_deg: moon.alt_refracted_deg,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reasons_read_as_before() {
        assert_eq!(SkipReason::NotRequested.to_string(), "not requested");
        assert_eq!(
            SkipReason::NotAvailable(Effect::Gi).to_string(),
            "not available yet: the gi pass arrives with a later version"
        );
        assert_eq!(
            SkipReason::MoonBelowHorizon {
                alt_refracted_deg: -10.0
            }
            .to_string(),
            "the Moon's disk is below the horizon (refracted altitude -10.00°; the moonlit sky is part of the atmosphere pass, which leaves it out below -6°)"
        );
        assert_eq!(
            SkipReason::MoonBelowHorizon {
                alt_refracted_deg: -2.0
            }
            .to_string(),
            "the Moon's disk is below the horizon (refracted altitude -2.00°; the moonlit sky is part of the atmosphere pass)"
        );
        let c = Culled::BackgroundBrighter {
            what: "star",
            background: 5190.0,
            peak: 12.5,
            ev100: 15.06,
        };
        assert_eq!(
            SkipReason::Culled(c).to_string(),
            "sky background brighter than the brightest visible star (background 5.190e3 cd/m², star peak 1.250e1 cd/m² at EV100 15.1)"
        );
        assert_eq!(
            serde_json::to_string(&SkipReason::PlanetsBelowHorizon).unwrap(),
            "\"every planet is below the horizon\""
        );
    }

    /// Munich, 2024-06-21 11:00 UTC: the Sun 65° high, 6° east of south.
    /// The screen-space shafts run looking south (its image 3.7 frame
    /// heights above the centre, inside the reach of 5), not looking north
    /// (behind), east (its image far to the side) or south through a 20°
    /// field (12 heights above).
    #[test]
    fn screen_space_shafts_need_the_light_near_the_frame() {
        let at = |look: [f64; 3], fov: f64, method| {
            let mut s = Scene::default();
            s.time.utc = "2024-06-21T11:00:00Z".into();
            s.observer.lat_deg = 48.14;
            s.observer.lon_deg = 11.58;
            s.camera.projection = crate::Projection::Perspective;
            (s.camera.width, s.camera.height, s.camera.fov_deg) = (160, 90, fov);
            s.camera.position_m = Some([0.0, 1.7, 0.0]);
            s.camera.look_at_m = Some(look);
            s.effects = vec![Effect::Sun, Effect::World, Effect::Godrays];
            s.world = Some(crate::WorldSpec {
                gltf: "w.glb".into(),
                ground: true,
            });
            s.fog = Some(crate::FogSpec {
                scattering_per_m: 0.01,
                ..crate::FogSpec::default()
            });
            s.lighting.godrays.method = method;
            let state = crate::SkyState::at(&s).unwrap();
            let p = state.passes.iter().find(|p| p.effect == Effect::Godrays);
            p.unwrap().reason.clone()
        };
        use crate::GodraysMethod::{Mitchell, Sousa, Toth};
        let (south, north, east) = ([0.0, 1.7, 10.0], [0.0, 1.7, -10.0], [10.0, 1.7, 0.0]);
        assert_eq!(at(south, 60.0, Mitchell), None);
        assert_eq!(at(north, 60.0, Toth), None);
        for (look, fov) in [(north, 60.0), (east, 60.0), (south, 20.0)] {
            let r = at(look, fov, Sousa).expect("skipped");
            let SkipReason::ShaftLightOffScreen {
                light,
                off_axis_deg,
            } = r
            else {
                panic!("{r}")
            };
            assert_eq!(light, "Sun");
            assert!(off_axis_deg > 60.0, "{off_axis_deg}");
            assert!(r.to_string().starts_with("the Sun is far off screen"));
        }
    }

    /// Shadows and light shafts need a light that lights the world: the
    /// Sun high at noon does not when `sun` is not among the effects.
    #[test]
    fn shadows_need_a_requested_light() {
        let reasons = |effects: &[Effect]| {
            let mut s = Scene::default();
            s.time.utc = "2024-06-21T11:00:00Z".into();
            s.effects = effects.to_vec();
            s.camera.projection = crate::Projection::Perspective;
            s.world = Some(crate::WorldSpec {
                gltf: "w.glb".into(),
                ground: false,
            });
            s.fog = Some(crate::FogSpec::default());
            let state = crate::SkyState::at(&s).unwrap();
            [Effect::Shadows, Effect::Godrays].map(|e| {
                let p = state.passes.iter().find(|p| p.effect == e).unwrap();
                p.reason.clone()
            })
        };
        let lit = [Effect::Sun, Effect::World, Effect::Shadows, Effect::Godrays];
        assert_eq!(reasons(&lit), [None, None]);
        let unlit = [Effect::World, Effect::Shadows, Effect::Godrays];
        assert_eq!(
            reasons(&unlit),
            [
                Some(SkipReason::NoDirectLight),
                Some(SkipReason::NoShaftLight)
            ]
        );
    }

    #[test]
    fn skip_keeps_the_first_reason() {
        let mut p = PlannedPass {
            effect: Effect::Stars,
            run: true,
            reason: None,
        };
        p.skip(SkipReason::PlanetsBelowHorizon);
        p.skip(SkipReason::NotRequested);
        assert!(!p.run);
        assert_eq!(p.reason, Some(SkipReason::PlanetsBelowHorizon));
    }
}
