//! `himmel sky-texture convert` and `himmel render --sky-*` from the
//! outside: the converted file's size and mean, exit codes and one-line
//! errors that name the file or flag.

use himmel_cpu::texture_io::{read_texture, write_texture};
use himmel_skymodel::texture_sky::{mean_radiance, LinearImage, Mapping};

mod common;

fn himmel(args: &[&str]) -> (i32, String) {
    let (code, _, err) = common::run(args);
    (code, err)
}

/// `himmel render` at a fixed instant and place (Munich, morning) with
/// `extra` flags.
fn render(extra: &[&str]) -> (i32, String) {
    let mut a = vec![
        "render",
        "--time",
        "2024-06-21T10:00:00Z",
        "--lat",
        "48",
        "--lon",
        "11",
    ];
    a.extend_from_slice(extra);
    himmel(&a)
}

fn tmp(name: &str) -> String {
    common::tmp_path("himmel-texcli", name)
}

/// A 128 × 64 equirect gradient (cd/m²).
fn pano() -> LinearImage {
    let (w, h) = (128u32, 64u32);
    let texels = (0..w * h)
        .map(|k| {
            let d = Mapping::Sphere
                .pixel_to_dir(f64::from(k % w) + 0.5, f64::from(k / w) + 0.5, w, h)
                .unwrap();
            let v = (1000.0 + 400.0 * d.z + 200.0 * d.x) as f32;
            [v, 0.9 * v, 1.1 * v]
        })
        .collect();
    LinearImage {
        width: w,
        height: h,
        texels,
    }
}

#[test]
fn convert_writes_a_cube_map_with_the_same_mean() {
    let (src, out) = (tmp("pano.exr"), tmp("cube.exr"));
    let img = pano();
    write_texture(std::path::Path::new(&src), &img).unwrap();
    let (code, err) = himmel(&[
        "sky-texture",
        "convert",
        &src,
        "--to",
        "cube-uniform",
        "--face-size",
        "16",
        "--output",
        &out,
    ]);
    assert_eq!(code, 0, "{err}");
    let cube = read_texture(std::path::Path::new(&out)).unwrap();
    assert_eq!((cube.image.width, cube.image.height), (96, 16));
    let (a, _) = mean_radiance(Mapping::Sphere, &img);
    let (b, _) = mean_radiance(Mapping::CubeUniform, &cube.image);
    assert!((b[0] / a[0] - 1.0).abs() < 0.005, "{} vs {}", b[0], a[0]);
    // Rendering with it runs the texture pass.
    let png = tmp("sky.png");
    let (code, err) = render(&[
        "--width",
        "32",
        "--height",
        "32",
        "--sky-texture",
        &out,
        "--sky-mapping",
        "cube-uniform",
        "--output",
        &png,
    ]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn bad_textures_and_flags_exit_2_naming_them() {
    let missing = tmp("missing.exr");
    let (code, err) = himmel(&[
        "sky-texture",
        "convert",
        &missing,
        "--to",
        "cube",
        "--output",
        &tmp("o.exr"),
    ]);
    assert_eq!(code, 2);
    assert!(
        err.starts_with("error: sky texture ") && err.contains("missing.exr"),
        "{err}"
    );
    // A strip of the wrong aspect as a cube.
    let src = tmp("wide.exr");
    write_texture(std::path::Path::new(&src), &pano()).unwrap();
    let (code, err) = render(&[
        "--width",
        "16",
        "--height",
        "16",
        "--sky-texture",
        &src,
        "--sky-mapping",
        "cube",
        "--output",
        &tmp("x.png"),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("wide.exr") && err.contains("6N × N") && err.lines().count() == 1,
        "{err}"
    );
    for (args, want) in [
        (vec!["--sky-mapping", "cube"], "need a sky texture"),
        (
            vec!["--sky-texture", &src, "--sky-mapping", "globe"],
            "--sky-mapping: unknown mapping 'globe'",
        ),
        (
            vec!["--sky-texture", &src, "--sky-keep", "atmosphere"],
            "--sky-keep: 'atmosphere' cannot be kept",
        ),
        (
            vec!["--sky-texture", &src, "--sky-blend", "2"],
            "--sky-blend (sky_texture.blend): 2 is outside [0, 1]",
        ),
    ] {
        let mut a = vec!["--output", "x.png"];
        a.extend(args);
        let (code, err) = render(&a);
        assert_eq!(code, 2, "{a:?}: {err}");
        assert!(err.contains(want), "{a:?}: {err}");
    }
    let (code, err) = himmel(&[
        "sky-texture",
        "convert",
        &src,
        "--to",
        "globe",
        "--output",
        &tmp("o.exr"),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--to: unknown mapping 'globe'"), "{err}");
}
