//! Mutation fuzzing of Himmel's parsers on stable Rust: the text formats
//! and glTF 2.0 worlds (`.glb` and `.gltf` bytes).
//!
//! No nightly toolchain is reachable here, so `cargo fuzz` (libFuzzer) is
//! out; this is a small structure-aware mutation fuzzer instead. Each
//! [`Target`] has a corpus of valid inputs (the formats' own examples and
//! the real excerpts the tests use). An input is a corpus entry after one to
//! four mutations drawn by a seeded generator (reproducible runs): bit
//! flips, bytes replaced by the formats' own punctuation, insertion of
//! tokens that break parsers (`1e999`, `-0`, `NaN`, `null`, 20-digit
//! numbers, non-ASCII), deletion and duplication of ranges, splices of two
//! corpus entries, and digit runs replaced by boundary numbers.
//!
//! For feedback without coverage instrumentation, an input whose outcome
//! (success, or the error's message with its digits removed) has not been
//! seen before joins the corpus, so that the run keeps mutating inputs that
//! reached new error paths.
//!
//! Every input runs under `catch_unwind`. A run fails when a parser panics,
//! when an error's message is empty or longer than one line (the CLI
//! prints it as its one-line `error:`), or when an accepted input breaks
//! the target's round-trip invariant (see each target).

use std::collections::HashSet;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

use himmel_astro::time::{parse_date, parse_date_or_rfc3339, parse_rfc3339};
use himmel_catalog::sources::{parse_d3_starnames, parse_d3_stars, parse_hip2, parse_hip2_line};
use himmel_cli::inputs::parse_batch_line;
use himmel_cli::timearg::{format_utc, parse_date_or_time};
use himmel_skymodel::scene::Scene;
use himmel_world::gltf_io;

/// A parser under test.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// RFC 3339 times and dates: the astro parsers and the CLI's
    /// `--time`/`--from`/`--to` parser.
    Time,
    /// `Scene::from_json` (the `--scene` file).
    Scene,
    /// `himmel ephemeris --batch` lines.
    Batch,
    /// `hip2.dat` lines and files (Hipparcos new reduction, CDS I/311).
    Hip2,
    /// d3-celestial's `stars.*.json` and `starnames.json`.
    D3,
    /// glTF 2.0 worlds, `.glb` or self-contained `.gltf`
    /// (`himmel_world::gltf_io::from_slice`, the `--world` loader).
    Gltf,
}

impl Target {
    /// Every target.
    pub const ALL: [Target; 6] = [
        Target::Time,
        Target::Scene,
        Target::Batch,
        Target::Hip2,
        Target::D3,
        Target::Gltf,
    ];

