//! The bounding-volume hierarchy and its two queries.
//!
//! Layout: an 8-wide tree (Wald et al. 2008; Embree's BVH8) whose nodes hold the boxes of their
//! eight children in structure-of-arrays form, `bounds[plane][child]`, so the eight slab tests
//! of a traversal step are lane-parallel arithmetic that LLVM turns into packed SSE
//! (`minps`/`maxps`/`mulps`). A node is 256 bytes, four adjacent cache lines; the tree is a
//! third as deep as a binary one, and on large scenes, where every node visited is a likely
//! cache miss, depth is what costs. Nodes are stored depth-first, so a first child follows its parent.
//! A child reference is a node index, or — top bit set — a leaf: `LEAF | first << 3 |
//! (count − 1)` naming up to [`MAX_LEAF`] consecutive triangles of the re-ordered triangle
//! array, which holds a vertex and the two edges of each (what Möller–Trumbore needs) in leaf
//! order. Unused child slots have an inverted (empty) box, which no slab test accepts.
//!
//! Measured against a binary tree with both child boxes in one 64-byte node (Aila & Laine
//! 2009) and a 4-wide tree, 8 wide was fastest on both benchmark scenes: see
//! `benches/README.md`.
//!
//! Traversal is ordered: of the children whose box is hit, the best is visited next and the
//! others are pushed, the next-best last:
//! - closest hit: nearest entry distance first (leaves included), and a popped entry is skipped
//!   when a closer hit has been found since;
//! - occlusion: leaf children are tested at once (cheap, and the large triangles of shallow
//!   leaves are the likeliest blockers), interior children largest box first. Any hit ends the query, and the chance that a random ray
//!   crossing a box hits something in it grows with the box's area (the surface-area order of
//!   Ize & Hansen 2011, "RTSAH traversal order for occlusion rays"); measured 6× faster than
//!   nearest-first on the 1M-triangle benchmark, whose closed room puts large walls high in
//!   the tree.
//!
//! The slab test (Kay & Kajiya 1986) reads each axis' near and far planes by the
//! sign of the direction, and widens the far distance by 1 + 2γ₃ (Ize 2013, "Robust BVH ray
//! traversal") so rounding never loses a triangle that lies on a box face. A zero direction
//! component is replaced by ±10⁻²⁰ (keeping its sign), so 1/d is finite and no 0·∞ appears.

use glam::Vec3;

use super::build::{build, Inputs, MAX_DEPTH};
use super::ray::{intersect, Hit, Ray};

/// Most triangles in one leaf (the leaf reference stores count − 1 in three bits).
pub(super) const MAX_LEAF: usize = 8;
/// Children per node.
pub(super) const WIDTH: usize = 8;
/// Entries of the traversal stack that always suffice: a step pushes at most `WIDTH − 1`, and
/// there are at most [`MAX_DEPTH`] steps down.
const DEEP_STACK: usize = (WIDTH - 1) * MAX_DEPTH + 1;
/// Entries of the traversal stack used when the tree needs no more (all trees but adversarial
/// ones): a small stack is cheaper to set up per ray.
const SHALLOW_STACK: usize = 64;
/// Reference in an unused child slot.
pub(super) const EMPTY_CHILD: u32 = u32::MAX;
/// Leaf bit of a child reference.
const LEAF: u32 = 1 << 31;
/// Largest triangle count a leaf reference can address.
const MAX_TRIANGLES: usize = 1 << 28;
/// 1 + 2γ₃ with γₙ = nε/(1 − nε), ε = 2⁻²⁴ (Pharr et al., PBRT 3rd ed., §3.9).
const ROBUST_FAR: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// An axis-aligned box; `EMPTY` has min = +∞, max = −∞.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box containing nothing: the identity of [`Aabb::union`].
    pub const EMPTY: Self = Self {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };

    /// The box of some points.
    #[must_use]
    pub fn from_points(points: &[Vec3]) -> Self {
        points.iter().copied().collect()
    }

    /// The smallest box containing both.
    #[must_use]
    pub fn union(&self, other: &Self) -> Self {
        Self {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Whether `other` lies inside this box (boundary included).
    #[must_use]
    pub fn contains(&self, other: &Self) -> bool {
        self.min.cmple(other.min).all() && other.max.cmple(self.max).all()
    }

    /// Half the surface area, the SAH's measure; 0 for an empty box.
    #[must_use]
    pub fn half_area(&self) -> f32 {
        let d = (self.max - self.min).max(Vec3::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
}

/// The box of the points an iterator yields ([`Aabb::EMPTY`] for none).
impl FromIterator<Vec3> for Aabb {
    fn from_iter<I: IntoIterator<Item = Vec3>>(points: I) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| Self {
            min: b.min.min(p),
            max: b.max.max(p),
        })
    }
}

/// A node: the boxes of its children as `bounds[plane][child]`, planes in the order
/// min x, max x, min y, max y, min z, max z, and the child references.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct Node {
    bounds: [[f32; WIDTH]; 6],
    child: [u32; WIDTH],
}

