//! The layout of the hierarchy's nodes, shared by its construction ([`super::build`]), the
//! [`super::Bvh`] that owns them and the queries ([`super::traverse`]).
//!
//! An 8-wide tree (Wald et al. 2008; Embree's BVH8) whose nodes hold the boxes of their
//! eight children in structure-of-arrays form, `q[plane][child]` (quantized to 8 bits, see
//! [`Node`]), so the eight slab tests of a traversal step are lane-parallel arithmetic that
//! LLVM turns into packed SSE or AVX (`minps`/`maxps`/`mulps`). A node is 128 bytes, two adjacent cache lines; the tree is a
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

use super::isa::le_mask;

/// Most triangles in one leaf: two packets (the leaf reference could name eight).
pub(super) const MAX_LEAF: usize = 8;
/// Children per node.
pub(super) const WIDTH: usize = 8;
/// Rays of a packet ([`super::coherent`]) tested together against one child box.
pub(super) const RAYS: usize = 8;
/// A node's children's planes, `[plane][child]` (see [`Node::planes`]).
pub(super) type Planes = [[f32; WIDTH]; 6];
/// Reference in an unused child slot.
pub(super) const EMPTY_CHILD: u32 = u32::MAX;
/// Leaf bit of a child reference.
const LEAF: u32 = 1 << 31;
/// Largest triangle count a leaf reference can address.
pub(super) const MAX_TRIANGLES: usize = 1 << 28;
/// 1 + 2γ₃ with γₙ = nε/(1 − nε), ε = 2⁻²⁴ (Pharr et al., PBRT 3rd ed., §3.9).
pub(super) const ROBUST_FAR: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

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

/// The index of `v`'s largest coordinate (the first of equals): the axis of a box's widest
/// extent, given that extent.
#[must_use]
pub fn largest_axis(v: Vec3) -> usize {
    if v.x >= v.y && v.x >= v.z {
        0
    } else if v.y >= v.z {
        1
    } else {
        2
    }
}

/// A node: the boxes of its children quantized to 8 bits in the frame of the node's own box
/// (Ylitie et al. 2017, "Efficient incoherent ray traversal on GPUs through compressed wide
/// BVHs"; Embree's `QBVH8`), and the child references.
///
/// On axis a, plane value q of a child stands for `origin[a] + q · step[a]` computed in `f32`,
/// `step[a]` a power of two (so `q · step` is exact and the sum is one rounding), and the
/// builder picks for each child the largest such value ≤ its box's min and the smallest ≥ its
/// max, checked in that very `f32` arithmetic: a quantized box contains the child's box, and
/// the slab test runs on exact `f32` planes as before, so its rounding bound holds unchanged.
/// Boxes grow by at most one step (1/255 of the node's extent) per side. A node is 128
/// bytes, two cache lines, where the `f32` boxes took four: on the 1M-triangle scenes a ray's
/// walk is a chain of cache misses, and this halves the bytes each node step brings in.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(128))]
pub(super) struct Node {
    /// Corner the planes count from: the node's box's min, per axis.
    origin: [f32; 3],
    /// Size of one quantization step per axis, a power of two.
    step: [f32; 3],
    /// `q[plane][child]`, planes in the order min x, max x, min y, max y, min z, max z.
    pub(super) q: [[u8; WIDTH]; 6],
    pub(super) child: [u32; WIDTH],
    /// Bit k set when slot k holds a child (unused slots have an empty box).
    valid: u32,
    /// The slots by the half area of their quantized boxes, largest first (equal areas in
    /// slot order), three bits per slot from the low end: the order in which occlusion visits
    /// a node's children, precomputed so that a step neither computes areas nor sorts
    /// (it fills four of the node's 20 spare bytes).
    area_order: u32,
}

