//! Lunar eclipses: per-instant shadow geometry and an interval search.
//!
//! Geometry (Explanatory Supplement to the Astronomical Almanac, 1992,
//! §8.3; Meeus ch. 54): seen from the Earth's centre, the shadow axis points
//! away from the apparent Sun (the Sun's apparent place includes annual
//! aberration, i.e. the direction its light arrives from in the geocentric
//! frame; the Moon's apparent place is its geometric one to 0.7″). With the
//! Moon's and the Sun's equatorial horizontal parallaxes π☾ = asin(a/r☾),
//! π☉ = asin(a/r☉) (a = 6378.137 km, WGS84 equatorial radius) and the Sun's
//! semidiameter s☉ = asin(695 700 km/r☉), the angular radii of the shadow
//! cones at the Moon's distance are
//!
//! * penumbra ρₚ = 1.01·π☾ + π☉ + s☉,
//! * umbra    ρᵤ = 1.01·π☾ + π☉ − s☉.
//!
//! **Shadow enlargement: Danjon's rule.** The factor 1.01 is
//! 0.998 340 × (1 + 1/85): the Earth's radius is taken as its mean at
//! latitude 45° (0.998 340 a, which accounts for the flattening) and enlarged
//! by 1/85 for the opaque lower atmosphere (A. Danjon 1951; the convention
//! of the Astronomical Almanac since 1951 and of NASA's Five Millennium
//! Canon). The enlargement applies to the Earth's term only, not to the Sun's
//! (Chauvenet's older rule instead multiplies all three terms by 1.02, which
//! makes the umbra about 0.01° larger). The factor used here is computed, not
//! rounded: 1.010 085.
//!
//! Magnitudes (fraction of the Moon's diameter inside the cone; s☾ the
//! Moon's geocentric semidiameter with radius 1737.4 km, δ the angular
//! distance of the Moon's centre from the axis): umbral (ρᵤ + s☾ − δ)/(2s☾),
//! penumbral (ρₚ + s☾ − δ)/(2s☾). Contacts: P1/P4 when δ = ρₚ + s☾,
//! U1/U4 at δ = ρᵤ + s☾, U2/U3 at δ = ρᵤ − s☾. Greatest eclipse: minimum of δ.
//! `gamma`: the Moon centre's distance from the axis at greatest eclipse in
//! equatorial Earth radii, positive when the Moon passes north of the axis
//! (spec/cli.md).
//!
//! Search: for each full Moon of Meeus' mean lunation (eq. 49.1) whose mean
//! argument of latitude has |sin F| ≤ 0.40 (Meeus ch. 54 rules out eclipses
//! above 0.36), δ is minimised over the mean full Moon ± 0.8 day (the true
//! full Moon lies within 0.6 day of the mean one and δ is unimodal there: the
//! Moon gains 12° a day on the shadow).

use glam::DVec3;

use crate::ephemeris::{Body, Ephemeris, Epoch};
use crate::error::AstroError;
use crate::time::Instant;
use crate::units::*;

use super::phases::{mean_argument_of_latitude, mean_phase_jde, LunationScan};
use super::{brent_min, brent_root, instant_tt};

/// Danjon's factor on the Moon's parallax: 0.998 340 × (1 + 1/85).
pub const DANJON_FACTOR: f64 = 0.998_340 * (1.0 + 1.0 / 85.0);

/// The Earth's shadow at the Moon's distance at one instant, seen from the
/// Earth's centre. Angles in radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowGeometry {
    /// Angular radius of the umbra at the Moon's distance, ρᵤ.
    pub umbra_radius: Radians,
    /// Angular radius of the penumbra at the Moon's distance, ρₚ.
    pub penumbra_radius: Radians,
    /// Umbra radius as a length at the Moon's distance, km.
    pub umbra_radius_km: Km,
    /// Penumbra radius as a length at the Moon's distance, km.
    pub penumbra_radius_km: Km,
    /// The Moon's geocentric semidiameter s☾.
    pub moon_semidiameter: Radians,
    /// The Moon's geocentric distance, km.
    pub moon_distance_km: Km,
    /// Angular distance δ of the Moon's centre from the shadow axis.
    pub moon_axis_distance: Radians,
    /// The Moon centre's signed distance from the axis in equatorial Earth
    /// radii (positive north of the axis); at greatest eclipse this is gamma.
    pub gamma: f64,
    /// The Moon's offset from the axis on the sky, toward celestial east
    /// and north (gnomonic, radians): the axis lies at −(east, north) from
    /// the Moon's centre.
    pub offset_east: Radians,
    /// See [`ShadowGeometry::offset_east`].
    pub offset_north: Radians,
}