impl Node {
    /// A node with children boxes `boxes` and references `child`; slots past them are empty.
    pub(super) fn new(boxes: &[Aabb], child: &[u32]) -> Self {
        let mut bounds = [[0.0; WIDTH]; 6];
        let mut refs = [EMPTY_CHILD; WIDTH];
        for k in 0..WIDTH {
            let b = boxes.get(k).copied().unwrap_or(Aabb::EMPTY);
            for axis in 0..3 {
                bounds[2 * axis][k] = b.min[axis];
                bounds[2 * axis + 1][k] = b.max[axis];
            }
            refs[k] = child.get(k).copied().unwrap_or(EMPTY_CHILD);
        }
        Self {
            bounds,
            child: refs,
        }
    }

    /// Box of child `k`.
    fn child_box(&self, k: usize) -> Aabb {
        let b = &self.bounds;
        Aabb {
            min: Vec3::new(b[0][k], b[2][k], b[4][k]),
            max: Vec3::new(b[1][k], b[3][k], b[5][k]),
        }
    }
}

/// Whether a child reference names a leaf.
pub(super) fn is_leaf(child: u32) -> bool {
    child & LEAF != 0
}

/// The reference of a leaf of `count` (1..=[`MAX_LEAF`]) triangles from position `first`.
pub(super) fn leaf_ref(first: usize, count: usize) -> u32 {
    debug_assert!((1..=MAX_LEAF).contains(&count) && first + count <= MAX_TRIANGLES);
    LEAF | ((first as u32) << 3) | (count as u32 - 1)
}

