//! The `himmel` command-line contract: field names, exit codes, one-line
//! errors that name the flag, negative numbers in the separated form.

use std::io::Write;
mod common;

use common::{himmel, json};
use std::process::{Command, Stdio};

const DALLAS: [&str; 8] = [
    "ephemeris",
    "--time",
    "2024-04-08T18:42:00Z",
    "--lat",
    "32.7767",
    "--lon",
    "-96.797",
    "--elevation",
];

#[test]
fn ephemeris_json_has_every_contract_field() {
    let mut args = DALLAS.to_vec();
    args.extend(["140", "--format", "json"]);
    let v = json(&himmel(&args));
    for k in [
        "time_utc",
        "jd_tt",
        "delta_t_s",
        "gast_hours",
        "observer",
        "precision",
        "bodies",
    ] {
        assert!(v.get(k).is_some(), "missing {k}");
    }
    assert_eq!(v["time_utc"], "2024-04-08T18:42:00.000Z");
    assert_eq!(v["precision"], "standard");
    assert_eq!(v["observer"]["lon_deg"].as_f64().unwrap(), -96.797);
    let common = [
        "ra_deg",
        "dec_deg",
        "distance_km",
        "ecl_lon_deg",
        "ecl_lat_deg",
        "alt_deg",
        "az_deg",
        "alt_refracted_deg",
        "topo_distance_km",
    ];
    let bodies = v["bodies"].as_object().unwrap();
    let names: Vec<_> = bodies.keys().cloned().collect();
    assert_eq!(
        names,
        ["sun", "moon", "mercury", "venus", "mars", "jupiter", "saturn"]
    );
    for (name, b) in bodies {
        for k in common {
            assert!(b[k].as_f64().unwrap().is_finite(), "{name}.{k}");
        }
        let extra: &[&str] = match name.as_str() {
            "sun" => &["semidiameter_deg"],
            "moon" => &[
                "semidiameter_deg",
                "phase_angle_deg",
                "illuminated_fraction",
                "elongation_deg",
                "bright_limb_pa_deg",
                "libration_lon_deg",
                "libration_lat_deg",
                "axis_pa_deg",
                "parallactic_angle_deg",
            ],
            _ => &["magnitude"],
        };
        for k in extra {
            assert!(b[*k].as_f64().unwrap().is_finite(), "{name}.{k}");
        }
    }
    // The 2024 eclipse: Sun and Moon within a few arcminutes, Sun high.
    let (s, m) = (&bodies["sun"], &bodies["moon"]);
    assert!(s["alt_deg"].as_f64().unwrap() > 60.0);
    let d_alt = s["alt_deg"].as_f64().unwrap() - m["alt_deg"].as_f64().unwrap();
    assert!(d_alt.abs() < 0.1, "{d_alt}");
    assert!(m["illuminated_fraction"].as_f64().unwrap() < 0.001);
}

#[test]
fn negative_numbers_work_separated_and_with_equals() {
    let a = json(&himmel(&[
        "ephemeris",
        "--time",
        "2024-01-01T00:00:00Z",
        "--lat",
        "-33.9",
        "--lon",
        "-70.6",
        "--body",
        "sun",
        "--format",
        "json",
    ]));
    let b = json(&himmel(&[
        "ephemeris",
        "--time=2024-01-01T00:00:00Z",
        "--lat=-33.9",
        "--lon=-70.6",
        "--body=sun",
        "--format=json",
    ]));
    assert_eq!(a, b);
    assert_eq!(a["observer"]["lat_deg"].as_f64().unwrap(), -33.9);
}

fn assert_input_error(args: &[&str], needle: &str) {
    let out = himmel(args);
    assert_eq!(out.status.code(), Some(2), "{args:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<_> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: {err}");
    assert!(lines[0].starts_with("error: "), "{err}");
    assert!(
        lines[0].contains(needle),
        "{args:?}: '{}' lacks '{needle}'",
        lines[0]
    );
}

#[test]
fn bad_input_exits_2_with_one_line_naming_the_flag() {
    let base = |time: &str, lat: &str| {
        vec![
            "ephemeris".to_string(),
            "--time".into(),
            time.into(),
            "--lat".into(),
            lat.into(),
            "--lon".into(),
            "0".into(),
        ]
    };
    let run = |v: Vec<String>, needle: &str| {
        let r: Vec<&str> = v.iter().map(String::as_str).collect();
        assert_input_error(&r, needle);
    };
    run(base("yesterday", "10"), "--time");
    run(base("2024-02-30T00:00:00Z", "10"), "--time");
    run(base("2024-04-08T18:42:00", "10"), "--time");
    run(base("2024-04-08T18:42:00Z", "91"), "--lat");
    run(base("2024-04-08T18:42:00Z", "nan"), "--lat");
    run(base("2024-04-08T18:42:00Z", "abc"), "--lat");
    let mut v = base("2024-04-08T18:42:00Z", "10");
    v.extend(["--body".into(), "pluto".into()]);
    run(v, "--body");
    let mut v = base("2024-04-08T18:42:00Z", "10");
    v.extend(["--precision".into(), "extreme".into()]);
    run(v, "--precision");
    let mut v = base("2024-04-08T18:42:00Z", "10");
    v.push("--frobnicate".into());
    run(v, "--frobnicate");
    assert_input_error(&["ephemeris", "--lat", "1", "--lon", "2"], "--time");
    assert_input_error(
        &["ephemeris", "--time", "now", "--lat", "1", "--lon", "400"],
        "--lon",
    );
}

