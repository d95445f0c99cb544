//! Contact refinement: elements crossed by another surface are split finer.
//!
//! Where a solid stands on a floor, or a partition meets a ceiling, the floor's elements
//! straddle the contact line: part of each lies in the open, part under the solid or on the
//! partition's dark side. Constant radiosity per element averages the two (the classic light
//! leak of non-conforming meshes, Baum, Mann, Smith & Winget 1991): such an element shines its
//! lit half's light into the dark side, and darkens the solid's faces next to the contact. The
//! exact cure is to mesh along the contact line (a D⁰ discontinuity, Heckbert 1992); within a
//! quadtree the next best is to split the straddling elements [`CONTACT_LEVELS`] levels deeper,
//! so the straddling area, and with it the leak, shrinks as 2^−levels of the element size and
//! keeps falling under uniform refinement.
//!
//! A leaf *touches* another polygon's triangle when the segment where the triangle crosses the
//! leaf's plane passes through the leaf's interior (by more than a relative tolerance from its
//! boundary): a solid standing on the floor touches the floor's elements along its footprint,
//! but a wall meeting the floor at the floor's edge touches nothing, and neither do coplanar
//! neighbours. A triangle hovering just in front of the leaf (closer than [`COVER`] of its own
//! size, the distance at which [`crate::scene::near_emitters`] warns) touches it where its
//! outline, projected, crosses the leaf: an emitter hung a millimetre in front of a wall and
//! facing it lights the gap, and the wall's elements straddling its outline leaked that light
//! into the room (measured on `scenes/suite/emitter-near-wall-facing`: the ceiling 123 % too
//! bright against Mitsuba 3 without this; +2.6 % with [`COVER_LEVELS`]). A large convex cover
//! is cut into the surface's root faces beforehand ([`super::imprint`]), so none of its elements
//! straddles the outline, and such a cover is skipped here. The reach is
//! relative to the hovering triangle, not to the leaf, so it holds at every level of the
//! refinement (it was relative to the leaf, and stopped after one level).
//!
//! A solid need not touch the floor to cast a contact line: in files made by modelling tools
//! the floor is a little out of plane, and a block's bottom edge floats a few millimetres over
//! it in places and sinks into it in others. Where it floats, the floor's elements straddling
//! its footprint leak just the same, so a triangle also touches a leaf when one of its edges,
//! within [`STAND`] of its size over the leaf's plane, passes over the leaf's interior
//! (measured on `scenes/suite/obj-box`: the blocks' insides were 59 % and 51 % too bright
//! against Mitsuba 3 with only crossings counted, +5 % and +9 % with this).

use glam::Vec3;

use super::ELEMENT_BATCH;
use super::{Mesh, MAX_LEVEL};
use crate::accel::Bvh;
use crate::progress::{Batched, Progress};

/// Extra quadtree levels for elements that a contact line crosses (each level halves the
/// straddling strip's width).
pub const CONTACT_LEVELS: u8 = 3;

/// Extra quadtree levels for elements that the outline of a hovering *emitter facing them*
/// crosses ([`COVER`]). Deeper than a contact line: the gap under the outline is lit by light
/// trapped between the two surfaces, brighter than the open side by two orders of magnitude
/// (an emitter facing a wall 1 mm away), so a straddling strip leaks far more (measured on
/// `scenes/suite/emitter-near-wall-facing`, the ceiling against Mitsuba 3: +12 % at 3 levels,
/// +4.7 % at 5, +2.6 % at 6). Other hovering surfaces leave a dark gap and get
/// [`CONTACT_LEVELS`].
pub const COVER_LEVELS: u8 = 6;

/// The search around a leaf reaches at most this many of its diameters (and at most the
/// largest triangle's [`STAND`] reach): a reach set by the scene's largest triangle alone (a
/// 20 m floor) made every small leaf of a million-triangle scene test thousands of triangles
/// (`radiosity bench --suite hierarchical`, the 1 024 002-triangle field: 312 s).
const QUERY_DIAMETERS: f32 = 8.0;

/// Relative tolerance of the contact test, as a fraction of the leaf's diameter.
const TOLERANCE: f32 = 1e-4;

