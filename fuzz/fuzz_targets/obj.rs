//! OBJ meshes: any text must parse to an `ObjFile` or a `SceneError`, never a panic.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use radiosity::io::obj::parse_obj;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = parse_obj(text, Path::new("fuzz.obj"));
    }
});
