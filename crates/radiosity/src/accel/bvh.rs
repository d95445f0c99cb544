//! The bounding-volume hierarchy: construction glue, box queries and invariants (the binned
//! SAH build is in `build`, the node layout in `node`, the ray queries in
//! [`super::traverse`]).
//!
//! Measured against a binary tree with both child boxes in one 64-byte node (Aila & Laine
//! 2009) and a 4-wide tree, 8 wide was fastest on both original benchmark scenes; packets of
//! four with the SAH counting packets made the hierarchy 35 % smaller (89 → 57 bytes per
//! triangle at 1M triangles) and its build 35 % faster, at equal speed on the 1M-triangle
//! scenes and 10–50 % slower on the 54-triangle Cornell box; child boxes quantized to 8 bits
//! then halved the nodes (57 → 50 bytes per triangle) and sped up incoherent rays at 1M
//! triangles (see `benches/README.md`).

use glam::Vec3;

use super::build::{build, Inputs, MAX_DEPTH};
use super::isa::le_mask;
use super::node::{is_leaf, leaf_range, leaf_ref, Aabb, Node, EMPTY_CHILD, MAX_TRIANGLES, WIDTH};
use super::packet::{Tri4, LANES};
use super::pages::{huge_copy, huge_vec};

/// Ray-end lift ([`Bvh::lift`]) as a fraction of the scene's diagonal. A point on a triangle
/// computed in `f32` is off its plane by a few units in the last place of its coordinates
/// (about 10⁻⁷ of the diagonal), so 10⁻⁵ leaves a hundredfold margin against a ray hitting the
/// surface it leaves; larger lifts shorten the narrow gaps light passes through (an emitter 1 mm
/// in front of a wall in a 5.6 m room: at 10⁻⁴ the rays' ends start 0.56 mm into the 1 mm slit
/// and half the light that escapes it was lost, the ceiling −1.9 %).
const LIFT: f32 = 1e-5;

/// Entries of the traversal stack that always suffice: a step pushes at most `WIDTH − 1`, and
/// there are at most [`MAX_DEPTH`] steps down.
pub(super) const DEEP_STACK: usize = (WIDTH - 1) * MAX_DEPTH + 1;
/// Entries of the traversal stack used when the tree needs no more (all trees but adversarial
/// ones): a small stack is cheaper to set up per ray.
pub(super) const SHALLOW_STACK: usize = 64;
/// The same for trees of a few million triangles, whose deepest paths need more than
/// [`SHALLOW_STACK`]: the single-ray walks zero their stack first, and zeroing all of
/// [`DEEP_STACK`] took 7 % of the staircase's hierarchical refinement (perf).
pub(super) const MID_STACK: usize = 128;

/// A triangle as Möller–Trumbore reads it: a vertex and the two edges from it.
#[derive(Clone, Copy, Debug)]
struct Tri {
    v0: Vec3,
    e1: Vec3,
    e2: Vec3,
}

impl Tri {
    fn vertices(&self) -> [Vec3; 3] {
        [self.v0, self.v0 + self.e1, self.v0 + self.e2]
    }
}

/// Original index of a padding lane.
pub(super) const PAD: u32 = u32::MAX;

/// A bounding-volume hierarchy over a triangle soup, for closest-hit and occlusion queries.
///
/// ```
/// use glam::Vec3;
/// use radiosity::accel::{Bvh, Ray};
///
/// let floor = [Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, -1.0), Vec3::new(0.0, 0.0, 1.0)];
/// let bvh = Bvh::build(&[floor]);
/// let down = Ray::new(Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
/// assert_eq!(bvh.closest_hit(&down, f32::INFINITY).map(|h| h.t), Some(2.0));
/// assert!(!bvh.occluded(&down, 1.5));
/// ```
#[derive(Clone, Debug)]
pub struct Bvh {
    pub(super) nodes: Vec<Node>,
    /// The leaves' triangles, in packets of [`LANES`]; a leaf reference names packets.
    pub(super) packets: Vec<Tri4>,
    /// Original index of the triangle in each lane of each packet ([`PAD`] for padding).
    pub(super) ids: Vec<u32>,
    /// Number of input triangles.
    count: usize,
    /// Root reference; meaningless when there are no triangles.
    pub(super) root: u32,
    bounds: Aabb,
    /// Length of the diagonal of `bounds` (0 when empty).
    pub(super) diagonal: f32,
    /// Most stack entries a traversal can need.
    pub(super) stack_need: usize,
}

