//! The clouds pass's frame ([`CloudFrame`]): the layers' fields at the
//! frame's instant, the lights at the cloud, the sky's ambient radiance,
//! and the composition of a cloud over what lies behind it.
//!
//! Composition. A pixel that already holds the sky behind the cloud, P =
//! L_air(0, d) + T_air(0, d) · X (X: the radiance reaching the cloud's
//! distance d from beyond, the stars and the Moon included), becomes
//!
//! ```text
//! P' = L_air(0, d) + T_air(0, d) · (L_cloud + T_cloud · X)
//!    = T_cloud · P + (1 − T_cloud) · L_air(0, d) + T_air(0, d) · L_cloud,
//! ```
//!
//! with L_air, T_air the aerial perspective between the camera and the
//! cloud ([`AerialPerspective`], Hillaire 2020 §5.5). Everything behind a
//! cloud of optical depth τ is dimmed by e^{−τ}, stars and Milky Way
//! included. The high layer is composed first (it is farther), then the
//! low layer.
//!
//! Lights. The Sun (and the Moon on a moonlit night) light the cloud with
//! their irradiance outside the atmosphere × the atmosphere's spectral
//! transmittance from the point where the view ray enters the layer (the
//! Earth's shadow included: high clouds stay lit after sunset). Without
//! the atmosphere pass the lights are not extinguished and there is no
//! sky light: the isolated configuration of `--effects clouds`, used by
//! the Mitsuba comparison.
//!
//! Ambient. The sky's mean radiance over the upper hemisphere, E_h / π
//! (E_h the sky's horizontal illuminance at the observer, no Sun disk),
//! scattered isotropically ([`crate::clouds::march`] scales it with the
//! height in the low layer).

use std::sync::Arc;

use glam::{DVec3, Vec3};

#[cfg(doc)]
use super::lights::sky_horizontal_rgb;
use super::lights::AerialPerspective;
use super::sky_light::SkyInputs;
use crate::atmosphere::{AtmosphereLuts, SkyView};
use crate::clouds::{
    march_height_field, march_low_with_grids, shade_high, CloudHit, CloudLight, DiffusionGrid,
    HeightField, HighField, LowField, MarchSettings, MultipleScattering, Shell, DIFFUSION, GRID,
    OCTAVES,
};
use crate::moon::lunar_reflectance_spectrum;
use crate::scene::Scene;
use crate::scene::{CloudScattering, LowCloudSpec, LowCloudTier};
use crate::spectrum::{BandWeights, Spectrum};
use crate::state::SkyState;

/// Julian date (TT) of J2000.0, the wind's epoch.
pub(crate) const J2000_TT: f64 = 2_451_545.0;
/// Earth radius without an atmosphere model, km.
pub(crate) const EARTH_RADIUS_KM: f32 = 6360.0;
/// Below this transmittance change a layer leaves the pixel alone.
pub const CLEAR: f32 = 1e-5;

/// A light of the frame: unit ENU direction and its spectrum outside the
/// atmosphere (band transfer factors of the 1 AU solar spectrum).
#[derive(Debug, Clone, Copy)]
struct FrameLight {
    dir: Vec3,
    spectrum: Spectrum,
}

/// A layer's hit along a view ray with the air in front of it: the
/// in-scattered radiance (cd/m², linear sRGB) and transmittance of the air
/// between the camera and the hit's distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeenHit {
    /// The layer's radiance, transmittance and distance.
    pub hit: CloudHit,
    /// The air's in-scattered radiance in front of the layer.
    pub air_radiance: [f32; 3],
    /// The air's transmittance in front of the layer.
    pub air_transmittance: [f32; 3],
}

/// A light's direct part of the ground's luminance below the horizon.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundLight {
    /// Unit ENU direction towards the light.
    pub dir: Vec3,
    /// albedo/π × E_direct × sin h, linear sRGB, cd/m²
    /// ([`crate::atmosphere::SkyView::ground_direct`]).
    pub rgb: [f32; 3],
}

/// The Sun's or Moon's step, degrees, below which a frame keeps the last
/// frame's diffusion grids ([`GridStore`]).
pub const GRID_REUSE_DEG: f32 = 0.05;

