//! Frame sequences: time-lapses, animations and camera paths from one base
//! [`Scene`].
//!
//! **Time.** Frame k (0-based) is at
//!
//! ```text
//!   t_k = t₀ + k · Δ,    Δ = time_step_s · time.speed
//! ```
//!
//! seconds of uniform time (SI seconds, TT; a leap second is a second like
//! any other), where t₀ is the base scene's instant (`time.utc`, or the
//! `time.day_fraction` of its date, resolved once: a `now` scene does not
//! drift while it renders). `time.speed` multiplies the step: 2 runs twice
//! as fast, −1 runs backwards. A sequence with speed −1 started at the last
//! instant of a speed-1 sequence renders the same instants in reverse order.
//!
//! **Camera.** Without a path every frame keeps the base scene's camera.
//! With a [`CameraPath`] each frame's `camera.position_m` and
//! `camera.look_at_m` come from the path at that frame (by index or by
//! t_k − t₀, [`camera_path`]).
//!
//! **History.** Each [`SequenceFrame`] carries the previous frame's
//! [`FrameHistory`] (index, instant, elapsed time, camera): what temporal
//! passes (reprojection, motion vectors, exposure adaptation) need.
//!
//! **Exposure.** [`exposure::smooth_ev100`] is the automatic exposure of a
//! whole sequence.

pub mod camera_path;
pub mod exposure;

use himmel_astro::{Instant, UtcDateTime};

pub use camera_path::{CameraKeyframe, CameraPath, PathKey, Placement};

use crate::projection::Camera;
use crate::scene::{Scene, SceneError};
use crate::solar_time::instant_after;
use crate::state::SkyState;

/// Most frames in one sequence.
pub const MAX_FRAMES: u32 = 1_000_000;

/// Largest |Δ| = |time_step_s · time.speed|, seconds (about 3000 years).
pub const MAX_STEP_S: f64 = 1e11;

const SECONDS_PER_DAY: f64 = 86_400.0;

