//! A texture prepared for drawing ([`SkyTexture`]): the image's tiles
//! with their one-texel borders (the seams, module docs of
//! [`crate::texture_sky`]), and optionally its own sun masked out
//! ([`SkyTexture::with_masked_sun`]).

use glam::DVec3;

use super::{LinearImage, Mapping};
use crate::spectrum::luminance;

/// An image prepared for bilinear lookups in both backends: every tile
/// (the image; each paraboloid half; each cube face) with a one-texel
/// border, tiles one after another, rows top to bottom (the GPU reads the
/// same texels as three floats each).
#[derive(Debug, Clone, PartialEq)]
pub struct SkyTexture {
    /// The mapping.
    pub mapping: Mapping,
    /// The source image's width, px.
    pub width: u32,
    /// The source image's height, px.
    pub height: u32,
    /// Tiles.
    pub tiles: u32,
    /// A tile's width with its border (tile width + 2).
    pub tile_w: u32,
    /// A tile's height with its border.
    pub tile_h: u32,
    /// `tiles × tile_h × tile_w` texels.
    pub texels: Vec<[f32; 3]>,
    /// The texture's own sun, when it was masked.
    pub masked_sun: Option<MaskedSun>,
}

/// The texture's own sun that was masked out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaskedSun {
    /// Its direction in the texture's frame (ENU unit vector).
    pub dir: DVec3,
    /// The masked radius, radians.
    pub radius: f64,
}

impl SkyTexture {
    /// Prepares `image` (its size already checked for `mapping`): refills
    /// the polar corners and the paraboloid's outsides, then borders each
    /// tile.
    pub fn new(mapping: Mapping, image: &LinearImage) -> SkyTexture {
        let filled = refill(mapping, image);
        let (w, h) = (image.width, image.height);
        let (tiles, tw, th) = mapping.tiles(w, h);
        let (pw, ph) = (tw + 2, th + 2);
        let mut texels = Vec::with_capacity((tiles * pw * ph) as usize);
        for t in 0..tiles {
            for j in 0..ph {
                for i in 0..pw {
                    let (x, y) = (i64::from(i) - 1, i64::from(j) - 1);
                    texels.push(border_texel(mapping, &filled, t, x, y));
                }
            }
        }
        SkyTexture {
            mapping,
            width: w,
            height: h,
            tiles,
            tile_w: pw,
            tile_h: ph,
            texels,
            masked_sun: None,
        }
    }

    /// The tile and the continuous position in the bordered tile's texel
    /// grid (texel (i, j) centred at (i, j)) of unit direction `d`.
    pub fn locate(&self, d: DVec3) -> (u32, f64, f64) {
        let (t, x, y) = self.mapping.locate(d, self.width, self.height);
        (t.min(self.tiles - 1), x + 0.5, y + 0.5)
    }

    /// The bilinearly filtered texture towards unit direction `d` (in the
    /// texture's frame).
    pub fn sample(&self, d: DVec3) -> [f32; 3] {
        let (t, x, y) = self.locate(d);
        let (pw, ph) = (self.tile_w as usize, self.tile_h as usize);
        let x = x.clamp(0.0, (pw - 1) as f64);
        let y = y.clamp(0.0, (ph - 1) as f64);
        let x0 = (x.floor() as usize).min(pw - 2);
        let y0 = (y.floor() as usize).min(ph - 2);
        let (tx, ty) = ((x - x0 as f64) as f32, (y - y0 as f64) as f32);
        let base = t as usize * pw * ph;
        let at = |i: usize, j: usize| {
            self.texels
                .get(base + j * pw + i)
                .copied()
                .unwrap_or_default()
        };
        let (a, b) = (at(x0, y0), at(x0 + 1, y0));
        let (c, e) = (at(x0, y0 + 1), at(x0 + 1, y0 + 1));
        std::array::from_fn(|k| {
            let top = a[k] + (b[k] - a[k]) * tx;
            let bot = c[k] + (e[k] - c[k]) * tx;
            top + (bot - top) * ty
        })
    }

    /// This texture with its own sun masked out: the texels within
    /// `radius` (radians) of the sun's direction filled from their
    /// surroundings, then prepared again. The sun is at `dir` (texture
    /// frame) when given, otherwise found as the brightest region: the
    /// brightest texel, refined to the luminance-weighted centroid of the
    /// texels within `radius` of it that are at least half as bright.
    ///
    /// The fill of a texel at angle ρ < R from the sun centre, at bearing
    /// β around it, is (1 − ρ/R) · the mean of 32 lookups on the circle of
    /// radius 1.5 R plus ρ/R · the lookup at angle 2R − ρ on the same
    /// bearing (the texture mirrored in the mask's edge): continuous at the
    /// edge and at the centre, and free of the sun (every lookup lies
    /// outside the mask).
    pub fn with_masked_sun(
        &self,
        image: &LinearImage,
        dir: Option<DVec3>,
        radius: f64,
    ) -> SkyTexture {
        let (w, h) = (image.width, image.height);
        let m = self.mapping;
        let centre = dir
            .map(|d| d.normalize_or(DVec3::Z))
            .unwrap_or_else(|| brightest(m, image, radius));
        let cos_r = radius.cos();
        // A frame at the sun: bearings β measured in (e1, e2).
        let e1 = centre.any_orthonormal_vector();
        let e2 = centre.cross(e1);
        let at = |rho: f64, beta: f64| {
            let t = e1 * beta.cos() + e2 * beta.sin();
            self.sample(centre * rho.cos() + t * rho.sin())
        };
        let ring: [f32; 3] = {
            let n = 32;
            let mut s = [0.0f32; 3];
            for k in 0..n {
                let c = at(1.5 * radius, std::f64::consts::TAU * k as f64 / n as f64);
                for (a, b) in s.iter_mut().zip(c) {
                    *a += b / n as f32;
                }
            }
            s
        };
        let mut out = image.clone();
        for j in 0..h {
            for i in 0..w {
                let Some(d) = m.pixel_to_dir(f64::from(i) + 0.5, f64::from(j) + 0.5, w, h) else {
                    continue;
                };
                let c = d.dot(centre);
                if c < cos_r {
                    continue;
                }
                let rho = c.clamp(-1.0, 1.0).acos();
                let q = d - centre * c;
                let beta = q.dot(e2).atan2(q.dot(e1));
                let f = (rho / radius) as f32;
                let mirror = at(2.0 * radius - rho, beta);
                if let Some(p) = out.texels.get_mut((j * w + i) as usize) {
                    *p = std::array::from_fn(|k| (1.0 - f) * ring[k] + f * mirror[k]);
                }
            }
        }
        let mut t = SkyTexture::new(m, &out);
        t.masked_sun = Some(MaskedSun {
            dir: centre,
            radius,
        });
        t
    }
}

