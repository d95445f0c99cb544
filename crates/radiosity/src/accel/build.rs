//! Binned surface-area-heuristic construction (Wald 2007, "On fast construction of SAH-based
//! bounding volume hierarchies").
//!
//! A node's expected cost with children L and R is
//!
//! ```text
//! C = C_trav + C_isect · (A(L)·N(L) + A(R)·N(R)) / A(parent)
//! ```
//!
//! (MacDonald & Booth 1990), A the surface area of a box and N the number of packets of four
//! its triangles fill, ⌈n/4⌉ (leaves are tested a packet at a time, [`super::packet`]; Embree
//! counts its SAH in blocks of four the same way); a leaf costs C_isect · N. The candidate
//! splits are the planes between [`BINS`] equal bins of the
//! centroids' extent on each axis, evaluated with one sweep each way. Subtrees above
//! [`PARALLEL_MIN`] triangles are built in parallel with `rayon::join` into their own node arrays
//! and concatenated in a fixed order, so the result does not depend on the thread count.
//!
//! The binary tree is then collapsed into a [`WIDTH`]-wide one (Wald et al. 2008, "Getting
//! rid of packets"): a node adopts the children of its largest interior child until it has
//! [`WIDTH`], which divides the depth by about log₂ WIDTH and so cuts the cache misses of a
//! traversal.

use glam::Vec3;

use super::node::{is_leaf, leaf_ref, Aabb, Node, EMPTY_CHILD, MAX_LEAF, WIDTH};
use super::packet::LANES;

/// A binary node: the boxes and references of its two children.
#[derive(Clone, Copy, Debug)]
struct Node2 {
    boxes: [Aabb; 2],
    child: [u32; 2],
}

/// Centroid bins per axis.
const BINS: usize = 32;
/// Cost of visiting a binary node (two slab tests and a likely cache miss), relative to one
/// packet test (with packets: 0.5, 1, 2 and 4 within noise of each other at 1M triangles;
/// with single triangles 1 was faster than 2 and 3).
const TRAVERSAL_COST: f32 = 1.0;
/// Below this depth splits follow the SAH; deeper, ranges are halved by count, which bounds
/// the depth by `SAH_DEPTH + log2(n)` (≤ 60 for the 2²⁸ triangles a leaf reference can address)
/// and so bounds the traversal stack.
const SAH_DEPTH: u32 = 32;
/// Ranges at least this large split their two halves over rayon.
const PARALLEL_MIN: usize = 32 * 1024;

/// Deepest a binary tree can be: SAH levels, then halving at most 2²⁸ triangles.
pub(super) const MAX_DEPTH: usize = SAH_DEPTH as usize + 28;

/// What a build sees of each triangle.
pub(super) struct Inputs<'a> {
    /// Bounding box of each triangle.
    pub boxes: &'a [Aabb],
    /// Centroid of each triangle's box.
    pub centroids: &'a [Vec3],
}

/// A built wide hierarchy: node array (root at 0 unless the root is a leaf), the triangle order
/// its leaves index, the root reference and the scene box.
pub(super) struct Built {
    pub nodes: Vec<Node>,
    pub order: Vec<u32>,
    pub root: u32,
    pub bounds: Aabb,
}

/// Builds the hierarchy over all triangles of `inputs`.
pub(super) fn build(inputs: &Inputs<'_>) -> Built {
    let mut order: Vec<u32> = (0..inputs.boxes.len() as u32).collect();
    let sub = build_parallel(inputs, &mut order, 0, 0);
    let mut nodes = Vec::with_capacity(sub.nodes.len() / 2 + 1);
    let root = if is_leaf(sub.root) {
        sub.root
    } else {
        collapse(&sub.nodes, sub.root, &mut nodes)
    };
    Built {
        nodes,
        order,
        root,
        bounds: sub.bounds,
    }
}

