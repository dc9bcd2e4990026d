//! Spherical ↔ Cartesian, and the rotations between the ecliptic, equatorial
//! and horizontal frames.

use glam::{DMat3, DVec3};

use super::nutation::Nutation;
use super::rotation::{rot_x, rot_z};
use crate::units::{wrap_tau, Radians};

/// Cartesian vector of length `r` at longitude `lon` (from +x towards +y) and
/// latitude `lat` (towards +z); the unit of the result is that of `r`.
pub fn spherical_to_vector(lon: Radians, lat: Radians, r: f64) -> DVec3 {
    let (sl, cl) = (libm::sin(lon), libm::cos(lon));
    let (sb, cb) = (libm::sin(lat), libm::cos(lat));
    DVec3::new(r * cb * cl, r * cb * sl, r * sb)
}

/// Longitude in [0, 2π), latitude in [−π/2, π/2] and length of `v`. Both
/// angles come from `atan2`, so they are accurate everywhere (poles
/// included); the zero vector gives (0, 0, 0).
pub fn vector_to_spherical(v: DVec3) -> (Radians, Radians, f64) {
    let rho = libm::hypot(v.x, v.y);
    let lon = if rho == 0.0 {
        0.0
    } else {
        wrap_tau(libm::atan2(v.y, v.x))
    };
    let lat = if rho == 0.0 && v.z == 0.0 {
        0.0
    } else {
        libm::atan2(v.z, rho)
    };
    (lon, lat, libm::sqrt(rho * rho + v.z * v.z))
}

/// Unit vector of right ascension `ra` and declination `dec` (radians), in
/// whichever equatorial frame they are referred to.
#[inline]
pub fn equatorial_to_vector(ra: Radians, dec: Radians) -> DVec3 {
    spherical_to_vector(ra, dec, 1.0)
}

/// Right ascension in [0, 2π) and declination (radians) of a vector in an
/// equatorial frame (its length is ignored; the zero vector gives (0, 0)).
#[inline]
pub fn vector_to_equatorial(v: DVec3) -> (Radians, Radians) {
    let (ra, dec, _) = vector_to_spherical(v);
    (ra, dec)
}

/// Nutation matrix N: multiplies a vector referred to the mean equator and
/// equinox of date to give it referred to the true equator and equinox of
/// date. `mean_obliquity` is ε₀ of date, `n` the nutation.
///
/// N = R₁(−(ε₀ + Δε))·R₃(−Δψ)·R₁(ε₀) (Explanatory Supplement 1992, eq.
/// 3.222-3; SOFA `iauNumat`).
pub fn nutation_matrix(mean_obliquity: Radians, n: &Nutation) -> DMat3 {
    rot_x(-(mean_obliquity + n.deps)) * rot_z(-n.dpsi) * rot_x(mean_obliquity)
}

/// Rotation taking an ecliptic-frame vector to the equatorial frame of the
/// same equinox: a rotation by +ε about the common x axis (the equinox).
/// Use the mean obliquity for mean places, the true one for apparent places.
/// Source: Meeus, *Astronomical Algorithms* 2nd ed., eq. 13.3–13.4 in matrix form.
pub fn ecliptic_to_equatorial_matrix(obliquity: Radians) -> DMat3 {
    rot_x(-obliquity)
}

/// Ecliptic longitude and latitude → (right ascension in [0, 2π),
/// declination), radians, for the equinox whose obliquity is given.
/// Source: Meeus, *Astronomical Algorithms* 2nd ed., eq. 13.3 and 13.4,
/// evaluated on vectors (no tan β, so exact at the ecliptic poles).
pub fn ecliptic_to_equatorial(
    lon: Radians,
    lat: Radians,
    obliquity: Radians,
) -> (Radians, Radians) {
    vector_to_equatorial(
        ecliptic_to_equatorial_matrix(obliquity) * spherical_to_vector(lon, lat, 1.0),
    )
}

/// Right ascension and declination → (ecliptic longitude in [0, 2π),
/// latitude), radians. Source: Meeus, *Astronomical Algorithms* 2nd ed.,
/// eq. 13.1 and 13.2, evaluated on vectors.
pub fn equatorial_to_ecliptic(ra: Radians, dec: Radians, obliquity: Radians) -> (Radians, Radians) {
    let v = rot_x(obliquity) * spherical_to_vector(ra, dec, 1.0);
    let (lon, lat, _) = vector_to_spherical(v);
    (lon, lat)
}

