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