#[test]
fn batch_prints_one_json_line_per_input_line_in_order() {
    let input = "time,lat,lon,elevation_m\n2024-04-08T18:42:00Z,32.7767,-96.797,140\n2000-01-01T12:00:00Z,-90,180,0\n\n2016-12-31T23:59:60Z,52.5,13.4,34\n";
    let mut child = Command::new(env!("CARGO_BIN_EXE_himmel"))
        .args([
            "ephemeris",
            "--batch",
            "-",
            "--body",
            "sun,moon",
            "--format",
            "json",
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<serde_json::Value> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 3);
    assert_eq!(lines[0]["time_utc"], "2024-04-08T18:42:00.000Z");
    assert_eq!(lines[1]["observer"]["lat_deg"].as_f64().unwrap(), -90.0);
    assert_eq!(lines[2]["time_utc"], "2016-12-31T23:59:60.000Z");
    assert_eq!(lines[2]["bodies"].as_object().unwrap().len(), 2);
}

#[test]
fn batch_errors_name_the_line() {
    let dir = std::env::temp_dir().join(format!("himmel-batch-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("bad.csv");
    std::fs::write(
        &f,
        "2024-04-08T18:42:00Z,10,10,0\n2024-04-08T18:42:00Z,95,10,0\n",
    )
    .unwrap();
    assert_input_error(&["ephemeris", "--batch", f.to_str().unwrap()], "line 2");
    std::fs::write(&f, "2024-04-08T18:42:00Z,10,10\n").unwrap();
    assert_input_error(&["ephemeris", "--batch", f.to_str().unwrap()], "line 1");
    assert_input_error(&["ephemeris", "--batch", "/nonexistent/x.csv"], "--batch");
}

#[test]
fn table_output_is_the_default() {
    let out = himmel(&[
        "ephemeris",
        "--time",
        "2024-04-08T18:42:00Z",
        "--lat",
        "32.7767",
        "--lon",
        "-96.797",
    ]);
    assert!(out.status.success());
    let s = String::from_utf8(out.stdout).unwrap();
    assert!(s.contains("moon") && s.contains("saturn") && s.contains("alt"));
}

#[test]
fn stars_json_contract_and_errors() {
    let out = himmel(&[
        "stars",
        "--time",
        "2024-01-15T21:00:00Z",
        "--lat",
        "-33.9",
        "--lon",
        "-70.6",
        "--limit-mag",
        "1.0",
        "--above-horizon",
        "--format",
        "json",
    ]);
    let v = json(&out);
    let arr = v.as_array().unwrap();
    assert!(!arr.is_empty());
    for s in arr {
        for k in [
            "hip", "hr", "name", "vmag", "bv", "ra_deg", "dec_deg", "alt_deg", "az_deg",
        ] {
            assert!(s.get(k).is_some(), "missing {k}");
        }
        assert!(s["alt_deg"].as_f64().unwrap() > 0.0);
        assert!(s["vmag"].as_f64().unwrap() <= 1.0);
    }
    // Brightest first; Canopus is up from Santiago on a January evening.
    let v: Vec<f64> = arr.iter().map(|s| s["vmag"].as_f64().unwrap()).collect();
    assert!(v.windows(2).all(|w| w[0] <= w[1]));
    assert!(arr.iter().any(|s| s["name"] == "Canopus"));
    let all = json(&himmel(&[
        "stars",
        "--time",
        "2024-01-15T21:00:00Z",
        "--lat",
        "90",
        "--lon",
        "0",
        "--format",
        "json",
    ]));
    assert!(all.as_array().unwrap().len() >= 8800);
    for (args, flag) in [
        (
            vec![
                "stars",
                "--time",
                "2024-01-15T21:00:00Z",
                "--lat",
                "91",
                "--lon",
                "0",
            ],
            "--lat",
        ),
        (
            vec!["stars", "--time", "yesterday", "--lat", "1", "--lon", "0"],
            "--time",
        ),
        (vec!["stars", "--lat", "1", "--lon", "0"], "--time"),
        (
            vec![
                "stars",
                "--time",
                "now",
                "--lat",
                "1",
                "--lon",
                "0",
                "--limit-mag",
                "NaN",
            ],
            "--limit-mag",
        ),
    ] {
        let out = himmel(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.starts_with("error:") && err.contains(flag) && err.lines().count() == 1,
            "{err}"
        );
    }
}

#[test]
fn a_reader_gone_before_the_output_ends_the_program_quietly() {
    // `himmel scene-template | head -1` and the like: the read end is
    // closed before the child writes (the child takes milliseconds to start),
    // so its write meets a closed pipe: success, nothing on stderr, no panic.
    for args in [
        &["scene-template", "--world"][..],
        &[
            "eclipses",
            "--kind",
            "solar",
            "--from",
            "2000-01-01",
            "--to",
            "2200-01-01",
        ][..],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_himmel"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        assert!(out.status.success(), "{args:?}: {:?}", out.status);
        assert!(
            out.stderr.is_empty(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn a_reader_that_stops_early_ends_the_program_quietly() {
    // `himmel stars … | head -1`: the closed pipe is not an error.
    use std::io::{BufRead, BufReader};
    let mut child = Command::new(env!("CARGO_BIN_EXE_himmel"))
        .args([
            "stars",
            "--time",
            "2024-03-20T21:00:00Z",
            "--lat",
            "52.52",
            "--lon",
            "13.4",
            "--limit-mag",
            "8",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    // The reader is dropped here: the pipe closes while the table is written.
    let out = child.wait_with_output().unwrap();
    assert!(!first.is_empty());
    assert!(out.status.success(), "{:?}", out.status);
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
