//! Exports Himmel's low cloud field on a voxel grid for the Mitsuba
//! reference (`tools/cloud_reference.py`): reads the setup
//! (`tests/fixtures/cloud_ref/setup.json`: the `low` scene key and the
//! `grid` resolution [nx, ny, nz]) and writes the extinction coefficient
//! (km⁻¹, f32 little-endian) at every voxel centre of the patch
//! [−e, e]² × [base, top] (e = `extent_km`), x fastest, then y, then z
//! (Mitsuba's [Z, Y, X] layout), and prints the sum of the values.
//!
//! `cargo run --release -p himmel-skymodel --example cloud_grid -- SETUP.json OUT.f32`

use himmel_skymodel::clouds::LowField;
use himmel_skymodel::scene::LowCloudSpec;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, setup, out] = args.as_slice() else {
        return Err("usage: cloud_grid SETUP.json OUT.f32".into());
    };
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(setup)?)?;
    let spec: LowCloudSpec = serde_json::from_value(v["low"].clone())?;
    let res: [usize; 3] = serde_json::from_value(v["grid"].clone())?;
    let field = LowField::new(&spec, 0.0);
    let values = field.voxel_grid(res);
    let sum: f64 = values.iter().map(|&x| x as f64).sum();
    let bytes: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
    std::fs::write(out, bytes)?;
    println!("{sum}");
    Ok(())
}
