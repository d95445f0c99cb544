//! Results do not depend on the number of worker threads: the built-in Cornell box solved with
//! 1, 2 and 8 threads gives byte-identical statistics (objects, energy, solver) and images.

use std::fs;

mod common;

use common::{radiosity, scratch};

/// Renders the built-in Cornell box with `threads` threads; returns the stats JSON and the
/// `.pfm` bytes.
fn run(threads: u32) -> (serde_json::Value, Vec<u8>) {
    let dir = scratch(&format!("determinism-{threads}"));
    let threads = threads.to_string();
    let out = radiosity()
        .args([
            "render",
            "cornell",
            "--elements",
            "300",
            "--width",
            "32",
            "--height",
            "32",
            "--threads",
            &threads,
            "-o",
            "image.pfm",
            "--stats",
            "stats.json",
            "--quiet",
        ])
        .current_dir(&dir)
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "{threads} threads: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stats = serde_json::from_slice(&fs::read(dir.join("stats.json")).unwrap()).unwrap();
    let image = fs::read(dir.join("image.pfm")).unwrap();
    let _ = fs::remove_dir_all(&dir);
    (stats, image)
}

#[test]
fn one_two_and_eight_threads_agree_bit_for_bit() {
    let (stats1, image1) = run(1);
    assert!(image1.len() > 32 * 32 * 3 * 4, "a 32×32 RGB float image");
    for threads in [2, 8] {
        let (stats, image) = run(threads);
        for section in ["objects", "energy", "solver"] {
            // serde_json prints floats with the shortest round-trip form: equal text is equal
            // bits.
            let a = serde_json::to_string(&stats1[section]).unwrap();
            let b = serde_json::to_string(&stats[section]).unwrap();
            assert!(stats1[section].is_object() || stats1[section].is_array());
            assert_eq!(a, b, "`{section}` differs between 1 and {threads} threads");
        }
        assert!(
            image == image1,
            "the .pfm image differs between 1 and {threads} threads"
        );
    }
}
