//! From apparent geocentric places to what an observer on the ground sees.
//!
//! ```
//! use himmel_astro::{Body, Instant, Observer, Precision, Sky, UtcDateTime};
//! let t = Instant::from_utc(&UtcDateTime::new(2024, 4, 8, 18, 42, 0.0).unwrap()).unwrap();
//! let dallas = Observer::new(32.7767, -96.797, 140.0).unwrap();
//! let sky = Sky::new(Precision::Standard, &t);
//! let sun = sky.topocentric(Body::Sun, &dallas).unwrap();
//! let moon = sky.topocentric(Body::Moon, &dallas).unwrap();
//! // Total solar eclipse: the Moon covers the Sun.
//! assert!(sun.separation_deg(&moon) < 0.1);
//! assert!(sun.alt_deg() > 60.0);
//! ```

use glam::DVec3;

use crate::ephemeris::{Apparent, Body, Ephemeris, Epoch, Precision, Tiered};
use crate::error::AstroError;
use crate::frames;
use crate::moon::{self, MoonPhysical, MoonSunApparent};
use crate::time::Instant;
use crate::units::*;

/// The Earth's rotation rate relative to the stars, rad/s (IERS).
const EARTH_ROTATION_RAD_S: f64 = 7.292_115_146_706_979e-5;

/// A place on the Earth: geodetic latitude and east longitude on the WGS84
/// ellipsoid, elevation above the ellipsoid.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Observer {
    lat: Radians,
    lon: Radians,
    elevation_m: f64,
    rho_sin_phi: Km,
    rho_cos_phi: Km,
}

impl Observer {
    /// An observer at geodetic latitude `lat_deg` ∈ [−90, 90], east longitude
    /// `lon_deg` ∈ [−360, 360] (wrapped to [−180, 180)) and `elevation_m` ∈
    /// [−12 000, 100 000] m above the WGS84 ellipsoid.
    pub fn new(lat_deg: Degrees, lon_deg: Degrees, elevation_m: f64) -> Result<Self, AstroError> {
        let lat = AstroError::check_range("latitude", lat_deg, -90.0, 90.0)? * DEG;
        let lon = AstroError::check_range("longitude", lon_deg, -360.0, 360.0)?;
        let lon = wrap_360(lon + 180.0) - 180.0;
        let elevation_m = AstroError::check_range("elevation", elevation_m, -12_000.0, 100_000.0)?;
        let (rho_sin_phi, rho_cos_phi) = frames::geocentric_observer(lat, elevation_m);
        Ok(Observer {
            lat,
            lon: lon * DEG,
            elevation_m,
            rho_sin_phi,
            rho_cos_phi,
        })
    }

    /// Geodetic latitude, degrees.
    pub fn lat_deg(&self) -> Degrees {
        self.lat / DEG
    }
    /// East longitude, degrees in [−180, 180).
    pub fn lon_deg(&self) -> Degrees {
        self.lon / DEG
    }
    /// Elevation above the ellipsoid, m.
    pub fn elevation_m(&self) -> f64 {
        self.elevation_m
    }
    /// Geodetic latitude, radians.
    pub fn lat(&self) -> Radians {
        self.lat
    }
    /// East longitude, radians.
    pub fn lon(&self) -> Radians {
        self.lon
    }

    /// Local apparent sidereal time at `epoch`, radians in [0, 2π).
    pub fn local_sidereal_time(&self, epoch: &Epoch) -> Radians {
        wrap_tau(epoch.gast() + self.lon)
    }

    /// Geocentric position of the observer, km, true equator and equinox of
    /// date (polar motion neglected: < 15 m).
    pub fn position_km(&self, epoch: &Epoch) -> DVec3 {
        let theta = self.local_sidereal_time(epoch);
        DVec3::new(
            self.rho_cos_phi * libm::cos(theta),
            self.rho_cos_phi * libm::sin(theta),
            self.rho_sin_phi,
        )
    }

