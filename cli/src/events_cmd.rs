//! `himmel phases`, `himmel riseset`, `himmel eclipses`: sky events
//! (spec/cli.md). The science is in `himmel_astro::events`.

use std::io::Write;

use clap::{Args, ValueEnum};
use himmel_astro::events::lunar_eclipse::lunar_eclipses;
use himmel_astro::events::phases::phases;
use himmel_astro::events::riseset::rise_set_transit;
use himmel_astro::events::solar_eclipse::{
    local_solar_eclipses, local_solar_eclipses_preferring_de421, solar_eclipses,
};
use himmel_astro::events::{MAX_SEARCH_DAYS, MAX_SEARCH_JD, MIN_SEARCH_JD};
use himmel_astro::{AstroError, Body, Instant, Precision, Tiered};
use serde_json::{json, Value};

use crate::common;
use crate::ephemeris_cmd::parse_precision;
use crate::timearg::{format_date, format_utc, parse_date, parse_date_or_time};
use crate::{CliError, Format};

/// Interval flags shared by `phases` and `eclipses`.
#[derive(Args, Debug)]
pub struct IntervalArgs {
    /// Start of the interval: YYYY-MM-DD (0h UTC) or RFC 3339; Julian
    /// calendar before 1582-10-15, signed years outside 0000-9999
    /// (-0500-03-01, as the event commands print them).
    #[arg(long, value_name = "DATE")]
    from: String,
    /// End of the interval (exclusive): YYYY-MM-DD (0h UTC) or RFC 3339; at
    /// most 1000 years after --from.
    #[arg(long, value_name = "DATE")]
    to: String,
}

#[derive(Args, Debug)]
pub struct PhasesArgs {
    #[command(flatten)]
    interval: IntervalArgs,
    /// Accuracy tier: low, standard or high.
    #[arg(long, value_name = "TIER", default_value = "standard")]
    precision: String,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
}

#[derive(Args, Debug)]
pub struct RiseSetArgs {
    /// Body: sun or moon (planets are accepted too).
    #[arg(long, value_name = "BODY")]
    body: String,
    /// UTC calendar day, YYYY-MM-DD.
    #[arg(long, value_name = "DATE")]
    date: String,
    #[command(flatten)]
    observer: common::ObserverArgs,
    /// Accuracy tier: low, standard or high.
    #[arg(long, value_name = "TIER", default_value = "standard")]
    precision: String,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
}

/// Which eclipses.
#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum EclipseKindArg {
    /// Lunar eclipses.
    Lunar,
    /// Solar eclipses (global, or local with --local).
    Solar,
}

#[derive(Args, Debug)]
pub struct EclipsesArgs {
    /// lunar or solar.
    #[arg(long, value_enum)]
    kind: EclipseKindArg,
    /// Solar eclipses only: local circumstances for --lat/--lon.
    #[arg(long)]
    local: bool,
    #[command(flatten)]
    interval: IntervalArgs,
    #[command(flatten)]
    observer: common::ObserverArgs,
    /// Accuracy tier: low, standard or high. Default: standard, except with
    /// --local, where every eclipse inside the DE421 Moon's span
    /// (1899-07-29 .. 2053-10-09) gets high (the DE421-fitted Moon: contacts
    /// within 0.5 s of DE421 instead of 10-40 s, at about 1.3x the time of
    /// standard) and every other eclipse standard. A tier given explicitly
    /// applies to every eclipse.
    #[arg(long, value_name = "TIER")]
    precision: Option<String>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
}

/// The validated interval as instants.
fn interval(args: &IntervalArgs) -> Result<(Instant, Instant), CliError> {
    let from = parse_date_or_time("--from", &args.from, false).map_err(CliError::input)?;
    let to = parse_date_or_time("--to", &args.to, false).map_err(CliError::input)?;
    let a = Instant::from_utc(&from).map_err(|e| CliError::input(format!("--from: {e}")))?;
    let b = Instant::from_utc(&to).map_err(|e| CliError::input(format!("--to: {e}")))?;
    if b.jd_tt < a.jd_tt {
        return Err(CliError::input(format!(
            "--to {} is before --from {}; expected --from <= --to",
            args.to, args.from
        )));
    }
    if b.jd_tt - a.jd_tt > MAX_SEARCH_DAYS {
        return Err(CliError::input(format!(
            "--to: the interval {} .. {} is longer than the maximum of 1000 years",
            args.from, args.to
        )));
    }
    for (flag, v, i) in [("--from", &args.from, &a), ("--to", &args.to, &b)] {
        if !(MIN_SEARCH_JD..=MAX_SEARCH_JD).contains(&i.jd_tt) {
            return Err(CliError::input(format!(
                "{flag} {v} is outside the searchable years -4000 .. 8000"
            )));
        }
    }
    Ok((a, b))
}