impl Node {
    /// A node with children boxes `boxes` and references `child`; slots past them are empty.
    pub(super) fn new(boxes: &[Aabb], child: &[u32]) -> Self {
        let whole = boxes.iter().fold(Aabb::EMPTY, |a, b| a.union(b));
        let mut origin = [0.0; 3];
        let mut step = [1.0; 3];
        for axis in 0..3 {
            if boxes.is_empty() {
                break;
            }
            // The smallest power of two whose 255 steps span the box.
            let extent = f64::from(whole.max[axis]) - f64::from(whole.min[axis]);
            let mut exp = if extent > 0.0 {
                ((extent / 255.0).log2().ceil() as i32).clamp(-126, 127)
            } else {
                -126
            };
            while exp < 127 && 255.0 * f64::from(pow2(exp)) < extent {
                exp += 1;
            }
            origin[axis] = whole.min[axis];
            step[axis] = pow2(exp);
        }
        let mut q = [[0u8; WIDTH]; 6];
        let mut refs = [EMPTY_CHILD; WIDTH];
        let mut valid = 0;
        for (k, b) in boxes.iter().enumerate().take(WIDTH) {
            for axis in 0..3 {
                let (o, s) = (origin[axis], step[axis]);
                let plane = |q: u8| o + f32::from(q) * s;
                let grid = |x: f32| (f64::from(x) - f64::from(o)) / f64::from(s);
                // Start from the rounded grid position, then move until the f32 plane that the
                // traversal computes lies outside the box.
                let mut lo = grid(b.min[axis]).floor().clamp(0.0, 255.0) as u8;
                while lo > 0 && plane(lo) > b.min[axis] {
                    lo -= 1;
                }
                while lo < 255 && plane(lo + 1) <= b.min[axis] {
                    lo += 1;
                }
                let mut hi = grid(b.max[axis]).ceil().clamp(0.0, 255.0) as u8;
                while hi < 255 && plane(hi) < b.max[axis] {
                    hi += 1;
                }
                while hi > lo && plane(hi - 1) >= b.max[axis] {
                    hi -= 1;
                }
                debug_assert!(plane(lo) <= b.min[axis] && plane(hi) >= b.max[axis]);
                q[2 * axis][k] = lo;
                q[2 * axis + 1][k] = hi;
            }
            refs[k] = child.get(k).copied().unwrap_or(EMPTY_CHILD);
            // An empty box (an unused slot the builder fills with `Aabb::EMPTY`) quantizes
            // to an inverted one, which `slabs` rejects but `slab_rays` would not.
            if b.min.cmple(b.max).all() {
                valid |= 1 << k;
            }
        }
        let mut node = Self {
            origin,
            step,
            q,
            child: refs,
            valid,
            area_order: 0,
        };
        let mut slots: [usize; WIDTH] = std::array::from_fn(|k| k);
        // Stable: equal areas keep slot order (unused slots, never hit, count as 0).
        let area = |k: usize| {
            if node.has_child(k) {
                node.half_area(k)
            } else {
                0.0
            }
        };
        slots.sort_by(|&a, &b| area(b).total_cmp(&area(a)));
        for (i, &k) in slots.iter().enumerate() {
            node.area_order |= (k as u32) << (3 * i);
        }
        node
    }

    /// The child slots from the largest box to the smallest (see `area_order`).
    #[inline(always)]
    pub(super) fn by_area(&self) -> impl Iterator<Item = usize> {
        let order = self.area_order;
        (0..WIDTH).map(move |i| (order >> (3 * i) & 7) as usize)
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
        let q = &self.q;
        let [ox, oy, oz] = self.origin;
        let [sx, sy, sz] = self.step;
        let [nx, ny, nz] = near;
        let (fx, fy, fz) = (1 - nx, 5 - ny, 9 - nz);
        let mut entry = [0f32; WIDTH];
        let mut exit = [0f32; WIDTH];
        for k in 0..WIDTH {
            // The planes, exactly as the builder checked them.
            let px0 = ox + f32::from(q[nx][k]) * sx;
            let py0 = oy + f32::from(q[ny][k]) * sy;
            let pz0 = oz + f32::from(q[nz][k]) * sz;
            let px1 = ox + f32::from(q[fx][k]) * sx;
            let py1 = oy + f32::from(q[fy][k]) * sy;
            let pz1 = oz + f32::from(q[fz][k]) * sz;
            let tx0 = (px0 - o.x) * inv.x;
            let ty0 = (py0 - o.y) * inv.y;
            let tz0 = (pz0 - o.z) * inv.z;
            let tx1 = (px1 - o.x) * inv.x;
            let ty1 = (py1 - o.y) * inv.y;
            let tz1 = (pz1 - o.z) * inv.z;
            entry[k] = max(max(tx0, ty0), max(tz0, 0.0));
            exit[k] = min(min(tx1, ty1), min(tz1, t_max)) * ROBUST_FAR;
        }
        (entry, le_mask(&entry, &exit) & self.valid)
    }

