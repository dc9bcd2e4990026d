//! The scene: what to render, from where, when, and how (serde; unknown
//! fields are an error naming the field; every field has a documented
//! default so a scene file may give only what it changes).

use serde::{Deserialize, Serialize};

use crate::atmosphere::{AtmosphereParams, LutConfig};
use crate::camera::Exposure;
pub use crate::cloud_spec::{
    CloudScattering, CloudsSpec, HighCloudSpec, LowCloudKind, LowCloudSpec, LowCloudTier,
};
pub use crate::overlay_spec::OverlaySpec;
use crate::projection::Camera;
use crate::scene_error::check_range;
pub use crate::scene_error::SceneError;
pub use crate::texture_spec::SkyTextureSpec;
use crate::units::show;
pub use crate::world_spec::{FogPhase, FogSpec, LightingSpec, ShadowFilter, WorldSpec};

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
    /// A texture-mapped sky (`sky_texture`), instead of or blended over
    /// the physical sky (`crate::texture_sky`).
    Texture,
    /// Cloud layers: a volumetric low layer and a thin high layer
    /// (`clouds`, `crate::clouds`).
    Clouds,
    /// A 3D world's G-buffer and its lighting by the Sun, Moon and sky
    /// (`spec/world.md`; wgpu backend).
    World,
    /// The Sun's and Moon's shadow maps on the world.
    Shadows,
    /// Light shafts: the fog's single scattering of the Sun, Moon and sky
    /// (`lighting.godrays`).
    Godrays,
    /// Screen-space ambient occlusion of the sky's light on the world
    /// (`lighting.ao`).
    Ao,
    /// Screen-space reflections (`lighting.ssr`).
    Ssr,
    /// Dynamic global illumination (a later issue).
    Gi,
    /// Temporal filtering: a jittered camera and the history of the
    /// world's pixels, reprojected (`lighting.temporal`).
    Temporal,
}

impl Effect {
    /// All effects in back-to-front pass order (design.md).
    /// The sky passes first, then the lighting passes of a 3D world in
    /// their order (design.md).
    pub const ALL: [Effect; 15] = [
        Effect::Milkyway,
        Effect::Stars,
        Effect::Planets,
        Effect::Moon,
        Effect::Sun,
        Effect::Atmosphere,
        Effect::Texture,
        Effect::Clouds,
        Effect::World,
        Effect::Shadows,
        Effect::Godrays,
        Effect::Ao,
        Effect::Ssr,
        Effect::Gi,
        Effect::Temporal,
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
            Effect::Texture => "texture",
            Effect::Clouds => "clouds",
            Effect::World => "world",
            Effect::Shadows => "shadows",
            Effect::Godrays => "godrays",
            Effect::Ao => "ao",
            Effect::Ssr => "ssr",
            Effect::Gi => "gi",
            Effect::Temporal => "temporal",
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
                | Effect::Texture
                | Effect::Clouds
                | Effect::World
                | Effect::Shadows
                | Effect::Godrays
                | Effect::Ao
                | Effect::Ssr
                | Effect::Temporal
        )
    }

    /// Whether the effect lights a 3D world (wgpu backend) rather than
    /// drawing the sky.
    pub fn is_lighting(self) -> bool {
        matches!(
            self,
            Effect::World
                | Effect::Shadows
                | Effect::Godrays
                | Effect::Ao
                | Effect::Ssr
                | Effect::Gi
                | Effect::Temporal
        )
    }
}

