//! Meshing (in progress).
pub mod lit_mesh;
pub use lit_mesh::LitMesh;
