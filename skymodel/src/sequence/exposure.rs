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
//! Here the exposure curve is the lowest curve that lies at or above the
//! metered curve m and whose frame-to-frame step is at most
//! R = `max_step_ev`:
//!
//! ```text
//!   EV_k = max_j (m_j − R·|k − j|)
//! ```
//!
//! (the upper R-Lipschitz envelope of m; a max of R-Lipschitz cones is
//! R-Lipschitz, so |EV_k − EV_{k+1}| ≤ R, and EV ≥ m with equality at m's
//! local maxima). A higher EV is a darker image, so **no frame is exposed
//! brighter than its own meter**: the day keeps its metered exposure and
//! its highlights, while a change too fast to follow (a 30-minute-step
//! twilight drops ~20 EV in four frames) is ramped at R per frame *before*
//! the sky brightens and *after* it darkens — dusk and night get darker on
//! screen, as they do to an eye watching the film. No R-limited curve can
//! follow both a day and a night exactly: a 24 h lapse of N frames can
//! travel at most N·R EV in all, and the ~40 EV down and up again of a
//! clear day need 160 frames at R = 0.25. Where m is itself slower than R,
//! EV = m: the exposure is the metered one. The time constant is the rate:
//! a change of ΔEV takes ΔEV/R frames. The envelope is two linear sweeps
//! (a distance transform), so the curve costs O(N) for N frames.
//!
//! **What the rate cannot do.** R bounds how far the exposure travels:
//! a 24 h lapse at 10-minute steps has a day metered at EV ≈ 15 and a
//! night at ≈ −5 (June, 48° N, the Moon up); 20 EV take 67 frames at
//! R = 0.3 and 80 at 0.25, but the night lasts ~30 frames and dusk drops
//! 17 EV in 12. Every R-limited curve then errs by many EV somewhere: this
//! one keeps the day exact and leaves the night 10–15 EV darker than its
//! meter (black frames; measured in the README, "How far the night
//! lags"); the curve closest to the meter in the worst frame (the mean of
//! this upper envelope and the lower one, min_j (m_j + R·|k − j|)) would
//! over-expose the morning by 6 EV and still leave the night ~6 EV dark.
//! Finer time steps or a larger R are the remedies.
//!
//! The metered curve must be known before the frames are written: the
//! command line meters a small preview of every frame first (the same
//! renderer and precomputed LUTs, a 48 × 27 sky view).

pub use crate::scene::DEFAULT_EXPOSURE_MAX_STEP_EV;

/// The exposure curve of a sequence (EV100 per frame) from its metered
/// EV100s: the lowest curve at or above them whose steps are at most
/// `max_step_ev` (see the module documentation; a negative step counts as
/// zero: the constant curve at the brightest meter).
pub fn smooth_ev100(metered: &[f64], max_step_ev: f64) -> Vec<f64> {
    let r = max_step_ev.max(0.0);
    let mut ev = metered.to_vec();
    for k in 1..ev.len() {
        ev[k] = ev[k].max(ev[k - 1] - r);
    }
    for k in (1..ev.len()).rev() {
        ev[k - 1] = ev[k - 1].max(ev[k] - r);
    }
    ev
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The envelope by brute force, O(N²), straight from the definition.
    fn reference(m: &[f64], r: f64) -> Vec<f64> {
        (0..m.len())
            .map(|k| {
                (0..m.len())
                    .map(|j| m[j] - r * (k as f64 - j as f64).abs())
                    .fold(f64::MIN, f64::max)
            })
            .collect()
    }

    #[test]
    fn matches_the_brute_force_envelope_and_never_exposes_brighter() {
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
        assert!(fast.iter().zip(&m).all(|(e, m)| e >= m));
        // The day's brightest meter is kept exactly.
        let top = m.iter().cloned().fold(f64::MIN, f64::max);
        assert!(fast.contains(&top));
    }

    #[test]
    fn slow_changes_are_followed_exactly() {
        let m: Vec<f64> = (0..20).map(|k| 3.0 + 0.1 * k as f64).collect();
        assert_eq!(smooth_ev100(&m, 0.25), m);
        assert_eq!(smooth_ev100(&[7.5], 0.25), vec![7.5]);
        assert!(smooth_ev100(&[], 0.25).is_empty());
    }

    #[test]
    fn a_step_up_is_anticipated_and_a_step_down_followed() {
        // 0 → 4 EV at frame 10 and back to 0 at frame 20, R = 0.5: the
        // exposure rises over the 8 frames before the first step and falls
        // over the 8 frames after the second.
        let m: Vec<f64> = (0..30)
            .map(|k| if (10..20).contains(&k) { 4.0 } else { 0.0 })
            .collect();
        let ev = smooth_ev100(&m, 0.5);
        assert_eq!((ev[1], ev[2], ev[6], ev[9]), (0.0, 0.0, 2.0, 3.5));
        assert_eq!((ev[10], ev[19]), (4.0, 4.0));
        assert_eq!((ev[20], ev[23], ev[27], ev[28]), (3.5, 2.0, 0.0, 0.0));
    }
}
