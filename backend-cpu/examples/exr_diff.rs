//! Compares two linear EXR images (e.g. the same frame before and after a
//! change, or from the two backends): bit identity, and the relative
//! luminance difference per pixel (median, 99th percentile, maximum) over
//! the pixels where the first image is above 10⁻⁹ × its brightest.
//!
//! ```sh
//! cargo run --release -p himmel-cpu --example exr_diff -- a.exr b.exr
//! ```

use himmel_skymodel::spectrum::luminance;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() != 2 {
        eprintln!("usage: exr_diff A.exr B.exr");
        std::process::exit(2);
    }
    let read = |p: &str| match himmel_cpu::output::read_exr(std::path::Path::new(p)) {
        Ok(img) => img,
        Err(e) => {
            eprintln!("error: {p}: {e}");
            std::process::exit(2);
        }
    };
    let (wa, ha, a) = read(&args[0]);
    let (wb, hb, b) = read(&args[1]);
    if (wa, ha) != (wb, hb) {
        eprintln!("error: sizes differ: {wa}×{ha} vs {wb}×{hb}");
        std::process::exit(1);
    }
    let identical = a
        .iter()
        .zip(&b)
        .all(|(p, q)| p.iter().zip(q).all(|(x, y)| x.to_bits() == y.to_bits()));
    let peak = a.iter().map(|p| luminance(*p)).fold(0.0f32, f32::max);
    let mut d: Vec<f64> = a
        .iter()
        .zip(&b)
        .filter(|(p, _)| luminance(**p) > 1e-9 * peak)
        .map(|(p, q)| {
            let (ya, yb) = (luminance(*p) as f64, luminance(*q) as f64);
            (yb - ya).abs() / ya
        })
        .collect();
    d.sort_by(f64::total_cmp);
    let q = |f: f64| {
        d.get(((d.len().max(1) - 1) as f64 * f) as usize)
            .copied()
            .unwrap_or(0.0)
    };
    println!(
        "{}×{}: bit-identical {identical}; relative ΔY median {:.2e}, p99 {:.2e}, max {:.2e} over {} pixels",
        wa,
        ha,
        q(0.5),
        q(0.99),
        q(1.0),
        d.len()
    );
}
