//! Temporal reprojection of the low layer's coarse grid over a frame
//! sequence (issue 18; after Schneider & Vos 2015): a renderer that draws
//! frame after frame keeps the last frame's coarse nodes of the amortised
//! march ([`super::LowCloudGrid`]) and, in the next frame, marches only a
//! rotating quarter of them — the nodes (i, j) with
//! (i mod 2) + 2 (j mod 2) = frame mod [`HISTORY_PERIOD`] — and takes the
//! others from the last frame, moved with the wind:
//!
//! * the cloud that a node's view ray `v` met at distance `d` (the last
//!   frame's extinction-weighted distance there; the middle of the layer
//!   along `v` where it was clear) has moved with the field by its offset's
//!   change Δ, so last frame it lay at `v d − Δ`: the last frame's image
//!   at that direction (bilinear over its coarse nodes) is the node's
//!   value now;
//! * a value is taken only where the nodes it is interpolated from agree
//!   (transmittances within [`HISTORY_AGREE`]: no edge of a cloud between
//!   them), were marched at most [`HISTORY_MAX_AGE`] frames ago (a value
//!   reprojected again and again drifts from the full march: each
//!   reprojection adds about 0.005 to the FLIP against it at 320², wind
//!   15 m/s), and under lights within [`HISTORY_LIGHT_DEG`] of this
//!   frame's (each light's direction then and now); otherwise the node is
//!   marched. A ray that never meets the layer keeps its clear value.
//!
//! With wind, about half the coarse nodes are reused (47 % over frames
//! 1–4 of `tests/tests/cloud_temporal.rs`: the quarter of the frame's
//! phase is marched, and every fourth frame most nodes, when the quarter
//! marched four frames ago has aged out and its neighbours interpolate
//! from it); with static clouds, three quarters.
//!
//! The fine level and the edge pixels are marched every frame, as without
//! history. The history is not used at all (every node marched) on the
//! first frame, or when the image size, the camera, the low layer's
//! parameters (all but the time), the observer's shell, the stride, the
//! atmosphere or the number of lights changed: [`HistoryMiss`] says which.
//! The CPU renderer also forgets it after a frame without the amortised
//! march (the next frame is a `first frame`), so that a history is never
//! older than the frame before.
//! [`HistoryUse`] counts the nodes reused and marched (`--stats`:
//! `cloud_history`).
//!
//! The per-frame decisions — whether the history serves and why not, the
//! quarter marched, the field's move, which ages' lights still hold — are
//! [`HistoryClock::step`]'s, which the wgpu backend runs as well: it keeps
//! the nodes in GPU buffers and ports `Kept::fetch` to WGSL
//! (`backend-wgpu/src/passes/clouds_history.rs`).

use std::collections::VecDeque;
use std::fmt;

use glam::{Vec2, Vec3};

use super::cloud_grid::{bilinear, cell, march_nodes};
use super::clouds::{CloudFrame, SeenHit, CLEAR};
use super::pixels::PixelDirections;
use crate::atmosphere::AtmosphereParams;
use crate::clouds::{CloudHit, Shell};
use crate::projection::Camera;
use crate::scene::{LowCloudSpec, Scene};
use crate::FramePlan;

/// Frames over which every coarse node is marched once (a quarter per
/// frame).
pub const HISTORY_PERIOD: usize = 4;

/// The most frames a reused value may have lived since it was marched
/// (reprojected again each frame).
pub const HISTORY_MAX_AGE: usize = HISTORY_PERIOD - 1;

/// The largest angle, degrees, by which a light (the Sun, the Moon) may
/// have moved since a reused node was marched. A node's lighting changes
/// by about 8 % per degree of the Sun's motion (cumulus at 08:00 UTC,
/// `tests/tests/cloud_amortised.rs`: 2.1 % per 0.25°), so a reused node
/// lags its full march by at most about 0.8 %.
pub const HISTORY_LIGHT_DEG: f32 = 0.1;

/// The largest spread of the transmittances of the nodes a reprojected
/// value is interpolated from (tighter than the grid's own
/// [`super::cloud_grid::AGREE_TRANSMITTANCE`]: an interpolated node is
/// interpolated again between the pixels).
pub const HISTORY_AGREE: f32 = 0.1;

/// Weights below this are left out of a reprojected node's corners.
pub const HISTORY_NEGLIGIBLE: f32 = 1e-4;