/// Appends the wide node made from binary node `index` and its descendants depth-first;
/// returns its index.
fn collapse(binary: &[Node2], index: u32, out: &mut Vec<Node>) -> u32 {
    let node = &binary[index as usize];
    let mut kids: Vec<(u32, Aabb)> = vec![
        (node.child[0], node.boxes[0]),
        (node.child[1], node.boxes[1]),
    ];
    // Open the largest interior child while there is room.
    while kids.len() < WIDTH {
        let Some(k) = (0..kids.len())
            .filter(|&k| !is_leaf(kids[k].0))
            .max_by(|&a, &b| kids[a].1.half_area().total_cmp(&kids[b].1.half_area()))
        else {
            break;
        };
        let opened = &binary[kids[k].0 as usize];
        kids[k] = (opened.child[0], opened.boxes[0]);
        kids.insert(k + 1, (opened.child[1], opened.boxes[1]));
    }
    let me = out.len();
    out.push(Node::new(&[], &[]));
    let mut boxes = [Aabb::EMPTY; WIDTH];
    let mut refs = [EMPTY_CHILD; WIDTH];
    for (k, &(r, b)) in kids.iter().enumerate() {
        boxes[k] = b;
        refs[k] = if is_leaf(r) {
            r
        } else {
            collapse(binary, r, out)
        };
    }
    out[me] = Node::new(&boxes, &refs);
    me as u32
}

/// A subtree in its own node array; interior references are local to it.
struct Subtree {
    nodes: Vec<Node2>,
    root: u32,
    bounds: Aabb,
}

/// Builds `refs` (which start at `base` in the global order), splitting large ranges over rayon.
fn build_parallel(inputs: &Inputs<'_>, refs: &mut [u32], base: usize, depth: u32) -> Subtree {
    if refs.len() < PARALLEL_MIN {
        let mut nodes = Vec::new();
        let (root, bounds) = build_serial(inputs, refs, base, depth, &mut nodes);
        return Subtree {
            nodes,
            root,
            bounds,
        };
    }
    let Some(mid) = split(inputs, refs, depth) else {
        // Unreachable for ranges this large (they always split), kept total for safety.
        let mut nodes = Vec::new();
        let (root, bounds) = build_serial(inputs, refs, base, depth, &mut nodes);
        return Subtree {
            nodes,
            root,
            bounds,
        };
    };
    let (left_refs, right_refs) = refs.split_at_mut(mid);
    let (left, right) = rayon::join(
        || build_parallel(inputs, left_refs, base, depth + 1),
        || build_parallel(inputs, right_refs, base + mid, depth + 1),
    );
    // Parent first, then the left subtree, then the right one (depth-first order).
    let left_offset = 1;
    let right_offset = 1 + left.nodes.len() as u32;
    let mut nodes = Vec::with_capacity(1 + left.nodes.len() + right.nodes.len());
    nodes.push(Node2 {
        boxes: [left.bounds, right.bounds],
        child: [
            relocate(left.root, left_offset),
            relocate(right.root, right_offset),
        ],
    });
    for (sub, offset) in [(&left, left_offset), (&right, right_offset)] {
        nodes.extend(sub.nodes.iter().map(|n| {
            let mut n = *n;
            n.child = n.child.map(|c| relocate(c, offset));
            n
        }));
    }
    Subtree {
        nodes,
        root: 0,
        bounds: left.bounds.union(&right.bounds),
    }
}

/// Moves an interior reference by `offset` nodes; leaf references are global already.
fn relocate(child: u32, offset: u32) -> u32 {
    if is_leaf(child) {
        child
    } else {
        child + offset
    }
}

/// Builds `refs` depth-first into `nodes`; returns the subtree's reference and box.
fn build_serial(
    inputs: &Inputs<'_>,
    refs: &mut [u32],
    base: usize,
    depth: u32,
    nodes: &mut Vec<Node2>,
) -> (u32, Aabb) {
    match split(inputs, refs, depth) {
        None => {
            let bounds = refs
                .iter()
                .fold(Aabb::EMPTY, |b, &i| b.union(&inputs.boxes[i as usize]));
            (leaf_ref(base, refs.len()), bounds)
        }
        Some(mid) => {
            let index = nodes.len();
            nodes.push(Node2 {
                boxes: [Aabb::EMPTY; 2],
                child: [0; 2],
            });
            let (left_refs, right_refs) = refs.split_at_mut(mid);
            let (l, lb) = build_serial(inputs, left_refs, base, depth + 1, nodes);
            let (r, rb) = build_serial(inputs, right_refs, base + mid, depth + 1, nodes);
            nodes[index] = Node2 {
                boxes: [lb, rb],
                child: [l, r],
            };
            (index as u32, lb.union(&rb))
        }
    }
}

