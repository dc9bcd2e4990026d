//! `himmel-cpu`: the reference CPU renderer. It executes the frame plan of
//! `himmel-skymodel` ([`FramePlan`]) per pixel in Rust on all cores
//! (rayon); images are written through the `image` crate.
//!
//! * [`CpuRenderer`] — the [`SkyRenderer`] implementation: the LUT store
//!   (memory and disk cache, with a progress bar on a terminal), the
//!   per-pixel directions, then each planned pass back to front;
//! * [`sun_pass`], [`moon_pass`], [`night_pass`] — the passes that are more
//!   than a per-pixel lookup; [`bands`] runs the per-pixel ones (the
//!   cloud layers among them) band by band;
//! * [`output`] — EXR (linear, absolute cd/m²) and PNG (camera model) files;
//! * [`overlay`] — the constellation figures and labels drawn into a PNG.

pub mod bands;
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
    CloudHistory, CpuSkyViews, FramePlan, HistoryKey, HistoryUse, LowCloudGrid, LutOrigin,
    LutProgress, LutStore, PixelDirections, SkyLight,
};
use himmel_skymodel::renderer::{HdrImage, PassStat, RenderError, RenderOutput, SkyRenderer};
use himmel_skymodel::{Effect, Scene, SkyState};

use bands::PixelPass;
use moon_pass::MoonDraw;
use rayon::prelude::*;
use sun_pass::SunDraw;

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
/// directory is given, on disk ([`LutStore`]), and the last frame's
/// coarse cloud grid for temporal reprojection ([`CloudHistory`]).
#[derive(Debug, Default)]
pub struct CpuRenderer {
    store: LutStore,
    cloud_history: CloudHistory,
}

impl CpuRenderer {
    /// A renderer with the given disk cache (see [`default_cache_dir`]).
    pub fn new(cache_dir: Option<PathBuf>) -> Self {
        let mut store = LutStore::new(cache_dir);
        store.textures.set_loader(Arc::new(texture_io::ImageLoader));
        CpuRenderer {
            store,
            cloud_history: CloudHistory::default(),
        }
    }

    /// Forgets the last frame's cloud grid: the next frame marches every
    /// coarse node (its `cloud_history` says `first frame`).
    pub fn clear_cloud_history(&mut self) {
        self.cloud_history.clear();
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

impl SkyRenderer for CpuRenderer {
    fn name(&self) -> &'static str {
        "cpu"
    }

    fn render(&mut self, scene: &Scene, state: &SkyState) -> Result<RenderOutput, RenderError> {
        let mut plan = self.plan(scene, state)?;
        let cam = scene.camera;
        let (w, h) = cam.image_size();
        let (w, h) = (w as usize, h as usize);
        if plan.runs(Effect::Atmosphere) {
            // Computed here (timed as `sky_view_ms`), read by the pass.
            plan.sky_light(&mut CpuSkyViews)?;
        }
        // The image buffer, written on all cores so that its pages are
        // mapped here and not by whichever pass touches them first (the
        // sparse star splats would otherwise pay for the page faults).
        let tg = Clock::now();
        let mut pixels: Vec<[f32; 3]> = (0..w * h).into_par_iter().map(|_| [0.0f32; 3]).collect();
        let mut valid = vec![false; w * h];
        let mut geometry_ms = ms(tg);
        // The low layer's history over a sequence (`clouds.low.reproject`).
        let mut history = scene
            .clouds
            .low
            .reproject
            .then_some((&mut self.cloud_history, None));
        let mut stats = execute(
            &plan,
            scene,
            &mut pixels,
            &mut valid,
            &mut geometry_ms,
            &mut history,
        )?;
        let cloud_history = history.and_then(|h| h.1);
        if cloud_history.is_none() {
            // A frame without the amortised march breaks the sequence: the
            // next one starts afresh rather than from an older frame.
            self.cloud_history.clear();
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
            cloud_maps_ms: plan.clouds.as_ref().map_or(0.0, |c| c.height_field_ms),
            cloud_grid_ms: plan.clouds.as_ref().map_or(0.0, |c| c.diffusion_grid_ms),
            cloud_history,
            lights,
        })
    }
}

