//! The scene: what to render, from where, when, and how (serde; unknown
//! fields are an error naming the field; every field has a documented
//! default so a scene file may give only what it changes).

use serde::{Deserialize, Serialize};

use crate::atmosphere::{AtmosphereParams, LutConfig};
use crate::camera::Exposure;
use crate::projection::Camera;

/// A sky effect (a render pass) a scene may call for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Effect {
    /// Scattering and extinction by air, aerosols and ozone.
    Atmosphere,
    /// The Sun's disk.
    Sun,
    /// The Moon.
    Moon,
    /// Catalogue stars as point sources (`crate::stars`).
    Stars,
    /// Mercury–Saturn as point sources.
    Planets,
    /// The Milky Way and the diffuse night-sky light (`crate::milkyway`).
    Milkyway,
    /// Cloud layers (a later issue).
    Clouds,
}

impl Effect {
    /// All effects in back-to-front pass order (design.md).
    pub const ALL: [Effect; 7] = [
        Effect::Milkyway,
        Effect::Stars,
        Effect::Planets,
        Effect::Moon,
        Effect::Sun,
        Effect::Atmosphere,
        Effect::Clouds,
    ];

    /// The effect's name as used on the command line and in `--stats`.
    pub fn name(self) -> &'static str {
        match self {
            Effect::Atmosphere => "atmosphere",
            Effect::Sun => "sun",
            Effect::Moon => "moon",
            Effect::Stars => "stars",
            Effect::Planets => "planets",
            Effect::Milkyway => "milkyway",
            Effect::Clouds => "clouds",
        }
    }

    /// Parses an effect name.
    pub fn from_name(s: &str) -> Option<Self> {
        Effect::ALL
            .into_iter()
            .find(|e| e.name().eq_ignore_ascii_case(s.trim()))
    }

    /// Whether this version renders the effect.
    pub fn available(self) -> bool {
        matches!(
            self,
            Effect::Atmosphere
                | Effect::Sun
                | Effect::Moon
                | Effect::Stars
                | Effect::Planets
                | Effect::Milkyway
        )
    }
}

/// Parses a comma list of effects (`--effects`), naming a bad entry.
pub fn parse_effects(list: &str) -> Result<Vec<Effect>, String> {
    let mut out = Vec::new();
    for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let e = Effect::from_name(name).ok_or_else(|| {
            format!(
                "unknown effect '{name}'; expected a comma list of atmosphere, sun, moon, stars, planets, milkyway, clouds"
            )
        })?;
        if !out.contains(&e) {
            out.push(e);
        }
    }
    Ok(out)
}

/// Where the observer stands.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ObserverSpec {
    /// Geodetic latitude, degrees in [−90, 90] (default 48.14, Munich).
    pub lat_deg: f64,
    /// East longitude, degrees in [−180, 180] (default 11.58).
    pub lon_deg: f64,
    /// Elevation above the WGS84 ellipsoid, m (default 0).
    pub elevation_m: f64,
}

impl Default for ObserverSpec {
    fn default() -> Self {
        ObserverSpec {
            lat_deg: 48.14,
            lon_deg: 11.58,
            elevation_m: 0.0,
        }
    }
}

/// When.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TimeSpec {
    /// Civil UTC, RFC 3339 (offsets allowed) or `now` (default `now`).
    pub utc: String,
    /// Time speed for animations: simulated seconds per real second (default 1).
    pub speed: f64,
}

impl Default for TimeSpec {
    fn default() -> Self {
        TimeSpec {
            utc: "now".into(),
            speed: 1.0,
        }
    }
}

/// Stars and planets as point sources (`crate::stars`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StarParams {
    /// Faintest V magnitude drawn, in [−2, 8] (default 6.5; above 6.5 the
    /// V ≤ 8 table of 41 411 stars is used).
    pub limit_mag: f64,
    /// Standard deviation of the Gaussian PSF core, pixels, in [0.3, 4] (default 0.7).
    pub core_px: f64,
    /// Glare: scale of the glare disk that carries the flux a star's core
    /// cannot show at the chosen exposure, in [0, 10] (default 1; 0 = no glare).
    pub glare: f64,
    /// Deterministic scintillation (twinkling) of the drawn flux (default false).
    pub scintillation: bool,
    /// Seed of the scintillation pattern (default 0).
    pub seed: u64,
}

impl Default for StarParams {
    fn default() -> Self {
        StarParams {
            limit_mag: 6.5,
            core_px: 0.7,
            glare: 1.0,
            scintillation: false,
            seed: 0,
        }
    }
}

