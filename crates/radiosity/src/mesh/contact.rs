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
//! size, the distance at which [`crate::scene::facing_emitters`] warns) touches it where its
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
use rayon::prelude::*;

use super::ELEMENT_BATCH;
use super::{Mesh, Node, MAX_LEVEL};
use crate::accel::{Aabb, BoxTree};
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

/// The search around a leaf reaches at most this many of its diameters: a triangle's
/// [`STAND`] reach grows with its size (20 cm for a wall 4 m across), and a leaf far smaller
/// than that distance (a detail of a fine mesh under the wall's edge) is not split for it. The
/// cap first bounded the search, when one reach for all (the largest triangle's) made every
/// small leaf of a million-triangle scene test thousands of triangles (`cargo xtask
/// bench --suite hierarchical`, the 1 024 002-triangle field: 312 s); the triangles' own reaches
/// ([`Mesh::contact_reaches`]) bound it now, and the cap keeps the meshes as they were.
const QUERY_DIAMETERS: f32 = 8.0;

/// Relative tolerance of the contact test, as a fraction of the leaf's diameter.
const TOLERANCE: f32 = 1e-4;

impl Mesh {
    /// Splits every element that another polygon's triangle crosses (see the module docs), and
    /// its crossed children, down to [`CONTACT_LEVELS`] more levels ([`COVER_LEVELS`] under a
    /// hovering outline; never below [`MAX_LEVEL`]). Gives up, leaving the mesh valid but
    /// unfinished, once `stop` returns true. Reports the elements tested to `progress`.
    pub fn refine_contacts(&mut self, stop: &(dyn Fn() -> bool + Sync), progress: &dyn Progress) {
        if self.triangles.is_empty() {
            return;
        }
        let reaches = self.contact_reaches();
        let cap = self
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
                .par_iter()
                .copied()
                .filter(|&(n, done)| {
                    tested.one();
                    self.nodes[n as usize].level < MAX_LEVEL
                        && !stop()
                        && done < self.touched(&reaches, cap, &lights, n, done)
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

    /// The triangles' boxes, each grown by the farthest a triangle touches a leaf from: the
    /// larger of [`STAND`] and [`COVER`] of its size. A leaf's candidates are the triangles
    /// whose grown box meets its own: a few neighbours in a dense mesh, where a search of
    /// the leaf's surroundings by one reach for all met hundreds (`veach-ajar` of the corpus,
    /// 256 566 polygons: 70 s, 90 % of it in that search).
    fn contact_reaches(&self) -> BoxTree {
        let boxes: Vec<Aabb> = self
            .triangles
            .iter()
            .map(|t| grown(Aabb::from_points(t), STAND.max(COVER) * diameter(t)))
            .collect();
        BoxTree::build(&boxes)
    }

    /// Calls `visit` with every triangle of another polygon than node `n`'s whose reach
    /// ([`Mesh::contact_reaches`]) meets the node's bounds grown by its [`tolerance`], and
    /// whose bounds lie within `cap` of them, or [`QUERY_DIAMETERS`] of the node's size if less:
    /// every triangle that can touch the node ([`crosses`]) within that distance.
    fn contact_candidates(
        &self,
        reaches: &BoxTree,
        cap: f32,
        n: u32,
        mut visit: impl FnMut(usize),
    ) {
        let node = &self.nodes[n as usize];
        let own = self.patches[node.patch as usize].polygon;
        let eps = tolerance(node);
        let bounds = Aabb::from_points(node.face.corners());
        let near = grown(bounds, cap.min(QUERY_DIAMETERS * node.diameter()).max(eps));
        reaches.overlapping(&grown(bounds, eps), |t| {
            let b = Aabb::from_points(&self.triangles[t]);
            let within = near.min.cmple(b.max).all() && b.min.cmple(near.max).all();
            if within && self.triangle_polygon[t] != own {
                visit(t);
            }
        });
    }

    /// How many levels node `n` wants added: [`COVER_LEVELS`] if a triangle of an emitting
    /// polygon facing it covers it partly from in front, [`CONTACT_LEVELS`] if another
    /// polygon's triangle crosses its face through the interior or covers it, 0 otherwise
    /// (among the [candidates](Mesh::contact_candidates) within `cap`). Stops looking once the
    /// answer exceeds `done`. `lights[p]` is the front normal of polygon `p` if it emits.
    fn touched(
        &self,
        reaches: &BoxTree,
        cap: f32,
        lights: &[Option<Vec3>],
        n: u32,
        done: u8,
    ) -> u8 {
        let node = &self.nodes[n as usize];
        let patch = &self.patches[node.patch as usize];
        let corners = node.face.corners();
        let eps = tolerance(node);
        let mut wanted = 0;
        self.contact_candidates(reaches, cap, n, |t| {
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

/// The contact test's tolerance for a node: relative to its size ([`TOLERANCE`]), and never
/// below what f32 coordinates can resolve.
fn tolerance(node: &Node) -> f32 {
    let magnitude = node
        .face
        .corners()
        .iter()
        .map(|c| c.abs().max_element())
        .fold(0.0, f32::max);
    (TOLERANCE * node.diameter()).max(8.0 * f32::EPSILON * magnitude)
}

/// `b` grown by `r` on every side.
fn grown(b: Aabb, r: f32) -> Aabb {
    Aabb {
        min: b.min - Vec3::splat(r),
        max: b.max + Vec3::splat(r),
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
const COVER: f32 = crate::scene::facing_emitters::NEAR;

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
    use crate::mesh::Subdivision;
    use crate::scene::{Material, Object, Polygon};
    use crate::Scene;

    /// A scene of the given polygons, one object, one two-sided material.
    fn scene(polygons: Vec<Vec<Vec3>>) -> Scene {
        Scene {
            materials: vec![Material {
                two_sided: true,
                ..Material::default()
            }],
            objects: vec![Object { name: "all".into() }],
            polygons: polygons
                .into_iter()
                .map(|vertices| Polygon {
                    vertices,
                    material: 0,
                    object: 0,
                    uv: None,
                })
                .collect(),
            ..Scene::default()
        }
    }

    /// The unit square in the plane z = 0 tiled by `n` × `n` squares, each its own polygon (as
    /// a mesh read from PLY or OBJ comes, a polygon per face).
    fn tiles(n: usize) -> Vec<Vec<Vec3>> {
        let step = 1.0 / n as f32;
        let at = |i: usize, j: usize| Vec3::new(i as f32 * step, j as f32 * step, 0.0);
        (0..n * n)
            .map(|k| {
                let (i, j) = (k % n, k / n);
                vec![at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]
            })
            .collect()
    }

    #[test]
    fn a_leaf_of_a_dense_mesh_tests_only_its_neighbours() {
        // Tiles of a fine mesh, and a wall of 10 × 10 far off whose STAND reach (0.7) spans
        // eleven tiles: each tile is tested against its eight neighbours' two triangles each,
        // however fine the tiling (one reach for all, capped at eight tile diameters, tested
        // about 23² tiles' triangles).
        for n in [16, 64] {
            let mut polygons = tiles(n);
            polygons.push(vec![
                Vec3::new(50.0, 0.0, 0.0),
                Vec3::new(60.0, 0.0, 0.0),
                Vec3::new(60.0, 0.0, 10.0),
                Vec3::new(50.0, 0.0, 10.0),
            ]);
            let mesh = Mesh::build(&scene(polygons), Subdivision::MaxArea(f64::INFINITY));
            let reaches = mesh.contact_reaches();
            let most = mesh
                .elements
                .iter()
                .map(|&e| {
                    let mut tested = 0;
                    mesh.contact_candidates(&reaches, f32::INFINITY, e, |_| tested += 1);
                    tested
                })
                .max();
            assert_eq!(most, Some(8 * 2), "{n} × {n} tiles");
        }
    }

    #[test]
    fn a_fine_mesh_standing_on_a_floor_splits_it_along_the_contact_line() {
        // A vertical strip tiled by 32 × 32 small squares (each its own polygon) stands across
        // a floor of 4 × 4, off the floor's dyadic grid: the floor's elements that its
        // footprint crosses go CONTACT_LEVELS deeper, though every triangle of the strip is a
        // thousand times smaller than a floor element.
        let floor = vec![
            Vec3::new(-2.0, -2.0, 0.0),
            Vec3::new(2.0, -2.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
            Vec3::new(-2.0, 2.0, 0.0),
        ];
        let strip = tiles(32)
            .into_iter()
            .map(|tile| {
                let stand = |v: Vec3| Vec3::new(v.x - 0.4321, 0.3456, v.y - 0.01);
                tile.into_iter().map(stand).collect()
            })
            .collect::<Vec<_>>();
        let mut polygons = vec![floor];
        polygons.extend(strip);
        let mesh = Mesh::build(&scene(polygons), Subdivision::MaxArea(0.3));
        let floor: Vec<&Node> = mesh.nodes[mesh.roots[0].start as usize]
            .elements
            .clone()
            .map(|e| mesh.element(e as usize))
            .collect();
        let levels = |f: &dyn Fn(&Node) -> bool| {
            let mut l: Vec<u8> = floor.iter().filter(|n| f(n)).map(|n| n.level).collect();
            l.dedup();
            l
        };
        // Elements the footprint (y = 0.3456, −0.4321 < x < 0.5679) runs through, and the rest.
        let crossed = |n: &Node| {
            let c = n.face.corners();
            let (lo, hi) = c
                .iter()
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), &p| {
                    (a.min(p), b.max(p))
                });
            lo.y < 0.3456 && 0.3456 < hi.y && lo.x < 0.5679 && -0.4321 < hi.x
        };
        let (uniform, deep) = (levels(&|n| !crossed(n)), levels(&crossed));
        assert_eq!(deep.len(), 1, "{deep:?}");
        assert!(
            uniform.contains(&(deep[0] - CONTACT_LEVELS)),
            "{uniform:?} {deep:?}"
        );
        mesh.validate().unwrap();
    }

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
