//! Every field of the scene template, one by one: a value of the wrong
//! type, and for numbers values out of range (huge, overflowing, negative
//! sizes), must give an error that names the field by its dotted path —
//! from `Scene::from_json` (types) or `Scene::validate` (ranges).

use himmel_skymodel::{Scene, SceneError};
use serde_json::Value;

/// Leaves whose every value of their type is valid, with the reason; the
/// in-type extreme value (u32::MAX for an integer) is not expected to fail
/// for them. Types still fail (1e300 is no u64).
const WHOLE_RANGE_VALID: &[(&str, &str)] = &[
    (
        "stars.seed",
        "any u64 seeds the scintillation pattern; no value is out of range",
    ),
    ("clouds.low.seed", "any u32 seeds the low layer's noise"),
    ("clouds.high.seed", "any u32 seeds the high layer's noise"),
];

/// String leaves of the template that also take a number (then range-checked).
const ALSO_NUMERIC: &[&str] = &["exposure"];

/// Optional groups and values of the template that `null` leaves out.
const NULLABLE: &[&str] = &[
    "sky_texture",
    "sky_texture.horizon",
    "sky_texture.sun_mask",
    "sky_texture.sun_mask.direction",
    "sky_texture.transitions[0].mapping",
];

/// A leaf of the template: dotted path (`camera.width`, `effects[0]`),
/// JSON pointer, value.
struct Leaf {
    path: String,
    pointer: String,
    value: Value,
}

fn walk(v: &Value, path: &str, pointer: &str, leaves: &mut Vec<Leaf>, nodes: &mut Vec<Leaf>) {
    match v {
        Value::Object(m) => {
            if !path.is_empty() {
                nodes.push(Leaf {
                    path: path.into(),
                    pointer: pointer.into(),
                    value: v.clone(),
                });
            }
            for (k, c) in m {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                walk(c, &p, &format!("{pointer}/{k}"), leaves, nodes);
            }
        }
        Value::Array(a) => {
            nodes.push(Leaf {
                path: path.into(),
                pointer: pointer.into(),
                value: v.clone(),
            });
            for (i, c) in a.iter().enumerate() {
                walk(
                    c,
                    &format!("{path}[{i}]"),
                    &format!("{pointer}/{i}"),
                    leaves,
                    nodes,
                );
            }
        }
        _ => leaves.push(Leaf {
            path: path.into(),
            pointer: pointer.into(),
            value: v.clone(),
        }),
    }
}

/// The template with every optional group that has keys filled in (the
/// default scene and a sky texture).
fn template() -> (Value, Vec<Leaf>, Vec<Leaf>) {
    let t: Value = serde_json::from_str(&Scene::template_sky_texture_json()).unwrap();
    let (mut leaves, mut nodes) = (Vec::new(), Vec::new());
    walk(&t, "", "", &mut leaves, &mut nodes);
    assert!(
        leaves.len() > 40,
        "the walk found only {} leaves",
        leaves.len()
    );
    (t, leaves, nodes)
}

const MARK: &str = "__himmel_test_value__";

/// The template with the value at `pointer` replaced by the raw JSON text
/// `raw` (which may be a number no `Value` holds, such as `1e999`).
fn with_raw(t: &Value, pointer: &str, raw: &str) -> String {
    let mut v = t.clone();
    *v.pointer_mut(pointer).unwrap() = Value::String(MARK.into());
    let text = serde_json::to_string_pretty(&v).unwrap();
    assert_eq!(text.matches(MARK).count(), 1);
    text.replace(&format!("\"{MARK}\""), raw)
}

/// Parses and validates: the first error.
fn load(text: &str) -> Result<Scene, SceneError> {
    let s = Scene::from_json(text)?;
    s.validate()?;
    Ok(s)
}

fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "bool",
        Value::Number(_) => "number",
        Value::String(_) => "string",
        Value::Array(_) => "array",
        Value::Object(_) => "object",
    }
}

fn assert_names(path: &str, raw: &str, text: &str) {
    match load(text) {
        Ok(_) => panic!("{path} = {raw}: accepted"),
        Err(e) => {
            assert_eq!(
                e.field, path,
                "{path} = {raw}: the error names another field: {e}"
            );
            assert!(
                e.to_string().starts_with(&format!("{path}: ")),
                "{path} = {raw}: {e}"
            );
            assert!(!e.message.is_empty() && !e.message.contains('\n'), "{e}");
        }
    }
}

