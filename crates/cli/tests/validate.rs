//! `radiosity validate --format json` exits 0 and every row of the suite is within its stated
//! tolerance, the Cornell box rows against the path-traced reference and the daylight rows
//! against their quadratures included.

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
    assert!(rows.len() >= 27, "{} rows", rows.len());
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
    // Daylight through an opening onto a black interior (CIE 171 §5.9–5.13): three floor
    // points per case, each lit (a positive illuminance) and within its tolerance above.
    for case in [
        "roof opening 1 × 1 m, CIE overcast sky",
        "roof opening 1 × 1 m, CIE clear sky (type 12), sun 30° high",
        "window 2 × 1 m, sill 1 m, CIE overcast sky",
    ] {
        let points: Vec<_> = rows
            .iter()
            .filter(|r| r["case"].as_str().unwrap().starts_with(case))
            .collect();
        assert_eq!(points.len(), 3, "{case}");
        for row in points {
            assert_eq!(row["quantity"], "illuminance (lx)", "{row}");
            assert!(row["ours"].as_f64().unwrap() > 0.0, "{row}");
        }
    }
}
