//! Spatial splits: the split BVH of Stich, Friedrich & Dietrich 2009 ("Spatial splits in
//! bounding volume hierarchies"), binned.
//!
//! An object split sends each triangle whole to one side, so long or slanted triangles make the
//! two children's boxes overlap and a ray in the overlap visits both. A spatial split cuts the
//! node's box by a plane and lets a triangle that crosses it be referenced on both sides, each
//! reference bounded by the part of the triangle on its side ("chopped" boxes, the triangle
//! clipped against the plane). At each node the cheapest of the binned object split
//! ([`super`]) and a spatial split among [`SPATIAL_BINS`] planes per axis is taken, by the same
//! cost (packets of four on each side, [`super::blocks`]); spatial splits are tried only where
//! the object split's children overlap by more than [`OVERLAP_MIN`] of the root's area, and a
//! crossing triangle goes whole to one side when that is cheaper (Stich's "reference
//! unsplitting").
//!
//! | setting | default | meaning |
//! |---|---|---|
//! | `budget` ([`super::BuildSettings::split_budget`]) | 0.3 | most references, as a fraction of the triangles, the splits may add |
//!
//! The budget is shared out down the tree in proportion to each side's references, so the
//! hierarchy does not depend on the order in which subtrees are built, nor on the thread count.
//! A triangle with several references is stored in several leaves; closest-hit and occlusion
//! queries are unaffected (they may test it twice), and the box query reports it once.

use glam::Vec3;

use super::{
    blocks, centroid_split, leaf_ref, relocate_leaf, Inputs, Node2, MAX_LEAF, PARALLEL_MIN,
    SAH_DEPTH, TRAVERSAL_COST,
};
#[cfg(test)]
use crate::accel::node::leaf_range;
use crate::accel::node::{is_leaf, Aabb};

/// Candidate planes per axis of a spatial split (the bins' boundaries).
const SPATIAL_BINS: usize = 16;
/// Spatial splits are tried where the best object split's children overlap by more than this
/// fraction of the root's surface area (Stich et al.'s α; 10⁻⁵ in the paper).
const OVERLAP_MIN: f32 = 1e-5;

/// A reference to (a part of) a triangle: its index and the box of the part.
#[derive(Clone, Copy, Debug)]
struct Ref {
    id: u32,
    bounds: Aabb,
}

/// What a build of a subtree needs to see.
struct Context<'a> {
    inputs: &'a Inputs<'a>,
    /// Overlap area above which spatial splits are tried.
    overlap_min: f32,
}

/// A subtree in its own arrays: interior references index `nodes`, leaves index `order`.
pub(super) struct Tree {
    pub nodes: Vec<Node2>,
    pub order: Vec<u32>,
    pub root: u32,
    pub bounds: Aabb,
}

/// Builds the binary tree over all triangles of `inputs` with spatial splits adding at most
/// `budget` references.
pub(super) fn build(inputs: &Inputs<'_>, budget: usize) -> Tree {
    let refs: Vec<Ref> = (0..inputs.boxes.len())
        .map(|i| Ref {
            id: i as u32,
            bounds: inputs.boxes[i],
        })
        .collect();
    let root = refs.iter().fold(Aabb::EMPTY, |b, r| b.union(&r.bounds));
    let context = Context {
        inputs,
        overlap_min: OVERLAP_MIN * root.half_area(),
    };
    subtree(&context, refs, budget, 0)
}

