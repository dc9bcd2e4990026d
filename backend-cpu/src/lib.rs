//! `himmel-cpu`: the reference CPU renderer. It executes the frame plan of
//! `himmel-skymodel` ([`FramePlan`]) per pixel in Rust on all cores
//! (rayon); images are written through the `image` crate.
//!
//! * [`CpuRenderer`] — the [`SkyRenderer`] implementation: the LUT store
//!   (memory and disk cache, with a progress bar on a terminal), the
//!   per-pixel directions, then each planned pass back to front;
//! * [`sun_pass`], [`moon_pass`], [`night_pass`], [`cloud_pass`] — the passes that are more
//!   than a per-pixel lookup;
//! * [`output`] — EXR (linear, absolute cd/m²) and PNG (camera model) files;
//! * [`overlay`] — the constellation figures and labels drawn into a PNG.

pub mod cloud_pass;
pub mod moon_pass;
pub mod night_pass;
pub mod output;
pub mod overlay;
pub mod sun_pass;
pub mod texture_io;
pub mod texture_pass;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant as Clock;

use glam::Vec3;
use himmel_skymodel::atmosphere::{AtmosphereLuts, AtmosphereParams, LutConfig};
use himmel_skymodel::frame::{
    CpuSkyViews, FramePlan, LutOrigin, LutProgress, LutStore, PixelDirections, SkyLight,
};
use himmel_skymodel::renderer::{HdrImage, PassStat, RenderError, RenderOutput, SkyRenderer};
use himmel_skymodel::{Effect, Scene, SkyState};
use rayon::prelude::*;

pub use himmel_skymodel::frame::luts::default_cache_dir;

/// A terminal progress bar for the LUT precomputation (stderr, drawn
/// only when it is a terminal).
#[derive(Debug, Default)]
pub struct TerminalProgress(std::sync::Mutex<Option<indicatif::ProgressBar>>);

impl LutProgress for TerminalProgress {
    fn start(&self, total: usize) {
        let b = indicatif::ProgressBar::new(total as u64);
        b.set_message("atmosphere LUTs");
        *self.0.lock().unwrap_or_else(|e| e.into_inner()) = Some(b);
    }
    fn advance(&self) {
        if let Some(b) = &*self.0.lock().unwrap_or_else(|e| e.into_inner()) {
            b.inc(1);
        }
    }
    fn finish(&self) {
        if let Some(b) = self.0.lock().unwrap_or_else(|e| e.into_inner()).take() {
            b.finish_and_clear();
        }
    }
}

/// Computes the parameter-dependent LUTs on all cores, with a progress bar
/// on stderr when `progress` is set and stderr is a terminal.
pub fn precompute(params: &AtmosphereParams, config: &LutConfig, progress: bool) -> AtmosphereLuts {
    let bar = TerminalProgress::default();
    let p: Option<&dyn LutProgress> = if progress { Some(&bar) } else { None };
    himmel_skymodel::frame::luts::precompute(params, config, p)
}

/// The ENU direction of every pixel centre (`None` outside the
/// projection), row-major ([`PixelDirections::buffer`]).
pub fn directions(cam: &himmel_skymodel::Camera) -> Vec<Option<Vec3>> {
    PixelDirections::new(cam).buffer()
}

/// The sky light of `state` computed on all cores ([`CpuSkyViews`]).
pub fn sky_light(luts: &AtmosphereLuts, scene: &Scene, state: &SkyState) -> Option<SkyLight> {
    use himmel_skymodel::frame::SkyViewSource;
    let inputs = himmel_skymodel::frame::sky_inputs(scene, state);
    let views = CpuSkyViews.sky_views(luts, &inputs.list()).ok()?;
    SkyLight::from_views(&inputs, views)
}

/// The CPU renderer. Keeps the last LUTs in memory and, when a cache
/// directory is given, on disk ([`LutStore`]).
#[derive(Debug, Default)]
pub struct CpuRenderer {
    store: LutStore,
}

impl CpuRenderer {
    /// A renderer with the given disk cache (see [`default_cache_dir`]).
    pub fn new(cache_dir: Option<PathBuf>) -> Self {
        let mut store = LutStore::new(cache_dir);
        store.textures.set_loader(Arc::new(texture_io::ImageLoader));
        CpuRenderer { store }
    }

    /// Shows a progress bar on stderr (when it is a terminal) during a
    /// long LUT precomputation.
    pub fn set_progress(&mut self, on: bool) {
        let bar: Option<Arc<dyn LutProgress>> = if on {
            Some(Arc::new(TerminalProgress::default()))
        } else {
            None
        };
        self.store.set_progress(bar);
    }