/// The volumetric tier's diffusion grids of the last frame, kept by the
/// renderer ([`crate::frame::LutStore`]): a frame with the same low layer
/// (all but its time), the same shell and its lights within
/// [`GRID_REUSE_DEG`] of theirs moves them with the wind
/// ([`DiffusionGrid::follow`]) instead of solving them anew — over an
/// unbounded layer until the wind carries the field a cell further, over a
/// patch while the field stands still. Building a grid costs hundreds of
/// milliseconds on the CPU; following it, a copy.
#[derive(Debug, Clone, Default)]
pub struct GridStore {
    last: Option<(LowCloudSpec, Shell, Arc<Vec<DiffusionGrid>>)>,
}

impl GridStore {
    /// The kept grids moved to `field`, when they answer for this layer,
    /// shell and lights (one grid per light, in order).
    fn get(
        &mut self,
        spec: &LowCloudSpec,
        shell: &Shell,
        dirs: &[Vec3],
        field: &LowField,
    ) -> Option<Arc<Vec<DiffusionGrid>>> {
        let (s, sh, grids) = self.last.as_ref()?;
        let near = |a: Vec3, b: Vec3| a.angle_between(b).to_degrees() < GRID_REUSE_DEG;
        let same = s == spec
            && sh == shell
            && grids.len() == dirs.len()
            && grids.iter().zip(dirs).all(|(g, &d)| near(g.light, d));
        if !same {
            return None;
        }
        let moved: Option<Vec<DiffusionGrid>> = grids.iter().map(|g| g.follow(field)).collect();
        let moved = Arc::new(moved?);
        self.last = Some((*spec, *shell, moved.clone()));
        Some(moved)
    }

    /// Keeps `grids` (built for `spec` and `shell`) and returns them.
    fn keep(
        &mut self,
        spec: LowCloudSpec,
        shell: Shell,
        grids: Vec<DiffusionGrid>,
    ) -> Arc<Vec<DiffusionGrid>> {
        let grids = Arc::new(grids);
        self.last = Some((spec, shell, grids.clone()));
        grids
    }
}

/// Everything the clouds pass of one frame needs.
#[derive(Debug, Clone)]
pub struct CloudFrame {
    /// The low layer, when it has coverage.
    pub low: Option<LowField>,
    /// The high layer, when it has coverage and optical depth.
    pub high: Option<HighField>,
    /// The ground and the observer, km.
    pub shell: Shell,
    /// The low layer's march.
    pub march: MarchSettings,
    /// Amortised marching: the grid's stride in pixels (1: every pixel).
    pub march_stride: u32,
    /// The low layer's height-field maps when `clouds.low.tier` is
    /// `heightfield` (built here, once per frame; none: the volumetric
    /// march).
    pub height_field: Option<Arc<HeightField>>,
    /// Time spent building [`Self::height_field`], ms.
    pub height_field_ms: f64,
    /// The volumetric tier's 3D diffusion grids, one per light in
    /// [`Self::light_sources`]' order, when `clouds.low.scattering` is
    /// `diffusion` ([`DiffusionGrid`]: half the diffuse light; empty: the
    /// column model alone).
    pub diffusion_grids: Arc<Vec<DiffusionGrid>>,
    /// Time spent building [`Self::diffusion_grids`], ms.
    pub diffusion_grid_ms: f64,
    /// The sky's mean downward radiance, linear sRGB, cd/m².
    pub ambient_rgb: [f32; 3],
    /// The direct part of the ground's luminance below the horizon, per
    /// light of the sky model (the Sun's, then the Moon's; none without
    /// the atmosphere pass), which cloud shadows dim
    /// ([`CloudFrame::shade_ground`]).
    pub ground_direct: Vec<GroundLight>,
    /// Each [`Self::ground_direct`] light's transmittance through the
    /// layers from the observer's place (the ground pixels' of an
    /// observer on the ground).
    pub ground_at_observer: Vec<f32>,
    lights: Vec<FrameLight>,
    luts: Option<Arc<AtmosphereLuts>>,
    sky_inputs: Option<SkyInputs>,
    weights: BandWeights,
}

