//! The light sources of the gathering solvers: a cut through the patches' quadtrees
//! (substructuring, Cohen et al. 1986).

use super::{Mesh, MAX_LEVEL};

impl Mesh {
    /// A cut through the quadtrees used as light sources: at most `max_sources` nodes (or the
    /// root faces, if there are more of those), each as
    /// small as that allows — for each root, the shallowest nodes whose area is at most a
    /// threshold, with the threshold found by bisection (or the leaves, if they are larger).
    ///
    /// Receivers are always the elements; sources may be coarser, which is the substructuring
    /// of Cohen et al. 1986: a source shoots the area-weighted mean radiosity of its elements.
    /// With `max_sources ≥ element_count()` the sources are exactly the elements, in order.
    ///
    /// A node whose leaves are not all at one level was refined locally, along a contact line
    /// (see [`Mesh::refine_contacts`]): it is always opened, since its mean radiosity mixes
    /// the lit and the dark side of the contact and would shine the lit side's light into the
    /// dark one (a two-sided block's inside came out 5 % as bright as its outside that way).
    /// If that takes more than `max_sources`, the count may grow up to `limit`; beyond it,
    /// only the mixed nodes above the deepest level that fits are opened, and sources straddle
    /// the finer parts of contact lines rather than overflow the limit (measured on
    /// `scenes/suite/bare-obj-many`, whose 4 926 root faces leave 8 192 sources too few: the
    /// inside of a block standing on the floor, dark in Mitsuba 3, was lit by straddling floor
    /// sources, 1.5 % of the block's radiosity).
    #[must_use]
    pub fn sources(&self, max_sources: usize, limit: usize) -> Vec<u32> {
        if max_sources >= self.element_count() {
            return self.elements.clone();
        }
        let mut mixed: Vec<bool> = self
            .nodes
            .iter()
            .map(|node| {
                let mut levels = self.elements
                    [node.elements.start as usize..node.elements.end as usize]
                    .iter()
                    .map(|&e| self.nodes[e as usize].level);
                let first = levels.next();
                levels.any(|l| Some(l) != first)
            })
            .collect();
        // At fine subdivisions the contact lines alone may hold more leaves than the budget:
        // then the budget grows to the limit, and past that only the mixed nodes above some
        // depth are opened, the deepest depth that fits: the large nodes, whose means mix the
        // most light across a line, go first. (Giving up on all of them at once let sources of
        // the wall behind an emitter facing it, 1 mm away, shine the light trapped there into
        // the room: +106 % at 16 000 elements, against +2.6 % at 4 000.)
        let cap = max_sources.max(limit);
        let total = self.total_area();
        let mut needed = self.cut(total, &mixed).len();
        if needed > cap {
            let all = std::mem::take(&mut mixed);
            for depth in (0..=MAX_LEVEL).rev() {
                mixed = all
                    .iter()
                    .zip(&self.nodes)
                    .map(|(&m, node)| m && node.level < depth)
                    .collect();
                needed = self.cut(total, &mixed).len();
                if needed <= cap {
                    break;
                }
            }
        }
        let max_sources = max_sources.max(needed.min(cap));
        // The count falls as the threshold grows; find the smallest threshold that fits.
        let (mut lo, mut hi) = (0.0, self.total_area());
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if self.cut(mid, &mixed).len() > max_sources.max(1) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        self.cut(hi, &mixed)
    }

    /// The shallowest nodes of area at most `threshold` (or leaves) that are not `mixed`, in
    /// element order.
    fn cut(&self, threshold: f64, mixed: &[bool]) -> Vec<u32> {
        let mut out = Vec::new();
        // Depth-first, roots in patch order: sources come out in element order.
        let mut stack: Vec<u32> = self.roots.iter().flat_map(|r| r.clone()).collect();
        stack.reverse();
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            match node.children {
                Some(c) if node.area() > threshold || mixed[n as usize] => {
                    stack.extend((c..c + 4).rev());
                }
                _ => out.push(n),
            }
        }
        out
    }
}