#[test]
fn the_template_is_valid() {
    load(&Scene::template_json()).unwrap();
    load(&Scene::template_sky_texture_json()).unwrap();
}

#[test]
fn every_field_of_the_wrong_type_is_named() {
    let (t, leaves, nodes) = template();
    let wrong = [
        ("null", Value::Null),
        ("true", Value::Bool(true)),
        ("12.5", serde_json::json!(12.5)),
        ("\"text\"", Value::String("text".into())),
        ("[]", serde_json::json!([])),
        ("{}", serde_json::json!({})),
    ];
    let mut checked = 0;
    for leaf in leaves.iter().chain(&nodes) {
        for (raw, w) in &wrong {
            let mut skip = kind(w) == kind(&leaf.value);
            skip |= ALSO_NUMERIC.contains(&leaf.path.as_str()) && kind(w) == "number";
            skip |= NULLABLE.contains(&leaf.path.as_str()) && w.is_null();
            if skip {
                continue;
            }
            let text = with_raw(&t, &leaf.pointer, raw);
            assert_names(&leaf.path, raw, &text);
            // In words, not serde's "invalid type: …, expected f64".
            let e = load(&text).unwrap_err();
            assert!(
                e.message.starts_with("expected ") && !e.message.contains("invalid type"),
                "{e}"
            );
            checked += 1;
        }
    }
    assert!(checked > 200, "only {checked} cases");
    // The readable wording of the most common case.
    let e = load(&with_raw(&t, "/observer/lat_deg", "\"not-a-number\"")).unwrap_err();
    assert!(
        e.message
            .starts_with("expected a number, found a string (\"not-a-number\")"),
        "{e}"
    );
}

#[test]
fn every_number_out_of_range_is_named() {
    let (t, leaves, _) = template();
    for (path, _) in WHOLE_RANGE_VALID {
        assert!(
            leaves.iter().any(|l| l.path == *path),
            "{path} is listed but is no field"
        );
    }
    let mut checked = 0;
    for leaf in &leaves {
        let numeric = leaf.value.is_number() || ALSO_NUMERIC.contains(&leaf.path.as_str());
        if !numeric {
            continue;
        }
        let mut raws = vec!["1e300", "-1e300", "1e999", "-1e999"];
        if leaf.value.is_u64() {
            // A negative size, one beyond u64, and the largest u32.
            raws.extend(["-1", "18446744073709551616"]);
            let exempt = WHOLE_RANGE_VALID.iter().any(|(p, _)| *p == leaf.path);
            if exempt {
                load(&with_raw(&t, &leaf.pointer, "4294967295")).unwrap();
            } else {
                raws.push("4294967295");
            }
        }
        for raw in raws {
            assert_names(&leaf.path, raw, &with_raw(&t, &leaf.pointer, raw));
            checked += 1;
        }
    }
    assert!(checked > 150, "only {checked} cases");
}

#[test]
fn a_few_messages_read_well() {
    let (t, _, _) = template();
    for (pointer, raw, want) in [
        (
            "/observer/lat_deg",
            "1e999",
            "observer.lat_deg: number out of range",
        ),
        (
            "/camera/width",
            "-1",
            "camera.width: expected a whole number in [0, 4294967295], found the number -1",
        ),
        (
            "/lut/forward_peak_deg",
            "-50",
            "lut.forward_peak_deg: -50 is outside [0, 90]",
        ),
        (
            "/lut/forward_peak_deg",
            "1e39",
            "lut.forward_peak_deg: number out of range",
        ),
        (
            "/stars/core_px",
            "1e300",
            "stars.core_px: 1e300 is outside [0.3, 4]",
        ),
        (
            "/dither",
            "\"yes\"",
            "dither: expected true or false, found a string (\"yes\")",
        ),
        (
            "/camera",
            "3",
            "camera: expected an object ({ … }), found the number 3",
        ),
    ] {
        let e = load(&with_raw(&t, pointer, raw)).unwrap_err().to_string();
        assert!(e.starts_with(want), "{pointer} = {raw}: {e}");
    }
}
