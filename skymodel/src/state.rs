//! `SkyState`: everything a renderer needs for one instant — the Sun's
//! apparent (refracted) direction in the horizontal frame, its distance,
//! angular size and extraterrestrial illuminance, and the pass plan.

use glam::DVec3;
use himmel_astro::units::{KM_PER_AU, SUN_RADIUS_KM};
use himmel_astro::{Body, Instant, Observer, Precision, Sky, UtcDateTime};
use serde::Serialize;

use crate::moon::MoonState;
use crate::projection::enu_from_alt_az;
use crate::scene::{Effect, Scene, SceneError};
use crate::spectrum::BandWeights;
use crate::units::{Degrees, Lux, Radians};

/// The Sun for one instant and observer.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SunState {
    /// Unit vector towards the Sun's refracted apparent place (ENU: x East, y North, z Zenith).
    pub enu: [f64; 3],
    /// Topocentric apparent altitude without refraction, degrees.
    pub alt_deg: Degrees,
    /// Altitude with standard refraction (1010 hPa, 10 °C), degrees.
    pub alt_refracted_deg: Degrees,
    /// Azimuth from North through East, degrees.
    pub az_deg: Degrees,
    /// Topocentric distance, km.
    pub distance_km: f64,
    /// True angular radius, radians.
    pub angular_radius: Radians,
    /// Extraterrestrial solar illuminance at this distance, lux.
    pub illuminance_lux: Lux,
    /// (1 AU / distance)².
    pub irradiance_scale: f64,
    /// Fraction of the solar disk not hidden by the Moon (1 outside solar
    /// eclipses; uniform-disk overlap of the topocentric disks,
    /// [`himmel_astro::events::solar_eclipse::disk_overlap_fraction`]).
    pub visible_fraction: f64,
}

impl SunState {
    /// The direction as a glam vector.
    pub fn dir(&self) -> DVec3 {
        DVec3::from_array(self.enu)
    }

    /// The irradiance scale of the sunlight that lights the sky and the
    /// ground: (1 AU / distance)² × (the visible fraction of the disk + the
    /// corona's [`crate::sun::CORONA_FRACTION`]); a solar eclipse dims the
    /// sky in proportion. (The light scattered into the umbra from the
    /// sunlit atmosphere outside it, which makes the real sky at totality
    /// ~10⁻⁴ of daylight, is not modelled: totality is darker here.)
    pub fn sky_irradiance_scale(&self) -> f64 {
        self.irradiance_scale * (self.visible_fraction + crate::sun::CORONA_FRACTION).min(1.0)
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
    pub reason: Option<String>,
}

/// Everything a renderer needs for one instant.
#[derive(Debug, Clone, PartialEq)]
pub struct SkyState {
    /// The civil UTC instant.
    pub utc: UtcDateTime,
    /// The Julian date (TT).
    pub jd_tt: f64,
    /// Observer altitude above the ground sphere used by the atmosphere, km.
    pub observer_altitude_km: f64,
    /// The Sun.
    pub sun: SunState,
    /// The Moon.
    pub moon: MoonState,
    /// ENU unit vector towards the celestial north pole.
    pub celestial_pole: [f64; 3],
    /// Star frame, planets and scintillation (`crate::night`).
    pub night: crate::night::NightSky,
    /// Every effect in back-to-front order, with its plan.
    pub passes: Vec<PlannedPass>,
}

/// Parses `now` or an RFC 3339 civil time (offsets converted, second 60 kept).
pub fn parse_utc(s: &str) -> Result<UtcDateTime, SceneError> {
    let err = |m: String| SceneError {
        field: "time.utc".into(),
        message: m,
    };
    if s.trim().eq_ignore_ascii_case("now") {
        UtcDateTime::try_from(chrono::Utc::now()).map_err(|e| err(format!("system clock: {e}")))
    } else {
        himmel_astro::time::parse_rfc3339(s).map_err(|e| {
            err(format!(
                "'{s}' is not an RFC 3339 time ({e}); expected e.g. 2024-04-08T18:42:00Z or now"
            ))
        })
    }
}

impl SkyState {
    /// The sky state of `scene` at its own time (`scene.time.utc`).
    pub fn at(scene: &Scene) -> Result<SkyState, SceneError> {
        let utc = parse_utc(&scene.time.utc)?;
        Self::at_utc(scene, utc)
    }