    /// Velocity of the observer due to the Earth's rotation, km/s, true
    /// equator and equinox of date.
    pub fn velocity_km_s(&self, epoch: &Epoch) -> DVec3 {
        let p = self.position_km(epoch);
        DVec3::new(-p.y, p.x, 0.0) * EARTH_ROTATION_RAD_S
    }

    /// Topocentric place of a body whose apparent geocentric place is `geo`:
    /// parallax (the observer's offset from the Earth's centre) and diurnal
    /// aberration (the observer's rotation velocity times the light time),
    /// then the horizontal coordinates (Meeus ch. 13, 40).
    pub fn topocentric(&self, geo: &Apparent, epoch: &Epoch) -> Topocentric {
        let g = geo.vector_km();
        let light_time_s = geo.distance_km / SPEED_OF_LIGHT_KM_S;
        let v = g - self.position_km(epoch) + self.velocity_km_s(epoch) * light_time_s;
        let (ra, dec, distance_km) = frames::vector_to_spherical(v);
        let hour_angle = wrap_tau(self.local_sidereal_time(epoch) - ra);
        let (az, alt) = frames::equatorial_to_horizontal(hour_angle, dec, self.lat);
        Topocentric {
            ra,
            dec,
            hour_angle,
            alt,
            az,
            distance_km,
            lat: self.lat,
        }
    }
}

/// Where a body stands for an observer: topocentric apparent equatorial and
/// horizontal coordinates. Altitudes are geometric (unrefracted) unless the
/// name says "refracted".
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Topocentric {
    /// Topocentric right ascension (true equator and equinox of date), radians.
    pub ra: Radians,
    /// Topocentric declination, radians.
    pub dec: Radians,
    /// Local hour angle, radians in [0, 2π).
    pub hour_angle: Radians,
    /// Altitude above the horizon (no refraction), radians in [−π/2, π/2].
    pub alt: Radians,
    /// Azimuth from North through East, radians in [0, 2π).
    pub az: Radians,
    /// Distance from the observer, km.
    pub distance_km: Km,
    lat: Radians,
}

impl Topocentric {
    /// Altitude, degrees (unrefracted).
    pub fn alt_deg(&self) -> Degrees {
        self.alt / DEG
    }
    /// Azimuth, degrees in [0, 360).
    pub fn az_deg(&self) -> Degrees {
        wrap_360(self.az / DEG)
    }
    /// Altitude including standard refraction (1010 hPa, 10 °C; Saemundsson,
    /// Meeus eq. 16.4), degrees.
    pub fn alt_refracted_deg(&self) -> Degrees {
        self.alt_refracted(
            frames::STANDARD_PRESSURE_HPA,
            frames::STANDARD_TEMPERATURE_C,
        ) / DEG
    }
    /// Altitude including refraction for the given pressure (hPa) and temperature (°C), radians.
    pub fn alt_refracted(&self, pressure_hpa: f64, temperature_c: f64) -> Radians {
        self.alt + frames::refraction_true_to_apparent(self.alt, pressure_hpa, temperature_c)
    }
    /// Parallactic angle (Meeus eq. 14.1), degrees in [0, 360).
    pub fn parallactic_angle_deg(&self) -> Degrees {
        wrap_360(frames::parallactic_angle(self.hour_angle, self.dec, self.lat) / DEG)
    }
    /// Angular separation from another topocentric place, degrees.
    pub fn separation_deg(&self, other: &Topocentric) -> Degrees {
        let a = frames::spherical_to_vector(self.ra, self.dec, 1.0);
        let b = frames::spherical_to_vector(other.ra, other.dec, 1.0);
        libm::atan2(a.cross(b).length(), a.dot(b)) / DEG
    }
    /// Unit vector towards the body in the horizontal frame (x = East,
    /// y = North, z = Zenith), unrefracted.
    pub fn enu(&self) -> DVec3 {
        let (sa, ca) = (libm::sin(self.alt), libm::cos(self.alt));
        DVec3::new(ca * libm::sin(self.az), ca * libm::cos(self.az), sa)
    }
    /// Topocentric angular semidiameter of a sphere of `radius_km`, degrees.
    pub fn semidiameter_deg(&self, radius_km: Km) -> Degrees {
        safe_asin(radius_km / self.distance_km.max(radius_km)) / DEG
    }
}

