//! `himmel phases`, `himmel riseset`, `himmel eclipses`: the JSON shapes of
//! spec/cli.md, exit code 2 with a one-line error naming the flag on bad
//! input.

mod common;

use common::{himmel, json};

fn keys(v: &serde_json::Value) -> Vec<String> {
    let mut k: Vec<String> = v.as_object().unwrap().keys().cloned().collect();
    k.sort();
    k
}

#[test]
fn phases_json_shape() {
    let v = json(&himmel(&[
        "phases",
        "--from",
        "2024-01-01",
        "--to",
        "2024-02-01",
        "--format",
        "json",
    ]));
    let a = v.as_array().unwrap();
    assert_eq!(a.len(), 4);
    assert_eq!(keys(&a[0]), ["phase", "utc"]);
    assert_eq!(a[0]["phase"], "last_quarter");
    assert!(a[0]["utc"].as_str().unwrap().ends_with('Z'));
    let names: Vec<_> = a.iter().map(|p| p["phase"].as_str().unwrap()).collect();
    assert_eq!(names, ["last_quarter", "new", "first_quarter", "full"]);
}

#[test]
fn riseset_json_shape_and_polar_state() {
    let v = json(&himmel(&[
        "riseset",
        "--body",
        "sun",
        "--date",
        "2024-06-21",
        "--lat",
        "-78",
        "--lon",
        "166.67",
        "--format",
        "json",
    ]));
    assert_eq!(keys(&v), ["body", "date", "events", "state"]);
    assert_eq!(v["state"], "always_down");
    assert_eq!(v["date"], "2024-06-21");
    let v = json(&himmel(&[
        "riseset",
        "--body",
        "moon",
        "--date",
        "2024-06-21",
        "--lat",
        "52.52",
        "--lon",
        "13.405",
        "--format",
        "json",
    ]));
    assert_eq!(v["state"], "normal");
    let ev = v["events"].as_array().unwrap();
    assert!(!ev.is_empty());
    assert_eq!(keys(&ev[0]), ["event", "utc"]);
    // The separated negative form works.
    let out = himmel(&[
        "riseset",
        "--body",
        "sun",
        "--date",
        "2024-01-01",
        "--lat",
        "-33.9",
        "--lon",
        "-70.5",
    ]);
    assert!(out.status.success());
}

#[test]
fn eclipses_json_shapes() {
    let v = json(&himmel(&[
        "eclipses",
        "--kind",
        "lunar",
        "--from",
        "2025-01-01",
        "--to",
        "2026-01-01",
        "--format",
        "json",
    ]));
    let a = v.as_array().unwrap();
    assert_eq!(a.len(), 2);
    assert_eq!(
        keys(&a[0]),
        [
            "gamma",
            "greatest_utc",
            "kind",
            "penumbral_magnitude",
            "type",
            "umbral_magnitude"
        ]
    );
    assert_eq!(a[0]["kind"], "lunar");
    assert_eq!(a[0]["type"], "total");
    let v = json(&himmel(&[
        "eclipses",
        "--kind",
        "solar",
        "--from",
        "2024-01-01",
        "--to",
        "2025-01-01",
        "--format",
        "json",
    ]));
    let a = v.as_array().unwrap();
    assert_eq!(a.len(), 2);
    assert_eq!(
        keys(&a[0]),
        ["gamma", "greatest_utc", "kind", "magnitude", "type"]
    );
    assert_eq!(a[0]["type"], "total");
    assert_eq!(a[1]["type"], "annular");
    let v = json(&himmel(&[
        "eclipses",
        "--kind",
        "solar",
        "--local",
        "--lat",
        "32.7767",
        "--lon",
        "-96.797",
        "--from",
        "2024-01-01",
        "--to",
        "2025-01-01",
        "--format",
        "json",
    ]));
    let a = v.as_array().unwrap();
    assert_eq!(a.len(), 1);
    assert_eq!(
        keys(&a[0]),
        [
            "c1_utc",
            "c2_utc",
            "c3_utc",
            "c4_utc",
            "max_magnitude",
            "max_obscuration",
            "max_utc",
            "type_local"
        ]
    );
    assert_eq!(a[0]["type_local"], "total");
    // New York 2024: partial, c2/c3 null.
    let v = json(&himmel(&[
        "eclipses",
        "--kind",
        "solar",
        "--local",
        "--lat",
        "40.71",
        "--lon",
        "-74.01",
        "--from",
        "2024-04-01",
        "--to",
        "2024-05-01",
        "--format",
        "json",
    ]));
    assert_eq!(v[0]["type_local"], "partial");
    assert!(v[0]["c2_utc"].is_null() && v[0]["c3_utc"].is_null());
}