/// The direction of the brightest region of `image` ([`SkyTexture::with_masked_sun`]).
fn brightest(m: Mapping, image: &LinearImage, radius: f64) -> DVec3 {
    let (w, h) = (image.width, image.height);
    let dir = |k: usize| {
        let (i, j) = ((k % w as usize) as f64, (k / w as usize) as f64);
        m.pixel_to_dir(i + 0.5, j + 0.5, w, h).unwrap_or(DVec3::Z)
    };
    let (mut kmax, mut ymax) = (0, f32::NEG_INFINITY);
    for (k, t) in image.texels.iter().enumerate() {
        let y = luminance(*t);
        if y > ymax && m.texel_in_domain((k % w as usize) as u32, (k / w as usize) as u32, w, h) {
            (kmax, ymax) = (k, y);
        }
    }
    let peak = dir(kmax);
    let cos_r = radius.cos();
    let mut sum = DVec3::ZERO;
    for (k, t) in image.texels.iter().enumerate() {
        let y = luminance(*t);
        if y >= 0.5 * ymax {
            let d = dir(k);
            if d.dot(peak) >= cos_r {
                sum += d * f64::from(y);
            }
        }
    }
    sum.try_normalize().unwrap_or(peak)
}

/// The image with the texels outside a polar image's circle (the lower
/// hemisphere mirrored: the texel of the mirrored direction) and outside
/// each paraboloid disk (the other half's texel of the same direction)
/// refilled; other mappings unchanged.
fn refill(m: Mapping, image: &LinearImage) -> LinearImage {
    if !matches!(m, Mapping::Polar | Mapping::Paraboloid) {
        return image.clone();
    }
    let (w, h) = (image.width, image.height);
    let n = f64::from(h);
    let mut out = image.clone();
    for j in 0..h {
        for i in 0..w {
            let (px, py) = (f64::from(i) + 0.5, f64::from(j) + 0.5);
            let half = (px / n).floor();
            let cx = if m == Mapping::Polar {
                n / 2.0
            } else {
                half * n + n / 2.0
            };
            if (px - cx).hypot(py - n / 2.0) <= n / 2.0 {
                continue;
            }
            let Some(d) = m.pixel_to_dir(px, py, w, h) else {
                continue;
            };
            let (t, qx, qy) = m.locate(d, w, h);
            let tile_w = m.tiles(w, h).1;
            let x0 = t * tile_w;
            if let Some(p) = out.texels.get_mut((j * w + i) as usize) {
                *p = image.bilinear_in(x0, tile_w, f64::from(x0) + qx, qy);
            }
        }
    }
    out
}

/// The texel at (x, y) of tile `t`, x and y from −1 to the tile size (the
/// border): inside, the image's; on the border, the neighbour's.
fn border_texel(m: Mapping, img: &LinearImage, t: u32, x: i64, y: i64) -> [f32; 3] {
    let (w, h) = (i64::from(img.width), i64::from(img.height));
    match m {
        Mapping::Sphere => {
            let (mut x, mut y) = (x, y);
            if y < 0 || y >= h {
                // Across the pole: the same row, half-way round.
                y = y.clamp(0, h - 1);
                x += w / 2;
            }
            img.at(x.rem_euclid(w), y)
        }
        Mapping::Polar => img.at(x, y),
        Mapping::Paraboloid => img.at(i64::from(t) * h + x.clamp(0, h - 1), y),
        Mapping::Cube | Mapping::CubeUniform => {
            if (0..h).contains(&x) && (0..h).contains(&y) {
                return img.at(i64::from(t) * h + x, y);
            }
            // The border continues the face's plane into its neighbour.
            let (px, py) = (i64::from(t) * h + x, y);
            let d = m.pixel_to_dir_in(
                Some(t),
                px as f64 + 0.5,
                py as f64 + 0.5,
                img.width,
                img.height,
            );
            let Some(d) = d else { return [0.0; 3] };
            let (face, x, y) = m.locate(d, img.width, img.height);
            let x0 = face.min(5) * img.height;
            img.bilinear_in(x0, img.height, f64::from(x0) + x, y)
        }
    }
}
