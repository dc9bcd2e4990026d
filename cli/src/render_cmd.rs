//! `himmel render` and `himmel scene-template` (spec/cli.md).

use std::path::PathBuf;
use std::time::Instant as Clock;

use clap::Args;
use himmel_cpu::output::{self, Format as ImageFormat};
use himmel_cpu::CpuRenderer;
use himmel_skymodel::camera::{CameraSettings, Exposure};
use himmel_skymodel::file::write_bytes;
use himmel_skymodel::overlay::OverlayGeometry;
use himmel_skymodel::scene::parse_effects;
use himmel_skymodel::{Projection, RenderError, RenderOutput, Scene, SkyRenderer, SkyState};
use serde_json::json;

use crate::common;
use crate::ephemeris_cmd::{parse_precision, parse_time};
use crate::flag_values::{finite, size, triple};
use crate::timearg::format_utc;
use crate::CliError;

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Instant: RFC 3339 civil UTC, a date, or `now` (dates before 1582-10-15 are Julian, as printed; signed and 5-digit years) (required unless the scene has one).
    #[arg(long, value_name = "TIME")]
    time: Option<String>,
    /// Geodetic latitude, degrees in [-90, 90].
    #[arg(long, value_name = "DEG")]
    lat: Option<f64>,
    /// East longitude, degrees in [-180, 180].
    #[arg(long, value_name = "DEG")]
    lon: Option<f64>,
    /// Elevation above the WGS84 ellipsoid, metres (default 0).
    #[arg(long, value_name = "M")]
    elevation: Option<f64>,
    /// Astronomy accuracy tier: low, standard or high.
    #[arg(long, value_name = "TIER")]
    precision: Option<String>,
    /// Image width in pixels (default 1024; a cube map is 6 × height wide).
    #[arg(long, value_name = "PX")]
    width: Option<u64>,
    /// Image height in pixels (default 1024).
    #[arg(long, value_name = "PX")]
    height: Option<u64>,
    /// fisheye, equirect, perspective or cubemap (default fisheye).
    #[arg(long, value_name = "NAME")]
    pub(crate) projection: Option<String>,
    /// Perspective camera azimuth, degrees from North through East, in [-720, 720].
    #[arg(long, value_name = "DEG")]
    yaw: Option<f64>,
    /// Perspective camera altitude, degrees in [-90, 90].
    #[arg(long, value_name = "DEG")]
    pitch: Option<f64>,
    /// Perspective vertical field of view, degrees in (0, 180).
    #[arg(long, value_name = "DEG")]
    fov: Option<f64>,
    /// cpu, wgpu or auto (default cpu).
    #[arg(long, value_name = "NAME", default_value = "cpu")]
    backend: String,
    /// Comma list of atmosphere, sun, moon, stars, planets, milkyway, texture, clouds.
    #[arg(long, value_name = "LIST")]
    effects: Option<String>,
    /// JSON scene file (see `himmel scene-template`); flags override it.
    #[arg(long, value_name = "FILE")]
    pub(crate) scene: Option<PathBuf>,
    /// `auto` or a fixed EV100.
    #[arg(long, value_name = "EV")]
    exposure: Option<String>,
    /// Drawn Moon size relative to the true one.
    #[arg(long, value_name = "K")]
    moon_scale: Option<f64>,
    /// Drawn Sun size relative to the true one (illuminance kept).
    #[arg(long, value_name = "K")]
    sun_scale: Option<f64>,
    /// Write render statistics (passes, times) as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub(crate) stats: Option<PathBuf>,
    /// Output image: FILE.png (tone-mapped sRGB) or FILE.exr (linear, cd/m²).
    #[arg(long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// A 3D world under the sky: a glTF 2.0 file (.gltf or .glb).
    #[arg(long, value_name = "FILE")]
    world: Option<PathBuf>,
    /// With a world: add an infinite ground plane at y = 0.
    #[arg(long)]
    ground: bool,
    /// Camera position in the world frame (x East, y Up, z South), metres.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    camera_pos: Option<String>,
    /// The world point the camera looks at, metres (replaces --yaw/--pitch).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    look_at: Option<String>,
    /// The camera's up hint with --look-at (default 0,1,0).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    up: Option<String>,
    /// Fog scattering coefficient, 1/m (adds a fog when the scene has none).
    #[arg(long, value_name = "PER_M")]
    fog_scattering: Option<f64>,
    /// Fog Henyey–Greenstein asymmetry g in (-1, 1).
    #[arg(long, value_name = "G", allow_hyphen_values = true)]
    fog_g: Option<f64>,
    /// Fog top, metres above the ground.
    #[arg(long, value_name = "M")]
    fog_top: Option<f64>,
    /// Instant by local apparent solar time: F × 24 h of the scene's local
    /// date, F in [0, 1) (0.25 = 06:00, 0.5 = the Sun on the meridian).
    #[arg(long, value_name = "F")]
    pub(crate) day_fraction: Option<f64>,
    /// Render a sequence of N frames, written as numbered files
    /// (`sky.png` → `sky_0000.png`, `sky_0001.png`, …; at least 4 digits).
    #[arg(long, value_name = "N")]
    pub(crate) frames: Option<u64>,
    /// Scene seconds between frames (may be negative; multiplied by the
    /// scene's time.speed): frame k is at t0 + k × step × speed.
    #[arg(long, value_name = "SECONDS", allow_hyphen_values = true)]
    pub(crate) time_step: Option<f64>,
    /// Camera keyframes for a sequence, JSON: {"keyframes": [{"frame": 0,
    /// "position_m": [x, y, z], "look_at_m": [x, y, z]}, …]} (or "time_s":
    /// scene seconds since the first frame instead of "frame"); linear
    /// between keyframes, held outside them.
    #[arg(long, value_name = "FILE")]
    pub(crate) camera_path: Option<PathBuf>,
    /// Chart overlay drawn into a PNG (never an EXR): comma list of
    /// constellations (the figures), labels (constellation, bright-star and
    /// planet names), or none; style from the scene's `overlay` key.
    #[arg(long, value_name = "LIST")]
    overlay: Option<String>,
    /// A texture-mapped sky: an image (PNG, JPEG: sRGB; EXR, HDR: linear,
    /// cd/m²) drawn instead of the physical sky (scene key `sky_texture`;
    /// adds the `texture` effect).
    #[arg(long, value_name = "FILE")]
    pub(crate) sky_texture: Option<PathBuf>,
    /// The sky texture's mapping: polar, sphere (equirect, default),
    /// paraboloid (2N×N), cube or cube-uniform (6N×N strips).
    #[arg(long, value_name = "NAME")]
    pub(crate) sky_mapping: Option<String>,
    /// The sky texture's weight over the physical sky, in [0, 1] (default 1:
    /// it replaces the atmosphere and every body not kept).
    #[arg(long, value_name = "A")]
    pub(crate) sky_blend: Option<f64>,
    /// `native` (HDR files in cd/m², LDR white = ldr_white_cd_m2) or `sky`
    /// (scaled to the physical sky's horizontal illuminance).
    #[arg(long, value_name = "UNITS")]
    pub(crate) sky_units: Option<String>,
    /// Physical passes drawn in front of the sky texture: a comma list of
    /// sun, moon, stars, planets.
    #[arg(long, value_name = "LIST")]
    pub(crate) sky_keep: Option<String>,
    /// Mask the sky texture's own sun (its brightest region, 3° radius);
    /// keep the physical Sun with --sky-keep sun.
    #[arg(long)]
    pub(crate) sky_mask_sun: bool,
    /// Low cloud layer's coverage in [0, 1] (scene key clouds.low.coverage;
    /// 0 = no low layer).
    #[arg(long, value_name = "C")]
    clouds_coverage: Option<f64>,
    /// Cloud type: cumulus, stratocumulus or stratus (the low layer,
    /// clouds.low.kind; coverage 0.5 unless set) or cirrus (the high
    /// layer, clouds.high; its coverage from --clouds-coverage, default 0.5).
    #[arg(long, value_name = "TYPE")]
    clouds_type: Option<String>,
    /// High cloud layer's (cirrus) coverage in [0, 1] (clouds.high.coverage).
    #[arg(long, value_name = "C")]
    cirrus_coverage: Option<f64>,
    /// How the low layer is drawn: volumetric (the ray march, default) or
    /// heightfield (the cheap height-field tier; clouds.low.tier).
    #[arg(long, value_name = "TIER")]
    clouds_tier: Option<String>,
}