    /// The target's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Target::Time => "time",
            Target::Scene => "scene",
            Target::Batch => "batch",
            Target::Hip2 => "hip2",
            Target::D3 => "d3",
            Target::Gltf => "gltf",
        }
    }

    /// The target called `name`.
    pub fn from_name(name: &str) -> Option<Target> {
        Target::ALL.into_iter().find(|t| t.name() == name)
    }

    /// The valid inputs the mutations start from.
    pub fn seeds(self) -> Vec<Vec<u8>> {
        let v: Vec<String> = match self {
            Target::Time => [
                "2024-04-08T18:42:00Z",
                "2024-04-08T20:42:00.5+02:00",
                "2016-12-31T23:59:60Z",
                "2017-01-01T08:59:60.999+09:00",
                "-1900-02-29T13:03:17.000Z",
                "+10000-01-01T00:00:00Z",
                "-4712-01-01T12:00:00Z",
                "1582-10-15T01:00:00+02:00",
                "1582-10-04",
                "-0500-01-01",
                "0000-02-29",
                "2024-04-08",
                "2024-04-08t18:42:00.123456789012345678z",
                "1999-12-31 23:59:59-00:30",
            ]
            .map(String::from)
            .to_vec(),
            Target::Scene => vec![
                Scene::template_json(),
                r#"{"observer": {"lat_deg": 52.5, "lon_deg": 13.4}, "time": {"utc": "-0500-03-01T12:00:00Z"}}"#.into(),
                r#"{"camera": {"projection": "perspective", "width": 64, "height": 32, "yaw_deg": 90, "pitch_deg": 10, "fov_deg": 40}, "effects": ["sun", "moon"], "exposure": 12.5}"#.into(),
                r#"{"lut": {"multiscatter_n": 8, "sky_view_w": 32, "sky_view_h": 32, "orders": 2, "forward_peak_deg": 10}, "stars": {"limit_mag": 8, "scintillation": true, "seed": 7}}"#.into(),
                r#"{"atmosphere": {"aerosol_density": 0.5, "ozone_du": 350}, "exposure": "auto", "sun_scale": 2, "moon_scale": 0.5, "night_vision": false, "dither": false}"#.into(),
            ],
            Target::Batch => [
                "time,lat,lon,elevation_m",
                "2024-04-08T18:42:00Z,32.7767,-96.797,140",
                "-1900-02-29T13:03:17Z, 52.5, 13.4, 34",
                "2024-04-08, -90, 180, 0",
                "+10000-01-01T00:00:00.5+01:00,89.9,-359.9,-400",
                "1582-10-15T01:00:00+02:00,0,0,99999",
            ]
            .map(String::from)
            .to_vec(),
            Target::Hip2 => {
                let text = include_str!("../../catalog/tests/data/hip2_excerpt.dat");
                let mut v: Vec<String> = text.lines().map(String::from).collect();
                v.push(text.into());
                v
            }
            Target::D3 => vec![
                include_str!("../../catalog/tests/data/stars8_excerpt.json").into(),
                include_str!("../../catalog/tests/data/starnames_excerpt.json").into(),
            ],
            Target::Gltf => return gltf_seeds(),
        };
        v.into_iter().map(String::into_bytes).collect()
    }

    /// Runs one input: `Ok(outcome)` names what happened (for the corpus
    /// feedback), `Err` is a finding other than a panic.
    fn run(self, input: &[u8]) -> Result<String, String> {
        match self {
            Target::Gltf => gltf(input),
            text => text.run_text(&String::from_utf8_lossy(input)),
        }
    }

    /// Runs one input of a text format.
    fn run_text(self, s: &str) -> Result<String, String> {
        match self {
            Target::Time => time(s),
            Target::Scene => scene(s),
            Target::Batch => batch(s),
            Target::Hip2 => {
                let a = outcome(parse_hip2_line(s, 1).map(|_| ()))?;
                let b = outcome(parse_hip2(s).map(|_| ()))?;
                Ok(format!("{a}|{b}"))
            }
            Target::D3 => {
                let a = outcome(parse_d3_stars(s).map(|_| ()))?;
                let b = outcome(parse_d3_starnames(s).map(|_| ()))?;
                Ok(format!("{a}|{b}"))
            }
            Target::Gltf => gltf(s.as_bytes()),
        }
    }

    /// The largest input of the target; longer mutants are cut.
    fn max_input(self) -> usize {
        match self {
            // The atrium seed is 210 kB.
            Target::Gltf => 256 * 1024,
            _ => 64 * 1024,
        }
    }
}

/// The glTF seeds: the test worlds as `.glb` (`tests/fixtures/worlds`),
/// the two small ones also as `.gltf` with the buffer as a data URI (so
/// that text mutations reach the JSON's structure without breaking the
/// binary container's lengths), and small hand-written files for what the
/// test worlds do not use: strips, fans, points, node hierarchies with
/// matrices and TRS, a mirroring scale, missing normals and indices,
/// byte strides, a second scene, extensions.
fn gltf_seeds() -> Vec<Vec<u8>> {
    let glbs: [&[u8]; 3] = [
        include_bytes!("../../tests/fixtures/worlds/plane_and_boxes.glb"),
        include_bytes!("../../tests/fixtures/worlds/sun_room.glb"),
        include_bytes!("../../tests/fixtures/worlds/atrium.glb"),
    ];
    let mut v: Vec<Vec<u8>> = glbs.iter().map(|b| b.to_vec()).collect();
    v.extend(glbs[..2].iter().filter_map(|b| glb_to_gltf(b)));
    // One triangle's positions (three f32 vec3), a vec3 of normals and u16
    // indices 0, 1, 2 (+2 padding), as one buffer.
    let mut bin = Vec::new();
    for f in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0] {
        bin.extend_from_slice(&f.to_le_bytes());
    }
    for f in [0.0f32, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0] {
        bin.extend_from_slice(&f.to_le_bytes());
    }
    for i in [0u16, 1, 2, 0] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::encode(&bin)
    );
    let buffers = format!(
        r#""buffers":[{{"byteLength":{},"uri":"{uri}"}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":36,"byteStride":12}},{{"buffer":0,"byteOffset":72,"byteLength":6}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,0,1]}},{{"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"}},{{"bufferView":2,"componentType":5123,"count":3,"type":"SCALAR"}}]"#,
        bin.len()
    );
    let asset = r#""asset":{"version":"2.0"}"#;
    let files = [
        // Indexed triangles with normals under a TRS node with a child
        // under a mirroring matrix; a material with emission strength.
        format!(
            r#"{{{asset},{buffers},
            "extensionsUsed":["KHR_materials_emissive_strength","KHR_texture_transform"],
            "materials":[{{"pbrMetallicRoughness":{{"baseColorFactor":[0.5,0.5,0.5,1],"metallicFactor":0,"roughnessFactor":0.7}},"emissiveFactor":[1,0.5,0],"extensions":{{"KHR_materials_emissive_strength":{{"emissiveStrength":5}}}}}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1}},"indices":2,"material":0}}]}}],
            "nodes":[{{"mesh":0,"translation":[1,2,3],"rotation":[0,0.7071068,0,0.7071068],"scale":[2,2,2],"children":[1]}},{{"mesh":0,"matrix":[-1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]}}],
            "scenes":[{{"nodes":[0]}},{{"nodes":[1]}}],"scene":0}}"#
        ),
        // Strip, fan and points, without indices or normals; no scene.
        format!(
            r#"{{{asset},{buffers},
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"mode":5}},{{"attributes":{{"POSITION":0}},"mode":6}},{{"attributes":{{"POSITION":0}},"mode":0}}]}}],
            "nodes":[{{"mesh":0}}]}}"#
        ),
    ];
    v.extend(files.into_iter().map(String::into_bytes));
    v
}

