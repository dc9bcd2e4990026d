use super::*;
use crate::projection::enu_from_alt_az;

/// An image of `mapping` whose texel (i, j) holds f at its centre's
/// direction.
fn image_of(mapping: Mapping, w: u32, h: u32, f: impl Fn(DVec3) -> [f32; 3]) -> LinearImage {
    let mut texels = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let d = mapping
                .pixel_to_dir(f64::from(i) + 0.5, f64::from(j) + 0.5, w, h)
                .unwrap();
            texels.push(f(d));
        }
    }
    LinearImage {
        width: w,
        height: h,
        texels,
    }
}

fn size(m: Mapping, n: u32) -> (u32, u32) {
    match m {
        Mapping::Polar => (n, n),
        Mapping::Sphere | Mapping::Paraboloid => (2 * n, n),
        Mapping::Cube | Mapping::CubeUniform => (6 * n, n),
    }
}

/// Directions on a fine grid plus the hard cases: zenith, nadir, the
/// horizon, both sides of the ±180° and 0°/360° azimuths, cube edges and
/// corners.
fn directions() -> Vec<DVec3> {
    let mut v = Vec::new();
    for alt in (-89..=89).step_by(7) {
        for az in (0..360).step_by(11) {
            v.push(enu_from_alt_az(
                f64::from(alt).to_radians(),
                f64::from(az).to_radians(),
            ));
        }
    }
    for (alt, az) in [
        (90.0, 0.0),
        (-90.0, 0.0),
        (89.999, 123.0),
        (-89.999, 321.0),
        (0.0, 0.0),
        (0.0, 180.0),
        (1e-6, 179.9999),
        (1e-6, 180.0001),
        (-1e-6, 359.9999),
        (12.0, 0.0001),
        (35.264_389_682_754_654, 45.0),
        (-35.264_389_682_754_654, 135.0),
        (45.0, 90.0),
        (0.0, 45.0),
    ] {
        v.push(enu_from_alt_az(f64::to_radians(alt), f64::to_radians(az)));
    }
    v
}

#[test]
fn round_trips_within_half_a_texel() {
    for m in Mapping::ALL {
        let (w, h) = size(m, 16);
        // Texel centre → direction → position: back at the centre.
        let mut worst = 0.0f64;
        for j in 0..h {
            for i in 0..w {
                if !m.texel_in_domain(i, j, w, h) {
                    continue;
                }
                let (cx, cy) = (f64::from(i) + 0.5, f64::from(j) + 0.5);
                let d = m.pixel_to_dir(cx, cy, w, h).unwrap();
                let (x, y) = m.dir_to_pixel(d, w, h);
                let mut dx = (x - cx).abs();
                if m == Mapping::Sphere {
                    dx = dx.min(f64::from(w) - dx);
                }
                worst = worst.max(dx.hypot(y - cy));
            }
        }
        assert!(worst < 1e-6, "{m}: texel centres come back {worst} px off");
        // Direction → texel → direction: within half the texel's extent.
        for d in directions() {
            if m == Mapping::Polar && d.z < 0.0 {
                continue; // the lower hemisphere mirrors the upper one
            }
            let (t, x, y) = m.locate(d, w, h);
            let x = x + f64::from(t * m.tiles(w, h).1);
            assert!(
                (0.0..=f64::from(w)).contains(&x) && (0.0..=f64::from(h)).contains(&y),
                "{m} {d}"
            );
            let tile = Some(t);
            let back = m.pixel_to_dir_in(tile, x, y, w, h).unwrap();
            assert!(
                back.angle_between(d) < 1e-7,
                "{m}: {d} → ({x}, {y}) → {back}"
            );
            // The texel that holds the position, within its tile.
            let tw = f64::from(m.tiles(w, h).1);
            let x0 = f64::from(t) * tw;
            let i = x.floor().clamp(x0, x0 + tw - 1.0);
            let j = y.floor().min(f64::from(h) - 1.0);
            let centre = m.pixel_to_dir_in(tile, i + 0.5, j + 0.5, w, h).unwrap();
            // The texel spans at most its farthest corner from the centre.
            let half_diagonal = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
                .iter()
                .map(|(a, b)| {
                    let c = m.pixel_to_dir_in(tile, i + a, j + b, w, h).unwrap();
                    centre.angle_between(c)
                })
                .fold(0.0, f64::max);
            assert!(
                centre.angle_between(d) <= half_diagonal + 1e-9,
                "{m}: {d} lands {}° from its texel's centre (half a texel: {}°)",
                centre.angle_between(d).to_degrees(),
                half_diagonal.to_degrees()
            );
        }
    }
}

