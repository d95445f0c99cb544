//! Consistent leaf rows: every element gathers the links above it with its own form factors.
//!
//! A link (q, s) carries the factor F_qs — the mean over the receiver q of the point factors
//! to s — and the push hands every element e below q that same irradiance F_qs V_qs B_s
//! ([`super::push_pull`]). The link's power A_q F_qs V_qs B_s is right; its spread over the
//! elements is not: an element in a corner inherits its ancestors' mean factors to the far
//! walls, averaged over a region that sees them better, beside its own fine link to the near
//! wall. In a white furnace (an empty cube, every face ρ = 0.5 and emitting, exact
//! B = E / (1 − ρ)) single elements' row sums Σ F ranged 0.90–1.44, where they must be 1, and
//! the bright ones fed their neighbours; a corner element was 17.5 % off (`docs/decisions/hierarchical-rows.md`).
//!
//! After the refinement has settled the links, each element's row is written out with its own
//! factor to the source of every link that it gathers through — its own links and those of
//! its ancestors, quadtree nodes and clusters:
//!
//! ```text
//! B_e = E_e + ρ_e Σ_{links (q, s), q ⊇ e} F_es V_es B̂_s
//! ```
//!
//! F_es is estimated as the link's own factor is ([`View::element_factor`]: Lambert's contour
//! integral over the element's quadrature points for a face source, its centroid alone in the
//! far field, the cluster kernel for a cluster). V_es is the link's visibility V_qs where the
//! link's shadow rays all arrived (or none did) and as many fresh ones agree
//! ([`View::fresh_visibility`]), and the element's own four rays ([`View::quick_visibility`])
//! where either found it partly hidden: an element in the umbra of a link that straddles a
//! shadow must not get the link's mean. The fresh rays are there because the refinement
//! selects: it keeps a link whose rays all arrived and splits one whose rays did not, so the
//! kept links' rays missed the occluders they missed. Counted against 2 304 cosine rays from
//! each of 750 elements of the furnished room (`docs/decisions/hierarchical-visibility.md`), the
//! links its rays called clear gave the floor's elements 1.1 % more of their hemisphere than
//! it holds (the floor under a chair's seat, +10 % in the picture), and the ceiling's 0.3 %.
//! A link with a cluster at either end takes the fresh rays' visibility, and so does the
//! factor of an element's own link (the mean of both estimates between two faces): kept
//! because their rays said little, the chairs' own links to the floor carried 4 % too
//! little. B̂_s
//! is what the source shines toward q, weighted over its pieces ([`super::source_pieces`]).
//! This is the push of Hanrahan, Salzman &
//! Aupperle (1991) with the children's own factors in place of the parent's (the "final
//! gather" of Lischinski, Tampieri & Greenberg 1993 and Smits, Arvo & Greenberg 1994, applied
//! to the elements instead of the pixels, and iterated): it costs one factor per element and
//! link above it, which the hierarchy bounds by its depth, and keeps the links' sources, so the
//! sources' side of the error is still the oracle's to bound. A receiving cluster's faces get
//! their own factors too, instead of the directional spread of the push: a face turned away
//! from a source gets nothing from it. Where the rows of every link would not fit the matrix
//! budget, only the links nearest the elements go through them ([`LeafRows::rowed`]).
//!
//! Measured (`docs/hierarchical.md`), before the elements' own visibility and the source
//! pieces: the white furnace exact to 0.016 % on every element; the
//! evaluated pictures against Mitsuba 3 8.28 → 2.80 % (Cornell box) and 4.36 → 2.81 %
//! (furnished room); the suite's worst objects move both ways (partitions 2.86 → 0.93 %, the
//! bare OBJ room 4.51 → 5.17 %): at the default ε most of their error is the oracle's, not
//! the push's.

use rayon::prelude::*;

use super::cluster::Clusters;
use super::link::{receiver_groups, End, Handle, Link, View};
use super::source_pieces::{SourcePieces, BYTES_PER_PIECE, PIECES};
use crate::mesh::Mesh;
use crate::Rgb;

/// Bytes per row entry: the link's index and the element's factor.
pub const BYTES_PER_ENTRY: u64 = 8;

/// No parent.
const NONE: u32 = u32::MAX;

/// Below this visibility (and above 0) a link counts as partly hidden: its elements cast
/// their own rays. (A wholly visible link's factor over its unoccluded factor is 1 to the
/// rounding of an `f32`.)
const PARTLY: f64 = 1.0 - 1e-4;

/// Elements whose rows are built together, between two looks at the stop flag.
const CHUNK: usize = 1024;