impl ShadowGeometry {
    /// The shadow geometry from apparent geocentric vectors of the Sun and
    /// the Moon (km, any equatorial frame of date whose z axis is the
    /// celestial pole).
    pub fn from_vectors(sun: DVec3, moon: DVec3) -> ShadowGeometry {
        let ds = sun.length();
        let dm = moon.length();
        let axis = -sun / ds;
        let mhat = moon / dm;
        let pi_m = safe_asin(WGS84_A_KM / dm);
        let pi_s = safe_asin(WGS84_A_KM / ds);
        let s_s = safe_asin(SUN_RADIUS_KM / ds);
        let s_m = safe_asin(MOON_RADIUS_KM / dm);
        let pi_1 = DANJON_FACTOR * pi_m;
        let rho_p = pi_1 + pi_s + s_s;
        let rho_u = pi_1 + pi_s - s_s;
        let along = moon.dot(axis);
        let perp = moon - axis * along;
        let delta = libm::atan2(perp.length(), along);
        let gamma = perp.length() / WGS84_A_KM * if perp.z >= 0.0 { 1.0 } else { -1.0 };
        // Sky basis at the Moon: east = ẑ × m̂, north = m̂ × east.
        let z = DVec3::Z;
        let east = z.cross(mhat);
        let east = if east.length_squared() > 1e-24 {
            east.normalize()
        } else {
            DVec3::X
        };
        let north = mhat.cross(east);
        let ca = axis.dot(mhat).max(1e-9);
        let (offset_east, offset_north) = (-axis.dot(east) / ca, -axis.dot(north) / ca);
        ShadowGeometry {
            umbra_radius: rho_u,
            penumbra_radius: rho_p,
            umbra_radius_km: dm * libm::tan(rho_u),
            penumbra_radius_km: dm * libm::tan(rho_p),
            moon_semidiameter: s_m,
            moon_distance_km: dm,
            moon_axis_distance: delta,
            gamma,
            offset_east,
            offset_north,
        }
    }

    /// Umbral magnitude (ρᵤ + s☾ − δ)/(2s☾): ≥ 1 total, > 0 partial.
    pub fn umbral_magnitude(&self) -> f64 {
        (self.umbra_radius + self.moon_semidiameter - self.moon_axis_distance)
            / (2.0 * self.moon_semidiameter)
    }

    /// Penumbral magnitude (ρₚ + s☾ − δ)/(2s☾).
    pub fn penumbral_magnitude(&self) -> f64 {
        (self.penumbra_radius + self.moon_semidiameter - self.moon_axis_distance)
            / (2.0 * self.moon_semidiameter)
    }

    /// Angular distance from the shadow axis of a point of the lunar disk,
    /// radians. The point is `(x, y)` in units of the Moon's semidiameter,
    /// x toward celestial east, y toward north, (0, 0) the Moon's centre.
    pub fn point_axis_distance(&self, x: f64, y: f64) -> Radians {
        let e = self.offset_east + x * self.moon_semidiameter;
        let n = self.offset_north + y * self.moon_semidiameter;
        libm::hypot(e, n)
    }

    /// Depth in the shadow of a point of the lunar disk (coordinates as in
    /// [`ShadowGeometry::point_axis_distance`]): 0 outside the penumbra,
    /// rising linearly to 1 at the umbra's edge ((ρₚ − d)/(ρₚ − ρᵤ)), then
    /// 1 + (ρᵤ − d)/ρᵤ inside the umbra, 2 on the axis.
    pub fn shadow_depth(&self, x: f64, y: f64) -> f64 {
        let d = self.point_axis_distance(x, y);
        if d >= self.penumbra_radius {
            0.0
        } else if d >= self.umbra_radius {
            (self.penumbra_radius - d) / (self.penumbra_radius - self.umbra_radius)
        } else {
            1.0 + (self.umbra_radius - d) / self.umbra_radius.max(1e-12)
        }
    }
}