#[test]
fn bad_input_exits_2_with_one_line_naming_the_flag() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["phases", "--from", "2024-02-01", "--to", "2024-01-01"],
            "--to",
        ),
        // A 20 000-year interval.
        (
            &[
                "eclipses",
                "--kind",
                "lunar",
                "--from=-9000-01-01T00:00:00Z",
                "--to=+11000-01-01T00:00:00Z",
            ],
            "1000 years",
        ),
        (
            &["phases", "--from", "2023-02-30", "--to", "2024-01-01"],
            "--from",
        ),
        (
            &["phases", "--from", "yesterday", "--to", "2024-01-01"],
            "--from",
        ),
        (
            &[
                "riseset",
                "--body",
                "moon",
                "--date",
                "2024-13-01",
                "--lat",
                "0",
                "--lon",
                "0",
            ],
            "--date",
        ),
        (
            &[
                "riseset",
                "--body",
                "sun",
                "--date",
                "2024-02-30",
                "--lat",
                "0",
                "--lon",
                "0",
            ],
            "--date",
        ),
        (
            &[
                "riseset",
                "--body",
                "pluto",
                "--date",
                "2024-01-01",
                "--lat",
                "0",
                "--lon",
                "0",
            ],
            "--body",
        ),
        (
            &[
                "riseset",
                "--body",
                "sun",
                "--date",
                "2024-01-01",
                "--lat",
                "91",
                "--lon",
                "0",
            ],
            "--lat",
        ),
        (
            &[
                "eclipses",
                "--kind",
                "solar",
                "--local",
                "--from",
                "2024-01-01",
                "--to",
                "2025-01-01",
            ],
            "--lat",
        ),
        (
            &[
                "eclipses",
                "--kind",
                "solar",
                "--local",
                "--lat",
                "0",
                "--lon",
                "0",
                "--from",
                "2024-01-01",
                "--to",
                "2025-01-01",
                "--precision",
                "best",
            ],
            "--precision",
        ),
        (
            &[
                "eclipses",
                "--kind",
                "comet",
                "--from",
                "2024-01-01",
                "--to",
                "2025-01-01",
            ],
            "--kind",
        ),
    ];
    for (args, needle) in cases {
        let out = himmel(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.starts_with("error:"), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(out.stdout.is_empty());
    }
}

/// Seconds of the UTC day of an RFC 3339 time `…THH:MM:SS.sssZ`.
fn day_seconds(v: &serde_json::Value) -> f64 {
    let s = v.as_str().unwrap();
    let clock = s.split_once('T').unwrap().1.trim_end_matches('Z');
    let mut parts = clock.split(':').map(|p| p.parse::<f64>().unwrap());
    let (h, m, sec) = (
        parts.next().unwrap(),
        parts.next().unwrap(),
        parts.next().unwrap(),
    );
    h * 3600.0 + m * 60.0 + sec
}

#[test]
fn local_solar_eclipses_default_to_the_de421_moon() {
    // Reykjavik, 2026-08-12, near the path limit: without --precision the
    // contacts are those of --precision high (DE421 Moon); an explicit
    // --precision standard is honoured (Meeus Moon: C2 about 15 s later).
    let run = |extra: &[&str]| {
        let mut args = vec![
            "eclipses",
            "--kind",
            "solar",
            "--local",
            "--lat",
            "64.1466",
            "--lon",
            "-21.9426",
            "--from",
            "2026-08-01",
            "--to",
            "2026-09-01",
            "--format",
            "json",
        ];
        args.extend_from_slice(extra);
        let v = json(&himmel(&args));
        assert_eq!(v.as_array().unwrap().len(), 1);
        assert_eq!(v[0]["type_local"], "total");
        v[0].clone()
    };
    let default = run(&[]);
    let high = run(&["--precision", "high"]);
    let standard = run(&["--precision", "standard"]);
    for key in ["c1_utc", "c2_utc", "c3_utc", "c4_utc"] {
        let d = day_seconds(&default[key]);
        assert!((d - day_seconds(&high[key])).abs() < 0.05, "{key}");
    }
    let off = (day_seconds(&default["c2_utc"]) - day_seconds(&standard["c2_utc"])).abs();
    assert!(off > 5.0, "standard C2 only {off} s from the default");
}

