//! `radiosity bake`: the baked model and its light map are written (and only they), the atlas
//! has the size asked for, and bad flags are one-line errors with exit status 2 that write
//! nothing.

use std::path::PathBuf;
use std::process::Command;

fn temp_dir(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("radiosity-cli-bake-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn radiosity(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(args)
        .output()
        .expect("the binary runs")
}

#[test]
fn a_bake_writes_the_model_and_its_light_map() {
    let dir = temp_dir("ok");
    let glb = dir.join("box.glb");
    let out = radiosity(&[
        "bake",
        "cornell",
        "-o",
        glb.to_str().unwrap(),
        "--lightmap-size",
        "64",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("in a 64 × 64 light map"), "{stderr}");
    let mut written: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(written, ["box.glb", "box.lightmap.exr"]);
    // The light map's size and the baked texture are in the file.
    let bytes = std::fs::read(&glb).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    assert_eq!(doc["images"].as_array().unwrap().len(), 2);
    assert_eq!(
        doc["materials"][0]["extras"]["lightmap"]["exr"],
        "box.lightmap.exr"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_bake_flags_are_errors_that_write_nothing() {
    let dir = temp_dir("bad");
    let glb = dir.join("x.glb");
    let glb = glb.to_str().unwrap();
    let obj = dir.join("x.obj");
    for (args, message) in [
        (
            vec!["--lightmap-size", "8"],
            "--lightmap-size 8: from 16 to 16384",
        ),
        (vec!["--padding", "1"], "--padding 1: at least 2 texels"),
        (
            vec!["--texels-per-unit", "0"],
            "--texels-per-unit 0: must be a positive number",
        ),
        (vec!["--texels-per-unit", "1e9"], "makes a"),
    ] {
        let mut all = vec!["bake", "cornell", "-o", glb];
        all.extend(args);
        let out = radiosity(&all);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{all:?}: {stderr}");
        assert!(stderr.contains(message), "{all:?}: {stderr}");
        assert_eq!(
            stderr
                .trim()
                .lines()
                .last()
                .map(|l| l.starts_with("error: ")),
            Some(true),
            "{stderr}"
        );
    }
    let out = radiosity(&["bake", "cornell", "-o", obj.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unsupported baked model extension"));
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    let _ = std::fs::remove_dir_all(&dir);
}
