//! Texture-mapped skies: an image of the sky (a photograph, a painting,
//! Himmel's own render) drawn as the background instead of, or blended
//! over, the physical atmosphere (`crate::frame::texture` makes the
//! frame's part; the backends draw it).
//!
//! Directions are ENU unit vectors of the horizontal frame
//! (conventions.md: x East, y North, z Zenith; azimuth from North through
//! East). Image pixel (x, y) has its centre at (x + 0.5, y + 0.5), x to the
//! right, y downwards. The mappings ([`Mapping`]):
//!
//! | mapping | image | layout |
//! |---|---|---|
//! | `polar` | N × N | zenith at the centre, the horizon on the inscribed circle, North up, East left (as seen looking up: Himmel's `fisheye`); the zenith angle grows linearly with the radius. The lower hemisphere is the upper one mirrored in the horizon (a polar image holds the sky only); the corners beyond the circle are refilled with that mirror when the texture is prepared, so filtering has no seam at the horizon |
//! | `sphere` | W × H (2:1 usual) | equirectangular, full sphere: azimuth 360° · x/W (North at the left edge, East at a quarter), altitude 90° − 180° · y/H (Himmel's `equirect`) |
//! | `paraboloid` | 2N × N | dual paraboloid, one image side by side: the left half the upper hemisphere seen from below (zenith at its centre, North up, East left), the right half the lower hemisphere seen from above (nadir at its centre, North up, East right); a direction d maps to (a, b) = (∓dₓ, d_y)/(1 ± d_z) on the unit disk of its half. The texels outside each disk are refilled from the other half when the texture is prepared |
//! | `cube` | 6N × N | six faces +X −X +Y −Y +Z −Z of the scene frame (x East, y Up, z South) in a horizontal strip, OpenGL face orientation (Himmel's `cubemap`) |
//! | `cube-uniform` | 6N × N | the same faces with the uniform-texel-density lookup: face coordinate s ∈ [−1, 1] holds the gnomonic coordinate tan(π s / 4), so that every texel spans nearly the same solid angle |
//!
//! Texel solid angles, largest over smallest (the test
//! `texel_solid_angle_ratios`; the limits for fine images in brackets):
//! `cube` 4.86 at 32 texels per face (3√3 = 5.20: face centre / corner),
//! `cube-uniform` 1.38 at 32 (√2 = 1.41: face centre / edge middle),
//! `paraboloid` 3.83 at 64 (4: disk centre / rim), `polar` 1.54 at 64
//! (π/2 = 1.57: zenith / horizon, upper hemisphere), `sphere` 20.4 at 32
//! rows (growing as the rows: equator / pole).
//!
//! Filtering is bilinear on a [`SkyTexture`]: each tile (the image, each
//! paraboloid half, each cube face) carries a one-texel border taken from
//! its neighbours (across ±180° and across the poles for `sphere`, from
//! the adjacent faces for the cubes, clamped for `polar` and `paraboloid`
//! after their refill), so bilinear filtering never crosses a seam. Both
//! backends sample the same bordered texels
//! ([`SkyTexture::sample`]; `backend-wgpu/src/shaders/texture.wgsl`).

pub mod convert;
pub mod prepare;
pub mod store;

use glam::DVec3;

use crate::projection::{cube_face_coords, cube_face_dir, Camera, Projection};

pub use convert::{convert, horizontal_illuminance, mean_radiance};
pub use prepare::{MaskedSun, SkyTexture};
pub use store::{TextureLoader, TextureStore};

/// How an image covers the sphere of directions (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mapping {
    /// Zenith at the centre, the horizon at the rim.
    Polar,
    /// Equirectangular, the full sphere.
    Sphere,
    /// Dual paraboloid, both halves side by side.
    Paraboloid,
    /// Six faces in a strip, OpenGL orientation.
    Cube,
    /// Six faces with the tangent-warped (uniform texel density) lookup.
    CubeUniform,
}

impl Mapping {
    /// Every mapping.
    pub const ALL: [Mapping; 5] = [
        Mapping::Polar,
        Mapping::Sphere,
        Mapping::Paraboloid,
        Mapping::Cube,
        Mapping::CubeUniform,
    ];

