//! `himmel-fuzz [--inputs N] [--seed S] [TARGET…]`: runs the mutation
//! fuzzer (see the library docs) on each target (default: all of `time`,
//! `scene`, `batch`, `hip2`, `d3`, `gltf`) and prints one line per target: inputs
//! executed, time, distinct outcomes, corpus size, findings. Exits 1 when
//! anything was found, 2 on bad arguments.
//!
//! The campaign recorded in `docs/hardening.md`:
//! `cargo run --release -p himmel-fuzz -- --inputs 1000000`

use std::process::ExitCode;

use himmel_fuzz::{fuzz, Target};

fn main() -> ExitCode {
    let mut inputs = 1_000_000u64;
    let mut seed = 19u64;
    let mut targets = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let number = |v: Option<String>, flag: &str| -> Result<u64, String> {
            v.as_deref()
                .and_then(|s| s.parse().ok())
                .ok_or_else(|| format!("{flag} needs a non-negative integer"))
        };
        let r = match a.as_str() {
            "--inputs" => number(args.next(), "--inputs").map(|n| inputs = n),
            "--seed" => number(args.next(), "--seed").map(|n| seed = n),
            name => Target::from_name(name)
                .map(|t| targets.push(t))
                .ok_or_else(|| {
                    format!(
                        "unknown target '{name}'; expected time, scene, batch, hip2, d3 or gltf"
                    )
                }),
        };
        if let Err(e) = r {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    }
    if targets.is_empty() {
        targets = Target::ALL.to_vec();
    }
    let mut found = 0;
    for t in targets {
        let r = fuzz(t, inputs, seed);
        println!(
            "{:<6} {:>9} inputs in {:>7.1} s ({:>6.0} inputs/s), {:>5} distinct outcomes, corpus {:>4}, {} findings",
            t.name(),
            r.executed,
            r.elapsed.as_secs_f64(),
            r.executed as f64 / r.elapsed.as_secs_f64().max(1e-9),
            r.distinct_outcomes,
            r.corpus,
            r.finding_count
        );
        for (input, what) in &r.findings {
            // Long inputs (glTF files) cut to their first 400 characters.
            let shown: String = input.chars().take(400).collect();
            let more = input.chars().count().saturating_sub(400);
            let tail = if more > 0 {
                format!(" … ({more} more characters)")
            } else {
                String::new()
            };
            println!("  {shown}{tail}\n    {what}");
        }
        found += r.finding_count;
    }
    if found > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
