//! `himmel-cpu`: the reference CPU renderer. Every pass is evaluated per
//! pixel in Rust on all cores (rayon), from the physics in
//! `himmel-skymodel`; images are written through the `image` crate.
//!
//! * [`precompute`] — the parameter-dependent atmosphere LUTs, in parallel,
//!   with a progress bar on a terminal, cached on disk ([`cache`]);
//! * [`CpuRenderer`] — the [`SkyRenderer`] implementation;
//! * [`output`] — EXR (linear, absolute cd/m²) and PNG (camera model) files.

pub mod cache;
pub mod moon_pass;
pub mod night_pass;
pub mod output;

use std::path::PathBuf;
use std::time::Instant as Clock;

use glam::Vec3;
use himmel_skymodel::atmosphere::{
    AtmosphereLuts, AtmosphereParams, LutConfig, SkyView, SkyViewInput,
};
use himmel_skymodel::renderer::{HdrImage, PassStat, RenderError, RenderOutput, SkyRenderer};
use himmel_skymodel::spectrum::Spectrum;
use himmel_skymodel::sun::SunDisk;
use himmel_skymodel::{Effect, Scene, SkyState};
use rayon::prelude::*;

/// Computes the parameter-dependent LUTs on all cores; shows a progress
/// bar on stderr when `progress` is set and stderr is a terminal.
pub fn precompute(params: &AtmosphereParams, config: &LutConfig, progress: bool) -> AtmosphereLuts {
    let medium = himmel_skymodel::atmosphere::Medium::new(params);
    let t = AtmosphereLuts::transmittance_lut(&medium, config, Spectrum::ZERO);
    let fwd = himmel_skymodel::atmosphere::lut::forward_scattering(&medium, config);
    let ts = AtmosphereLuts::transmittance_lut(&medium, config, fwd);
    let n = config.multiscatter_n;
    let bar = if progress {
        let b = indicatif::ProgressBar::new(n as u64);
        b.set_message("atmosphere LUTs");
        Some(b)
    } else {
        None
    };
    let rows: Vec<Vec<Spectrum>> = (0..n)
        .into_par_iter()
        .map(|j| {
            let r = AtmosphereLuts::multiscatter_row(&medium, config, &ts, j);
            if let Some(b) = &bar {
                b.inc(1);
            }
            r
        })
        .collect();
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    AtmosphereLuts::from_parts(params, config, t, ts, rows)
}

/// Computes the per-frame sky-view LUT on all cores.
pub fn sky_view(luts: &AtmosphereLuts, input: &SkyViewInput) -> SkyView {
    let rows = (0..luts.config.sky_view_h)
        .into_par_iter()
        .map(|j| SkyView::row(luts, input, j))
        .collect();
    SkyView::from_rows(luts, input, rows)
}

/// The ENU direction of every pixel centre (`None` outside the
/// projection), row-major. Fisheye and equirect use separable/closed forms
/// in f32 (equal to [`himmel_skymodel::Camera::pixel_to_dir`] within 1e-6);
/// the other projections call it per pixel.
pub fn directions(cam: &himmel_skymodel::Camera) -> Vec<Option<Vec3>> {
    use himmel_skymodel::Projection;
    let (w, h) = cam.image_size();
    let (w, h) = (w as usize, h as usize);
    let mut out = vec![None; w * h];
    match cam.projection {
        Projection::Fisheye => {
            let r = (w.min(h) as f64 / 2.0) as f32;
            out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
                let dy = (y as f64 + 0.5 - h as f64 / 2.0) as f32;
                for (x, o) in row.iter_mut().enumerate() {
                    let dx = (x as f64 + 0.5 - w as f64 / 2.0) as f32;
                    let rho = (dx * dx + dy * dy).sqrt();
                    let zenith = std::f32::consts::FRAC_PI_2 * rho / r;
                    if zenith > std::f32::consts::PI {
                        continue;
                    }
                    let (s, c) = zenith.sin_cos();
                    *o = Some(if rho > 0.0 {
                        Vec3::new(-dx / rho * s, -dy / rho * s, c)
                    } else {
                        Vec3::Z
                    });
                }
            });
        }
        Projection::Equirect => {
            let az: Vec<(f32, f32)> = (0..w)
                .map(|x| {
                    let a = std::f64::consts::TAU * (x as f64 + 0.5) / w as f64;
                    (a.sin() as f32, a.cos() as f32)
                })
                .collect();
            out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
                let alt = std::f64::consts::FRAC_PI_2
                    - std::f64::consts::PI * (y as f64 + 0.5) / h as f64;
                let (sa, ca) = (alt.sin() as f32, alt.cos() as f32);
                for (o, &(s, c)) in row.iter_mut().zip(&az) {
                    *o = Some(Vec3::new(ca * s, ca * c, sa));
                }
            });
        }
        _ => {
            out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
                for (x, o) in row.iter_mut().enumerate() {
                    *o = cam
                        .pixel_to_dir(x as f64 + 0.5, y as f64 + 0.5)
                        .map(|d| d.as_vec3());
                }
            });
        }
    }
    out
}

