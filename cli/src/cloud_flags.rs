//! The cloud flags of `himmel render`: `--clouds-coverage`,
//! `--clouds-type`, `--cirrus-coverage` and `--clouds-tier` onto the
//! scene's `clouds` keys.

use himmel_skymodel::scene::{LowCloudKind, LowCloudTier};
use himmel_skymodel::{Effect, Scene};

use crate::flag_values::finite;
use crate::CliError;

/// The cloud flags as given.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CloudFlags<'a> {
    /// `--clouds-type`.
    pub kind: Option<&'a str>,
    /// `--clouds-coverage`.
    pub coverage: Option<f64>,
    /// `--cirrus-coverage`.
    pub cirrus_coverage: Option<f64>,
    /// `--clouds-tier`.
    pub tier: Option<&'a str>,
    /// Whether `--effects` listed the effects.
    pub effects_listed: bool,
}

/// Applies `--clouds-coverage`, `--clouds-type` and `--cirrus-coverage`.
/// A flag that asks for clouds adds the `clouds` effect when `--effects`
/// did not list the effects.
pub(crate) fn apply(a: CloudFlags, scene: &mut Scene) -> Result<(), CliError> {
    let c = &mut scene.clouds;
    if let Some(t) = a.tier {
        c.low.tier = match t.trim().to_ascii_lowercase().as_str() {
            "volumetric" => LowCloudTier::Volumetric,
            "heightfield" => LowCloudTier::Heightfield,
            _ => {
                return Err(CliError::input(format!(
                    "--clouds-tier: unknown tier '{t}'; expected volumetric or heightfield"
                )))
            }
        };
    }
    let cirrus = match a.kind {
        None => false,
        Some(t) if t.trim().eq_ignore_ascii_case("cirrus") => true,
        Some(t) => {
            c.low.kind = LowCloudKind::from_name(t).ok_or_else(|| {
                CliError::input(format!(
                    "--clouds-type: unknown type '{t}'; expected cumulus, stratocumulus, stratus or cirrus"
                ))
            })?;
            false
        }
    };
    let cov = a
        .coverage
        .map(|v| finite("--clouds-coverage", v))
        .transpose()?;
    if cirrus {
        c.high.coverage = cov.unwrap_or(0.5);
        if let Some(v) = a.cirrus_coverage {
            c.high.coverage = finite("--cirrus-coverage", v)?;
        }
    } else {
        if let Some(v) = cov {
            c.low.coverage = v;
        } else if a.kind.is_some() && c.low.coverage == 0.0 {
            c.low.coverage = 0.5;
        }
        if let Some(v) = a.cirrus_coverage {
            c.high.coverage = finite("--cirrus-coverage", v)?;
        }
    }
    let asked = a.kind.is_some() || cov.is_some() || a.cirrus_coverage.is_some();
    if asked && !a.effects_listed && !scene.effects.contains(&Effect::Clouds) {
        scene.effects.push(Effect::Clouds);
    }
    Ok(())
}