/// Builds `refs` into a tree of its own, the two halves of large ones over rayon.
fn subtree(cx: &Context<'_>, refs: Vec<Ref>, budget: usize, depth: u32) -> Tree {
    if refs.len() < PARALLEL_MIN {
        let mut tree = Tree {
            nodes: Vec::new(),
            order: Vec::new(),
            root: 0,
            bounds: Aabb::EMPTY,
        };
        let (root, bounds) = serial(cx, refs, budget, depth, &mut tree.nodes, &mut tree.order);
        tree.root = root;
        tree.bounds = bounds;
        return tree;
    }
    let (left, right, left_budget, right_budget) = match split(cx, refs, budget, depth) {
        Choice::Split(l, r, lb, rb) => (l, r, lb, rb),
        Choice::Leaf(refs) => {
            // Unreachable for ranges this large (they always split), kept total for safety.
            let mut tree = Tree {
                nodes: Vec::new(),
                order: Vec::new(),
                root: 0,
                bounds: Aabb::EMPTY,
            };
            let (root, bounds) = leaf(refs, &mut tree.order);
            tree.root = root;
            tree.bounds = bounds;
            return tree;
        }
    };
    let (l, r) = rayon::join(
        || subtree(cx, left, left_budget, depth + 1),
        || subtree(cx, right, right_budget, depth + 1),
    );
    // Parent first, then the left subtree, then the right one (depth-first order); the right
    // subtree's leaves follow the left one's in the order.
    let moved = |c: u32, nodes: u32, order: usize| {
        if is_leaf(c) {
            relocate_leaf(c, order)
        } else {
            c + nodes
        }
    };
    let (left_nodes, right_nodes) = (1, 1 + l.nodes.len() as u32);
    let right_order = l.order.len();
    let mut nodes = Vec::with_capacity(1 + l.nodes.len() + r.nodes.len());
    nodes.push(Node2 {
        boxes: [l.bounds, r.bounds],
        child: [
            moved(l.root, left_nodes, 0),
            moved(r.root, right_nodes, right_order),
        ],
    });
    for (t, offset, order) in [(&l, left_nodes, 0), (&r, right_nodes, right_order)] {
        nodes.extend(t.nodes.iter().map(|n| Node2 {
            boxes: n.boxes,
            child: n.child.map(|c| moved(c, offset, order)),
        }));
    }
    let mut order = l.order;
    order.extend_from_slice(&r.order);
    Tree {
        nodes,
        order,
        root: 0,
        bounds: l.bounds.union(&r.bounds),
    }
}

/// Builds `refs` depth-first into `nodes` and `order`; returns the subtree's reference and box.
fn serial(
    cx: &Context<'_>,
    refs: Vec<Ref>,
    budget: usize,
    depth: u32,
    nodes: &mut Vec<Node2>,
    order: &mut Vec<u32>,
) -> (u32, Aabb) {
    match split(cx, refs, budget, depth) {
        Choice::Leaf(refs) => leaf(refs, order),
        Choice::Split(left, right, left_budget, right_budget) => {
            let index = nodes.len();
            nodes.push(Node2 {
                boxes: [Aabb::EMPTY; 2],
                child: [0; 2],
            });
            let (l, lb) = serial(cx, left, left_budget, depth + 1, nodes, order);
            let (r, rb) = serial(cx, right, right_budget, depth + 1, nodes, order);
            nodes[index] = Node2 {
                boxes: [lb, rb],
                child: [l, r],
            };
            (index as u32, lb.union(&rb))
        }
    }
}

/// Appends a leaf of `refs` to `order`.
fn leaf(refs: Vec<Ref>, order: &mut Vec<u32>) -> (u32, Aabb) {
    let bounds = refs.iter().fold(Aabb::EMPTY, |b, r| b.union(&r.bounds));
    let first = order.len();
    order.extend(refs.iter().map(|r| r.id));
    (leaf_ref(first, refs.len()), bounds)
}

/// A node's fate: a leaf, or two sides with the budget each may still spend.
enum Choice {
    Leaf(Vec<Ref>),
    Split(Vec<Ref>, Vec<Ref>, usize, usize),
}

/// The best spatial split found: cost (area × packets, unnormalized), axis, first bin on the
/// right, and the binned sides' boxes and counts (for unsplitting).
struct Spatial {
    cost: f32,
    axis: usize,
    k: usize,
    left: Aabb,
    right: Aabb,
    n_left: usize,
    n_right: usize,
}