impl CloudFrame {
    /// The frame of `scene` at `state`: `luts` and `sky_inputs` when the
    /// atmosphere pass runs, `sky_horizontal_rgb` the sky's horizontal
    /// illuminance ([`sky_horizontal_rgb`], linear sRGB, lux) when known.
    pub fn prepare(
        scene: &Scene,
        state: &SkyState,
        luts: Option<Arc<AtmosphereLuts>>,
        sky_inputs: Option<SkyInputs>,
        sky_horizontal_rgb: Option<[f64; 3]>,
        grids: &mut GridStore,
    ) -> CloudFrame {
        let seconds = (state.jd_tt - J2000_TT) * 86_400.0;
        let c = &scene.clouds;
        let r_ground = luts.as_ref().map_or(EARTH_RADIUS_KM, |l| l.medium.bottom);
        let shell = Shell {
            r_ground,
            r_observer: r_ground + state.observer_altitude_km as f32,
        };
        let sun = &state.sun;
        let mut lights = Vec::new();
        let sun_dir = sun.dir().as_vec3().normalize();
        // With an atmosphere the transmittance LUT decides (Earth's shadow);
        // without, the Sun lights the clouds while it is up.
        if sun_dir.z > if luts.is_some() { -0.2 } else { 0.0 } {
            let scale = (sun.irradiance_scale * sun.visible_fraction) as f32;
            lights.push(FrameLight {
                dir: sun_dir,
                spectrum: Spectrum::splat(scale),
            });
        }
        let pole = DVec3::from_array(state.celestial_pole).as_vec3();
        if let Some(scale) = crate::moon::moonlight_scale(scene, sun, &state.moon, pole) {
            lights.push(FrameLight {
                dir: state.moon.dir().as_vec3().normalize(),
                spectrum: lunar_reflectance_spectrum() * scale as f32,
            });
        }
        let ambient_rgb =
            sky_horizontal_rgb.map_or([0.0; 3], |e| e.map(|v| (v / std::f64::consts::PI) as f32));
        let ground_direct: Vec<GroundLight> = match (&luts, &sky_inputs) {
            (Some(l), Some(i)) => std::iter::once((i.sun, i.sun_dir))
                .chain(i.moon)
                .map(|(input, dir)| GroundLight {
                    dir,
                    rgb: SkyView::ground_direct(l, &input).1,
                })
                .collect(),
            _ => Vec::new(),
        };
        let low = c.has_low().then(|| LowField::new(&c.low, seconds));
        let march = MarchSettings {
            steps: c.low.steps,
            light_steps: c.low.light_steps,
            scattering: match c.low.scattering {
                CloudScattering::Diffusion | CloudScattering::Column => {
                    MultipleScattering::Diffusion(DIFFUSION)
                }
                CloudScattering::Octaves => MultipleScattering::Octaves(OCTAVES),
            },
        };
        let dirs: Vec<Vec3> = lights.iter().map(|l| l.dir).collect();
        let clock = std::time::Instant::now();
        let height_field = low
            .filter(|_| c.low.tier == LowCloudTier::Heightfield)
            .map(|f| Arc::new(HeightField::build(&f, &shell, &dirs, &march)));
        let height_field_ms = match height_field {
            Some(_) => clock.elapsed().as_secs_f64() * 1e3,
            None => 0.0,
        };
        let clock = std::time::Instant::now();
        // A grid that cannot be built (a layer too thick for
        // `diffusion_grid::MAX_CELLS`) leaves the column model alone.
        let diffusion_grids: Arc<Vec<DiffusionGrid>> = match low {
            Some(f)
                if c.low.tier == LowCloudTier::Volumetric
                    && c.low.scattering == CloudScattering::Diffusion =>
            {
                grids.get(&c.low, &shell, &dirs, &f).unwrap_or_else(|| {
                    let built: Vec<DiffusionGrid> = dirs
                        .iter()
                        .filter_map(|&d| DiffusionGrid::build(&f, &shell, d, &GRID).ok())
                        .collect();
                    grids.keep(c.low, shell, built)
                })
            }
            _ => Arc::new(Vec::new()),
        };
        let diffusion_grid_ms = if diffusion_grids.is_empty() {
            0.0
        } else {
            clock.elapsed().as_secs_f64() * 1e3
        };
        let mut frame = CloudFrame {
            low,
            high: c.has_high().then(|| HighField::new(&c.high, seconds)),
            shell,
            march,
            march_stride: c.low.march_stride,
            height_field,
            height_field_ms,
            diffusion_grids,
            diffusion_grid_ms,
            ambient_rgb,
            ground_direct,
            ground_at_observer: Vec::new(),
            lights,
            luts,
            sky_inputs,
            weights: BandWeights::solar(),
        };
        let eye = Vec3::new(0.0, 0.0, frame.shell.r_observer);
        frame.ground_at_observer = frame
            .ground_direct
            .iter()
            .map(|g| frame.transmittance_towards(eye, g.dir))
            .collect();
        frame
    }

