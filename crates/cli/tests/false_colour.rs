//! `render --false-colour`: the illuminance (or luminance) of the surface seen through each
//! pixel, as a PNG in false colour with its legend and as float images of the values.

use std::f64::consts::PI;
use std::fs;
use std::path::Path;
use std::process::Output;

mod common;

use common::{radiosity, scratch};
use radiosity::color::scale::{colour, Scale, Spacing};
use radiosity::formfactor::analytic::point_to_parallel_rectangle_corner;
use radiosity::io::image_file::read_image;
use radiosity::render::tonemap::encode_srgb8;
use radiosity::render::Image;

/// A 4 × 4 grey floor and a 0.5 × 0.5 lamp of radiance 100 facing it from 1 above its
/// centre; the camera looks at the floor's centre from the side, past the lamp.
const LAMP: &str = r#"
[camera]
eye = [0.0, 0.6, 1.2]
target = [0.0, 0.0, 0.0]
fov_y = 10.0

[materials.floor]
reflectance = 0.3
[materials.lamp]
emission = 100.0

[[objects]]
name = "floor"
material = "floor"
shape = "polygon"
vertices = [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]

[[objects]]
name = "lamp"
material = "lamp"
shape = "polygon"
vertices = [[-0.25, 1, -0.25], [0.25, 1, -0.25], [0.25, 1, 0.25], [-0.25, 1, 0.25]]
"#;

/// E at the floor's centre: π L F, F four corner factors of 0.25 × 0.25 rectangles 1 above.
fn exact() -> f64 {
    PI * 100.0 * 4.0 * point_to_parallel_rectangle_corner(0.25, 0.25, 1.0)
}

/// Writes the lamp scene into `dir` and renders it 33 × 33 with `args`.
fn render(dir: &Path, args: &[&str]) -> Output {
    render_sized(dir, (33, 33), args)
}