/// Chooses a leaf, an object split or a spatial split for `refs`.
fn split(cx: &Context<'_>, mut refs: Vec<Ref>, budget: usize, depth: u32) -> Choice {
    let n = refs.len();
    if n <= 1 {
        return Choice::Leaf(refs);
    }
    if depth >= SAH_DEPTH {
        if n <= MAX_LEAF {
            return Choice::Leaf(refs);
        }
        let right = refs.split_off(n / 2);
        return sides(refs, right, budget, n);
    }
    let bounds = refs.iter().fold(Aabb::EMPTY, |b, r| b.union(&r.bounds));
    let centroids: Vec<Vec3> = refs
        .iter()
        .map(|r| (r.bounds.min + r.bounds.max) * 0.5)
        .collect();
    let object = centroid_split(n, |i| centroids[i], |i| refs[i].bounds);
    let try_spatial = budget > 0
        && object
            .as_ref()
            .is_none_or(|o| overlap(&o.left, &o.right).half_area() > cx.overlap_min);
    let spatial = if try_spatial {
        best_spatial(cx, &refs, &bounds, budget)
    } else {
        None
    };
    let object_cost = object.as_ref().map_or(f32::INFINITY, |o| o.cost);
    let spatial_cost = spatial.as_ref().map_or(f32::INFINITY, |s| s.cost);
    let cost = object_cost.min(spatial_cost);
    if !cost.is_finite() {
        // All centroids coincide and no plane separates: only a split by count is possible.
        if n <= MAX_LEAF {
            return Choice::Leaf(refs);
        }
        let right = refs.split_off(n / 2);
        return sides(refs, right, budget, n);
    }
    let parent_area = bounds.half_area();
    let split_cost = TRAVERSAL_COST
        + if parent_area > 0.0 {
            cost / parent_area
        } else {
            0.0
        };
    if n <= MAX_LEAF && blocks(n) <= split_cost {
        return Choice::Leaf(refs);
    }
    if let (Some(s), true) = (&spatial, spatial_cost < object_cost) {
        let (left, right) = spatial_partition(cx, &refs, &bounds, s);
        if !left.is_empty() && !right.is_empty() {
            return sides(left, right, budget, n);
        }
    }
    match object {
        Some(o) => {
            let goes_left: Vec<bool> = (0..n).map(|i| o.goes_left(centroids[i])).collect();
            let mut left = Vec::with_capacity(o.n_left);
            let mut right = Vec::with_capacity(n - o.n_left);
            for (r, l) in refs.into_iter().zip(goes_left) {
                if l {
                    left.push(r);
                } else {
                    right.push(r);
                }
            }
            sides(left, right, budget, n)
        }
        None => {
            let right = refs.split_off(n / 2);
            sides(refs, right, budget, n)
        }
    }
}

/// Two sides with the budget left over (after the references they add to the parent's `n`)
/// shared in proportion to their sizes.
fn sides(left: Vec<Ref>, right: Vec<Ref>, budget: usize, n: usize) -> Choice {
    let total = left.len() + right.len();
    let rest = budget - (total - n);
    let left_budget = (rest as u64 * left.len() as u64 / total as u64) as usize;
    Choice::Split(left, right, left_budget, rest - left_budget)
}

/// The common part of two boxes (empty when they are apart).
fn overlap(a: &Aabb, b: &Aabb) -> Aabb {
    Aabb {
        min: a.min.max(b.min),
        max: a.max.min(b.max),
    }
}

/// Whether a box holds no point.
fn is_empty(b: &Aabb) -> bool {
    !b.min.cmple(b.max).all()
}

/// Spatial bin of coordinate `x` on a range starting at `lo` with `scale` bins per unit.
fn spatial_bin(x: f32, lo: f32, scale: f32) -> usize {
    (((x - lo) * scale).max(0.0) as usize).min(SPATIAL_BINS - 1)
}

