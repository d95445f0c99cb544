//! The refinement oracle and one refinement round.
//!
//! BF refinement (Hanrahan, Salzman & Aupperle 1991, §4): a link from source s to receiver r
//! moves the power B_s·F_rs·A_r. If that exceeds the threshold ε·Φ (Φ the power the emitters deliver to what reflects,
//! [`super::delivered`]) the
//! link is too coarse: the larger of the two sides (by area) is split and the link replaced by
//! links from or to its children, each estimated afresh, recursively. A second test bounds
//! how much the link's factor varies over its receiver: B_s·ΔF·A_r must stay below
//! [`VARIATION`]·ε·Φ, where ΔF is the spread of the factor over the receiver's quadrature points
//! — or the *unoccluded* F when shadow rays found the pair partly or wholly hidden, and F
//! itself when a cluster is involved. A link found wholly hidden is kept, carrying nothing,
//! so that later passes judge it again with the radiosity they have. So links that straddle a
//! shadow boundary, or join elements across a shared edge, are refined further than open
//! ones, which puts small elements along shadow edges and into corners (where a link gathered
//! by a parent would give its children the parent's average factor). A quadtree leaf is split only while its children keep at least the minimum
//! element area and the deepest level is not reached.
//!
//! A receiver that reflects nothing (ρ = 0: an environment's tiles, the default sky, a
//! Mitsuba area light) keeps B = E whatever it gathers; its links serve the power balance
//! alone. So it gets one link per pair it is met in, its factor by rays
//! ([`View::unresolved_factor`]), never refined: refining them split the scene's elements so
//! that each carried a small part of the light a far sky tile of 10³ m² absorbs, and a closed
//! room under a uniform environment took 88 million links.
//!
//! Splitting a leaf of the mesh renumbers the elements ([`Mesh::refine`]), so a round only
//! *collects* the leaves it wants split; the caller splits them all at once and runs another
//! round, in which the pending links descend into the new children. Links are processed in
//! parallel and their outputs concatenated in input order, so the link list after a round
//! does not depend on the thread count.

use rayon::prelude::*;

use super::link::{End, Estimate, Handle, Link, Sight, View};
use crate::mesh::{Mesh, MAX_LEVEL};

/// The largest share of a receiving cluster's radiosity one link may bring
/// ([`Oracle::pushes_unevenly`]).
pub const PUSH: f64 = 0.1;

/// The fewest pairs of root faces an unresolved pair must stand for to be kept as one link
/// ([`Refiner::unresolved`]); smaller ones are opened to faces, whose links are exact.
pub const UNRESOLVED_PAIRS: u64 = 256;

/// The variation test's threshold, as a fraction of the power threshold.
pub const VARIATION: f64 = 0.125;

/// Refinement thresholds and the current radiosity of every handle.
#[derive(Clone, Copy, Debug)]
pub struct Oracle<'a> {
    /// ε·Φ: the most power one link may move.
    pub threshold: f64,
    /// The smallest element area a split may create.
    pub min_area: f64,
    /// Radiosity (largest channel) of every mesh node.
    pub node_b: &'a [f64],
    /// Max − min of the radiosity (largest channel) over the leaves below every mesh node.
    pub node_spread: &'a [f64],
    /// Radiosity (largest channel) of every cluster.
    pub cluster_b: &'a [f64],
}

