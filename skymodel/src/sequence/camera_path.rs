//! A camera path: keyframes of the perspective camera's position and the
//! point it looks at, linearly interpolated between keyframes.
//!
//! JSON (`--camera-path FILE`), keyed by frame index:
//!
//! ```json
//! {"keyframes": [
//!   {"frame": 0,  "position_m": [0, 1.7, 0],  "look_at_m": [0, 1.7, -10]},
//!   {"frame": 47, "position_m": [5, 1.7, 0],  "look_at_m": [0, 1.7, -10]}
//! ]}
//! ```
//!
//! or keyed by scene time, `"time_s"`: seconds of scene time since the
//! sequence's first frame (t − t₀, negative when the sequence runs
//! backwards). All keyframes use the same key, in strictly increasing
//! order. Between two keyframes both points move linearly in the key;
//! before the first and after the last keyframe the camera holds still.
//! Positions are in the world frame (x East, y Up, z South), metres, each
//! component in [−1e6, 1e6] (the range of `camera.position_m`).

use serde::Deserialize;

use super::SequenceError;

/// One keyframe.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraKeyframe {
    /// Frame index of this keyframe (exclusive with `time_s`).
    #[serde(default)]
    pub frame: Option<u32>,
    /// Scene seconds since the first frame (exclusive with `frame`).
    #[serde(default)]
    pub time_s: Option<f64>,
    /// Camera position, world frame, metres.
    pub position_m: [f64; 3],
    /// The point looked at, world frame, metres.
    pub look_at_m: [f64; 3],
}

/// What the keyframes are keyed by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathKey {
    /// Frame index.
    Frame,
    /// Scene seconds since the first frame.
    Time,
}

/// A validated camera path.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraPath {
    /// The keyframes, strictly increasing in their key.
    pub keyframes: Vec<CameraKeyframe>,
}

/// A camera placement: position and the point looked at (world frame, m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Camera position.
    pub position_m: [f64; 3],
    /// The point looked at.
    pub look_at_m: [f64; 3],
}

fn path_err(field: impl Into<String>, message: impl Into<String>) -> SequenceError {
    SequenceError::CameraPath {
        field: field.into(),
        message: message.into(),
    }
}

fn lerp3(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * t)
}

