//! Amortised marching of the low cloud layer (`clouds.low.march_stride`).
//!
//! The view ray's march through the low layer ([`crate::clouds::march_low`])
//! is the frame's most expensive per-pixel work: tens of steps, each with
//! two short marches towards and away from each light. Inside a cloud and
//! in clear sky the result varies slowly from pixel to pixel; it changes
//! fast only at the cloud's edges. [`LowCloudGrid`] marches every N-th
//! pixel of every N-th row (and the last column and row), and a pixel
//! between four grid pixels is
//!
//! * clear when all four are clear (no cloud on any of their rays),
//! * interpolated (bilinearly: radiance, transmittance, distance) when the
//!   four agree — transmittances within [`AGREE_TRANSMITTANCE`] of each
//!   other and luminances within [`AGREE_LUMINANCE`] of their largest,
//! * marched otherwise (edges, the cloud's fine structure).
//!
//! With N = 4 about one pixel in 16 is marched on the grid; the edges add
//! what the sky's cloud structure asks for. The cost and the difference
//! from the full march (FLIP) are measured by `tests/tests/cloud_amortised.rs`
//! and the `clouds` benchmark. Each frame is marched for its own instant,
//! so nothing lags behind a moving Sun and nothing flickers from frame to
//! frame that the full march does not.

use std::sync::atomic::{AtomicUsize, Ordering};

use glam::Vec3;
use rayon::prelude::*;

use super::clouds::CloudFrame;
use super::pixels::PixelDirections;
use crate::clouds::CloudHit;
use crate::spectrum::luminance;

/// Largest spread of the four grid pixels' transmittances for which a
/// pixel between them is interpolated.
pub const AGREE_TRANSMITTANCE: f32 = 0.04;
/// Largest spread of the four grid pixels' luminances, as a fraction of
/// the largest, for which a pixel between them is interpolated.
pub const AGREE_LUMINANCE: f32 = 0.06;

/// A transmittance this close to 1 is clear sky.
const CLEAR: f32 = 1e-5;

/// The low layer marched on a grid of an image's pixels.
#[derive(Debug)]
pub struct LowCloudGrid {
    xs: Vec<usize>,
    ys: Vec<usize>,
    /// Row-major over (ys, xs); `None` where the pixel shows no scene.
    hits: Vec<Option<CloudHit>>,
    /// Pixels marched outside the grid (edges).
    marched: AtomicUsize,
}

/// The grid's coordinates along an axis of `n` pixels: every `stride`-th
/// pixel and the last.
fn nodes(n: usize, stride: usize) -> Vec<usize> {
    let mut v: Vec<usize> = (0..n).step_by(stride.max(1)).collect();
    if n > 0 && v.last() != Some(&(n - 1)) {
        v.push(n - 1);
    }
    v
}

/// The interval [v[i], v[i + 1]] that holds `x` and the fraction of the
/// way through it (`None` with fewer than two nodes).
fn cell(v: &[usize], stride: usize, x: usize) -> Option<(usize, f32)> {
    if v.len() < 2 {
        return None;
    }
    let i = (x / stride.max(1)).min(v.len() - 2);
    let (a, b) = (v[i], v[i + 1]);
    Some((i, (x.saturating_sub(a)) as f32 / (b - a).max(1) as f32))
}

impl LowCloudGrid {
    /// Marches `frame`'s low layer at the grid pixels of `dirs`' image,
    /// every `stride`-th pixel (on all cores).
    pub fn build(frame: &CloudFrame, dirs: &PixelDirections, stride: usize) -> LowCloudGrid {
        let stride = stride.max(1);
        let (w, h) = dirs.size();
        let (xs, ys) = (nodes(w, stride), nodes(h, stride));
        let hits = ys
            .par_iter()
            .flat_map_iter(|&y| {
                xs.iter()
                    .map(move |&x| dirs.dir(x, y).map(|v| frame.low_hit(v)))
                    .collect::<Vec<_>>()
            })
            .collect();
        LowCloudGrid {
            xs,
            ys,
            hits,
            marched: AtomicUsize::new(0),
        }
    }

    /// The grid's stride (its first interval).
    fn stride(&self) -> usize {
        self.xs.get(1).map_or(1, |&x| x.max(1))
    }

    /// Grid pixels marched.
    pub fn grid_pixels(&self) -> usize {
        self.hits.iter().filter(|h| h.is_some()).count()
    }

    /// Pixels marched because their grid pixels disagreed.
    pub fn edge_pixels(&self) -> usize {
        self.marched.load(Ordering::Relaxed)
    }

    /// The low layer at pixel (`x`, `y`) whose direction is `view`: from the
    /// grid where its four grid pixels agree, else marched.
    pub fn hit(&self, frame: &CloudFrame, x: usize, y: usize, view: Vec3) -> CloudHit {
        match self.interpolate(x, y) {
            Some(hit) => hit,
            None => {
                self.marched.fetch_add(1, Ordering::Relaxed);
                frame.low_hit(view)
            }
        }
    }

    /// The bilinear interpolation of the four grid pixels around (x, y)
    /// when they agree.
    fn interpolate(&self, x: usize, y: usize) -> Option<CloudHit> {
        let s = self.stride();
        let (i, fx) = cell(&self.xs, s, x)?;
        let (j, fy) = cell(&self.ys, s, y)?;
        let n = self.xs.len();
        let at = |ii: usize, jj: usize| self.hits.get(jj * n + ii).copied().flatten();
        let q = [at(i, j)?, at(i + 1, j)?, at(i, j + 1)?, at(i + 1, j + 1)?];
        if q.iter().all(|h| h.transmittance >= 1.0 - CLEAR) {
            return Some(CloudHit::CLEAR);
        }
        let (t_lo, t_hi) = q.iter().fold((f32::MAX, f32::MIN), |(a, b), h| {
            (a.min(h.transmittance), b.max(h.transmittance))
        });
        let ys = q.map(|h| luminance(h.radiance));
        let (y_lo, y_hi) = ys
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        if t_hi - t_lo > AGREE_TRANSMITTANCE || y_hi - y_lo > AGREE_LUMINANCE * y_hi.max(1e-30) {
            return None;
        }
        let wts = [
            (1.0 - fx) * (1.0 - fy),
            fx * (1.0 - fy),
            (1.0 - fx) * fy,
            fx * fy,
        ];
        let mut out = CloudHit {
            radiance: [0.0; 3],
            transmittance: 0.0,
            distance_km: 0.0,
        };
        for (h, w) in q.iter().zip(wts) {
            for c in 0..3 {
                out.radiance[c] += w * h.radiance[c];
            }
            out.transmittance += w * h.transmittance;
            out.distance_km += w * h.distance_km;
        }
        Some(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nodes_cover_the_axis_and_cells_find_their_interval() {
        assert_eq!(nodes(10, 4), vec![0, 4, 8, 9]);
        assert_eq!(nodes(9, 4), vec![0, 4, 8]);
        assert_eq!(nodes(1, 4), vec![0]);
        let v = nodes(10, 4);
        for x in 0..10 {
            let (i, f) = cell(&v, 4, x).unwrap();
            assert!(v[i] <= x && x <= v[i + 1], "{x}: {i}");
            assert!((0.0..=1.0).contains(&f));
            let back = v[i] as f32 + f * (v[i + 1] - v[i]) as f32;
            assert!((back - x as f32).abs() < 1e-5);
        }
        assert!(cell(&nodes(1, 4), 4, 0).is_none());
    }
}