/// Sub-samples per axis for pixels near the Sun's disk.
pub const SUN_SUPERSAMPLING: usize = 16;

/// The CPU renderer. Keeps the last LUTs in memory and, when `cache_dir`
/// is set, on disk (keyed by a hash of the parameters).
#[derive(Debug, Default)]
pub struct CpuRenderer {
    /// On-disk LUT cache directory (none: no disk cache).
    pub cache_dir: Option<PathBuf>,
    /// Show a progress bar during long precomputation.
    pub progress: bool,
    luts: Option<AtmosphereLuts>,
}

impl CpuRenderer {
    /// A renderer with the given disk cache (see [`cache::default_dir`]).
    pub fn new(cache_dir: Option<PathBuf>) -> Self {
        CpuRenderer {
            cache_dir,
            progress: false,
            luts: None,
        }
    }

    /// The LUTs for `params`/`config`, from memory, disk or computation;
    /// returns them with their source.
    pub fn luts(
        &mut self,
        params: &AtmosphereParams,
        config: &LutConfig,
    ) -> (&AtmosphereLuts, &'static str) {
        let mut source = "memory";
        let luts = match self.luts.take() {
            Some(l) if l.params == *params && l.config == *config => l,
            _ => {
                let loaded = self
                    .cache_dir
                    .as_ref()
                    .and_then(|d| cache::load(d, params, config));
                match loaded {
                    Some(l) => {
                        source = "disk-cache";
                        l
                    }
                    None => {
                        source = "computed";
                        let l = precompute(params, config, self.progress);
                        if let Some(d) = &self.cache_dir {
                            // A cache that cannot be written only costs time next run.
                            let _ = cache::store(d, &l);
                        }
                        l
                    }
                }
            }
        };
        (&*self.luts.insert(luts), source)
    }

    /// Replaces the in-memory LUTs (e.g. with LUTs computed elsewhere: the
    /// wgpu backend's compute shaders; `None` empties the memory cache) and
    /// returns the previous ones. [`Self::luts`] then serves them from
    /// memory while the parameters and configuration match.
    pub fn replace_luts(&mut self, luts: Option<AtmosphereLuts>) -> Option<AtmosphereLuts> {
        std::mem::replace(&mut self.luts, luts)
    }
}

/// The sky-view inputs of `state`.
/// The sky's in-scattered light for one frame: the Sun's sky view and, on
/// a moonlit night, a second one lit from the Moon
/// ([`himmel_skymodel::moon::moonlight_scale`]).
#[derive(Debug, Clone)]
pub struct SkyLight {
    /// The sky lit by the Sun (ground below the horizon included).
    pub sun: SkyView,
    sun_dir: Vec3,
    /// The sky lit by the Moon, and the Moon's ENU direction.
    pub moon: Option<(SkyView, Vec3)>,
}

impl SkyLight {
    /// Computes the sky light of `state` on all cores.
    pub fn new(luts: &AtmosphereLuts, scene: &Scene, state: &SkyState) -> SkyLight {
        let pole = glam::DVec3::from_array(state.celestial_pole).as_vec3();
        let moon = himmel_skymodel::moon::moonlight_scale(scene, &state.sun, &state.moon, pole)
            .map(|scale| {
                let dir = state.moon.dir().as_vec3().normalize();
                let input = SkyViewInput {
                    observer_altitude_km: state.observer_altitude_km as f32,
                    sun_sin_elevation: dir.z,
                    irradiance_scale: scale as f32,
                };
                (sky_view(luts, &input), dir)
            });
        SkyLight {
            sun: sky_view(luts, &sky_view_input(state)),
            sun_dir: state.sun.dir().as_vec3().normalize(),
            moon,
        }
    }

    /// Sky radiance (linear sRGB, cd/m²) towards ENU `dir` (unit); the
    /// ground's luminance below the horizon.
    #[inline]
    pub fn radiance(&self, dir: Vec3) -> [f32; 3] {
        let mut l = self.sun.radiance(dir, self.sun_dir);
        if let Some((sv, m)) = &self.moon {
            let k = sv.radiance(dir, *m);
            for c in 0..3 {
                l[c] += k[c];
            }
        }
        l
    }
}