/// A `.glb`'s JSON chunk with its binary chunk moved into the first
/// buffer as a base64 data URI (a `.gltf`), if it has both chunks.
fn glb_to_gltf(glb: &[u8]) -> Option<Vec<u8>> {
    let u32_at = |i: usize| -> Option<usize> {
        Some(u32::from_le_bytes(glb.get(i..i + 4)?.try_into().ok()?) as usize)
    };
    let json_len = u32_at(12)?;
    let json = glb.get(20..20 + json_len)?;
    let bin_at = 20 + json_len;
    let bin = glb.get(bin_at + 8..bin_at + 8 + u32_at(bin_at)?)?;
    let mut root: serde_json::Value = serde_json::from_slice(json).ok()?;
    let buffer = root.get_mut("buffers")?.get_mut(0)?.as_object_mut()?;
    buffer.insert(
        "uri".into(),
        format!(
            "data:application/octet-stream;base64,{}",
            base64::encode(bin)
        )
        .into(),
    );
    serde_json::to_vec_pretty(&root).ok()
}

/// The glTF loader. Invariants of an accepted world (what the renderer
/// relies on): per mesh as many normals and texture coordinates as
/// positions, whole triangles, every index below the vertex count, the
/// material index valid; each material's texture index valid; each
/// texture's texel count its width × height.
fn gltf(input: &[u8]) -> Result<String, String> {
    let r = gltf_io::from_slice(input, "fuzz.glb");
    if let Ok(w) = &r {
        for (i, m) in w.meshes.iter().enumerate() {
            let n = m.positions.len();
            if m.normals.len() != n || m.uvs.len() != n || m.indices.len() % 3 != 0 {
                return Err(format!(
                    "mesh {i}: {n} positions, {} normals, {} uvs, {} indices",
                    m.normals.len(),
                    m.uvs.len(),
                    m.indices.len()
                ));
            }
            if let Some(bad) = m.indices.iter().find(|&&k| k as usize >= n) {
                return Err(format!("mesh {i}: index {bad} of {n} vertices"));
            }
            if m.material >= w.materials.len() {
                return Err(format!(
                    "mesh {i}: material {} of {}",
                    m.material,
                    w.materials.len()
                ));
            }
        }
        for (i, m) in w.materials.iter().enumerate() {
            if m.base_color_texture.is_some_and(|t| t >= w.textures.len()) {
                return Err(format!(
                    "material {i}: texture {:?} of {}",
                    m.base_color_texture,
                    w.textures.len()
                ));
            }
        }
        for (i, t) in w.textures.iter().enumerate() {
            if t.texels.len() as u64 != t.width as u64 * t.height as u64 {
                return Err(format!(
                    "texture {i}: {} texels for {}×{}",
                    t.texels.len(),
                    t.width,
                    t.height
                ));
            }
        }
    }
    outcome(r)
}

/// The outcome of a parse: "ok", or the error message without digits and
/// quoted input; a finding if the message is empty, not one line, or holds
/// a control character (echoed input must be escaped).
fn outcome<T, E: std::fmt::Display>(r: Result<T, E>) -> Result<String, String> {
    match r {
        Ok(_) => Ok("ok".into()),
        Err(e) => {
            let m = e.to_string();
            if m.trim().is_empty() || m.chars().any(char::is_control) {
                return Err(format!("error message is not one printable line: {m:?}"));
            }
            Ok(error_kind(&m))
        }
    }
}

