//! A hierarchy of boxes for overlap queries: which of many boxes meet a given box?
//!
//! The [`super::Bvh`] answers ray queries over triangles; a *range* query ("every triangle
//! whose box meets this one") runs over it too ([`super::Bvh::overlapping`]), but only over
//! the triangles' own boxes. A test that reaches out from each triangle by a distance of its
//! own (a contact test: a triangle touches a surface within a few percent of its size,
//! [`crate::mesh`]) must then query with the largest reach around every element, and a small
//! element of a dense mesh visits hundreds of triangles that cannot touch it. Here each item
//! has a box of its own choosing (the triangle's bounds grown by its reach), so a query visits
//! only the items whose boxes meet it: the work per query is bounded by what it finds, plus
//! O(log n) steps down the tree.
//!
//! The tree is binary, built top-down by splitting the items at the median of their box
//! centres along the widest axis of those centres (a k-d split of the centres, Bentley 1975;
//! O(n log n), depth ⌈log₂(n / [`LEAF`])⌉ + 1 whatever the boxes). Nodes are stored depth-first:
//! an inner node's first child follows it.

use glam::Vec3;

use super::Aabb;

/// Most items in a leaf.
pub const LEAF: usize = 4;

/// Stack entries a query needs: one per level of a median-split tree over 2³² items.
const STACK: usize = 64;

/// Boxes in a hierarchy, for finding those that overlap a query box.
///
/// ```
/// use glam::Vec3;
/// use radiosity::accel::{Aabb, BoxTree};
///
/// let boxes: Vec<Aabb> = (0..10)
///     .map(|k| Aabb::from_points(&[Vec3::splat(k as f32), Vec3::splat(k as f32 + 0.5)]))
///     .collect();
/// let tree = BoxTree::build(&boxes);
/// let mut found = Vec::new();
/// tree.overlapping(&Aabb::from_points(&[Vec3::splat(2.2), Vec3::splat(3.1)]), |k| found.push(k));
/// found.sort();
/// assert_eq!(found, [2, 3]);
/// ```
#[derive(Clone, Debug, Default)]
pub struct BoxTree {
    nodes: Vec<BoxNode>,
    /// The items' boxes in leaf order.
    boxes: Vec<Aabb>,
    /// The original index of each entry of `boxes`.
    ids: Vec<u32>,
}

/// A node: its bounds, and either its items (`count > 0`: `boxes[first..first + count]`) or,
/// for an inner node (`count == 0`), its second child `first` (the first is the next node).
#[derive(Clone, Copy, Debug)]
struct BoxNode {
    bounds: Aabb,
    first: u32,
    count: u32,
}

impl BoxTree {
    /// Builds the hierarchy over `boxes`. A box with a non-finite coordinate stands for
    /// nothing: no query finds it.
    ///
    /// # Panics
    /// With 2³² or more boxes.
    #[must_use]
    pub fn build(boxes: &[Aabb]) -> Self {
        assert!(u32::try_from(boxes.len()).is_ok(), "too many boxes");
        let finite = |b: &Aabb| b.min.is_finite() && b.max.is_finite();
        let boxes: Vec<Aabb> = boxes
            .iter()
            .map(|b| if finite(b) { *b } else { Aabb::EMPTY })
            .collect();
        let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut tree = Self::default();
        if !boxes.is_empty() {
            tree.split(&boxes, &mut order, 0);
        }
        tree.boxes = order.iter().map(|&k| boxes[k as usize]).collect();
        tree.ids = order;
        debug_assert_eq!(tree.validate(), Ok(()));
        tree
    }

    /// Appends the subtree over `order[..]` (its items start at `offset` in leaf order).
    fn split(&mut self, boxes: &[Aabb], order: &mut [u32], offset: usize) {
        let bounds = order
            .iter()
            .fold(Aabb::EMPTY, |b, &k| b.union(&boxes[k as usize]));
        let at = self.nodes.len();
        self.nodes.push(BoxNode {
            bounds,
            first: offset as u32,
            count: order.len() as u32,
        });
        if order.len() <= LEAF {
            return;
        }
        // Split at the median centre along the centres' widest axis (an empty box's centre
        // counts as the origin).
        let centre = |k: u32| {
            let b = &boxes[k as usize];
            let c = (b.min + b.max) * 0.5;
            if c.is_finite() {
                c
            } else {
                Vec3::ZERO
            }
        };
        let spread: Aabb = order.iter().map(|&k| centre(k)).collect();
        let extent = spread.max - spread.min;
        let axis = (0..3).fold(0, |a, k| if extent[k] > extent[a] { k } else { a });
        let half = order.len() / 2;
        order.select_nth_unstable_by(half, |&a, &b| centre(a)[axis].total_cmp(&centre(b)[axis]));
        let (low, high) = order.split_at_mut(half);
        self.split(boxes, low, offset);
        self.nodes[at].count = 0;
        self.nodes[at].first = self.nodes.len() as u32;
        self.split(boxes, high, offset + half);
    }