/// Every element's row: the links it gathers through, each with the element's own factor.
#[derive(Clone, Debug, Default)]
pub struct LeafRows {
    /// Element k's entries are `start[k]..start[k + 1]` (k an index of [`Mesh::elements`]).
    start: Vec<usize>,
    /// The link of each entry.
    link: Vec<u32>,
    /// F_es V_qs of each entry.
    factor: Vec<f32>,
    /// Whether each link goes through the rows ([`LeafRows::rowed`]); the others are pushed.
    rowed: Vec<bool>,
    /// The pieces of the rows' links' sources.
    pieces: SourcePieces,
}

/// Where each handle's row links are, and each handle's parent.
struct Tree {
    /// Indices of the links that go through the rows ([`LeafRows::rowed`]), grouped by
    /// receiver.
    members: Vec<u32>,
    /// `members[lo..hi]`: the row links received by each mesh node.
    node_links: Vec<(u32, u32)>,
    /// The same for each cluster.
    cluster_links: Vec<(u32, u32)>,
    /// Parent handle of each mesh node: its parent node, or for a root face its leaf cluster.
    node_parent: Vec<Handle>,
    /// Parent of each cluster ([`NONE`] for the root).
    cluster_parent: Vec<u32>,
}

impl Tree {
    /// `links` sorted by receiver, `rowed` saying which go through the rows.
    fn new(mesh: &Mesh, clusters: &Clusters, links: &[Link], rowed: &[bool]) -> Self {
        let mut node_links = vec![(0, 0); mesh.nodes.len()];
        let mut cluster_links = vec![(0, 0); clusters.nodes.len()];
        let mut members = Vec::new();
        for g in receiver_groups(links) {
            let lo = members.len() as u32;
            members.extend((g.start as u32..g.end as u32).filter(|&k| rowed[k as usize]));
            let range = (lo, members.len() as u32);
            match links[g.start].receiver.end() {
                End::Node(n) => node_links[n] = range,
                End::Cluster(c) => cluster_links[c] = range,
            }
        }
        // Until set below: a cluster past the tree's end, where a chain stops.
        let mut node_parent = vec![Handle::cluster(NONE >> 1); mesh.nodes.len()];
        for (n, node) in mesh.nodes.iter().enumerate() {
            if let Some(c) = node.children {
                for k in c..c + 4 {
                    node_parent[k as usize] = Handle::node(n as u32);
                }
            }
        }
        let mut cluster_parent = vec![NONE; clusters.nodes.len()];
        for (c, cluster) in clusters.nodes.iter().enumerate() {
            match cluster.children {
                Some([a, b]) => {
                    cluster_parent[a as usize] = c as u32;
                    cluster_parent[b as usize] = c as u32;
                }
                None => {
                    let faces = cluster.faces.start as usize..cluster.faces.end as usize;
                    for &f in &clusters.faces[faces] {
                        node_parent[f as usize] = Handle::cluster(c as u32);
                    }
                }
            }
        }
        Self {
            members,
            node_links,
            cluster_links,
            node_parent,
            cluster_parent,
        }
    }

    /// The row links that node `n` gathers through, its own first, then its ancestors' up to
    /// the root cluster.
    fn chain(&self, n: usize, mut visit: impl FnMut(&[u32])) {
        let at = |(lo, hi): (u32, u32)| &self.members[lo as usize..hi as usize];
        let mut h = Handle::node(n as u32);
        loop {
            match h.end() {
                End::Node(k) => {
                    visit(at(self.node_links[k]));
                    h = self.node_parent[k];
                }
                End::Cluster(c) if c < self.cluster_parent.len() => {
                    visit(at(self.cluster_links[c]));
                    match self.cluster_parent[c] {
                        NONE => return,
                        p => h = Handle::cluster(p),
                    }
                }
                End::Cluster(_) => return,
            }
        }
    }
}

/// A link as the elements below it see it ([`judge`]).
#[derive(Clone, Copy, Debug, Default)]
struct Judged {
    /// V_qs: 1 or 0 where both estimates agree on it, their estimate otherwise.
    visibility: f64,
    /// Whether the elements cast their own rays.
    partly: bool,
    /// The factor F_es V_es of an element that is the link's receiver.
    own: f32,
}

