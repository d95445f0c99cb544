//! File output: images, the lit mesh (PLY, binary glTF), bakes (glTF with light maps), the HTML
//! viewer, and the atomic
//! writes they all go through. (The scene readers — OBJ/MTL, glTF — belong to the scene:
//! [`crate::scene::import`].)
pub mod atomic;
pub mod baked;
pub mod export;
pub mod gltf;
pub mod grids;
pub mod html;
pub mod image_file;
pub mod ply;
