//! `himmel render --frames N [--time-step S] [--camera-path FILE]`: frame
//! sequences (time-lapses, animations, camera flights) with one renderer.
//!
//! * Frame k is at t0 + k × S × `time.speed` (`himmel_skymodel::sequence`);
//!   `--day-fraction` moves t0.
//! * Files: `--output DIR/sky.png` → `DIR/sky_0000.png`, `DIR/sky_0001.png`,
//!   … (the frame index, zero-padded to at least 4 digits, more when N − 1
//!   needs them).
//! * The renderer (device, LUTs, pipelines) is built once; every frame goes
//!   through [`render_frame`], the single-frame path's own function.
//! * Automatic exposure of a PNG sequence: a small preview of every frame
//!   (64 px, a 48 × 27 sky view on the frames' own precomputed LUTs) is
//!   metered first, then the exposure curve changes by at most
//!   `exposure_max_step_ev` per frame
//!   (`himmel_skymodel::sequence::exposure::smooth_ev100`).
//! * A progress bar on stderr (hidden when stderr is not a terminal).

use std::path::{Path, PathBuf};
use std::time::Instant as Clock;

use himmel_cpu::output::Format as ImageFormat;
use himmel_skymodel::camera::meter_ev100;
use himmel_skymodel::sequence::exposure::smooth_ev100;
use himmel_skymodel::sequence::{CameraPath, Sequence, SequenceError, MAX_FRAMES};
use himmel_skymodel::{Effect, Exposure, Projection, Scene};
use serde_json::json;

use crate::render_cmd::{
    cloud_history_stats, frame_stats, render_frame, scene_error, write_stats, FrameRenderer,
    RenderArgs,
};
use crate::timearg::format_utc;
use crate::CliError;

/// Longest side of the metering preview, pixels (a cube map's face: a
/// sixth of it).
const PREVIEW_SIDE: u32 = 64;

/// The sequence flags of `himmel render`, validated.
pub(crate) struct SequenceArgs {
    frames: u32,
    time_step_s: f64,
    camera_path: Option<CameraPath>,
}

impl SequenceArgs {
    /// The sequence the flags ask for (none without `--frames`).
    pub(crate) fn of(a: &RenderArgs) -> Result<Option<SequenceArgs>, CliError> {
        let Some(n) = a.frames else {
            for (flag, given) in [
                ("--time-step", a.time_step.is_some()),
                ("--camera-path", a.camera_path.is_some()),
            ] {
                if given {
                    return Err(CliError::input(format!(
                        "{flag} needs --frames N (a frame sequence)"
                    )));
                }
            }
            return Ok(None);
        };
        if !(1..=u64::from(MAX_FRAMES)).contains(&n) {
            return Err(CliError::input(format!(
                "--frames {n}: expected a frame count in [1, {MAX_FRAMES}]"
            )));
        }
        let time_step_s = a.time_step.unwrap_or(0.0);
        if !time_step_s.is_finite() {
            return Err(CliError::input(format!(
                "--time-step {time_step_s}: expected a finite number of seconds"
            )));
        }
        let camera_path =
            match &a.camera_path {
                None => None,
                Some(p) => {
                    let text = std::fs::read_to_string(p).map_err(|e| {
                        CliError::input(format!("--camera-path {}: cannot read ({e})", p.display()))
                    })?;
                    Some(CameraPath::from_json(&text).map_err(|e| {
                        CliError::input(format!("--camera-path {}: {e}", p.display()))
                    })?)
                }
            };
        Ok(Some(SequenceArgs {
            frames: n as u32,
            time_step_s,
            camera_path,
        }))
    }
}

/// The numbered file of frame `index` in a sequence of `frames`:
/// `sky.png` → `sky_0007.png` (at least 4 digits).
pub(crate) fn numbered(output: &Path, index: u32, frames: u32) -> PathBuf {
    let digits = frames.saturating_sub(1).max(1).ilog10() as usize + 1;
    let width = digits.max(4);
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name = match output.extension() {
        Some(ext) => format!("{stem}_{index:0width$}.{}", ext.to_string_lossy()),
        None => format!("{stem}_{index:0width$}"),
    };
    output.with_file_name(name)
}

/// A progress bar of `total` frames on stderr (indicatif hides it when
/// stderr is not a terminal).
fn progress(total: u64) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(total);
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "{msg:>9} [{bar:30}] {pos}/{len} frames, {elapsed} (eta {eta})",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// Sky-view LUT of the metering preview: a quarter of the default's
/// 192 × 108 texels each way (the precomputed LUTs are the frames' own,
/// `LutConfig::same_tables`). The sky view is most of a preview's cost;
/// at this size it is 16× cheaper.
const PREVIEW_SKY_VIEW: (usize, usize) = (48, 27);