    /// The name used in scenes and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Mapping::Polar => "polar",
            Mapping::Sphere => "sphere",
            Mapping::Paraboloid => "paraboloid",
            Mapping::Cube => "cube",
            Mapping::CubeUniform => "cube-uniform",
        }
    }

    /// Parses a mapping's name.
    pub fn from_name(s: &str) -> Option<Mapping> {
        Mapping::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s.trim()))
    }

    /// The shader's number of the mapping (`texture.wgsl`).
    pub fn id(self) -> u32 {
        self as u32
    }

    /// Checks an image size for this mapping; the error says what was
    /// expected.
    pub fn check_size(self, width: u32, height: u32) -> Result<(), String> {
        let (ok, want) = match self {
            Mapping::Polar => (width == height, "a square image (N × N)"),
            Mapping::Sphere => (true, "at least 2 × 2 pixels"),
            Mapping::Paraboloid => (
                width == 2 * height,
                "two N × N halves side by side (2N × N)",
            ),
            Mapping::Cube | Mapping::CubeUniform => {
                (width == 6 * height, "a strip of six N × N faces (6N × N)")
            }
        };
        if ok && width >= 2 && height >= 2 {
            Ok(())
        } else {
            Err(format!(
                "a {} texture is {want}, found {width} × {height}",
                self.name()
            ))
        }
    }

    /// The number of tiles and one tile's size (without its border) of a
    /// `width` × `height` image.
    pub fn tiles(self, width: u32, height: u32) -> (u32, u32, u32) {
        match self {
            Mapping::Polar | Mapping::Sphere => (1, width, height),
            Mapping::Paraboloid => (2, height, height),
            Mapping::Cube | Mapping::CubeUniform => (6, height, height),
        }
    }

    /// The tile that shows unit direction `d` and the continuous position
    /// in it (x from 0 to the tile's width: a position on a tile's right
    /// edge stays in that tile).
    pub fn locate(self, d: DVec3, width: u32, height: u32) -> (u32, f64, f64) {
        let (w, h) = (f64::from(width), f64::from(height));
        match self {
            Mapping::Polar => {
                let m = DVec3::new(d.x, d.y, d.z.abs());
                let (x, y) = camera(Projection::Fisheye, width, height)
                    .dir_to_pixel(m)
                    .unwrap_or((w / 2.0, h / 2.0));
                (0, x, y)
            }
            Mapping::Sphere => {
                let (x, y) = camera(Projection::Equirect, width, height)
                    .dir_to_pixel(d)
                    .unwrap_or((0.0, 0.0));
                (0, x, y)
            }
            Mapping::Paraboloid => {
                let (a, b, half) = if d.z >= 0.0 {
                    (-d.x / (1.0 + d.z), d.y / (1.0 + d.z), 0)
                } else {
                    (d.x / (1.0 - d.z), d.y / (1.0 - d.z), 1)
                };
                (half, (1.0 + a) / 2.0 * h, (1.0 - b) / 2.0 * h)
            }
            Mapping::Cube | Mapping::CubeUniform => {
                let (face, mut sc, mut tc) = cube_face_coords(d);
                if self == Mapping::CubeUniform {
                    sc = unwarp(sc);
                    tc = unwarp(tc);
                }
                (face as u32, (sc + 1.0) / 2.0 * h, (tc + 1.0) / 2.0 * h)
            }
        }
    }

    /// The continuous image position (whole image) of unit direction `d`.
    pub fn dir_to_pixel(self, d: DVec3, width: u32, height: u32) -> (f64, f64) {
        let (t, x, y) = self.locate(d, width, height);
        let tw = f64::from(self.tiles(width, height).1);
        (f64::from(t) * tw + x, y)
    }

    /// The direction at continuous image position (px, py), in tile
    /// `tile` when given (positions beyond the tile's edge continue its
    /// mapping: the paraboloid beyond its disk, the cube face beyond its
    /// edge); `None` where the mapping has no direction.
    pub fn pixel_to_dir_in(
        self,
        tile: Option<u32>,
        px: f64,
        py: f64,
        width: u32,
        height: u32,
    ) -> Option<DVec3> {
        let h = f64::from(height);
        let tile_of = |px: f64| {
            let n = self.tiles(width, height).0;
            tile.unwrap_or(((px / h).floor().max(0.0) as u32).min(n - 1))
        };
        match self {
            Mapping::Polar => camera(Projection::Fisheye, width, height).pixel_to_dir(px, py),
            Mapping::Sphere => camera(Projection::Equirect, width, height).pixel_to_dir(px, py),
            Mapping::Paraboloid => {
                let t = tile_of(px);
                let a = 2.0 * (px - f64::from(t) * h) / h - 1.0;
                let b = 1.0 - 2.0 * py / h;
                let q = 1.0 + a * a + b * b;
                let z = (2.0 - q) / q;
                Some(if t == 0 {
                    DVec3::new(-2.0 * a / q, 2.0 * b / q, z)
                } else {
                    DVec3::new(2.0 * a / q, 2.0 * b / q, -z)
                })
            }
            Mapping::Cube | Mapping::CubeUniform => {
                let t = tile_of(px);
                let mut sc = 2.0 * (px - f64::from(t) * h) / h - 1.0;
                let mut tc = 2.0 * py / h - 1.0;
                if self == Mapping::CubeUniform {
                    sc = warp(sc);
                    tc = warp(tc);
                }
                Some(cube_face_dir(t as usize, sc, tc))
            }
        }
    }

    /// The direction at continuous image position (px, py) ([`Self::pixel_to_dir_in`]
    /// in the tile that holds the position).
    pub fn pixel_to_dir(self, px: f64, py: f64, width: u32, height: u32) -> Option<DVec3> {
        self.pixel_to_dir_in(None, px, py, width, height)
    }

    /// Whether texel (i, j) lies inside the mapping's domain (its whole
    /// area maps one to one: not in a polar image's corners, not outside a
    /// paraboloid's disks).
    pub fn texel_in_domain(self, i: u32, j: u32, _width: u32, height: u32) -> bool {
        let h = f64::from(height);
        let corners_in = |cx: f64, cy: f64, r: f64| {
            [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
                .iter()
                .all(|(a, b)| {
                    let (x, y) = (f64::from(i) + a - cx, f64::from(j) + b - cy);
                    x * x + y * y <= r * r
                })
        };
        match self {
            Mapping::Polar => corners_in(h / 2.0, h / 2.0, h / 2.0),
            Mapping::Paraboloid => {
                let cx = if f64::from(i) < h { h / 2.0 } else { 1.5 * h };
                corners_in(cx, h / 2.0, h / 2.0)
            }
            _ => true,
        }
    }

    /// The solid angle (sr) of texel (i, j): the area element |∂d/∂x ×
    /// ∂d/∂y| integrated over 4 × 4 points of the texel (central
    /// differences).
    pub fn texel_solid_angle(self, i: u32, j: u32, width: u32, height: u32) -> f64 {
        let n = 4;
        let e = 1e-4;
        let tile = Some(i / self.tiles(width, height).1);
        let dir = |x: f64, y: f64| {
            self.pixel_to_dir_in(tile, x, y, width, height)
                .unwrap_or(DVec3::Z)
        };
        let mut sum = 0.0;
        for a in 0..n {
            for b in 0..n {
                let x = f64::from(i) + (a as f64 + 0.5) / n as f64;
                let y = f64::from(j) + (b as f64 + 0.5) / n as f64;
                let dx = (dir(x + e, y) - dir(x - e, y)) / (2.0 * e);
                let dy = (dir(x, y + e) - dir(x, y - e)) / (2.0 * e);
                sum += dx.cross(dy).length();
            }
        }
        sum / (n * n) as f64
    }
}

