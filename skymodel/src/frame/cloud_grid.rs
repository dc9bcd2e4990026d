//! Amortised marching of the low cloud layer (`clouds.low.march_stride`).
//!
//! The view ray's march through the low layer ([`crate::clouds::march_low`])
//! is the frame's most expensive per-pixel work: tens of steps, each with
//! short marches towards and away from each light. Inside a cloud and in
//! clear sky its result varies slowly from pixel to pixel; it changes fast
//! only at the cloud's edges. [`LowCloudGrid`] marches in two levels:
//!
//! 1. every N-th pixel of every N-th row (and the last column and row):
//!    the coarse grid, one pixel in N²;
//! 2. in each coarse cell whose four corners disagree — their
//!    transmittances spread by more than [`AGREE_TRANSMITTANCE`] — the
//!    midpoints of its edges and its centre: the cell's 2 × 2 fine cells.
//!
//! A pixel is then clear when the corners of its cell are all clear,
//! interpolated bilinearly (radiance, transmittance, distance, and the
//! aerial perspective in front, weighted by extinction) from the
//! corners of its coarse cell when they agree, else from the corners of
//! its fine cell when those agree, else marched (the cloud's sharp edges).
//!
//! The luminance is not a criterion: inside a dense cloud the march's own
//! sampling makes neighbouring rays differ by factors of 2–3 in radiance
//! (a step is about one mean free path long), which interpolation smooths
//! rather than loses. The cost (the view rays marched) and the difference
//! from the full march (FLIP) are measured by
//! `tests/tests/cloud_amortised.rs`. Each frame is marched for its own
//! instant: nothing lags behind a moving Sun, and nothing changes from
//! frame to frame that the full march does not change.

use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::Vec3;
use rayon::prelude::*;

use super::cloud_history::{CloudHistory, HistoryKey, HistoryUse};
use super::clouds::{CloudFrame, SeenHit};
use super::pixels::PixelDirections;
use crate::clouds::CloudHit;

/// Largest spread of a cell's corner transmittances for which the pixels
/// inside it are interpolated.
pub const AGREE_TRANSMITTANCE: f32 = 0.3;

/// A transmittance this close to 1 is clear sky.
const CLEAR: f32 = 1e-5;

