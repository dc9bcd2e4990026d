//! The per-pixel passes of a frame, run together over bands of rows.
//!
//! A frame's passes run back to front in the plan's order. The passes that
//! work pixel by pixel from the pixel's view direction (Milky Way, Moon,
//! Sun, corona, atmosphere, texture) need the directions of the whole
//! image; the point-source splats (stars, planets) do not. Each run of
//! consecutive per-pixel passes is executed band by band: a band of
//! [`BAND_ROWS`] rows computes its directions into a small per-thread
//! buffer ([`PixelDirections::row`], in cache) and applies every pass of
//! the run to it, in order. Each pixel sees the same operations in the
//! same order as when the run's passes go one after the other over a
//! direction buffer, so a run's result is the same bit for bit; what goes
//! is the 33 MB per-frame direction buffer (at 1920 × 1080) and the
//! passes' trips through it.
//!
//! Pass times: each band times its direction rows and each pass with the
//! monotonic clock; a run's wall time is shared among its passes (and the
//! geometry) in proportion to the time they took over all bands.

use std::time::Instant as Clock;

use glam::Vec3;
use himmel_skymodel::atmosphere::AtmosphereLuts;
use himmel_skymodel::frame::{
    CloudFrame, CoronaFrame, LowCloudGrid, NightFrame, PixelDirections, SkyLight, TextureFrame,
};
use rayon::prelude::*;

use crate::moon_pass::MoonDraw;
use crate::sun_pass::SunDraw;

/// Rows per band: 8 rows of a 1920-pixel image are 15 360 pixels (180 kB
/// of directions), 135 bands for two cores to balance.
pub const BAND_ROWS: usize = 8;

/// Runs `f(i0, pixels, dirs)` on all cores over chunks of `chunk` pixels
/// (the last may be shorter) and their directions; `i0` is the chunk's
/// first pixel index.
pub fn par_chunks(
    pixels: &mut [[f32; 3]],
    dirs: &[Option<Vec3>],
    chunk: usize,
    f: impl Fn(usize, &mut [[f32; 3]], &[Option<Vec3>]) + Sync + Send,
) {
    let chunk = chunk.max(1);
    pixels
        .par_chunks_mut(chunk)
        .zip(dirs.par_chunks(chunk))
        .enumerate()
        .for_each(|(b, (p, d))| f(b * chunk, p, d));
}