#[test]
fn polar_lower_hemisphere_mirrors_the_upper() {
    let d = enu_from_alt_az(0.3, 1.1);
    let m = DVec3::new(d.x, d.y, -d.z);
    let (w, h) = (32, 32);
    assert_eq!(
        Mapping::Polar.dir_to_pixel(d, w, h),
        Mapping::Polar.dir_to_pixel(m, w, h)
    );
}

/// Largest over smallest texel solid angle in the mapping's domain, and
/// the domain's total solid angle.
fn ratio(m: Mapping, n: u32) -> (f64, f64) {
    let (w, h) = size(m, n);
    let (mut lo, mut hi, mut sum) = (f64::INFINITY, 0.0f64, 0.0);
    for j in 0..h {
        for i in 0..w {
            if m.texel_in_domain(i, j, w, h) {
                let o = m.texel_solid_angle(i, j, w, h);
                lo = lo.min(o);
                hi = hi.max(o);
                sum += o;
            }
        }
    }
    (hi / lo, sum)
}

#[test]
fn texel_solid_angle_ratios() {
    let four_pi = 4.0 * std::f64::consts::PI;
    let (cube, s) = ratio(Mapping::Cube, 32);
    assert!((s - four_pi).abs() < 1e-3 * four_pi, "cube covers {s} sr");
    let (uniform, s) = ratio(Mapping::CubeUniform, 32);
    assert!(
        (s - four_pi).abs() < 1e-3 * four_pi,
        "uniform cube covers {s} sr"
    );
    let (sphere, s) = ratio(Mapping::Sphere, 32);
    assert!((s - four_pi).abs() < 1e-3 * four_pi, "sphere covers {s} sr");
    let (polar, _) = ratio(Mapping::Polar, 64);
    let (paraboloid, _) = ratio(Mapping::Paraboloid, 64);
    println!(
        "texel solid angle max/min: cube {cube:.3}, cube-uniform {uniform:.3}, sphere {sphere:.1} (64 rows), polar {polar:.3}, paraboloid {paraboloid:.3}"
    );
    // The goal for the uniform-density lookup, and the plain
    // cube's 3√3 (face centre over corner) approached at 32 texels.
    assert!(uniform <= 1.5, "{uniform}");
    assert!((4.5..5.2).contains(&cube), "{cube}");
    assert!((3.5..4.01).contains(&paraboloid), "{paraboloid}");
    assert!((1.4..1.58).contains(&polar), "{polar}");
    assert!(sphere > 20.0, "{sphere}");
}

/// A smooth test radiance (even in the altitude: the polar mapping folds
/// the sphere at the horizon, and a function with a kink there is
/// filtered half a texel into the fold).
fn smooth(d: DVec3) -> [f32; 3] {
    [
        (2.0 + d.x) as f32,
        (2.0 + d.y) as f32,
        (2.0 + d.z * d.z + 0.5 * d.x * d.y) as f32,
    ]
}

