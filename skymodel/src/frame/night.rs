//! The night passes' frame (Milky Way / night-sky light, stars, planets):
//! the exposure the camera will use, the extinction table, the diffuse
//! night background, the point sources above the horizon, and the culling
//! that decides before rendering whether each pass can show at that
//! exposure ([`crate::night`] states the criterion).
//!
//! The metering and the Milky Way culling look at a sub-sampled grid of
//! the image's own view directions (every [`SAMPLE_STEP`]th pixel each way,
//! [`PixelDirections::dir`]): the sky radiance there comes from the frame's
//! [`SkyLight`], whichever backend computed it.

use glam::Vec3;

use crate::atmosphere::AtmosphereLuts;
use crate::frame::pixels::PixelDirections;
use crate::frame::sky_light::SkyLight;
use crate::milkyway::NightBackground;
use crate::night::{cull_diffuse, cull_points, estimate_ev100, white_luminance};
use crate::plan::Culled;
use crate::projection::Camera;
use crate::scene::{Effect, Scene};
use crate::spectrum::luminance;
use crate::stars::{
    catalogue, splat_plan, star_source, Extinction, PointSource, Psf, SplatPlan, SplatScratch,
};
use crate::state::SkyState;

/// Sub-sampling step (pixels, each direction) of the exposure and Milky Way
/// culling estimates.
pub const SAMPLE_STEP: usize = 16;

/// A point source's light after extinction and its image position
/// ([`NightFrame::place`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placed {
    /// Colour after extinction, linear sRGB per lux.
    pub rgb: [f32; 3],
    /// Its luminance (the extinction's luminance factor).
    pub y: f32,
    /// Continuous image position, px.
    pub pos: (f64, f64),
}

/// Per-frame state shared by the night passes.
#[derive(Debug, Clone)]
pub struct NightFrame {
    /// The EV100 the camera uses (fixed, or estimated for `auto`).
    pub ev100: f64,
    /// Extinction towards each altitude (none without the atmosphere).
    pub extinction: Extinction,
    /// The diffuse night sky (Milky Way map, zodiacal light, airglow).
    pub background: NightBackground,
    /// The passes culled at this exposure, with their reasons.
    pub culled: Vec<(Effect, Culled)>,
    /// The stars above the horizon (scintillation applied), brightest
    /// first, when the stars pass runs.
    pub stars: Vec<PointSource>,
    /// The planets above the horizon, when the planets pass runs.
    pub planets: Vec<PointSource>,
}

impl NightFrame {
    /// Prepares the night passes of `state` and decides which are
    /// invisible. `luts` are the atmosphere LUTs when the atmosphere pass
    /// runs (their transmittance from radius `r0` extincts everything
    /// behind it), `sky` its per-frame sky radiance.
    pub fn prepare(
        scene: &Scene,
        state: &SkyState,
        luts: Option<&AtmosphereLuts>,
        r0: f32,
        sky: Option<&SkyLight>,
    ) -> NightFrame {
        let cam = &scene.camera;
        let extinction = match luts {
            Some(l) => Extinction::from_transmittance(|mu| l.sun_transmittance(r0, mu)),
            None => Extinction::none(),
        };
        let background = NightBackground::new(state.night.star_frame.icrs_to_enu);
        let mw = state.runs(Effect::Milkyway);
        let sky_at = |d: Vec3| sky.map_or([0.0; 3], |s| s.radiance(d));
        let night_light = |d: Vec3| {
            if !mw || d.z < 0.0 {
                return [0.0; 3];
            }
            let l = background.radiance(d);
            let t = extinction.rgb(d);
            [l[0] * t[0], l[1] * t[1], l[2] * t[2]]
        };
        // Sub-sampled view directions: the metering estimate and the Milky
        // Way culling.
        let dirs = PixelDirections::new(cam);
        let (w, h) = dirs.size();
        let mut samples = Vec::new();
        let mut pairs = Vec::new();
        let off = SAMPLE_STEP / 2;
        for y in (off.min(h - 1)..h).step_by(SAMPLE_STEP) {
            for x in (off.min(w - 1)..w).step_by(SAMPLE_STEP) {
                let Some(d) = dirs.dir(x, y) else { continue };
                let s = sky_at(d);
                let n = night_light(d);
                samples.push([s[0] + n[0], s[1] + n[1], s[2] + n[2]]);
                if d.z >= 0.0 {
                    pairs.push((luminance(s), luminance(n)));
                }
            }
        }
        let ev100 = estimate_ev100(scene.exposure, &samples);
        let background_y = |d: Vec3| luminance(sky_at(d)) + luminance(night_light(d));
        let core = scene.stars.core_px as f32;
        let mut culled = Vec::new();
        if state.runs(Effect::Milkyway) {
            if let Some(r) = cull_diffuse(&pairs, ev100) {
                culled.push((Effect::Milkyway, r));
            }
        }
        let mut stars = Vec::new();
        if state.runs(Effect::Stars) {
            let all = state.night.stars(scene);
            match cull_points("star", all, cam, core, &extinction, background_y, ev100) {
                Some(r) => culled.push((Effect::Stars, r)),
                None => stars = star_sources(scene, state),
            }
        }
        let mut planets = Vec::new();
        if state.runs(Effect::Planets) {
            let mut up = planet_sources(state);
            up.sort_by(|a, b| b.lux.total_cmp(&a.lux));
            let c = cull_points(
                "planet",
                up.iter().copied(),
                cam,
                core,
                &extinction,
                background_y,
                ev100,
            );
            match c {
                Some(r) => culled.push((Effect::Planets, r)),
                None => planets = planet_sources(state),
            }
        }
        NightFrame {
            ev100,
            extinction,
            background,
            culled,
            stars,
            planets,
        }
    }