/// Link `l`'s visibility for its elements: between two faces, the link's own V_qs = (F_qs
/// V_qs) / F_qs where [`View::fresh_visibility`] agrees that it is wholly visible or wholly
/// hidden, partly hidden otherwise (with the mean of both); with a cluster at either end, the
/// fresh estimate alone (see the module docs).
fn judge(view: &View, l: &Link) -> Judged {
    let f = view.unoccluded(l.receiver, l.source);
    if f <= 0.0 {
        return Judged::default();
    }
    let again = view.fresh_visibility(l.receiver, l.source);
    let partly = |v: f64| v > 0.0 && v < PARTLY;
    let v = if l.receiver.is_cluster() || l.source.is_cluster() {
        again
    } else {
        let own = f64::from(l.factor) / f;
        let clear = own >= PARTLY && again >= PARTLY;
        let hidden = own <= 0.0 && again <= 0.0;
        if clear || hidden {
            return Judged {
                visibility: own,
                partly: false,
                own: l.factor,
            };
        }
        0.5 * (own + again)
    };
    Judged {
        visibility: v,
        partly: partly(v),
        own: (f * v) as f32,
    }
}

impl LeafRows {
    /// Which links go through the rows, within `budget` bytes of entries: every link when all
    /// fit; otherwise those whose receivers hold the fewest elements (a link costs an entry
    /// per element below its receiver), up to the largest such size that fits — the links
    /// nearest the elements, where the factor varies most over a receiver. The rest are
    /// pushed as before. (Every link through the rows cost the furnished room 13 M entries at
    /// ε = 10⁻⁴, and outgrew a gigabyte at 3·10⁻⁶.) A link's cost also counts its source's
    /// pieces ([`PIECES`] at most).
    #[must_use]
    pub fn rowed(mesh: &Mesh, clusters: &Clusters, links: &[Link], budget: u64) -> Vec<bool> {
        let below_face = |f: u32| mesh.nodes[f as usize].elements.len() as u64;
        let below: Vec<u64> = links
            .par_iter()
            .map(|l| match l.receiver.end() {
                End::Node(n) => mesh.nodes[n].elements.len() as u64,
                End::Cluster(c) => {
                    let faces = &clusters.nodes[c].faces;
                    clusters.faces[faces.start as usize..faces.end as usize]
                        .iter()
                        .map(|&f| below_face(f))
                        .sum()
                }
            })
            .collect();
        let mut order: Vec<u64> = below.clone();
        order.sort_unstable();
        let (mut limit, mut bytes) = (0, 0u64);
        for (k, &n) in order.iter().enumerate() {
            bytes += n * BYTES_PER_ENTRY + PIECES as u64 * BYTES_PER_PIECE;
            if bytes > budget {
                break;
            }
            if order.get(k + 1) != Some(&n) {
                limit = n;
            }
        }
        below.iter().map(|&n| n <= limit).collect()
    }

    /// Every element's row over `links` (sorted by receiver), or `None` if `stop` said so on
    /// the way. Each row is its element's alone, so the rows do not depend on the thread count.
    #[must_use]
    pub fn build(
        view: &View,
        links: &[Link],
        rowed: Vec<bool>,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Option<Self> {
        let mesh = view.mesh;
        // A link the cluster kernel cannot resolve has no factor for its elements to take
        // instead of its own: it is pushed.
        let rowed: Vec<bool> = rowed
            .iter()
            .zip(links)
            .map(|(&rowed, l)| rowed && view.resolves(l.receiver, l.source))
            .collect();
        let tree = Tree::new(mesh, view.clusters, links, &rowed);
        // Every link's visibility as its elements take it, whether they cast their own rays,
        // and the factor it gives an element that is its receiver.
        let judged: Vec<Judged> = links
            .par_iter()
            .zip(&rowed)
            .map(|(l, &rowed)| {
                if rowed {
                    judge(view, l)
                } else {
                    Judged::default()
                }
            })
            .collect();
        let hidden: Vec<bool> = judged.iter().map(|j| j.partly).collect();
        let pieces = SourcePieces::build(view, links, &rowed, &hidden, stop)?;
        let row = |n: u32| {
            let own = Handle::node(n);
            let mut row = Vec::new();
            tree.chain(n as usize, |members| {
                for &i in members {
                    let l = &links[i as usize];
                    let i = i as usize;
                    let factor = if l.receiver == own {
                        judged[i].own
                    } else if judged[i].visibility > 0.0 {
                        let f = view.element_factor(own, l.source);
                        let v = if judged[i].partly && f > 0.0 {
                            view.quick_visibility(own, l.source)
                        } else {
                            judged[i].visibility
                        };
                        (f * v) as f32
                    } else {
                        0.0
                    };
                    if factor > 0.0 {
                        row.push((i as u32, factor));
                    }
                }
            });
            row
        };
        let mut out = LeafRows {
            start: Vec::with_capacity(mesh.elements.len() + 1),
            rowed,
            pieces,
            ..LeafRows::default()
        };
        out.start.push(0);
        // A chunk of elements at a time, so that the rows are held once, not twice.
        for chunk in mesh.elements.chunks(CHUNK) {
            if stop() {
                return None;
            }
            let rows: Vec<Vec<(u32, f32)>> = chunk.par_iter().map(|&n| row(n)).collect();
            for row in rows {
                for (link, factor) in row {
                    out.link.push(link);
                    out.factor.push(factor);
                }
                out.start.push(out.link.len());
            }
        }
        Some(out)
    }

    /// Bytes held.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        self.link.len() as u64 * BYTES_PER_ENTRY
            + self.start.len() as u64 * 8
            + self.rowed.len() as u64
            + self.pieces.bytes()
    }

