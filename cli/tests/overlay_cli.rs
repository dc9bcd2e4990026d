//! `himmel render --overlay`: the chart overlay is in the PNG and never in
//! the EXR, and a bad list exits 2 naming the flag.

use std::path::{Path, PathBuf};

mod common;

fn himmel(args: &[&str]) -> (i32, String) {
    let (code, _, err) = common::run(args);
    (code, err)
}

fn dir(name: &str) -> PathBuf {
    common::fresh_dir("himmel-overlay", name)
}

/// Munich, 15 January 2024, 22:00 CET, 96 × 96 fisheye, a fixed exposure.
fn render(out: &Path, extra: &[&str]) {
    let mut a = vec![
        "render",
        "--time",
        "2024-01-15T21:00:00Z",
        "--lat",
        "48.14",
        "--lon",
        "11.58",
        "--width",
        "96",
        "--height",
        "96",
        "--exposure",
        "-4",
        "--output",
        out.to_str().unwrap(),
    ];
    a.extend_from_slice(extra);
    let (code, err) = himmel(&a);
    assert_eq!(code, 0, "{err}");
}

fn png_pixels(p: &Path) -> Vec<u8> {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(p).unwrap()));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    buf
}

#[test]
fn overlay_is_in_the_png_and_not_in_the_exr() {
    let d = dir("png-exr");
    let on = ["--overlay", "constellations,labels"];
    render(&d.join("plain.png"), &[]);
    render(&d.join("chart.png"), &on);
    render(&d.join("plain.exr"), &[]);
    render(&d.join("chart.exr"), &on);
    let (a, b) = (
        png_pixels(&d.join("plain.png")),
        png_pixels(&d.join("chart.png")),
    );
    assert_eq!(a.len(), 96 * 96 * 3);
    let changed = a.chunks(3).zip(b.chunks(3)).filter(|(p, q)| p != q).count();
    // Lines and names cover some per cent of a 96² all-sky chart.
    assert!(changed > 300, "{changed} pixels carry the overlay");
    // Every changed pixel moved towards the overlay colour (a light blue:
    // blue rises, nothing gets darker in blue).
    assert!(a.chunks(3).zip(b.chunks(3)).all(|(p, q)| q[2] >= p[2]));
    let exr = |n: &str| himmel_cpu::output::read_exr(&d.join(n)).unwrap();
    assert!(
        exr("plain.exr") == exr("chart.exr"),
        "the overlay reached the EXR"
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_bad_overlay_list_exits_2_naming_the_flag() {
    let d = dir("bad");
    let (code, err) = himmel(&[
        "render",
        "--time",
        "2024-01-15T21:00:00Z",
        "--lat",
        "48",
        "--lon",
        "11",
        "--overlay",
        "grid",
        "--output",
        d.join("x.png").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.starts_with("error: --overlay: unknown part 'grid'"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&d);
}
