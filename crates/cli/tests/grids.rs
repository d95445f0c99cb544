//! `--grids DIR`: the illuminance on a scene's calculation grids, written as CSV and JSON.

use std::fs;
use std::path::Path;

mod common;

use common::{radiosity, scratch};
use radiosity::formfactor::analytic::point_to_parallel_rectangle_corner;

/// A 1 m square lamp of radiance 100 facing down over a black floor 0.999 below it, and a grid
/// just above the floor.
const ROOM: &str = r#"
[materials.black]
reflectance = 0.0
[materials.glow]
emission = 100.0

[[objects]]
name = "floor"
material = "black"
shape = "polygon"
vertices = [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, 0.0]]

[[objects]]
name = "lamp"
material = "glow"
shape = "polygon"
vertices = [[0.0, 0.999, 0.0], [1.0, 0.999, 0.0], [1.0, 0.999, 1.0], [0.0, 0.999, 1.0]]

[[grids]]
name = "floor"
corners = [[0.0, 0.001, 0.0], [1.0, 0.001, 0.0], [0.0, 0.001, 1.0]]
spacing = 0.5
"#;

/// Writes `scene` as `dir/room.toml`, runs `radiosity solve room.toml --grids lux --stats
/// s.json`, asserts that it succeeds and returns `lux/grids.json`.
fn solve_with_grids(dir: &Path, scene: &str) -> serde_json::Value {
    fs::write(dir.join("room.toml"), scene).unwrap();
    let out = radiosity()
        .args([
            "solve",
            "room.toml",
            "--grids",
            "lux",
            "--stats",
            "s.json",
            "--quiet",
        ])
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(&fs::read_to_string(dir.join("lux/grids.json")).unwrap()).unwrap()
}