#[derive(Args, Debug)]
pub struct TemplateArgs {
    /// Include a world, its camera, a fog and every lighting key.
    #[arg(long)]
    world: bool,
    /// Include a sky texture with every one of its keys.
    #[arg(long, conflicts_with = "world")]
    sky_texture: bool,
}

/// A scene error as a one-line input error naming the flag and the field:
/// `--lat (observer.lat_deg): …` when the flag set the value, else
/// `--scene FILE: field: …` (or `--scene (field): …` without a file).
pub(crate) fn scene_error(a: &RenderArgs, e: himmel_skymodel::SceneError) -> CliError {
    match (flag_of(a, &e.field), &a.scene) {
        (Some(flag), _) => CliError::input(format!("{flag} ({}): {}", e.field, e.message)),
        (None, Some(p)) => CliError::input(format!("--scene {}: {e}", p.display())),
        (None, None) => CliError::input(format!("--scene ({}): {}", e.field, e.message)),
    }
}

/// The flag that set a scene field on this command line, if one did (for
/// error messages).
fn flag_of(a: &RenderArgs, field: &str) -> Option<&'static str> {
    let (flag, given) = match field {
        "camera.width" => ("--width", a.width.is_some()),
        "camera.height" => ("--height", a.height.is_some()),
        "camera.fov_deg" => ("--fov", a.fov.is_some()),
        "camera.yaw_deg" => ("--yaw", a.yaw.is_some()),
        "camera.pitch_deg" => ("--pitch", a.pitch.is_some()),
        "observer.lat_deg" => ("--lat", a.lat.is_some()),
        "observer.lon_deg" => ("--lon", a.lon.is_some()),
        "observer.elevation_m" => ("--elevation", a.elevation.is_some()),
        "time.utc" => ("--time", a.time.is_some()),
        "precision" => ("--precision", a.precision.is_some()),
        "sun_scale" => ("--sun-scale", a.sun_scale.is_some()),
        "moon_scale" => ("--moon-scale", a.moon_scale.is_some()),
        "exposure" => ("--exposure", a.exposure.is_some()),
        "camera.position_m" => ("--camera-pos", a.camera_pos.is_some()),
        "camera.look_at_m" => ("--look-at", a.look_at.is_some()),
        "camera.up" => ("--up", a.up.is_some()),
        "fog.scattering_per_m" => ("--fog-scattering", a.fog_scattering.is_some()),
        "fog.phase.hg" => ("--fog-g", a.fog_g.is_some()),
        "fog.top_m" => ("--fog-top", a.fog_top.is_some()),
        "time.day_fraction" => ("--day-fraction", a.day_fraction.is_some()),
        "sky_texture.path" => ("--sky-texture", a.sky_texture.is_some()),
        "sky_texture.blend" => ("--sky-blend", a.sky_blend.is_some()),
        "clouds.low.coverage" => ("--clouds-coverage", a.clouds_coverage.is_some()),
        "clouds.high.coverage" => ("--cirrus-coverage", a.cirrus_coverage.is_some()),
        _ => return None,
    };
    // Without a scene file every value comes from a flag or its default.
    (given || a.scene.is_none()).then_some(flag)
}

