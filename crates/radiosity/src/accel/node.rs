//! The layout of the hierarchy's nodes, shared by its construction ([`super::build`]), the
//! [`super::Bvh`] that owns them and the queries ([`super::traverse`]).
//!
//! An 8-wide tree (Wald et al. 2008; Embree's BVH8) whose nodes hold the boxes of their
//! eight children in structure-of-arrays form, `bounds[plane][child]`, so the eight slab tests
//! of a traversal step are lane-parallel arithmetic that LLVM turns into packed SSE
//! (`minps`/`maxps`/`mulps`). A node is 256 bytes, four adjacent cache lines; the tree is a
//! third as deep as a binary one, and on large scenes, where every node visited is a likely
//! cache miss, depth is what costs. Nodes are stored depth-first, so a first child follows its
//! parent. A child reference is a node index, or — top bit set — a leaf: `LEAF | first << 3 |
//! (count − 1)` naming `count` consecutive packets of four triangles ([`super::packet`]),
//! which hold a vertex and the two edges of each (what Möller–Trumbore needs); a leaf holds up
//! to [`MAX_LEAF`] triangles, so one or two packets, and `ids` gives the original index of
//! each lane (padding lanes hold zero-area triangles and [`PAD`](super::bvh::PAD)). Unused child slots have an
//! inverted (empty) box, which no slab test accepts.
//!
//! The slab test (Kay & Kajiya 1986) reads each axis' near and far planes by the
//! sign of the direction, and widens the far distance by 1 + 2γ₃ (Ize 2013, "Robust BVH ray
//! traversal") so rounding never loses a triangle that lies on a box face. A zero direction
//! component is replaced by ±10⁻²⁰ (keeping its sign), so 1/d is finite and no 0·∞ appears.

use glam::Vec3;

/// Most triangles in one leaf: two packets (the leaf reference could name eight).
pub(super) const MAX_LEAF: usize = 8;
/// Children per node.
pub(super) const WIDTH: usize = 8;
/// Reference in an unused child slot.
pub(super) const EMPTY_CHILD: u32 = u32::MAX;
/// Leaf bit of a child reference.
const LEAF: u32 = 1 << 31;
/// Largest triangle count a leaf reference can address.
pub(super) const MAX_TRIANGLES: usize = 1 << 28;
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
    pub(super) bounds: [[f32; WIDTH]; 6],
    pub(super) child: [u32; WIDTH],
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

    /// Slab tests of all children against the ray o + t·d with t in (0, `t_max`), lane by
    /// lane: the entry distance of each child and the mask of the children hit.
    /// `inv` is 1/d made finite and `near` the index of each axis' near plane.
    #[inline(always)]
    pub(super) fn slabs(
        &self,
        o: Vec3,
        inv: Vec3,
        near: [usize; 3],
        t_max: f32,
    ) -> ([f32; WIDTH], u32) {
        let b = &self.bounds;
        let [nx, ny, nz] = near;
        let (fx, fy, fz) = (1 - nx, 5 - ny, 9 - nz);
        let mut entry = [0f32; WIDTH];
        let mut exit = [0f32; WIDTH];
        for k in 0..WIDTH {
            let tx0 = (b[nx][k] - o.x) * inv.x;
            let ty0 = (b[ny][k] - o.y) * inv.y;
            let tz0 = (b[nz][k] - o.z) * inv.z;
            let tx1 = (b[fx][k] - o.x) * inv.x;
            let ty1 = (b[fy][k] - o.y) * inv.y;
            let tz1 = (b[fz][k] - o.z) * inv.z;
            entry[k] = max(max(tx0, ty0), max(tz0, 0.0));
            exit[k] = min(min(tx1, ty1), min(tz1, t_max)) * ROBUST_FAR;
        }
        let mut mask = 0u32;
        for k in 0..WIDTH {
            mask |= u32::from(entry[k] <= exit[k]) << k;
        }
        (entry, mask)
    }

    /// Box of child `k`.
    pub(super) fn child_box(&self, k: usize) -> Aabb {
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
pub(super) fn leaf_range(child: u32) -> (usize, usize) {
    (((child & !LEAF) >> 3) as usize, (child & 7) as usize + 1)
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
}
