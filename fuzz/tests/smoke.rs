//! The CI smoke run of the fuzzer: 20 000 mutated inputs per target
//! (`HIMMEL_FUZZ_INPUTS` to change), no panic, no broken invariant.

use himmel_fuzz::{fuzz, Target};

#[test]
fn every_parser_survives_a_smoke_run() {
    let inputs = std::env::var("HIMMEL_FUZZ_INPUTS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20_000);
    let mut failed = Vec::new();
    for t in Target::ALL {
        let r = fuzz(t, inputs, 19);
        println!(
            "{}: {} inputs in {:.2} s, {} distinct outcomes, {} findings",
            t.name(),
            r.executed,
            r.elapsed.as_secs_f64(),
            r.distinct_outcomes,
            r.finding_count
        );
        assert_eq!(r.executed, inputs);
        // Mutation reaches many error paths, not one.
        assert!(
            r.distinct_outcomes > 20,
            "{}: {}",
            t.name(),
            r.distinct_outcomes
        );
        if r.finding_count > 0 {
            failed.push(format!("{}: {:#?}", t.name(), r.findings));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