/// The cheapest spatial split of `refs` (box `bounds`) that adds at most `budget` references.
fn best_spatial(cx: &Context<'_>, refs: &[Ref], bounds: &Aabb, budget: usize) -> Option<Spatial> {
    let n = refs.len();
    let mut best: Option<Spatial> = None;
    for axis in 0..3 {
        let (lo, hi) = (bounds.min[axis], bounds.max[axis]);
        let extent = hi - lo;
        if !(extent > 0.0) {
            continue;
        }
        let scale = SPATIAL_BINS as f32 / extent;
        let plane = |k: usize| lo + extent * (k as f32 / SPATIAL_BINS as f32);
        let mut entries = [0usize; SPATIAL_BINS];
        let mut exits = [0usize; SPATIAL_BINS];
        let mut boxes = [Aabb::EMPTY; SPATIAL_BINS];
        for r in refs {
            let first = spatial_bin(r.bounds.min[axis], lo, scale);
            let last = spatial_bin(r.bounds.max[axis], lo, scale).max(first);
            entries[first] += 1;
            exits[last] += 1;
            // Chop the reference at each plane it crosses.
            let tri = cx.inputs.triangle(r.id);
            let mut rest = r.bounds;
            for (b, bin) in boxes.iter_mut().enumerate().take(last).skip(first) {
                let (part, beyond) = clip(&tri, &rest, axis, plane(b + 1));
                *bin = bin.union(&part);
                rest = beyond;
            }
            boxes[last] = boxes[last].union(&rest);
        }
        // Sweep from the right, then from the left.
        let mut right_box = [Aabb::EMPTY; SPATIAL_BINS];
        let mut right_count = [0usize; SPATIAL_BINS];
        let (mut acc, mut count) = (Aabb::EMPTY, 0);
        for k in (1..SPATIAL_BINS).rev() {
            acc = acc.union(&boxes[k]);
            count += exits[k];
            right_box[k] = acc;
            right_count[k] = count;
        }
        let (mut acc, mut count) = (Aabb::EMPTY, 0);
        for k in 1..SPATIAL_BINS {
            acc = acc.union(&boxes[k - 1]);
            count += entries[k - 1];
            let right = right_count[k];
            if count == 0 || right == 0 || count + right - n > budget {
                continue;
            }
            let cost = acc.half_area() * blocks(count) + right_box[k].half_area() * blocks(right);
            if best.as_ref().is_none_or(|s| cost < s.cost) {
                best = Some(Spatial {
                    cost,
                    axis,
                    k,
                    left: acc,
                    right: right_box[k],
                    n_left: count,
                    n_right: right,
                });
            }
        }
    }
    best
}

/// Sends each reference of `refs` to its side of split `s`, chopping the ones that cross the
/// plane unless one side can take them whole for less (reference unsplitting).
fn spatial_partition(
    cx: &Context<'_>,
    refs: &[Ref],
    bounds: &Aabb,
    s: &Spatial,
) -> (Vec<Ref>, Vec<Ref>) {
    let axis = s.axis;
    let (lo, extent) = (bounds.min[axis], bounds.max[axis] - bounds.min[axis]);
    let scale = SPATIAL_BINS as f32 / extent;
    let plane = lo + extent * (s.k as f32 / SPATIAL_BINS as f32);
    let (a_left, a_right) = (s.left.half_area(), s.right.half_area());
    let (n_left, n_right) = (s.n_left as f32, s.n_right as f32);
    let both = a_left * n_left + a_right * n_right;
    let mut left = Vec::with_capacity(s.n_left);
    let mut right = Vec::with_capacity(s.n_right);
    for r in refs {
        let first = spatial_bin(r.bounds.min[axis], lo, scale);
        let last = spatial_bin(r.bounds.max[axis], lo, scale).max(first);
        if last < s.k {
            left.push(*r);
        } else if first >= s.k {
            right.push(*r);
        } else {
            let whole_left =
                s.left.union(&r.bounds).half_area() * n_left + a_right * (n_right - 1.0);
            let whole_right =
                a_left * (n_left - 1.0) + s.right.union(&r.bounds).half_area() * n_right;
            let (part_left, part_right) = clip(&cx.inputs.triangle(r.id), &r.bounds, axis, plane);
            if is_empty(&part_right) || (whole_left < both && whole_left <= whole_right) {
                left.push(*r);
            } else if is_empty(&part_left) || whole_right < both {
                right.push(*r);
            } else {
                left.push(Ref {
                    id: r.id,
                    bounds: part_left,
                });
                right.push(Ref {
                    id: r.id,
                    bounds: part_right,
                });
            }
        }
    }
    (left, right)
}

