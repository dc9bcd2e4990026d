//! The night passes of the CPU renderer: Milky Way / night-sky light, stars
//! and planets, with the culling that decides before rendering whether they
//! can show at the chosen exposure (physics in `himmel_skymodel::{stars,
//! milkyway, night}`).

use glam::Vec3;
use himmel_skymodel::atmosphere::AtmosphereLuts;

use crate::SkyLight;
use himmel_skymodel::milkyway::NightBackground;
use himmel_skymodel::night::{cull_diffuse, cull_points, estimate_ev100, white_luminance};
use himmel_skymodel::spectrum::luminance;
use himmel_skymodel::stars::{
    catalogue, splat_at, splat_plan, star_source, Extinction, PointSource, Psf, SplatPlan,
    SplatScratch,
};
use himmel_skymodel::{Effect, Scene, SkyState};
use rayon::prelude::*;

/// Sub-sampling step (pixels, each direction) of the exposure and Milky Way
/// culling estimates.
pub const SAMPLE_STEP: usize = 16;

/// A source ready to splat.
struct Prepared {
    pos: (f64, f64),
    dir_z: f32,
    lux: f32,
    rgb: [f32; 3],
    glare: bool,
}

impl Prepared {
    /// Splats the source into `pixels`, the image's rows from pixel
    /// `offset` on ([`splat_at`]).
    fn splat(
        &self,
        pixels: &mut [[f32; 3]],
        offset: usize,
        cam: &himmel_skymodel::Camera,
        psf: &Psf,
        scratch: &mut SplatScratch,
    ) {
        let (pos, z, rgb) = (self.pos, self.dir_z, self.rgb);
        splat_at(pixels, offset, cam, pos, z, self.lux, rgb, psf, scratch);
    }
}

/// Per-frame state shared by the night passes.
pub struct NightFrame {
    /// The EV100 the camera uses (fixed, or estimated for `auto`).
    pub ev100: f64,
    extinction: Extinction,
    background: NightBackground,
    reasons: Vec<(Effect, String)>,
}

impl NightFrame {
    /// Prepares the night passes of `state` and decides which are
    /// invisible. `luts` are the atmosphere LUTs when the atmosphere pass
    /// runs (their transmittance extincts everything behind it), `sky_view`
    /// its per-frame sky radiance, `dirs` the pixel directions.
    pub fn prepare(
        scene: &Scene,
        state: &SkyState,
        luts: Option<&AtmosphereLuts>,
        sky_view: Option<&SkyLight>,
        dirs: &[Option<Vec3>],
    ) -> NightFrame {
        let cam = &scene.camera;
        let (w, h) = cam.image_size();
        let (w, h) = (w as usize, h as usize);
        let extinction = match luts {
            Some(l) => {
                let r0 = l.medium.bottom + state.observer_altitude_km as f32;
                Extinction::from_transmittance(|mu| l.sun_transmittance(r0, mu))
            }
            None => Extinction::none(),
        };
        let background = NightBackground::new(state.night.star_frame.icrs_to_enu);
        let mw = state.runs(Effect::Milkyway);
        let sky = |d: Vec3| sky_view.map_or([0.0; 3], |s| s.radiance(d));
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
        let mut samples = Vec::new();
        let mut pairs = Vec::new();
        let off = SAMPLE_STEP / 2;
        for y in (off.min(h - 1)..h).step_by(SAMPLE_STEP) {
            for x in (off.min(w - 1)..w).step_by(SAMPLE_STEP) {
                let Some(d) = dirs[y * w + x] else { continue };
                let s = sky(d);
                let n = night_light(d);
                samples.push([s[0] + n[0], s[1] + n[1], s[2] + n[2]]);
                if d.z >= 0.0 {
                    pairs.push((luminance(s), luminance(n)));
                }
            }
        }
        let ev100 = estimate_ev100(scene.exposure, &samples);
        let background_y = |d: Vec3| luminance(sky(d)) + luminance(night_light(d));
        let core = scene.stars.core_px as f32;
        let mut reasons = Vec::new();
        if state.runs(Effect::Milkyway) {
            if let Some(r) = cull_diffuse(&pairs, ev100) {
                reasons.push((Effect::Milkyway, r));
            }
        }
        if state.runs(Effect::Stars) {
            let stars = state.night.stars(scene);
            if let Some(r) = cull_points("star", stars, cam, core, &extinction, background_y, ev100)
            {
                reasons.push((Effect::Stars, r));
            }
        }
        if state.runs(Effect::Planets) {
            let mut planets: Vec<PointSource> = state
                .night
                .planets
                .iter()
                .copied()
                .filter(|p| p.dir.z >= 0.0)
                .collect();
            planets.sort_by(|a, b| b.lux.total_cmp(&a.lux));
            if let Some(r) = cull_points(
                "planet",
                planets.into_iter(),
                cam,
                core,
                &extinction,
                background_y,
                ev100,
            ) {
                reasons.push((Effect::Planets, r));
            }
        }
        NightFrame {
            ev100,
            extinction,
            background,
            reasons,
        }
    }

    /// Why the pass of `e` is culled, if it is.
    pub fn reason(&self, e: Effect) -> Option<&str> {
        self.reasons
            .iter()
            .find(|(f, _)| *f == e)
            .map(|(_, r)| r.as_str())
    }

    fn psf(&self, scene: &Scene) -> Psf {
        Psf {
            core_px: scene.stars.core_px as f32,
            glare: scene.stars.glare as f32,
            white_cd_m2: white_luminance(self.ev100),
        }
    }