impl Bvh {
    /// Builds the hierarchy (binned SAH, see [`crate::accel`]). Triangles of zero area are kept
    /// but never hit; a triangle with a non-finite coordinate is treated as a zero-area one at
    /// its first finite vertex (or the origin). Deterministic whatever the thread count.
    ///
    /// # Panics
    /// With 2²⁸ or more triangles (leaf references address 2²⁸; that many triangles would
    /// take 9 GiB before any hierarchy).
    #[must_use]
    pub fn build(triangles: &[[Vec3; 3]]) -> Self {
        assert!(
            triangles.len() < MAX_TRIANGLES,
            "Bvh::build: at most 2^28 triangles"
        );
        let tris: Vec<Tri> = triangles.iter().map(sanitize).collect();
        if tris.is_empty() {
            return Self {
                nodes: Vec::new(),
                packets: Vec::new(),
                ids: Vec::new(),
                count: 0,
                root: 0,
                bounds: Aabb::EMPTY,
                diagonal: 0.0,
                stack_need: 0,
            };
        }
        let boxes: Vec<Aabb> = tris
            .iter()
            .map(|t| Aabb::from_points(&t.vertices()))
            .collect();
        let centroids: Vec<Vec3> = boxes.iter().map(|b| (b.min + b.max) * 0.5).collect();
        let mut built = build(&Inputs {
            boxes: &boxes,
            centroids: &centroids,
        });
        // Leaves name ranges of `order`; pack each into its own packets, in node order, in a
        // buffer on huge pages (`pages`) of the exact size.
        let leaf_packets = |r: u32| leaf_range(r).1.div_ceil(LANES);
        let packet_count = if is_leaf(built.root) {
            leaf_packets(built.root)
        } else {
            built
                .nodes
                .iter()
                .flat_map(|n| n.child)
                .filter(|&c| c != EMPTY_CHILD && is_leaf(c))
                .map(leaf_packets)
                .sum()
        };
        let mut packets = huge_vec(packet_count);
        let mut ids = Vec::with_capacity(packet_count * LANES);
        let mut pack = |r: u32| -> u32 {
            let (first, count) = leaf_range(r);
            let at = packets.len();
            for chunk in built.order[first..first + count].chunks(LANES) {
                let mut packet = Tri4::EMPTY;
                for (lane, &i) in chunk.iter().enumerate() {
                    let t = tris[i as usize];
                    packet.set(lane, t.v0, t.e1, t.e2);
                }
                packets.push(packet);
                ids.extend((0..LANES).map(|lane| chunk.get(lane).copied().unwrap_or(PAD)));
            }
            leaf_ref(at, packets.len() - at)
        };
        let root = if is_leaf(built.root) {
            pack(built.root)
        } else {
            for node in &mut built.nodes {
                for c in &mut node.child {
                    if *c != EMPTY_CHILD && is_leaf(*c) {
                        *c = pack(*c);
                    }
                }
            }
            built.root
        };
        let bvh = Self {
            // The arrays every ray reads, on huge pages where the system allows (`pages`).
            nodes: huge_copy(&built.nodes),
            packets,
            ids,
            count: tris.len(),
            root,
            bounds: built.bounds,
            diagonal: (built.bounds.max - built.bounds.min).length(),
            stack_need: 0,
        };
        let bvh = Self {
            stack_need: bvh.stack_need(bvh.root),
            ..bvh
        };
        debug_assert_eq!(bvh.validate(), Ok(()));
        bvh
    }

