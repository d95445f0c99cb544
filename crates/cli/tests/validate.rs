//! `radiosity validate --format json` exits 0 and every row of the suite is within its stated
//! tolerance.

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
    assert!(rows.len() >= 10, "{} rows", rows.len());
    for row in rows {
        let error = row["error"].as_f64().unwrap();
        let tolerance = row["tolerance"].as_f64().unwrap();
        assert!(row["pass"] == true && error <= tolerance, "{row}");
    }
}