/// Writes the lamp scene into `dir` and renders it `width` × `height` with `args`.
fn render_sized(dir: &Path, (width, height): (u32, u32), args: &[&str]) -> Output {
    fs::write(dir.join("lamp.toml"), LAMP).unwrap();
    let (width, height) = (width.to_string(), height.to_string());
    radiosity()
        .args([
            "render",
            "lamp.toml",
            "--width",
            &width,
            "--height",
            &height,
        ])
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

fn succeeded(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The 8-bit sRGB codes of pixel (x, y) of an image read back from a PNG.
fn codes(image: &Image, x: u32, y: u32) -> [u8; 3] {
    let p = image.get(x, y);
    [p.x, p.y, p.z].map(encode_srgb8)
}

/// The value whose colour on `scale` is nearest `code` (the colour map inverted by search).
fn decode(scale: &Scale, code: [u8; 3]) -> f64 {
    let distance = |t: f64| {
        let c = colour(t);
        (0..3)
            .map(|i| (f64::from(c[i]) - f64::from(code[i])).powi(2))
            .sum::<f64>()
    };
    let t = (0..=100_000)
        .map(|k| f64::from(k) / 100_000.0)
        .min_by(|a, b| distance(*a).total_cmp(&distance(*b)))
        .unwrap();
    scale.value_at(t)
}

/// The centre pixel sees the floor's centre: the PFM holds its illuminance, the closed form
/// (the direct light is exact and nothing the floor sees reflects); the PNG's colour at that
/// pixel, decoded on a tight linear scale, is the same within the colour map's 8-bit steps
/// (1/700 of the scale, 0.003 lx here).
#[test]
fn the_centre_pixel_reads_the_closed_form_illuminance() {
    let dir = scratch("false-colour-exact");
    let out = render(
        &dir,
        &[
            "--false-colour",
            "lux",
            "--false-colour-scale",
            "linear",
            "--false-colour-range",
            "22:24",
            "-o",
            "fc.png",
            "-o",
            "fc.pfm",
            "--quiet",
        ],
    );
    succeeded(&out);
    let exact = exact();
    let values = read_image(&dir.join("fc.pfm")).unwrap();
    assert_eq!(
        (values.width, values.height),
        (33, 33),
        "no legend in the values"
    );
    let lux = values.get(16, 16);
    assert_eq!(lux.x, lux.y, "the value on every channel");
    assert!(
        (lux.x / exact - 1.0).abs() < 1e-5,
        "{} lx against {exact}",
        lux.x
    );
    let picture = read_image(&dir.join("fc.png")).unwrap();
    assert!(picture.width > 33, "the legend's strip widens the picture");
    let scale = Scale::new(22.0, 24.0, Spacing::Linear).unwrap();
    let decoded = decode(&scale, codes(&picture, 16, 16));
    assert!(
        (decoded / exact - 1.0).abs() < 3e-4,
        "decoded {decoded} lx against {exact}"
    );
}

/// The default scale is logarithmic and fitted to the picture, said on stderr; the legend is
/// drawn in a white strip at the right: the colour bar (the map's colours, blue to red) with
/// black ticks, labels and unit.
#[test]
fn the_picture_carries_its_legend() {
    let dir = scratch("false-colour-legend");
    let out = render_sized(&dir, (48, 240), &["--false-colour", "lux", "-o", "fc.png"]);
    succeeded(&out);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("false colour: lux on a log scale from"),
        "{err}"
    );
    assert!(err.contains(" lx (fitted)"), "{err}");
    let picture = read_image(&dir.join("fc.png")).unwrap();
    assert_eq!(picture.height, 240);
    let strip: Vec<[u8; 3]> = (0..picture.height)
        .flat_map(|y| (48..picture.width).map(move |x| (x, y)))
        .map(|(x, y)| codes(&picture, x, y))
        .collect();
    let count = |f: &dyn Fn(&[u8; 3]) -> bool| strip.iter().filter(|c| f(c)).count();
    let white = count(&|c| *c == [255, 255, 255]);
    let ink = count(&|c| *c == [0, 0, 0]);
    let coloured = count(&|c| c[0] != c[1] || c[1] != c[2]);
    assert!(white > strip.len() / 2, "white {white} of {}", strip.len());
    // Outline, ticks and at least the unit and the two ends' labels (a glyph has 10 to 20
    // font pixels).
    assert!(ink > 2 * 200 + 60, "ink {ink}");
    // The bar: 10 pixels wide less its outline, some 200 rows.
    assert!(coloured > 8 * 190, "bar {coloured}");
    // The bar runs through the map: its bluest and its reddest colours are there.
    assert!(strip.iter().any(|c| c[2] > 200 && c[0] < 60), "blue end");
    assert!(strip.iter().any(|c| c[0] > 200 && c[2] < 40), "red end");
}

/// Luminance is the picture's own luminance: the PFM of `--false-colour luminance` equals the
/// luminance of the plain render's PFM at a pixel inside the floor.
#[test]
fn luminance_is_the_pictures() {
    let dir = scratch("false-colour-luminance");
    succeeded(&render(
        &dir,
        &["--false-colour", "luminance", "-o", "l.pfm", "--quiet"],
    ));
    succeeded(&render(&dir, &["-o", "plain.pfm", "--quiet"]));
    let l = read_image(&dir.join("l.pfm")).unwrap().get(16, 16).x;
    let plain = read_image(&dir.join("plain.pfm")).unwrap().get(16, 16);
    let y = radiosity::color::luminance(plain);
    assert!((l / y - 1.0).abs() < 1e-6, "{l} cd/m² against {y}");
    // The floor reflects ρE/π.
    assert!((l / (0.3 * exact() / PI) - 1.0).abs() < 1e-4, "{l}");
}

/// Bad false-colour flags stop the run before any work: one line, status 2, no file.
#[test]
fn bad_flags_are_one_line_errors() {
    let dir = scratch("false-colour-bad");
    for (args, says) in [
        (
            &["--false-colour-scale", "log"][..],
            "--false-colour-scale applies to --false-colour only",
        ),
        (
            &["--false-colour-range", "1:10"][..],
            "--false-colour-range applies to --false-colour only",
        ),
        (&["--false-colour", "kelvin"][..], "kelvin"),
        (
            &["--false-colour", "lux", "--false-colour-range", "0:100"][..],
            "a logarithmic scale needs a lower end above 0",
        ),
        (
            &["--false-colour", "lux", "--false-colour-range", "100:10"][..],
            "is not MIN:MAX",
        ),
        (
            &["--false-colour", "lux", "--false-colour-scale", "cubic"][..],
            "cubic",
        ),
        (
            &["--false-colour", "lux", "--mode", "radiosity"][..],
            "leave out --mode radiosity",
        ),
        (
            &["--false-colour", "lux", "--exposure", "1"][..],
            "--exposure does not apply to --false-colour",
        ),
    ] {
        let mut all = args.to_vec();
        all.extend(["-o", "bad.png"]);
        let out = render(&dir, &all);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(
            err.starts_with("error: ") && err.contains(says),
            "{args:?}: {err}"
        );
        assert!(!dir.join("bad.png").exists(), "{args:?}");
    }
}