    /// The planes of every child, `[plane][child]`, each exactly as [`Node::slabs`] computes it
    /// (for the packet traversal, which tests one node against several rays: decoded once,
    /// eight lanes at a time, instead of once per child and ray).
    #[inline(always)]
    pub(super) fn planes(&self) -> Planes {
        let mut planes = [[0f32; WIDTH]; 6];
        for (p, plane) in planes.iter_mut().enumerate() {
            let (o, s) = (self.origin[p / 2], self.step[p / 2]);
            for (x, &q) in plane.iter_mut().zip(&self.q[p]) {
                *x = o + f32::from(q) * s;
            }
        }
        planes
    }

    /// The mask of the slots that hold a child.
    #[inline(always)]
    pub(super) fn children(&self) -> u32 {
        self.valid
    }

    /// Whether slot `k` holds a child.
    #[inline(always)]
    pub(super) fn has_child(&self, k: usize) -> bool {
        self.valid >> k & 1 != 0
    }

    /// Box of child `k` (as the traversal sees it: quantized outwards).
    pub(super) fn child_box(&self, k: usize) -> Aabb {
        let plane = |p: usize| self.origin[p / 2] + f32::from(self.q[p][k]) * self.step[p / 2];
        Aabb {
            min: Vec3::new(plane(0), plane(2), plane(4)),
            max: Vec3::new(plane(1), plane(3), plane(5)),
        }
    }

    /// Half the surface area of child `k`'s box. (A box flat along an axis whose step vanishes
    /// next to the origin quantizes to planes lo = 255, hi = 0, all at the origin: no extent.)
    #[inline(always)]
    pub(super) fn half_area(&self, k: usize) -> f32 {
        let side = |a: usize| {
            f32::from(self.q[2 * a + 1][k].saturating_sub(self.q[2 * a][k])) * self.step[a]
        };
        let (dx, dy, dz) = (side(0), side(1), side(2));
        dx * dy + dy * dz + dz * dx
    }
}

/// Slab tests of child `k` of a node whose planes are `planes` ([`Node::planes`]) against
/// [`RAYS`] rays at once (ray r: `o[axis][r]`, `inv` and `t_max` likewise), lane by lane over
/// the rays: each ray's entry distance (+∞ for a ray that misses) and the mask of the rays
/// that enter. Lane r computes exactly what [`Node::slabs`] computes for ray r and child `k`
/// (the near plane's distance is
/// the smaller of the two planes' distances, which for a positive 1/d is the min plane's and
/// for a negative one the max plane's).
#[inline(always)]
pub(super) fn slab_rays(
    planes: &Planes,
    k: usize,
    o: &[[f32; RAYS]; 3],
    inv: &[[f32; RAYS]; 3],
    t_max: &[f32; RAYS],
) -> ([f32; RAYS], u32) {
    let [x0, x1, y0, y1, z0, z1] = [0, 1, 2, 3, 4, 5].map(|p| planes[p][k]);
    let mut entry = [0f32; RAYS];
    let mut exit = [0f32; RAYS];
    for r in 0..RAYS {
        let ax = (x0 - o[0][r]) * inv[0][r];
        let bx = (x1 - o[0][r]) * inv[0][r];
        let ay = (y0 - o[1][r]) * inv[1][r];
        let by = (y1 - o[1][r]) * inv[1][r];
        let az = (z0 - o[2][r]) * inv[2][r];
        let bz = (z1 - o[2][r]) * inv[2][r];
        let (tx0, tx1) = (min(ax, bx), max(ax, bx));
        let (ty0, ty1) = (min(ay, by), max(ay, by));
        let (tz0, tz1) = (min(az, bz), max(az, bz));
        entry[r] = max(max(tx0, ty0), max(tz0, 0.0));
        exit[r] = min(min(tx1, ty1), min(tz1, t_max[r])) * ROBUST_FAR;
    }
    let mask = le_mask(&entry, &exit);
    for r in 0..RAYS {
        entry[r] = if entry[r] <= exit[r] {
            entry[r]
        } else {
            f32::INFINITY
        };
    }
    (entry, mask)
}

