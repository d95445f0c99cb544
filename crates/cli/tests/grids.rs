//! `--grids DIR`: the illuminance on a scene's calculation grids, written as CSV and JSON.

use std::fs;

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

#[test]
fn solve_writes_each_grid_and_its_statistics() {
    let dir = scratch("grids-solve");
    fs::write(dir.join("room.toml"), ROOM).unwrap();
    let out = radiosity()
        .args(["solve", "room.toml", "--grids", "lux", "--quiet"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
    let json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("lux/grids.json")).unwrap()).unwrap();
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