/// Builds the scene from the file and the flags.
fn build_scene(a: &RenderArgs) -> Result<Scene, CliError> {
    let mut scene = match &a.scene {
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|e| {
                CliError::input(format!("--scene {}: cannot read ({e})", p.display()))
            })?;
            Scene::from_json(&text)
                .map_err(|e| CliError::input(format!("--scene {}: {e}", p.display())))?
        }
        None => {
            let mut s = Scene::default();
            if a.time.is_none() {
                return Err(CliError::input(
                    "--time is required (RFC 3339 UTC, e.g. 2024-04-08T18:42:00Z, or now)",
                ));
            }
            common::required("--lat", a.lat, "degrees in [-90, 90]")?;
            common::required("--lon", a.lon, "degrees east in [-180, 180]")?;
            s.time.utc = String::new();
            s
        }
    };
    if let Some(t) = &a.time {
        let utc = parse_time(t).map_err(CliError::input)?;
        scene.time.utc = format_utc(&utc);
    }
    if let Some(f) = a.day_fraction {
        scene.time.day_fraction = Some(f);
    }
    if let Some(v) = a.lat {
        scene.observer.lat_deg = common::check_input("--lat", v, -90.0, 90.0)?;
    }
    if let Some(v) = a.lon {
        scene.observer.lon_deg = common::check_input("--lon", v, -360.0, 360.0)?;
    }
    if let Some(v) = a.elevation {
        scene.observer.elevation_m = finite("--elevation", v)?;
    }
    if let Some(p) = &a.precision {
        parse_precision(p).map_err(CliError::input)?;
        scene.precision = p.trim().to_ascii_lowercase();
    }
    if let Some(v) = a.width {
        scene.camera.width = size("--width", v)?;
    }
    if let Some(v) = a.height {
        scene.camera.height = size("--height", v)?;
    }
    if let Some(p) = &a.projection {
        scene.camera.projection = Projection::from_name(p).ok_or_else(|| {
            CliError::input(format!(
                "--projection: unknown projection '{p}'; expected fisheye, equirect, perspective or cubemap"
            ))
        })?;
    }
    if let Some(v) = a.yaw {
        scene.camera.yaw_deg = finite("--yaw", v)?;
    }
    if let Some(v) = a.pitch {
        scene.camera.pitch_deg = finite("--pitch", v)?;
    }
    if let Some(v) = a.fov {
        scene.camera.fov_deg = finite("--fov", v)?;
    }
    if let Some(list) = &a.effects {
        scene.effects =
            parse_effects(list).map_err(|e| CliError::input(format!("--effects: {e}")))?;
    }
    if let Some(e) = &a.exposure {
        scene.exposure = Exposure::parse(e).ok_or_else(|| {
            CliError::input(format!(
                "--exposure: '{e}' is neither auto nor an EV100 number in [-30, 40]"
            ))
        })?;
    }
    if let Some(list) = &a.overlay {
        scene
            .overlay
            .set_parts(list)
            .map_err(|e| CliError::input(format!("--overlay: {e}")))?;
    }
    if let Some(v) = a.sun_scale {
        scene.sun_scale = finite("--sun-scale", v)?;
    }
    if let Some(v) = a.moon_scale {
        scene.moon_scale = finite("--moon-scale", v)?;
    }
    if let Some(w) = &a.world {
        scene.world = Some(himmel_skymodel::WorldSpec {
            gltf: w.display().to_string(),
            ground: a.ground,
        });
    } else if a.ground {
        match &mut scene.world {
            Some(w) => w.ground = true,
            None => return Err(CliError::input("--ground needs a world (--world FILE)")),
        }
    }
    if let Some(t) = &a.camera_pos {
        scene.camera.position_m = Some(triple("--camera-pos", t)?);
    }
    if let Some(t) = &a.look_at {
        scene.camera.look_at_m = Some(triple("--look-at", t)?);
    }
    if let Some(t) = &a.up {
        scene.camera.up = Some(triple("--up", t)?);
    }
    if a.camera_pos.is_some() || a.look_at.is_some() {
        // A placed camera is a perspective camera (world.md).
        if a.projection.is_none() {
            scene.camera.projection = Projection::Perspective;
        }
    }
    if a.fog_scattering.is_some() || a.fog_g.is_some() || a.fog_top.is_some() {
        let fog = scene.fog.get_or_insert_with(Default::default);
        if let Some(v) = a.fog_scattering {
            fog.scattering_per_m = finite("--fog-scattering", v)?;
        }
        if let Some(g) = a.fog_g {
            fog.phase = himmel_skymodel::FogPhase::Hg(finite("--fog-g", g)?);
        }
        if let Some(v) = a.fog_top {
            fog.top_m = Some(finite("--fog-top", v)?);
        }
    }
    crate::texture_cmd::apply_flags(a, &mut scene)?;
    crate::cloud_flags::apply(
        crate::cloud_flags::CloudFlags {
            kind: a.clouds_type.as_deref(),
            coverage: a.clouds_coverage,
            cirrus_coverage: a.cirrus_coverage,
            tier: a.clouds_tier.as_deref(),
            effects_listed: a.effects.is_some(),
        },
        &mut scene,
    )?;
    if scene.world.is_some() && a.projection.is_none() && a.scene.is_none() {
        scene.camera.projection = Projection::Perspective;
    }
    scene.validate().map_err(|e| scene_error(a, e))?;
    Ok(scene)
}

