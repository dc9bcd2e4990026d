//! `himmel render --sky-texture …` (the flags of a texture-mapped sky,
//! [`apply_flags`]) and `himmel sky-texture convert`: resamples a sky texture into another
//! mapping (an equirect photograph into a uniform-density cube map, …),
//! keeping its solid-angle-weighted mean radiance
//! (`himmel_skymodel::texture_sky::convert`).

use std::path::PathBuf;

use clap::{Args, Subcommand};
use himmel_cpu::texture_io::{read_texture, write_texture};
use himmel_skymodel::texture_sky::{convert, Mapping, SkyTexture};

use himmel_skymodel::Scene;

use crate::render_cmd::RenderArgs;
use crate::CliError;

#[derive(Args, Debug)]
pub struct SkyTextureArgs {
    #[command(subcommand)]
    command: SkyTextureCommand,
}

#[derive(Subcommand, Debug)]
enum SkyTextureCommand {
    /// Resample a sky texture into another mapping and write it as EXR
    /// (linear; an LDR input is decoded from sRGB to linear 0 … 1).
    Convert(ConvertArgs),
}

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// The input image: PNG, JPEG (sRGB), EXR or Radiance HDR (linear).
    #[arg(value_name = "IN")]
    input: PathBuf,
    /// The input's mapping: polar, sphere, paraboloid, cube or cube-uniform.
    #[arg(long, value_name = "MAPPING", default_value = "sphere")]
    from: String,
    /// The output's mapping: cube-uniform (six faces, texels of nearly
    /// equal solid angle), cube, paraboloid, polar or sphere.
    #[arg(long, value_name = "MAPPING")]
    to: String,
    /// Texels per tile side: a cube's face size, a paraboloid half's or a
    /// polar image's side, a sphere's height (default: the input's height
    /// / 2 for cubes, its height otherwise).
    #[arg(long, value_name = "N")]
    face_size: Option<u32>,
    /// The output file (.exr).
    #[arg(long, value_name = "FILE")]
    output: PathBuf,
}

fn mapping(flag: &str, s: &str) -> Result<Mapping, CliError> {
    Mapping::from_name(s).ok_or_else(|| {
        CliError::input(format!(
            "{flag}: unknown mapping '{s}'; expected polar, sphere, paraboloid, cube or cube-uniform"
        ))
    })
}

/// Runs `himmel sky-texture …`.
pub fn run(a: &SkyTextureArgs) -> Result<(), CliError> {
    let SkyTextureCommand::Convert(c) = &a.command;
    let from = mapping("--from", &c.from)?;
    let to = mapping("--to", &c.to)?;
    let ext = c.output.extension().and_then(|e| e.to_str()).unwrap_or("");
    if !ext.eq_ignore_ascii_case("exr") {
        return Err(CliError::input(format!(
            "--output {}: expected an .exr file",
            c.output.display()
        )));
    }
    let d = read_texture(&c.input).map_err(|e| CliError::input(e.to_string()))?;
    let img = &d.image;
    from.check_size(img.width, img.height)
        .map_err(|e| CliError::input(format!("sky texture {}: {e}", c.input.display())))?;
    let n = match c.face_size {
        Some(0) => return Err(CliError::input("--face-size 0: must be at least 2")),
        Some(n) if n > 8192 => {
            return Err(CliError::input(format!("--face-size {n}: at most 8192")))
        }
        Some(n) => n,
        None if matches!(to, Mapping::Cube | Mapping::CubeUniform) => (img.height / 2).max(2),
        None => img.height.max(2),
    };
    let out = convert(&SkyTexture::new(from, img), to, n);
    write_texture(&c.output, &out).map_err(|e| CliError::other(format!("--output {e}")))?;
    Ok(())
}

/// Applies the `--sky-*` flags; a scene file's texture paths are taken
/// relative to the scene file.
pub(crate) fn apply_flags(a: &RenderArgs, scene: &mut Scene) -> Result<(), CliError> {
    use himmel_skymodel::texture_spec::{SunMaskSpec, TextureUnits};
    if let (Some(file), Some(spec)) = (&a.scene, &mut scene.sky_texture) {
        let dir = file.parent().unwrap_or(std::path::Path::new("."));
        let resolve = |p: &mut String| *p = dir.join(&*p).display().to_string();
        resolve(&mut spec.path);
        for t in &mut spec.transitions {
            resolve(&mut t.path);
        }
    }
    if let Some(p) = &a.sky_texture {
        let spec = scene.sky_texture.get_or_insert_with(Default::default);
        spec.path = p.display().to_string();
        if !scene.effects.contains(&himmel_skymodel::Effect::Texture) {
            scene.effects.push(himmel_skymodel::Effect::Texture);
        }
    }
    let given = a.sky_mapping.is_some()
        || a.sky_blend.is_some()
        || a.sky_units.is_some()
        || a.sky_keep.is_some()
        || a.sky_mask_sun;
    let Some(spec) = scene.sky_texture.as_mut() else {
        return if given {
            Err(CliError::input(
                "--sky-mapping/--sky-blend/--sky-units/--sky-keep/--sky-mask-sun need a sky texture (--sky-texture FILE)",
            ))
        } else {
            Ok(())
        };
    };
    if let Some(m) = &a.sky_mapping {
        spec.mapping = himmel_skymodel::texture_sky::Mapping::from_name(m).ok_or_else(|| {
            CliError::input(format!(
                "--sky-mapping: unknown mapping '{m}'; expected polar, sphere, paraboloid, cube or cube-uniform"
            ))
        })?;
    }
    if let Some(v) = a.sky_blend {
        spec.blend = crate::flag_values::finite("--sky-blend", v)?;
    }
    if let Some(u) = &a.sky_units {
        spec.units = match u.trim() {
            "native" => TextureUnits::Native,
            "sky" => TextureUnits::Sky,
            _ => {
                return Err(CliError::input(format!(
                    "--sky-units: unknown units '{u}'; expected native or sky"
                )))
            }
        };
    }
    if let Some(list) = &a.sky_keep {
        spec.keep = himmel_skymodel::texture_spec::KeptPass::parse_list(list)
            .map_err(|e| CliError::input(format!("--sky-keep: {e}")))?;
    }
    if a.sky_mask_sun && spec.sun_mask.is_none() {
        spec.sun_mask = Some(SunMaskSpec::default());
    }
    Ok(())
}