    /// The sky state of `scene` at civil UTC `utc`.
    pub fn at_utc(scene: &Scene, utc: UtcDateTime) -> Result<SkyState, SceneError> {
        scene.validate()?;
        let precision = Precision::from_name(&scene.precision).unwrap_or(Precision::Standard);
        let o = &scene.observer;
        let observer =
            Observer::new(o.lat_deg, o.lon_deg, o.elevation_m).map_err(|e| SceneError {
                field: "observer".into(),
                message: e.to_string(),
            })?;
        let instant = Instant::from_utc(&utc).map_err(|e| SceneError {
            field: "time.utc".into(),
            message: e.to_string(),
        })?;
        let sky = Sky::new(precision, &instant);
        let topo = sky
            .topocentric(Body::Sun, &observer)
            .map_err(|e| SceneError {
                field: "time.utc".into(),
                message: e.to_string(),
            })?;
        let alt_r = topo.alt_refracted_deg();
        let enu = enu_from_alt_az(alt_r.to_radians(), topo.az);
        let irradiance_scale = (KM_PER_AU / topo.distance_km).powi(2);
        let sun = SunState {
            enu: enu.to_array(),
            alt_deg: topo.alt_deg(),
            alt_refracted_deg: alt_r,
            az_deg: topo.az_deg(),
            distance_km: topo.distance_km,
            angular_radius: (SUN_RADIUS_KM / topo.distance_km).asin(),
            illuminance_lux: BandWeights::solar().solar_illuminance_lux() * irradiance_scale,
            irradiance_scale,
            visible_fraction: 1.0,
        };
        let (moon, visible_fraction) =
            crate::moon::moon_state(&sky, &observer, &sun).map_err(|e| SceneError {
                field: "time.utc".into(),
                message: e.to_string(),
            })?;
        let sun = SunState {
            visible_fraction,
            ..sun
        };
        let night =
            crate::night::NightSky::new(scene, &sky, &observer).map_err(|e| SceneError {
                field: "time.utc".into(),
                message: e.to_string(),
            })?;
        let mut passes = plan(scene, &sun);
        crate::moon::plan_moon(&mut passes, scene, &moon);
        night.refine_plan(&mut passes);
        let lat = o.lat_deg.to_radians();
        Ok(SkyState {
            utc,
            jd_tt: instant.jd_tt,
            observer_altitude_km: (o.elevation_m / 1000.0)
                .clamp(0.0, scene.atmosphere.thickness_km * 0.9),
            sun,
            moon,
            celestial_pole: [0.0, lat.cos(), lat.sin()],
            night,
            passes,
        })
    }

    /// Whether the pass of `e` runs.
    pub fn runs(&self, e: Effect) -> bool {
        self.passes.iter().any(|p| p.effect == e && p.run)
    }
}

/// The pass plan: every effect, back to front, with the reason it does not run.
pub fn plan(scene: &Scene, sun: &SunState) -> Vec<PlannedPass> {
    Effect::ALL
        .into_iter()
        .map(|e| {
            let reason = if !scene.wants(e) {
                Some("not requested".to_string())
            } else if !e.available() {
                Some(format!(
                    "not available yet: the {} pass arrives with a later version",
                    e.name()
                ))
            } else if e == Effect::Sun
                && sun.alt_refracted_deg + (sun.angular_radius * scene.sun_scale).to_degrees() < 0.0
            {
                Some("the Sun's disk is below the horizon".to_string())
            } else {
                None
            };
            PlannedPass {
                effect: e,
                run: reason.is_none(),
                reason,
            }
        })
        .collect()
}