/// 2^`exp` for `exp` in −126..=127 (a normal `f32`).
fn pow2(exp: i32) -> f32 {
    f32::from_bits(((exp + 127) as u32) << 23)
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
pub(super) fn min(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// `a > b ? a : b`: one `maxss`.
#[inline(always)]
pub(super) fn max(a: f32, b: f32) -> f32 {
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
    fn node_is_two_cache_lines() {
        assert_eq!(std::mem::size_of::<Node>(), 128);
    }

    #[test]
    fn quantized_boxes_contain_their_children() {
        let mut rng = crate::hash::SplitMix(5);
        for scale in [1e-3f32, 1.0, 777.0, 1e6] {
            for _ in 0..200 {
                let mut v = || (rng.next_f32() * 2.0 - 1.0) * scale + scale * 0.3;
                let boxes: Vec<Aabb> = (0..1 + (v().abs() as usize % WIDTH))
                    .map(|_| {
                        Aabb::from_points(&[Vec3::new(v(), v(), v()), Vec3::new(v(), v(), v())])
                    })
                    .collect();
                let node = Node::new(&boxes, &[0; WIDTH]);
                assert_eq!(node.valid, (1 << boxes.len()) - 1);
                for (k, b) in boxes.iter().enumerate() {
                    let q = node.child_box(k);
                    assert!(q.contains(b), "{q:?} does not contain {b:?}");
                    // At most one step larger on each side.
                    for a in 0..3 {
                        assert!(b.min[a] - q.min[a] <= node.step[a]);
                        assert!(q.max[a] - b.max[a] <= node.step[a]);
                    }
                }
            }
        }
    }

    #[test]
    fn rays_in_lanes_match_the_one_ray_slab_test() {
        let mut rng = crate::hash::SplitMix(6);
        let mut v = || rng.next_f32() * 2.0 - 1.0;
        for _ in 0..300 {
            let boxes: Vec<Aabb> = (0..5)
                .map(|_| Aabb::from_points(&[Vec3::new(v(), v(), v()), Vec3::new(v(), v(), v())]))
                .collect();
            let node = Node::new(&boxes, &[0; WIDTH]);
            let planes = node.planes();
            let (mut o, mut inv, mut t_max) = ([[0f32; RAYS]; 3], [[0f32; RAYS]; 3], [0f32; RAYS]);
            let mut rays = Vec::new();
            for r in 0..RAYS {
                let origin = Vec3::new(v(), v(), v()) * 2.0;
                // Some components zero, as `Walk::new` makes them: ±10²⁰.
                let i = Vec3::new(
                    1.0 / v(),
                    if r % 3 == 0 { 1e20 } else { 1.0 / v() },
                    -1.0 / v(),
                );
                for a in 0..3 {
                    o[a][r] = origin[a];
                    inv[a][r] = i[a];
                }
                t_max[r] = if r % 2 == 0 {
                    f32::INFINITY
                } else {
                    v().abs() * 2.0
                };
                rays.push((origin, i));
            }
            for k in 0..WIDTH {
                let (entry, mask) = slab_rays(&planes, k, &o, &inv, &t_max);
                let mask = if node.has_child(k) { mask } else { 0 };
                for (r, &(origin, i)) in rays.iter().enumerate() {
                    let near = [
                        usize::from(i.x < 0.0),
                        2 + usize::from(i.y < 0.0),
                        4 + usize::from(i.z < 0.0),
                    ];
                    let (e1, m1) = node.slabs(origin, i, near, t_max[r]);
                    assert_eq!(mask >> r & 1, m1 >> k & 1, "ray {r} child {k}");
                    if m1 >> k & 1 != 0 {
                        assert_eq!(entry[r], e1[k]);
                    }
                }
            }
        }
    }

    #[test]
    fn area_order_is_a_permutation_largest_first() {
        let mut rng = crate::hash::SplitMix(7);
        let mut v = || rng.next_f32() * 2.0 - 1.0;
        for n in 0..=WIDTH {
            let boxes: Vec<Aabb> = (0..n)
                .map(|_| Aabb::from_points(&[Vec3::new(v(), v(), v()), Vec3::new(v(), v(), v())]))
                .collect();
            let node = Node::new(&boxes, &[0; WIDTH]);
            let order: Vec<usize> = node.by_area().collect();
            let mut sorted = order.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..WIDTH).collect::<Vec<_>>());
            // The used slots first, by falling area.
            let used: Vec<f32> = order[..n].iter().map(|&k| node.half_area(k)).collect();
            assert!(order[..n].iter().all(|&k| node.has_child(k)));
            assert!(used.windows(2).all(|w| w[0] >= w[1]), "{used:?}");
        }
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