    /// Number of triangles the hierarchy was built from.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.count
    }

    /// Bytes the hierarchy holds on the heap: nodes, triangle packets and the original
    /// indices of their lanes (the input triangles are not kept).
    #[must_use]
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of_val(self.nodes.as_slice())
            + std::mem::size_of_val(self.packets.as_slice())
            + std::mem::size_of_val(self.ids.as_slice())
    }

    /// The surface-area-heuristic cost of the wide tree: Σ over the wide nodes of A(node) and
    /// over the leaves of A(leaf) · packets, divided by A(root) — the steps and packet tests of
    /// a ray through the scene box that visits every box it crosses. A comparison of builders
    /// (`cargo xtask traversal-counts`), not a prediction of ray speed.
    #[must_use]
    pub fn sah_cost(&self) -> f64 {
        let root = f64::from(self.bounds.half_area());
        if self.packets.is_empty() || root <= 0.0 {
            return 0.0;
        }
        if is_leaf(self.root) {
            return leaf_range(self.root).1 as f64;
        }
        let mut sum = root;
        for node in &self.nodes {
            for k in 0..WIDTH {
                let c = node.child[k];
                if c == EMPTY_CHILD {
                    continue;
                }
                let area = f64::from(node.half_area(k));
                sum += area
                    * if is_leaf(c) {
                        leaf_range(c).1 as f64
                    } else {
                        1.0
                    };
            }
        }
        sum / root
    }

    /// Box of all triangles ([`Aabb::EMPTY`] when there are none).
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// How far a ray starts (and ends) off the surface it leaves (or aims at), along the
    /// surface's normal, so that it hits neither: [`LIFT`] times the diagonal of
    /// [`Self::bounds`] (1 without triangles).
    #[must_use]
    pub fn lift(&self) -> f32 {
        let diagonal = (self.bounds.max - self.bounds.min).length();
        LIFT * if diagonal.is_finite() && diagonal > 0.0 {
            diagonal
        } else {
            1.0
        }
    }

    /// Most stack entries a traversal from reference `r` can hold: along any path down, the sum
    /// of each node's children less the one visited next.
    fn stack_need(&self, r: u32) -> usize {
        if is_leaf(r) {
            return 0;
        }
        let node = &self.nodes[r as usize];
        let used = node.child.iter().filter(|&&c| c != EMPTY_CHILD).count();
        let below = node
            .child
            .iter()
            .filter(|&&c| !is_leaf(c))
            .map(|&c| self.stack_need(c))
            .max()
            .unwrap_or(0);
        used.saturating_sub(1) + below
    }

    /// Calls `visit` with the original index of every triangle whose box overlaps `query`
    /// (boundaries included), in no particular order: a broad phase for geometric queries.
    pub fn overlapping(&self, query: &Aabb, mut visit: impl FnMut(usize)) {
        if self.packets.is_empty() {
            return;
        }
        let overlaps = |b: &Aabb| query.min.cmple(b.max).all() && b.min.cmple(query.max).all();
        // A node's eight children at once: their planes decoded together, each of the six
        // comparisons one mask (the query's low corner below every child's high planes, and
        // every child's low planes below the query's high corner).
        let low = [query.min.x, query.min.y, query.min.z].map(|x| [x; WIDTH]);
        let high = [query.max.x, query.max.y, query.max.z].map(|x| [x; WIDTH]);
        let mut stack = [0u32; DEEP_STACK];
        stack[0] = self.root;
        let mut depth = 1;
        while depth > 0 {
            depth -= 1;
            let cur = stack[depth];
            if is_leaf(cur) {
                let (first, count) = leaf_range(cur);
                for p in first..first + count {
                    for lane in 0..LANES {
                        let id = self.ids[p * LANES + lane];
                        let tri = self.packets[p].vertices(lane);
                        if id != PAD && overlaps(&Aabb::from_points(&tri)) {
                            visit(id as usize);
                        }
                    }
                }
                continue;
            }
            let node = &self.nodes[cur as usize];
            let planes = node.planes();
            let mut hit = node.children();
            for axis in 0..3 {
                hit &= le_mask(&low[axis], &planes[2 * axis + 1]);
                hit &= le_mask(&planes[2 * axis], &high[axis]);
            }
            while hit != 0 {
                let k = hit.trailing_zeros() as usize;
                hit &= hit - 1;
                stack[depth] = node.child[k];
                depth += 1;
            }
        }
    }

    /// Checks every structural invariant: each triangle inside the boxes on its way down, each node reached
    /// once, leaf ranges in bounds and non-overlapping, every triangle in exactly one lane and
    /// inside its leaf's box, padding lanes of zero area, the depth within the traversal stack,
    /// and the original indices a permutation.
    ///
    /// # Errors
    /// A description of the first violation found.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.count;
        let slots = self.packets.len() * LANES;
        if self.ids.len() != slots {
            return Err(format!("{} ids for {slots} lanes", self.ids.len()));
        }
        let mut seen_id = vec![false; n];
        for (slot, &id) in self.ids.iter().enumerate() {
            if id == PAD {
                if !self.packets[slot / LANES].is_point(slot % LANES) {
                    return Err(format!("padding lane {slot} holds a triangle"));
                }
                continue;
            }
            let seen = seen_id
                .get_mut(id as usize)
                .ok_or(format!("id {id} out of range"))?;
            if std::mem::replace(seen, true) {
                return Err(format!("triangle {id} stored twice"));
            }
        }
        if let Some(id) = seen_id.iter().position(|s| !s) {
            return Err(format!("triangle {id} stored nowhere"));
        }
        if n == 0 {
            return if self.nodes.is_empty() && self.packets.is_empty() {
                Ok(())
            } else {
                Err("nodes without triangles".into())
            };
        }
        let mut covered = vec![false; self.packets.len()];
        let mut visited = vec![false; self.nodes.len()];
        // (reference, box it must lie in, depth)
        let mut todo = vec![(self.root, self.bounds, 1usize)];
        while let Some((r, outer, depth)) = todo.pop() {
            if depth > MAX_DEPTH + 1 {
                return Err(format!("depth {depth} exceeds {MAX_DEPTH} levels"));
            }
            if is_leaf(r) {
                let (first, count) = leaf_range(r);
                if first + count > self.packets.len() {
                    return Err(format!("leaf {first}+{count} beyond the packets"));
                }
                for (p, covered) in covered.iter_mut().enumerate().skip(first).take(count) {
                    if std::mem::replace(covered, true) {
                        return Err(format!("packet {p} in two leaves"));
                    }
                    for lane in 0..LANES {
                        let tri = Aabb::from_points(&self.packets[p].vertices(lane));
                        if self.ids[p * LANES + lane] != PAD && !outer.contains(&tri) {
                            return Err(format!("lane {lane} of packet {p} outside its leaf"));
                        }
                    }
                }
                continue;
            }
            let node = self
                .nodes
                .get(r as usize)
                .ok_or(format!("node {r} out of range"))?;
            if std::mem::replace(&mut visited[r as usize], true) {
                return Err(format!("node {r} reached twice"));
            }
            for k in 0..WIDTH {
                if node.child[k] == EMPTY_CHILD {
                    continue;
                }
                // A quantized box may reach past its parent's by a step; what must hold is
                // that each triangle lies inside every box on its way down.
                let b = node.child_box(k);
                let inner = Aabb {
                    min: outer.min.max(b.min),
                    max: outer.max.min(b.max),
                };
                todo.push((node.child[k], inner, depth + 1));
            }
        }
        if let Some(p) = covered.iter().position(|c| !c) {
            return Err(format!("packet {p} in no leaf"));
        }
        if let Some(i) = visited.iter().position(|v| !v) {
            return Err(format!("node {i} unreachable"));
        }
        let need = self.stack_need(self.root);
        if need != self.stack_need || need > DEEP_STACK {
            return Err(format!("stack need {need} (recorded {})", self.stack_need));
        }
        Ok(())
    }
}