/// The low layer marched on a two-level grid of an image's pixels.
#[derive(Debug)]
pub struct LowCloudGrid {
    stride: usize,
    xs: Vec<usize>,
    ys: Vec<usize>,
    /// Row-major over (ys, xs); `None` where the pixel shows no scene.
    hits: Vec<Option<SeenHit>>,
    /// The fine level: hits at pixel (x, y) of the refined cells.
    fine: HashMap<(usize, usize), Option<SeenHit>>,
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

/// The number of grid nodes along an axis of `n` pixels at `stride`
/// (every `stride`-th pixel and the last): the wgpu backend's grid has
/// the same nodes.
pub fn grid_nodes(n: usize, stride: usize) -> usize {
    nodes(n, stride).len()
}

/// Marches the coarse nodes (row-major over `ys`, `xs`) for which `pick(i,
/// j)` holds, on all cores: `None` for those not picked, `Some(None)` where
/// the pixel shows no scene.
pub(crate) fn march_nodes(
    frame: &CloudFrame,
    dirs: &PixelDirections,
    xs: &[usize],
    ys: &[usize],
    pick: impl Fn(usize, usize) -> bool + Sync,
) -> Vec<Option<Option<SeenHit>>> {
    let pick = &pick;
    ys.par_iter()
        .enumerate()
        .flat_map_iter(|(j, &y)| {
            xs.iter()
                .enumerate()
                .map(move |(i, &x)| pick(i, j).then(|| dirs.dir(x, y).map(|v| frame.low_seen(v))))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The interval [v[i], v[i + 1]] that holds `x` (`None` with fewer than
/// two nodes).
pub(crate) fn cell(v: &[usize], stride: usize, x: usize) -> Option<usize> {
    (v.len() >= 2).then(|| (x / stride.max(1)).min(v.len() - 2))
}

/// Where `x` lies in [a, b]: 0 at a, 1 at b.
fn frac(x: usize, a: usize, b: usize) -> f32 {
    x.saturating_sub(a) as f32 / (b - a).max(1) as f32
}

/// Whether four corner hits agree: all clear, or transmittances within
/// [`AGREE_TRANSMITTANCE`].
pub(crate) fn agree(q: &[SeenHit]) -> bool {
    let (lo, hi) = q.iter().fold((f32::MAX, f32::MIN), |(a, b), h| {
        (a.min(h.hit.transmittance), b.max(h.hit.transmittance))
    });
    hi - lo <= AGREE_TRANSMITTANCE
}

/// The bilinear interpolation of corners `q` (x0y0, x1y0, x0y1, x1y1) at
/// fractions (fx, fy); clear when all four are. The air in front is the
/// corners' air weighted by their extinction (1 − T) as well: a clear
/// corner has no air in front of a cloud to give.
pub(crate) fn bilinear(q: &[SeenHit; 4], fx: f32, fy: f32) -> SeenHit {
    let clear = SeenHit {
        hit: CloudHit::CLEAR,
        air_radiance: [0.0; 3],
        air_transmittance: [1.0; 3],
    };
    if q.iter().all(|h| h.hit.transmittance >= 1.0 - CLEAR) {
        return clear;
    }
    let wts = [
        (1.0 - fx) * (1.0 - fy),
        fx * (1.0 - fy),
        (1.0 - fx) * fy,
        fx * fy,
    ];
    let mut out = SeenHit {
        hit: CloudHit {
            radiance: [0.0; 3],
            transmittance: 0.0,
            distance_km: 0.0,
        },
        air_radiance: [0.0; 3],
        air_transmittance: [0.0; 3],
    };
    let mut ext = 0.0;
    for (h, w) in q.iter().zip(wts) {
        for c in 0..3 {
            out.hit.radiance[c] += w * h.hit.radiance[c];
        }
        out.hit.transmittance += w * h.hit.transmittance;
        out.hit.distance_km += w * h.hit.distance_km;
        let we = w * (1.0 - h.hit.transmittance);
        for c in 0..3 {
            out.air_radiance[c] += we * h.air_radiance[c];
            out.air_transmittance[c] += we * h.air_transmittance[c];
        }
        ext += we;
    }
    if ext > 0.0 {
        for c in 0..3 {
            out.air_radiance[c] /= ext;
            out.air_transmittance[c] /= ext;
        }
    } else {
        (out.air_radiance, out.air_transmittance) = (clear.air_radiance, clear.air_transmittance);
    }
    out
}

impl LowCloudGrid {
    /// Marches `frame`'s low layer at the two-level grid of `dirs`' image,
    /// coarse stride `stride` (on all cores).
    pub fn build(frame: &CloudFrame, dirs: &PixelDirections, stride: usize) -> LowCloudGrid {
        let stride = stride.max(2);
        let (w, h) = dirs.size();
        let (xs, ys) = (nodes(w, stride), nodes(h, stride));
        let hits = march_nodes(frame, dirs, &xs, &ys, |_, _| true)
            .into_iter()
            .map(|h| h.flatten())
            .collect();
        LowCloudGrid::from_coarse(frame, dirs, stride, xs, ys, hits)
    }

    /// The grid of `frame` over `dirs`' image whose coarse nodes come from
    /// `history` where it holds them for this frame (marched otherwise;
    /// [`CloudHistory`]), and what the history gave. `history` then keeps
    /// this frame's nodes.
    pub fn build_with_history(
        frame: &CloudFrame,
        dirs: &PixelDirections,
        stride: usize,
        history: &mut CloudHistory,
        key: HistoryKey,
    ) -> (LowCloudGrid, HistoryUse) {
        let stride = stride.max(2);
        let (w, h) = dirs.size();
        let (xs, ys) = (nodes(w, stride), nodes(h, stride));
        let (hits, used) = history.coarse(frame, dirs, key, &xs, &ys);
        (
            LowCloudGrid::from_coarse(frame, dirs, stride, xs, ys, hits),
            used,
        )
    }

    /// The grid from its coarse nodes `hits` (row-major over `ys`, `xs`):
    /// the fine level marched in the cells whose corners disagree.
    fn from_coarse(
        frame: &CloudFrame,
        dirs: &PixelDirections,
        stride: usize,
        xs: Vec<usize>,
        ys: Vec<usize>,
        hits: Vec<Option<SeenHit>>,
    ) -> LowCloudGrid {
        let mut grid = LowCloudGrid {
            stride,
            xs,
            ys,
            hits,
            fine: HashMap::new(),
            marched: AtomicUsize::new(0),
        };
        // The fine level: edge midpoints and centres of disagreeing cells.
        let mut want: Vec<(usize, usize)> = Vec::new();
        let (nx, ny) = (grid.xs.len(), grid.ys.len());
        for j in 0..ny.saturating_sub(1) {
            for i in 0..nx.saturating_sub(1) {
                if grid.corners(i, j).is_some_and(|q| agree(&q)) {
                    continue;
                }
                let (x0, x1) = (grid.xs[i], grid.xs[i + 1]);
                let (y0, y1) = (grid.ys[j], grid.ys[j + 1]);
                let (xm, ym) = ((x0 + x1) / 2, (y0 + y1) / 2);
                want.extend([(xm, y0), (x0, ym), (xm, ym), (x1, ym), (xm, y1)]);
            }
        }
        want.sort_unstable();
        want.dedup();
        grid.fine = want
            .into_par_iter()
            .map(|(x, y)| ((x, y), dirs.dir(x, y).map(|v| frame.low_seen(v))))
            .collect();
        grid
    }

    /// The coarse grid's hit at node (i, j).
    fn node(&self, i: usize, j: usize) -> Option<SeenHit> {
        self.hits.get(j * self.xs.len() + i).copied().flatten()
    }

    /// The hit at pixel (x, y) if the grid marched it.
    fn at(&self, x: usize, y: usize) -> Option<SeenHit> {
        let (i, j) = (
            self.xs.binary_search(&x).ok(),
            self.ys.binary_search(&y).ok(),
        );
        match (i, j) {
            (Some(i), Some(j)) => self.node(i, j),
            _ => self.fine.get(&(x, y)).copied().flatten(),
        }
    }

    /// The four corners of coarse cell (i, j), when all show the scene.
    fn corners(&self, i: usize, j: usize) -> Option<[SeenHit; 4]> {
        Some([
            self.node(i, j)?,
            self.node(i + 1, j)?,
            self.node(i, j + 1)?,
            self.node(i + 1, j + 1)?,
        ])
    }

    /// View rays the grid marched (both levels).
    pub fn grid_pixels(&self) -> usize {
        self.hits.iter().filter(|h| h.is_some()).count()
            + self.fine.values().filter(|h| h.is_some()).count()
    }

    /// Pixels marched because their cell's corners disagreed.
    pub fn edge_pixels(&self) -> usize {
        self.marched.load(Ordering::Relaxed)
    }

    /// The low layer at pixel (`x`, `y`) whose direction is `view`: from the
    /// grid where the corners of its cell agree, else marched.
    pub fn hit(&self, frame: &CloudFrame, x: usize, y: usize, view: Vec3) -> SeenHit {
        match self.interpolate(x, y) {
            Some(hit) => hit,
            None => {
                self.marched.fetch_add(1, Ordering::Relaxed);
                frame.low_seen(view)
            }
        }
    }

    /// The pixel from its coarse cell, or its fine cell, when their
    /// corners agree.
    fn interpolate(&self, x: usize, y: usize) -> Option<SeenHit> {
        let i = cell(&self.xs, self.stride, x)?;
        let j = cell(&self.ys, self.stride, y)?;
        let (x0, x1) = (self.xs[i], self.xs[i + 1]);
        let (y0, y1) = (self.ys[j], self.ys[j + 1]);
        let q = self.corners(i, j)?;
        if agree(&q) {
            // A grid pixel itself gets its own value (weights 1, 0, 0, 0).
            return Some(bilinear(&q, frac(x, x0, x1), frac(y, y0, y1)));
        }
        let (xm, ym) = ((x0 + x1) / 2, (y0 + y1) / 2);
        let (xa, xb) = if x <= xm { (x0, xm) } else { (xm, x1) };
        let (ya, yb) = if y <= ym { (y0, ym) } else { (ym, y1) };
        let f = [
            self.at(xa, ya)?,
            self.at(xb, ya)?,
            self.at(xa, yb)?,
            self.at(xb, yb)?,
        ];
        if agree(&f) {
            return Some(bilinear(&f, frac(x, xa, xb), frac(y, ya, yb)));
        }
        // A pixel the grid marched is not marched again.
        [(xa, ya), (xb, ya), (xa, yb), (xb, yb)]
            .iter()
            .zip(f)
            .find_map(|(&c, h)| (c == (x, y)).then_some(h))
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
            let i = cell(&v, 4, x).unwrap();
            assert!(v[i] <= x && x <= v[i + 1], "{x}: {i}");
            let f = frac(x, v[i], v[i + 1]);
            assert!((0.0..=1.0).contains(&f));
            let back = v[i] as f32 + f * (v[i + 1] - v[i]) as f32;
            assert!((back - x as f32).abs() < 1e-5);
        }
        assert!(cell(&nodes(1, 4), 4, 0).is_none());
        assert_eq!(grid_nodes(10, 4), 4);
        assert_eq!(grid_nodes(640, 4), 161);
    }
}
