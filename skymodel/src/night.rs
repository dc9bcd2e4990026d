//! The night sky of one instant (star frame, planets, scintillation) and
//! the culling of the stars, planets and Milky Way passes.
//!
//! **Culling criterion.** A point source is visible when adding the peak
//! luminance of its PSF core to the sky background at its place changes the
//! displayed 8-bit value by at least half a code value, through the camera
//! model of [`crate::camera`] (exposure H = L / (1.2 · 2^EV100), ACES
//! filmic curve, sRGB encoding; night vision is ignored). A pass is culled
//! when none of its 32 brightest sources above the horizon is visible; the
//! Milky Way pass when the diffuse night light changes no sample of the
//! sky by half a code value.
//!
//! **Exposure before rendering.** A fixed EV100 is used as given. For
//! `exposure: auto` the metering of [`crate::camera::meter_ev100`] (the
//! geometric mean of the image's luminance) is estimated before rendering
//! from the renderer's sky-view radiance (plus the diffuse night light) at a
//! sub-sampled grid of the image's own view directions (every 16th pixel in
//! each direction); stars, planets and the Sun's disk change the geometric
//! mean by a negligible amount, so the estimate is the EV the metering picks.

use glam::Vec3;
use himmel_astro::stars::FrameRotation;
use himmel_astro::{Body, Observer, Sky};

use crate::camera::{aces_filmic, exposure_scale, meter_ev100, srgb_encode, Exposure};
use crate::plan::Culled;
use crate::projection::{enu_from_alt_az, Camera};
use crate::scene::{Effect, Scene};
use crate::stars::{
    colour_from_bv, core_peak_luminance, illuminance_lux, refracted, star_frame, star_source,
    Extinction, PointSource, Scintillation, PLANET_BV,
};

/// The night-sky part of the sky state.
#[derive(Debug, Clone, PartialEq)]
pub struct NightSky {
    /// ICRS → ENU rotation (with aberration) of the catalogue stars.
    pub star_frame: FrameRotation,
    /// Mercury–Saturn (when the scene asks for planets), refracted, with
    /// their magnitudes (Meeus ch. 41) and colours; below-horizon ones included.
    pub planets: Vec<PointSource>,
    /// The scintillation pattern of this instant, when enabled.
    pub scintillation: Option<Scintillation>,
}

impl NightSky {
    /// The night sky of `sky`'s instant for `observer`.
    pub fn new(
        scene: &Scene,
        sky: &Sky,
        observer: &Observer,
    ) -> Result<NightSky, himmel_astro::AstroError> {
        let mut planets = Vec::new();
        if scene.wants(Effect::Planets) {
            for (i, body) in [
                Body::Mercury,
                Body::Venus,
                Body::Mars,
                Body::Jupiter,
                Body::Saturn,
            ]
            .into_iter()
            .enumerate()
            {
                let topo = sky.topocentric(body, observer)?;
                let mag = sky.planet_magnitude(body)?;
                let enu = refracted(enu_from_alt_az(topo.alt, topo.az));
                planets.push(PointSource {
                    dir: enu.as_vec3(),
                    lux: illuminance_lux(mag) as f32,
                    rgb: colour_from_bv(PLANET_BV[i]),
                    id: i as u32 + 1,
                });
            }
        }
        let jd = sky.epoch().instant.jd_tt;
        Ok(NightSky {
            star_frame: star_frame(sky.epoch(), observer),
            planets,
            scintillation: scene.stars.scintillation.then(|| Scintillation {
                seed: scene.stars.seed,
                step: (jd * 864_000.0).floor() as i64,
            }),
        })
    }

    /// The catalogue stars above the horizon for `scene`, in catalogue
    /// order (brightest first).
    pub fn stars(&self, scene: &Scene) -> impl Iterator<Item = PointSource> + '_ {
        let cat = crate::stars::catalogue(scene.stars.limit_mag);
        cat.iter()
            .filter_map(move |s| star_source(&self.star_frame, s, self.scintillation.as_ref()))
    }
}

/// The 8-bit display value (0–255, continuous) of luminance `l` (cd/m²) at
/// `ev100` through exposure, the ACES curve and sRGB encoding.
pub fn display_code(l: f32, ev100: f64) -> f32 {
    255.0 * srgb_encode(aces_filmic(l * exposure_scale(ev100)))
}

/// Whether adding `added` to `background` (luminances, cd/m²) changes the
/// display by at least half a code value at `ev100`.
pub fn visible_on_display(background: f32, added: f32, ev100: f64) -> bool {
    display_code(background + added, ev100) - display_code(background, ev100) >= 0.5
}

