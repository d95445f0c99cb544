//! `radiosity validate --format json` exits 0 and every row of the suite is within its stated
//! tolerance, the Cornell box rows against the path-traced reference included.

use std::process::Command;

#[test]
fn validation_suite_passes_every_row() {
    let out = Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(["validate", "--format", "json"])
        .current_dir(std::env::temp_dir())
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    let rows = rows.as_array().expect("an array of rows");
    assert!(rows.len() >= 18, "{} rows", rows.len());
    for row in rows {
        let error = row["error"].as_f64().unwrap();
        let tolerance = row["tolerance"].as_f64().unwrap();
        assert!(row["pass"] == true && error <= tolerance, "{row}");
    }
    // One row per object of the Cornell box against Mitsuba 3, each a positive radiosity.
    let cornell: Vec<_> = rows
        .iter()
        .filter(|r| {
            r["case"]
                .as_str()
                .unwrap()
                .starts_with("Cornell box vs Mitsuba 3")
        })
        .collect();
    let mut names: Vec<_> = cornell
        .iter()
        .map(|r| r["case"].as_str().unwrap().rsplit(": ").next().unwrap())
        .collect();
    names.sort_unstable();
    assert_eq!(
        names,
        [
            "back_wall",
            "ceiling",
            "floor",
            "left_wall",
            "light",
            "right_wall",
            "short_block",
            "tall_block"
        ]
    );
    for row in cornell {
        assert!(row["reference"].as_f64().unwrap() > 0.0, "{row}");
        assert!(row["ours"].as_f64().unwrap() > 0.0, "{row}");
    }
}

/// The cheap part of the reference suite (`radiosity validate --suite`): a closed two-sided
/// mesh on a floor, a Blender-style glTF with every material double-sided (blocks standing on
/// a floor that runs under them), and an emitter 1 mm in front of a wall facing into the room.
/// Each object of each scene within 1 % of its Mitsuba 3 reference (standard error ≤ 0.2 %), and
/// the closed room's absorbed power within 0.1 % of its emitted power (measured 1.0008).
#[test]
fn reference_suite_subset_is_within_one_percent() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut args = vec!["validate", "--format", "json", "--suite", "--suite-dir"];
    let root_str = root.to_str().expect("a UTF-8 path");
    args.push(root_str);
    for scene in ["closed-mesh", "blender-gltf", "emitter-near-wall-away"] {
        args.extend(["--suite-scene", scene]);
    }
    let out = Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(&args)
        .output()
        .expect("the binary runs");
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    let suite: Vec<_> = rows
        .as_array()
        .expect("rows")
        .iter()
        .filter(|r| r["case"].as_str().unwrap().starts_with("suite "))
        .collect();
    assert_eq!(suite.len(), 4, "{rows}");
    for row in &suite {
        assert!(row["pass"] == true, "{row}");
    }
    assert!(suite.iter().any(|r| r["case"]
        .as_str()
        .unwrap()
        .starts_with("suite emitter-near-wall-away (auto, raycast")
        && r["quantity"]
            .as_str()
            .unwrap()
            .starts_with("absorbed / emitted")));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut args = vec!["validate", "--format", "json", "--suite", "--suite-dir"];
    args.push(root.to_str().expect("a UTF-8 path"));
    for scene in [
        "partitions",
        "closed-mesh",
        "blender-gltf",
        "emitter-near-wall-away",
        "bare-obj-many",
    ] {
        args.extend(["--suite-scene", scene]);
    }
    args.extend(["--suite-solver", "hierarchical"]);
    let out = Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(&args)
        .output()
        .expect("the binary runs");
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    let suite: Vec<_> = rows
        .as_array()
        .expect("rows")
        .iter()
        .filter(|r| r["case"].as_str().unwrap().starts_with("suite "))
        .collect();
    assert_eq!(suite.len(), 7, "{rows}");
    for row in &suite {
        assert!(row["pass"] == true, "{row}");
    }
}