/// Parses a comma list of effects (`--effects`), naming a bad entry.
pub fn parse_effects(list: &str) -> Result<Vec<Effect>, String> {
    let mut out = Vec::new();
    for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let e = Effect::from_name(name).ok_or_else(|| {
            format!(
                "unknown effect '{name}'; expected a comma list of atmosphere, sun, moon, stars, planets, milkyway, texture, clouds, world, shadows, godrays, ao, ssr, gi, temporal"
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
    /// East longitude, degrees in [−180, 180]; 360-wrapped values in
    /// [−360, 360] are accepted (default 11.58).
    pub lon_deg: f64,
    /// Elevation above the WGS84 ellipsoid, m, in [−12000, 100000] (default 0).
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
    /// Time speed for animations: simulated seconds per real second, in
    /// [−1e9, 1e9] (about ±32 years per second; negative runs backwards)
    /// (default 1). In a frame sequence it multiplies the time step
    /// (`crate::sequence`).
    pub speed: f64,
    /// Fraction of the day F in [0, 1): when given, the instant is local
    /// apparent solar time F × 24 h (0.25 = 06:00, 0.5 = the Sun on the
    /// meridian) on the local date of `utc` at the observer's longitude
    /// (`crate::solar_time`) (default none: `utc` itself).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub day_fraction: Option<f64>,
}

impl Default for TimeSpec {
    fn default() -> Self {
        TimeSpec {
            utc: "now".into(),
            speed: 1.0,
            day_fraction: None,
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
    /// Seed of the scintillation pattern, any u64 (default 0).
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

/// Default largest exposure step between consecutive frames of a sequence,
/// EV (`Scene::exposure_max_step_ev`).
pub const DEFAULT_EXPOSURE_MAX_STEP_EV: f64 = 0.25;

/// The complete scene. Every number has a documented range that
/// [`Scene::validate`] checks; [`Scene::from_json`] names the field of any
/// error by its path.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Scene {
    /// The observer.
    pub observer: ObserverSpec,
    /// The instant.
    pub time: TimeSpec,
    /// Astronomy accuracy tier: `low`, `standard` (default) or `high`.
    pub precision: String,
    /// The camera (projection, size, orientation; ranges in [`Camera`]).
    pub camera: Camera,
    /// Effects to simulate (default: every sky effect).
    pub effects: Vec<Effect>,
    /// The atmosphere's physical parameters (ranges in [`AtmosphereParams`]).
    pub atmosphere: AtmosphereParams,
    /// LUT sizes and scattering orders of the atmosphere model (ranges in
    /// [`LutConfig`]).
    pub lut: LutConfig,
    /// Exposure: `"auto"` (default) or an EV100 number in [−30, 40].
    pub exposure: Exposure,
    /// Drawn Sun size relative to the true one, in [0.01, 100] (default 1;
    /// the illuminance is kept).
    pub sun_scale: f64,
    /// Drawn Moon size relative to the true one, in [0.01, 100] (default 1;
    /// the radiance is kept, so the illuminance grows with its square).
    pub moon_scale: f64,
    /// Night vision (mesopic/scotopic) in the camera stage (default true).
    pub night_vision: bool,
    /// Stars and planets.
    pub stars: StarParams,
    /// Ordered dithering of 8-bit output (default true).
    pub dither: bool,
    /// Largest change of the automatic exposure between consecutive frames
    /// of a sequence, EV, in [0.01, 10] (default 0.25;
    /// `crate::sequence::exposure`).
    pub exposure_max_step_ev: f64,
    /// A 3D world under the sky (default none: a sky-only render).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub world: Option<WorldSpec>,
    /// A homogeneous fog over the world (default none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fog: Option<FogSpec>,
    /// The lighting passes' settings (ranges in [`LightingSpec`]).
    #[serde(skip_serializing_if = "is_default_lighting")]
    pub lighting: LightingSpec,
    /// Constellation figures and labels over the PNG (ranges in
    /// [`OverlaySpec`]; default off).
    pub overlay: OverlaySpec,
    /// A texture-mapped sky (default none; `crate::texture_spec`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sky_texture: Option<SkyTextureSpec>,
    /// The cloud layers (ranges in [`CloudsSpec`]; default none: both
    /// coverages 0).
    pub clouds: CloudsSpec,
}

fn is_default_lighting(l: &LightingSpec) -> bool {
    *l == LightingSpec::default()
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
            exposure_max_step_ev: DEFAULT_EXPOSURE_MAX_STEP_EV,
            world: None,
            fog: None,
            lighting: LightingSpec::default(),
            overlay: OverlaySpec::default(),
            sky_texture: None,
            clouds: CloudsSpec::default(),
        }
    }
}

impl Scene {
    /// Parses a scene from JSON. Every error names the field by its dotted
    /// path ([`SceneError::field`], e.g. `observer.lat_deg`,
    /// `effects[1]`; `scene` for the document itself) and says what was
    /// expected and found in words ("expected a number, found a string").
    /// A document that is not a JSON object is refused. Ranges are checked
    /// by [`Scene::validate`].
    pub fn from_json(s: &str) -> Result<Scene, SceneError> {
        if !s.trim_start().starts_with('{') {
            let found = match serde_json::from_str::<serde_json::Value>(s) {
                Ok(v) => kind_of(&v),
                Err(e) => return Err(json_error("", &e)),
            };
            return Err(SceneError::new(
                "scene",
                format!("a scene must be a JSON object ({{ … }}), found {found}"),
            ));
        }
        let de = &mut serde_json::Deserializer::from_str(s);
        let scene: Scene =
            serde_path_to_error::deserialize(&mut *de).map_err(|e| path_error(s, &e))?;
        // Characters after the object.
        de.end().map_err(|e| json_error("", &e))?;
        // serde also fills a struct from a list, by position
        // (`"observer": [48, 11]`): each group must be an object.
        // (The structure: the default scene with every optional group
        // that has one filled in.)
        let structure = Scene {
            sky_texture: Some(SkyTextureSpec::template()),
            ..Scene::default()
        };
        if let (Ok(given), Ok(default)) = (
            serde_json::from_str::<serde_json::Value>(s),
            serde_json::to_value(structure),
        ) {
            objects_where_objects(&given, &default, "")?;
        }
        Ok(scene)
    }

    /// The complete default scene as pretty JSON (`himmel scene-template`).
    pub fn template_json() -> String {
        serde_json::to_string_pretty(&Scene::default()).unwrap_or_default()
    }

    /// The default scene with a world, its camera, a fog and every lighting
    /// key at its default (`himmel scene-template --world`).
    pub fn template_world_json() -> String {
        let mut s = Scene {
            world: Some(WorldSpec {
                gltf: "world.glb".into(),
                ground: true,
            }),
            ..Scene::default()
        };
        s.camera.projection = crate::Projection::Perspective;
        s.camera.width = 1280;
        s.camera.height = 720;
        s.camera.fov_deg = 60.0;
        s.camera.position_m = Some(crate::projection::DEFAULT_EYE_M);
        s.camera.look_at_m = Some([0.0, 1.7, -10.0]);
        s.camera.up = Some([0.0, 1.0, 0.0]);
        s.fog = Some(FogSpec {
            top_m: Some(50.0),
            ..FogSpec::default()
        });
        let mut v = serde_json::to_value(&s).unwrap_or_default();
        v["lighting"] = serde_json::to_value(LightingSpec::default()).unwrap_or_default();
        serde_json::to_string_pretty(&v).unwrap_or_default()
    }

    /// The default scene with a sky texture, every one of its keys filled
    /// (`himmel scene-template --sky-texture`).
    pub fn template_sky_texture_json() -> String {
        let s = Scene {
            sky_texture: Some(SkyTextureSpec::template()),
            ..Scene::default()
        };
        serde_json::to_string_pretty(&s).unwrap_or_default()
    }

    /// Whether the scene asks for `e`.
    pub fn wants(&self, e: Effect) -> bool {
        self.effects.contains(&e)
    }

    /// Checks every value against its range (documented on each field),
    /// naming the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        let o = &self.observer;
        let t = &self.time;
        let st = &self.stars;
        for (f, v, lo, hi) in [
            ("observer.lat_deg", o.lat_deg, -90.0, 90.0),
            ("observer.lon_deg", o.lon_deg, -360.0, 360.0),
            ("observer.elevation_m", o.elevation_m, -12_000.0, 100_000.0),
            ("time.speed", t.speed, -1e9, 1e9),
            ("sun_scale", self.sun_scale, 0.01, 100.0),
            ("moon_scale", self.moon_scale, 0.01, 100.0),
            (
                "exposure_max_step_ev",
                self.exposure_max_step_ev,
                0.01,
                10.0,
            ),
            ("stars.limit_mag", st.limit_mag, -2.0, 8.0),
            ("stars.core_px", st.core_px, 0.3, 4.0),
            ("stars.glare", st.glare, 0.0, 10.0),
        ] {
            check_range(f, v, lo, hi)?;
        }
        if let Exposure::Ev100(v) = self.exposure {
            check_range("exposure", v, -30.0, 40.0)?;
        }
        if let Some(f) = t.day_fraction {
            if !(f.is_finite() && (0.0..1.0).contains(&f)) {
                return Err(SceneError::new(
                    "time.day_fraction",
                    format!(
                        "{} is outside [0, 1) (0.25 = apparent solar 06:00)",
                        show(f)
                    ),
                ));
            }
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
        crate::world_spec::validate_fog(&self.fog)?;
        self.lighting.validate()?;
        self.overlay.validate()?;
        if let Some(t) = &self.sky_texture {
            t.validate()?;
        }
        self.clouds.validate()?;
        if self.world.is_some() && self.camera.projection != crate::Projection::Perspective {
            return Err(SceneError::new(
                "camera.projection",
                format!(
                    "a 3D world is rendered through the perspective camera, not {}",
                    self.camera.projection.name()
                ),
            ));
        }
        self.validate_lut()
    }

    /// The LUT sizes, orders and forward peak ([`LutConfig`]).
    fn validate_lut(&self) -> Result<(), SceneError> {
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
                format!("{} is outside [0, 1000] (0 = all orders)", l.orders),
            ));
        }
        check_range("lut.forward_peak_deg", l.forward_peak_deg.into(), 0.0, 90.0)
    }
}