    /// The frame's lights: unit ENU direction and spectrum outside the
    /// atmosphere (band factors of the 1 AU solar spectrum), the Sun's
    /// first. [`Self::lights_at`] extinguishes them at the cloud.
    pub fn light_sources(&self) -> Vec<(Vec3, Spectrum)> {
        self.lights.iter().map(|l| (l.dir, l.spectrum)).collect()
    }

    /// The lights at the point `t` km along `view` (their irradiance after
    /// the atmosphere's transmittance from there).
    pub fn lights_at(&self, view: Vec3, t: f32) -> Vec<CloudLight> {
        let p = Vec3::new(0.0, 0.0, self.shell.r_observer) + view * t;
        let r = p.length();
        self.lights
            .iter()
            .map(|l| {
                let e = match &self.luts {
                    Some(luts) => l.spectrum * luts.sun_transmittance(r, p.dot(l.dir) / r),
                    None => l.spectrum,
                };
                CloudLight {
                    dir: l.dir,
                    irradiance_rgb: self.weights.to_rgb(&e).map(|v| v.max(0.0)),
                }
            })
            .collect()
    }

    /// The low layer along `view` (no aerial perspective).
    pub fn low_hit(&self, view: Vec3) -> CloudHit {
        let Some(f) = &self.low else {
            return CloudHit::CLEAR;
        };
        let Some((t0, _)) = self.shell.slab(view, f.base_km, f.top_km) else {
            return CloudHit::CLEAR;
        };
        let lights = self.lights_at(view, t0);
        match &self.height_field {
            Some(hf) => march_height_field(
                hf,
                f,
                &self.shell,
                view,
                &lights,
                self.ambient_rgb,
                &self.march,
            ),
            None => march_low_with_grids(
                f,
                &self.shell,
                view,
                &lights,
                self.ambient_rgb,
                &self.march,
                &self.diffusion_grids,
            ),
        }
    }

    /// The high layer along `view` (no aerial perspective).
    pub fn high_hit(&self, view: Vec3) -> CloudHit {
        let Some(f) = &self.high else {
            return CloudHit::CLEAR;
        };
        let probe = shade_high(f, &self.shell, view, &[], [0.0; 3]);
        if probe.transmittance >= 1.0 - CLEAR {
            return CloudHit::CLEAR;
        }
        let lights = self.lights_at(view, probe.distance_km);
        shade_high(f, &self.shell, view, &lights, self.ambient_rgb)
    }

    /// The low layer along `view` with the air in front of it.
    pub fn low_seen(&self, view: Vec3) -> SeenHit {
        self.seen(view, self.low_hit(view))
    }

    /// `hit` along `view` with the air in front of it (none when clear).
    fn seen(&self, view: Vec3, hit: CloudHit) -> SeenHit {
        let air = if hit.transmittance >= 1.0 - CLEAR {
            ([0.0; 3], [1.0; 3])
        } else {
            self.air(view, hit.distance_km)
        };
        SeenHit {
            hit,
            air_radiance: air.0,
            air_transmittance: air.1,
        }
    }

    /// `behind` (the pixel's radiance so far, cd/m²) seen through both
    /// layers along `view`, with the aerial perspective in front of each.
    pub fn composite(&self, view: Vec3, behind: [f32; 3]) -> [f32; 3] {
        self.composite_with(view, behind, self.low_seen(view))
    }

    /// [`CloudFrame::composite`] with the low layer along `view` given
    /// (from an amortised grid, [`super::LowCloudGrid`]).
    pub fn composite_with(&self, view: Vec3, behind: [f32; 3], low: SeenHit) -> [f32; 3] {
        let mut px = self.shade_ground(view, behind);
        for s in [self.seen(view, self.high_hit(view)), low] {
            let t = s.hit.transmittance;
            if t >= 1.0 - CLEAR {
                continue;
            }
            for c in 0..3 {
                px[c] = t * px[c]
                    + (1.0 - t) * s.air_radiance[c]
                    + s.air_transmittance[c] * s.hit.radiance[c];
            }
        }
        px
    }