/// Chooses how to split `refs`: reorders it and returns the size of the left part, or `None`
/// when a leaf is cheaper (or there is one triangle).
fn split(inputs: &Inputs<'_>, refs: &mut [u32], depth: u32) -> Option<usize> {
    let n = refs.len();
    if n <= 1 {
        return None;
    }
    let centroid = |i: u32| inputs.centroids[i as usize];
    if depth >= SAH_DEPTH {
        return (n > MAX_LEAF).then_some(n / 2);
    }
    // Box of the range and of its centroids.
    let mut bounds = Aabb::EMPTY;
    let mut cmin = Vec3::INFINITY;
    let mut cmax = Vec3::NEG_INFINITY;
    for &i in refs.iter() {
        bounds = bounds.union(&inputs.boxes[i as usize]);
        cmin = cmin.min(centroid(i));
        cmax = cmax.max(centroid(i));
    }
    let extent = cmax - cmin;
    let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, first bin on the right)
    for axis in 0..3 {
        if extent[axis].is_nan() || extent[axis] <= 0.0 {
            continue;
        }
        let scale = BINS as f32 * (1.0 - 1e-6) / extent[axis];
        let bin_of = |c: Vec3| (((c[axis] - cmin[axis]) * scale) as usize).min(BINS - 1);
        // Count and bound the triangles in each bin.
        let mut counts = [0u32; BINS];
        let mut boxes = [Aabb::EMPTY; BINS];
        for &i in refs.iter() {
            let b = bin_of(centroid(i));
            counts[b] += 1;
            boxes[b] = boxes[b].union(&inputs.boxes[i as usize]);
        }
        // Sweep from the right: area × count of bins k.. for every k.
        let mut right_cost = [0f32; BINS];
        let mut acc = Aabb::EMPTY;
        let mut count = 0u32;
        for k in (1..BINS).rev() {
            acc = acc.union(&boxes[k]);
            count += counts[k];
            right_cost[k] = acc.half_area() * blocks(count as usize);
        }
        // Sweep from the left and keep the cheapest plane with triangles on both sides.
        let mut acc = Aabb::EMPTY;
        let mut count = 0u32;
        for k in 1..BINS {
            acc = acc.union(&boxes[k - 1]);
            count += counts[k - 1];
            if count == 0 || count as usize == n {
                continue;
            }
            let cost = acc.half_area() * blocks(count as usize) + right_cost[k];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, k));
            }
        }
    }
    let parent_area = bounds.half_area();
    let leaf_cost = blocks(n);
    match best {
        Some((cost, axis, k)) => {
            let split_cost = TRAVERSAL_COST
                + if parent_area > 0.0 {
                    cost / parent_area
                } else {
                    0.0
                };
            if n <= MAX_LEAF && leaf_cost <= split_cost {
                return None;
            }
            let scale = BINS as f32 * (1.0 - 1e-6) / extent[axis];
            let goes_left = |i: u32| {
                let b = (((centroid(i)[axis] - cmin[axis]) * scale) as usize).min(BINS - 1);
                b < k
            };
            Some(partition(refs, goes_left))
        }
        // All centroids coincide: only a split by count is possible.
        None => (n > MAX_LEAF).then_some(n / 2),
    }
}

/// Packets of [`LANES`] that `n` triangles fill: what a leaf of them costs to test.
fn blocks(n: usize) -> f32 {
    n.div_ceil(LANES) as f32
}

/// Moves the elements satisfying `left` to the front; returns how many there are.
fn partition(refs: &mut [u32], left: impl Fn(u32) -> bool) -> usize {
    let mut i = 0;
    let mut j = refs.len();
    while i < j {
        if left(refs[i]) {
            i += 1;
        } else {
            j -= 1;
            refs.swap(i, j);
        }
    }
    i
}
