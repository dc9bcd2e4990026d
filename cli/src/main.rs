//! `himmel` — the command line of the Himmel sky system.
//!
//! The contract (subcommands, flags, JSON field names, exit codes) is the
//! project's `spec/cli.md`. Exit codes: 0 success, 2 invalid input,
//! 3 resource unavailable, 1 other failure. Errors are one line on stderr.

mod cloud_flags;
mod common;
mod ephemeris_cmd;
mod events_cmd;
mod flag_values;
mod render_cmd;
mod sequence_cmd;
mod stars_cmd;
mod texture_cmd;

use himmel_cli::timearg;

use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

/// A failure with its exit code and one-line message.
#[derive(Debug)]
pub struct CliError {
    code: u8,
    message: String,
}

impl CliError {
    /// Invalid input (exit code 2).
    pub fn input(message: impl Into<String>) -> Self {
        CliError {
            code: 2,
            message: message.into(),
        }
    }
    /// Any other failure (exit code 1).
    pub fn other(message: impl Into<String>) -> Self {
        CliError {
            code: 1,
            message: message.into(),
        }
    }
    /// A failed write to stdout. A reader that stopped early (`| head`)
    /// closes the pipe: that ends the program quietly with success.
    pub fn stdout(e: std::io::Error) -> Self {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            CliError {
                code: 0,
                message: String::new(),
            }
        } else {
            CliError::other(format!("writing stdout: {e}"))
        }
    }
    /// A failed JSON write to stdout; see [`CliError::stdout`].
    pub fn json(e: serde_json::Error) -> Self {
        match e.io_error_kind() {
            Some(kind) => CliError::stdout(kind.into()),
            None => CliError::other(e.to_string()),
        }
    }
}

#[derive(Parser, Debug)]
#[command(
    name = "himmel",
    version,
    about = "Where are the Sun, the Moon, the planets — from here, now?",
    propagate_version = true
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// Output format of data-printing subcommands.
#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum, Default)]
pub enum Format {
    /// A readable table.
    #[default]
    Table,
    /// One JSON document on stdout (JSON Lines for batch mode).
    Json,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Apparent positions of the Sun, Moon and planets for an observer.
    #[command(allow_negative_numbers = true)]
    Ephemeris(ephemeris_cmd::EphemerisArgs),
    /// Apparent places of the catalogue stars for an observer.
    #[command(allow_negative_numbers = true)]
    Stars(stars_cmd::StarsArgs),
    /// Principal Moon phases in an interval.
    Phases(events_cmd::PhasesArgs),
    /// Rise, set and transit of the Sun or Moon on one UTC day.
    #[command(allow_negative_numbers = true)]
    Riseset(events_cmd::RiseSetArgs),
    /// Lunar and solar eclipses in an interval (solar: global or --local).
    #[command(allow_negative_numbers = true)]
    Eclipses(events_cmd::EclipsesArgs),
    /// Render the sky in absolute units to a PNG (camera model) or EXR (cd/m²).
    #[command(allow_negative_numbers = true)]
    Render(Box<render_cmd::RenderArgs>),
    /// Print a complete default scene (JSON) for `render --scene`.
    SceneTemplate(render_cmd::TemplateArgs),
    /// Sky textures: `convert` resamples one into another mapping (e.g. an
    /// equirect photograph into a uniform-density cube map).
    SkyTexture(texture_cmd::SkyTextureArgs),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            match e.kind() {
                ErrorKind::DisplayHelp
                | ErrorKind::DisplayVersion
                | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
                    let _ = e.print();
                    return if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                        ExitCode::from(2)
                    } else {
                        ExitCode::SUCCESS
                    };
                }
                _ => {
                    let rendered = e.render().to_string();
                    let first = rendered
                        .lines()
                        .find(|l| !l.trim().is_empty())
                        .unwrap_or("error: invalid arguments");
                    let first = first.trim();
                    if first.starts_with("error:") {
                        eprintln!("{first}");
                    } else {
                        eprintln!("error: {first}");
                    }
                    return ExitCode::from(2);
                }
            }
        }
    };
    let result = match cli.command {
        Command::Ephemeris(args) => ephemeris_cmd::run(&args),
        Command::Stars(args) => stars_cmd::run(&args),
        Command::Phases(args) => events_cmd::run_phases(&args),
        Command::Riseset(args) => events_cmd::run_riseset(&args),
        Command::Eclipses(args) => events_cmd::run_eclipses(&args),
        Command::Render(args) => render_cmd::run(&args),
        Command::SceneTemplate(a) => render_cmd::template(&a),
        Command::SkyTexture(a) => texture_cmd::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            if !e.message.is_empty() {
                // One line, and no control character from an input reaches
                // the terminal.
                let one_line = e.message.replace('\n', " ");
                eprintln!("error: {}", himmel_cli::inputs::printable(&one_line));
            }
            ExitCode::from(e.code)
        }
    }
}