/// A deserialisation error of the document `text`, named by its path.
fn path_error(text: &str, e: &serde_path_to_error::Error<serde_json::Error>) -> SceneError {
    use serde_path_to_error::Segment;
    // A syntax error has no meaningful last segment ("?"): name the group.
    let path = e.path().to_string();
    let path = path.trim_end_matches('?').trim_end_matches('.');
    let path = if path == "." { "" } else { path };
    let mut err = json_error(path, e.inner());
    // serde_json says only "expected value" when an enum (a name such as
    // `fisheye`) is given another type in a well-formed document.
    if e.inner().to_string().starts_with("expected value at") {
        if let Ok(doc) = serde_json::from_str::<serde_json::Value>(text) {
            let found = e.path().iter().try_fold(&doc, |v, seg| match seg {
                Segment::Map { key } => v.get(key),
                Segment::Seq { index } => v.get(index),
                _ => None,
            });
            if let Some(found) = found {
                err.message = format!(
                    "expected a name (a string), found {} (line {}, column {})",
                    kind_of(found),
                    e.inner().line(),
                    e.inner().column()
                );
            }
        }
    }
    err
}

/// A JSON error at `path` ("" for the document) in readable words.
fn json_error(path: &str, e: &serde_json::Error) -> SceneError {
    let text = e.to_string();
    let at = format!(" at line {} column {}", e.line(), e.column());
    let (text, place) = match text.strip_suffix(&at) {
        Some(t) if e.line() > 0 => (t, format!(" (line {}, column {})", e.line(), e.column())),
        _ => (text.as_str(), String::new()),
    };
    let field = if path.is_empty() { "scene" } else { path };
    SceneError::new(field, format!("{}{place}", readable(text)))
}

