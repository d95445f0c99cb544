//! Scene files: any text must parse, validate and build to a scene or a `SceneError`, never a
//! panic. Mesh paths resolve relative to the working directory (`fuzz/`).
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use radiosity::Scene;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = Scene::from_toml_str(text, Path::new("fuzz.toml"));
    }
});