/// One per-pixel pass of a frame, ready to draw a band.
#[derive(Clone, Copy)]
pub enum PixelPass<'a> {
    /// The sky's in-scattered light ([`SkyLight::radiance`]), added
    /// ([`SkyLight::add_band`]).
    Atmosphere(&'a SkyLight),
    /// The Sun's disk.
    Sun(SunDraw<'a>),
    /// The inner corona of an eclipsed Sun.
    Corona {
        /// The frame plan's corona.
        corona: &'a CoronaFrame,
        /// The LUTs that extinguish it, if any.
        luts: Option<&'a AtmosphereLuts>,
        /// The observer's radius, km.
        r0: f32,
    },
    /// The Moon's disk, composited over what lies behind it.
    Moon(MoonDraw<'a>),
    /// The Milky Way and the diffuse night-sky light.
    Milkyway(&'a NightFrame),
    /// A texture-mapped sky over what lies behind it.
    Texture(&'a TextureFrame),
    /// The cloud layers over what lies behind them
    /// ([`CloudFrame::composite`]: the cloud's radiance with the air in
    /// front of it, what lies behind dimmed by the layers' transmittance),
    /// the low layer from its amortised grid when there is one.
    Clouds(&'a CloudFrame, Option<&'a LowCloudGrid>),
}

impl PixelPass<'_> {
    /// Whether the pass only adds light to what lies behind it (it does
    /// not hide or blend it).
    pub fn is_additive(&self) -> bool {
        match self {
            PixelPass::Atmosphere(_)
            | PixelPass::Sun(_)
            | PixelPass::Corona { .. }
            | PixelPass::Milkyway(_) => true,
            PixelPass::Moon(_) | PixelPass::Texture(_) | PixelPass::Clouds(..) => false,
        }
    }

    /// Draws the pass into whole rows from row `y0` on of a `w`-wide image.
    fn band(&self, y0: usize, w: usize, pixels: &mut [[f32; 3]], dirs: &[Option<Vec3>]) {
        match self {
            PixelPass::Atmosphere(sky) => sky.add_band(pixels, dirs),
            PixelPass::Sun(s) => s.band(y0 * w, pixels, dirs),
            PixelPass::Corona { corona, luts, r0 } => {
                crate::sun_pass::corona_band(pixels, dirs, corona, *luts, *r0)
            }
            PixelPass::Moon(m) => m.band(y0, pixels, dirs),
            PixelPass::Milkyway(n) => crate::night_pass::milkyway_band(n, pixels, dirs),
            PixelPass::Texture(t) => crate::texture_pass::band(pixels, dirs, t),
            PixelPass::Clouds(c, None) => {
                for (p, d) in pixels.iter_mut().zip(dirs) {
                    if let Some(d) = d {
                        *p = c.composite(*d, *p);
                    }
                }
            }
            PixelPass::Clouds(c, Some(grid)) => {
                for (k, (p, d)) in pixels.iter_mut().zip(dirs).enumerate() {
                    if let Some(d) = d {
                        let low = grid.hit(c, k % w, y0 + k / w, *d);
                        *p = c.composite_with(*d, *p, low);
                    }
                }
            }
        }
    }
}

/// Times of one run of per-pixel passes ([`run`]), ms of wall time.
#[derive(Debug, Clone, PartialEq)]
pub struct RunTimes {
    /// The pixel directions' share.
    pub geometry_ms: f64,
    /// Each pass's share, in the order given.
    pub pass_ms: Vec<f64>,
}

/// Runs `passes` in order over every band of `pixels` (row-major,
/// `directions`' image) and marks in `valid` the pixels that show the
/// scene (a direction exists).
pub fn run(
    directions: &PixelDirections,
    pixels: &mut [[f32; 3]],
    valid: &mut [bool],
    passes: &[PixelPass],
) -> RunTimes {
    let t0 = Clock::now();
    himmel_skymodel::frame::pixels::count_direction_walk();
    let w = directions.size().0.max(1);
    let chunk = BAND_ROWS * w;
    let zero = || vec![0.0f64; passes.len() + 1];
    let cpu = pixels
        .par_chunks_mut(chunk)
        .zip(valid.par_chunks_mut(chunk))
        .enumerate()
        .map_init(Vec::new, |dirs: &mut Vec<Option<Vec3>>, (b, (px, val))| {
            let mut t = vec![0.0f64; passes.len() + 1];
            let y0 = b * BAND_ROWS;
            let tg = Clock::now();
            dirs.resize(px.len(), None);
            for (r, row) in dirs.chunks_mut(w).enumerate() {
                directions.row(y0 + r, row);
            }
            for (v, d) in val.iter_mut().zip(dirs.iter()) {
                *v = d.is_some();
            }
            t[0] = tg.elapsed().as_secs_f64();
            for (k, pass) in passes.iter().enumerate() {
                let tp = Clock::now();
                pass.band(y0, w, px, dirs);
                t[k + 1] = tp.elapsed().as_secs_f64();
            }
            t
        })
        .reduce(zero, |a, b| a.iter().zip(&b).map(|(x, y)| x + y).collect());
    let wall = t0.elapsed().as_secs_f64() * 1e3;
    let total: f64 = cpu.iter().sum();
    let share = |c: f64| if total > 0.0 { wall * c / total } else { 0.0 };
    RunTimes {
        geometry_ms: share(cpu[0]),
        pass_ms: cpu[1..].iter().map(|&c| share(c)).collect(),
    }
}