impl Oracle<'_> {
    /// The radiosity (largest channel) of a handle.
    fn radiosity(&self, h: Handle) -> f64 {
        match h.end() {
            End::Cluster(c) => self.cluster_b[c],
            End::Node(n) => self.node_b[n],
        }
    }

    /// Whether the link moves too much power (B_s·F·A_r), or too uncertain a part of it.
    fn too_coarse(&self, view: &View, l: &Link) -> bool {
        let b = self.radiosity(l.source);
        let scale = b * view.area(l.receiver);
        scale * f64::from(l.factor) > self.threshold
            || scale * f64::from(l.spread()) > self.threshold * VARIATION
    }

    /// Whether the source of `l` is a split face whose leaves' radiosities differ so much that
    /// its mean misstates what it sends: ΔB_s·F·A_r above the variation threshold. BF
    /// refinement judges a link by the source's mean B alone, so a face split across a
    /// shadow edge sent every receiver the mean of its lit and shadowed parts. Measured on
    /// `benches/suite` at ε = 10⁻⁴ (docs/decisions/hierarchical-rows.md): closed-mesh +3.3 % →
    /// −1.8 %, cornell-faces −4.3 % → −3.5 %, obj-box +4.4 % → +3.6 %; the furnished room's
    /// ball (+6.9 %) did not move.
    fn source_varies(&self, view: &View, l: &Link) -> bool {
        l.source.as_node().is_some_and(|s| {
            self.node_spread[s] * f64::from(l.factor) * view.area(l.receiver)
                > self.threshold * VARIATION
        })
    }

    /// Whether a cluster receives through `l` so much of its light that pushing it to all its
    /// faces alike would show: B_s·F > [`PUSH`]·B_r. A cluster spreads what it gathers evenly
    /// over its faces, also those turned away from the source; that is harmless for a trickle
    /// of indirect light and visibly wrong for a lamp (blotches on the teapot), so such links
    /// are split on the receiver side until they reach faces. In the first pass (B = E) every
    /// emitter's links reach faces this way.
    fn pushes_unevenly(&self, l: &Link) -> bool {
        if !l.receiver.is_cluster() {
            return false;
        }
        let b = self.radiosity(l.source);
        b * f64::from(l.factor) > PUSH * self.radiosity(l.receiver)
    }

    /// Whether a handle can be split: clusters and split faces always, leaves while their
    /// children stay above the minimum area and below the deepest level.
    fn splittable(mesh: &Mesh, min_area: f64, h: Handle) -> bool {
        let End::Node(n) = h.end() else {
            return true;
        };
        let node = &mesh.nodes[n];
        node.children.is_some() || (node.level < MAX_LEVEL && node.area() >= 4.0 * min_area)
    }
}

/// What a round produces.
#[derive(Debug, Default)]
pub struct Round {
    /// The new link list.
    pub links: Vec<Link>,
    /// Leaves to split before the next round (sorted, without repeats).
    pub splits: Vec<u32>,
    /// Links replaced by finer ones in this round.
    pub refined: u64,
}

impl Round {
    fn append(mut self, mut other: Round) -> Round {
        self.links.append(&mut other.links);
        self.splits.append(&mut other.splits);
        self.refined += other.refined;
        self
    }
}

/// One refinement round over `links`. `force` lists receivers (sorted) whose links must be
/// split on the receiver side whatever they move (the display criterion). Once `stop` says so
/// the round skips the work left: the caller must then discard it.
#[must_use]
pub fn round(
    view: &View,
    oracle: &Oracle,
    links: &[Link],
    force: &[Handle],
    stop: &(dyn Fn() -> bool + Sync),
) -> Round {
    let mut out = links
        .par_iter()
        .fold(Round::default, |mut acc, l| {
            let split = if force.binary_search(&l.receiver).is_ok() {
                Split::Receiver
            } else {
                Split::AsJudged
            };
            Refiner { view, oracle, stop }.link(*l, split, &mut acc);
            acc
        })
        .reduce(Round::default, Round::append);
    out.splits.sort_unstable();
    out.splits.dedup();
    out
}

/// The first links: the root cluster with itself, refined as far as the oracle asks (or until
/// `stop` says so, as for [`round`]).
#[must_use]
pub fn start(view: &View, oracle: &Oracle, stop: &(dyn Fn() -> bool + Sync)) -> Round {
    let mut out = Round::default();
    if !view.clusters.nodes.is_empty() {
        let root = Handle::ROOT_CLUSTER;
        Refiner { view, oracle, stop }.pair(root, root, Sight::Unknown, &mut out);
    }
    out.splits.sort_unstable();
    out.splits.dedup();
    out
}

/// The recursive refinement of one link.
struct Refiner<'v, 'a> {
    view: &'v View<'a>,
    oracle: &'v Oracle<'a>,
    /// Whether to give up (Ctrl-C): checked before each link and pair.
    stop: &'v (dyn Fn() -> bool + Sync),
}

/// Which side of a link to split.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    Receiver,
    Source,
}

/// Whether a link's receiver is split whatever the oracle says: the display passes' steep
/// elements ([`round`]'s `force`).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Split {
    /// As the oracle judges.
    AsJudged,
    /// The receiver, if it can be.
    Receiver,
}