impl CameraPath {
    /// Parses and validates a path. Errors name the field by its path
    /// (`keyframes[1].position_m`, `keyframes`) and say what is accepted.
    pub fn from_json(text: &str) -> Result<CameraPath, SequenceError> {
        if !text.trim_start().starts_with('{') {
            return Err(path_err(
                "camera path",
                "expected a JSON object {\"keyframes\": [...]}",
            ));
        }
        let de = &mut serde_json::Deserializer::from_str(text);
        let path: CameraPath = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
            let field = e.path().to_string();
            let field = match field.trim_end_matches('?').trim_end_matches('.') {
                "" | "." => "camera path".to_string(),
                f => f.to_string(),
            };
            path_err(field, e.inner().to_string())
        })?;
        de.end()
            .map_err(|e| path_err("camera path", e.to_string()))?;
        path.validate()?;
        Ok(path)
    }

    /// The key of the path (all keyframes share it).
    pub fn key(&self) -> PathKey {
        match self.keyframes.first() {
            Some(k) if k.time_s.is_some() => PathKey::Time,
            _ => PathKey::Frame,
        }
    }

    fn key_of(k: &CameraKeyframe) -> f64 {
        k.frame
            .map_or_else(|| k.time_s.unwrap_or(f64::NAN), f64::from)
    }

    /// Checks: at least one keyframe; each keyed by exactly one of `frame`
    /// and `time_s`, all by the same; keys finite and strictly increasing;
    /// coordinates finite within [−1e6, 1e6]; position ≠ look-at point.
    pub fn validate(&self) -> Result<(), SequenceError> {
        if self.keyframes.is_empty() {
            return Err(path_err("keyframes", "at least one keyframe is needed"));
        }
        let key = self.key();
        let mut prev = f64::NEG_INFINITY;
        for (i, k) in self.keyframes.iter().enumerate() {
            let at = |f: &str| format!("keyframes[{i}].{f}");
            match (k.frame, k.time_s, key) {
                (Some(_), None, PathKey::Frame) | (None, Some(_), PathKey::Time) => {}
                (None, None, _) => {
                    return Err(path_err(
                        format!("keyframes[{i}]"),
                        "needs \"frame\" (an index) or \"time_s\" (scene seconds since the first frame)",
                    ))
                }
                (Some(_), Some(_), _) => {
                    return Err(path_err(
                        format!("keyframes[{i}]"),
                        "has both \"frame\" and \"time_s\"; give one",
                    ))
                }
                _ => {
                    return Err(path_err(
                        format!("keyframes[{i}]"),
                        "all keyframes must use the same key as the first (\"frame\" or \"time_s\")",
                    ))
                }
            }
            let v = Self::key_of(k);
            let name = if key == PathKey::Frame {
                "frame"
            } else {
                "time_s"
            };
            if !v.is_finite() {
                return Err(path_err(at(name), format!("{v} is not a finite number")));
            }
            if v <= prev {
                return Err(path_err(
                    at(name),
                    format!(
                        "{v} does not increase (keyframes must be in strictly increasing order)"
                    ),
                ));
            }
            prev = v;
            for (f, p) in [("position_m", k.position_m), ("look_at_m", k.look_at_m)] {
                if p.iter().any(|c| !(c.is_finite() && c.abs() <= 1e6)) {
                    return Err(path_err(
                        at(f),
                        format!("{p:?}: each component must be a finite number in [-1e6, 1e6] m"),
                    ));
                }
            }
            if k.position_m == k.look_at_m {
                return Err(path_err(
                    at("look_at_m"),
                    "equals position_m; the camera must look at another point",
                ));
            }
        }
        Ok(())
    }

    /// The placement at frame `index`, `elapsed_s` scene seconds after the
    /// first frame: linear between the keyframes around the key, held
    /// before the first and after the last.
    pub fn at(&self, index: u32, elapsed_s: f64) -> Placement {
        let x = match self.key() {
            PathKey::Frame => f64::from(index),
            PathKey::Time => elapsed_s,
        };
        let ks = &self.keyframes;
        let place = |k: &CameraKeyframe| Placement {
            position_m: k.position_m,
            look_at_m: k.look_at_m,
        };
        let (Some(first), Some(last)) = (ks.first(), ks.last()) else {
            return Placement {
                position_m: crate::projection::DEFAULT_EYE_M,
                look_at_m: [0.0, 1.7, -1.0],
            };
        };
        if x <= Self::key_of(first) {
            return place(first);
        }
        if x >= Self::key_of(last) {
            return place(last);
        }
        // The segment [a, b] with key(a) ≤ x < key(b).
        let j = ks.partition_point(|k| Self::key_of(k) <= x);
        let (a, b) = (&ks[j - 1], &ks[j]);
        let (ka, kb) = (Self::key_of(a), Self::key_of(b));
        let t = (x - ka) / (kb - ka);
        Placement {
            position_m: lerp3(a.position_m, b.position_m, t),
            look_at_m: lerp3(a.look_at_m, b.look_at_m, t),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FRAMES: &str = r#"{"keyframes": [
        {"frame": 0, "position_m": [0, 1.7, 0], "look_at_m": [0, 1.7, -10]},
        {"frame": 10, "position_m": [10, 1.7, 0], "look_at_m": [0, 11.7, -10]},
        {"frame": 20, "position_m": [10, 1.7, -20], "look_at_m": [0, 11.7, -10]}
    ]}"#;

    #[test]
    fn exact_at_keyframes_and_midpoints() {
        let p = CameraPath::from_json(FRAMES).unwrap();
        assert_eq!(p.key(), PathKey::Frame);
        for k in &p.keyframes {
            let at = p.at(k.frame.unwrap(), 0.0);
            assert_eq!((at.position_m, at.look_at_m), (k.position_m, k.look_at_m));
        }
        let mid = p.at(5, 0.0);
        assert_eq!(mid.position_m, [5.0, 1.7, 0.0]);
        assert_eq!(mid.look_at_m, [0.0, 6.7, -10.0]);
        let mid = p.at(15, 0.0);
        assert_eq!(mid.position_m, [10.0, 1.7, -10.0]);
        // Held outside the keyed range.
        assert_eq!(p.at(99, 0.0).position_m, [10.0, 1.7, -20.0]);
    }

    #[test]
    fn keyed_by_time_including_backwards_sequences() {
        let p = CameraPath::from_json(
            r#"{"keyframes": [
                {"time_s": -3600, "position_m": [-4, 2, 0], "look_at_m": [0, 2, -10]},
                {"time_s": 0, "position_m": [0, 2, 0], "look_at_m": [0, 2, -10]}
            ]}"#,
        )
        .unwrap();
        assert_eq!(p.key(), PathKey::Time);
        // The frame index is ignored; the elapsed scene time decides.
        assert_eq!(p.at(7, -1800.0).position_m, [-2.0, 2.0, 0.0]);
        assert_eq!(p.at(0, 0.0).position_m, [0.0, 2.0, 0.0]);
        assert_eq!(p.at(0, -7200.0).position_m, [-4.0, 2.0, 0.0]);
    }

    #[test]
    fn errors_name_the_field() {
        let cases = [
            (r#"{"keyframes": []}"#, "keyframes"),
            (
                r#"{"keyframes": [{"frame": 0, "position_m": [0, 1], "look_at_m": [0, 0, 1]}]}"#,
                "keyframes[0].position_m",
            ),
            (
                r#"{"keyframes": [{"frame": 0, "position_m": [0, 0, 0], "look_at_m": [0, 0, 1], "fov": 3}]}"#,
                "keyframes[0].fov",
            ),
            (
                r#"{"keyframes": [{"position_m": [0, 0, 0], "look_at_m": [0, 0, 1]}]}"#,
                "keyframes[0]",
            ),
            (
                r#"{"keyframes": [{"frame": 2, "position_m": [0, 0, 0], "look_at_m": [0, 0, 1]},
                               {"frame": 2, "position_m": [0, 0, 0], "look_at_m": [0, 0, 1]}]}"#,
                "keyframes[1].frame",
            ),
            (
                r#"{"keyframes": [{"frame": 0, "position_m": [0, 0, 0], "look_at_m": [0, 0, 1]},
                               {"time_s": 9, "position_m": [0, 0, 0], "look_at_m": [0, 0, 1]}]}"#,
                "keyframes[1]",
            ),
            (
                r#"{"keyframes": [{"frame": 0, "position_m": [0, 0, 0], "look_at_m": [0, 0, 0]}]}"#,
                "keyframes[0].look_at_m",
            ),
            (
                r#"{"keyframes": [{"frame": 0, "position_m": [0, 0, 2e6], "look_at_m": [0, 0, 0]}]}"#,
                "keyframes[0].position_m",
            ),
            (
                r#"{"keyframes": [{"frame": -1, "position_m": [0, 0, 0], "look_at_m": [0, 0, 1]}]}"#,
                "keyframes[0].frame",
            ),
            ("[1, 2]", "camera path"),
        ];
        for (text, field) in cases {
            match CameraPath::from_json(text) {
                Err(SequenceError::CameraPath { field: f, .. }) => assert_eq!(f, field, "{text}"),
                other => panic!("{text}: {other:?}"),
            }
        }
    }
}