fn sky_view_input(state: &SkyState) -> SkyViewInput {
    SkyViewInput {
        observer_altitude_km: state.observer_altitude_km as f32,
        sun_sin_elevation: state.sun.dir().as_vec3().normalize().z,
        // Scaled by the visible fraction of the solar disk (solar eclipses).
        irradiance_scale: state.sun.sky_irradiance_scale() as f32,
    }
}

fn ms(t: Clock) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

impl CpuRenderer {
    /// The night passes (Milky Way, stars, planets) of `state` that would
    /// be invisible at the scene's exposure, with their reasons: the
    /// culling [`CpuRenderer::render`] applies, for a backend that has not
    /// ported those passes (it costs the CPU sky view and a sparse
    /// metering of the frame; nothing when no night pass is planned).
    pub fn night_culling(&mut self, scene: &Scene, state: &SkyState) -> Vec<(Effect, String)> {
        let night = [Effect::Milkyway, Effect::Stars, Effect::Planets];
        match self.night_frame(scene, state) {
            Some(frame) => night
                .into_iter()
                .filter_map(|e| frame.reason(e).map(|r| (e, r.to_string())))
                .collect(),
            None => Vec::new(),
        }
    }

    /// The night passes' per-frame state (exposure, extinction, culling) as
    /// [`CpuRenderer::render`] prepares it, or `None` when no night pass is
    /// planned: for a backend that draws the stars from
    /// [`night_pass::NightFrame::splat_plans`].
    pub fn night_frame(
        &mut self,
        scene: &Scene,
        state: &SkyState,
    ) -> Option<night_pass::NightFrame> {
        let night = [Effect::Milkyway, Effect::Stars, Effect::Planets];
        if !night.into_iter().any(|e| state.runs(e)) {
            return None;
        }
        let atmosphere = state.runs(Effect::Atmosphere);
        if atmosphere {
            self.luts(&scene.atmosphere, &scene.lut);
        }
        let luts = self.luts.as_ref().filter(|_| atmosphere);
        let sky = luts.map(|l| SkyLight::new(l, scene, state));
        let dirs = directions(&scene.camera);
        Some(night_pass::NightFrame::prepare(
            scene,
            state,
            luts,
            sky.as_ref(),
            &dirs,
        ))
    }
}