impl std::fmt::Display for Mapping {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The uniform-density cube's face coordinate s → gnomonic coordinate.
pub fn warp(s: f64) -> f64 {
    (std::f64::consts::FRAC_PI_4 * s).tan()
}

/// The gnomonic coordinate → the uniform-density cube's face coordinate.
pub fn unwarp(u: f64) -> f64 {
    u.atan() / std::f64::consts::FRAC_PI_4
}

fn camera(projection: Projection, width: u32, height: u32) -> Camera {
    Camera {
        projection,
        width,
        height,
        ..Camera::default()
    }
}

/// A linear RGB image (linear sRGB primaries, row-major, top row first).
#[derive(Debug, Clone, PartialEq)]
pub struct LinearImage {
    /// Width, px.
    pub width: u32,
    /// Height, px.
    pub height: u32,
    /// Row-major texels.
    pub texels: Vec<[f32; 3]>,
}

impl LinearImage {
    /// The texel at (i, j), clamped to the image.
    pub fn at(&self, i: i64, j: i64) -> [f32; 3] {
        let i = i.clamp(0, i64::from(self.width) - 1) as usize;
        let j = j.clamp(0, i64::from(self.height) - 1) as usize;
        self.texels
            .get(j * self.width as usize + i)
            .copied()
            .unwrap_or([0.0; 3])
    }

    /// Bilinear value at continuous position (px, py) within the tile of
    /// `tile_w` columns that starts at column `x0` (clamped to the tile).
    pub fn bilinear_in(&self, x0: u32, tile_w: u32, px: f64, py: f64) -> [f32; 3] {
        let (lo, hi) = (f64::from(x0), f64::from(x0 + tile_w) - 1.0);
        let x = (px - 0.5).clamp(lo, hi);
        let y = (py - 0.5).clamp(0.0, f64::from(self.height) - 1.0);
        let (xf, yf) = (x.floor(), y.floor());
        let (tx, ty) = ((x - xf) as f32, (y - yf) as f32);
        let (xi, yi) = (xf as i64, yf as i64);
        let x1 = (xi + 1).min(hi as i64);
        let (a, b) = (self.at(xi, yi), self.at(x1, yi));
        let (c, d) = (self.at(xi, yi + 1), self.at(x1, yi + 1));
        std::array::from_fn(|k| {
            let top = a[k] + (b[k] - a[k]) * tx;
            let bot = c[k] + (d[k] - c[k]) * tx;
            top + (bot - top) * ty
        })
    }
}

/// Why a texture cannot be used.
#[derive(Debug, Clone, PartialEq)]
pub enum TextureError {
    /// The file cannot be read or decoded (file, reason).
    File {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// The image has the wrong size for its mapping (file, reason).
    Size {
        /// The file.
        path: String,
        /// What was expected and found.
        reason: String,
    },
    /// No image loader was given to the renderer's store.
    NoLoader(String),
}

impl std::fmt::Display for TextureError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TextureError::File { path, reason } | TextureError::Size { path, reason } => {
                write!(f, "sky texture {path}: {reason}")
            }
            TextureError::NoLoader(path) => write!(
                f,
                "sky texture {path}: this renderer was given no image loader (TextureStore::set_loader)"
            ),
        }
    }
}

impl std::error::Error for TextureError {}

#[cfg(test)]
mod tests;