/// Runs the planned passes of `plan` back to front into `pixels` (and
/// `valid`): runs of per-pixel passes band by band ([`bands::run`]), the
/// point-source splats over the whole image between them — or before a
/// pending run that only adds light (the night frame's Milky Way: one run
/// of Milky Way, Moon and atmosphere after the stars and planets instead
/// of two, so that every pixel's direction is computed once). Returns each
/// pass's stat; the directions' time is added to `geometry_ms`. With
/// `history`, an amortised low layer takes its coarse nodes from the
/// renderer's [`CloudHistory`] and notes what it gave.
fn execute(
    plan: &FramePlan,
    scene: &Scene,
    pixels: &mut [[f32; 3]],
    valid: &mut [bool],
    geometry_ms: &mut f64,
    history: &mut Option<(&mut CloudHistory, Option<HistoryUse>)>,
) -> Result<Vec<PassStat>, RenderError> {
    let cam = &scene.camera;
    let (w, h) = cam.image_size();
    let (w, h) = (w as usize, h as usize);
    let (luts, r0) = (plan.luts.as_deref(), plan.observer_radius_km);
    let cloud_grid = std::cell::OnceCell::new();
    let mut runner = Runner {
        directions: PixelDirections::new(cam),
        run: Vec::new(),
        stats: Vec::new(),
        valid,
        valid_done: false,
        geometry_ms: 0.0,
    };
    for planned in &plan.passes {
        let name = planned.effect.name().into();
        if !planned.run {
            let reason = planned.reason.as_ref().map(ToString::to_string);
            runner.stats.push(PassStat {
                name,
                ran: false,
                ms: None,
                reason,
            });
            continue;
        }
        let point_sources = matches!(planned.effect, Effect::Stars | Effect::Planets);
        if point_sources && !runner.run.iter().all(|(_, p)| p.is_additive()) {
            // A splat may move ahead of the pending passes only when they
            // all add light, like the splat itself (the sums are the same
            // up to the order of addition: float rounding).
            runner.flush(pixels);
        }
        let i = runner.stats.len();
        let t0 = Clock::now();
        let run = &mut runner.run;
        match planned.effect {
            Effect::Atmosphere => run.extend(
                plan.sky_light
                    .as_ref()
                    .map(|s| (i, PixelPass::Atmosphere(s))),
            ),
            Effect::Sun => {
                if let Some(sun) = &plan.sun {
                    run.push((i, PixelPass::Sun(SunDraw { cam, sun, luts, r0 })));
                }
                if let Some(corona) = &plan.corona {
                    run.push((i, PixelPass::Corona { corona, luts, r0 }));
                }
            }
            Effect::Moon => run.extend(
                plan.moon
                    .as_ref()
                    .map(|m| (i, PixelPass::Moon(MoonDraw::new(cam, m, w, h)))),
            ),
            Effect::Milkyway => {
                run.extend(plan.night.as_ref().map(|n| (i, PixelPass::Milkyway(n))))
            }
            Effect::Texture => {
                run.extend(plan.texture.as_ref().map(|t| (i, PixelPass::Texture(t))))
            }
            Effect::Clouds => {
                if let Some(c) = &plan.clouds {
                    // Amortised marching: the low layer's grid first.
                    let grid = (c.low.is_some() && c.march_stride > 1).then(|| {
                        cloud_grid.get_or_init(|| {
                            let stride = c.march_stride as usize;
                            let dirs = &runner.directions;
                            match history.as_mut() {
                                Some((h, used)) => {
                                    let key = HistoryKey::of(scene, plan, c);
                                    let (g, u) =
                                        LowCloudGrid::build_with_history(c, dirs, stride, h, key);
                                    *used = Some(u);
                                    g
                                }
                                None => LowCloudGrid::build(c, dirs, stride),
                            }
                        })
                    });
                    runner.run.push((i, PixelPass::Clouds(c, grid)));
                }
            }
            Effect::Stars | Effect::Planets => {
                if let Some(n) = &plan.night {
                    let sources = if planned.effect == Effect::Stars {
                        &n.stars
                    } else {
                        &n.planets
                    };
                    night_pass::splat_all(n, pixels, scene, sources);
                }
            }
            other => return Err(RenderError::PassNotAvailable(other)),
        }
        runner.stats.push(PassStat {
            name,
            ran: true,
            ms: Some(ms(t0)),
            reason: None,
        });
    }
    runner.flush(pixels);
    if !runner.valid_done {
        // No per-pixel pass ran: the valid pixels still come from the directions.
        runner.valid_done = true;
        runner.geometry_ms += bands::run(&runner.directions, pixels, runner.valid, &[]).geometry_ms;
    }
    *geometry_ms += runner.geometry_ms;
    Ok(runner.stats)
}

/// The state of [`execute`]: the pending run of per-pixel passes (each
/// with its stat's index) and the stats so far.
struct Runner<'a, 'v> {
    directions: PixelDirections<'a>,
    run: Vec<(usize, PixelPass<'a>)>,
    stats: Vec<PassStat>,
    valid: &'v mut [bool],
    valid_done: bool,
    geometry_ms: f64,
}

impl Runner<'_, '_> {
    /// Runs the pending per-pixel passes band by band and adds their
    /// shares of the wall time to their stats.
    fn flush(&mut self, pixels: &mut [[f32; 3]]) {
        if self.run.is_empty() {
            return;
        }
        let passes: Vec<PixelPass> = self.run.iter().map(|(_, p)| *p).collect();
        let t = bands::run(&self.directions, pixels, self.valid, &passes);
        self.valid_done = true;
        self.geometry_ms += t.geometry_ms;
        for ((i, _), ms) in self.run.iter().zip(t.pass_ms) {
            *self.stats[*i].ms.get_or_insert(0.0) += ms;
        }
        self.run.clear();
    }
}