/// The shadow geometry at `instant` from the ephemeris `eph`.
pub fn shadow_geometry<E: Ephemeris>(
    eph: &E,
    instant: &Instant,
) -> Result<ShadowGeometry, AstroError> {
    let epoch = Epoch::new(instant, eph.nutation_model());
    let s = eph.apparent(Body::Sun, &epoch)?.vector_km();
    let m = eph.apparent(Body::Moon, &epoch)?.vector_km();
    Ok(ShadowGeometry::from_vectors(s, m))
}

fn geometry_tt<E: Ephemeris>(eph: &E, jd_tt: JulianDay) -> Result<ShadowGeometry, AstroError> {
    shadow_geometry(eph, &instant_tt(jd_tt))
}

/// Type of a lunar eclipse.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LunarEclipseKind {
    /// The Moon enters the penumbra only.
    Penumbral,
    /// Part of the Moon enters the umbra.
    Partial,
    /// The whole Moon enters the umbra.
    Total,
}

impl LunarEclipseKind {
    /// `"penumbral"`, `"partial"` or `"total"` (spec/cli.md).
    pub const fn name(self) -> &'static str {
        match self {
            LunarEclipseKind::Penumbral => "penumbral",
            LunarEclipseKind::Partial => "partial",
            LunarEclipseKind::Total => "total",
        }
    }
}

/// One lunar eclipse: type, greatest eclipse, magnitudes, gamma, contacts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LunarEclipse {
    /// Type.
    pub kind: LunarEclipseKind,
    /// Greatest eclipse (minimum distance of the Moon from the axis).
    pub greatest: Instant,
    /// Umbral magnitude at greatest eclipse (negative for a penumbral eclipse).
    pub umbral_magnitude: f64,
    /// Penumbral magnitude at greatest eclipse.
    pub penumbral_magnitude: f64,
    /// Gamma, equatorial Earth radii, positive north of the axis.
    pub gamma: f64,
    /// First contact with the penumbra.
    pub p1: Instant,
    /// First contact with the umbra (partial and total eclipses).
    pub u1: Option<Instant>,
    /// Totality begins.
    pub u2: Option<Instant>,
    /// Totality ends.
    pub u3: Option<Instant>,
    /// Last contact with the umbra.
    pub u4: Option<Instant>,
    /// Last contact with the penumbra.
    pub p4: Instant,
}

/// The lunar eclipse of the full Moon with lunation number `k` (an integer;
/// the full Moon is k + 0.5 in Meeus' numbering), if there is one.
pub fn lunar_eclipse_of_lunation<E: Ephemeris>(
    eph: &E,
    k: i64,
) -> Result<Option<LunarEclipse>, AstroError> {
    let kk = k as f64 + 0.5;
    if libm::sin(mean_argument_of_latitude(kk)).abs() > 0.40 {
        return Ok(None);
    }
    let jde = mean_phase_jde(kk);
    let (tg, _) = brent_min(
        |t| Ok(geometry_tt(eph, t)?.moon_axis_distance),
        jde - 0.8,
        jde + 0.8,
        1e-7,
    )?;
    let g = geometry_tt(eph, tg)?;
    let pen = g.penumbral_magnitude();
    if pen <= 0.0 {
        return Ok(None);
    }
    let umb = g.umbral_magnitude();
    let kind = if umb >= 1.0 {
        LunarEclipseKind::Total
    } else if umb > 0.0 {
        LunarEclipseKind::Partial
    } else {
        LunarEclipseKind::Penumbral
    };
    // Contacts: δ − limit crosses zero once on each side of greatest.
    let contact =
        |limit: fn(&ShadowGeometry) -> f64, before: bool| -> Result<Option<Instant>, AstroError> {
            let f = |t: f64| -> Result<f64, AstroError> {
                let g = geometry_tt(eph, t)?;
                Ok(g.moon_axis_distance - limit(&g))
            };
            let f0 = f(tg)?;
            if f0 >= 0.0 {
                return Ok(None);
            }
            let far = if before { tg - 0.4 } else { tg + 0.4 };
            let ff = f(far)?;
            if ff <= 0.0 {
                return Ok(None);
            }
            Ok(Some(instant_tt(brent_root(
                f,
                tg,
                far,
                f0,
                ff,
                1e-3 / SECONDS_PER_DAY,
            )?)))
        };
    let pen_lim: fn(&ShadowGeometry) -> f64 = |g| g.penumbra_radius + g.moon_semidiameter;
    let u_out: fn(&ShadowGeometry) -> f64 = |g| g.umbra_radius + g.moon_semidiameter;
    let u_in: fn(&ShadowGeometry) -> f64 = |g| g.umbra_radius - g.moon_semidiameter;
    let greatest = instant_tt(tg);
    let p1 = contact(pen_lim, true)?.unwrap_or(greatest);
    let p4 = contact(pen_lim, false)?.unwrap_or(greatest);
    Ok(Some(LunarEclipse {
        kind,
        greatest,
        umbral_magnitude: umb,
        penumbral_magnitude: pen,
        gamma: g.gamma,
        p1,
        u1: contact(u_out, true)?,
        u2: contact(u_in, true)?,
        u3: contact(u_in, false)?,
        u4: contact(u_out, false)?,
        p4,
    }))
}

