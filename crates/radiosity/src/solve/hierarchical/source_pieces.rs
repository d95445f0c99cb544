//! Source pieces: a coarse source shines toward each receiver what the parts of it that the
//! receiver sees best shine.
//!
//! A link (q, s) whose source is a large node or cluster carries s's mean radiosity B̄_s
//! (the pull of [`super::push_pull`]). What q really gathers is
//!
//! ```text
//! F_qs B̂_s = Σ_{leaves l ⊂ s} F_ql V_ql B_l ,
//! ```
//!
//! and B̂_s differs from B̄_s wherever the source's radiosity correlates with how well the
//! receiver sees it: the bright middle of a floor under a lamp sees the ceiling better than its
//! dark corners do, so every ceiling element that gathers the whole floor through one link gets
//! too little, and the errors of the elements add up instead of cancelling. BF refinement
//! judges each link alone (B_s F A_q against ε Φ), so links into small receivers keep coarse
//! sources however many of them there are; the source-variation test
//! ([`super::refine::Oracle`]) bounds each link's part, not the sum.
//!
//! So every link through the rows ([`super::leaf_rows`]) splits its source down the hierarchy (a
//! node into its four children, a cluster into its two or its faces), the piece the receiver
//! sees most first, into at most [`PIECES`] pieces c, and shines the weighted mean
//!
//! ```text
//! B̂_s = Σ_c w_c P_c / Σ_c w_c O_c ,      w_c = F_qc V_qc / A_c ,
//! ```
//!
//! where P_c is the power piece c shines (its open area times its open part's radiosity, or a
//! cluster's area times its radiosity toward q) and O_c its open area. F_qc is the unoccluded
//! factor from the receiver to the piece ([`View::unoccluded`]); V_qc is one where the link is
//! wholly visible and, where its shadow rays found it partly hidden, the piece's own four rays
//! ([`View::quick_visibility`]) — a bright piece hidden from the receiver behind a partition
//! must not pull the mean up. The link's factor F_qs V_qs stays as it is: the pieces move only
//! which radiosity it carries, so its power changes by what the correlation was worth. This is
//! the reciprocal of the leaf rows: those give every element its own factor to a source; these
//! give every part of a source its own factor to a receiver, at the resolution of the pieces
//! ([`Clusters`] and quadtree levels), which bounds the cost by [`PIECES`] factors per link.
//!
//! Measured on `benches/suite` (docs/decisions/hierarchical-rows.md), with the elements' own
//! visibility in the rows: the bare OBJ room's ceiling −5.2 → −0.8 %, the furnished room's
//! ball +6.0 → +1.8 % split evenly, +0.3 % split where the receiver looks (the dark spot of
//! the table right under it), cornell-faces' short block +4.0 → +1.0 %; the closed
//! rooms' energy 0.3–1.4 % short → within 0.1 % (partitions, emitter beside a wall) and 0.3 %
//! (furnished room).

use rayon::prelude::*;

use super::link::{Handle, Link, View};

/// The most pieces a link's source is split into.
pub const PIECES: usize = 16;

/// Bytes per piece: its handle and its weight.
pub const BYTES_PER_PIECE: u64 = 8;

/// Links whose pieces are found together, between two looks at the stop flag.
const CHUNK: usize = 16_384;

/// The pieces of every link's source.
#[derive(Clone, Debug, Default)]
pub struct SourcePieces {
    /// Link l's pieces are `pieces[start[l]..start[l + 1]]`.
    start: Vec<u32>,
    /// Each piece's handle and w_c = F_qc V_qc / A_c.
    pieces: Vec<(Handle, f32)>,
}

