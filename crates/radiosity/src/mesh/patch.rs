//! Patches: the sides of the scene's planar polygons that take part in light transport.
//!
//! Each polygon gives one patch for its front. A `two_sided` material gives a second patch for
//! the back (the same corners in reverse order, so its "front" is the polygon's back), which
//! reflects with the same ρ but never emits: emission is from the front only (docs/scene-format.md).
//!
//! A patch is planar. Files made by modelling tools are full of quads a little out of plane
//! (the published Cornell box's left wall by 0.1 %, walls "as exported" by 1–2 %); a quadtree of
//! bilinear faces over such a quad is not the surface rays see (two triangles), so points of one
//! side sit behind the other side's triangles, and the front and back twins of a two-sided
//! polygon face each other across the fold and trade light through it. So a polygon whose
//! corners stray from its mean plane by more than [`PLANAR_TOLERANCE`] of its diameter is cut
//! into triangles (the quad along its first diagonal, as path tracers fan it), each its own
//! planar patch with its own normal, and those triangles are exactly what rays hit.
//!
//! [`PLANAR_TOLERANCE`]: super::root_faces::PLANAR_TOLERANCE

use glam::Vec3;
use rayon::prelude::*;

use super::discontinuity::cut_shadows;
use super::enclosure::enclosed_objects;
use super::imprint::{imprint, Piece};
use super::root_faces::{is_planar, root_faces};
use super::triangulate::is_convex;
use super::Face;
use crate::{Rgb, Scene};

/// One reflecting (and possibly emitting) side of a scene polygon.
#[derive(Clone, Debug)]
pub struct Patch {
    /// Index into [`Scene::polygons`].
    pub polygon: u32,
    /// Index into [`Scene::objects`].
    pub object: u32,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Whether this is the back side of a two-sided polygon.
    pub back: bool,
    /// Whether the polygon's material is two-sided (so this patch has a reversed twin).
    pub two_sided: bool,
    /// Unit normal (Newell's method).
    pub normal: Vec3,
    /// Area.
    pub area: f64,
    /// Diffuse reflectance ρ: the material's, or a textured polygon's mean of its texture over
    /// the polygon ([`crate::scene::Material::reflectance_of`]); every piece of the polygon
    /// shares it.
    pub reflectance: Rgb,
    /// Emitted exitance E = π·L_e (W·m⁻²); zero on back sides.
    pub emission: Rgb,
    /// Polygons whose outline was cut into the root faces ([`super::imprint`]).
    pub imprinted: Vec<u32>,
    /// Whether it is part of a distant environment's far cube
    /// ([`crate::scene::environment`]): light that the hierarchical solver gathers along rays
    /// rather than links ([`crate::solve::hierarchical::distant`]).
    pub distant: bool,
}

/// The patches of `scene` with the root faces of each patch's element quadtree, cut along
/// the outlines of large polygons lying on them ([`super::imprint`]) and, with
/// `discontinuity`, along the outlines of sharp shadows ([`super::discontinuity`]).
pub(super) fn patches(scene: &Scene, discontinuity: bool) -> Vec<(Patch, Vec<Face>)> {
    let enclosed = enclosed_objects(scene);
    let mut pieces: Vec<Piece> = scene
        .polygons
        .iter()
        .enumerate()
        .flat_map(|(polygon, p)| {
            planar_pieces(&p.vertices)
                .into_iter()
                .map(move |(normal, roots)| Piece {
                    polygon,
                    normal,
                    roots,
                    imprinted: Vec::new(),
                })
        })
        .collect();
    imprint(scene, &mut pieces);
    if discontinuity {
        cut_shadows(scene, &mut pieces);
    }
    // Each polygon's reflectance once (a textured one's is a mean over its footprint), for
    // all its pieces.
    let reflectance: Vec<Rgb> = scene
        .polygons
        .par_iter()
        .map(|p| scene.materials[p.material].reflectance_of(p))
        .collect();
    let mut out = Vec::with_capacity(pieces.len());
    for piece in pieces {
        let polygon = &scene.polygons[piece.polygon];
        let material = &scene.materials[polygon.material];
        let two_sided = material.two_sided && !enclosed[polygon.object];
        let area = piece.roots.iter().map(Face::area).sum();
        let front = Patch {
            polygon: piece.polygon as u32,
            object: polygon.object as u32,
            material: polygon.material as u32,
            back: false,
            two_sided,
            normal: piece.normal,
            area,
            reflectance: reflectance[piece.polygon],
            emission: material.emission * std::f64::consts::PI,
            imprinted: piece.imprinted,
            distant: scene.objects[polygon.object].name == crate::scene::environment::NAME
                && material.reflectance == Rgb::ZERO,
        };
        if two_sided {
            let back = Patch {
                back: true,
                normal: -piece.normal,
                emission: Rgb::ZERO,
                ..front.clone()
            };
            let reversed = piece.roots.iter().map(reverse).collect();
            out.push((front, piece.roots));
            out.push((back, reversed));
        } else {
            out.push((front, piece.roots));
        }
    }
    out
}

/// The polygon as planar pieces, each with its unit normal and root faces: the whole polygon
/// when it is planar ([`is_planar`]), else one piece per triangle.
fn planar_pieces(vertices: &[Vec3]) -> Vec<(Vec3, Vec<Face>)> {
    let normal = model::polymesh::vector_area(vertices).normalize_or_zero();
    if is_planar(vertices, normal) {
        return vec![(normal, root_faces(vertices, normal))];
    }
    let triangles = match *vertices {
        [a, b, c, d] if is_convex(vertices, normal) => {
            vec![Face::triangle(a, b, c), Face::triangle(a, c, d)]
        }
        _ => root_faces(vertices, normal),
    };
    triangles
        .into_iter()
        .filter(|t| t.area() > 0.0)
        .map(|t| (t.normal(), vec![t]))
        .collect()
}

/// The same face seen from the other side.
fn reverse(face: &Face) -> Face {
    match *face.corners() {
        [a, b, c] => Face::triangle(a, c, b),
        [a, b, c, d] => Face::quad(a, d, c, b),
        _ => unreachable!("faces have three or four corners"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_planar_quad_becomes_two_planar_triangles_planar_quad_stays() {
        let (a, b, c, d) = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.02),
            Vec3::new(0.0, 1.0, 0.0),
        );
        let pieces = planar_pieces(&[a, b, c, d]);
        assert_eq!(pieces.len(), 2);
        for (normal, roots) in &pieces {
            assert_eq!(roots.len(), 1);
            assert!(!roots[0].is_quad());
            assert!((roots[0].normal() - *normal).length() < 1e-6);
        }
        // The first diagonal a–c, as the triangles rays hit and path tracers fan.
        assert_eq!(pieces[0].1[0].corners(), &[a, b, c]);
        assert_eq!(pieces[1].1[0].corners(), &[a, c, d]);
        let flat = planar_pieces(&[a, b, Vec3::new(1.0, 1.0, 0.00001), d]);
        assert_eq!(flat.len(), 1);
        assert!(flat[0].1[0].is_quad());
    }

    #[test]
    fn reversed_face_has_opposite_normal() {
        let f = Face::quad(Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Y, Vec3::Y);
        assert_eq!(reverse(&f).normal(), -f.normal());
    }
}