/// The kind of an error, not the input it echoes: for each quote character
/// (' ` "), everything from its first to its last occurrence removed (the
/// echoed text may itself hold quotes), then the digits.
fn error_kind(m: &str) -> String {
    let mut k = m.to_string();
    for q in ['\'', '`', '"'] {
        if let (Some(a), Some(b)) = (k.find(q), k.rfind(q)) {
            if a < b {
                k.replace_range(a..=b, "…");
            }
        }
    }
    k.chars()
        .filter(|c| !c.is_ascii_digit())
        .take(160)
        .collect()
}

/// The time parsers. Invariants: the lenient parsers accept everything the
/// strict ones do, with the same result; whatever the CLI parser accepts,
/// [`format_utc`] prints, and that text reads back as the same fields (to
/// the printed millisecond) — one calendar in and out.
fn time(s: &str) -> Result<String, String> {
    let strict = parse_rfc3339(s);
    let lenient = parse_date_or_rfc3339(s);
    let date = parse_date(s);
    if let Ok(t) = &strict {
        if lenient.as_ref() != Ok(t) {
            return Err(format!("{s:?}: strict {t:?}, lenient {lenient:?}"));
        }
    }
    if let Ok(t) = &date {
        if lenient.as_ref() != Ok(t) {
            return Err(format!("{s:?}: date {t:?}, lenient {lenient:?}"));
        }
    }
    let cli = parse_date_or_time("--time", s, false);
    if let Ok(t) = &cli {
        let printed = format_utc(t);
        let back = parse_date_or_time("--time", &printed, false)
            .map_err(|e| format!("{s:?} printed as {printed:?} does not read back: {e}"))?;
        if format_utc(&back) != printed
            || (back.year, back.month, back.day, back.hour, back.minute)
                != (t.year, t.month, t.day, t.hour, t.minute)
        {
            return Err(format!(
                "{s:?} printed as {printed:?} reads back as {back:?}"
            ));
        }
        // The instant exists for the time scales too (or says why not).
        outcome(himmel_astro::Instant::from_utc(t))?;
    }
    let a = outcome(strict)?;
    let b = outcome(date)?;
    let c = outcome(cli)?;
    Ok(format!("{a}|{b}|{c}"))
}

/// `Scene::from_json`. Invariant: an accepted scene written back as JSON
/// reads back as the same scene.
fn scene(s: &str) -> Result<String, String> {
    let r = Scene::from_json(s);
    if let Ok(scene) = &r {
        let json = serde_json::to_string(scene).map_err(|e| format!("{s:?}: to_json: {e}"))?;
        let back = Scene::from_json(&json)
            .map_err(|e| format!("{s:?}: written as {json:?}, not read back: {e}"))?;
        if &back != scene {
            return Err(format!("{s:?}: written as {json:?}, read back as {back:?}"));
        }
    }
    outcome(r)
}

/// `--batch` lines (line numbers 1 and 2: the header is allowed on line 1
/// only). Invariant: errors start with `--batch: line n:`.
fn batch(s: &str) -> Result<String, String> {
    let mut out = String::new();
    for n in [1, 2] {
        let r = parse_batch_line(n, s);
        if let Err(e) = &r {
            if !e.starts_with(&format!("--batch: line {n}: ")) {
                return Err(format!("{s:?}: error does not name the line: {e}"));
            }
        }
        out += &outcome(r)?;
    }
    Ok(out)
}

