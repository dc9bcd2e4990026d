//! The scene key `sky_texture`: a texture-mapped sky drawn instead of, or
//! blended over, the physical atmosphere (`crate::texture_sky` for the
//! mappings, `crate::frame::texture` for what a frame draws).

use serde::{Deserialize, Serialize};

use crate::scene_error::SceneError;
use crate::texture_sky::Mapping;
use crate::units::show;

/// A physical pass that can be kept in front of the texture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum KeptPass {
    /// The Sun's disk.
    Sun,
    /// The Moon.
    Moon,
    /// The catalogue stars.
    Stars,
    /// Mercury–Saturn.
    Planets,
}

impl KeptPass {
    /// Every pass that can be kept.
    pub const ALL: [KeptPass; 4] = [
        KeptPass::Sun,
        KeptPass::Moon,
        KeptPass::Stars,
        KeptPass::Planets,
    ];

    /// Its name (the effect's).
    pub fn name(self) -> &'static str {
        match self {
            KeptPass::Sun => "sun",
            KeptPass::Moon => "moon",
            KeptPass::Stars => "stars",
            KeptPass::Planets => "planets",
        }
    }

    /// Parses a comma list of names (`--sky-keep`), naming a bad entry.
    pub fn parse_list(list: &str) -> Result<Vec<KeptPass>, String> {
        let mut out = Vec::new();
        for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let k = KeptPass::ALL
                .into_iter()
                .find(|k| k.name().eq_ignore_ascii_case(name))
                .ok_or_else(|| {
                    format!("'{name}' cannot be kept in front of a sky texture; expected a comma list of sun, moon, stars, planets")
                })?;
            if !out.contains(&k) {
                out.push(k);
            }
        }
        Ok(out)
    }
}

/// How the texture's values become radiance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TextureUnits {
    /// In its own units: an HDR file's (EXR, HDR) values are cd/m² (linear
    /// sRGB, Y = 0.2126 R + 0.7152 G + 0.0722 B); an LDR file's (PNG,
    /// JPEG) linear values times `ldr_white_cd_m2`.
    Native,
    /// Scaled so that its horizontal illuminance (the cosine-weighted
    /// integral of its luminance over the upper hemisphere, after the sun
    /// mask and rotation) equals the physical sky's at the instant (the
    /// sky dome without the Sun's disk, as `--stats`'
    /// `sky.horizontal_illuminance_lux`); needs the atmosphere effect.
    Sky,
}

/// How the texture turns about the observer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RotationMode {
    /// Turned by `azimuth_deg` about the zenith, fixed.
    Fixed,
    /// Turned about the zenith by `azimuth_deg` + `rate_deg_per_h` × the
    /// hours since `reference_utc` (towards East: a positive rate moves
    /// the texture's North towards East).
    Rate,
    /// Turned with the stars: about the celestial pole by the Earth's
    /// sidereal rotation (15.041 068 6°/h) since `reference_utc`, the
    /// instant the texture shows (a star photograph stays on the stars),
    /// after the fixed `azimuth_deg`.
    Sidereal,
}

/// The texture's rotation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RotationSpec {
    /// `fixed` (default), `rate` or `sidereal`.
    pub mode: RotationMode,
    /// Azimuth the texture's North is turned to, degrees in [−360, 360]
    /// (default 0).
    pub azimuth_deg: f64,
    /// With `rate`: degrees per hour in [−1e6, 1e6] (default 0).
    pub rate_deg_per_h: f64,
    /// With `rate` and `sidereal`: the instant of zero turn, RFC 3339 UTC
    /// (default 2000-01-01T12:00:00Z).
    pub reference_utc: String,
}

impl Default for RotationSpec {
    fn default() -> Self {
        RotationSpec {
            mode: RotationMode::Fixed,
            azimuth_deg: 0.0,
            rate_deg_per_h: 0.0,
            reference_utc: "2000-01-01T12:00:00Z".into(),
        }
    }
}

