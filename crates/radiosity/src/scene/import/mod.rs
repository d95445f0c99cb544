//! Scene files made elsewhere, read into the scene's own types: Wavefront OBJ with its MTL
//! materials ([`obj`]) and glTF 2.0, `.gltf` or `.glb` ([`gltf_file`]). They sit below the scene
//! builder, which turns their meshes into polygons.
pub mod gltf_file;
pub mod mitsuba;
pub mod obj;
pub mod ply;