/// Loads the scene's world, if it has one: `world.gltf` relative to the
/// scene file (to the working directory for `--world`). A file that cannot
/// be read or parsed exits 2 naming it; ignored content is reported on
/// stderr, one `warning:` line each.
fn load_world(a: &RenderArgs, scene: &Scene) -> Result<Option<himmel_world::World>, CliError> {
    let Some(spec) = &scene.world else {
        return Ok(None);
    };
    // Where the error points: the flag, or the scene file's field.
    let (context, path) = match (&a.world, &a.scene) {
        (Some(p), _) => ("--world".to_string(), p.clone()),
        (None, Some(s)) => (
            format!("--scene {}: world.gltf:", s.display()),
            s.parent()
                .unwrap_or(std::path::Path::new("."))
                .join(&spec.gltf),
        ),
        (None, None) => ("--world".to_string(), PathBuf::from(&spec.gltf)),
    };
    let world = himmel_world::gltf_io::load(&path)
        .map_err(|e| CliError::input(format!("{context} {e}")))?;
    for w in &world.warnings {
        eprintln!("warning: {w}");
    }
    Ok(Some(world))
}

pub fn run(a: &RenderArgs) -> Result<(), CliError> {
    let t_total = Clock::now();
    let output = a
        .output
        .as_ref()
        .ok_or_else(|| CliError::input("--output is required (FILE.png or FILE.exr)"))?;
    let format = ImageFormat::of(output).ok_or_else(|| {
        CliError::input(format!(
            "--output {}: unsupported extension; expected .png or .exr",
            output.display()
        ))
    })?;
    let backend = a.backend.trim();
    if !matches!(backend, "cpu" | "wgpu" | "auto") {
        return Err(CliError::input(format!(
            "--backend: unknown backend '{backend}'; expected cpu, wgpu or auto"
        )));
    }
    let scene = build_scene(a)?;
    if scene.overlay.is_on() && format == ImageFormat::Exr {
        eprintln!("note: the overlay is drawn into PNG images only; the EXR keeps the radiance");
    }
    let sequence = crate::sequence_cmd::SequenceArgs::of(a)?;
    let t_world = Clock::now();
    let world = load_world(a, &scene)?;
    let world_load_ms = t_world.elapsed().as_secs_f64() * 1e3;
    if world.is_some() && backend == "cpu" {
        // World rendering belongs to the wgpu backend (world.md).
        return Err(CliError {
            code: 3,
            message: "--backend cpu cannot render a 3D world; use --backend wgpu".into(),
        });
    }
    let world_stats = world.as_ref().map(|w| {
        json!({
            "triangles": w.triangles(),
            "materials": w.materials.len(),
            "load_ms": world_load_ms,
        })
    });
    if let Some(seq) = sequence {
        let run = crate::sequence_cmd::SequenceRun {
            args: a,
            seq,
            output,
            format,
            backend,
            world: world.as_ref(),
            world_stats,
            t_total,
        };
        return run.run(scene);
    }
    let state = SkyState::at(&scene).map_err(|e| scene_error(a, e))?;
    let mut renderer = FrameRenderer::new(backend, world.as_ref())?;
    let frame = render_frame(&mut renderer, &scene, &state, output, format)?;
    if let Some(path) = &a.stats {
        let mut stats = frame_stats(&renderer, &frame, &state);
        stats["total_ms"] = json!(t_total.elapsed().as_secs_f64() * 1e3);
        stats["world"] = world_stats.unwrap_or(serde_json::Value::Null);
        write_stats(path, &stats)?;
    }
    Ok(())
}