/// A band of colour over the texture at the horizon.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HorizonSpec {
    /// Its radiance, linear sRGB cd/m², each in [0, 1e9] (default a grey
    /// of 1 000 cd/m²).
    pub color_cd_m2: [f64; 3],
    /// Its top, degrees of altitude in [−90, 90] (default 5): the band
    /// covers everything below.
    pub height_deg: f64,
    /// The width of its smooth (smoothstep) edge above `height_deg`,
    /// degrees in [0, 90] (default 2; 0 = a hard edge).
    pub softness_deg: f64,
}

impl Default for HorizonSpec {
    fn default() -> Self {
        HorizonSpec {
            color_cd_m2: [1000.0; 3],
            height_deg: 5.0,
            softness_deg: 2.0,
        }
    }
}

/// A direction in the texture's own frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureDirection {
    /// Azimuth from North through East, degrees in [−360, 360].
    pub az_deg: f64,
    /// Altitude, degrees in [−90, 90].
    pub alt_deg: f64,
}

/// The texture's own sun, masked out (`SkyTexture::with_masked_sun`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SunMaskSpec {
    /// Where the texture's sun is, in the texture's frame (before the
    /// rotation); default none: found as the brightest region.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub direction: Option<TextureDirection>,
    /// The masked radius, degrees in (0, 45] (default 3).
    pub radius_deg: f64,
}

impl Default for SunMaskSpec {
    fn default() -> Self {
        SunMaskSpec {
            direction: None,
            radius_deg: 3.0,
        }
    }
}

/// A timed change to another texture: from `at_utc` the sky cross-fades
/// over `fade_s` seconds from the texture shown before to this one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransitionSpec {
    /// The image file.
    pub path: String,
    /// Its mapping (default: the first texture's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mapping: Option<Mapping>,
    /// When the cross-fade starts, RFC 3339 UTC (scene time).
    pub at_utc: String,
    /// The cross-fade's duration, seconds in [0, 1e9] (default 0: a cut).
    #[serde(default)]
    pub fade_s: f64,
}

/// A texture-mapped sky (scene key `sky_texture`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SkyTextureSpec {
    /// The image file (PNG, JPEG: sRGB; EXR, Radiance HDR: linear).
    pub path: String,
    /// `polar`, `sphere` (default), `paraboloid`, `cube` or
    /// `cube-uniform` (`crate::texture_sky`).
    pub mapping: Mapping,
    /// `native` (default) or `sky` ([`TextureUnits`]).
    pub units: TextureUnits,
    /// The luminance of an LDR file's white, cd/m², in [1e-6, 1e9]
    /// (default 5 000: a bright overcast or a clear daytime sky).
    pub ldr_white_cd_m2: f64,
    /// The texture's weight over the physical sky, in [0, 1] (default 1:
    /// it replaces the atmosphere, the Milky Way and every physical
    /// body not kept).
    pub blend: f64,
    /// Physical passes drawn in front of the texture: any of `sun`,
    /// `moon`, `stars`, `planets` (default none).
    pub keep: Vec<KeptPass>,
    /// The rotation (default fixed at 0°).
    pub rotation: RotationSpec,
    /// A horizon band (default none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub horizon: Option<HorizonSpec>,
    /// The texture's own sun masked out (default none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sun_mask: Option<SunMaskSpec>,
    /// Timed changes to other textures, in time order (default none).
    pub transitions: Vec<TransitionSpec>,
}

impl Default for SkyTextureSpec {
    fn default() -> Self {
        SkyTextureSpec {
            path: "sky.exr".into(),
            mapping: Mapping::Sphere,
            units: TextureUnits::Native,
            ldr_white_cd_m2: 5000.0,
            blend: 1.0,
            keep: Vec::new(),
            rotation: RotationSpec::default(),
            horizon: None,
            sun_mask: None,
            transitions: Vec::new(),
        }
    }
}

