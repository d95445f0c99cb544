//! The lit mesh: the viewer-independent product of a solve.
//!
//! Radiosity is stored per vertex (area-weighted mean of the elements around it) so renderers
//! can interpolate it smoothly (Gouraud). Every renderer and exporter reads this structure.

use glam::Vec3;

use crate::Rgb;

/// Triangles with radiosity B (W·m⁻²) at their vertices.
#[derive(Clone, Debug, Default)]
pub struct LitMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Radiosity per vertex, W·m⁻² per channel. Radiance is B/π.
    pub radiosity: Vec<Rgb>,
    /// Triangles, counter-clockwise seen from their lit front.
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle: its patch index (see [`crate::mesh::Mesh::patches`]).
    pub triangle_patch: Vec<u32>,
    /// Per triangle: whether a reversed twin triangle carries its back side (two-sided
    /// material). Such a triangle is culled when seen from behind; a one-sided triangle seen
    /// from behind is drawn black, because its back reflects nothing but still hides what is
    /// behind it.
    pub has_back_twin: Vec<bool>,
    /// Per triangle: its object index (see [`crate::Scene::objects`]).
    pub triangle_object: Vec<u32>,
}
