//! Culling the night passes under an overcast sky: when the cloud layers
//! hide every direction of the view above the horizon, the stars, planets
//! and Milky Way passes do not run ([`SkipReason::Overcast`]).
//!
//! The test samples the camera's own pixel directions on a grid (about
//! [`OVERCAST_SAMPLES`] along the image's longer side, and its last row
//! and column) and marches each through both layers as the clouds pass
//! does ([`optical_depth_low`] with the layer's `steps`, the high sheet's
//! e^{−τ/μ}). The sky is overcast when every sample above the horizon
//! keeps at most [`OVERCAST_TRANSMITTANCE`] of the light behind it: 10⁻⁵
//! is 12.5 magnitudes, which leaves Venus at its brightest (−4.6) fainter
//! than 7.9 and the Milky Way's brightest clouds 10⁵ times below the
//! darkest night sky. The first sample that lets more through ends the
//! test, so a sky with a gap costs little; an overcast one costs one march
//! per sample (about 2 300 at 16:9). A gap narrower than the grid's
//! spacing in every direction goes unseen; the layers' noise has no
//! features below an eighth of `scale_km`.
//!
//! The Moon's pass keeps running: 12.5 magnitudes leave the full Moon at
//! about −0.2, and its light through the cloud is the clouds pass's.

use glam::Vec3;

use super::clouds::{EARTH_RADIUS_KM, J2000_TT};
use super::pixels::PixelDirections;
use crate::atmosphere::AtmosphereLuts;
use crate::clouds::{optical_depth_low, shade_high, HighField, LowField, Shell};
use crate::scene::Scene;
use crate::state::SkyState;

/// Largest transmittance of the layers in every sampled direction for
/// which the sky counts as overcast.
pub const OVERCAST_TRANSMITTANCE: f32 = 1e-5;
/// Samples along the image's longer side.
pub const OVERCAST_SAMPLES: usize = 64;

/// The grid's coordinates along an axis of `n` pixels: every `step`-th
/// and the last.
fn axis(n: usize, step: usize) -> impl Iterator<Item = usize> {
    let last = n.checked_sub(1);
    (0..n)
        .step_by(step.max(1))
        .chain(last.filter(|l| l % step.max(1) != 0))
}

/// The largest transmittance of `scene`'s cloud layers over the sampled
/// directions of its view above the horizon, when it is at most
/// [`OVERCAST_TRANSMITTANCE`] (the sky is overcast); `None` when some
/// direction sees through, when there is no layer, or when no sample lies
/// above the horizon.
pub fn overcast(scene: &Scene, state: &SkyState, luts: Option<&AtmosphereLuts>) -> Option<f32> {
    let c = &scene.clouds;
    if !c.has_low() && !c.has_high() {
        return None;
    }
    let seconds = (state.jd_tt - J2000_TT) * 86_400.0;
    let low = c.has_low().then(|| LowField::new(&c.low, seconds));
    let high = c.has_high().then(|| HighField::new(&c.high, seconds));
    let r_ground = luts.map_or(EARTH_RADIUS_KM, |l| l.medium.bottom);
    let shell = Shell {
        r_ground,
        r_observer: r_ground + state.observer_altitude_km as f32,
    };
    let transmittance = |v: Vec3| {
        let t_low = low.as_ref().map_or(1.0, |f| {
            (-optical_depth_low(f, &shell, v, c.low.steps)).exp()
        });
        let t_high = high.as_ref().map_or(1.0, |f| {
            shade_high(f, &shell, v, &[], [0.0; 3]).transmittance
        });
        t_low * t_high
    };
    let dirs = PixelDirections::new(&scene.camera);
    let (w, h) = dirs.size();
    let step = (w.max(h) / OVERCAST_SAMPLES).max(1);
    let mut worst: Option<f32> = None;
    for y in axis(h, step) {
        for x in axis(w, step) {
            let Some(v) = dirs.dir(x, y).filter(|v| v.z > 0.0) else {
                continue;
            };
            let t = transmittance(v);
            if t > OVERCAST_TRANSMITTANCE {
                return None;
            }
            worst = Some(worst.map_or(t, |w| w.max(t)));
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Effect, LowCloudKind};

    fn night(coverage: f64, extinction: f64) -> (Scene, SkyState) {
        let mut s = Scene::default();
        s.time.utc = "2024-01-25T22:00:00Z".into();
        s.effects = vec![Effect::Stars, Effect::Clouds];
        s.camera.width = 96;
        s.camera.height = 96;
        s.clouds.low.coverage = coverage;
        s.clouds.low.kind = LowCloudKind::Stratus;
        s.clouds.low.extinction_per_km = extinction;
        let state = SkyState::at(&s).expect("state");
        (s, state)
    }

    #[test]
    fn axis_ends_on_the_last_pixel() {
        assert_eq!(axis(10, 4).collect::<Vec<_>>(), vec![0, 4, 8, 9]);
        assert_eq!(axis(9, 4).collect::<Vec<_>>(), vec![0, 4, 8]);
        assert_eq!(axis(0, 4).count(), 0);
    }

    /// A dense stratus deck hides the whole sky; broken or thin cloud does
    /// not; a clear scene is no overcast.
    #[test]
    fn a_dense_deck_is_overcast_and_broken_cloud_is_not() {
        let (s, state) = night(1.0, 200.0);
        let t = overcast(&s, &state, None).expect("overcast");
        assert!(t <= OVERCAST_TRANSMITTANCE, "{t}");
        let (s, state) = night(0.5, 200.0);
        assert_eq!(overcast(&s, &state, None), None);
        let (s, state) = night(1.0, 0.5);
        assert_eq!(overcast(&s, &state, None), None);
        let (s, state) = night(0.0, 200.0);
        assert_eq!(overcast(&s, &state, None), None);
    }
}