#[test]
fn bilinear_lookups_have_no_seams() {
    for m in Mapping::ALL {
        let (w, h) = size(m, 48);
        let tex = SkyTexture::new(m, &image_of(m, w, h, smooth));
        let mut worst = (0.0f32, DVec3::ZERO);
        for d in directions() {
            let (got, want) = (tex.sample(d), smooth(d));
            for k in 0..3 {
                let e = (got[k] - want[k]).abs();
                if e > worst.0 {
                    worst = (e, d);
                }
            }
        }
        // Second-order interpolation error of a texel of ≤ 4°; a seam
        // filtered across the wrong neighbour is off by ~0.1–1.
        assert!(worst.0 < 4e-3, "{m}: off by {} at {}", worst.0, worst.1);
    }
}

#[test]
fn sizes_are_checked() {
    assert!(Mapping::Cube.check_size(600, 100).is_ok());
    let e = Mapping::Cube.check_size(500, 100).unwrap_err();
    assert!(e.contains("6N × N") && e.contains("500 × 100"), "{e}");
    assert!(Mapping::Polar.check_size(64, 32).is_err());
    assert!(Mapping::Paraboloid.check_size(64, 32).is_ok());
    assert!(Mapping::Sphere.check_size(1, 1).is_err());
}

/// An equirect sky: a smooth gradient with a bright spot of 0.5° at
/// (az 100°, alt 30°).
fn sky_with_sun(w: u32, h: u32) -> LinearImage {
    let sun = enu_from_alt_az(30f64.to_radians(), 100f64.to_radians());
    image_of(Mapping::Sphere, w, h, |d| {
        let base = 100.0 + 50.0 * d.z.max(0.0) as f32 + 20.0 * d.x as f32;
        let a = d.angle_between(sun).to_degrees();
        let spot = if a < 1.0 { 1e5 } else { 0.0 };
        [base + spot, base + spot, base * 1.2 + spot]
    })
}

#[test]
fn conversion_keeps_the_mean_radiance() {
    let src = sky_with_sun(256, 128);
    let (want, omega) = mean_radiance(Mapping::Sphere, &src);
    assert!((omega - 4.0 * std::f64::consts::PI).abs() < 1e-3);
    let tex = SkyTexture::new(Mapping::Sphere, &src);
    for to in [Mapping::Cube, Mapping::CubeUniform, Mapping::Paraboloid] {
        let out = convert(&tex, to, 32);
        let (got, _) = mean_radiance(to, &out);
        for k in 0..3 {
            let rel = (got[k] / want[k] - 1.0).abs();
            println!(
                "{to}: channel {k} mean {:.4} vs {:.4} ({:.3} %)",
                got[k],
                want[k],
                100.0 * rel
            );
            let bound = if to == Mapping::Paraboloid {
                0.02
            } else {
                0.005
            };
            assert!(rel < bound, "{to}: channel {k}: {} vs {}", got[k], want[k]);
        }
    }
}

#[test]
fn the_brightest_region_is_found_and_masked() {
    let src = sky_with_sun(360, 180);
    let tex = SkyTexture::new(Mapping::Sphere, &src);
    let masked = tex.with_masked_sun(&src, None, 3f64.to_radians());
    let sun = enu_from_alt_az(30f64.to_radians(), 100f64.to_radians());
    let found = masked.masked_sun.unwrap().dir;
    assert!(
        found.angle_between(sun).to_degrees() < 0.3,
        "{}",
        found.angle_between(sun).to_degrees()
    );
    // The spot is gone: every lookup within the mask is within the
    // gradient's range around it.
    for k in 0..200 {
        let a = f64::from(k) * 0.7;
        let r = (f64::from(k) / 200.0 * 2.9).to_radians();
        let e1 = sun.any_orthonormal_vector();
        let d = sun * r.cos() + (e1 * a.cos() + sun.cross(e1) * a.sin()) * r.sin();
        let y = crate::spectrum::luminance(masked.sample(d));
        assert!((100.0..200.0).contains(&y), "{y} at {r} rad");
    }
    // Outside the mask the texture is unchanged.
    let far = enu_from_alt_az(0.2, 3.0);
    assert_eq!(masked.sample(far), tex.sample(far));
}