impl SourcePieces {
    /// The pieces of the source of every link marked in `split`, or `None` if `stop` said so
    /// on the way; `hidden[l]` says whether link l's shadow rays found it partly hidden. A
    /// source that cannot be split (an element) has no pieces, nor do unmarked links.
    #[must_use]
    pub fn build(
        view: &View,
        links: &[Link],
        split: &[bool],
        hidden: &[bool],
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Option<Self> {
        let mut out = SourcePieces {
            start: Vec::with_capacity(links.len() + 1),
            pieces: Vec::new(),
        };
        out.start.push(0);
        for (k, chunk) in links.chunks(CHUNK).enumerate() {
            if stop() {
                return None;
            }
            let lo = k * CHUNK;
            let found: Vec<Vec<(Handle, f32)>> = chunk
                .par_iter()
                .enumerate()
                .map(|(i, l)| {
                    if split[lo + i] {
                        pieces(view, l, hidden[lo + i])
                    } else {
                        Vec::new()
                    }
                })
                .collect();
            for p in found {
                out.pieces.extend(p);
                out.start.push(out.pieces.len() as u32);
            }
        }
        Some(out)
    }

    /// The pieces of link `l`'s source, each with its weight w_c (empty: shine it whole).
    #[must_use]
    pub fn of(&self, l: usize) -> &[(Handle, f32)] {
        &self.pieces[self.start[l] as usize..self.start[l + 1] as usize]
    }

    /// Bytes held.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        self.pieces.len() as u64 * BYTES_PER_PIECE + self.start.len() as u64 * 4
    }
}

/// Link `l`'s source split into at most [`PIECES`] pieces, each with its weight; empty if it
/// cannot be split. The piece the receiver sees most (the largest unoccluded factor F_qc) is
/// split first, so the pieces are finest where the receiver looks: the part of a table top
/// right under a ball standing on it, not its far corners.
fn pieces(view: &View, l: &Link, hidden: bool) -> Vec<(Handle, f32)> {
    let mut kids = Vec::new();
    view.children(l.source, &mut kids);
    if kids.is_empty() {
        return Vec::new();
    }
    let factor = |h: Handle| view.unoccluded(l.receiver, h);
    let mut list: Vec<(f64, Handle)> = vec![(factor(l.source), l.source)];
    loop {
        let mut best: Option<(f64, usize)> = None;
        for (i, &(f, h)) in list.iter().enumerate() {
            if f <= 0.0 || best.is_some_and(|(b, _)| f <= b) {
                continue;
            }
            kids.clear();
            view.children(h, &mut kids);
            if !kids.is_empty() && list.len() - 1 + kids.len() <= PIECES {
                best = Some((f, i));
            }
        }
        let Some((_, i)) = best else { break };
        let (_, h) = list.remove(i);
        kids.clear();
        view.children(h, &mut kids);
        list.extend(kids.iter().map(|&k| (factor(k), k)));
    }
    if list.len() < 2 {
        return Vec::new();
    }
    list.into_iter()
        .map(|(mut f, c)| {
            if hidden && f > 0.0 {
                f *= view.quick_visibility(l.receiver, c);
            }
            (c, (f / view.area(c).max(f64::MIN_POSITIVE)) as f32)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::Bvh;
    use crate::mesh::{Mesh, Subdivision};
    use crate::solve::hierarchical::cluster::Clusters;
    use crate::solve::hierarchical::link::{Estimate, Sight};

    /// A source's pieces cover it once, and their weights are the receiver's factors to them:
    /// Σ_c w_c A_c = F_qs for a wholly visible pair (additivity of form factors).
    #[test]
    fn pieces_cover_the_source_and_add_up_to_its_factor() {
        let scene = crate::testing::closed_cube(0.5, [1.0; 6]);
        let mesh = Mesh::build(&scene, Subdivision::Elements(600));
        let bvh = Bvh::build(&mesh.triangles);
        let clusters = Clusters::build(&mesh);
        let view = View::new(&mesh, &clusters, &bvh);
        let roots: Vec<u32> = mesh.roots.iter().flat_map(Clone::clone).collect();
        let mut checked = 0;
        for &q in &roots {
            for &s in &roots {
                let (q, s) = (Handle::node(q), Handle::node(s));
                let Estimate::Link(l) = view.estimate(q, s, Sight::Unknown) else {
                    continue;
                };
                let p = pieces(&view, &l, false);
                assert!(p.len() > 1 && p.len() <= PIECES, "{}", p.len());
                let area: f64 = p.iter().map(|&(c, _)| view.area(c)).sum();
                assert!((area - view.area(s)).abs() < 1e-6 * area, "{area}");
                let f: f64 = p.iter().map(|&(c, w)| f64::from(w) * view.area(c)).sum();
                let whole = view.unoccluded(q, s);
                // The two quadratures (the receiver's points against each piece, against the
                // whole face) agree to 1 % (adjacent faces' kernel is log-singular on the edge).
                assert!((f - whole).abs() < 0.01 * whole, "{f} vs {whole}");
                checked += 1;
            }
        }
        assert_eq!(checked, 30);
    }
}