/// The renderer of one `himmel render` run, built once for all its frames
/// (device, LUTs, pipelines), with how it times passes.
pub(crate) struct FrameRenderer {
    renderer: Box<dyn SkyRenderer>,
    /// `cpu` or `gpu-timestamps`.
    pub timing: &'static str,
    /// The `--backend` asked for (`cpu`, `wgpu`, `auto`).
    backend: String,
    /// Renderer creation, ms.
    pub init_ms: f64,
}

impl FrameRenderer {
    /// The renderer for `--backend` (and the world, if any).
    pub(crate) fn new(
        backend: &str,
        world: Option<&himmel_world::World>,
    ) -> Result<FrameRenderer, CliError> {
        let t_init = Clock::now();
        let (renderer, timing) = match world {
            Some(w) => make_world_renderer(backend, w)?,
            None => make_renderer(backend)?,
        };
        Ok(FrameRenderer {
            renderer,
            timing,
            backend: backend.to_string(),
            init_ms: t_init.elapsed().as_secs_f64() * 1e3,
        })
    }

    /// The backend's name as `--stats` reports it.
    pub(crate) fn name(&self) -> &'static str {
        self.renderer.name()
    }

    /// Renders one frame; with `--backend auto`, a frame the GPU cannot
    /// hold (its buffer or texture limits) falls back to the CPU for good.
    pub(crate) fn render(
        &mut self,
        scene: &Scene,
        state: &SkyState,
    ) -> Result<RenderOutput, CliError> {
        match self.renderer.render(scene, state) {
            Ok(out) => Ok(out),
            Err(RenderError::Unavailable(m)) if self.backend == "auto" => {
                eprintln!("note: {m}; falling back to --backend cpu");
                (self.renderer, self.timing) = (cpu_renderer(), "cpu");
                self.renderer
                    .render(scene, state)
                    .map_err(|e| CliError::other(e.to_string()))
            }
            Err(RenderError::Unavailable(m)) => Err(CliError {
                code: 3,
                message: format!(
                    "--backend {}: {m}; use --backend cpu (or auto) instead",
                    self.backend
                ),
            }),
            // A sky texture that cannot be read is bad input (exit 2).
            Err(RenderError::Texture(e)) => Err(CliError::input(e.to_string())),
            Err(e) => Err(CliError::other(e.to_string())),
        }
    }
}