/// The metering preview of `scene`: the same camera at most
/// [`PREVIEW_SIDE`] pixels on its longer side; with `small_sky_view`, a
/// sky-view LUT of [`PREVIEW_SKY_VIEW`] texels (never larger than the
/// frame's). The small sky view is for the CPU backend, whose sky view is
/// a preview's main cost; the wgpu backend computes the sky view in its
/// shaders and keys its GPU LUTs by the whole configuration, so there the
/// preview keeps the frame's.
///
/// With a 3D world the preview's lighting is coarser where that barely
/// moves a 64-pixel mean and costs the most: the sky's occlusion from 16
/// directions per set of 128² maps in one part each, a 16² sky cube,
/// 512² shadow maps, and no temporal filter (a preview has no history to
/// average). The lights, materials and the other passes are the frame's.
fn preview(scene: &Scene, small_sky_view: bool) -> Scene {
    let mut s = scene.clone();
    if small_sky_view {
        s.lut.sky_view_w = s.lut.sky_view_w.min(PREVIEW_SKY_VIEW.0);
        s.lut.sky_view_h = s.lut.sky_view_h.min(PREVIEW_SKY_VIEW.1);
    }
    if s.world.is_some() {
        let sky = &mut s.lighting.sky;
        sky.directions = sky.directions.min(16);
        sky.visibility_resolution = sky.visibility_resolution.min(128);
        sky.parts = 1;
        sky.cube_face = sky.cube_face.min(16);
        s.lighting.shadows.resolution = s.lighting.shadows.resolution.min(512);
        s.effects.retain(|e| *e != Effect::Temporal);
    }
    let c = &mut s.camera;
    let side = match c.projection {
        Projection::Cubemap => c.height.saturating_mul(6),
        _ => c.width.max(c.height),
    };
    if side > PREVIEW_SIDE {
        let k = f64::from(PREVIEW_SIDE) / f64::from(side);
        c.width = ((f64::from(c.width) * k).round() as u32).max(1);
        c.height = ((f64::from(c.height) * k).round() as u32).max(1);
    }
    s
}

/// A sequence run of `himmel render`.
pub(crate) struct SequenceRun<'a> {
    pub args: &'a RenderArgs,
    pub seq: SequenceArgs,
    pub output: &'a Path,
    pub format: ImageFormat,
    pub backend: &'a str,
    pub world: Option<&'a himmel_world::World>,
    pub world_stats: Option<serde_json::Value>,
    pub t_total: Clock,
}

