//! The lunar albedo and normal maps (embedded from `skymodel/data/`) and
//! the fast `atan2` that turns surface points into their texture
//! coordinates.

use std::sync::OnceLock;

/// The lunar albedo map: relative albedo on a 1024 × 512 equirectangular
/// grid (selenographic longitude −180° at the left edge, 0° at the centre,
/// east to the right; north at the top), from Stellarium's public-domain
/// texture (USGS Astrogeology and Clementine via Celestia; see README).
#[derive(Debug, Clone)]
pub struct AlbedoMap {
    /// Width in texels.
    pub w: usize,
    /// Height in texels.
    pub h: usize,
    /// Relative albedo, row-major, normalised to a mean of 1 over the mean
    /// near side weighted by projected area.
    pub data: Vec<f32>,
}

static MAP_BYTES: &[u8] = include_bytes!("../../data/moon_albedo_1024x512.u8");

impl AlbedoMap {
    /// The embedded map, normalised once.
    pub fn get() -> &'static AlbedoMap {
        static MAP: OnceLock<AlbedoMap> = OnceLock::new();
        MAP.get_or_init(|| {
            let (w, h) = (1024usize, 512usize);
            // The 8-bit values are taken as proportional to albedo (the source
            // mosaics are calibrated reflectance; see the README).
            let mut data: Vec<f32> = MAP_BYTES.iter().map(|&b| b as f32 / 255.0).collect();
            // Mean over the near side (|lon| < 90°) weighted by the
            // projected area cos(lat) cos(lon) · cos(lat) dlat dlon.
            let (mut s, mut ws) = (0.0f64, 0.0f64);
            for j in 0..h {
                let lat = std::f64::consts::FRAC_PI_2
                    - std::f64::consts::PI * (j as f64 + 0.5) / h as f64;
                for i in 0..w {
                    let lon =
                        -std::f64::consts::PI + std::f64::consts::TAU * (i as f64 + 0.5) / w as f64;
                    if lon.abs() >= std::f64::consts::FRAC_PI_2 {
                        continue;
                    }
                    let wt = lat.cos() * lat.cos() * lon.cos();
                    s += data[j * w + i] as f64 * wt;
                    ws += wt;
                }
            }
            let k = (ws / s) as f32;
            for v in data.iter_mut() {
                *v *= k;
            }
            AlbedoMap { w, h, data }
        })
    }

    /// Relative albedo at selenographic longitude `lon` and latitude `lat`
    /// (radians), bilinear, wrapping in longitude.
    #[inline]
    pub fn sample(&self, lon: f32, lat: f32) -> f32 {
        let u = (lon / std::f32::consts::TAU + 0.5) * self.w as f32 - 0.5;
        let v = (0.5 - lat / std::f32::consts::PI) * self.h as f32 - 0.5;
        let v = v.clamp(0.0, (self.h - 1) as f32);
        let (i0, j0) = (u.floor(), v.floor());
        let (fu, fv) = (u - i0, v - j0);
        let w = self.w as i32;
        let i0 = (i0 as i32).rem_euclid(w) as usize;
        let i1 = (i0 + 1) % self.w;
        let j0 = j0 as usize;
        let j1 = (j0 + 1).min(self.h - 1);
        let d = &self.data;
        let a = d[j0 * self.w + i0] * (1.0 - fu) + d[j0 * self.w + i1] * fu;
        let b = d[j1 * self.w + i0] * (1.0 - fu) + d[j1 * self.w + i1] * fu;
        a * (1.0 - fv) + b * fv
    }
}

/// The lunar normal map: the surface normal's east and north components
/// (tangent frame of the mean sphere) on a 512 × 256 equirectangular grid
/// laid out like [`AlbedoMap`], from Stellarium's public-domain
/// `moon_normals.png` (converted by `tools/moon_normals.py`). Used to shade
/// the relief near the terminator.
#[derive(Debug, Clone)]
pub struct NormalMap {
    /// Width in texels.
    pub w: usize,
    /// Height in texels.
    pub h: usize,
    /// (east, north) components, row-major.
    pub data: Vec<[f32; 2]>,
}

static NORMAL_BYTES: &[u8] = include_bytes!("../../data/moon_normals_512x256.u8");