#[test]
fn solve_writes_each_grid_and_its_statistics() {
    let dir = scratch("grids-solve");
    let json = solve_with_grids(&dir, ROOM);
    let csv = fs::read_to_string(dir.join("lux/floor.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows[0], "x,y,z,lux");
    assert_eq!(rows.len(), 5, "2 × 2 cells");
    // The four points sit alike under the ceiling (a quarter in from two walls): each reads
    // πL·F, F the sum of four corner factors of rectangles 0.25 or 0.75 wide, 0.998 above.
    let h = 0.998;
    let f = point_to_parallel_rectangle_corner(0.25, 0.25, h)
        + point_to_parallel_rectangle_corner(0.75, 0.75, h)
        + 2.0 * point_to_parallel_rectangle_corner(0.25, 0.75, h);
    let exact = std::f64::consts::PI * 100.0 * f;
    for row in &rows[1..] {
        let lux: f64 = row.rsplit(',').next().unwrap().parse().unwrap();
        assert!((lux / exact - 1.0).abs() < 2e-3, "{row}: {exact}");
    }
    let grid = &json["grids"][0];
    assert_eq!(grid["points"], 4);
    let average = grid["average"].as_f64().unwrap();
    assert!((average / exact - 1.0).abs() < 2e-3);
    assert!(grid["uniformity"].as_f64().unwrap() > 0.99);
}

#[test]
fn asking_for_grids_of_a_scene_without_any_is_refused_before_the_work() {
    let dir = scratch("grids-none");
    let out = radiosity()
        .args(["solve", "cornell", "--grids", "lux"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--grids: cornell has no calculation grids"),
        "{err}"
    );
    assert!(!dir.join("lux").exists());
}

/// Under a CIE overcast sky of zenith luminance L_z a horizontal grid open to the whole sky
/// reads E_h = 7π L_z / 9 (the sky's closed form) and a daylight factor of 100 %: the sky is
/// carried by tiles of a far cube, each emitting its mean luminance.
#[test]
fn an_open_grid_under_the_overcast_sky_reads_its_closed_form() {
    let dir = scratch("grids-sky");
    let scene = r#"
[sky]
type = "cie-overcast"
zenith_luminance = 10000.0

[materials.ground]
reflectance = 0.2

[[objects]]
name = "ground"
material = "ground"
shape = "polygon"
vertices = [[-5.0, 0.0, -5.0], [-5.0, 0.0, 5.0], [5.0, 0.0, 5.0], [5.0, 0.0, -5.0]]

[[grids]]
name = "open"
corners = [[-1.0, 0.8, -1.0], [1.0, 0.8, -1.0], [-1.0, 0.8, 1.0]]
spacing = 1.0
"#;
    let json = solve_with_grids(&dir, scene);
    let grid = &json["grids"][0];
    let exact = 7.0 * std::f64::consts::PI * 10000.0 / 9.0;
    for key in ["minimum", "maximum"] {
        let e = grid[key].as_f64().unwrap();
        assert!((e / exact - 1.0).abs() < 0.01, "{key} {e} vs {exact}");
    }
    let df = grid["daylight_factor"]["average"].as_f64().unwrap();
    assert!((df - 100.0).abs() < 1.0, "{df}");
}

/// A closed 6 × 3 × 4 m room of two-sided walls under the overcast sky: no daylight gets in,
/// so its desk grid reads 0 lx, and its flat roof, open to the whole sky, reflects ρ E_h
/// (E_h = 7π L_z / 9). The sky's far tiles emit some 10⁴ times what reaches the room; judged
/// against that power, the solver refined nothing in the house: the desk read 7.8 lx (a
/// daylight factor of 0.03 %) and the roof 7 % too bright.
#[test]
fn a_closed_room_under_the_overcast_sky_stays_dark() {
    let dir = scratch("grids-closed-room");
    let quad = |name: &str, v: [[f64; 3]; 4]| {
        format!(
            "[[objects]]\nname = \"{name}\"\nmaterial = \"paint\"\nshape = \"polygon\"\n\
             vertices = {v:?}\n"
        )
    };
    let (x, y, z) = (6.0, 3.0, 4.0);
    let mut scene = String::from(
        "[sky]\ntype = \"cie-overcast\"\nzenith_luminance = 10000.0\n\n\
         [materials.paint]\nreflectance = 0.5\ntwo_sided = true\n\n\
         [[grids]]\nname = \"desk\"\n\
         corners = [[0.5, 0.85, 0.5], [5.5, 0.85, 0.5], [0.5, 0.85, 3.5]]\nspacing = 0.5\n\n",
    );
    // Every wall counter-clockwise seen from inside.
    for (name, v) in [
        (
            "floor",
            [[0.0, 0.0, 0.0], [0.0, 0.0, z], [x, 0.0, z], [x, 0.0, 0.0]],
        ),
        (
            "ceiling",
            [[0.0, y, 0.0], [x, y, 0.0], [x, y, z], [0.0, y, z]],
        ),
        (
            "west",
            [[0.0, 0.0, 0.0], [0.0, y, 0.0], [0.0, y, z], [0.0, 0.0, z]],
        ),
        ("east", [[x, 0.0, 0.0], [x, 0.0, z], [x, y, z], [x, y, 0.0]]),
        (
            "north",
            [[0.0, 0.0, 0.0], [x, 0.0, 0.0], [x, y, 0.0], [0.0, y, 0.0]],
        ),
        (
            "south",
            [[0.0, 0.0, z], [0.0, y, z], [x, y, z], [x, 0.0, z]],
        ),
    ] {
        scene += &quad(name, v);
    }
    let json = solve_with_grids(&dir, &scene);
    let df = json["grids"][0]["daylight_factor"]["maximum"]
        .as_f64()
        .unwrap();
    assert!(df < 0.003, "daylight factor {df} % in a closed room");
    let stats: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("s.json")).unwrap()).unwrap();
    let roof = stats["objects"]
        .as_array()
        .unwrap()
        .iter()
        .find(|o| o["name"] == "ceiling")
        .unwrap()["back"][0]
        .as_f64()
        .unwrap();
    let exact = 0.5 * 7.0 * std::f64::consts::PI * 10000.0 / 9.0;
    assert!((roof / exact - 1.0).abs() < 0.01, "roof {roof} vs {exact}");
}

#[test]
fn a_luminaire_file_lights_a_grid_by_the_inverse_square_and_cosine_laws() {
    // A downlight of I(γ) = 1000 cos γ cd (tabulated every 5°, nothing above the horizon),
    // derated by 0.8, 200 cm over a black floor in a scene in centimetres: each grid point
    // reads E = 0.8 · 1000 cos γ · cos γ / r², r in metres, and nothing else.
    let dir = scratch("grids-luminaire");
    let gammas: Vec<String> = (0..=18).map(|k| (5 * k).to_string()).collect();
    let candela: Vec<String> = (0..=18)
        .map(|k| format!("{:.6}", 1000.0 * f64::from(5 * k).to_radians().cos()))
        .collect();
    let ies = format!(
        "IESNA:LM-63-2002\n[LUMINAIRE] cosine downlight\nTILT=NONE\n\
         1 -1 1 19 1 1 2 0 0 0\n1 1 20\n{}\n0\n{}\n",
        gammas.join(" "),
        candela.join(" ")
    );
    fs::write(dir.join("downlight.ies"), ies).unwrap();
    let scene = r#"
units = "cm"

[materials.black]
reflectance = 0.0

[[objects]]
name = "floor"
shape = "polygon"
material = "black"
vertices = [[-300.0, 0.0, -300.0], [-300.0, 0.0, 300.0], [300.0, 0.0, 300.0], [300.0, 0.0, -300.0]]

[[objects]]
name = "downlight"
shape = "luminaire"
file = "downlight.ies"
position = [0.0, 200.0, 0.0]
multiplier = 0.8

[[grids]]
name = "floor"
corners = [[-150.0, 0.0, -150.0], [150.0, 0.0, -150.0], [-150.0, 0.0, 150.0]]
spacing = 50.0
"#;
    let json = solve_with_grids(&dir, scene);
    assert_eq!(json["grids"][0]["points"], 36);
    let csv = fs::read_to_string(dir.join("lux/floor.csv")).unwrap();
    let mut worst: f64 = 0.0;
    for row in csv.lines().skip(1) {
        let v: Vec<f64> = row.split(',').map(|x| x.parse().unwrap()).collect();
        let (x, z) = (v[0] / 100.0, v[2] / 100.0);
        let r2 = x * x + z * z + 4.0;
        let cos = 2.0 / r2.sqrt();
        let exact = 0.8 * 1000.0 * cos * cos / r2;
        worst = worst.max((v[3] / exact - 1.0).abs());
    }
    // The table's linear interpolation between 5° steps of cos γ: below 0.1 %.
    assert!(worst < 1e-3, "worst {worst}");
    // The stats count the luminaire's flux, 0.8 · π · 1000 lm (∫ cos γ dΩ over the lower
    // hemisphere is π), in the scene's power units (cm²·W/m²: × 10⁴).
    let stats: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("s.json")).unwrap()).unwrap();
    let emitted = stats["energy"]["emitted"][1].as_f64().unwrap();
    let flux = 0.8 * std::f64::consts::PI * 1000.0;
    assert!((emitted / 1e4 / flux - 1.0).abs() < 1e-3, "{emitted}");
}