/// First position and count of a leaf reference.
fn leaf_range(child: u32) -> (usize, usize) {
    (((child & !LEAF) >> 3) as usize, (child & 7) as usize + 1)
}

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
    nodes: Vec<Node>,
    tris: Vec<Tri>,
    /// Original index of each re-ordered triangle.
    ids: Vec<u32>,
    /// Root reference; meaningless when there are no triangles.
    root: u32,
    bounds: Aabb,
    /// Most stack entries a traversal can need.
    stack_need: usize,
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
                tris,
                ids: Vec::new(),
                root: 0,
                bounds: Aabb::EMPTY,
                stack_need: 0,
            };
        }
        let boxes: Vec<Aabb> = tris
            .iter()
            .map(|t| Aabb::from_points(&t.vertices()))
            .collect();
        let centroids: Vec<Vec3> = boxes.iter().map(|b| (b.min + b.max) * 0.5).collect();
        let built = build(&Inputs {
            boxes: &boxes,
            centroids: &centroids,
        });
        let bvh = Self {
            nodes: built.nodes,
            tris: built.order.iter().map(|&i| tris[i as usize]).collect(),
            ids: built.order,
            root: built.root,
            bounds: built.bounds,
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
        self.tris.len()
    }

    /// Box of all triangles ([`Aabb::EMPTY`] when there are none).
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The nearest hit with t in (0, `t_max`), if any.
    #[must_use]
    pub fn closest_hit(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        if self.stack_need <= SHALLOW_STACK {
            self.traverse::<false, SHALLOW_STACK>(ray, t_max)
        } else {
            self.traverse::<false, DEEP_STACK>(ray, t_max)
        }
    }

    /// Whether anything is hit with t in (0, `t_max`) (stops at the first hit found).
    #[must_use]
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        if self.stack_need <= SHALLOW_STACK {
            self.traverse::<true, SHALLOW_STACK>(ray, t_max).is_some()
        } else {
            self.traverse::<true, DEEP_STACK>(ray, t_max).is_some()
        }
    }

    /// Ordered traversal; with `ANY` it returns the first hit found instead of the nearest.
    #[inline(always)]
    fn traverse<const ANY: bool, const STACK: usize>(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        if self.tris.is_empty() {
            return None;
        }
        let o = ray.origin;
        let d = ray.dir;
        // Per-ray slab set-up: finite reciprocal direction, and near planes by its sign.
        let safe = |x: f32| {
            if x.abs() < 1e-20 {
                1e-20f32.copysign(x)
            } else {
                x
            }
        };
        let inv = Vec3::new(1.0 / safe(d.x), 1.0 / safe(d.y), 1.0 / safe(d.z));
        let nx = usize::from(inv.x < 0.0);
        let ny = 2 + usize::from(inv.y < 0.0);
        let nz = 4 + usize::from(inv.z < 0.0);
        let (fx, fy, fz) = (1 - nx, 5 - ny, 9 - nz);

        let mut best_t = t_max;
        let mut best: Option<(usize, f32, f32)> = None;
        let mut stack = [(0u32, 0f32); STACK];
        let mut sp = 0usize;
        let mut cur = self.root;
        loop {
            if is_leaf(cur) {
                if self.leaf::<ANY>(cur, o, d, &mut best_t, &mut best) && ANY {
                    return self.hit(best, best_t);
                }
            } else {
                let node = &self.nodes[cur as usize];
                let b = &node.bounds;
                // Slab tests of all children, lane by lane.
                let mut near = [0f32; WIDTH];
                let mut far = [0f32; WIDTH];
                for k in 0..WIDTH {
                    let tx0 = (b[nx][k] - o.x) * inv.x;
                    let ty0 = (b[ny][k] - o.y) * inv.y;
                    let tz0 = (b[nz][k] - o.z) * inv.z;
                    let tx1 = (b[fx][k] - o.x) * inv.x;
                    let ty1 = (b[fy][k] - o.y) * inv.y;
                    let tz1 = (b[fz][k] - o.z) * inv.z;
                    near[k] = max(max(tx0, ty0), max(tz0, 0.0));
                    far[k] = min(min(tx1, ty1), min(tz1, best_t)) * ROBUST_FAR;
                }
                // Gather the children hit with their sort key: entry distance for closest
                // hits; for occlusion leaves are tested at once and interior children keyed
                // by minus their half area.
                let mut todo = [(0u32, 0f32); WIDTH];
                let mut n = 0;
                for k in 0..WIDTH {
                    if near[k] <= far[k] {
                        let c = node.child[k];
                        let key = if !ANY {
                            near[k]
                        } else if is_leaf(c) {
                            if self.leaf::<ANY>(c, o, d, &mut best_t, &mut best) {
                                return self.hit(best, best_t);
                            }
                            continue;
                        } else {
                            let dx = b[1][k] - b[0][k];
                            let dy = b[3][k] - b[2][k];
                            let dz = b[5][k] - b[4][k];
                            -(dx * dy + dy * dz + dz * dx)
                        };
                        todo[n] = (c, key);
                        n += 1;
                    }
                }
                if n > 0 {
                    // Sort worst first (insertion sort of at most eight), push all but the
                    // best, go on with it.
                    for i in 1..n {
                        let mut j = i;
                        while j > 0 && todo[j - 1].1 < todo[j].1 {
                            todo.swap(j - 1, j);
                            j -= 1;
                        }
                    }
                    stack[sp..sp + n - 1].copy_from_slice(&todo[..n - 1]);
                    sp += n - 1;
                    cur = todo[n - 1].0;
                    continue;
                }
            }
            // Pop the next subtree that may still hold a closer hit.
            loop {
                if sp == 0 {
                    return self.hit(best, best_t);
                }
                sp -= 1;
                let (next, t) = stack[sp];
                if ANY || t <= best_t {
                    cur = next;
                    break;
                }
            }
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

    /// Tests the triangles of leaf `r`, keeping the nearest hit below `best_t`; with `ANY`
    /// stops at the first. Returns whether anything was hit.
    #[inline(always)]
    fn leaf<const ANY: bool>(
        &self,
        r: u32,
        o: Vec3,
        d: Vec3,
        best_t: &mut f32,
        best: &mut Option<(usize, f32, f32)>,
    ) -> bool {
        let (first, count) = leaf_range(r);
        let mut found = false;
        for (k, tri) in self.tris[first..first + count].iter().enumerate() {
            if let Some((t, u, v)) = intersect(o, d, tri.v0, tri.e1, tri.e2, *best_t) {
                *best_t = t;
                *best = Some((first + k, u, v));
                found = true;
                if ANY {
                    break;
                }
            }
        }
        found
    }

    fn hit(&self, best: Option<(usize, f32, f32)>, t: f32) -> Option<Hit> {
        best.map(|(i, u, v)| Hit {
            t,
            triangle: self.ids[i],
            u,
            v,
        })
    }

    /// Calls `visit` with the original index of every triangle whose box overlaps `query`
    /// (boundaries included), in no particular order: a broad phase for geometric queries.
    pub fn overlapping(&self, query: &Aabb, mut visit: impl FnMut(usize)) {
        if self.tris.is_empty() {
            return;
        }
        let overlaps = |b: &Aabb| query.min.cmple(b.max).all() && b.min.cmple(query.max).all();
        let mut stack = vec![self.root];
        while let Some(cur) = stack.pop() {
            if is_leaf(cur) {
                let (first, count) = leaf_range(cur);
                for k in first..first + count {
                    if overlaps(&Aabb::from_points(&self.tris[k].vertices())) {
                        visit(self.ids[k] as usize);
                    }
                }
                continue;
            }
            let node = &self.nodes[cur as usize];
            for k in 0..WIDTH {
                if node.child[k] != EMPTY_CHILD && overlaps(&node.child_box(k)) {
                    stack.push(node.child[k]);
                }
            }
        }
    }

    /// Checks every structural invariant: child boxes inside their parent's, each node reached
    /// once, leaf ranges in bounds and non-overlapping, every triangle referenced exactly once
    /// and inside its leaf's box, the depth within the traversal stack, and the original
    /// indices a permutation.
    ///
    /// # Errors
    /// A description of the first violation found.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.tris.len();
        if self.ids.len() != n {
            return Err(format!("{} ids for {n} triangles", self.ids.len()));
        }
        let mut seen_id = vec![false; n];
        for &id in &self.ids {
            let slot = seen_id
                .get_mut(id as usize)
                .ok_or(format!("id {id} out of range"))?;
            if std::mem::replace(slot, true) {
                return Err(format!("triangle {id} stored twice"));
            }
        }
        if n == 0 {
            return if self.nodes.is_empty() {
                Ok(())
            } else {
                Err("nodes without triangles".into())
            };
        }
        let mut covered = vec![false; n];
        let mut visited = vec![false; self.nodes.len()];
        // (reference, box it must lie in, depth)
        let mut todo = vec![(self.root, self.bounds, 1usize)];
        while let Some((r, outer, depth)) = todo.pop() {
            if depth > MAX_DEPTH + 1 {
                return Err(format!("depth {depth} exceeds {MAX_DEPTH} levels"));
            }
            if !is_leaf(r) && r as usize >= self.nodes.len() {
                return Err(format!("node {r} out of range"));
            }
            if is_leaf(r) {
                let (first, count) = leaf_range(r);
                if first + count > n {
                    return Err(format!("leaf {first}+{count} beyond {n} triangles"));
                }
                for (i, c) in covered.iter_mut().enumerate().skip(first).take(count) {
                    if std::mem::replace(c, true) {
                        return Err(format!("triangle slot {i} in two leaves"));
                    }
                    if !outer.contains(&Aabb::from_points(&self.tris[i].vertices())) {
                        return Err(format!("triangle slot {i} outside its leaf box"));
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
                let b = node.child_box(k);
                if !outer.contains(&b) {
                    return Err(format!("child {k} of node {r} outside its parent box"));
                }
                todo.push((node.child[k], b, depth + 1));
            }
        }
        if let Some(i) = covered.iter().position(|c| !c) {
            return Err(format!("triangle slot {i} in no leaf"));
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

/// `a < b ? a : b`: one `minss`, unlike `f32::min`'s NaN handling.
#[inline(always)]
fn min(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// `a > b ? a : b`: one `maxss`.
#[inline(always)]
fn max(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
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
    use super::*;

    #[test]
    fn node_is_four_cache_lines() {
        assert_eq!(std::mem::size_of::<Node>(), 256);
    }

    #[test]
    fn leaf_reference_round_trips() {
        for (first, count) in [(0, 1), (5, 8), (MAX_TRIANGLES - 8, 8)] {
            let r = leaf_ref(first, count);
            assert!(is_leaf(r));
            assert_ne!(r, EMPTY_CHILD);
            assert_eq!(leaf_range(r), (first, count));
        }
    }

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
        bvh.nodes[0].bounds[1][0] -= 0.5;
        assert!(bvh.validate().is_err());
    }

    #[test]
    fn deep_and_shallow_stacks_agree() {
        // Triangles on a helix: a tree that needs a few stack entries but far fewer than 64.
        let tris: Vec<[Vec3; 3]> = (0..2000)
            .map(|i| {
                let a = i as f32 * 0.05;
                let o = Vec3::new(a.cos() * 3.0, i as f32 * 0.01, a.sin() * 3.0);
                [
                    o,
                    o + Vec3::new(0.2, 0.0, 0.0),
                    o + Vec3::new(0.0, 0.2, 0.1),
                ]
            })
            .collect();
        let bvh = Bvh::build(&tris);
        assert!(bvh.stack_need > 0 && bvh.stack_need <= SHALLOW_STACK);
        for i in 0..500 {
            let a = i as f32 * 0.37;
            let ray = Ray::new(
                Vec3::new(0.0, i as f32 * 0.04, 0.0),
                Vec3::new(a.cos(), (a * 3.0).sin() * 0.3, a.sin()),
            );
            assert_eq!(
                bvh.traverse::<false, SHALLOW_STACK>(&ray, f32::INFINITY),
                bvh.traverse::<false, DEEP_STACK>(&ray, f32::INFINITY)
            );
            assert_eq!(
                bvh.traverse::<true, SHALLOW_STACK>(&ray, 2.0).is_some(),
                bvh.traverse::<true, DEEP_STACK>(&ray, 2.0).is_some()
            );
        }
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