/// Checks that every group of `given` that is an object in `default` (the
/// scene's structure) is an object too, naming the first that is not.
fn objects_where_objects(
    given: &serde_json::Value,
    default: &serde_json::Value,
    path: &str,
) -> Result<(), SceneError> {
    let (Some(given), Some(default)) = (given.as_object(), default.as_object()) else {
        return Ok(());
    };
    let object = |g: &serde_json::Value, d: &serde_json::Value, p: &str| {
        if g.is_null() || g.is_object() {
            objects_where_objects(g, d, p)
        } else {
            Err(SceneError::new(
                p,
                format!("expected an object ({{ … }}), found {}", kind_of(g)),
            ))
        }
    };
    for (k, d) in default.iter() {
        let Some(g) = given.get(k) else { continue };
        let p = if path.is_empty() {
            k.clone()
        } else {
            format!("{path}.{k}")
        };
        if d.is_object() {
            object(g, d, &p)?;
        }
        // A list of groups (`sky_texture.transitions`): each an object.
        if let (Some(d0), Some(list)) = (d.get(0).filter(|d0| d0.is_object()), g.as_array()) {
            for (i, gi) in list.iter().enumerate() {
                object(gi, d0, &format!("{p}[{i}]"))?;
            }
        }
    }
    Ok(())
}

/// What kind of JSON value `v` is, in words.
fn kind_of(v: &serde_json::Value) -> String {
    use serde_json::Value;
    match v {
        Value::Null => "null".into(),
        Value::Bool(b) => format!("a boolean ({b})"),
        Value::Number(n) => format!("the number {n}"),
        Value::String(s) => format!("a string ({s:?})"),
        Value::Array(_) => "a list".into(),
        Value::Object(_) => "an object".into(),
    }
}

/// serde's "invalid type: X, expected Y" and "invalid value: X, expected
/// Y" as "expected Y', found X'" in words (other messages unchanged).
fn readable(text: &str) -> String {
    // A list given for a group without defaults (serde fills structs
    // from lists by position).
    if text.starts_with("invalid length ") && text.contains(", expected struct ") {
        return "expected an object ({ … }), found a list".into();
    }
    let Some(rest) = text
        .strip_prefix("invalid type: ")
        .or_else(|| text.strip_prefix("invalid value: "))
    else {
        return match text {
            "number out of range" => {
                "number out of range (beyond the largest 64-bit floating-point number)".into()
            }
            _ => text.to_string(),
        };
    };
    // The found value may be a string holding ", expected ": split at the last.
    let Some((found, expected)) = rest.rsplit_once(", expected ") else {
        return text.to_string();
    };
    format!(
        "expected {}, found {}",
        expected_words(expected),
        found_words(found)
    )
}