    /// The pieces of the rows' links' sources.
    #[must_use]
    pub fn pieces(&self) -> &SourcePieces {
        &self.pieces
    }

    /// Whether each link goes through the rows (the others are gathered and pushed).
    #[must_use]
    pub fn links(&self) -> &[bool] {
        &self.rowed
    }

    /// Σ F of every element's row.
    #[must_use]
    pub fn sums(&self) -> Vec<f64> {
        self.start
            .windows(2)
            .map(|w| self.factor[w[0]..w[1]].iter().map(|&f| f64::from(f)).sum())
            .collect()
    }

    /// Every element's irradiance Σ F_es V_qs X_l, given what the source of each link l shines
    /// along it, X_l (`shone[l]`).
    #[must_use]
    pub fn gather(&self, shone: &[Rgb]) -> Vec<Rgb> {
        (0..self.start.len() - 1)
            .into_par_iter()
            .map(|k| {
                let range = self.start[k]..self.start[k + 1];
                self.link[range.clone()]
                    .iter()
                    .zip(&self.factor[range])
                    .map(|(&l, &f)| f64::from(f) * shone[l as usize])
                    .sum()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::Bvh;
    use crate::formfactor::analytic::point_to_polygon;
    use crate::formfactor::Receiver;
    use crate::mesh::Subdivision;
    use crate::solve::hierarchical::link::{Estimate, Sight};

    /// The closed unit cube in about 600 elements, with the coarsest links that cover it: every
    /// root face gathers from every other one.
    fn cube() -> (Mesh, Clusters, Bvh, Vec<Link>) {
        let scene = crate::testing::closed_cube(0.5, [1.0; 6]);
        let mesh = Mesh::build(&scene, Subdivision::Elements(600));
        let bvh = Bvh::build(&mesh.triangles);
        let clusters = Clusters::build(&mesh);
        let view = View::new(&mesh, &clusters, &bvh);
        let roots: Vec<u32> = mesh.roots.iter().flat_map(Clone::clone).collect();
        let mut links = Vec::new();
        for &q in &roots {
            for &s in &roots {
                if let Estimate::Link(l) =
                    view.estimate(Handle::node(q), Handle::node(s), Sight::Unknown)
                {
                    links.push(l);
                }
            }
        }
        links.sort_unstable_by_key(|l| (l.receiver, l.source));
        (mesh, clusters, bvh, links)
    }

    #[test]
    fn elements_gather_with_their_own_factors_and_keep_each_links_power() {
        let (mesh, clusters, bvh, links) = cube();
        let view = View::new(&mesh, &clusters, &bvh);
        let rowed = vec![true; links.len()];
        let rows = LeafRows::build(&view, &links, rowed, &|| false).unwrap();
        assert_eq!(rows.start.len(), mesh.elements.len() + 1);
        // Additivity: the area-weighted factors of a link's elements are the link's own
        // A_q F_qs, to the receiver quadratures' difference (measured 0.94 % at most: the root
        // faces' 4 × 4 points give adjacent faces 0.2017, their elements 0.1999, exact 0.2000).
        let mut carried = vec![0.0; links.len()];
        for (k, &e) in mesh.elements.iter().enumerate() {
            let area = mesh.nodes[e as usize].area();
            for i in rows.start[k]..rows.start[k + 1] {
                carried[rows.link[i] as usize] += area * f64::from(rows.factor[i]);
            }
        }
        for (l, &c) in links.iter().zip(&carried) {
            let own = view.area(l.receiver) * f64::from(l.factor);
            assert!((c - own).abs() < 0.012 * own, "{c} vs {own}");
        }
        // Each element's entry is its own factor to the source face: within 1 % of Lambert's
        // kernel integrated over it at 32 × 32 points, where the root's mean (0.2000 between
        // adjacent faces of the cube, 0.1998 between opposite ones) is up to 2× off.
        let mut receiver = Receiver::default();
        let mut farthest_from_mean: f64 = 0.0;
        for (k, &e) in mesh.elements.iter().enumerate() {
            let face = &mesh.nodes[e as usize].face;
            receiver.set(face, 32);
            for i in rows.start[k]..rows.start[k + 1] {
                let l = &links[rows.link[i] as usize];
                let source = l.source.as_node().unwrap();
                let (corners, n) = mesh.nodes[source].face.corners_f64();
                let exact: f64 = receiver
                    .points
                    .iter()
                    .map(|&(x, w)| w * point_to_polygon(x, receiver.normal, &corners[..n]))
                    .sum();
                let f = f64::from(rows.factor[i]);
                assert!((f - exact).abs() < 0.01 * exact, "{f} vs {exact}");
                farthest_from_mean =
                    farthest_from_mean.max((exact / f64::from(l.factor)).ln().abs());
            }
        }
        assert!(farthest_from_mean > 0.5, "{farthest_from_mean}");
        // A closed cube: every element's row sums to one.
        for sum in rows.sums() {
            assert!((sum - 1.0).abs() < 5e-3, "{sum}");
        }
    }

    /// A link that its own rays called wholly visible, or wholly hidden, is taken at its word
    /// only where fresh rays agree: between the half-blocked squares (exactly half hidden) both
    /// claims are judged partly hidden, so the elements cast their own rays; between the open
    /// squares the claim of full sight stands.
    #[test]
    fn fresh_rays_overrule_what_a_links_rays_missed() {
        let judged = |scene: crate::Scene, claim: f64| {
            let mesh = Mesh::build(&scene, Subdivision::Elements(64));
            let bvh = Bvh::build(&mesh.triangles);
            let clusters = Clusters::build(&mesh);
            let view = View::new(&mesh, &clusters, &bvh);
            let (bottom, top) = (mesh.roots[0].start, mesh.roots[1].start);
            let (r, s) = (Handle::node(bottom), Handle::node(top));
            let f = view.unoccluded(r, s);
            let link = Link::new(r, s, (f * claim) as f32, 0.0, Sight::Unknown);
            (judge(&view, &link), f)
        };
        let blocked = crate::testing::half_blocked_squares;
        for claim in [1.0, 0.0] {
            let (j, f) = judged(blocked(), claim);
            assert!(j.partly, "claimed {claim}");
            assert!((j.visibility - (claim + 0.5) / 2.0).abs() < 0.15, "{j:?}");
            assert!(
                (f64::from(j.own) - f * j.visibility).abs() < 1e-6 * f,
                "{j:?}"
            );
        }
        let (j, f) = judged(crate::testing::parallel_squares(1.0), 1.0);
        assert!(!j.partly && j.visibility >= PARTLY, "{j:?}");
        assert!((f64::from(j.own) - f).abs() < 1e-6 * f, "{j:?}");
    }

    #[test]
    fn a_stopped_build_returns_nothing() {
        let (mesh, clusters, bvh, links) = cube();
        let view = View::new(&mesh, &clusters, &bvh);
        let every = vec![true; links.len()];
        assert!(LeafRows::build(&view, &links, every, &|| true).is_none());
        // Every element lies under five links, one from each other face.
        let count = mesh.elements.len() as u64 * 5;
        // Within the budget (the entries and every link's pieces) every link goes through the
        // rows; a byte short, none does (the thirty links hold as many elements each); with
        // room for one link's pieces and two entries, an element's own link goes and its
        // face's link does not.
        let pieces = links.len() as u64 * PIECES as u64 * BYTES_PER_PIECE;
        let all = count * BYTES_PER_ENTRY + pieces;
        assert!(LeafRows::rowed(&mesh, &clusters, &links, all)
            .iter()
            .all(|&r| r));
        assert!(!LeafRows::rowed(&mesh, &clusters, &links, all - 1)
            .iter()
            .any(|&r| r));
        let leaf = Handle::node(mesh.elements[0]);
        let wall = links
            .iter()
            .find(|l| view.unoccluded(leaf, l.source) > 0.0)
            .unwrap();
        let Estimate::Link(own) = view.estimate(leaf, wall.source, Sight::Unknown) else {
            panic!("no link");
        };
        let mut mixed = vec![own, *wall];
        mixed.sort_unstable_by_key(|l| (l.receiver, l.source));
        let budget = PIECES as u64 * BYTES_PER_PIECE + 2 * BYTES_PER_ENTRY;
        let rowed = LeafRows::rowed(&mesh, &clusters, &mixed, budget);
        assert_eq!(
            rowed,
            mixed.iter().map(|l| l.receiver == leaf).collect::<Vec<_>>()
        );
    }
}
