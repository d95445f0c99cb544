//! Pairs the cluster kernel cannot resolve, estimated by rays.
//!
//! [`View::estimate`] trusts its point kernel between a cluster and another handle only when
//! their bounding spheres lie apart and no face's plane cuts the other's sphere. Two
//! neighbouring pieces of one tessellated surface, or a cluster with itself, never do, and
//! opening them always, as the refinement did, links every face of a fine mesh with each of its
//! neighbours before any light is known: Bitterli's veach-ajar, whose four teapots hold 250 000
//! triangles, made 24 million links in the first pass (B = E, when no surface but the
//! emitters sends anything) and never finished.
//!
//! So the refinement keeps such a pair as one link while even the most it could carry is small
//! ([`super::super::refine`]), and its factor is estimated the way Nusselt's analogue reads it:
//! from points x_k drawn over the receiver in proportion to area, rays in cosine-distributed
//! directions ω_k; the fraction whose first hit lies on the source is the form factor with its
//! visibility (Malley's method; Cohen & Wallace 1993, §4.10):
//!
//! ```text
//! F_rs = (1/A_r) ∫_r ∫_Ω cos θ / π · [ray (x, ω) first hits s] dω dA  ≈  (1/N) Σ_k [hit_k ∈ s]
//! ```
//!
//! Each draw is 0 or 1, so the estimate is bounded whatever the distance (the two-point kernel
//! cos θ cos θ' / (π r²) is not, between touching neighbours), and its noise, at most
//! √(F(1 − F)/N), falls on links that carry little by construction. A receiving cluster spreads
//! what such a link brings evenly over its faces; a cluster with itself shines its mean
//! ([`super::super::push_pull`]); the elements below do not take factors of their own from it
//! ([`super::super::leaf_rows`]).

use glam::Vec3;

use super::{End, Handle, View};
use crate::accel::Ray;
use crate::formfactor::visibility::jitter;
use crate::hash::{mix, unit_f64};
use crate::mesh::Face;
use crate::sampling::cosine_direction;

/// Rays per unresolved pair.
pub const RAYS: u32 = 256;

/// Salt of the rays, apart from every other estimator's.
const SALT: u64 = 0x0E5_0000_0000_0000;

impl View<'_> {
    /// The form factor F_rs with its visibility by [`RAYS`] cosine-distributed rays from the
    /// receiver (module docs).
    #[must_use]
    pub fn unresolved_factor(&self, r: Handle, s: Handle) -> f64 {
        let pair = mix(mix(u64::from(r.to_bits()) ^ SALT) ^ u64::from(s.to_bits()));
        let mut hits = 0u32;
        for k in 0..RAYS {
            let bits = mix(pair ^ u64::from(k));
            let node = match r.end() {
                End::Node(n) => n as u32,
                End::Cluster(c) => self.clusters.draw_face(c, unit_f64(mix(bits ^ 1))),
            };
            let node = &self.mesh.nodes[node as usize];
            let normal = self.mesh.patches[node.patch as usize].normal;
            // Stratified over the square of directions, jittered within each cell.
            let (i, j) = (k % 8, (k / 8) % 8);
            let u1 = (i as f32 + jitter(bits, 2)) / 8.0;
            let u2 = (j as f32 + jitter(bits, 3)) / 8.0;
            let from = node.face.point(jitter(bits, 0), jitter(bits, 1)) + normal * self.lift;
            let ray = Ray::new(from, cosine_direction(normal, u1, u2));
            let Some(hit) = self.bvh.closest_hit(&ray, f32::INFINITY) else {
                continue;
            };
            let at = from + ray.dir * hit.t;
            let polygon = self.mesh.triangle_polygon[hit.triangle as usize];
            if self.lands_on(s, polygon, at, ray.dir) {
                hits += 1;
            }
        }
        f64::from(hits) / f64::from(RAYS)
    }

    /// Whether a ray along `dir` that first hits scene polygon `polygon` at `at` lands on
    /// handle `h`: on the side of a root face facing the ray that `h` holds or, for a
    /// quadtree node, within its face.
    fn lands_on(&self, h: Handle, polygon: u32, at: Vec3, dir: Vec3) -> bool {
        // A point outside h's bounding sphere is on none of its faces: most rays land far from
        // a small source on a polygon cut into thousands of root faces (the staircase's walls
        // and ceiling), whose search below would cost a test per root face.
        let (centre, radius) = self.sphere(h);
        if at.distance(centre) > radius * (1.0 + 1e-4) + 2.0 * self.lift {
            return false;
        }
        // Only the polygon's root faces that h holds are tested, each in O(1) before its
        // edges: a wall's polygon may hold thousands of root faces (the staircase's walls),
        // and testing the edges of each took 38 % of its solve.
        let holds = |f: u32| match h.end() {
            End::Cluster(c) => self.clusters.holds(c, f),
            End::Node(n) => self.mesh.nodes[n].patch == self.mesh.nodes[f as usize].patch,
        };
        let on_root = self.clusters.roots_of(polygon).iter().any(|&f| {
            let node = &self.mesh.nodes[f as usize];
            holds(f)
                && self.mesh.patches[node.patch as usize].normal.dot(dir) < 0.0
                && within(&node.face, at)
        });
        on_root
            && h.as_node()
                .is_none_or(|n| within(&self.mesh.nodes[n].face, at))
    }
}

/// Whether point `p`, on (or very near) the plane of a convex face, lies within it: on the
/// inner side of every edge, to a tolerance of 10⁻⁴ of the edge's length.
fn within(face: &Face, p: Vec3) -> bool {
    let corners = face.corners();
    let n = face.normal();
    (0..corners.len()).all(|i| {
        let (a, b) = (corners[i], corners[(i + 1) % corners.len()]);
        let edge = b - a;
        edge.cross(p - a).dot(n) >= -1e-4 * edge.length_squared()
    })
}

#[cfg(test)]
mod tests {
    use super::super::{Handle, View};
    use crate::accel::Bvh;
    use crate::mesh::{Mesh, Subdivision};
    use crate::solve::hierarchical::cluster::Clusters;

    /// Inside a closed unit cube every ray from a face lands on another face: its factor to the
    /// root cluster (all six faces) is exactly 1, and its factors to the five other faces are
    /// each near 0.2 (the closed forms: 0.20004 to a perpendicular unit square
    /// sharing an edge, 0.19982 to the parallel one 1 away).
    #[test]
    fn rays_from_a_cube_face_land_on_the_others_in_their_form_factors() {
        let scene = crate::testing::closed_cube(0.5, [1.0; 6]);
        let mesh = Mesh::build(&scene, Subdivision::MaxArea(f64::INFINITY));
        let bvh = Bvh::build(&mesh.triangles);
        let clusters = Clusters::build(&mesh);
        let view = View::new(&mesh, &clusters, &bvh);
        let face = Handle::node(clusters.faces[0]);
        assert!((view.unresolved_factor(face, Handle::ROOT_CLUSTER) - 1.0).abs() < 1e-12);
        let mut total = 0.0;
        for &f in &clusters.faces[1..] {
            let other = Handle::node(f);
            let factor = view.unresolved_factor(face, other);
            // 64 rays: one standard deviation is √(0.2·0.8/64) = 0.05.
            assert!((factor - 0.2).abs() < 0.16, "{factor}");
            total += factor;
        }
        // Each face's rays are drawn apart: the five sum to 1 within their noise (σ ≈ 0.11).
        assert!((total - 1.0).abs() < 0.25, "{total}");
    }
}