impl Refiner<'_, '_> {
    /// Keeps `l`, or replaces it by finer links, or keeps it pending a leaf split.
    fn link(&self, l: Link, split: Split, acc: &mut Round) {
        if (self.stop)() {
            return;
        }
        if !self.view.reflects(l.receiver) {
            // What it gathers changes no radiosity (module docs): kept as it is.
            acc.links.push(l);
            return;
        }
        let can = |h| Oracle::splittable(self.view.mesh, self.oracle.min_area, h);
        let forced = split == Split::Receiver;
        let side = if (forced || self.oracle.pushes_unevenly(&l)) && can(l.receiver) {
            Some(Side::Receiver)
        } else if self.oracle.source_varies(self.view, &l) {
            Some(Side::Source)
        } else if !self.oracle.too_coarse(self.view, &l) {
            None
        } else {
            match (can(l.receiver), can(l.source)) {
                (true, true) => {
                    if self.view.area(l.receiver) >= self.view.area(l.source) {
                        Some(Side::Receiver)
                    } else {
                        Some(Side::Source)
                    }
                }
                (true, false) => Some(Side::Receiver),
                (false, true) => Some(Side::Source),
                (false, false) => None,
            }
        };
        let Some(side) = side else {
            // Kept even when shadow rays found it wholly hidden: the radiosity it is judged by
            // changes between passes (the first pass has B = E, so every link from a surface
            // that does not emit looks weak), and a dropped link is never judged again. Dropping
            // them lost the light that reaches a room through a door: its far walls came out 27 %
            // dark at any ε.
            acc.links.push(l);
            return;
        };
        let h = if side == Side::Receiver {
            l.receiver
        } else {
            l.source
        };
        let leaf = h
            .as_node()
            .filter(|&n| self.view.mesh.nodes[n].children.is_none());
        if let Some(n) = leaf {
            acc.splits.push(n as u32);
            acc.links.push(l);
            return;
        }
        acc.refined += 1;
        self.expand(l.receiver, l.source, side, l.sight(), acc);
    }

    /// Links from or to the children of one side of the pair (r, s), whose visibility is
    /// known as `sight`.
    fn expand(&self, r: Handle, s: Handle, side: Side, sight: Sight, acc: &mut Round) {
        let mut children = Vec::with_capacity(4);
        self.view
            .children(if side == Side::Receiver { r } else { s }, &mut children);
        let pair = |c: Handle| {
            if side == Side::Receiver {
                (c, s)
            } else {
                (r, c)
            }
        };
        if (r.is_cluster() || s.is_cluster()) && children.len() > 1 {
            let more = children
                .par_iter()
                .fold(Round::default, |mut acc, &c| {
                    let (r, s) = pair(c);
                    self.pair(r, s, sight, &mut acc);
                    acc
                })
                .reduce(Round::default, Round::append);
            *acc = std::mem::take(acc).append(more);
        } else {
            for c in children {
                let (r, s) = pair(c);
                self.pair(r, s, sight, acc);
            }
        }
    }

    /// A pair the cluster kernel cannot estimate ([`View::resolves`]: overlapping spheres, a
    /// cluster with itself) kept as one link while even the most it could move,
    /// B_s·A_r·F_max with F_max = min(1, A_s/A_r) (F ≤ 1, and A_r F_rs = A_s F_sr ≤ A_s),
    /// stays below the variation threshold. Its factor is estimated by rays
    /// ([`View::unresolved_factor`]), its spread is F_max, and later passes open it as soon as
    /// the radiosity they have makes it matter (the module [`super::link`]'s `unresolved`
    /// says why).
    fn unresolved(&self, r: Handle, s: Handle) -> Option<Link> {
        let faces = |h: Handle| match h.end() {
            End::Cluster(c) => self.view.clusters.nodes[c].faces.len() as u64,
            End::Node(_) => 1,
        };
        if faces(r) * faces(s) < UNRESOLVED_PAIRS {
            return None;
        }
        let most = (self.view.area(s) / self.view.area(r)).min(1.0);
        let bound = Link::new(r, s, 0.0, most as f32, Sight::Unknown);
        if !most.is_finite() || self.oracle.too_coarse(self.view, &bound) {
            return None;
        }
        let factor = self.view.unresolved_factor(r, s) as f32;
        Some(Link::new(r, s, factor, most as f32, Sight::Unknown))
    }