/// Issue 19, one calendar in and out: every `greatest_utc` that `eclipses`
/// prints for −1999 … +3000 (Julian calendar before 1582-10-15, signed
/// years) is read back by `ephemeris` (`--batch`, which parses each line's
/// time as `--time` does) as the same text.
#[test]
fn every_printed_eclipse_time_reads_back_unchanged() {
    let chunks = [
        ("-1999-01-01", "-0999-01-01"),
        ("-0999-01-01", "0001-01-01"),
        ("0001-01-01", "1001-01-01"),
        ("1001-01-01", "2001-01-01"),
        ("2001-01-01", "3001-01-01"),
    ];
    let mut times = Vec::new();
    for kind in ["solar", "lunar"] {
        for (from, to) in chunks {
            let from = format!("--from={from}");
            let to = format!("--to={to}");
            let v = json(&himmel(&[
                "eclipses", "--kind", kind, &from, &to, "--format", "json",
            ]));
            for e in v.as_array().unwrap() {
                times.push(e["greatest_utc"].as_str().unwrap().to_owned());
            }
        }
    }
    // 2.4 solar and 2.4 lunar eclipses a year on average (Espenak & Meeus).
    assert!(times.len() > 22_000, "{}", times.len());
    assert!(times.iter().any(|t| t.starts_with('-')));
    assert!(times.iter().any(|t| t.contains("-02-29T")));
    let dir = std::env::temp_dir().join(format!("himmel-calendar-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("times.csv");
    let text: String = times.iter().map(|t| format!("{t},0,0,0\n")).collect();
    std::fs::write(&csv, text).unwrap();
    let out = himmel(&[
        "ephemeris",
        "--batch",
        csv.to_str().unwrap(),
        "--body",
        "sun",
    ]);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), times.len());
    for (line, t) in lines.iter().zip(&times) {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(v["time_utc"].as_str().unwrap(), t);
    }
}

/// Negative and five-digit years, date-only and full, on every flag that
/// takes a time; 1582 October 5–14 do not exist.
#[test]
fn signed_years_and_the_gregorian_switch_on_the_command_line() {
    let v = json(&himmel(&[
        "ephemeris",
        "--time=-0500-01-01",
        "--lat",
        "0",
        "--lon",
        "0",
        "--body",
        "sun",
        "--format",
        "json",
    ]));
    assert_eq!(v["time_utc"], "-0500-01-01T00:00:00.000Z");
    let v = json(&himmel(&[
        "ephemeris",
        "--time",
        "+10000-01-01T12:00:00Z",
        "--lat",
        "0",
        "--lon",
        "0",
        "--body",
        "sun",
        "--format",
        "json",
    ]));
    assert_eq!(v["time_utc"], "+10000-01-01T12:00:00.000Z");
    let v = json(&himmel(&[
        "phases",
        "--from=-0500-01-01",
        "--to=-0500-02-01",
        "--format",
        "json",
    ]));
    assert!(v[0]["utc"].as_str().unwrap().starts_with("-0500-01-"));
    let v = json(&himmel(&[
        "riseset",
        "--body",
        "sun",
        "--date=-0500-03-01",
        "--lat",
        "40",
        "--lon",
        "0",
        "--format",
        "json",
    ]));
    assert_eq!(v["date"], "-0500-03-01");
    // October 4 (Julian) 12h to October 15 (Gregorian) 12h is one day.
    let jd = |t: &str| {
        json(&himmel(&[
            "ephemeris",
            "--time",
            t,
            "--lat",
            "0",
            "--lon",
            "0",
            "--body",
            "sun",
            "--format",
            "json",
        ]))["jd_tt"]
            .as_f64()
            .unwrap()
    };
    let d = jd("1582-10-15T12:00:00Z") - jd("1582-10-04T12:00:00Z");
    assert!((d - 1.0).abs() < 1e-6, "{d}");
    for bad in ["--time=1582-10-10", "--time=1582-10-10T00:00:00Z"] {
        let out = himmel(&["ephemeris", bad, "--lat", "0", "--lon", "0"]);
        assert_eq!(out.status.code(), Some(2));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.starts_with("error: --time:") && err.contains("Gregorian reform"),
            "{err}"
        );
        assert_eq!(err.lines().count(), 1);
    }
}