/// A 3D world under the sky (`shared/spec/world.md`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldSpec {
    /// The glTF 2.0 file (`.gltf` or `.glb`), relative to the scene file.
    pub gltf: String,
    /// Adds an infinite Lambertian plane at y = 0 with
    /// `atmosphere.ground_albedo` (default false).
    #[serde(default)]
    pub ground: bool,
}

/// The complete scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Scene {
    /// The observer.
    pub observer: ObserverSpec,
    /// The instant.
    pub time: TimeSpec,
    /// Astronomy accuracy tier: `low`, `standard` (default) or `high`.
    pub precision: String,
    /// The camera (projection, size, orientation).
    pub camera: Camera,
    /// Effects to simulate (default: every sky effect).
    pub effects: Vec<Effect>,
    /// The atmosphere's physical parameters.
    pub atmosphere: AtmosphereParams,
    /// LUT sizes and scattering orders of the atmosphere model.
    pub lut: LutConfig,
    /// Exposure: `"auto"` (default) or an EV100 number.
    pub exposure: Exposure,
    /// Drawn Sun size relative to the true one (default 1; the illuminance is kept).
    pub sun_scale: f64,
    /// Drawn Moon size relative to the true one (default 1; the radiance is
    /// kept, so the illuminance grows with its square).
    pub moon_scale: f64,
    /// Night vision (mesopic/scotopic) in the camera stage (default true).
    pub night_vision: bool,
    /// Stars and planets.
    pub stars: StarParams,
    /// Ordered dithering of 8-bit output (default true).
    pub dither: bool,
    /// A 3D world under the sky (default none: a sky-only render).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub world: Option<WorldSpec>,
}

impl Default for Scene {
    fn default() -> Self {
        Scene {
            observer: ObserverSpec::default(),
            time: TimeSpec::default(),
            precision: "standard".into(),
            camera: Camera::default(),
            effects: Effect::ALL.to_vec(),
            atmosphere: AtmosphereParams::default(),
            lut: LutConfig::default(),
            exposure: Exposure::Auto,
            sun_scale: 1.0,
            moon_scale: 1.0,
            night_vision: true,
            stars: StarParams::default(),
            dither: true,
            world: None,
        }
    }
}

/// An invalid scene, naming the field.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// The field or flag-like path (`observer.lat_deg`, `camera.fov_deg`, …).
    pub field: String,
    /// What is wrong and what is accepted.
    pub message: String,
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.field, self.message)
    }
}

impl std::error::Error for SceneError {}

impl SceneError {
    fn new(field: &str, message: impl Into<String>) -> Self {
        SceneError {
            field: field.into(),
            message: message.into(),
        }
    }
}

impl Scene {
    /// Parses a scene from JSON; errors name the field (serde's message
    /// carries the path, e.g. "unknown field `fov`").
    pub fn from_json(s: &str) -> Result<Scene, SceneError> {
        serde_json::from_str(s).map_err(|e| SceneError::new("scene", e.to_string()))
    }

    /// The complete default scene as pretty JSON (`himmel scene-template`).
    pub fn template_json() -> String {
        serde_json::to_string_pretty(&Scene::default()).unwrap_or_default()
    }

    /// Whether the scene asks for `e`.
    pub fn wants(&self, e: Effect) -> bool {
        self.effects.contains(&e)
    }