/// An invalid sequence.
#[derive(Debug, Clone, PartialEq)]
pub enum SequenceError {
    /// The frame count is outside [1, [`MAX_FRAMES`]].
    Frames(u64),
    /// The time step is not finite, or |Δ| exceeds [`MAX_STEP_S`].
    TimeStep(f64),
    /// The camera path is invalid: the field (`keyframes[1].position_m`)
    /// and what is accepted.
    CameraPath {
        /// The field's path in the camera-path document.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// The base scene, or a frame's scene, is invalid.
    Scene(SceneError),
}

impl std::fmt::Display for SequenceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SequenceError::Frames(n) => {
                write!(f, "frames: {n} is outside [1, {MAX_FRAMES}]")
            }
            SequenceError::TimeStep(s) => write!(
                f,
                "time_step_s: {s} s (times time.speed) is not a finite number of seconds within ±{MAX_STEP_S:e}"
            ),
            SequenceError::CameraPath { field, message } => write!(f, "{field}: {message}"),
            SequenceError::Scene(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for SequenceError {}

impl From<SceneError> for SequenceError {
    fn from(e: SceneError) -> Self {
        SequenceError::Scene(e)
    }
}

/// What a temporal pass needs to know about the frame before.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameHistory {
    /// The frame's index.
    pub index: u32,
    /// Its civil UTC instant.
    pub utc: UtcDateTime,
    /// Its Julian date, TT.
    pub jd_tt: f64,
    /// Scene seconds since the first frame (t − t₀).
    pub elapsed_s: f64,
    /// Its camera (projection, size, orientation, placement).
    pub camera: Camera,
}

/// One frame of a sequence.
#[derive(Debug, Clone)]
pub struct SequenceFrame {
    /// Index, 0-based.
    pub index: u32,
    /// Scene seconds since the first frame, t_k − t₀ = k·Δ.
    pub elapsed_s: f64,
    /// The frame's scene: the base scene at t_k (`time.utc` set,
    /// `time.day_fraction` cleared) with the path's camera placement.
    pub scene: Scene,
    /// The sky at t_k.
    pub state: SkyState,
    /// The previous frame (none for the first).
    pub previous: Option<FrameHistory>,
}

impl SequenceFrame {
    /// This frame as the history of the next.
    pub fn history(&self) -> FrameHistory {
        FrameHistory {
            index: self.index,
            utc: self.state.utc,
            jd_tt: self.state.jd_tt,
            elapsed_s: self.elapsed_s,
            camera: self.scene.camera,
        }
    }
}

/// A validated sequence (see the module documentation).
#[derive(Debug, Clone)]
pub struct Sequence {
    base: Scene,
    frames: u32,
    step_s: f64,
    path: Option<CameraPath>,
    start: Instant,
}

/// Half a millisecond, days: frame instants are read half a millisecond
/// late and cut to the millisecond, which rounds them with the carry into
/// the next second, minute or day done by the calendar.
const HALF_MS_DAYS: f64 = 5e-4 / SECONDS_PER_DAY;

/// RFC 3339 UTC with milliseconds (what the frame scenes carry): the clock
/// reading cut to the millisecond (never into a second that does not
/// exist).
fn rfc3339_ms(t: &UtcDateTime) -> String {
    let last_ms = if t.second >= 60.0 { 60_999.0 } else { 59_999.0 };
    let ms = (t.second * 1e3).floor().min(last_ms) as u32;
    format!(
        "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z",
        t.year,
        t.month,
        t.day,
        t.hour,
        t.minute,
        ms / 1000,
        ms % 1000
    )
}

impl Sequence {
    /// A sequence of `frames` frames from `base` with `time_step_s` scene
    /// seconds per frame (multiplied by `base.time.speed`; may be negative)
    /// and an optional camera path. Validates the base scene and the path
    /// and resolves t₀.
    pub fn new(
        base: Scene,
        frames: u32,
        time_step_s: f64,
        path: Option<CameraPath>,
    ) -> Result<Sequence, SequenceError> {
        if !(1..=MAX_FRAMES).contains(&frames) {
            return Err(SequenceError::Frames(frames.into()));
        }
        let step_s = time_step_s * base.time.speed;
        if !(step_s.is_finite() && step_s.abs() <= MAX_STEP_S) {
            return Err(SequenceError::TimeStep(time_step_s));
        }
        base.validate()?;
        if let Some(p) = &path {
            p.validate()?;
        }
        let utc = crate::state::scene_utc(&base)?;
        let start = Instant::from_utc(&utc).map_err(|e| SceneError {
            field: "time.utc".into(),
            message: e.to_string(),
        })?;
        Ok(Sequence {
            base,
            frames,
            step_s,
            path,
            start,
        })
    }

    /// Number of frames.
    pub fn len(&self) -> u32 {
        self.frames
    }

    /// Whether the sequence is empty (never: at least one frame).
    pub fn is_empty(&self) -> bool {
        self.frames == 0
    }

    /// Δ, scene seconds between consecutive frames (time step × speed).
    pub fn step_s(&self) -> f64 {
        self.step_s
    }

    /// The base scene.
    pub fn base(&self) -> &Scene {
        &self.base
    }

    /// The scene of frame `index` (any index; frames need not be visited in
    /// order), and its elapsed scene seconds.
    pub fn scene(&self, index: u32) -> Result<(Scene, f64), SequenceError> {
        let elapsed_s = f64::from(index) * self.step_s;
        let utc = instant_after(&self.start, elapsed_s / SECONDS_PER_DAY + HALF_MS_DAYS).to_utc();
        let mut scene = self.base.clone();
        scene.time.utc = rfc3339_ms(&utc);
        scene.time.day_fraction = None;
        if let Some(p) = &self.path {
            let at = p.at(index, elapsed_s);
            scene.camera.position_m = Some(at.position_m);
            scene.camera.look_at_m = Some(at.look_at_m);
        }
        scene.validate()?;
        Ok((scene, elapsed_s))
    }