/// What must stay the same for the history to serve a frame.
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryKey {
    /// The camera (projection, size, orientation).
    pub camera: Camera,
    /// The low layer's parameters (its field moves with the time).
    pub layer: LowCloudSpec,
    /// The observer's shell.
    pub shell: Shell,
    /// The grid's stride.
    pub stride: usize,
    /// The atmosphere's parameters when the atmosphere pass runs (the air
    /// in front of the clouds).
    pub atmosphere: Option<AtmosphereParams>,
}

impl HistoryKey {
    /// The key of `scene`'s frame `plan` with clouds `c` (both backends).
    pub fn of(scene: &Scene, plan: &FramePlan, c: &CloudFrame) -> HistoryKey {
        HistoryKey {
            camera: scene.camera,
            layer: scene.clouds.low,
            shell: c.shell,
            stride: c.march_stride as usize,
            atmosphere: plan.luts.is_some().then(|| scene.atmosphere.clone()),
        }
    }
}

/// Why a frame did not use the history.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HistoryMiss {
    /// No earlier frame.
    First,
    /// The image size changed.
    Resized,
    /// The camera moved or turned (or changed its projection).
    CameraMoved,
    /// The low layer's parameters, the observer, the stride or the
    /// atmosphere changed.
    LayerChanged,
    /// A light rose or set (the number of lights changed).
    LightsChanged,
}

impl fmt::Display for HistoryMiss {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            HistoryMiss::First => "first frame",
            HistoryMiss::Resized => "image resized",
            HistoryMiss::CameraMoved => "camera moved",
            HistoryMiss::LayerChanged => "cloud layer, observer or atmosphere changed",
            HistoryMiss::LightsChanged => "a light rose or set",
        })
    }
}

/// What the history gave a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HistoryUse {
    /// Coarse nodes taken from the last frame.
    pub reused: usize,
    /// Coarse nodes marched (showing the scene).
    pub marched: usize,
    /// Of those, nodes marched because a light moved more than
    /// [`HISTORY_LIGHT_DEG`] since the values they would have come from.
    pub light_moved: usize,
    /// Why the history was not used at all (`None`: it was).
    pub miss: Option<HistoryMiss>,
}

/// What a history keeps of the last frame beside its nodes: the key, the
/// field's wind offset and the lights of the last frames; and the frame
/// count that picks each frame's quarter. Both backends decide each
/// frame's use of their nodes with it ([`HistoryClock::step`]).
#[derive(Debug, Clone, Default)]
pub struct HistoryClock {
    frame: usize,
    last: Option<LastFrame>,
}

#[derive(Debug, Clone)]
struct LastFrame {
    key: HistoryKey,
    /// The field's wind offset, km.
    offset_km: Vec2,
    /// The lights' directions of the last frames, newest last.
    lights: VecDeque<Vec<Vec3>>,
}

/// A frame's use of the history, decided before its nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HistoryStep {
    /// Why the history cannot serve this frame (`None`: it can).
    pub miss: Option<HistoryMiss>,
    /// The quarter marched: the nodes (i, j) with
    /// (i mod 2) + 2 (j mod 2) = `phase`.
    pub phase: usize,
    /// The field's move since the last frame, km (East, North).
    pub delta_km: Vec2,
    /// `lit[a]`: whether every light of `a` frames ago lies within
    /// [`HISTORY_LIGHT_DEG`] of its direction now (`lit[0]` holds).
    pub lit: [bool; HISTORY_PERIOD],
}

impl HistoryStep {
    /// Whether the nodes (i, j) are marched this frame whatever the
    /// history holds.
    pub fn fresh(&self, i: usize, j: usize) -> bool {
        (i % 2) + 2 * (j % 2) == self.phase
    }
}

impl HistoryClock {
    /// Forgets the last frame: the next one is a `first frame`.
    pub fn clear(&mut self) {
        self.last = None;
    }