/// The luminance (cd/m²) the camera shows as white at `ev100`: the ACES
/// curve reaches 1 at exposed value 7.24 (0.08 x² − 0.56 x − 0.14 = 0).
pub fn white_luminance(ev100: f64) -> f32 {
    7.24 / exposure_scale(ev100)
}

/// The EV100 the camera will use: `exposure` if fixed, else the metering
/// of the luminance `samples` (see the module documentation).
pub fn estimate_ev100(exposure: Exposure, samples: &[[f32; 3]]) -> f64 {
    match exposure {
        Exposure::Ev100(v) => v,
        Exposure::Auto => meter_ev100(samples, &vec![true; samples.len()]),
    }
}

/// Number of the brightest sources the culling looks at.
pub const CULL_CANDIDATES: usize = 32;

/// Why a point-source pass (`what` = "star" or "planet") is invisible at
/// `ev100`, or `None` when one of its `CULL_CANDIDATES` brightest sources
/// inside the image (`sources`, brightest first, above the horizon) shows: peak core
/// luminance after extinction against `background(dir)` (luminance, cd/m²).
pub fn cull_points(
    what: &'static str,
    sources: impl Iterator<Item = PointSource>,
    cam: &Camera,
    core_px: f32,
    extinction: &Extinction,
    background: impl Fn(Vec3) -> f32,
    ev100: f64,
) -> Option<Culled> {
    let mut brightest_bg = None;
    let mut n = 0;
    for s in sources {
        if n == CULL_CANDIDATES {
            break;
        }
        let t = extinction.rgb(s.dir);
        let y = crate::spectrum::luminance([s.rgb[0] * t[0], s.rgb[1] * t[1], s.rgb[2] * t[2]]);
        let peak = core_peak_luminance(cam, s.dir, s.lux * y, core_px);
        if peak <= 0.0 {
            continue;
        }
        n += 1;
        let bg = background(s.dir);
        if visible_on_display(bg, peak, ev100) {
            return None;
        }
        brightest_bg.get_or_insert((peak, bg));
    }
    Some(match brightest_bg {
        None => Culled::NoSourceInView(what),
        Some((peak, background)) if display_code(background, ev100) >= 0.5 => {
            Culled::BackgroundBrighter {
                what,
                background,
                peak,
                ev100,
            }
        }
        Some((peak, _)) => Culled::BelowDisplayLevel { what, peak, ev100 },
    })
}

/// Why the Milky Way pass is invisible at `ev100`, or `None`: `samples`
/// holds (sky background, diffuse night light after extinction) luminance
/// pairs at directions above the horizon.
pub fn cull_diffuse(samples: &[(f32, f32)], ev100: f64) -> Option<Culled> {
    if samples.is_empty() {
        return Some(Culled::NoSkyInView);
    }
    if samples
        .iter()
        .any(|&(bg, add)| visible_on_display(bg, add, ev100))
    {
        return None;
    }
    let (bg, add) = samples
        .iter()
        .copied()
        .fold((f32::MAX, 0.0f32), |a, s| (a.0.min(s.0), a.1.max(s.1)));
    Some(if display_code(bg, ev100) >= 0.5 {
        Culled::DiffuseBackgroundBrighter {
            background: bg,
            night_light: add,
            ev100,
        }
    } else {
        Culled::DiffuseBelowDisplayLevel { ev100 }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_visibility_criterion() {
        // At EV100 −6 (the darkest auto exposure) Sirius-like 1 cd/m² on a
        // 2e-4 cd/m² night sky shows; on a 5000 cd/m² day sky at EV 14 it does not.
        assert!(visible_on_display(2e-4, 1.0, -6.0));
        assert!(!visible_on_display(5000.0, 1.0, 14.0));
        // White: the tone curve saturates at the white luminance.
        let w = white_luminance(0.0);
        assert!(display_code(w, 0.0) > 254.5);
        assert!(display_code(0.5 * w, 0.0) < 254.5);
        assert_eq!(estimate_ev100(Exposure::Ev100(3.0), &[]), 3.0);
        assert_eq!(estimate_ev100(Exposure::Auto, &[[1e-6; 3]; 4]), -6.0);
    }

    #[test]
    fn diffuse_culling_reasons() {
        assert!(cull_diffuse(&[(2e-4, 2e-4)], -6.0).is_none());
        let r = cull_diffuse(&[(5000.0, 2e-4)], 14.0).unwrap().to_string();
        assert!(r.starts_with("sky background brighter"), "{r}");
        let r = cull_diffuse(&[(0.0, 2e-4)], 14.0).unwrap().to_string();
        assert!(r.contains("below one display level"), "{r}");
    }
}