/// The boxes of the parts of triangle `tri` on either side of the plane `x[axis] = p`, within
/// `within` (the box of the part a reference stands for). Crossing points are widened by a few
/// ulps on the other axes, so rounding never leaves a point of the triangle outside both parts.
fn clip(tri: &[Vec3; 3], within: &Aabb, axis: usize, p: f32) -> (Aabb, Aabb) {
    let (mut left, mut right) = (Aabb::EMPTY, Aabb::EMPTY);
    let grow = |b: &mut Aabb, lo: Vec3, hi: Vec3| {
        b.min = b.min.min(lo);
        b.max = b.max.max(hi);
    };
    for i in 0..3 {
        let (a, b) = (tri[i], tri[(i + 1) % 3]);
        if a[axis] <= p {
            grow(&mut left, a, a);
        }
        if a[axis] >= p {
            grow(&mut right, a, a);
        }
        if (a[axis] < p && p < b[axis]) || (b[axis] < p && p < a[axis]) {
            let t = ((p - a[axis]) / (b[axis] - a[axis])).clamp(0.0, 1.0);
            let mut x = a + (b - a) * t;
            x[axis] = p;
            let mut pad = a.abs().max(b.abs()) * (4.0 * f32::EPSILON);
            pad[axis] = 0.0;
            grow(&mut left, x - pad, x + pad);
            grow(&mut right, x - pad, x + pad);
        }
    }
    (overlap(&left, within), overlap(&right, within))
}

/// Whether every reference of a leaf reference lies in the order (a debugging aid).
#[cfg(test)]
fn leaves_in_range(tree: &Tree) -> bool {
    let ok = |c: u32| {
        !is_leaf(c) || {
            let (first, count) = leaf_range(c);
            first + count <= tree.order.len()
        }
    };
    ok(tree.root) && tree.nodes.iter().all(|n| n.child.iter().all(|&c| ok(c)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipped_parts_cover_the_triangle() {
        let tri = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(4.0, 1.0, 0.5),
            Vec3::new(1.0, 3.0, -2.0),
        ];
        let whole = Aabb::from_points(&tri);
        for p in [0.5f32, 1.0, 2.5, 3.9] {
            let (l, r) = clip(&tri, &whole, 0, p);
            assert!(l.max.x <= p && r.min.x >= p);
            // Points of the triangle on a grid of barycentric coordinates.
            for i in 0..=20 {
                for j in 0..=20 - i {
                    let (u, v) = (i as f32 / 20.0, j as f32 / 20.0);
                    let x = tri[0] + (tri[1] - tri[0]) * u + (tri[2] - tri[0]) * v;
                    let inside = |b: &Aabb| b.min.cmple(x).all() && x.cmple(b.max).all();
                    assert!(inside(&l) || inside(&r), "{x} outside both parts at {p}");
                }
            }
        }
    }

    #[test]
    fn long_triangles_are_split_within_the_budget() {
        // Long thin slanted triangles: object splits overlap everywhere.
        let tris: Vec<[Vec3; 3]> = (0..2000)
            .map(|i| {
                let y = i as f32 * 0.01;
                [
                    Vec3::new(0.0, y, 0.0),
                    Vec3::new(10.0, y + 1.0, 0.3),
                    Vec3::new(0.0, y + 0.01, 0.1),
                ]
            })
            .collect();
        let boxes: Vec<Aabb> = tris.iter().map(|t| Aabb::from_points(t)).collect();
        let centroids: Vec<Vec3> = boxes.iter().map(|b| (b.min + b.max) * 0.5).collect();
        let inputs = Inputs {
            boxes: &boxes,
            centroids: &centroids,
            triangles: &tris,
        };
        let tree = build(&inputs, 600);
        assert!(leaves_in_range(&tree));
        assert!(tree.order.len() > tris.len(), "no spatial split taken");
        assert!(tree.order.len() <= tris.len() + 600);
        let mut seen = vec![false; tris.len()];
        for &i in &tree.order {
            seen[i as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
    }
}
