//! `cargo xtask suite --format json`: the reference suite's rows (our solvers against Mitsuba 3
//! on scenes made elsewhere, `benches/suite`) are within their tolerances. The suite finds the
//! repository by itself (the first test runs it from another folder) or from `--dir` (the
//! second).

use std::path::Path;
use std::process::Command;

/// Runs `xtask suite --format json` with `args` from the folder `dir`; checks that it succeeds
/// with `count` rows, each passing, and returns them.
fn passing_rows(args: &[&str], dir: &Path, count: usize) -> Vec<serde_json::Value> {
    let out = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(["suite", "--format", "json"])
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs");
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    let suite: Vec<_> = rows
        .as_array()
        .expect("rows")
        .iter()
        .filter(|r| r["case"].as_str().unwrap().starts_with("suite "))
        .cloned()
        .collect();
    assert_eq!(suite.len(), count, "{rows}");
    for row in &suite {
        assert!(row["pass"] == true, "{row}");
    }
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    suite
}

/// The cheap part of the reference suite: a closed two-sided mesh on a floor, a Blender-style
/// glTF with every material double-sided (blocks standing on a floor that runs under them), and
/// an emitter 1 mm in front of a wall facing into the room.
/// Each object of each scene within 1 % of its Mitsuba 3 reference (standard error ≤ 0.2 %), and
/// the closed room's absorbed power within 0.1 % of its emitted power (measured 1.0008).
#[test]
fn reference_suite_subset_is_within_one_percent() {
    let mut args = vec![];
    for scene in ["closed-mesh", "blender-gltf", "emitter-near-wall-away"] {
        args.extend(["--scene", scene]);
    }
    let suite = passing_rows(&args, &std::env::temp_dir(), 4);
    assert!(suite.iter().any(|r| r["case"]
        .as_str()
        .unwrap()
        .starts_with("suite emitter-near-wall-away (auto, raycast")
        && r["quantity"]
            .as_str()
            .unwrap()
            .starts_with("absorbed / emitted")));
}

/// Hierarchical radiosity on the cheap part of the suite and the partitioned room
/// (`benches/suite/partitions`: two rooms lit only through a door and a gap). Links from
/// surfaces that do not emit look weak in the first pass (B = E); dropping the hidden ones once
/// lost every link through the door, and the far room came out 27 % dark at any ε. Measured
/// with the elements' own rows, visibility and source pieces (docs/decisions/hierarchical-rows.md): partitions +0.67 %, closed-mesh −0.23 %, blender-gltf +0.31 %,
/// emitter-near-wall-away −0.35 %; each within the suite's 1 %. The two closed rooms' absorbed
/// over emitted power, 1.0009 and 1.0008, within the suite's 0.1 %. And the bare OBJ room
/// (`bare-obj-many`, every face two-sided), whose block stands on the floor without a bottom:
/// its inner sides, lit by the floor's elements straddling its footprint, took it to +1.46 %
/// until the floor was taken to close it (`mesh/enclosure.rs`; +0.68 % since).
#[test]
fn hierarchical_lights_rooms_through_a_door_and_the_cheap_suite() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut args = vec!["--dir", root.to_str().expect("a UTF-8 path")];
    for scene in [
        "partitions",
        "closed-mesh",
        "blender-gltf",
        "emitter-near-wall-away",
        "bare-obj-many",
    ] {
        args.extend(["--scene", scene]);
    }
    args.extend(["--solver", "hierarchical"]);
    passing_rows(&args, &std::env::temp_dir(), 7);
}