    /// Estimates a new pair and refines it as far as it needs.
    fn pair(&self, r: Handle, s: Handle, sight: Sight, acc: &mut Round) {
        if (self.stop)() {
            return;
        }
        if self.view.distant(s) {
            // Its light is gathered along rays ([`super::distant`]).
            return;
        }
        if !self.view.reflects(r) {
            // A receiver that reflects nothing (an environment's tiles): one link, by rays,
            // whatever the pair, for the power balance alone.
            if r != s || r.is_cluster() {
                let factor = self.view.unresolved_factor(r, s) as f32;
                acc.links.push(Link::new(r, s, factor, 0.0, Sight::Unknown));
            }
            return;
        }
        if r == s {
            // A cluster with itself: every pair of its children (a face never lights itself).
            if !r.is_cluster() || self.view.coplanar(r, r) {
                return;
            }
            if let Some(l) = self.unresolved(r, s) {
                acc.links.push(l);
                return;
            }
            let mut children = Vec::with_capacity(4);
            self.view.children(r, &mut children);
            let pairs: Vec<(Handle, Handle)> = children
                .iter()
                .flat_map(|&a| children.iter().map(move |&b| (a, b)))
                .collect();
            let more = pairs
                .par_iter()
                .fold(Round::default, |mut acc, &(a, b)| {
                    self.pair(a, b, Sight::Unknown, &mut acc);
                    acc
                })
                .reduce(Round::default, Round::append);
            *acc = std::mem::take(acc).append(more);
            return;
        }
        match self.view.estimate(r, s, sight) {
            Estimate::Nothing => {}
            Estimate::Link(l) => self.link(l, Split::AsJudged, acc),
            Estimate::Open => {
                if let Some(l) = self.unresolved(r, s) {
                    acc.links.push(l);
                    return;
                }
                // Open the cluster side (the larger sphere when both are clusters).
                let side = match (r.is_cluster(), s.is_cluster()) {
                    (true, true) => {
                        if self.view.sphere(r).1 >= self.view.sphere(s).1 {
                            Side::Receiver
                        } else {
                            Side::Source
                        }
                    }
                    (true, false) => Side::Receiver,
                    _ => Side::Source,
                };
                self.expand(r, s, side, Sight::Unknown, acc);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicUsize, Ordering};

    use super::super::cluster::Clusters;
    use super::super::push_pull::State;
    use super::super::{brightness, spread};
    use super::*;
    use crate::accel::Bvh;
    use crate::mesh::Subdivision;

    /// The scene as the hierarchical solver meshes it, root faces only, with its clusters
    /// and visibility structure.
    fn root_faces(scene: &crate::scene::Scene) -> (Mesh, Clusters, Bvh) {
        let mesh = Mesh::build(scene, Subdivision::MaxArea(f64::INFINITY));
        let bvh = Bvh::build(&mesh.triangles);
        let clusters = Clusters::build(&mesh);
        (mesh, clusters, bvh)
    }

    /// The radiosity of every node, its spread and every cluster's, as the first pass sees
    /// them (B = E).
    fn first_pass(mesh: &Mesh, clusters: &Clusters, bvh: &Bvh) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let state = State::new(mesh, clusters, bvh);
        let (node_b, cluster_b) = brightness(&state);
        let node_spread = spread(mesh, &node_b);
        (node_b, node_spread, cluster_b)
    }

    /// Ctrl-C must not wait for a refinement round (minutes on large scenes at small ε): a
    /// round asks its stop question before every link, and once told to stop does no more.
    /// Counting the questions states this without a clock.
    #[test]
    fn a_round_asks_whether_to_stop_before_each_link_and_skips_the_rest_when_told() {
        // The closed cube glowing on every face, as the first pass sees it (B = E), root
        // faces only, as the hierarchical solver meshes it.
        let (mesh, clusters, bvh) = root_faces(&crate::testing::closed_cube(0.5, [1.0; 6]));
        let (node_b, node_spread, cluster_b) = first_pass(&mesh, &clusters, &bvh);
        // A link may move a thousandth of the cube's emitted power (6 m² at B = 1): the
        // face-to-face links are far coarser than that.
        let oracle = Oracle {
            threshold: 1e-3 * mesh.total_area(),
            min_area: mesh.total_area() * 1e-6,
            node_b: &node_b,
            node_spread: &node_spread,
            cluster_b: &cluster_b,
        };
        let view = View::new(&mesh, &clusters, &bvh);
        let asked = AtomicUsize::new(0);
        let counting = || {
            asked.fetch_add(1, Ordering::SeqCst);
            false
        };
        let first = start(&view, &oracle, &counting);
        assert!(!first.links.is_empty() && !first.splits.is_empty());
        assert!(asked.load(Ordering::SeqCst) >= first.links.len());
        asked.store(0, Ordering::SeqCst);
        let next = round(&view, &oracle, &first.links, &[], &counting);
        assert!(!next.links.is_empty());
        assert!(asked.load(Ordering::SeqCst) >= first.links.len());
        // Told to stop, neither makes a link nor asks for a split.
        let stopped = start(&view, &oracle, &|| true);
        assert!(stopped.links.is_empty() && stopped.splits.is_empty());
        let stopped = round(&view, &oracle, &first.links, &[], &|| true);
        assert!(stopped.links.is_empty() && stopped.splits.is_empty());
    }

    /// A glowing floor of 24 × 24 quads, one object, lying in one plane but for a corner
    /// lifted by `tilt`: the hierarchical solver's view of it, root faces only.
    fn floor(tilt: f32) -> (Mesh, Clusters, Bvh) {
        use crate::scene::{Material, Object, Polygon, Scene};
        let n = 24;
        let mut polygons = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (x, z) = (i as f32, j as f32);
                // Counter-clockwise seen from above: facing +y. `tilt` lifts one corner of
                // the last quad out of the plane.
                let lift = if i == n - 1 && j == n - 1 { tilt } else { 0.0 };
                polygons.push(Polygon {
                    vertices: vec![
                        glam::Vec3::new(x, 0.0, z),
                        glam::Vec3::new(x, 0.0, z + 1.0),
                        glam::Vec3::new(x + 1.0, lift, z + 1.0),
                        glam::Vec3::new(x + 1.0, 0.0, z),
                    ],
                    material: 0,
                    object: 0,
                    uv: None,
                });
            }
        }
        let scene = Scene {
            materials: vec![Material {
                emission: crate::Rgb::ONE,
                ..Material::default()
            }],
            objects: vec![Object {
                name: "floor".into(),
            }],
            polygons,
            ..Scene::default()
        };
        root_faces(&scene)
    }

    /// Faces in one plane never see each other, so a tessellated floor's clusters, with
    /// themselves and with each other, exchange nothing: the refinement makes no link and
    /// opens no cluster of it, however bright it is. Before, their overlapping bounding
    /// spheres made it open them down to every neighbouring pair of faces (the staircase's
    /// walls and steps gave tens of millions of such empty pairs), which a floor with one
    /// corner lifted out of the plane still needs.
    #[test]
    fn a_flat_tessellated_floor_is_not_opened_against_itself() {
        let examined = |tilt: f32| {
            let (mesh, clusters, bvh) = floor(tilt);
            let (node_b, node_spread, cluster_b) = first_pass(&mesh, &clusters, &bvh);
            let oracle = Oracle {
                threshold: 1e-4 * mesh.total_area(),
                min_area: mesh.total_area() * 1e-6,
                node_b: &node_b,
                node_spread: &node_spread,
                cluster_b: &cluster_b,
            };
            let view = View::new(&mesh, &clusters, &bvh);
            let asked = AtomicUsize::new(0);
            let counting = || {
                asked.fetch_add(1, Ordering::SeqCst);
                false
            };
            let round = start(&view, &oracle, &counting);
            (
                view.coplanar(Handle::ROOT_CLUSTER, Handle::ROOT_CLUSTER),
                round.links.len(),
                asked.into_inner(),
            )
        };
        let (flat, links, asked) = examined(0.0);
        assert!(flat);
        assert_eq!(
            (links, asked),
            (0, 1),
            "the root cluster with itself, and no more"
        );
        // A corner 0.1 units out of the plane: the floor is no longer one plane, and the
        // lifted quad does see its neighbours.
        let (flat, links, asked) = examined(0.1);
        assert!(!flat);
        assert!(links > 0 && asked > 100, "{links} links, {asked} pairs");
    }
}
