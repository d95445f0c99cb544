//! Quadtree nodes: a face of a patch, its place in the tree, and the measures of its face that
//! every form factor asks for.
//!
//! A hierarchical solve estimates about twenty-five million factors on the furnished room, each
//! wanting the receiver's area, centroid, normal and bounding sphere; computed from the corners
//! at every call they were a tenth of the solver's time (`perf`). A face never
//! changes once its node is made, so the node computes them once, when it is made.

use std::ops::Range;

use glam::Vec3;

use super::Face;

/// A quadtree node: a face of a patch, with four children or none (then it is an element).
#[derive(Clone, Debug)]
pub struct Node {
    /// The node's triangle or quadrilateral. Not to be changed once the node is made: its
    /// measures are kept from it ([`super::Mesh::validate`] checks).
    pub face: Face,
    /// Index into [`super::Mesh::patches`].
    pub patch: u32,
    /// Depth below the patch's root faces (roots are level 0).
    pub level: u8,
    /// Index of the first of four consecutive children in [`super::Mesh::nodes`], if any.
    pub children: Option<u32>,
    /// The elements below this node (itself, for a leaf): a range of [`super::Mesh::elements`].
    pub elements: Range<u32>,
    /// Whether another surface lies in this node's near field, where form factors need a finer
    /// receiver grid ([`super::Mesh::mark_near_field`]; children inherit it).
    pub near: bool,
    /// The face's measures, computed once.
    measures: Measures,
}

/// What [`Face`] would compute again and again.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Measures {
    area: f64,
    centroid: Vec3,
    normal: Vec3,
    diameter: f32,
    /// Centre of the bounding sphere: the mean of the corners.
    centre: Vec3,
    /// Its radius: the farthest corner from the centre.
    radius: f32,
}

impl Measures {
    fn of(face: &Face) -> Self {
        let corners = face.corners();
        let centre = corners.iter().copied().sum::<Vec3>() / corners.len() as f32;
        let radius = corners
            .iter()
            .map(|c| c.distance(centre))
            .fold(0.0, f32::max);
        Self {
            area: face.area(),
            centroid: face.centroid(),
            normal: face.normal(),
            diameter: face.diameter(),
            centre,
            radius,
        }
    }
}

impl Node {
    /// A leaf node of `face` on patch `patch`, `level` below its root.
    #[must_use]
    pub fn new(face: Face, patch: u32, level: u8, near: bool) -> Self {
        Self {
            measures: Measures::of(&face),
            face,
            patch,
            level,
            children: None,
            elements: 0..0,
            near,
        }
    }

    /// Whether the kept measures are those of the face (a node whose face was changed after
    /// it was made is not).
    #[must_use]
    pub fn consistent(&self) -> bool {
        self.measures == Measures::of(&self.face)
    }

    /// [`Face::area`] of the node's face.
    #[must_use]
    pub fn area(&self) -> f64 {
        self.measures.area
    }

    /// [`Face::centroid`].
    #[must_use]
    pub fn centroid(&self) -> Vec3 {
        self.measures.centroid
    }

    /// [`Face::normal`]: the face's own, which for a slightly non-planar patch differs from
    /// the patch's.
    #[must_use]
    pub fn normal(&self) -> Vec3 {
        self.measures.normal
    }

    /// [`Face::diameter`].
    #[must_use]
    pub fn diameter(&self) -> f32 {
        self.measures.diameter
    }

    /// A bounding sphere (centre, radius): about the mean of the corners, through the
    /// farthest.
    #[must_use]
    pub fn sphere(&self) -> (Vec3, f32) {
        (self.measures.centre, self.measures.radius)
    }
}
