//! `himmel ephemeris`: apparent positions for an observer, single or batch.

use std::io::{BufRead, Write};

use clap::Args;
use himmel_astro::units::{DEG, KM_PER_AU, MOON_RADIUS_KM, SUN_RADIUS_KM};
use himmel_astro::{Body, Instant, Observer, Precision, Sky, UtcDateTime};
use serde_json::{json, Map, Value};

use crate::common;
use crate::timearg::{format_utc, parse_date_or_time};
use crate::{CliError, Format};
use himmel_cli::inputs::parse_batch_line;

#[derive(Args, Debug)]
pub struct EphemerisArgs {
    /// Instant: RFC 3339 civil UTC (e.g. 2024-04-08T18:42:00Z), a date
    /// YYYY-MM-DD (0h UTC) or `now`. Julian calendar before 1582-10-15,
    /// signed years outside 0000-9999 (-0500-03-01T12:00:00Z).
    #[arg(long, value_name = "TIME")]
    time: Option<String>,
    #[command(flatten)]
    observer: common::ObserverArgs,
    /// Comma-separated bodies (sun, moon, mercury, venus, mars, jupiter, saturn) or `all`.
    #[arg(long, value_name = "LIST", default_value = "all")]
    body: String,
    /// Accuracy tier: low, standard or high.
    #[arg(long, value_name = "TIER", default_value = "standard")]
    precision: String,
    /// Read CSV lines `time,lat,lon,elevation_m` from FILE (or `-` for stdin)
    /// and print one JSON object per line.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["time", "lat", "lon"])]
    batch: Option<String>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
}

/// Parses `--body`.
pub fn parse_bodies(list: &str) -> Result<Vec<Body>, String> {
    let mut out = Vec::new();
    for name in list.split(',').map(str::trim) {
        if name.eq_ignore_ascii_case("all") {
            for b in Body::ALL {
                if !out.contains(&b) {
                    out.push(b);
                }
            }
            continue;
        }
        let b = Body::from_name(name).ok_or_else(|| {
            format!(
                "--body: unknown body '{name}'; expected a comma list of sun, moon, mercury, venus, mars, jupiter, saturn, or all"
            )
        })?;
        if !out.contains(&b) {
            out.push(b);
        }
    }
    Ok(out)
}

/// Parses `--precision`.
pub fn parse_precision(s: &str) -> Result<Precision, String> {
    Precision::from_name(s.trim())
        .ok_or_else(|| format!("--precision: unknown tier '{s}'; expected low, standard or high"))
}

/// Parses `--time`: `now`, RFC 3339 or a date (0h UTC); Julian calendar
/// before 1582-10-15 ([`crate::timearg`]).
pub fn parse_time(s: &str) -> Result<UtcDateTime, String> {
    parse_date_or_time("--time", s, true)
}

/// One observation request.
struct Request {
    utc: UtcDateTime,
    observer: Observer,
}

fn request(time: &str, lat: f64, lon: f64, elevation: f64) -> Result<Request, String> {
    let utc = parse_time(time)?;
    let observer = common::observer(lat, lon, elevation)?;
    Ok(Request { utc, observer })
}

pub fn run(args: &EphemerisArgs) -> Result<(), CliError> {
    let bodies = parse_bodies(&args.body).map_err(CliError::input)?;
    let precision = parse_precision(&args.precision).map_err(CliError::input)?;
    if let Some(path) = &args.batch {
        return run_batch(path, &bodies, precision);
    }
    let time = args.time.as_deref().ok_or_else(|| {
        CliError::input(
            "--time is required (RFC 3339 UTC, e.g. 2024-04-08T18:42:00Z, a date, or now)",
        )
    })?;
    let (lat, lon) = args.observer.lat_lon("")?;
    let req = request(time, lat, lon, args.observer.elevation).map_err(CliError::input)?;
    let doc = compute(&req, &bodies, precision).map_err(CliError::input)?;
    let mut out = std::io::stdout().lock();
    let text = match args.format {
        Format::Json => {
            serde_json::to_string_pretty(&doc).map_err(|e| CliError::other(e.to_string()))?
        }
        Format::Table => table(&doc),
    };
    writeln!(out, "{text}").map_err(CliError::stdout)?;
    Ok(())
}

