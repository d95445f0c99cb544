//! File input and output (in progress).
pub mod atomic;
pub mod gltf;
pub mod gltf_import;
pub mod html;
pub mod image_file;
pub mod obj;
pub mod ply;
