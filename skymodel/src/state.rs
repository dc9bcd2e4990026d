//! `SkyState`: everything a renderer needs for one instant — the Sun's
//! apparent (refracted) direction in the horizontal frame, its distance,
//! angular size and extraterrestrial illuminance, and the pass plan.

use himmel_astro::units::{KM_PER_AU, SUN_RADIUS_KM};
use himmel_astro::{Body, Instant, Observer, Precision, Sky, UtcDateTime};

use crate::moon::MoonState;
pub use crate::plan::PlannedPass;
use crate::projection::enu_from_alt_az;
use crate::scene::{Effect, Scene, SceneError};
use crate::spectrum::BandWeights;
pub use crate::sun::SunState;
use himmel_astro::error::printable;

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
                "'{}' is not an RFC 3339 time ({e}); expected e.g. 2024-04-08T18:42:00Z or now",
                printable(s)
            ))
        })
    }
}

/// The scene's instant: `time.utc`, or with `time.day_fraction` F the
/// instant of local apparent solar time F × 24 h on the local date of
/// `time.utc` ([`crate::solar_time::day_fraction_instant`]).
pub fn scene_utc(scene: &Scene) -> Result<UtcDateTime, SceneError> {
    let utc = parse_utc(&scene.time.utc)?;
    let Some(f) = scene.time.day_fraction else {
        return Ok(utc);
    };
    let o = &scene.observer;
    let observer = Observer::new(o.lat_deg, o.lon_deg, o.elevation_m).map_err(|e| SceneError {
        field: "observer".into(),
        message: e.to_string(),
    })?;
    let precision = Precision::from_name(&scene.precision).unwrap_or(Precision::Standard);
    crate::solar_time::day_fraction_instant(&utc, &observer, precision, f)
}

impl SkyState {
    /// The sky state of `scene` at its own time (`scene.time.utc`).
    /// With `time.day_fraction` the instant is that apparent solar time of
    /// the date ([`scene_utc`]).
    pub fn at(scene: &Scene) -> Result<SkyState, SceneError> {
        Self::at_utc(scene, scene_utc(scene)?)
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
        let passes = crate::plan::plan(scene, &sun, &moon, &night.planets);
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
