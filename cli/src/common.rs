//! Validation shared by the subcommands: the common observer flags of the
//! contract (`--lat`, `--lon`, `--elevation`) and range checks that name the
//! flag.

use clap::Args;
use himmel_astro::Observer;

use crate::CliError;
pub use himmel_cli::inputs::{check, observer};

/// The common observer flags of the contract.
#[derive(Args, Debug)]
pub struct ObserverArgs {
    /// Geodetic latitude, degrees in [-90, 90].
    #[arg(long, value_name = "DEG")]
    pub lat: Option<f64>,
    /// East longitude, degrees in [-180, 180] (360-wrapped input accepted).
    #[arg(long, value_name = "DEG")]
    pub lon: Option<f64>,
    /// Elevation above the WGS84 ellipsoid, metres.
    #[arg(long, value_name = "M", default_value_t = 0.0)]
    pub elevation: f64,
}

impl ObserverArgs {
    /// `--lat` and `--lon`, both required here (`when` qualifies the
    /// message, e.g. "with --local").
    pub fn lat_lon(&self, when: &str) -> Result<(f64, f64), CliError> {
        let when = if when.is_empty() {
            String::new()
        } else {
            format!("{when}; ")
        };
        let lat = required("--lat", self.lat, &format!("{when}degrees in [-90, 90]"))?;
        let lon = required(
            "--lon",
            self.lon,
            &format!("{when}degrees east in [-180, 180]"),
        )?;
        Ok((lat, lon))
    }

    /// The validated observer (see [`observer`]).
    pub fn observer(&self, when: &str) -> Result<Observer, CliError> {
        let (lat, lon) = self.lat_lon(when)?;
        observer(lat, lon, self.elevation).map_err(CliError::input)
    }
}

/// [`check`] with the error as a [`CliError`] (exit code 2).
pub fn check_input(flag: &str, v: f64, min: f64, max: f64) -> Result<f64, CliError> {
    check(flag, v, min, max).map_err(CliError::input)
}

/// The value of a flag that is required here, or an error naming it and what
/// it expects (`expected`, e.g. "degrees in [-90, 90]").
pub fn required(flag: &str, v: Option<f64>, expected: &str) -> Result<f64, CliError> {
    v.ok_or_else(|| CliError::input(format!("{flag} is required ({expected})")))
}