    /// Checks every value against its range, naming the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        let o = &self.observer;
        if !(o.lat_deg.is_finite() && (-90.0..=90.0).contains(&o.lat_deg)) {
            return Err(SceneError::new(
                "observer.lat_deg",
                format!("{} is outside [-90, 90]", o.lat_deg),
            ));
        }
        if !(o.lon_deg.is_finite() && (-360.0..=360.0).contains(&o.lon_deg)) {
            return Err(SceneError::new(
                "observer.lon_deg",
                format!("{} is outside [-180, 180]", o.lon_deg),
            ));
        }
        if !(o.elevation_m.is_finite() && (-12_000.0..=100_000.0).contains(&o.elevation_m)) {
            return Err(SceneError::new(
                "observer.elevation_m",
                format!("{} is outside [-12000, 100000] m", o.elevation_m),
            ));
        }
        if !self.time.speed.is_finite() {
            return Err(SceneError::new("time.speed", "must be a finite number"));
        }
        if himmel_astro::Precision::from_name(&self.precision).is_none() {
            return Err(SceneError::new(
                "precision",
                format!(
                    "unknown tier '{}'; expected low, standard or high",
                    self.precision
                ),
            ));
        }
        self.camera
            .validate()
            .map_err(|e| SceneError::new(e.field, e.message))?;
        self.atmosphere
            .validate()
            .map_err(|e| SceneError::new(&e.field, e.expected))?;
        let l = &self.lut;
        let sizes = [
            ("lut.transmittance_w", l.transmittance_w),
            ("lut.transmittance_h", l.transmittance_h),
            ("lut.transmittance_steps", l.transmittance_steps),
            ("lut.multiscatter_n", l.multiscatter_n),
            ("lut.multiscatter_dirs", l.multiscatter_dirs),
            ("lut.multiscatter_steps", l.multiscatter_steps),
            ("lut.sky_view_w", l.sky_view_w),
            ("lut.sky_view_h", l.sky_view_h),
            ("lut.sky_view_steps", l.sky_view_steps),
        ];
        for (f, v) in sizes {
            if !(2..=1024).contains(&v) {
                return Err(SceneError::new(f, format!("{v} is outside [2, 1024]")));
            }
        }
        if l.orders > 1000 {
            return Err(SceneError::new(
                "lut.orders",
                "expected 0 (all orders) or 1..1000",
            ));
        }
        for (f, v) in [
            ("sun_scale", self.sun_scale),
            ("moon_scale", self.moon_scale),
        ] {
            if !(v.is_finite() && (0.01..=100.0).contains(&v)) {
                return Err(SceneError::new(f, format!("{v} is outside [0.01, 100]")));
            }
        }
        let st = &self.stars;
        for (f, v, lo, hi) in [
            ("stars.limit_mag", st.limit_mag, -2.0, 8.0),
            ("stars.core_px", st.core_px, 0.3, 4.0),
            ("stars.glare", st.glare, 0.0, 10.0),
        ] {
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                return Err(SceneError::new(f, format!("{v} is outside [{lo}, {hi}]")));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn serde_round_trip_and_template() {
        let mut s = Scene::default();
        s.camera.fov_deg = 42.0;
        s.exposure = Exposure::Ev100(-3.5);
        s.effects = vec![Effect::Atmosphere, Effect::Moon];
        s.atmosphere.aerosol_density = 2.5;
        let j = serde_json::to_string(&s).unwrap();
        let back: Scene = serde_json::from_str(&j).unwrap();
        assert_eq!(back, s);
        let t = Scene::template_json();
        assert_eq!(Scene::from_json(&t).unwrap(), Scene::default());
        // Partial scenes take defaults.
        let p = Scene::from_json(r#"{"camera": {"width": 64}}"#).unwrap();
        assert_eq!(p.camera.width, 64);
        assert_eq!(p.camera.height, 1024);
    }

    #[test]
    fn unknown_fields_and_wrong_types_name_the_field() {
        let e = Scene::from_json(r#"{"camera": {"fvo": 3}}"#).unwrap_err();
        assert!(e.message.contains("fvo"), "{e}");
        let e = Scene::from_json(r#"{"camera": {"width": "wide"}}"#).unwrap_err();
        assert!(e.to_string().contains("invalid type"), "{e}");
        let e = Scene::from_json(r#"{"effects": ["sun", "rainbow"]}"#).unwrap_err();
        assert!(e.message.contains("rainbow"), "{e}");
    }

    #[test]
    fn effects_parse() {
        assert_eq!(
            parse_effects("sun, atmosphere,sun").unwrap(),
            vec![Effect::Sun, Effect::Atmosphere]
        );
        assert!(parse_effects("sun,rainbow")
            .unwrap_err()
            .contains("rainbow"));
    }

    #[test]
    fn validation() {
        let mut s = Scene::default();
        assert!(s.validate().is_ok());
        s.observer.lat_deg = 91.0;
        assert_eq!(s.validate().unwrap_err().field, "observer.lat_deg");
        s.observer.lat_deg = 0.0;
        s.atmosphere.aerosol_g = 1.5;
        assert_eq!(s.validate().unwrap_err().field, "atmosphere.aerosol_g");
        s.atmosphere.aerosol_g = 0.8;
        s.stars.core_px = 0.1;
        assert_eq!(s.validate().unwrap_err().field, "stars.core_px");
        s.stars.core_px = 0.7;
        s.stars.limit_mag = f64::NAN;
        assert_eq!(s.validate().unwrap_err().field, "stars.limit_mag");
    }
}