    /// Why the pass of `e` is culled, if it is.
    pub fn reason(&self, e: Effect) -> Option<&Culled> {
        self.culled.iter().find(|(f, _)| *f == e).map(|(_, r)| r)
    }

    /// The point-spread function at this frame's exposure.
    pub fn psf(&self, scene: &Scene) -> Psf {
        Psf {
            core_px: scene.stars.core_px as f32,
            glare: scene.stars.glare as f32,
            white_cd_m2: white_luminance(self.ev100),
        }
    }

    /// A source's colour after extinction, its luminance factor and its
    /// image position, or `None` when it is extinguished or lies more than
    /// 64 px (the largest footprint reach) outside the image.
    pub fn place(&self, cam: &Camera, s: &PointSource) -> Option<Placed> {
        let t = self.extinction.rgb(s.dir);
        let c = [s.rgb[0] * t[0], s.rgb[1] * t[1], s.rgb[2] * t[2]];
        let y = luminance(c);
        let (cx, cy) = cam.dir_to_pixel(s.dir.as_dvec3())?;
        let (w, h) = cam.image_size();
        let (fw, fh) = (w as f64, h as f64);
        let margin = 64.0;
        if y <= 0.0
            || !(-margin..fw + margin).contains(&cx)
            || !(-margin..fh + margin).contains(&cy)
        {
            return None;
        }
        Some(Placed {
            rgb: c,
            y,
            pos: (cx, cy),
        })
    }

    /// The footprints the point passes deposit, for a backend that
    /// evaluates them per pixel: each source's [`SplatPlan`] (extinction
    /// applied) and its colour (luminance 1).
    pub fn splat_plans(
        &self,
        scene: &Scene,
        sources: &[PointSource],
    ) -> Vec<(SplatPlan, [f32; 3])> {
        use rayon::prelude::*;
        let psf = self.psf(scene);
        let cam = &scene.camera;
        sources
            .par_iter()
            .with_min_len(256)
            .map_init(SplatScratch::default, |scratch, s| {
                let p = self.place(cam, s)?;
                let plan = splat_plan(cam, p.pos, s.dir.z, s.lux * p.y, &psf, scratch)?;
                Some((plan, [p.rgb[0] / p.y, p.rgb[1] / p.y, p.rgb[2] / p.y]))
            })
            .flatten()
            .collect()
    }
}

/// The sources of the stars pass: every catalogue star to
/// `scene.stars.limit_mag` above the horizon (with scintillation).
pub fn star_sources(scene: &Scene, state: &SkyState) -> Vec<PointSource> {
    use rayon::prelude::*;
    let night = &state.night;
    catalogue(scene.stars.limit_mag)
        .par_iter()
        .with_min_len(512)
        .filter_map(|s| star_source(&night.star_frame, s, night.scintillation.as_ref()))
        .collect()
}

/// The sources of the planets pass: Mercury–Saturn above the horizon.
pub fn planet_sources(state: &SkyState) -> Vec<PointSource> {
    state
        .night
        .planets
        .iter()
        .copied()
        .filter(|p| p.dir.z >= 0.0)
        .collect()
}