impl Mesh {
    /// Splits every element that another polygon's triangle crosses (see the module docs), and
    /// its crossed children, down to [`CONTACT_LEVELS`] more levels ([`COVER_LEVELS`] under a
    /// hovering outline; never below [`MAX_LEVEL`]). Gives up, leaving the mesh valid but
    /// unfinished, once `stop` returns true. Reports the elements tested to `progress`.
    pub fn refine_contacts(
        &mut self,
        bvh: &Bvh,
        stop: &(dyn Fn() -> bool + Sync),
        progress: &dyn Progress,
    ) {
        if self.triangles.is_empty() {
            return;
        }
        let reach = self
            .triangles
            .iter()
            .map(|t| STAND * diameter(t))
            .fold(0.0, f32::max);
        let polygons = self.patches.iter().map(|p| p.polygon as usize + 1).max();
        let mut lights = vec![None; polygons.unwrap_or(0)];
        for p in self.patches.iter().filter(|p| !p.back) {
            if p.emission.max_element() > 0.0 {
                lights[p.polygon as usize] = Some(p.normal);
            }
        }
        // Leaves to test, with the levels already added above them.
        let mut candidates: Vec<(u32, u8)> = self.elements.iter().map(|&n| (n, 0)).collect();
        let tested = Batched::new(progress, ELEMENT_BATCH);
        while !candidates.is_empty() {
            let split: Vec<(u32, u8)> = candidates
                .iter()
                .copied()
                .filter(|&(n, done)| {
                    tested.one();
                    self.nodes[n as usize].level < MAX_LEVEL
                        && !stop()
                        && done < self.touched(bvh, reach, &lights, n, done)
                })
                .collect();
            if split.is_empty() {
                break;
            }
            let leaves: Vec<u32> = split.iter().map(|&(n, _)| n).collect();
            self.refine(&leaves);
            candidates = split
                .iter()
                .flat_map(|&(n, done)| {
                    let c = self.nodes[n as usize].children.expect("just split");
                    (c..c + 4).map(move |k| (k, done + 1))
                })
                .collect();
        }
    }

    /// How many levels node `n` wants added: [`COVER_LEVELS`] if a triangle of an emitting
    /// polygon facing it covers it partly from in front (within `reach`), [`CONTACT_LEVELS`] if
    /// another polygon's triangle crosses its face through the interior or covers it, 0
    /// otherwise. Stops looking once the answer exceeds `done`. `lights[p]` is the front normal
    /// of polygon `p` if it emits.
    fn touched(&self, bvh: &Bvh, reach: f32, lights: &[Option<Vec3>], n: u32, done: u8) -> u8 {
        let node = &self.nodes[n as usize];
        let patch = &self.patches[node.patch as usize];
        let corners = node.face.corners();
        // Relative to the leaf's size, and never below what f32 coordinates can resolve.
        let magnitude = corners
            .iter()
            .map(|c| c.abs().max_element())
            .fold(0.0, f32::max);
        let eps = (TOLERANCE * node.diameter()).max(8.0 * f32::EPSILON * magnitude);
        let mut wanted = 0;
        let reach = reach.min(QUERY_DIAMETERS * node.diameter()).max(eps);
        self.other_triangles_near(bvh, n, reach, |t| {
            if wanted <= done {
                let polygon = self.triangle_polygon[t] as usize;
                let facing_light = lights[polygon].is_some_and(|n| n.dot(patch.normal) < 0.0);
                // An outline cut into the patch's root faces leaves nothing to straddle (only
                // its triangles' inner diagonal would seem to cross).
                let imprinted = patch.imprinted.contains(&(polygon as u32));
                wanted = match crosses(corners, patch.normal, &self.triangles[t], eps) {
                    Some(Touch::Cover) if imprinted => 0,
                    Some(Touch::Cover) if facing_light => COVER_LEVELS,
                    Some(_) => CONTACT_LEVELS,
                    None => 0,
                };
            }
        });
        wanted
    }
}

/// How a triangle touches a polygon.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Touch {
    /// It crosses the polygon's plane inside the polygon.
    Contact,
    /// It hovers just in front, and its outline crosses the polygon.
    Cover,
}

/// How `triangle` touches the planar convex polygon `corners` (unit normal `normal`): along a
/// segment that enters its interior by more than `eps`, or hovering in front with an edge whose
/// projection does.
fn crosses(corners: &[Vec3], normal: Vec3, triangle: &[Vec3; 3], eps: f32) -> Option<Touch> {
    // Signed heights of the triangle's corners over the polygon's plane.
    let origin = corners[0];
    let d = triangle.map(|v| normal.dot(v - origin));
    if d.iter().all(|&h| h > eps && h < COVER * diameter(triangle)) {
        return covers_partly(corners, normal, triangle, eps).then_some(Touch::Cover);
    }
    if d.iter().all(|&h| h < -eps) {
        return None;
    }
    if d.iter().all(|&h| h.abs() <= eps) {
        return None; // coplanar: a neighbour, not a contact
    }
    let touch = crossing(triangle, d, eps).is_some_and(|(p, q)| enters(corners, normal, p, q, eps))
        || stands_near(corners, normal, triangle, d, eps);
    touch.then_some(Touch::Contact)
}