    /// Calls `visit` with the index (into the boxes given to [`BoxTree::build`]) of every box
    /// that overlaps `query` (boundaries included), in no particular order.
    pub fn overlapping(&self, query: &Aabb, mut visit: impl FnMut(usize)) {
        let overlaps = |b: &Aabb| query.min.cmple(b.max).all() && b.min.cmple(query.max).all();
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = [0u32; STACK];
        let mut depth = 1;
        while depth > 0 {
            depth -= 1;
            let n = stack[depth];
            let node = &self.nodes[n as usize];
            if !overlaps(&node.bounds) {
                continue;
            }
            if node.count == 0 {
                stack[depth] = node.first;
                stack[depth + 1] = n + 1;
                depth += 2;
                continue;
            }
            for k in node.first as usize..(node.first + node.count) as usize {
                if overlaps(&self.boxes[k]) {
                    visit(self.ids[k] as usize);
                }
            }
        }
    }

    /// Number of boxes the hierarchy was built from.
    #[must_use]
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// Whether it was built from no boxes.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// Checks the invariants: every box appears in exactly one leaf, leaves hold 1 to [`LEAF`]
    /// boxes in consecutive ranges, and every node's bounds contain its children's and its
    /// boxes.
    ///
    /// # Errors
    /// A description of the first broken invariant.
    pub fn validate(&self) -> Result<(), String> {
        let mut seen = vec![false; self.ids.len()];
        for &id in &self.ids {
            let slot = seen.get_mut(id as usize).ok_or("id out of range")?;
            if std::mem::replace(slot, true) {
                return Err(format!("box {id} appears twice"));
            }
        }
        if self.nodes.is_empty() {
            return if self.ids.is_empty() {
                Ok(())
            } else {
                Err("boxes without nodes".into())
            };
        }
        // Depth-first: the leaves' ranges follow one another from 0 to the end.
        let mut next = 0;
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = self.nodes.get(n).ok_or("node out of range")?;
            let contains = |b: &Aabb| node.bounds.contains(b);
            if node.count > 0 {
                if node.count as usize > LEAF || node.first as usize != next {
                    return Err(format!("leaf {n} holds a wrong range"));
                }
                next += node.count as usize;
                let boxes = self
                    .boxes
                    .get(node.first as usize..next)
                    .ok_or("leaf range")?;
                if !boxes.iter().all(contains) {
                    return Err(format!("leaf {n} does not contain its boxes"));
                }
            } else {
                let (a, b) = (n + 1, node.first as usize);
                let children = [self.nodes.get(a), self.nodes.get(b)];
                if b <= a
                    || !children
                        .iter()
                        .all(|c| c.is_some_and(|c| contains(&c.bounds)))
                {
                    return Err(format!("children of node {n} are misplaced or outside it"));
                }
                stack.extend([b, a]);
            }
        }
        if next != self.ids.len() {
            return Err("leaves do not cover the boxes".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::SplitMix;

    /// `count` boxes of random sizes up to `size` in the unit cube.
    fn random_boxes(count: usize, size: f32, seed: u64) -> Vec<Aabb> {
        let mut g = SplitMix(seed);
        let mut point = || Vec3::new(g.next_f32(), g.next_f32(), g.next_f32());
        (0..count)
            .map(|_| {
                let (corner, extent) = (point(), point() * size);
                Aabb::from_points(&[corner, corner + extent])
            })
            .collect()
    }

    #[test]
    fn finds_exactly_the_overlapping_boxes() {
        for count in [0, 1, LEAF, LEAF + 1, 1000] {
            let boxes = random_boxes(count, 0.05, count as u64);
            let tree = BoxTree::build(&boxes);
            assert_eq!(tree.validate(), Ok(()));
            assert_eq!(tree.len(), count);
            for query in random_boxes(50, 0.2, 7) {
                let mut found = Vec::new();
                tree.overlapping(&query, |k| found.push(k));
                found.sort_unstable();
                let expected: Vec<usize> = (0..count)
                    .filter(|&k| {
                        query.min.cmple(boxes[k].max).all() && boxes[k].min.cmple(query.max).all()
                    })
                    .collect();
                assert_eq!(found, expected);
            }
        }
    }

    #[test]
    fn identical_and_non_finite_boxes_are_kept_and_never_found_when_not_finite() {
        let mut boxes = vec![Aabb::from_points(&[Vec3::ZERO, Vec3::ONE]); 100];
        boxes[17].max.x = f32::NAN;
        boxes[40].min.y = f32::NEG_INFINITY;
        let tree = BoxTree::build(&boxes);
        assert_eq!(tree.validate(), Ok(()));
        let mut found = Vec::new();
        tree.overlapping(&Aabb::from_points(&[Vec3::splat(0.5)]), |k| found.push(k));
        found.sort_unstable();
        let expected: Vec<usize> = (0..100).filter(|&k| k != 17 && k != 40).collect();
        assert_eq!(found, expected);
    }

    #[test]
    fn validate_catches_a_box_outside_its_leaf() {
        let mut tree = BoxTree::build(&random_boxes(100, 0.05, 3));
        tree.boxes[50].max += Vec3::ONE;
        assert!(tree.validate().is_err());
    }
}