    /// In-scattered radiance and transmittance of the air between the
    /// camera and `d_km` along `view` (none without the atmosphere pass).
    fn air(&self, view: Vec3, d_km: f32) -> ([f32; 3], [f32; 3]) {
        match (&self.luts, &self.sky_inputs) {
            (Some(luts), Some(inputs)) => {
                let ap = AerialPerspective::compute(
                    luts,
                    inputs,
                    self.shell.r_observer,
                    &[view],
                    &[d_km * 1000.0],
                );
                ap.table.first().copied().unwrap_or(([0.0; 3], [1.0; 3]))
            }
            _ => ([0.0; 3], [1.0; 3]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clouds::optical_depth_low;
    use crate::scene::Effect;

    /// A scene with a low layer and no atmosphere (the isolated
    /// configuration), at noon.
    fn frame(coverage: f64) -> CloudFrame {
        let mut s = Scene::default();
        s.time.utc = "2024-06-21T11:00:00Z".into();
        s.effects = vec![Effect::Clouds];
        s.clouds.low.coverage = coverage;
        let state = SkyState::at(&s).expect("state");
        CloudFrame::prepare(&s, &state, None, None, None, &mut GridStore::default())
    }

    /// What lies behind a cloud (stars, the Milky Way, the Moon) is dimmed
    /// by e^{−τ} of the cloud's optical depth along the line of sight.
    #[test]
    fn what_lies_behind_is_dimmed_by_the_optical_depth() {
        let mut f = frame(0.6);
        f.lights.clear();
        let low = f.low.expect("a low layer");
        let mut checked = 0;
        for i in 0..60 {
            let a = i as f32 * 0.21;
            let v = Vec3::new(a.cos() * 0.4, a.sin() * 0.4, 0.9).normalize();
            let star = [3.0, 2.0, 1.0];
            let out = f.composite(v, star);
            let t = (-optical_depth_low(&low, &f.shell, v, f.march.steps)).exp();
            if t > 0.01 && t < 0.99 {
                for c in 0..3 {
                    assert!((out[c] / (star[c] * t) - 1.0).abs() < 0.02, "{out:?} {t}");
                }
                checked += 1;
            }
        }
        assert!(checked > 5, "{checked}");
    }

    /// A renderer's next frame one second later keeps the diffusion grids,
    /// moved with the wind (the same cells, the corner 10 m east); ten
    /// minutes later the Sun has moved ~2°, and they are solved anew.
    #[test]
    fn the_grids_are_kept_while_the_sun_stands_still() {
        let mut store = GridStore::default();
        let mut s = Scene {
            effects: vec![Effect::Clouds],
            ..Scene::default()
        };
        s.clouds.low.coverage = 0.6;
        s.clouds.low.wind_m_s = [10.0, 0.0];
        let mut at = |t: &str| {
            s.time.utc = t.into();
            let state = SkyState::at(&s).expect("state");
            CloudFrame::prepare(&s, &state, None, None, None, &mut store).diffusion_grids
        };
        let a = at("2024-06-21T11:00:00Z");
        let b = at("2024-06-21T11:00:01Z");
        let c = at("2024-06-21T11:10:00Z");
        assert_eq!((a.len(), b.len(), c.len()), (1, 1, 1));
        assert_eq!(a[0].cells, b[0].cells);
        let moved = b[0].origin - a[0].origin;
        let expect = (b[0].offset_km - a[0].offset_km).x;
        assert!(
            (moved.x - expect).abs() < 1e-4 && expect > 0.009,
            "{moved:?} vs {expect}"
        );
        assert!(a[0].light.angle_between(c[0].light).to_degrees() > 1.0);
        assert_ne!(a[0].cells, c[0].cells);
    }

    /// The Sun lights the clouds while it is up: a sunlit cloud is bright,
    /// and without an atmosphere its light is the Sun's illuminance outside
    /// the atmosphere (about 130 klx).
    #[test]
    fn the_sun_lights_the_clouds() {
        let f = frame(0.8);
        let lights = f.lights_at(Vec3::Z, 1.0);
        assert_eq!(lights.len(), 1);
        let e = crate::spectrum::luminance(lights[0].irradiance_rgb);
        assert!((125_000.0..140_000.0).contains(&e), "{e}");
        let hit = f.low_hit(Vec3::new(0.2, 0.1, 0.97).normalize());
        assert!(hit.transmittance < 1.0);
        let y = crate::spectrum::luminance(hit.radiance);
        assert!(y > 100.0 && y.is_finite(), "{y}");
    }
}
