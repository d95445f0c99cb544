//! glTF 2.0 (JSON or GLB): any bytes must import to a `GltfFile` or a `SceneError`, never a
//! panic.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use radiosity::io::gltf_import::parse_gltf;

fuzz_target!(|data: &[u8]| {
    let _ = parse_gltf(data, Path::new("fuzz.gltf"));
});