/// A small, fast, seeded generator (SplitMix64, Steele et al. 2014).
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in `0..n` (`n` > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// Bytes that carry structure in the formats under test.
const PUNCTUATION: &[u8] = b"-+:.TtZz ,{}[]\"\\eE0123456789\n\r\t\x00";

/// Tokens that break parsers.
const TOKENS: &[&str] = &[
    "-",
    "+",
    "1e999",
    "-1e999",
    "-0",
    "NaN",
    "inf",
    "null",
    "true",
    "[]",
    "{}",
    "\"\"",
    "99999999999999999999",
    "-99999999999999999999",
    "4294967296",
    "-1",
    "0.0000000000000001",
    "1e-400",
    "60",
    "61",
    "24",
    "00",
    "31",
    "29",
    "1582",
    "-4713",
    "+1000000",
    "é",
    "\u{feff}",
    "𝄞",
    "\u{0}",
    ":",
    "T",
    "Z",
    ",",
    "\"now\"",
    "now",
    "\"x\":",
    "{\"a\":1}",
    "  ",
];

/// One random mutation of `input`; `other` is another corpus entry for
/// splicing.
fn mutate_once(rng: &mut Rng, input: &mut Vec<u8>, other: &[u8]) {
    let len = input.len();
    match rng.below(9) {
        0 if len > 0 => {
            let i = rng.below(len);
            input[i] ^= 1 << rng.below(8);
        }
        1 if len > 0 => {
            let i = rng.below(len);
            input[i] = PUNCTUATION[rng.below(PUNCTUATION.len())];
        }
        2 => {
            let i = rng.below(len + 1);
            let t = TOKENS[rng.below(TOKENS.len())].as_bytes();
            input.splice(i..i, t.iter().copied());
        }
        3 if len > 0 => {
            let i = rng.below(len);
            let n = 1 + rng.below((len - i).min(16));
            input.drain(i..i + n);
        }
        4 if len > 0 => {
            let i = rng.below(len);
            let n = 1 + rng.below((len - i).min(32));
            let copy: Vec<u8> = input[i..i + n].to_vec();
            let j = rng.below(len + 1);
            input.splice(j..j, copy);
        }
        5 if !other.is_empty() => {
            let i = rng.below(len + 1);
            let j = rng.below(other.len());
            input.truncate(i);
            input.extend_from_slice(&other[j..]);
        }
        6 if len > 0 => input.truncate(rng.below(len)),
        7 => {
            // A run of digits replaced by a boundary number.
            let digits: Vec<usize> = (0..len).filter(|&i| input[i].is_ascii_digit()).collect();
            if let Some(&start) = digits.get(rng.below(digits.len().max(1))) {
                let mut end = start;
                while end < len && input[end].is_ascii_digit() {
                    end += 1;
                }
                let n = [
                    "0",
                    "1",
                    "9",
                    "59",
                    "60",
                    "99",
                    "9999",
                    "10000",
                    "2147483648",
                    "1e308",
                ][rng.below(10)];
                input.splice(start..end, n.bytes());
            }
        }
        _ => {
            let i = rng.below(len + 1);
            input.insert(i, rng.next_u64() as u8);
        }
    }
}

/// What one target's run found.
#[derive(Debug, Clone)]
pub struct Report {
    /// The target.
    pub target: Target,
    /// Inputs executed.
    pub executed: u64,
    /// Wall-clock time.
    pub elapsed: Duration,
    /// Distinct outcomes seen (success, or an error message without digits).
    pub distinct_outcomes: usize,
    /// Corpus size at the end (seeds plus inputs with a new outcome).
    pub corpus: usize,
    /// Panics and broken invariants: (input, what happened), the first 20.
    pub findings: Vec<(String, String)>,
    /// All findings, counted.
    pub finding_count: u64,
}

/// Largest corpus kept; beyond it, new outcomes are counted but not kept.
const MAX_CORPUS: usize = 4096;

/// Runs `inputs` mutated inputs through `target` from `seed`.
pub fn fuzz(target: Target, inputs: u64, seed: u64) -> Report {
    let mut rng = Rng::new(seed ^ (target as u64).wrapping_mul(0x2545_f491_4f6c_dd1d));
    let mut corpus = target.seeds();
    let mut seen = HashSet::new();
    let mut findings = Vec::new();
    let mut finding_count = 0;
    let start = Instant::now();
    // Silence the default hook's message for caught panics; keep the text.
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    for k in 0..inputs {
        let mut input = corpus[rng.below(corpus.len())].clone();
        // The seeds themselves go first, unmutated.
        if k >= corpus.len() as u64 {
            let other = corpus[rng.below(corpus.len())].clone();
            for _ in 0..1 + rng.below(4) {
                mutate_once(&mut rng, &mut input, &other);
            }
            input.truncate(target.max_input());
        } else {
            input = corpus[k as usize].clone();
        }
        let result = catch_unwind(AssertUnwindSafe(|| target.run(&input)));
        let finding = match result {
            Ok(Ok(outcome)) => {
                if seen.insert(outcome) && corpus.len() < MAX_CORPUS {
                    corpus.push(input.clone());
                }
                None
            }
            Ok(Err(broken)) => Some(broken),
            Err(panic) => Some(format!(
                "panic: {}",
                panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default()
            )),
        };
        if let Some(f) = finding {
            finding_count += 1;
            if findings.len() < 20 {
                findings.push((format!("{:?}", String::from_utf8_lossy(&input)), f));
            }
        }
    }
    std::panic::set_hook(previous);
    Report {
        target,
        executed: inputs,
        elapsed: start.elapsed(),
        distinct_outcomes: seen.len(),
        corpus: corpus.len(),
        findings,
        finding_count,
    }
}