/// The segment where a triangle with corner heights `d` crosses the plane, if it does.
fn crossing(triangle: &[Vec3; 3], d: [f32; 3], eps: f32) -> Option<(Vec3, Vec3)> {
    if d.iter().all(|&h| h > eps) {
        return None;
    }
    // The points of the triangle on the plane: corners on it, and edge crossings.
    let mut on: Vec<Vec3> = Vec::with_capacity(3);
    for k in 0..3 {
        let (a, b) = (triangle[k], triangle[(k + 1) % 3]);
        let (da, db) = (d[k], d[(k + 1) % 3]);
        if da.abs() <= eps {
            on.push(a);
        } else if db.abs() > eps && (da > 0.0) != (db > 0.0) {
            on.push(a + (b - a) * (da / (da - db)));
        }
    }
    Some((*on.first()?, *on.last()?))
}

/// Whether the segment p–q (in the polygon's plane) passes through the polygon shrunk by `eps`
/// (Cyrus–Beck clipping against each edge's inward half-plane).
fn enters(corners: &[Vec3], normal: Vec3, p: Vec3, q: Vec3, eps: f32) -> bool {
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for k in 0..corners.len() {
        let (a, b) = (corners[k], corners[(k + 1) % corners.len()]);
        let inward = normal.cross(b - a).normalize_or_zero();
        let (hp, hq) = (inward.dot(p - a) - eps, inward.dot(q - a) - eps);
        if hp < 0.0 && hq < 0.0 {
            return false;
        }
        if hp < 0.0 {
            t0 = t0.max(hp / (hp - hq));
        } else if hq < 0.0 {
            t1 = t1.min(hp / (hp - hq));
        }
    }
    t0 < t1 || (t0 <= t1 && p.distance(q) <= eps)
}

/// A triangle hovering in front of a leaf closer than this fraction of its own size covers it:
/// an emitter a millimetre in front of a wall lights the gap, and the wall's elements that
/// straddle its outline are split like those along a contact line. Relative to the covering
/// triangle, not to the leaf, so the test holds at every level of the refinement.
const COVER: f32 = crate::scene::near_emitters::NEAR;

/// A triangle whose lowest point is closer to a leaf than this fraction of its own size stands
/// *near* it: a block whose bottom edge floats a centimetre over a floor that is not quite flat
/// (modelling tools' output: `scenes/suite/obj-box`) lets light in through the wedge-shaped
/// gap, but little, and the floor's elements straddling its footprint leak like those along a
/// contact line.
const STAND: f32 = 0.05;

/// A standing triangle's footprint must enter a leaf by more than this fraction of the leaf's
/// diameter to count.
const SLIVER: f32 = 0.02;

/// Only a triangle standing steeply on a leaf (the cosine between their planes' normals at
/// most this) parts it into two sides; a surface nearly parallel to the leaf hovers over it and
/// is a cover, within the shorter reach [`COVER`] (a torus lying on a tiled floor: counting its
/// tangent faces as standing near the floor quadrupled the torus's elements).
const STEEP: f32 = 0.5;

/// Whether `triangle` (corner heights `d` over the plane) stands near the polygon ([`STAND`]):
/// one of its edges, clipped to heights between 0 and that reach and projected onto the plane,
/// passes through the polygon's interior. Only the triangle's own edges count, so a wall that
/// meets the floor along the floor's edge and leans a little over it stands near no element
/// but the corner ones.
fn stands_near(
    corners: &[Vec3],
    normal: Vec3,
    triangle: &[Vec3; 3],
    d: [f32; 3],
    eps: f32,
) -> bool {
    let across = (triangle[1] - triangle[0]).cross(triangle[2] - triangle[0]);
    if normal.dot(across.normalize_or_zero()).abs() > STEEP {
        return false;
    }
    let cut = STAND * diameter(triangle);
    let origin = corners[0];
    let flat = |v: Vec3| v - normal * normal.dot(v - origin);
    // A footprint that grazes the leaf's edge parts off a sliver: not worth a split (the
    // walls of the classic Cornell box lean a few millimetres over the ceiling's edge).
    let eps = eps.max(SLIVER * super::face::diameter(corners));
    (0..3).any(|k| {
        let (a, b) = (triangle[k], triangle[(k + 1) % 3]);
        let (da, db) = (d[k], d[(k + 1) % 3]);
        // The part of a→b whose height is within [0, cut], as parameters along it.
        let (t0, t1) = if da == db {
            if !(0.0..=cut).contains(&da) {
                return false;
            }
            (0.0, 1.0)
        } else {
            let (u, v) = (-da / (db - da), (cut - da) / (db - da));
            (u.min(v).max(0.0), u.max(v).min(1.0))
        };
        t0 < t1
            && enters(
                corners,
                normal,
                flat(a + (b - a) * t0),
                flat(a + (b - a) * t1),
                eps,
            )
    })
}