    /// Frame `index` with its sky state (`previous` is left empty; the
    /// iterator fills it).
    pub fn frame(&self, index: u32) -> Result<SequenceFrame, SequenceError> {
        let (scene, elapsed_s) = self.scene(index)?;
        let state = SkyState::at(&scene)?;
        Ok(SequenceFrame {
            index,
            elapsed_s,
            scene,
            state,
            previous: None,
        })
    }

    /// The frames in order, each with the previous frame's history.
    pub fn iter(&self) -> SequenceIter<'_> {
        SequenceIter {
            seq: self,
            next: 0,
            previous: None,
        }
    }
}

/// The frames of a [`Sequence`] in order ([`Sequence::iter`]).
#[derive(Debug)]
pub struct SequenceIter<'a> {
    seq: &'a Sequence,
    next: u32,
    previous: Option<FrameHistory>,
}

impl Iterator for SequenceIter<'_> {
    type Item = Result<SequenceFrame, SequenceError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.next >= self.seq.frames {
            return None;
        }
        let k = self.next;
        self.next += 1;
        Some(self.seq.frame(k).map(|mut f| {
            f.previous = self.previous;
            self.previous = Some(f.history());
            f
        }))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = (self.seq.frames - self.next) as usize;
        (n, Some(n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base(utc: &str, speed: f64) -> Scene {
        let mut s = Scene::default();
        s.time.utc = utc.into();
        s.time.speed = speed;
        s.camera.width = 8;
        s.camera.height = 8;
        s
    }

    fn seconds(a: &UtcDateTime, b: &UtcDateTime) -> f64 {
        let (a, b) = (Instant::from_utc(a).unwrap(), Instant::from_utc(b).unwrap());
        (b.jd_tt - a.jd_tt) * SECONDS_PER_DAY
    }

    #[test]
    fn frames_are_evenly_spaced_and_speed_multiplies_the_step() {
        let seq = Sequence::new(base("2024-06-21T10:00:00Z", 3.0), 4, 600.0, None).unwrap();
        assert_eq!(seq.step_s(), 1800.0);
        let frames: Vec<_> = seq.iter().map(Result::unwrap).collect();
        assert_eq!(frames.len(), 4);
        assert_eq!(frames[3].scene.time.utc, "2024-06-21T11:30:00.000Z");
        for w in frames.windows(2) {
            let dt = seconds(&w[0].state.utc, &w[1].state.utc);
            // Frame instants are kept to the millisecond.
            assert!((dt - 1800.0).abs() < 2e-3, "{dt}");
            // History: the previous frame as it was.
            let p = w[1].previous.unwrap();
            assert_eq!(
                (p.index, p.utc, p.elapsed_s),
                (w[0].index, w[0].state.utc, w[0].elapsed_s)
            );
        }
        assert!(frames[0].previous.is_none());
    }

    /// Whole steps land on whole clock readings: half-hour steps read
    /// :00.000 and :30.000 (not 04:59:59.999 from the f64 Julian day's
    /// rounding), also across midnight and backwards.
    #[test]
    fn frame_instants_round_to_the_millisecond() {
        for (start, step) in [
            ("2024-06-21T04:00:00Z", 1800.0),
            ("2024-06-21T00:00:00Z", 1800.0),
            ("2024-06-22T12:00:00Z", -1800.0),
        ] {
            let seq = Sequence::new(base(start, 1.0), 48, step, None).unwrap();
            for k in 0..48 {
                let utc = seq.scene(k).unwrap().0.time.utc;
                assert!(
                    utc.ends_with(":00:00.000Z") || utc.ends_with(":30:00.000Z"),
                    "{start} frame {k}: {utc}"
                );
            }
        }
    }

    #[test]
    fn leap_seconds_are_counted() {
        // 2016-12-31 ended with a leap second: 10 s of uniform time from
        // 23:59:55 reach 00:00:04 of the next day.
        let seq = Sequence::new(base("2016-12-31T23:59:55Z", 1.0), 2, 10.0, None).unwrap();
        assert_eq!(seq.scene(1).unwrap().0.time.utc, "2017-01-01T00:00:04.000Z");
        // … and 5.5 s reach into the leap second itself.
        let seq = Sequence::new(base("2016-12-31T23:59:55Z", 1.0), 2, 5.5, None).unwrap();
        assert_eq!(seq.scene(1).unwrap().0.time.utc, "2016-12-31T23:59:60.500Z");
    }

    #[test]
    fn speed_minus_one_renders_the_same_instants_in_reverse() {
        let fwd = Sequence::new(base("2024-03-01T00:00:00Z", 1.0), 5, 3600.0, None).unwrap();
        let last = fwd.scene(4).unwrap().0.time.utc;
        let back = Sequence::new(base(&last, -1.0), 5, 3600.0, None).unwrap();
        for k in 0..5 {
            let a = fwd.frame(k).unwrap();
            let b = back.frame(4 - k).unwrap();
            assert!(seconds(&a.state.utc, &b.state.utc).abs() < 2e-3);
            assert!((a.state.sun.alt_deg - b.state.sun.alt_deg).abs() < 1e-5);
        }
        // A negative step with speed 1 is the same as speed −1.
        let neg = Sequence::new(base(&last, 1.0), 5, -3600.0, None).unwrap();
        assert_eq!(neg.step_s(), back.step_s());
    }

    #[test]
    fn one_frame_is_the_base_scene() {
        let b = base("2024-06-21T10:00:00Z", 1.0);
        let seq = Sequence::new(b.clone(), 1, 0.0, None).unwrap();
        let frames: Vec<_> = seq.iter().map(Result::unwrap).collect();
        assert_eq!(frames.len(), 1);
        assert_eq!(frames[0].state, SkyState::at(&b).unwrap());
    }

    #[test]
    fn the_camera_follows_the_path() {
        let path = CameraPath::from_json(
            r#"{"keyframes": [
                {"frame": 0, "position_m": [0, 2, 0], "look_at_m": [0, 2, -10]},
                {"frame": 2, "position_m": [4, 2, 0], "look_at_m": [0, 2, -10]}
            ]}"#,
        )
        .unwrap();
        let mut b = base("2024-06-21T10:00:00Z", 1.0);
        b.camera.projection = crate::Projection::Perspective;
        let seq = Sequence::new(b, 3, 60.0, Some(path)).unwrap();
        let f: Vec<_> = seq.iter().map(Result::unwrap).collect();
        assert_eq!(f[1].scene.camera.position_m, Some([2.0, 2.0, 0.0]));
        assert_eq!(
            f[2].previous.unwrap().camera.position_m,
            Some([2.0, 2.0, 0.0])
        );
        assert_eq!(f[2].scene.camera.look_at_m, Some([0.0, 2.0, -10.0]));
    }

    #[test]
    fn invalid_sequences_are_refused() {
        let b = base("2024-06-21T10:00:00Z", 1.0);
        assert_eq!(
            Sequence::new(b.clone(), 0, 1.0, None).unwrap_err(),
            SequenceError::Frames(0)
        );
        assert!(matches!(
            Sequence::new(b.clone(), 2, f64::NAN, None),
            Err(SequenceError::TimeStep(_))
        ));
        assert!(matches!(
            Sequence::new(b.clone(), 2, 1e12, None),
            Err(SequenceError::TimeStep(_))
        ));
        let mut bad = b;
        bad.observer.lat_deg = 95.0;
        match Sequence::new(bad, 2, 1.0, None) {
            Err(SequenceError::Scene(e)) => assert_eq!(e.field, "observer.lat_deg"),
            other => panic!("{other:?}"),
        }
    }
}