impl SkyTextureSpec {
    /// A spec with every key filled (`himmel scene-template --sky-texture`).
    pub fn template() -> SkyTextureSpec {
        SkyTextureSpec {
            keep: vec![KeptPass::Sun, KeptPass::Moon],
            horizon: Some(HorizonSpec::default()),
            sun_mask: Some(SunMaskSpec {
                direction: Some(TextureDirection {
                    az_deg: 180.0,
                    alt_deg: 30.0,
                }),
                radius_deg: 3.0,
            }),
            transitions: vec![TransitionSpec {
                path: "dusk.exr".into(),
                mapping: Some(Mapping::Sphere),
                at_utc: "2024-06-21T18:00:00Z".into(),
                fade_s: 600.0,
            }],
            ..SkyTextureSpec::default()
        }
    }

    /// Checks every value against its range, naming the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        let p = "sky_texture";
        let r = &self.rotation;
        let mut checks = vec![
            (
                format!("{p}.ldr_white_cd_m2"),
                self.ldr_white_cd_m2,
                1e-6,
                1e9,
            ),
            (format!("{p}.blend"), self.blend, 0.0, 1.0),
            (
                format!("{p}.rotation.azimuth_deg"),
                r.azimuth_deg,
                -360.0,
                360.0,
            ),
            (
                format!("{p}.rotation.rate_deg_per_h"),
                r.rate_deg_per_h,
                -1e6,
                1e6,
            ),
        ];
        if let Some(h) = &self.horizon {
            for (k, c) in h.color_cd_m2.iter().enumerate() {
                checks.push((format!("{p}.horizon.color_cd_m2[{k}]"), *c, 0.0, 1e9));
            }
            checks.push((format!("{p}.horizon.height_deg"), h.height_deg, -90.0, 90.0));
            checks.push((
                format!("{p}.horizon.softness_deg"),
                h.softness_deg,
                0.0,
                90.0,
            ));
        }
        if let Some(m) = &self.sun_mask {
            if let Some(d) = &m.direction {
                checks.push((
                    format!("{p}.sun_mask.direction.az_deg"),
                    d.az_deg,
                    -360.0,
                    360.0,
                ));
                checks.push((
                    format!("{p}.sun_mask.direction.alt_deg"),
                    d.alt_deg,
                    -90.0,
                    90.0,
                ));
            }
            checks.push((format!("{p}.sun_mask.radius_deg"), m.radius_deg, 1e-3, 45.0));
        }
        for (k, t) in self.transitions.iter().enumerate() {
            checks.push((format!("{p}.transitions[{k}].fade_s"), t.fade_s, 0.0, 1e9));
        }
        for (f, v, lo, hi) in checks {
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                return Err(SceneError::new(
                    &f,
                    format!("{} is outside [{}, {}]", show(v), show(lo), show(hi)),
                ));
            }
        }
        if self.path.trim().is_empty() {
            return Err(SceneError::new(
                &format!("{p}.path"),
                "expected an image file",
            ));
        }
        parse_time(&format!("{p}.rotation.reference_utc"), &r.reference_utc)?;
        let mut last = f64::NEG_INFINITY;
        for (k, t) in self.transitions.iter().enumerate() {
            let f = format!("{p}.transitions[{k}].at_utc");
            let jd = parse_time(&f, &t.at_utc)?;
            if jd < last {
                return Err(SceneError::new(&f, "transitions must be in time order"));
            }
            last = jd;
            if t.path.trim().is_empty() {
                return Err(SceneError::new(
                    &format!("{p}.transitions[{k}].path"),
                    "expected an image file",
                ));
            }
        }
        Ok(())
    }
}

/// The Julian date (TT) of an RFC 3339 UTC time `s` of `field`.
pub fn parse_time(field: &str, s: &str) -> Result<f64, SceneError> {
    let utc = himmel_astro::time::parse_rfc3339(s).map_err(|e| {
        SceneError::new(
            field,
            format!("'{s}' is not an RFC 3339 time ({e}); expected e.g. 2024-06-21T18:00:00Z"),
        )
    })?;
    himmel_astro::Instant::from_utc(&utc)
        .map(|i| i.jd_tt)
        .map_err(|e| SceneError::new(field, e.to_string()))
}