    /// This frame's use of the history under `key`; keeps this frame's
    /// key, wind offset and lights for the next.
    pub fn step(&mut self, frame: &CloudFrame, key: HistoryKey) -> HistoryStep {
        self.frame = self.frame.wrapping_add(1);
        let lights: Vec<Vec3> = frame.light_sources().iter().map(|l| l.0).collect();
        let offset_km = frame.low.as_ref().map_or(Vec2::ZERO, |f| f.offset_km);
        let last = self.last.take();
        let miss = match &last {
            None => Some(HistoryMiss::First),
            Some(k) if k.key.camera.image_size() != key.camera.image_size() => {
                Some(HistoryMiss::Resized)
            }
            Some(k) if k.key.camera != key.camera => Some(HistoryMiss::CameraMoved),
            Some(k) if k.key != key => Some(HistoryMiss::LayerChanged),
            Some(k) if k.lights.back().map(Vec::len) != Some(lights.len()) => {
                Some(HistoryMiss::LightsChanged)
            }
            Some(_) => None,
        };
        let mut lit = [true; HISTORY_PERIOD];
        let (delta_km, mut ring) = match (last, miss) {
            (Some(k), None) => {
                for (age, l) in lit.iter_mut().enumerate().skip(1) {
                    *l = age <= k.lights.len()
                        && k.lights[k.lights.len() - age]
                            .iter()
                            .zip(&lights)
                            .all(|(a, b)| a.angle_between(*b).to_degrees() <= HISTORY_LIGHT_DEG);
                }
                (offset_km - k.offset_km, k.lights)
            }
            _ => (Vec2::ZERO, VecDeque::new()),
        };
        ring.push_back(lights);
        while ring.len() > HISTORY_PERIOD {
            ring.pop_front();
        }
        self.last = Some(LastFrame {
            key,
            offset_km,
            lights: ring,
        });
        HistoryStep {
            miss,
            phase: self.frame % HISTORY_PERIOD,
            delta_km,
            lit,
        }
    }
}

/// The last frame's coarse nodes.
#[derive(Debug, Clone)]
struct Kept {
    camera: Camera,
    stride: usize,
    xs: Vec<usize>,
    ys: Vec<usize>,
    nodes: Vec<Option<SeenHit>>,
    /// Frames since each node's value was marched (0: in that frame).
    ages: Vec<usize>,
}

/// The low layer's coarse grid kept from frame to frame by a renderer.
#[derive(Debug, Clone, Default)]
pub struct CloudHistory {
    clock: HistoryClock,
    kept: Option<Kept>,
}

impl CloudHistory {
    /// Forgets the kept frame.
    pub fn clear(&mut self) {
        self.clock.clear();
        self.kept = None;
    }

    /// The coarse nodes of this frame at (`xs`, `ys`): the quarter of
    /// this frame's phase and whatever the history cannot give marched,
    /// the rest reprojected; keeps them for the next frame.
    pub(crate) fn coarse(
        &mut self,
        frame: &CloudFrame,
        dirs: &PixelDirections,
        key: HistoryKey,
        xs: &[usize],
        ys: &[usize],
    ) -> (Vec<Option<SeenHit>>, HistoryUse) {
        let (camera, stride) = (key.camera, key.stride);
        let step = self.clock.step(frame, key);
        let kept = self
            .kept
            .take()
            .filter(|k| k.xs == xs && k.ys == ys && step.miss.is_none());
        let (nodes, ages, used) = match kept {
            Some(k) => Self::reproject(frame, dirs, &k, &step),
            None => {
                let nodes: Vec<Option<SeenHit>> = march_nodes(frame, dirs, xs, ys, |_, _| true)
                    .into_iter()
                    .map(Option::flatten)
                    .collect();
                let used = HistoryUse {
                    reused: 0,
                    marched: nodes.iter().filter(|n| n.is_some()).count(),
                    light_moved: 0,
                    miss: Some(step.miss.unwrap_or(HistoryMiss::First)),
                };
                (nodes, vec![0; xs.len() * ys.len()], used)
            }
        };
        self.kept = Some(Kept {
            camera,
            stride,
            xs: xs.to_vec(),
            ys: ys.to_vec(),
            nodes: nodes.clone(),
            ages,
        });
        (nodes, used)
    }

    /// This frame's nodes from the kept frame `k`: the phase's quarter and
    /// the nodes the history cannot give marched.
    fn reproject(
        frame: &CloudFrame,
        dirs: &PixelDirections,
        k: &Kept,
        step: &HistoryStep,
    ) -> (Vec<Option<SeenHit>>, Vec<usize>, HistoryUse) {
        let nx = k.xs.len();
        let mut light_moved = 0;
        let mut from_history: Vec<Option<(Option<SeenHit>, usize)>> =
            Vec::with_capacity(k.nodes.len());
        for (j, &y) in k.ys.iter().enumerate() {
            for (i, &x) in k.xs.iter().enumerate() {
                let got = if step.fresh(i, j) {
                    None
                } else {
                    match dirs.dir(x, y) {
                        None => Some((None, 0)),
                        Some(v) => match k.fetch(frame, v, step.delta_km, j * nx + i) {
                            Some((hit, age)) if step.lit.get(age) == Some(&true) => {
                                Some((Some(hit), age))
                            }
                            Some(_) => {
                                light_moved += 1;
                                None
                            }
                            None => None,
                        },
                    }
                };
                from_history.push(got);
            }
        }
        let marched = march_nodes(frame, dirs, &k.xs, &k.ys, |i, j| {
            from_history[j * nx + i].is_none()
        });
        let (mut nodes, mut ages) = (Vec::with_capacity(marched.len()), Vec::new());
        let (mut reused, mut fresh_count) = (0, 0);
        for (m, h) in marched.into_iter().zip(&from_history) {
            match (m, h) {
                (Some(m), _) => {
                    fresh_count += usize::from(m.is_some());
                    nodes.push(m);
                    ages.push(0);
                }
                (None, Some((hit, age))) => {
                    reused += usize::from(hit.is_some());
                    nodes.push(*hit);
                    ages.push(*age);
                }
                (None, None) => {
                    nodes.push(None);
                    ages.push(0);
                }
            }
        }
        let used = HistoryUse {
            reused,
            marched: fresh_count,
            light_moved,
            miss: None,
        };
        (nodes, ages, used)
    }
}