/// serde's name of what a field's type accepts, in words.
fn expected_words(expected: &str) -> String {
    let int = |max: u64| format!("a whole number in [0, {max}]");
    match expected {
        "f64" | "f32" => "a number".into(),
        "u8" => int(u8::MAX.into()),
        "u16" => int(u16::MAX.into()),
        "u32" => int(u32::MAX.into()),
        "u64" => int(u64::MAX),
        "usize" => int(usize::MAX as u64),
        "a boolean" => "true or false".into(),
        "a sequence" => "a list ([ … ])".into(),
        e if e.starts_with("struct ") => "an object ({ … })".into(),
        e => e.to_string(),
    }
}

/// serde_json's description of a value that was found, in words.
fn found_words(found: &str) -> String {
    let quoted = |prefix: &str| {
        found
            .strip_prefix(prefix)
            .and_then(|v| v.strip_prefix('`'))
            .and_then(|v| v.strip_suffix('`'))
            .map(str::to_string)
    };
    if let Some(v) = quoted("integer ") {
        return format!("the number {v}");
    }
    if let Some(v) = quoted("floating point ") {
        return format!("the number {}", v.replace("e+", "e"));
    }
    if let Some(v) = quoted("boolean ") {
        return format!("a boolean ({v})");
    }
    if let Some(v) = found.strip_prefix("string ") {
        return format!("a string ({v})");
    }
    match found {
        "sequence" => "a list".into(),
        "map" => "an object".into(),
        "null" | "unit value" => "null".into(),
        f => f.to_string(),
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
        assert_eq!(e.field, "camera.fvo");
        let e = Scene::from_json(r#"{"camera": {"width": "wide"}}"#).unwrap_err();
        assert_eq!(e.field, "camera.width");
        assert!(
            e.message
                .starts_with("expected a whole number in [0, 4294967295], found a string"),
            "{e}"
        );
        let e = Scene::from_json(r#"{"observer": {"lat_deg": "not-a-number"}}"#).unwrap_err();
        assert_eq!(
            e.to_string(),
            r#"observer.lat_deg: expected a number, found a string ("not-a-number") (line 1, column 39)"#
        );
        let e = Scene::from_json(r#"{"effects": ["sun", "rainbow"]}"#).unwrap_err();
        assert!(e.message.contains("rainbow"), "{e}");
        assert_eq!(e.field, "effects[1]");
    }

    #[test]
    fn documents_that_are_not_objects_are_refused() {
        for (text, found) in [
            ("[]", "a list"),
            ("3", "the number 3"),
            (r#""x""#, "a string"),
            ("null", "null"),
            ("true", "a boolean"),
        ] {
            let e = Scene::from_json(text).unwrap_err();
            assert_eq!(e.field, "scene", "{text}: {e}");
            assert!(
                e.message.contains("a scene must be a JSON object") && e.message.contains(found),
                "{text}: {e}"
            );
        }
        for text in ["", "{", "{} {}", "{\"camera\": {\"width\": 1e999}}"] {
            assert!(Scene::from_json(text).is_err(), "{text:?}");
        }
    }

    #[test]
    fn overflow_and_negative_sizes_name_the_field() {
        for (text, field) in [
            (r#"{"observer": {"lat_deg": 1e999}}"#, "observer.lat_deg"),
            (r#"{"observer": {"lat_deg": -1e999}}"#, "observer.lat_deg"),
            (r#"{"camera": {"width": -1}}"#, "camera.width"),
            (r#"{"camera": {"height": 4294967296}}"#, "camera.height"),
            (r#"{"lut": {"sky_view_w": -1}}"#, "lut.sky_view_w"),
            (r#"{"lut": {"orders": 1e999}}"#, "lut.orders"),
            (r#"{"stars": {"seed": 18446744073709551616}}"#, "stars.seed"),
        ] {
            let e = Scene::from_json(text).unwrap_err();
            assert_eq!(e.field, field, "{text}: {e}");
        }
        // f32 overflow is refused while reading (serde_json's
        // `float_roundtrip` parses exactly), naming the field.
        let e = Scene::from_json(r#"{"lut": {"forward_peak_deg": 1e39}}"#).unwrap_err();
        assert_eq!(e.field, "lut.forward_peak_deg");
        let s = Scene::from_json(r#"{"lut": {"forward_peak_deg": -50}}"#).unwrap();
        assert_eq!(s.validate().unwrap_err().field, "lut.forward_peak_deg");
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