fn utc_of(i: &Instant) -> String {
    format_utc(&i.to_utc())
}

fn astro(e: AstroError) -> CliError {
    CliError::input(e.to_string())
}

fn print(format: Format, doc: &Value, table: impl FnOnce() -> String) -> Result<(), CliError> {
    let text = match format {
        Format::Json => {
            serde_json::to_string_pretty(doc).map_err(|e| CliError::other(e.to_string()))?
        }
        Format::Table => table(),
    };
    let mut out = std::io::stdout().lock();
    writeln!(out, "{text}").map_err(CliError::stdout)
}

fn precision(s: &str) -> Result<Tiered, CliError> {
    let p: Precision = parse_precision(s).map_err(CliError::input)?;
    Ok(Tiered(p))
}

/// `himmel phases`.
pub fn run_phases(args: &PhasesArgs) -> Result<(), CliError> {
    let eph = precision(&args.precision)?;
    let (a, b) = interval(&args.interval)?;
    let mut rows = Vec::new();
    for ev in phases(eph, &a, &b).map_err(astro)? {
        let ev = ev.map_err(astro)?;
        rows.push(json!({"phase": ev.phase.name(), "utc": utc_of(&ev.instant)}));
    }
    let doc = Value::Array(rows);
    print(args.format, &doc, || {
        let mut s = format!("{:<14} {}\n", "phase", "utc");
        for r in doc.as_array().into_iter().flatten() {
            s += &format!(
                "{:<14} {}\n",
                r["phase"].as_str().unwrap_or(""),
                r["utc"].as_str().unwrap_or("")
            );
        }
        s.trim_end().to_string()
    })
}

/// `himmel riseset`.
pub fn run_riseset(args: &RiseSetArgs) -> Result<(), CliError> {
    let eph = precision(&args.precision)?;
    let body = Body::from_name(args.body.trim()).ok_or_else(|| {
        CliError::input(format!(
            "--body: unknown body '{}'; expected sun or moon (or a planet)",
            args.body
        ))
    })?;
    let (y, m, d) = parse_date("--date", &args.date).map_err(CliError::input)?;
    let obs = args.observer.observer("")?;
    let day = rise_set_transit(&eph, body, &obs, y, m, d).map_err(astro)?;
    let events: Vec<Value> = day
        .events()
        .iter()
        .map(|e| json!({"event": e.kind.name(), "utc": utc_of(&e.instant)}))
        .collect();
    let doc = json!({
        "date": format_date(y, m, d),
        "body": body.name(),
        "state": day.state.name(),
        "events": events,
    });
    print(args.format, &doc, || {
        let mut s = format!(
            "{} {} at {:.4}, {:.4}: {}\n",
            doc["date"].as_str().unwrap_or(""),
            body.name(),
            obs.lat_deg(),
            obs.lon_deg(),
            day.state.name()
        );
        for e in day.events() {
            s += &format!("  {:<8} {}\n", e.kind.name(), utc_of(&e.instant));
        }
        s.trim_end().to_string()
    })
}

fn opt_utc(i: Option<Instant>) -> Value {
    i.map_or(Value::Null, |i| Value::String(utc_of(&i)))
}

fn table_time(v: &Value) -> String {
    v.as_str()
        .and_then(|s| s.split_once('T'))
        .and_then(|(_, clock)| clock.get(..8))
        .map_or_else(|| "-".to_string(), str::to_string)
}