/// One instant seen through one ephemeris: the skyfield-like entry point.
///
/// `Sky::new(precision, &instant)` prepares nutation and sidereal time once;
/// `apparent`, `topocentric` and `moon_physical` then reduce bodies.
#[derive(Debug, Clone)]
pub struct Sky<E = Tiered> {
    ephemeris: E,
    epoch: Epoch,
}

impl Sky<Tiered> {
    /// The computed ephemeris at `precision`, at `instant`.
    pub fn new(precision: Precision, instant: &Instant) -> Self {
        Sky::with_ephemeris(Tiered(precision), instant)
    }
}

impl<E: Ephemeris> Sky<E> {
    /// Any provider (e.g. [`crate::Cached`] or [`crate::Manual`]) at `instant`.
    pub fn with_ephemeris(ephemeris: E, instant: &Instant) -> Self {
        let epoch = Epoch::new(instant, ephemeris.nutation_model());
        Sky { ephemeris, epoch }
    }

    /// The shared reduction quantities of this instant.
    pub fn epoch(&self) -> &Epoch {
        &self.epoch
    }

    /// Apparent geocentric place of `body`.
    pub fn apparent(&self, body: Body) -> Result<Apparent, AstroError> {
        self.ephemeris.apparent(body, &self.epoch)
    }

    /// Topocentric place of `body` for `observer`.
    pub fn topocentric(&self, body: Body, observer: &Observer) -> Result<Topocentric, AstroError> {
        Ok(observer.topocentric(&self.apparent(body)?, &self.epoch))
    }

    /// The Moon's physical ephemeris (phase, bright limb, libration, axis),
    /// geocentric, Meeus ch. 48 and 53.
    pub fn moon_physical(&self) -> Result<MoonPhysical, AstroError> {
        let m = self.apparent(Body::Moon)?;
        let s = self.apparent(Body::Sun)?;
        Ok(moon::physical(&MoonSunApparent {
            moon_lon: m.ecl_lon,
            moon_lat: m.ecl_lat,
            moon_ra: m.ra,
            moon_dec: m.dec,
            moon_distance_km: m.distance_km,
            sun_lon: s.ecl_lon,
            sun_lat: s.ecl_lat,
            sun_ra: s.ra,
            sun_dec: s.dec,
            sun_distance_km: s.distance_km,
            dpsi: self.epoch.nutation.dpsi,
            true_obliquity: self.epoch.true_obliquity,
            t: self.epoch.t,
        }))
    }
}

impl<E: Ephemeris> Sky<E> {
    /// Apparent visual magnitude of a planet (Meeus ch. 41), from the
    /// apparent places of the planet and the Sun: heliocentric distance r,
    /// geocentric distance Δ, phase angle, and for Saturn the ring tilt
    /// (Meeus ch. 45). `BodyUnavailable` for the Sun and the Moon.
    pub fn planet_magnitude(&self, body: Body) -> Result<f64, AstroError> {
        let planet = body
            .planet()
            .ok_or(AstroError::BodyUnavailable { body: body.name() })?;
        let p = self.apparent(body)?;
        let s = self.apparent(Body::Sun)?;
        let pv = p.vector_km();
        let to_sun = s.vector_km() - pv;
        let to_earth = -pv;
        let phase = libm::atan2(to_sun.cross(to_earth).length(), to_sun.dot(to_earth));
        let tilt = crate::planets::saturn_ring_tilt(p.ecl_lon, p.ecl_lat, self.epoch.t);
        Ok(crate::planets::magnitude(
            planet,
            to_sun.length() / KM_PER_AU,
            p.distance_km / KM_PER_AU,
            phase,
            tilt,
        ))
    }
}