/// A rendered and written frame.
pub(crate) struct WrittenFrame {
    /// The renderer's output (HDR image, passes, lights).
    pub out: RenderOutput,
    /// The frame incl. read-back, ms.
    pub render_ms: f64,
    /// The file write (camera stage included for a PNG), ms.
    pub write_ms: f64,
    /// The EV100 of a PNG's camera stage (none for an EXR).
    pub ev100: Option<f64>,
    /// The chart overlay (geometry and drawing; part of `write_ms`), ms.
    pub overlay_ms: f64,
}

/// Renders one frame of `scene` at `state` and writes it to `output`: the
/// EXR holds the absolute radiance, the PNG the camera stage at
/// `scene.exposure`. The single-frame and the sequence paths both call it.
pub(crate) fn render_frame(
    renderer: &mut FrameRenderer,
    scene: &Scene,
    state: &SkyState,
    output: &std::path::Path,
    format: ImageFormat,
) -> Result<WrittenFrame, CliError> {
    let t_render = Clock::now();
    let out = renderer.render(scene, state)?;
    let render_ms = t_render.elapsed().as_secs_f64() * 1e3;
    let t_write = Clock::now();
    let overlay_ms = std::cell::Cell::new(0.0);
    let ev100 = match format {
        ImageFormat::Exr => {
            output::write_exr(output, &out.image).map_err(|e| write_error("--output", e))?;
            None
        }
        ImageFormat::Png => {
            let settings = CameraSettings {
                exposure: scene.exposure,
                night_vision: scene.night_vision,
                dither: scene.dither,
            };
            let t_overlay = Clock::now();
            let overlay = if scene.overlay.is_on() {
                let g = OverlayGeometry::build(scene, state)
                    .map_err(|e| CliError::other(format!("overlay: {e}")))?;
                Some(g)
            } else {
                None
            };
            let geometry_ms = t_overlay.elapsed().as_secs_f64() * 1e3;
            let (w, h) = (out.image.width, out.image.height);
            let draw = |rgb8: &mut [u8]| {
                let t = Clock::now();
                let r = match &overlay {
                    Some(g) => himmel_cpu::overlay::draw(rgb8, w, h, g, &scene.overlay),
                    None => Ok(()),
                };
                overlay_ms.set(geometry_ms + t.elapsed().as_secs_f64() * 1e3);
                r
            };
            // Without an overlay the camera stage and the encoder overlap.
            let written = match overlay {
                Some(_) => output::write_png_overlaid(output, &out.image, &settings, draw),
                None => output::write_png(output, &out.image, &settings),
            };
            Some(written.map_err(|e| write_error("--output", e))?)
        }
    };
    Ok(WrittenFrame {
        out,
        render_ms,
        write_ms: t_write.elapsed().as_secs_f64() * 1e3,
        ev100,
        overlay_ms: overlay_ms.get(),
    })
}

