//! Exposure over a sequence: the automatic exposure of a time-lapse or an
//! animation follows the metered EV100 of its frames, but changes by at
//! most `max_step_ev` per frame, so that the film does not flicker or jump.
//!
//! A single frame's camera meters each image on its own
//! ([`crate::camera::meter_ev100`]). Over a sequence that would jump by
//! several EV between two frames of a twilight at 30-minute steps: the sky
//! darkens by ~20 EV between sunset and astronomical night. A time-lapse
//! photographer ramps the exposure instead ("bulb ramping", or the
//! deflicker pass of time-lapse software): the exposure changes smoothly,
//! by a fraction of a stop per frame, and starts before the light changes.
//!
//! Here the exposure curve is the one closest to the metered curve m
//! (smallest maximum deviation) among all curves whose frame-to-frame step
//! is at most R = `max_step_ev`:
//!
//! ```text
//!   U_k = min_j (m_j + R·|k − j|)     the lowest R-Lipschitz curve above m
//!   L_k = max_j (m_j − R·|k − j|)     the highest R-Lipschitz curve below m
//!   EV_k = (U_k + L_k) / 2
//! ```
//!
//! U and L are R-Lipschitz, so their mean is too (|EV_k − EV_{k+1}| ≤ R),
//! and L ≤ m ≤ U bounds the deviation by (U − L)/2, which no R-limited curve
//! can beat (the minimax fit). Where m is itself slower than R, U = L = m:
//! the exposure is the metered one. The time constant is the rate: an
//! isolated jump of ΔEV is ramped over 2·ΔEV/R frames centred on it (R/2
//! per frame, half the frames before the jump); light that changes at R per
//! frame or slower is followed exactly. U and L
//! are each two linear sweeps (a distance transform), so the curve costs
//! O(N) for N frames.
//!
//! The metered curve must be known before the frames are written: the
//! command line meters a small preview of every frame first (the same
//! renderer, LUTs reused).

pub use crate::scene::DEFAULT_EXPOSURE_MAX_STEP_EV;

/// The exposure curve of a sequence (EV100 per frame) from its metered
/// EV100s: the minimax fit whose steps are at most `max_step_ev` (see the
/// module documentation). `max_step_ev` must be positive (a zero or
/// negative step gives the constant mid-range curve).
pub fn smooth_ev100(metered: &[f64], max_step_ev: f64) -> Vec<f64> {
    let r = max_step_ev.max(0.0);
    let n = metered.len();
    let mut upper = metered.to_vec();
    let mut lower = metered.to_vec();
    for k in 1..n {
        upper[k] = upper[k].min(upper[k - 1] + r);
        lower[k] = lower[k].max(lower[k - 1] - r);
    }
    for k in (0..n.saturating_sub(1)).rev() {
        upper[k] = upper[k].min(upper[k + 1] + r);
        lower[k] = lower[k].max(lower[k + 1] - r);
    }
    upper
        .iter()
        .zip(&lower)
        .map(|(u, l)| 0.5 * (u + l))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The brute-force envelopes, O(N²), straight from the definition.
    fn reference(m: &[f64], r: f64) -> Vec<f64> {
        (0..m.len())
            .map(|k| {
                let d = |j: usize| r * (k as f64 - j as f64).abs();
                let u = (0..m.len()).map(|j| m[j] + d(j)).fold(f64::MAX, f64::min);
                let l = (0..m.len()).map(|j| m[j] - d(j)).fold(f64::MIN, f64::max);
                0.5 * (u + l)
            })
            .collect()
    }

    #[test]
    fn matches_the_brute_force_envelopes() {
        // A day: night at −6, a 20 EV jump at dawn and dusk, noise.
        let m: Vec<f64> = (0..48)
            .map(|k| {
                let base = if (12..36).contains(&k) { 14.0 } else { -6.0 };
                base + 0.3 * ((k * 7 % 5) as f64 - 2.0)
            })
            .collect();
        let fast = smooth_ev100(&m, 0.25);
        for (a, b) in fast.iter().zip(reference(&m, 0.25)) {
            assert!((a - b).abs() < 1e-12, "{a} {b}");
        }
        for w in fast.windows(2) {
            assert!((w[1] - w[0]).abs() <= 0.25 + 1e-12);
        }
    }

    #[test]
    fn slow_changes_are_followed_exactly() {
        let m: Vec<f64> = (0..20).map(|k| 3.0 + 0.1 * k as f64).collect();
        assert_eq!(smooth_ev100(&m, 0.25), m);
        assert_eq!(smooth_ev100(&[7.5], 0.25), vec![7.5]);
        assert!(smooth_ev100(&[], 0.25).is_empty());
    }

    #[test]
    fn a_step_is_ramped_symmetrically_around_it() {
        // 0 then 4 EV from frame 10: the ramp spans 2·4/0.5 = 16 frames
        // (2 to 17) at 0.25 EV per frame, centred on the step, and the
        // deviation is at most half the step.
        let m: Vec<f64> = (0..20).map(|k| if k < 10 { 0.0 } else { 4.0 }).collect();
        let ev = smooth_ev100(&m, 0.5);
        assert!((ev[9] - 1.75).abs() < 1e-12 && (ev[10] - 2.25).abs() < 1e-12);
        assert!((ev[5] - 0.75).abs() < 1e-12);
        assert_eq!((ev[1], ev[2]), (0.0, 0.0));
        assert_eq!((ev[17], ev[18]), (4.0, 4.0));
        let worst = ev
            .iter()
            .zip(&m)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(worst <= 2.0);
    }
}
