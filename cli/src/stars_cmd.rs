//! `himmel stars`: apparent places of the embedded catalogue's stars for an
//! observer (spec/cli.md): apparent geocentric RA/Dec of date and
//! topocentric alt/az (unrefracted), brightest first.

use std::io::Write;

use clap::Args;
use himmel_astro::frames::NutationModel;
use himmel_astro::stars::StarReduction;
use himmel_astro::{Epoch, Instant};
use himmel_catalog::Catalog;
use serde::Serialize;

use crate::common;
use crate::ephemeris_cmd::parse_time;
use crate::timearg::format_utc;
use crate::{CliError, Format};

#[derive(Args, Debug)]
pub struct StarsArgs {
    /// Instant: RFC 3339 civil UTC (e.g. 2024-04-08T18:42:00Z), a date
    /// YYYY-MM-DD (0h UTC) or `now`. Julian calendar before 1582-10-15,
    /// signed years outside 0000-9999 (-0500-03-01T12:00:00Z).
    #[arg(long, value_name = "TIME")]
    time: Option<String>,
    #[command(flatten)]
    observer: common::ObserverArgs,
    /// Faintest V magnitude listed (the embedded catalogue reaches 6.5).
    #[arg(long, value_name = "MAG", default_value_t = 6.5)]
    limit_mag: f64,
    /// List only stars whose (unrefracted) altitude is above 0°.
    #[arg(long)]
    above_horizon: bool,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
}

/// One output record; field names as in `spec/cli.md`.
#[derive(Serialize)]
struct StarOut<'a> {
    hip: Option<u32>,
    hr: Option<u16>,
    name: Option<&'a str>,
    vmag: f64,
    bv: Option<f64>,
    ra_deg: f64,
    dec_deg: f64,
    alt_deg: f64,
    az_deg: f64,
}

/// `x` with `decimals` fixed decimals, through integer formatting (Rust's
/// fixed-precision float formatting is several times slower, and the table
/// prints 50 000 numbers).
fn fixed(x: f64, decimals: u32) -> String {
    let k = 10i64.pow(decimals);
    let n = (x * k as f64).round() as i64;
    let sign = if n < 0 { "-" } else { "" };
    let n = n.unsigned_abs();
    let k = k as u64;
    format!(
        "{sign}{}.{:0width$}",
        n / k,
        n % k,
        width = decimals as usize
    )
}

fn round(x: f64, digits: i32) -> f64 {
    let k = 10f64.powi(digits);
    (x * k).round() / k
}

pub fn run(args: &StarsArgs) -> Result<(), CliError> {
    let time = args.time.as_deref().ok_or_else(|| {
        CliError::input(
            "--time is required (RFC 3339 UTC, e.g. 2024-04-08T18:42:00Z, a date, or now)",
        )
    })?;
    let (lat, lon) = args.observer.lat_lon("")?;
    let utc = parse_time(time).map_err(CliError::input)?;
    let observer = common::observer(lat, lon, args.observer.elevation).map_err(CliError::input)?;
    let limit = common::check_input("--limit-mag", args.limit_mag, -30.0, 30.0)?;
    let instant = Instant::from_utc(&utc).map_err(|e| CliError::input(format!("--time: {e}")))?;
    let epoch = Epoch::new(&instant, NutationModel::Iau1980);
    let catalog = Catalog::embedded().map_err(|e| CliError::other(e.to_string()))?;
    let reduction = StarReduction::new(&epoch);

    let mut rows = Vec::new();
    let mut labels = Vec::new();
    for star in catalog.brighter_than(limit) {
        let (geo, topo) = reduction.geocentric_and_topocentric(&star.astrometry, &observer);
        if args.above_horizon && topo.alt <= 0.0 {
            continue;
        }
        labels.push(star.name.clone().or_else(|| star.designation()));
        rows.push((star, geo, topo));
    }
    let out: Vec<StarOut> = rows
        .iter()
        .zip(&labels)
        .map(|((star, geo, topo), label)| StarOut {
            hip: Some(star.hip),
            hr: star.hr,
            name: label.as_deref(),
            vmag: round(star.vmag, 3),
            bv: star.bv.map(|b| round(b, 3)),
            ra_deg: round(geo.ra_deg(), 7),
            dec_deg: round(geo.dec_deg(), 7),
            alt_deg: round(topo.alt_deg(), 7),
            az_deg: round(topo.az_deg(), 7),
        })
        .collect();

    let stdout = std::io::stdout();
    let mut w = std::io::BufWriter::new(stdout.lock());
    let io = CliError::stdout;
    match args.format {
        Format::Json => {
            serde_json::to_writer(&mut w, &out).map_err(CliError::json)?;
            writeln!(w).map_err(io)?;
        }
        Format::Table => {
            writeln!(
                w,
                "{} — lat {lat}°, lon {lon}°, {} stars (V ≤ {limit}{})",
                format_utc(&utc),
                out.len(),
                if args.above_horizon {
                    ", above the horizon"
                } else {
                    ""
                }
            )
            .map_err(io)?;
            writeln!(
                w,
                "{:>6}  {:<22} {:>6} {:>6} {:>11} {:>11} {:>10} {:>10}",
                "HIP", "name", "V", "B-V", "RA (°)", "Dec (°)", "alt (°)", "az (°)"
            )
            .map_err(io)?;
            for s in &out {
                writeln!(
                    w,
                    "{:>6}  {:<22} {:>6} {:>6} {:>11} {:>11} {:>10} {:>10}",
                    s.hip.map(|h| h.to_string()).unwrap_or_default(),
                    s.name.unwrap_or(""),
                    fixed(s.vmag, 2),
                    s.bv.map(|b| fixed(b, 2)).unwrap_or_else(|| "—".into()),
                    fixed(s.ra_deg, 5),
                    fixed(s.dec_deg, 5),
                    fixed(s.alt_deg, 4),
                    fixed(s.az_deg, 4)
                )
                .map_err(io)?;
            }
        }
    }
    w.flush().map_err(io)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::fixed;

    #[test]
    fn fixed_decimals() {
        assert_eq!(fixed(-16.749_735_7, 5), "-16.74974");
        assert_eq!(fixed(-0.004, 2), "0.00");
        assert_eq!(fixed(-0.006, 2), "-0.01");
        assert_eq!(fixed(359.999_996, 5), "360.00000");
        assert_eq!(fixed(0.5, 4), "0.5000");
    }
}