impl NormalMap {
    /// The embedded map, decoded once.
    pub fn get() -> &'static NormalMap {
        static MAP: OnceLock<NormalMap> = OnceLock::new();
        MAP.get_or_init(|| NormalMap {
            w: 512,
            h: 256,
            data: NORMAL_BYTES
                .chunks_exact(2)
                .map(|c| [c[0] as f32 / 127.5 - 1.0, c[1] as f32 / 127.5 - 1.0])
                .collect(),
        })
    }

    /// (east, north) normal components at selenographic `lon`, `lat`
    /// (radians), bilinear.
    #[inline]
    pub fn sample(&self, lon: f32, lat: f32) -> [f32; 2] {
        let u = (lon / std::f32::consts::TAU + 0.5) * self.w as f32 - 0.5;
        let v = ((0.5 - lat / std::f32::consts::PI) * self.h as f32 - 0.5)
            .clamp(0.0, (self.h - 1) as f32);
        let (i0, j0) = (u.floor(), v.floor());
        let (fu, fv) = (u - i0, v - j0);
        let i0 = (i0 as i32).rem_euclid(self.w as i32) as usize;
        let i1 = (i0 + 1) % self.w;
        let j0 = j0 as usize;
        let j1 = (j0 + 1).min(self.h - 1);
        let d = &self.data;
        let mut out = [0.0f32; 2];
        for k in 0..2 {
            let a = d[j0 * self.w + i0][k] * (1.0 - fu) + d[j0 * self.w + i1][k] * fu;
            let b = d[j1 * self.w + i0][k] * (1.0 - fu) + d[j1 * self.w + i1][k] * fu;
            out[k] = a * (1.0 - fv) + b * fv;
        }
        out
    }
}

/// atan2(y, x) in f32 with a degree-11 odd minimax polynomial for atan on
/// [−1, 1] (max error 2 × 10⁻⁶ rad; coefficients of the classic
/// Hastings-type fit, cf. Abramowitz & Stegun 4.4.49); for texture lookups.
#[inline]
pub fn fast_atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let (num, den, swap) = if ay > ax {
        (ax, ay, true)
    } else {
        (ay, ax, false)
    };
    if den == 0.0 {
        return 0.0;
    }
    let t = num / den;
    let t2 = t * t;
    let mut a = t
        * (0.999_977_26
            + t2 * (-0.332_623_47
                + t2 * (0.193_543_46
                    + t2 * (-0.116_432_87 + t2 * (0.052_653_32 + t2 * -0.011_721_2)))));
    if swap {
        a = std::f32::consts::FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = std::f32::consts::PI - a;
    }
    if y < 0.0 {
        -a
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn albedo_map_orientation() {
        // Mare Crisium (59° E, 17° N) is dark, the highlands south of it
        // and Tycho's ray system (11° W, 43° S) are bright; Oceanus
        // Procellarum (57° W, 10° N) is dark; the far side highlands bright.
        let m = AlbedoMap::get();
        let at = |lon: f32, lat: f32| m.sample(lon.to_radians(), lat.to_radians());
        let crisium = at(59.0, 17.0);
        let tycho = at(-11.4, -43.3);
        let procellarum = at(-57.0, 10.0);
        let far = at(180.0, 0.0);
        assert!(crisium < 0.75 * tycho, "{crisium} {tycho}");
        assert!(procellarum < 0.75 * far, "{procellarum} {far}");
        // The mirrored places are not dark (a flipped map fails): Mare
        // Humorum (39° W, 24° S) against the highlands at 39° E, and
        // Crisium against 17° S.
        let humorum = at(-39.0, -24.0);
        assert!(at(39.0, -24.0) > humorum * 1.5, "{humorum}");
        assert!(at(59.0, -17.0) > crisium * 1.5);
    }

    #[test]
    fn fast_atan2_matches_std() {
        let mut worst = 0.0f32;
        for i in 0..400 {
            for j in 0..400 {
                let (x, y) = (-2.0 + i as f32 * 0.01, -2.0 + j as f32 * 0.01);
                if x == 0.0 && y == 0.0 {
                    continue;
                }
                worst = worst.max((fast_atan2(y, x) - y.atan2(x)).abs());
            }
        }
        assert!(worst < 1e-5, "{worst}");
        assert_eq!(fast_atan2(0.0, 0.0), 0.0);
    }
}