/// Iterator over the lunar eclipses whose greatest eclipse lies in
/// `[from, to)`, chronological (made by [`lunar_eclipses`]; no allocation).
/// An eclipse in progress at `from` whose greatest phase came earlier is not
/// included; one whose greatest phase is before `to` is, with its later
/// contacts.
#[derive(Debug, Clone)]
pub struct LunarEclipses<E>(LunationScan<E, LunarEclipse>);

/// All lunar eclipses with greatest eclipse in `[from, to)`. Errors: the
/// interval is reversed or longer than [`super::MAX_SEARCH_DAYS`].
pub fn lunar_eclipses<E: Ephemeris>(
    eph: E,
    from: &Instant,
    to: &Instant,
) -> Result<LunarEclipses<E>, AstroError> {
    LunationScan::new(eph, from, to, 0.5, lunar_eclipse_of_lunation, |e| {
        e.greatest.jd_tt
    })
    .map(LunarEclipses)
}

impl<E: Ephemeris> Iterator for LunarEclipses<E> {
    type Item = Result<LunarEclipse, AstroError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.0.next()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shadow_radii_of_a_mean_configuration() {
        // Sun 1 AU along +x, Moon 384 400 km along −x, 0.5° north of the axis.
        let sun = DVec3::new(KM_PER_AU, 0.0, 0.0);
        let d = 0.5 * DEG;
        let moon = DVec3::new(-libm::cos(d), 0.0, libm::sin(d)) * 384_400.0;
        let g = ShadowGeometry::from_vectors(sun, moon);
        let pi_m = libm::asin(WGS84_A_KM / 384_400.0);
        let pi_s = libm::asin(WGS84_A_KM / KM_PER_AU);
        let s_s = libm::asin(SUN_RADIUS_KM / KM_PER_AU);
        assert!((g.umbra_radius - (DANJON_FACTOR * pi_m + pi_s - s_s)).abs() < 1e-15);
        assert!((g.penumbra_radius - (DANJON_FACTOR * pi_m + pi_s + s_s)).abs() < 1e-15);
        // Roughly 0.69° and 1.22° for these distances.
        assert!((g.umbra_radius / DEG - 0.694).abs() < 0.01);
        assert!((g.penumbra_radius / DEG - 1.227).abs() < 0.01);
        assert!((g.moon_axis_distance - d).abs() < 1e-12);
        // North of the axis: positive gamma, offset toward north.
        assert!((g.gamma - 384_400.0 * libm::sin(d) / WGS84_A_KM).abs() < 1e-9);
        assert!(g.offset_north > 0.0 && g.offset_east.abs() < 1e-12);
        // Depth: the southern limb (toward the axis) is deeper than the northern.
        assert!(g.shadow_depth(0.0, -1.0) > g.shadow_depth(0.0, 1.0));
        assert!(g.shadow_depth(0.0, -1.0) > 1.0);
        assert!((DANJON_FACTOR - 1.010_085).abs() < 1e-6);
    }
}