/// A grey unit room (every face counter-clockwise seen from inside) lit by a lamp under its
/// ceiling, with a 3 × 3 grid 0.2 above the floor: part of each reading is gathered from the
/// walls by the meter's random rays.
const GREY_ROOM: &str = r#"
[materials.grey]
reflectance = 0.5
[materials.glow]
emission = 100.0

[[objects]]
name = "lamp"
material = "glow"
shape = "polygon"
vertices = [[0.3, 0.999, 0.3], [0.7, 0.999, 0.3], [0.7, 0.999, 0.7], [0.3, 0.999, 0.7]]

[[objects]]
name = "floor"
material = "grey"
shape = "polygon"
vertices = [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, 0.0]]

[[objects]]
name = "ceiling"
material = "grey"
shape = "polygon"
vertices = [[0.0, 1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0]]

[[objects]]
name = "west"
material = "grey"
shape = "polygon"
vertices = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 1.0], [0.0, 0.0, 1.0]]

[[objects]]
name = "east"
material = "grey"
shape = "polygon"
vertices = [[1.0, 0.0, 0.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [1.0, 1.0, 0.0]]

[[objects]]
name = "north"
material = "grey"
shape = "polygon"
vertices = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]

[[objects]]
name = "south"
material = "grey"
shape = "polygon"
vertices = [[0.0, 0.0, 1.0], [0.0, 1.0, 1.0], [1.0, 1.0, 1.0], [1.0, 0.0, 1.0]]

[[grids]]
name = "low"
corners = [[0.0, 0.2, 0.0], [1.0, 0.2, 0.0], [0.0, 0.2, 1.0]]
spacing = 0.3333334
"#;