fn run_batch(path: &str, bodies: &[Body], precision: Precision) -> Result<(), CliError> {
    let reader: Box<dyn BufRead> = if path == "-" {
        Box::new(std::io::BufReader::new(std::io::stdin()))
    } else {
        let f = std::fs::File::open(path)
            .map_err(|e| CliError::input(format!("--batch: cannot read '{path}': {e}")))?;
        Box::new(std::io::BufReader::new(f))
    };
    // Parse everything first so that a bad line fails before any output.
    let mut requests = Vec::new();
    for (i, line) in reader.lines().enumerate() {
        let n = i + 1;
        let line = line.map_err(|e| CliError::input(format!("--batch: line {n}: {e}")))?;
        if let Some(b) = parse_batch_line(n, &line).map_err(CliError::input)? {
            requests.push(Request {
                utc: b.utc,
                observer: b.observer,
            });
        }
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    for req in &requests {
        let doc = compute(req, bodies, precision).map_err(CliError::input)?;
        serde_json::to_writer(&mut out, &doc).map_err(CliError::json)?;
        out.write_all(b"\n").map_err(CliError::stdout)?;
    }
    out.flush().map_err(CliError::stdout)?;
    Ok(())
}

/// The JSON document of one request, field names as in `spec/cli.md`.
fn compute(req: &Request, bodies: &[Body], precision: Precision) -> Result<Value, String> {
    let instant = Instant::from_utc(&req.utc).map_err(|e| format!("--time: {e}"))?;
    let sky = Sky::new(precision, &instant);
    let epoch = sky.epoch();
    let mut map = Map::new();
    for &body in bodies {
        let geo = sky.apparent(body).map_err(|e| e.to_string())?;
        let topo = req.observer.topocentric(&geo, epoch);
        let mut rec = Map::new();
        rec.insert("ra_deg".into(), json!(geo.ra / DEG));
        rec.insert("dec_deg".into(), json!(geo.dec / DEG));
        rec.insert("distance_km".into(), json!(geo.distance_km));
        rec.insert("ecl_lon_deg".into(), json!(geo.ecl_lon / DEG));
        rec.insert("ecl_lat_deg".into(), json!(geo.ecl_lat / DEG));
        rec.insert("alt_deg".into(), json!(topo.alt_deg()));
        rec.insert("az_deg".into(), json!(topo.az_deg()));
        rec.insert("alt_refracted_deg".into(), json!(topo.alt_refracted_deg()));
        rec.insert("topo_distance_km".into(), json!(topo.distance_km));
        match body {
            Body::Sun => {
                rec.insert(
                    "semidiameter_deg".into(),
                    json!(topo.semidiameter_deg(SUN_RADIUS_KM)),
                );
            }
            Body::Moon => {
                rec.insert(
                    "semidiameter_deg".into(),
                    json!(topo.semidiameter_deg(MOON_RADIUS_KM)),
                );
                let p = sky.moon_physical().map_err(|e| e.to_string())?;
                rec.insert("phase_angle_deg".into(), json!(p.phase_angle / DEG));
                rec.insert("illuminated_fraction".into(), json!(p.illuminated_fraction));
                rec.insert("elongation_deg".into(), json!(p.elongation / DEG));
                rec.insert("bright_limb_pa_deg".into(), json!(p.bright_limb_pa / DEG));
                rec.insert("libration_lon_deg".into(), json!(p.libration_lon / DEG));
                rec.insert("libration_lat_deg".into(), json!(p.libration_lat / DEG));
                rec.insert("axis_pa_deg".into(), json!(p.axis_pa / DEG));
                rec.insert(
                    "parallactic_angle_deg".into(),
                    json!(topo.parallactic_angle_deg()),
                );
            }
            _ => {
                let m = sky.planet_magnitude(body).map_err(|e| e.to_string())?;
                rec.insert("magnitude".into(), json!(m));
            }
        }
        map.insert(body.name().into(), Value::Object(rec));
    }
    Ok(json!({
        "time_utc": format_utc(&req.utc),
        "jd_tt": instant.jd_tt,
        "delta_t_s": instant.delta_t(),
        "gast_hours": epoch.gast() / DEG / 15.0,
        "observer": {
            "lat_deg": req.observer.lat_deg(),
            "lon_deg": req.observer.lon_deg(),
            "elevation_m": req.observer.elevation_m(),
        },
        "precision": precision.name(),
        "bodies": Value::Object(map),
    }))
}

/// A readable table of one document.
fn table(doc: &Value) -> String {
    let f = |v: &Value, k: &str| v.get(k).and_then(Value::as_f64).unwrap_or(f64::NAN);
    let mut s = String::new();
    let obs = &doc["observer"];
    s.push_str(&format!(
        "{}  lat {:.4}°  lon {:.4}°  elev {:.0} m  ({} precision)\n",
        doc["time_utc"].as_str().unwrap_or(""),
        f(obs, "lat_deg"),
        f(obs, "lon_deg"),
        f(obs, "elevation_m"),
        doc["precision"].as_str().unwrap_or("")
    ));
    s.push_str(&format!(
        "JD(TT) {:.6}   ΔT {:.2} s   GAST {:.6} h\n\n",
        f(doc, "jd_tt"),
        f(doc, "delta_t_s"),
        f(doc, "gast_hours")
    ));
    s.push_str(&format!(
        "{:<8} {:>11} {:>10} {:>15} {:>9} {:>9} {:>9}  {}\n",
        "body", "RA (h)", "Dec (°)", "dist (km)", "alt (°)", "az (°)", "alt+R (°)", "notes"
    ));
    if let Some(bodies) = doc["bodies"].as_object() {
        for (name, b) in bodies {
            let dist = f(b, "distance_km");
            let dist_s = if dist > 1e7 {
                format!("{:.6} au", dist / KM_PER_AU)
            } else {
                format!("{dist:.1}")
            };
            let notes = if name == "moon" {
                format!(
                    "phase {:.1}°, illuminated {:.1}%, bright limb {:.1}°",
                    f(b, "phase_angle_deg"),
                    100.0 * f(b, "illuminated_fraction"),
                    f(b, "bright_limb_pa_deg")
                )
            } else if b.get("magnitude").is_some() {
                format!("mag {:+.2}", f(b, "magnitude"))
            } else {
                format!("semidiameter {:.4}°", f(b, "semidiameter_deg"))
            };
            s.push_str(&format!(
                "{:<8} {:>11.6} {:>10.5} {:>15} {:>9.4} {:>9.4} {:>9.4}  {}\n",
                name,
                f(b, "ra_deg") / 15.0,
                f(b, "dec_deg"),
                dist_s,
                f(b, "alt_deg"),
                f(b, "az_deg"),
                f(b, "alt_refracted_deg"),
                notes
            ));
        }
    }
    s.trim_end().to_string()
}