/// Length of a triangle's longest edge.
fn diameter(t: &[Vec3; 3]) -> f32 {
    (0..3)
        .map(|k| t[k].distance(t[(k + 1) % 3]))
        .fold(0.0, f32::max)
}

/// Whether an edge of `triangle` (all in front of the plane, close to it), projected onto the
/// polygon's plane, passes through the polygon's interior.
fn covers_partly(corners: &[Vec3], normal: Vec3, triangle: &[Vec3; 3], eps: f32) -> bool {
    let origin = corners[0];
    let flat = triangle.map(|v| v - normal * normal.dot(v - origin));
    (0..3).any(|k| enters(corners, normal, flat[k], flat[(k + 1) % 3], eps))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> [Vec3; 4] {
        [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ]
    }

    #[test]
    fn wall_standing_inside_crosses_wall_at_the_edge_does_not() {
        let eps = 1e-4;
        // A vertical triangle whose bottom edge lies on the square's interior.
        let inside = [
            Vec3::new(0.2, 0.5, 0.0),
            Vec3::new(0.8, 0.5, 0.0),
            Vec3::new(0.5, 0.5, 1.0),
        ];
        assert_eq!(
            crosses(&square(), Vec3::Z, &inside, eps),
            Some(Touch::Contact)
        );
        // The same along the square's edge y = 0: a corner, not a contact.
        let edge = [
            Vec3::new(0.2, 0.0, 0.0),
            Vec3::new(0.8, 0.0, 0.0),
            Vec3::new(0.5, 0.0, 1.0),
        ];
        assert_eq!(crosses(&square(), Vec3::Z, &edge, eps), None);
        // Coplanar, and wholly above.
        let flat = [Vec3::new(0.5, 0.5, 0.0), Vec3::new(2.0, 0.5, 0.0), Vec3::Y];
        assert_eq!(crosses(&square(), Vec3::Z, &flat, eps), None);
        let above = inside.map(|v| v + Vec3::Z * 0.1);
        assert_eq!(crosses(&square(), Vec3::Z, &above, eps), None);
        // Piercing through the plane, outside the square.
        let outside = [
            Vec3::new(2.0, 0.5, -1.0),
            Vec3::new(3.0, 0.5, -1.0),
            Vec3::new(2.5, 0.5, 1.0),
        ];
        assert_eq!(crosses(&square(), Vec3::Z, &outside, eps), None);
    }

    #[test]
    fn a_wall_floating_just_over_the_square_stands_near_it() {
        let eps = 1e-4;
        // A vertical triangle (diameter about 1.17) whose bottom edge runs 1 cm over the
        // square's interior: within STAND of its size.
        let floating = [
            Vec3::new(0.2, 0.5, 0.01),
            Vec3::new(0.8, 0.5, 0.01),
            Vec3::new(0.5, 0.5, 1.0),
        ];
        assert!(0.01 < STAND * diameter(&floating));
        assert_eq!(
            crosses(&square(), Vec3::Z, &floating, eps),
            Some(Touch::Contact)
        );
        // Tilted so that it crosses the plane beyond the square, yet floats 1 cm over it.
        let tilted = [
            Vec3::new(0.2, 0.5, 0.01),
            Vec3::new(3.0, 0.5, -0.02),
            Vec3::new(0.5, 0.5, 1.0),
        ];
        assert_eq!(
            crosses(&square(), Vec3::Z, &tilted, eps),
            Some(Touch::Contact)
        );
        // Meeting the square along its edge and leaning over it (by 2 mm at the reach): its
        // edges reach the square only where they leave that edge, beyond the square's corners.
        let leaning = [
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.5, 0.002 / (STAND * 3.2), 1.0),
        ];
        assert_eq!(crosses(&square(), Vec3::Z, &leaning, eps), None);
    }

    #[test]
    fn a_triangle_hovering_just_in_front_covers_where_its_outline_crosses() {
        let eps = 1e-4;
        let h = 20.0 * eps;
        // Its edge x = 0.5 runs across the square: the square straddles the outline.
        let half = [
            Vec3::new(0.5, -1.0, h),
            Vec3::new(3.0, 0.5, h),
            Vec3::new(0.5, 2.0, h),
        ];
        assert_eq!(crosses(&square(), Vec3::Z, &half, eps), Some(Touch::Cover));
        // Wholly covering it, or beyond a cover's reach in front of it: no outline crosses (a
        // parallel surface never stands near, however close).
        let all = [
            Vec3::new(-1.0, -1.0, h),
            Vec3::new(4.0, -1.0, h),
            Vec3::new(-1.0, 4.0, h),
        ];
        assert_eq!(crosses(&square(), Vec3::Z, &all, eps), None);
        let far = half.map(|v| v + Vec3::Z * (COVER * diameter(&half)));
        assert_eq!(crosses(&square(), Vec3::Z, &far, eps), None);
    }
}