/// A triangle with non-finite coordinates becomes a point (zero area, never hit).
fn sanitize(tri: &[Vec3; 3]) -> Tri {
    let [a, b, c] = *tri;
    if a.is_finite() && b.is_finite() && c.is_finite() {
        Tri {
            v0: a,
            e1: b - a,
            e2: c - a,
        }
    } else {
        let p = [a, b, c]
            .into_iter()
            .find(|v| v.is_finite())
            .unwrap_or(Vec3::ZERO);
        Tri {
            v0: p,
            e1: Vec3::ZERO,
            e2: Vec3::ZERO,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::ray::Ray;
    use super::*;

    #[test]
    fn box_query_finds_exactly_the_overlapping_triangles() {
        let tris: Vec<[Vec3; 3]> = (0..3000u32)
            .map(|i| {
                let h = |k: u32| ((i.wrapping_mul(2_654_435_761) >> k) & 1023) as f32 / 64.0;
                let o = Vec3::new(h(0), h(7), h(13));
                [
                    o,
                    o + Vec3::new(0.3, 0.0, 0.1),
                    o + Vec3::new(0.0, 0.2, 0.4),
                ]
            })
            .collect();
        let bvh = Bvh::build(&tris);
        for (lo, hi) in [(0.0, 3.0), (5.0, 5.5), (15.0, 16.0), (-2.0, -1.0)] {
            let query = Aabb {
                min: Vec3::splat(lo),
                max: Vec3::new(hi, hi + 2.0, hi),
            };
            let mut found = Vec::new();
            bvh.overlapping(&query, |t| found.push(t));
            found.sort_unstable();
            let expected: Vec<usize> = (0..tris.len())
                .filter(|&t| {
                    let b = Aabb::from_points(&tris[t]);
                    query.min.cmple(b.max).all() && b.min.cmple(query.max).all()
                })
                .collect();
            assert_eq!(found, expected);
        }
    }

    #[test]
    fn validate_catches_a_shrunk_box() {
        let tris: Vec<[Vec3; 3]> = (0..40)
            .map(|i| {
                let o = Vec3::new(i as f32, (i * 7 % 5) as f32, 0.0);
                [o, o + Vec3::X, o + Vec3::Y]
            })
            .collect();
        let mut bvh = Bvh::build(&tris);
        assert_eq!(bvh.validate(), Ok(()));
        // Child 0's max x moves to its min x: its triangles stick out.
        bvh.nodes[0].q[1][0] = bvh.nodes[0].q[0][0];
        assert!(bvh.validate().is_err());
    }

    #[test]
    fn non_finite_triangles_are_never_hit() {
        let bad = [Vec3::new(f32::NAN, 0.0, 0.0), Vec3::X, Vec3::Y];
        let good = [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(0.0, 1.0, 1.0),
        ];
        let bvh = Bvh::build(&[bad, good]);
        assert_eq!(bvh.validate(), Ok(()));
        let ray = Ray::new(Vec3::new(0.2, 0.2, -1.0), Vec3::Z);
        let hit = bvh.closest_hit(&ray, f32::INFINITY).unwrap();
        assert_eq!((hit.triangle, hit.t), (1, 2.0));
    }
}