/// `--stats`' `cloud_history`: whether the low layer's coarse grid came
/// from the last frame (temporal reprojection, both backends), why not, and
/// the nodes reused and marched; null without an amortised march.
pub(crate) fn cloud_history_stats(out: &himmel_skymodel::RenderOutput) -> serde_json::Value {
    match &out.cloud_history {
        None => serde_json::Value::Null,
        Some(h) => json!({
            "used": h.miss.is_none(),
            "why_not": h.miss.map(|m| m.to_string()),
            "nodes_reused": h.reused,
            "nodes_marched": h.marched,
            "nodes_marched_light_moved": h.light_moved,
        }),
    }
}

/// The single-frame `--stats` fields of a frame (`total_ms` and `world`
/// are the caller's).
pub(crate) fn frame_stats(
    renderer: &FrameRenderer,
    frame: &WrittenFrame,
    state: &SkyState,
) -> serde_json::Value {
    let out = &frame.out;
    let sun_direct = direct_stats(out.lights.direct.sun.as_ref());
    json!({
        "backend": renderer.name(),
        "timing": renderer.timing,
        "width": out.image.width,
        "height": out.image.height,
        "passes": out.passes,
        "total_ms": serde_json::Value::Null,
        "init_ms": renderer.init_ms,
        "render_ms": frame.render_ms,
        "precompute_ms": out.precompute_ms,
        "lut_source": out.lut_source,
        "geometry_ms": out.geometry_ms,
        "sky_view_ms": out.sky_view_ms,
        "cloud_maps_ms": out.cloud_maps_ms,
        "cloud_grid_ms": out.cloud_grid_ms,
        "cloud_history": cloud_history_stats(out),
        "write_ms": frame.write_ms,
        "overlay_ms": frame.overlay_ms,
        "ev100": frame.ev100,
        "time_utc": format_utc(&state.utc),
        "sun": {
            "alt_deg": state.sun.alt_deg,
            "alt_refracted_deg": state.sun.alt_refracted_deg,
            "az_deg": state.sun.az_deg,
            "distance_km": state.sun.distance_km,
            "semidiameter_deg": state.sun.angular_radius.to_degrees(),
            "illuminance_lux": state.sun.illuminance_lux,
            "visible_fraction": state.sun.visible_fraction,
            "direct_illuminance_lux": sun_direct.0,
            "direct_rgb": sun_direct.1,
        },
        "moon": moon_stats(&state.moon, direct_stats(out.lights.direct.moon.as_ref())),
        "world": serde_json::Value::Null,
        "sky": {
            "horizontal_illuminance_lux": himmel_skymodel::frame::lights::luminance(out.lights.sky_horizontal_rgb),
            "horizontal_rgb": out.lights.sky_horizontal_rgb,
        },
    })
}

/// Writes `--stats` (pretty JSON).
pub(crate) fn write_stats(
    path: &std::path::Path,
    stats: &serde_json::Value,
) -> Result<(), CliError> {
    let text = serde_json::to_string_pretty(stats).map_err(|e| CliError::other(e.to_string()))?;
    write_bytes(path, (text + "\n").as_bytes()).map_err(|e| write_error("--stats", e.to_string()))
}

/// A failed file write (exit 1): `FLAG FILE: what failed`.
pub(crate) fn write_error(flag: &str, e: String) -> CliError {
    CliError::other(format!("{flag} {e}"))
}

fn cpu_renderer() -> Box<dyn SkyRenderer> {
    let mut r = CpuRenderer::new(himmel_cpu::default_cache_dir());
    r.set_progress(true);
    Box::new(r)
}