/// Local hour angle and declination → (azimuth, altitude), radians, for an
/// observer at geodetic latitude `lat`. Azimuth from North (0) through East
/// (π/2), in [0, 2π); altitude in [−π/2, π/2], geometric (no refraction).
///
/// Source: Meeus, *Astronomical Algorithms* 2nd ed., eq. 13.5–13.6, on
/// vectors in the (North, East, Up) frame so that poles, zenith and nadir
/// are finite (azimuth 0 where it is undefined).
pub fn equatorial_to_horizontal(
    hour_angle: Radians,
    dec: Radians,
    lat: Radians,
) -> (Radians, Radians) {
    let (sh, ch) = (libm::sin(hour_angle), libm::cos(hour_angle));
    let (sd, cd) = (libm::sin(dec), libm::cos(dec));
    let (sp, cp) = (libm::sin(lat), libm::cos(lat));
    let north = cp * sd - sp * cd * ch;
    let east = -cd * sh;
    let up = sp * sd + cp * cd * ch;
    let horizontal = libm::hypot(north, east);
    let az = if horizontal == 0.0 {
        0.0
    } else {
        wrap_tau(libm::atan2(east, north))
    };
    (az, libm::atan2(up, horizontal))
}

/// Parallactic angle q of an object at local hour angle `hour_angle` and
/// declination `dec` for an observer at latitude `lat`: the position angle of
/// the zenith measured at the object from celestial North through East,
/// radians in [0, 2π).
///
/// Source: Meeus, *Astronomical Algorithms* 2nd ed., eq. 14.1, in the form
/// tan q = sin H cos φ / (sin φ cos δ − cos φ sin δ cos H) evaluated with
/// `atan2`, which stays finite at the poles and the zenith (where q is
/// undefined and 0 is returned).
pub fn parallactic_angle(hour_angle: Radians, dec: Radians, lat: Radians) -> Radians {
    let (sh, ch) = (libm::sin(hour_angle), libm::cos(hour_angle));
    let (sd, cd) = (libm::sin(dec), libm::cos(dec));
    let (sp, cp) = (libm::sin(lat), libm::cos(lat));
    let y = sh * cp;
    let x = sp * cd - cp * sd * ch;
    if y == 0.0 && x == 0.0 {
        0.0
    } else {
        wrap_tau(libm::atan2(y, x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::{DEG, TAU};

    #[test]
    fn meeus_example_13a_pollux() {
        // α = 116.328942°, δ = 28.026183°, ε = 23.4392911° →
        // λ = 113.215630°, β = 6.684170°.
        let eps = 23.439_291_1 * DEG;
        let (lon, lat) = equatorial_to_ecliptic(116.328_942 * DEG, 28.026_183 * DEG, eps);
        assert!((lon / DEG - 113.215_630).abs() < 1e-6, "{}", lon / DEG);
        assert!((lat / DEG - 6.684_170).abs() < 1e-6, "{}", lat / DEG);
        let (ra, dec) = ecliptic_to_equatorial(lon, lat, eps);
        assert!((ra / DEG - 116.328_942).abs() < 1e-9);
        assert!((dec / DEG - 28.026_183).abs() < 1e-9);
    }

    #[test]
    fn meeus_example_13b_venus_from_washington() {
        // H = 64.352133°, δ = −6.719892°, φ = 38°55′17″ →
        // A = 68.0337° from the South, i.e. 248.0337° from North; h = 15.1249°.
        let lat = (38.0 + 55.0 / 60.0 + 17.0 / 3600.0) * DEG;
        let (az, alt) = equatorial_to_horizontal(64.352_133 * DEG, -6.719_892 * DEG, lat);
        assert!((az / DEG - 248.0337).abs() < 1e-4, "{}", az / DEG);
        assert!((alt / DEG - 15.1249).abs() < 1e-4, "{}", alt / DEG);
    }

    #[test]
    fn horizontal_edge_cases() {
        // Zenith, nadir, poles: finite, az in range.
        let cases = [
            (0.0, 30.0, 30.0),
            (TAU / 2.0, -30.0, 30.0),
            (1.0, 90.0, 45.0),
            (1.0, 12.0, 90.0),
            (1.0, 12.0, -90.0),
            (2.0, -90.0, -90.0),
            (0.0, 0.0, 0.0),
        ];
        for (h, d, p) in cases {
            let (az, alt) = equatorial_to_horizontal(h, d * DEG, p * DEG);
            assert!(az.is_finite() && alt.is_finite());
            assert!((0.0..TAU).contains(&az));
            assert!(alt.abs() <= TAU / 4.0);
        }
        let (_, alt) = equatorial_to_horizontal(0.0, 30.0 * DEG, 30.0 * DEG);
        assert!((alt - TAU / 4.0).abs() < 1e-15);
        // At the North pole the altitude is the declination.
        let (_, alt) = equatorial_to_horizontal(1.234, 12.0 * DEG, 90.0 * DEG);
        assert!((alt / DEG - 12.0).abs() < 1e-12);
        // Rising due East on the equator: H = −90°, δ = 0 → az 90°, alt 0.
        let (az, alt) = equatorial_to_horizontal(-TAU / 4.0, 0.0, 0.0);
        assert!((az / DEG - 90.0).abs() < 1e-12 && alt.abs() < 1e-15);
    }

    #[test]
    fn spherical_round_trip_and_poles() {
        for &(lon, lat) in &[
            (0.0, 0.0),
            (1.0, 0.5),
            (6.0, -1.2),
            (3.0, TAU / 4.0),
            (2.0, -TAU / 4.0),
        ] {
            let v = spherical_to_vector(lon, lat, 2.5);
            let (l2, b2, r2) = vector_to_spherical(v);
            assert!((r2 - 2.5).abs() < 1e-15);
            assert!((b2 - lat).abs() < 1e-15);
            if lat.abs() < 1.5 {
                assert!((l2 - lon).abs() < 1e-15);
            }
        }
        assert_eq!(vector_to_spherical(DVec3::ZERO), (0.0, 0.0, 0.0));
        let (lon, _, _) = vector_to_spherical(DVec3::new(1.0, -1e-300, 0.0));
        assert!((0.0..TAU).contains(&lon));
        // Ecliptic pole ↔ equatorial: finite.
        let (ra, dec) = ecliptic_to_equatorial(0.0, TAU / 4.0, 23.44 * DEG);
        assert!((ra / DEG - 270.0).abs() < 1e-9 && (dec / DEG - 66.56).abs() < 1e-9);
    }

    #[test]
    fn nutation_matrix_matches_sofa() {
        // eraNumat(eraObl80, eraNut80) at MJD 61000 (tools/gen_frames_refs.py).
        let n = Nutation {
            dpsi: 1.4945532361458725e-05,
            deps: 4.093028161062949e-05,
        };
        let m = nutation_matrix(0.4090340479197496, &n);
        let expected = [
            [
                0.9999999998883156,
                -1.3712607131243692e-05,
                -5.944185664575383e-06,
            ],
            [
                1.371236382256428e-05,
                0.99999999906834,
                -4.093032235363836e-05,
            ],
            [
                5.944746920467613e-06,
                4.0930240840231225e-05,
                0.9999999991446877,
            ],
        ];
        for (i, row) in expected.iter().enumerate() {
            for (j, e) in row.iter().enumerate() {
                assert!((m.row(i)[j] - e).abs() < 1e-16, "N[{i}][{j}]");
            }
        }
    }

    /// Position angle of the zenith at the object, from explicit vectors.
    fn zenith_position_angle(h: f64, dec: f64, lat: f64) -> f64 {
        // Frame: x towards (H = 0, δ = 0), y towards H = −90° (east), z = pole.
        let s = DVec3::new(
            libm::cos(dec) * libm::cos(h),
            -libm::cos(dec) * libm::sin(h),
            libm::sin(dec),
        );
        let pole = DVec3::Z;
        let zenith = DVec3::new(libm::cos(lat), 0.0, libm::sin(lat));
        let north = (pole - s * pole.dot(s)).normalize();
        let east = pole.cross(s).normalize();
        let zt = zenith - s * zenith.dot(s);
        wrap_tau(libm::atan2(zt.dot(east), zt.dot(north)))
    }

    #[test]
    fn parallactic_angle_matches_vector_geometry() {
        let mut worst: f64 = 0.0;
        for i in 0..40 {
            for j in 0..15 {
                for k in 0..9 {
                    let h = -3.1 + i as f64 * 0.155;
                    let dec = (-80.0 + j as f64 * 11.0) * DEG;
                    let lat = (-85.0 + k as f64 * 21.0) * DEG;
                    let q = parallactic_angle(h, dec, lat);
                    assert!((0.0..TAU).contains(&q));
                    let r = zenith_position_angle(h, dec, lat);
                    let d = crate::units::wrap_pi(q - r).abs();
                    worst = worst.max(d);
                }
            }
        }
        assert!(worst < 1e-12, "{worst}");
        // On the meridian south of the zenith the zenith is due North: q = 0;
        // west of the meridian (H > 0, northern observer) q is positive.
        assert!(parallactic_angle(0.0, 10.0 * DEG, 50.0 * DEG).abs() < 1e-15);
        assert!(parallactic_angle(0.5, 10.0 * DEG, 50.0 * DEG) < 1.0);
        // Pole observer, zenith object: finite.
        for (h, d, p) in [
            (1.0, 40.0, 90.0),
            (0.0, 50.0, 50.0),
            (2.0, 90.0, 10.0),
            (0.3, -90.0, -90.0),
        ] {
            assert!(parallactic_angle(h, d * DEG, p * DEG).is_finite());
        }
    }
}