impl Kept {
    /// The value and age (frames since marched) that node `n`, looking
    /// along `v`, takes from this frame when the field has moved by
    /// `delta` km since; `None` when the nodes it would come from
    /// disagree, show no scene or are too old.
    fn fetch(
        &self,
        frame: &CloudFrame,
        v: Vec3,
        delta: Vec2,
        n: usize,
    ) -> Option<(SeenHit, usize)> {
        let last = self.nodes.get(n).copied().flatten()?;
        let low = frame.low.as_ref()?;
        let Some((t0, t1)) = frame.shell.slab(v, low.base_km, low.top_km) else {
            // A ray that never meets the layer is clear at any time.
            let clear = SeenHit {
                hit: CloudHit::CLEAR,
                air_radiance: [0.0; 3],
                air_transmittance: [1.0; 3],
            };
            return Some((clear, 0));
        };
        let d = if last.hit.transmittance < 1.0 - CLEAR {
            last.hit.distance_km
        } else {
            0.5 * (t0 + t1)
        };
        let then = (v * d - delta.extend(0.0)).normalize_or_zero();
        let (px, py) = self.camera.dir_to_pixel(then.as_dvec3())?;
        let (fx, fy) = (px as f32 - 0.5, py as f32 - 0.5);
        let (w, h) = self.camera.image_size();
        if !(fx >= 0.0 && fy >= 0.0 && fx <= (w - 1) as f32 && fy <= (h - 1) as f32) {
            return None;
        }
        let stride = self.stride;
        let i = cell(&self.xs, stride, fx as usize)?;
        let j = cell(&self.ys, stride, fy as usize)?;
        let span = |v: &[usize], k: usize, f: f32| {
            ((f - v[k] as f32) / (v[k + 1] - v[k]).max(1) as f32).clamp(0.0, 1.0)
        };
        let (ax, ay) = (span(&self.xs, i, fx), span(&self.ys, j, fy));
        let nx = self.xs.len();
        let idx = [
            j * nx + i,
            j * nx + i + 1,
            (j + 1) * nx + i,
            (j + 1) * nx + i + 1,
        ];
        let wts = [
            (1.0 - ax) * (1.0 - ay),
            ax * (1.0 - ay),
            (1.0 - ax) * ay,
            ax * ay,
        ];
        let mut q = [last; 4];
        let (mut used, mut age) = (Vec::with_capacity(4), 0);
        for k in 0..4 {
            q[k] = self.nodes.get(idx[k]).copied().flatten()?;
            if wts[k] > HISTORY_NEGLIGIBLE {
                used.push(q[k]);
                age = age.max(self.ages[idx[k]] + 1);
            }
        }
        let (lo, hi) = used.iter().fold((f32::MAX, f32::MIN), |(a, b), h| {
            (a.min(h.hit.transmittance), b.max(h.hit.transmittance))
        });
        (hi - lo <= HISTORY_AGREE && age <= HISTORY_MAX_AGE).then(|| (bilinear(&q, ax, ay), age))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::Projection;

    /// A node's own direction leads back to its own pixel: without wind
    /// the history gives each node its last value.
    #[test]
    fn directions_lead_back_to_their_pixels() {
        let cam = Camera {
            projection: Projection::Fisheye,
            width: 160,
            height: 160,
            ..Default::default()
        };
        let dirs = PixelDirections::new(&cam);
        let mut worst = 0.0f64;
        for y in (0..160).step_by(4) {
            for x in (0..160).step_by(4) {
                let Some(v) = dirs.dir(x, y) else { continue };
                let (px, py) = cam.dir_to_pixel(v.as_dvec3()).expect("shown");
                worst = worst.max((px - 0.5 - x as f64).abs().max((py - 0.5 - y as f64).abs()));
            }
        }
        assert!(worst < 1e-3, "{worst} px");
    }
}