impl SkyRenderer for CpuRenderer {
    fn name(&self) -> &'static str {
        "cpu"
    }

    fn render(&mut self, scene: &Scene, state: &SkyState) -> Result<RenderOutput, RenderError> {
        scene
            .validate()
            .map_err(|e| RenderError::Scene(e.field, e.message))?;
        let cam = scene.camera;
        let (w, h) = cam.image_size();
        let (w, h) = (w as usize, h as usize);
        let sun_dir = state.sun.dir().as_vec3().normalize();

        // Geometry: one direction per pixel centre.
        let tg = Clock::now();
        let dirs = directions(&cam);
        // The image buffer, written on all cores so that its pages are
        // mapped here and not by whichever pass touches them first (the
        // sparse star splats would otherwise pay for the page faults).
        let mut pixels: Vec<[f32; 3]> = (0..w * h).into_par_iter().map(|_| [0.0f32; 3]).collect();
        let geometry_ms = ms(tg);
        let mut sky_view_ms = 0.0;
        let valid: Vec<bool> = dirs.iter().map(Option::is_some).collect();
        let mut stats = Vec::new();
        let mut precompute_ms = 0.0;
        let mut lut_source = "none";

        // The parameter-dependent LUTs first: the Sun pass (behind the
        // atmosphere) needs their transmittance.
        if state.runs(Effect::Atmosphere) {
            let tp = Clock::now();
            let (_, source) = self.luts(&scene.atmosphere, &scene.lut);
            precompute_ms = ms(tp);
            lut_source = source;
        }
        // The night passes decide before rendering whether they can show
        // at the chosen exposure; they need the sky view for that.
        let mut sv = None;
        let night = if [Effect::Milkyway, Effect::Stars, Effect::Planets]
            .into_iter()
            .any(|e| state.runs(e))
        {
            let luts = self
                .luts
                .as_ref()
                .filter(|_| state.runs(Effect::Atmosphere));
            if let Some(l) = luts {
                let tsv = Clock::now();
                sv = Some(SkyLight::new(l, scene, state));
                sky_view_ms = ms(tsv);
            }
            Some(night_pass::NightFrame::prepare(
                scene,
                state,
                luts,
                sv.as_ref(),
                &dirs,
            ))
        } else {
            None
        };
        for planned in &state.passes {
            let culled = night.as_ref().and_then(|n| n.reason(planned.effect));
            if !planned.run || culled.is_some() {
                stats.push(PassStat {
                    name: planned.effect.name().into(),
                    ran: false,
                    ms: None,
                    reason: planned.reason.clone().or(culled.map(str::to_string)),
                });
                continue;
            }
            let t0 = Clock::now();
            match planned.effect {
                Effect::Atmosphere => {
                    let sv = match sv.take() {
                        Some(sv) => sv,
                        None => {
                            let (luts, _) = self.luts(&scene.atmosphere, &scene.lut);
                            let tsv = Clock::now();
                            let sv = SkyLight::new(luts, scene, state);
                            sky_view_ms = ms(tsv);
                            sv
                        }
                    };
                    pixels
                        .par_iter_mut()
                        .zip(dirs.par_iter())
                        .for_each(|(p, d)| {
                            if let Some(d) = d {
                                let l = sv.radiance(*d);
                                for k in 0..3 {
                                    p[k] += l[k];
                                }
                            }
                        });
                }
                Effect::Sun => {
                    let disk = SunDisk::new(
                        sun_dir,
                        state.sun.angular_radius * scene.sun_scale,
                        state.sun.irradiance_scale,
                    );
                    let margin = (disk.radius as f64 + 1.5 * cam.max_pixel_angle()).min(3.0);
                    let cos_margin = margin.cos() as f32;
                    // Back to front: the atmosphere pass comes later, but its
                    // extinction applies to the disk behind it.
                    let luts = if state.runs(Effect::Atmosphere) {
                        self.luts.as_ref()
                    } else {
                        None
                    };
                    let r0 = luts
                        .map(|l| l.medium.bottom + state.observer_altitude_km as f32)
                        .unwrap_or(0.0);
                    let n = SUN_SUPERSAMPLING;
                    // Solar eclipses: the Moon's disk hides the Sun's.
                    let (moon_c, moon_sin) = (
                        state.moon.dir().as_vec3(),
                        (state.moon.angular_radius * scene.moon_scale).sin() as f32,
                    );
                    pixels
                        .par_iter_mut()
                        .zip(dirs.par_iter())
                        .enumerate()
                        .for_each(|(i, (p, d))| {
                            let Some(d) = d else { return };
                            if d.dot(sun_dir) < cos_margin {
                                return;
                            }
                            let (x, y) = ((i % w) as f64, (i / w) as f64);
                            let mut acc = [0.0f32; 3];
                            for sj in 0..n {
                                for si in 0..n {
                                    let sx = x + (si as f64 + 0.5) / n as f64;
                                    let sy = y + (sj as f64 + 0.5) / n as f64;
                                    let Some(sd) = cam.pixel_to_dir(sx, sy) else {
                                        continue;
                                    };
                                    let sd = sd.as_vec3();
                                    // The ground hides the disk below the horizon.
                                    let behind_moon = sd.dot(moon_c) > 0.0
                                        && sd.cross(moon_c).length() < moon_sin;
                                    if sd.z < 0.0 || !disk.covers(sd) || behind_moon {
                                        continue;
                                    }
                                    let t = match luts {
                                        Some(l) => l.sun_transmittance(r0, sd.z),
                                        None => Spectrum::ONE,
                                    };
                                    let l = disk.radiance_rgb(sd, &t);
                                    for k in 0..3 {
                                        acc[k] += l[k];
                                    }
                                }
                            }
                            let k = 1.0 / (n * n) as f32;
                            for c in 0..3 {
                                p[c] += acc[c] * k;
                            }
                        });
                    moon_pass::render_corona(&mut pixels, &dirs, scene, state, luts, r0);
                }
                Effect::Moon => {
                    let luts = self
                        .luts
                        .as_ref()
                        .filter(|_| state.runs(Effect::Atmosphere));
                    let r0 =
                        luts.map_or(0.0, |l| l.medium.bottom + state.observer_altitude_km as f32);
                    moon_pass::render(&mut pixels, &dirs, w, scene, state, luts, r0);
                }
                Effect::Milkyway | Effect::Stars | Effect::Planets => {
                    if let Some(n) = &night {
                        match planned.effect {
                            Effect::Milkyway => n.milkyway(&mut pixels, &dirs),
                            Effect::Stars => n.stars(&mut pixels, scene, state),
                            _ => n.planets(&mut pixels, scene, state),
                        }
                    }
                }
                other => {
                    return Err(RenderError::Other(format!(
                        "the {} pass is not available in this version",
                        other.name()
                    )))
                }
            }
            stats.push(PassStat {
                name: planned.effect.name().into(),
                ran: true,
                ms: Some(ms(t0)),
                reason: None,
            });
        }
        stats.extend(PassStat::moon_eclipse(state));
        Ok(RenderOutput {
            image: HdrImage {
                width: w,
                height: h,
                pixels,
                valid,
            },
            passes: stats,
            precompute_ms,
            lut_source,
            geometry_ms,
            sky_view_ms,
        })
    }
}