/// The grid's lux column of `radiosity solve room.toml --grids DIR` with `extra` options.
fn lux_with(dir: &Path, out: &str, extra: &[&str]) -> Vec<f64> {
    let run = radiosity()
        .args(["solve", "room.toml", "--quiet", "--grids", out])
        .args(extra)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    fs::read_to_string(dir.join(out).join("low.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|row| row.rsplit(',').next().unwrap().parse().unwrap())
        .collect()
}

/// `--seed` draws the meter's rays: the same seed gives the same bits, another one other
/// readings that agree within the meter's noise. The gathered part is about 40 % of each
/// reading here and its noise at most 1 % of it (4 096 rays, `render/evaluated/meter.rs`;
/// measured, two seeds differ by 0.11 % at most): bounded by 2 % per point and 1 % on the
/// mean. The seed also reaches the meter under analytic form factors, which have no other use
/// for it.
#[test]
fn the_seed_draws_the_meters_rays() {
    let dir = scratch("grids-seed");
    fs::write(dir.join("room.toml"), GREY_ROOM).unwrap();
    let first = lux_with(&dir, "a", &["--seed", "1"]);
    let again = lux_with(&dir, "b", &["--seed", "1"]);
    let other = lux_with(&dir, "c", &["--seed", "2"]);
    assert_eq!(first.len(), 9);
    assert_eq!(
        fs::read(dir.join("a/low.csv")).unwrap(),
        fs::read(dir.join("b/low.csv")).unwrap(),
        "the same seed, the same bits"
    );
    assert_eq!(first, again);
    assert_ne!(first, other, "another seed, other rays");
    for (a, b) in first.iter().zip(&other) {
        assert!((a / b - 1.0).abs() < 0.02, "{a} vs {b}");
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    assert!((mean(&first) / mean(&other) - 1.0).abs() < 0.01);
    let analytic = |out, seed| {
        lux_with(
            &dir,
            out,
            &[
                "--form-factors",
                "analytic",
                "--elements",
                "200",
                "--seed",
                seed,
            ],
        )
    };
    assert_ne!(analytic("d", "1"), analytic("e", "2"));
}

/// A desk (a box) under a lamp in a room of grey walls: a grid `on = "desk"` reads as the
/// `corners` grid of the desk's top lifted 1 mm (the same points, to f32 rounding, and so the
/// same readings: the solve does not depend on the grid, and each grid's rays are keyed by its
/// points' order), and grids.json reports it alike.
#[test]
fn a_grid_on_a_box_top_reads_as_the_corners_grid_of_that_top() {
    let room = r#"
[materials.grey]
reflectance = 0.5
[materials.glow]
emission = 50.0

[[objects]]
name = "floor"
material = "grey"
shape = "polygon"
vertices = [[-2.0, 0.0, -2.0], [-2.0, 0.0, 2.0], [2.0, 0.0, 2.0], [2.0, 0.0, -2.0]]

[[objects]]
name = "wall"
material = "grey"
shape = "polygon"
vertices = [[-2.0, 0.0, -2.0], [2.0, 0.0, -2.0], [2.0, 2.5, -2.0], [-2.0, 2.5, -2.0]]

[[objects]]
name = "desk"
material = "grey"
shape = "box"
min = [-0.8, 0.0, -1.0]
max = [0.8, 0.75, -0.2]

[[objects]]
name = "lamp"
material = "glow"
shape = "polygon"
vertices = [[-0.5, 2.5, -0.5], [0.5, 2.5, -0.5], [0.5, 2.5, 0.5], [-0.5, 2.5, 0.5]]
"#;
    let on = format!("{room}\n[[grids]]\nname = \"desk\"\non = \"desk\"\nspacing = 0.2\n");
    let corners = format!(
        "{room}\n[[grids]]\nname = \"desk\"\n\
         corners = [[-0.8, 0.751, -1.0], [0.8, 0.751, -1.0], [-0.8, 0.751, -0.2]]\nspacing = 0.2\n"
    );
    let read = |name: &str, scene: &str| {
        let dir = scratch(name);
        let json = solve_with_grids(&dir, scene);
        let csv = fs::read_to_string(dir.join("lux/desk.csv")).unwrap();
        let mut rows: Vec<[f64; 4]> = csv
            .lines()
            .skip(1)
            .map(|l| {
                let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
                [v[0], v[1], v[2], v[3]]
            })
            .collect();
        rows.sort_by(|a, b| (a[2], a[0]).partial_cmp(&(b[2], b[0])).unwrap());
        (json, rows)
    };
    let (json_on, on) = read("grids-on-desk", &on);
    let (json_corners, corners) = read("grids-on-desk-corners", &corners);
    assert_eq!(on.len(), 8 * 4, "8 × 4 cells of 0.2 on the 1.6 × 0.8 top");
    assert_eq!(on.len(), corners.len());
    for (a, b) in on.iter().zip(&corners) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() < 1e-5, "{a:?} {b:?}");
        }
        assert!((a[3] / b[3] - 1.0).abs() < 1e-3, "{a:?} {b:?}");
    }
    for key in ["points", "normal"] {
        assert_eq!(
            json_on["grids"][0][key], json_corners["grids"][0][key],
            "{key}"
        );
    }
    let (a, b) = (
        json_on["grids"][0]["average"].as_f64().unwrap(),
        json_corners["grids"][0]["average"].as_f64().unwrap(),
    );
    assert!((a / b - 1.0).abs() < 1e-3, "E_avg {a} against {b}");
}