/// The renderer for `--backend` and how it times passes (`cpu`, or
/// `gpu-timestamps` on an adapter with timestamp queries): `wgpu` without an
/// adapter exits 3; `auto` falls back to the CPU with a note on stderr.
fn make_renderer(backend: &str) -> Result<(Box<dyn SkyRenderer>, &'static str), CliError> {
    let cpu = cpu_renderer;
    if backend == "cpu" {
        return Ok((cpu(), "cpu"));
    }
    // Mesa's implicit device-select Vulkan layer probes for a Wayland
    // display and prints "error: XDG_RUNTIME_DIR is invalid …" on headless
    // machines; wgpu chooses the adapter itself, so skip the layer (this
    // process only, before any other thread exists).
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
    match himmel_wgpu::WgpuRenderer::new(himmel_cpu::default_cache_dir()) {
        Ok(mut r) => {
            r.set_progress(Some(std::sync::Arc::new(
                himmel_cpu::TerminalProgress::default(),
            )));
            r.set_texture_loader(std::sync::Arc::new(himmel_cpu::texture_io::ImageLoader));
            let timing = r.timing().name();
            Ok((Box::new(r), timing))
        }
        Err(e) if backend == "auto" => {
            eprintln!("note: {e}; falling back to --backend cpu");
            Ok((cpu(), "cpu"))
        }
        Err(e) => Err(CliError {
            code: 3,
            message: format!("--backend wgpu: {e}; use --backend cpu (or auto) instead"),
        }),
    }
}

/// The wgpu renderer with `world` uploaded (worlds are the wgpu backend's,
/// world.md): without an adapter `wgpu` and `auto` exit 3 alike, as there
/// is no CPU fallback for a world.
fn make_world_renderer(
    backend: &str,
    world: &himmel_world::World,
) -> Result<(Box<dyn SkyRenderer>, &'static str), CliError> {
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
    match himmel_wgpu::WgpuRenderer::new(himmel_cpu::default_cache_dir()) {
        Ok(mut r) => {
            r.set_progress(Some(std::sync::Arc::new(
                himmel_cpu::TerminalProgress::default(),
            )));
            r.set_world(world);
            r.set_texture_loader(std::sync::Arc::new(himmel_cpu::texture_io::ImageLoader));
            let timing = r.timing().name();
            Ok((Box::new(r), timing))
        }
        Err(e) => Err(CliError {
            code: 3,
            message: format!(
                "--backend {backend}: {e}; 3D worlds need a wgpu adapter (lavapipe serves without a GPU)"
            ),
        }),
    }
}

/// `himmel scene-template [--world | --sky-texture]`: prints the complete
/// default scene (with `--world`, also the world, camera placement, fog and
/// lighting keys; with `--sky-texture`, every `sky_texture` key).
pub fn template(a: &TemplateArgs) -> Result<(), CliError> {
    use std::io::Write;
    let text = if a.world {
        Scene::template_world_json()
    } else if a.sky_texture {
        Scene::template_sky_texture_json()
    } else {
        Scene::template_json()
    };
    // A reader that stops early (`| head`) ends the program quietly.
    writeln!(std::io::stdout().lock(), "{text}").map_err(CliError::stdout)
}

/// A directional light's `--stats` fields (zero when it does not light).
fn direct_stats(l: Option<&himmel_skymodel::frame::DirectLight>) -> (f64, [f64; 3]) {
    l.map_or((0.0, [0.0; 3]), |l| (l.lux(), l.rgb))
}

/// The Moon's block of `--stats`: place, size, phase, magnitude and, near a
/// lunar eclipse, the eclipse magnitudes.
fn moon_stats(m: &himmel_skymodel::moon::MoonState, direct: (f64, [f64; 3])) -> serde_json::Value {
    json!({
        "direct_illuminance_lux": direct.0,
        "direct_rgb": direct.1,
        "alt_deg": m.alt_deg,
        "alt_refracted_deg": m.alt_refracted_deg,
        "az_deg": m.az_deg,
        "distance_km": m.distance_km,
        "semidiameter_deg": m.angular_radius.to_degrees(),
        "phase_angle_deg": m.phase_angle.to_degrees(),
        "illuminated_fraction": m.illuminated_fraction,
        "bright_limb_pa_deg": m.bright_limb_pa.to_degrees(),
        "parallactic_angle_deg": m.parallactic_angle.to_degrees(),
        "magnitude": m.magnitude,
        "earthshine_lux": m.earthshine_lux,
        "umbral_magnitude": m.eclipse.map(|e| e.umbral_magnitude),
        "penumbral_magnitude": m.eclipse.map(|e| e.penumbral_magnitude),
    })
}