    /// A source's colour after extinction, its luminance factor and its
    /// image position, or None when it is extinguished or lies more than
    /// 64 px (the largest footprint reach) outside the image.
    fn place(
        &self,
        cam: &himmel_skymodel::Camera,
        s: &PointSource,
    ) -> Option<([f32; 3], f32, (f64, f64))> {
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
        Some((c, y, (cx, cy)))
    }

    /// Splats `sources` (extinction applied here) into `pixels`: sources
    /// whose core may overflow into a glare disk one after the other over
    /// the whole image, the rest in parallel over bands of rows (each band
    /// takes the sources whose core footprint reaches it and writes only its
    /// own rows; the footprint and its normalisation are the whole image's,
    /// so the result is the same as a serial splat).
    fn splat_all(&self, pixels: &mut [[f32; 3]], scene: &Scene, sources: &[PointSource]) {
        let psf = self.psf(scene);
        let cam = &scene.camera;
        let (w, h) = cam.image_size();
        let (w, h) = (w as usize, h as usize);
        // Upper bound of the core's peak weight (see `core_peak_luminance`).
        let sigma = psf.core_px.max(0.1);
        let w0 = (1.0 / (2.0 * std::f32::consts::PI * sigma * sigma)).min(1.0);
        // Extinction, colour and image position of each source, in parallel.
        let mut prepared: Vec<Prepared> = sources
            .par_iter()
            .with_min_len(256)
            .filter_map(|s| {
                let (c, y, (cx, cy)) = self.place(cam, s)?;
                let lux = s.lux * y;
                // Glare candidates: a core peak within 2× of white (the
                // splat decides exactly).
                let glare = psf.glare > 0.0 && {
                    let omega = cam.pixel_solid_angle(cx.floor() + 0.5, cy.floor() + 0.5) as f32;
                    lux * w0 * 2.0 >= psf.white_cd_m2 * omega
                };
                Some(Prepared {
                    pos: (cx, cy),
                    dir_z: s.dir.z,
                    lux,
                    rgb: [c[0] / y, c[1] / y, c[2] / y],
                    glare,
                })
            })
            .collect();
        prepared.sort_by(|a, b| a.pos.1.total_cmp(&b.pos.1));
        let reach = (2.5 * psf.core_px).ceil() as f64 + 1.0;
        let bands = (rayon::current_num_threads() * 4).clamp(1, h.max(1));
        let rows = h.div_ceil(bands);
        pixels
            .par_chunks_mut(rows * w)
            .enumerate()
            .for_each(|(b, band)| {
                let (y0, y1) = ((b * rows) as f64, ((b + 1) * rows) as f64);
                let first = prepared.partition_point(|p| p.pos.1 < y0 - reach);
                let mut scratch = SplatScratch::default();
                for p in prepared[first..]
                    .iter()
                    .take_while(|p| p.pos.1 < y1 + reach)
                {
                    if !p.glare {
                        p.splat(band, b * rows * w, cam, &psf, &mut scratch);
                    }
                }
            });
        let mut scratch = SplatScratch::default();
        for p in prepared.iter().filter(|p| p.glare) {
            p.splat(pixels, 0, cam, &psf, &mut scratch);
        }
    }

    /// The footprints that [`Self::stars`] / [`Self::planets`] deposit, for
    /// a backend that evaluates them per pixel (`himmel-wgpu`): each
    /// source's [`SplatPlan`] (extinction applied) and its colour
    /// (luminance 1), for the sources that `splat_all` draws.
    pub fn splat_plans(
        &self,
        scene: &Scene,
        sources: &[PointSource],
    ) -> Vec<(SplatPlan, [f32; 3])> {
        let psf = self.psf(scene);
        let cam = &scene.camera;
        sources
            .par_iter()
            .with_min_len(256)
            .map_init(SplatScratch::default, |scratch, s| {
                let (c, y, (cx, cy)) = self.place(cam, s)?;
                let plan = splat_plan(cam, (cx, cy), s.dir.z, s.lux * y, &psf, scratch)?;
                Some((plan, [c[0] / y, c[1] / y, c[2] / y]))
            })
            .flatten()
            .collect()
    }

    /// The stars pass: every catalogue star above the horizon.
    pub fn stars(&self, pixels: &mut [[f32; 3]], scene: &Scene, state: &SkyState) {
        self.splat_all(pixels, scene, &star_sources(scene, state));
    }

    /// The planets pass: Mercury–Saturn above the horizon.
    pub fn planets(&self, pixels: &mut [[f32; 3]], scene: &Scene, state: &SkyState) {
        self.splat_all(pixels, scene, &planet_sources(state));
    }

    /// The Milky Way pass: the diffuse night sky, extinguished, above the horizon.
    pub fn milkyway(&self, pixels: &mut [[f32; 3]], dirs: &[Option<Vec3>]) {
        pixels
            .par_iter_mut()
            .zip(dirs.par_iter())
            .with_min_len(4096)
            .for_each(|(p, d)| {
                let Some(d) = *d else { return };
                if d.z < 0.0 {
                    return;
                }
                let l = self.background.radiance(d);
                let t = self.extinction.rgb(d);
                for k in 0..3 {
                    p[k] += l[k] * t[k];
                }
            });
    }
}

/// The sources of the stars pass: every catalogue star to
/// `scene.stars.limit_mag` above the horizon (with scintillation).
pub fn star_sources(scene: &Scene, state: &SkyState) -> Vec<PointSource> {
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