impl SequenceRun<'_> {
    fn error(&self, e: SequenceError) -> CliError {
        match e {
            SequenceError::Scene(e) => scene_error(self.args, e),
            SequenceError::TimeStep(s) => CliError::input(format!(
                "--time-step {s}: times time.speed it must be a finite number of seconds within ±{:e}",
                himmel_skymodel::sequence::MAX_STEP_S
            )),
            SequenceError::Frames(n) => CliError::input(format!(
                "--frames {n}: expected a frame count in [1, {MAX_FRAMES}]"
            )),
            SequenceError::CameraPath { .. } => {
                let file = self
                    .args
                    .camera_path
                    .as_ref()
                    .map(|p| p.display().to_string())
                    .unwrap_or_default();
                CliError::input(format!("--camera-path {file}: {e}"))
            }
        }
    }

    /// Renders and writes every frame, then `--stats`.
    pub(crate) fn run(self, mut scene: Scene) -> Result<(), CliError> {
        let a = self.args;
        if self.seq.camera_path.is_some() && scene.camera.projection != Projection::Perspective {
            if a.projection.is_some() || a.scene.is_some() {
                return Err(CliError::input(format!(
                    "--camera-path: a camera path moves the perspective camera, not {} (use --projection perspective)",
                    scene.camera.projection.name()
                )));
            }
            scene.camera.projection = Projection::Perspective;
        }
        let seq = Sequence::new(
            scene,
            self.seq.frames,
            self.seq.time_step_s,
            self.seq.camera_path.clone(),
        )
        .map_err(|e| self.error(e))?;
        let n = seq.len();
        let mut renderer = FrameRenderer::new(self.backend, self.world)?;
        let adapt =
            seq.base().exposure == Exposure::Auto && self.format == ImageFormat::Png && n > 1;
        let bar = progress(u64::from(n) * if adapt { 2 } else { 1 });

        // Automatic exposure over the sequence: meter a preview of every
        // frame, then the rate-limited curve.
        let t_meter = Clock::now();
        let mut metered_preview = Vec::new();
        let mut preview_lut_source = None;
        if adapt {
            bar.set_message("metering");
            for k in 0..n {
                let f = seq.frame(k).map_err(|e| self.error(e))?;
                let small = renderer.name() == "cpu";
                let out = renderer.render(&preview(&f.scene, small), &f.state)?;
                preview_lut_source.get_or_insert(out.lut_source);
                metered_preview.push(meter_ev100(&out.image.pixels, &out.image.valid));
                bar.inc(1);
            }
        }
        let metering_ms = t_meter.elapsed().as_secs_f64() * 1e3;
        let curve = smooth_ev100(&metered_preview, seq.base().exposure_max_step_ev);

        bar.set_message("rendering");
        let mut first = None;
        let mut entries = Vec::with_capacity(n as usize);
        let mut frames_ms = 0.0;
        for f in seq.iter() {
            let f = f.map_err(|e| self.error(e))?;
            let mut scene = f.scene;
            if let Some(&ev) = curve.get(f.index as usize) {
                scene.exposure = Exposure::Ev100(ev);
            }
            let path = numbered(self.output, f.index, n);
            let w = render_frame(&mut renderer, &scene, &f.state, &path, self.format)?;
            let frame_ms = w.render_ms + w.write_ms;
            frames_ms += frame_ms;
            let passes: Vec<_> = w
                .out
                .passes
                .iter()
                .map(|p| json!({"name": p.name, "ran": p.ran, "ms": p.ms}))
                .collect();
            entries.push(json!({
                "index": f.index,
                "output": path.display().to_string(),
                "time_utc": format_utc(&f.state.utc),
                "elapsed_s": f.elapsed_s,
                "frame_ms": frame_ms,
                "render_ms": w.render_ms,
                "write_ms": w.write_ms,
                "precompute_ms": w.out.precompute_ms,
                "lut_source": w.out.lut_source,
                "sky_view_ms": w.out.sky_view_ms,
                "cloud_maps_ms": w.out.cloud_maps_ms,
                "cloud_grid_ms": w.out.cloud_grid_ms,
                "cloud_history": cloud_history_stats(&w.out),
                "passes": passes,
                "non_finite_pixels": w
                    .out
                    .image
                    .pixels
                    .iter()
                    .filter(|p| !p.iter().all(|c| c.is_finite()))
                    .count(),
                "ev100": w.ev100,
                "ev100_metered": w.ev100.map(|_| meter_ev100(&w.out.image.pixels, &w.out.image.valid)),
                "camera": {
                    "position_m": scene.camera.position_m,
                    "look_at_m": scene.camera.look_at_m,
                },
            }));
            if first.is_none() {
                first = Some(frame_stats(&renderer, &w, &f.state));
            }
            bar.inc(1);
        }
        bar.finish_and_clear();
        if let Some(path) = &a.stats {
            let mut stats = first.unwrap_or_else(|| json!({}));
            let total_ms = self.t_total.elapsed().as_secs_f64() * 1e3;
            stats["total_ms"] = json!(total_ms);
            stats["world"] = self.world_stats.clone().unwrap_or(serde_json::Value::Null);
            stats["sequence"] = json!({
                "frames": n,
                "time_step_s": self.seq.time_step_s,
                "step_s": seq.step_s(),
                "renderers_built": 1,
                "frames_ms": frames_ms,
                "average_frame_ms": frames_ms / f64::from(n),
                "exposure": if adapt { "auto-sequence" } else { "per-frame" },
                "exposure_max_step_ev": seq.base().exposure_max_step_ev,
                "metering_ms": metering_ms,
                "metering_lut_source": preview_lut_source,
                "metered_preview_ev100": metered_preview,
            });
            stats["frames"] = json!(entries);
            write_stats(path, &stats)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbered_names_are_padded_to_the_frame_count() {
        let p = Path::new("out/sky.png");
        assert_eq!(numbered(p, 7, 48), Path::new("out/sky_0007.png"));
        assert_eq!(numbered(p, 0, 1), Path::new("out/sky_0000.png"));
        assert_eq!(numbered(p, 12_345, 20_000), Path::new("out/sky_12345.png"));
        assert_eq!(numbered(p, 3, 10_001), Path::new("out/sky_00003.png"));
        assert_eq!(
            numbered(Path::new("a.b.exr"), 1, 2),
            Path::new("a.b_0001.exr")
        );
    }

    #[test]
    fn preview_keeps_the_aspect_within_the_side() {
        let mut s = Scene::default();
        s.camera.width = 1920;
        s.camera.height = 1080;
        let p = preview(&s, true);
        assert_eq!((p.camera.width, p.camera.height), (64, 36));
        s.camera.width = 32;
        s.camera.height = 32;
        assert_eq!(preview(&s, true).camera, s.camera);
        assert_eq!(preview(&s, false).lut, s.lut);
        assert_eq!((p.lut.sky_view_w, p.lut.sky_view_h), PREVIEW_SKY_VIEW);
        // Without a world the lighting keys are left alone; with one they
        // are capped, never raised.
        assert_eq!(p.lighting, s.lighting);
        s.world = Some(himmel_skymodel::WorldSpec {
            gltf: "room.glb".into(),
            ground: false,
        });
        s.lighting.sky.directions = 8;
        s.effects.push(Effect::Temporal);
        let w = preview(&s, false);
        assert_eq!(w.lighting.sky.directions, 8);
        assert_eq!(w.lighting.sky.visibility_resolution, 128);
        assert_eq!(w.lighting.shadows.resolution, 512);
        assert!(!w.effects.contains(&Effect::Temporal));
        assert!(w.lighting.validate().is_ok());
    }
}