/// `himmel eclipses`.
pub fn run_eclipses(args: &EclipsesArgs) -> Result<(), CliError> {
    // None: no --precision given (the --local default differs, see the flag).
    let explicit = args.precision.as_deref().map(precision).transpose()?;
    let eph = explicit.unwrap_or(Tiered(Precision::Standard));
    if args.local && args.kind == EclipseKindArg::Lunar {
        return Err(CliError::input(
            "--local applies to --kind solar only (lunar eclipses look the same from everywhere the Moon is up)",
        ));
    }
    let (a, b) = interval(&args.interval)?;
    match (args.kind, args.local) {
        (EclipseKindArg::Lunar, _) => {
            let mut rows = Vec::new();
            let mut list = Vec::new();
            for e in lunar_eclipses(eph, &a, &b).map_err(astro)? {
                let e = e.map_err(astro)?;
                rows.push(json!({
                    "kind": "lunar",
                    "type": e.kind.name(),
                    "greatest_utc": utc_of(&e.greatest),
                    "umbral_magnitude": e.umbral_magnitude,
                    "penumbral_magnitude": e.penumbral_magnitude,
                    "gamma": e.gamma,
                }));
                list.push(e);
            }
            let doc = Value::Array(rows);
            print(args.format, &doc, || {
                let mut s = format!(
                    "{:<10} {:<24} {:>7} {:>7} {:>8}  {:>8} {:>8} {:>8} {:>8} {:>8} {:>8}\n",
                    "type",
                    "greatest (UTC)",
                    "umbral",
                    "penumb",
                    "gamma",
                    "P1",
                    "U1",
                    "U2",
                    "U3",
                    "U4",
                    "P4"
                );
                for e in &list {
                    let t = |i: Option<Instant>| table_time(&opt_utc(i));
                    s += &format!(
                        "{:<10} {:<24} {:>7.4} {:>7.4} {:>8.4}  {:>8} {:>8} {:>8} {:>8} {:>8} {:>8}\n",
                        e.kind.name(),
                        utc_of(&e.greatest),
                        e.umbral_magnitude,
                        e.penumbral_magnitude,
                        e.gamma,
                        t(Some(e.p1)),
                        t(e.u1),
                        t(e.u2),
                        t(e.u3),
                        t(e.u4),
                        t(Some(e.p4)),
                    );
                }
                s.trim_end().to_string()
            })
        }
        (EclipseKindArg::Solar, false) => {
            let mut rows = Vec::new();
            for e in solar_eclipses(eph, &a, &b).map_err(astro)? {
                let e = e.map_err(astro)?;
                rows.push(json!({
                    "kind": "solar",
                    "type": e.kind.name(),
                    "greatest_utc": utc_of(&e.greatest),
                    "gamma": e.gamma,
                    "magnitude": e.magnitude,
                }));
            }
            let doc = Value::Array(rows);
            print(args.format, &doc, || {
                let mut s = format!(
                    "{:<8} {:<24} {:>8} {:>9}\n",
                    "type", "greatest (UTC)", "gamma", "magnitude"
                );
                for r in doc.as_array().into_iter().flatten() {
                    s += &format!(
                        "{:<8} {:<24} {:>8.4} {:>9.4}\n",
                        r["type"].as_str().unwrap_or(""),
                        r["greatest_utc"].as_str().unwrap_or(""),
                        r["gamma"].as_f64().unwrap_or(f64::NAN),
                        r["magnitude"].as_f64().unwrap_or(f64::NAN),
                    );
                }
                s.trim_end().to_string()
            })
        }
        (EclipseKindArg::Solar, true) => {
            let obs = args.observer.observer("with --local")?;
            let mut rows = Vec::new();
            let search = match explicit {
                Some(eph) => local_solar_eclipses(eph, &obs, &a, &b),
                None => local_solar_eclipses_preferring_de421(eph, &obs, &a, &b),
            };
            for e in search.map_err(astro)? {
                let e = e.map_err(astro)?;
                rows.push(json!({
                    "c1_utc": utc_of(&e.c1),
                    "c2_utc": opt_utc(e.c2),
                    "max_utc": utc_of(&e.max),
                    "c3_utc": opt_utc(e.c3),
                    "c4_utc": utc_of(&e.c4),
                    "max_magnitude": e.max_magnitude,
                    "max_obscuration": e.max_obscuration,
                    "type_local": e.kind.name(),
                }));
            }
            let doc = Value::Array(rows);
            print(args.format, &doc, || {
                let mut s = format!(
                    "{:<8} {:<24} {:>8} {:>8} {:>8} {:>8} {:>9} {:>11}\n",
                    "type", "maximum (UTC)", "C1", "C2", "C3", "C4", "magnitude", "obscuration"
                );
                for r in doc.as_array().into_iter().flatten() {
                    s += &format!(
                        "{:<8} {:<24} {:>8} {:>8} {:>8} {:>8} {:>9.4} {:>11.4}\n",
                        r["type_local"].as_str().unwrap_or(""),
                        r["max_utc"].as_str().unwrap_or(""),
                        table_time(&r["c1_utc"]),
                        table_time(&r["c2_utc"]),
                        table_time(&r["c3_utc"]),
                        table_time(&r["c4_utc"]),
                        r["max_magnitude"].as_f64().unwrap_or(f64::NAN),
                        r["max_obscuration"].as_f64().unwrap_or(f64::NAN),
                    );
                }
                s.trim_end().to_string()
            })
        }
    }
}