    /// The LUTs for `params`/`config`, from memory, disk or computation,
    /// with their origin.
    pub fn luts(
        &mut self,
        params: &AtmosphereParams,
        config: &LutConfig,
    ) -> (Arc<AtmosphereLuts>, LutOrigin) {
        self.store.get(params, config)
    }

    /// The renderer's LUT store.
    pub fn lut_store(&mut self) -> &mut LutStore {
        &mut self.store
    }

    /// The frame plan of `scene` at `state` as this renderer makes it
    /// (sky views on the CPU).
    pub fn plan(&mut self, scene: &Scene, state: &SkyState) -> Result<FramePlan, RenderError> {
        FramePlan::prepare(scene, state, &mut self.store, &mut CpuSkyViews)
    }
}

fn ms(t: Clock) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Adds the sky's radiance to every pixel.
fn atmosphere_pass(pixels: &mut [[f32; 3]], dirs: &[Option<Vec3>], sky: &SkyLight) {
    pixels
        .par_iter_mut()
        .zip(dirs.par_iter())
        .for_each(|(p, d)| {
            if let Some(d) = d {
                let l = sky.radiance(*d);
                for k in 0..3 {
                    p[k] += l[k];
                }
            }
        });
}

impl SkyRenderer for CpuRenderer {
    fn name(&self) -> &'static str {
        "cpu"
    }

    fn render(&mut self, scene: &Scene, state: &SkyState) -> Result<RenderOutput, RenderError> {
        let mut plan = self.plan(scene, state)?;
        let cam = scene.camera;
        let (w, h) = cam.image_size();
        let (w, h) = (w as usize, h as usize);

        // Geometry: one direction per pixel centre.
        let tg = Clock::now();
        let dirs = PixelDirections::new(&cam).buffer();
        // The image buffer, written on all cores so that its pages are
        // mapped here and not by whichever pass touches them first (the
        // sparse star splats would otherwise pay for the page faults).
        let mut pixels: Vec<[f32; 3]> = (0..w * h).into_par_iter().map(|_| [0.0f32; 3]).collect();
        let geometry_ms = ms(tg);
        let valid: Vec<bool> = dirs.iter().map(Option::is_some).collect();
        let mut stats = Vec::new();
        let r0 = plan.observer_radius_km;
        for planned in plan.passes.clone() {
            if !planned.run {
                stats.push(PassStat {
                    name: planned.effect.name().into(),
                    ran: false,
                    ms: None,
                    reason: planned.reason.as_ref().map(ToString::to_string),
                });
                continue;
            }
            let t0 = Clock::now();
            let luts = plan.luts.clone();
            match planned.effect {
                Effect::Atmosphere => {
                    if let Some(sky) = plan.sky_light(&mut CpuSkyViews)? {
                        atmosphere_pass(&mut pixels, &dirs, sky);
                    }
                }
                Effect::Sun => {
                    if let Some(sun) = &plan.sun {
                        sun_pass::render(&mut pixels, &dirs, &cam, sun, luts.as_deref(), r0);
                    }
                    if let Some(c) = &plan.corona {
                        sun_pass::render_corona(&mut pixels, &dirs, c, luts.as_deref(), r0);
                    }
                }
                Effect::Moon => {
                    if let Some(m) = &plan.moon {
                        moon_pass::render(&mut pixels, &dirs, w, &cam, m);
                    }
                }
                Effect::Milkyway | Effect::Stars | Effect::Planets => {
                    if let Some(n) = &plan.night {
                        match planned.effect {
                            Effect::Milkyway => night_pass::milkyway(n, &mut pixels, &dirs),
                            Effect::Stars => night_pass::splat_all(n, &mut pixels, scene, &n.stars),
                            _ => night_pass::splat_all(n, &mut pixels, scene, &n.planets),
                        }
                    }
                }
                Effect::Texture => {
                    if let Some(t) = &plan.texture {
                        texture_pass::render(&mut pixels, &dirs, t);
                    }
                }
                Effect::Clouds => {
                    if let Some(c) = &plan.clouds {
                        cloud_pass::render(&mut pixels, &dirs, c);
                    }
                }
                other => return Err(RenderError::PassNotAvailable(other)),
            }
            stats.push(PassStat {
                name: planned.effect.name().into(),
                ran: true,
                ms: Some(ms(t0)),
                reason: None,
            });
        }
        stats.extend(PassStat::moon_eclipse(state));
        let lights = plan.observer_lights(scene, state, &mut CpuSkyViews)?;
        Ok(RenderOutput {
            image: HdrImage {
                width: w,
                height: h,
                pixels,
                valid,
            },
            passes: stats,
            precompute_ms: plan.precompute_ms,
            lut_source: plan.lut_origin,
            geometry_ms,
            sky_view_ms: plan.sky_view_ms,
            lights,
        })
    }
}
