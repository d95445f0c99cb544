//! Gathering over links, and push-pull through the hierarchy.
//!
//! One iteration (Hanrahan, Salzman & Aupperle 1991, §5):
//!
//! 1. **Gather**: every handle r collects the irradiance H_r = Σ_links F_rs V_rs B_s of the
//!    links it receives; links are sorted by receiver and each receiver's sum is sequential,
//!    receivers in parallel, so the sums do not depend on the thread count.
//! 2. **Push**: irradiance is per unit area, so a node's children receive it unchanged:
//!    H_total(child) = H(child) + H_total(parent), from the root cluster down to the elements
//!    (an isotropic cluster gives every member face the same irradiance). An element's new
//!    radiosity is B = E + ρ H_total.
//! 3. **Pull**: every node's B is the area-weighted mean of its children's,
//!    B_p = Σ A_c B_c / A_p, from the elements up to the root cluster.
//!
//! In the arenas a parent always has a smaller index than its children (nodes and clusters
//! are appended below existing ones), so the push is one forward pass and the pull one
//! backward pass.
//!
//! **Clusters are directional.** A cluster is a bag of faces turned every way: the two sides of
//! a two-sided floor, the outside and inside of an open box. Pushing a cluster's irradiance
//! evenly onto all of them lights faces turned away from the source, and a cluster's mean B
//! shines the dark back sides' zero into the room and the lit fronts' light out of its back
//! (a bare OBJ room, every face two-sided, lost half its light that way and came out 56 %
//! too dark). So light crosses a cluster link with its direction (Sillion 1995, Smits et al.
//! 1994 §4.2 treat clusters as directional emitters and receivers): with the six axis
//! weights w_k(ω) = max(0, ω·e_k) and each cluster's facing areas D_k = Σ_f A_f max(0, n_f·e_k)
//! ([`super::cluster::axis_weights`]),
//!
//! - a source cluster shines toward ω the mean B of the faces that face ω,
//!   B(ω) = Σ_k w_k N_k / Σ_k w_k D_k with N_k = Σ_f A_f B_f max(0, n_f·e_k) (pulled up like
//!   B), and nothing at all where no face faces ω;
//! - the power Φ a receiving cluster gathers from direction ω goes to its faces in proportion
//!   to A_f max(0, n_f·ω) ≈ A_f Σ_k w_k(ω) max(0, n_f·e_k): it accumulates
//!   Q_k += Φ w_k / Σ_j w_j D_j, which pushes down unchanged, and a face receives the
//!   irradiance Σ_k Q_k max(0, n_f·e_k). Energy is kept: Σ_f A_f H_f = Σ_k Q_k D_k = Φ.
//!
//! The direction of a link is between the centres of its two ends.

use rayon::prelude::*;

use glam::DVec3;

use super::cluster::{axis_weights, Clusters};
use super::distant;
use super::leaf_rows::LeafRows;
use super::link::{receiver_groups, resolved, End, Handle, Link};
use crate::accel::Bvh;
use crate::formfactor::exposure::open_fraction;
use crate::mesh::Mesh;
use crate::solve::first_shot;
use crate::Rgb;

/// The largest gain ρ Σ F an element may have ([`State::bury_rows`]): below 1, so that no
/// group of elements amplifies the light it passes around.
pub const GAIN: f64 = 0.99;

/// Six RGB values, one per axis direction (+x, −x, +y, −y, +z, −z).
pub type Directional = [Rgb; 6];

/// Radiosity and irradiance of every node and cluster.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct State {
    /// B of every mesh node (leaves: the element's; others: the mean below).
    pub node_b: Vec<Rgb>,
    /// Irradiance gathered by every mesh node's own links, then pushed (total) during an
    /// iteration.
    pub node_h: Vec<Rgb>,
    /// Area of every mesh node.
    pub node_area: Vec<f64>,
    /// Open fraction u of every leaf as the probes of [`crate::formfactor::exposure`] find it
    /// (0 for interior nodes).
    pub node_probed: Vec<f64>,
    /// Open area A·u of every mesh node ([`State::bury`]), summed over the leaves below an
    /// interior node.
    pub node_open: Vec<f64>,
    /// The radiosity every mesh node shines from its open part (see [`State::pull`]).
    pub node_shine: Vec<Rgb>,
    /// The irradiance every leaf takes along rays, from a distant environment
    /// ([`super::distant`]) and the point luminaires ([`crate::solve::first_shot`]); zero for
    /// interior nodes and without either.
    pub node_sky: Vec<Rgb>,
    /// The factor by which every element's gathered irradiance is scaled so that its gain
    /// ρ Σ F stays below 1 ([`State::bury_rows`]); 1 for most, and for interior nodes.
    pub node_gain: Vec<f64>,
    /// B of every cluster (the area-weighted mean of its faces).
    pub cluster_b: Vec<Rgb>,
    /// N_k of every cluster: power leaving its faces weighted by how much they face e_k.
    pub cluster_n: Vec<Directional>,
    /// Irradiance of every cluster that no face of it faces (spread evenly).
    pub cluster_h: Vec<Rgb>,
    /// Q_k of every cluster: directional irradiance, per unit of facing area.
    pub cluster_q: Vec<Directional>,
}

impl State {
    /// B = E everywhere, pulled up.
    #[must_use]
    pub fn new(mesh: &Mesh, clusters: &Clusters, bvh: &Bvh) -> Self {
        let n = clusters.nodes.len();
        let mut s = State {
            cluster_b: vec![Rgb::ZERO; n],
            cluster_n: vec![[Rgb::ZERO; 6]; n],
            cluster_h: vec![Rgb::ZERO; n],
            cluster_q: vec![[Rgb::ZERO; 6]; n],
            ..State::default()
        };
        s.grow(mesh, bvh);
        // B starts as E plus the light taken along rays (the first shot): the first pass's
        // links then start from every surface the luminaires or the sky light.
        for &n in &mesh.elements {
            let patch = &mesh.patches[mesh.nodes[n as usize].patch as usize];
            s.node_b[n as usize] = patch.emission + patch.reflectance * s.node_sky[n as usize];
        }
        s.pull(mesh, clusters);
        s
    }

    /// Extends the arrays to new nodes of `mesh`; a new node starts with its parent's B and
    /// its probed open fraction, and open area, until [`State::bury`] judges them with the
    /// links.
    pub fn grow(&mut self, mesh: &Mesh, bvh: &Bvh) {
        let old = self.node_area.len();
        let n = mesh.nodes.len();
        self.node_b.resize(n, Rgb::ZERO);
        self.node_h.resize(n, Rgb::ZERO);
        self.node_shine.resize(n, Rgb::ZERO);
        self.node_gain.resize(n, 1.0);
        self.node_area
            .extend(mesh.nodes[old..].iter().map(|k| k.area()));
        let leaves: Vec<u32> = (old as u32..n as u32)
            .filter(|&k| mesh.nodes[k as usize].children.is_none())
            .collect();
        let probed = open_fraction(mesh, bvh, &leaves);
        let sky = distant::irradiance(mesh, bvh, &leaves);
        let shot = first_shot::irradiance(mesh, bvh, &leaves);
        self.node_sky.resize(n, Rgb::ZERO);
        for ((&k, h), l) in leaves.iter().zip(sky).zip(shot) {
            self.node_sky[k as usize] = h + l;
        }
        for p in 0..old {
            if mesh.nodes[p].children.is_some() {
                self.node_sky[p] = Rgb::ZERO;
            }
        }
        self.node_probed.resize(n, 0.0);
        self.node_open.resize(n, 0.0);
        for (&k, u) in leaves.iter().zip(probed) {
            self.node_probed[k as usize] = u;
            self.node_open[k as usize] = self.node_area[k as usize] * u;
        }
        self.sum_open(mesh);
        for p in 0..old {
            if let Some(c) = mesh.nodes[p].children {
                if c as usize >= old {
                    for k in c..c + 4 {
                        self.node_b[k as usize] = self.node_b[p];
                    }
                }
            }
        }
        self.pull_nodes(mesh);
    }

    /// The open fraction of every leaf for gathering, as the gathering solvers read it
    /// ([`crate::solve`]'s `bury`): the probed u, never below the leaf's row sum Σ F over
    /// the links it gathers through (its own and its ancestors'), so that the gain ρ Σ F / u
    /// stays below 1 however the probes and the shadow rays disagree; 0 where that row is empty
    /// and the leaf does not emit (it sees nothing at all: the floor under a block).
    pub fn bury(&mut self, mesh: &Mesh, clusters: &Clusters, links: &[Link]) {
        let rows = self.link_rows(mesh, clusters, links, None);
        self.bury_rows(mesh, &rows);
    }

    /// Every element's row sum Σ F through the push of `links` (a radiosity of one gathered
    /// and pushed), in the order of [`Mesh::elements`]; links marked in `skip` left out.
    #[must_use]
    pub fn link_rows(
        &self,
        mesh: &Mesh,
        clusters: &Clusters,
        links: &[Link],
        skip: Option<&[bool]>,
    ) -> Vec<f64> {
        let n = mesh.nodes.len();
        let mut unit = State {
            node_b: Vec::new(),
            node_h: vec![Rgb::ZERO; n],
            node_area: self.node_area.clone(),
            node_probed: Vec::new(),
            node_open: Vec::new(),
            node_shine: vec![Rgb::ONE; n],
            node_sky: Vec::new(),
            node_gain: Vec::new(),
            cluster_b: vec![Rgb::ONE; clusters.nodes.len()],
            cluster_n: clusters
                .nodes
                .iter()
                .map(|c| c.facing.map(Rgb::splat))
                .collect(),
            cluster_h: vec![Rgb::ZERO; clusters.nodes.len()],
            cluster_q: vec![[Rgb::ZERO; 6]; clusters.nodes.len()],
        };
        unit.gather(mesh, clusters, links, skip);
        unit.push(mesh, clusters);
        mesh.elements
            .iter()
            .map(|&e| unit.node_h[e as usize].x)
            .collect()
    }

    /// [`State::bury`] with every element's row sum Σ F given (`rows`, in the order of
    /// [`Mesh::elements`]); and every element's gain factor.
    ///
    /// A row of form factors sums to at most 1 (the hemisphere), but a link gathered by a
    /// parent gives every child the parent's mean factor, so single rows overshoot where the
    /// factor varies over the receiver (up to 1.6 on the furnished room, 1.9 on veach-ajar's
    /// door handle), and their neighbours undershoot: over an object, rows mostly balance.
    /// Where an overshooting row makes the element's gain ρ Σ F (largest channel) exceed 1,
    /// the element amplifies what it gathers, and a group of such elements made the gather
    /// diverge (veach-ajar at ε = 3·10⁻⁵, to NaN). Their gathered irradiance is scaled so that
    /// the gain is [`GAIN`]; the other rows are left as they are. The price is a bias where
    /// many rows are capped: a closed room of ρ = 0.95 with a faceted ball in it absorbs 0.983
    /// of what it emits at ε = 10⁻⁵ (1.006 uncapped) and 1.002 at ε = 10⁻⁴ (0.999); scaling
    /// every overshooting row to 1 instead gave 0.961 (the undershooting rows that balance
    /// them keep their deficit).
    pub fn bury_rows(&mut self, mesh: &Mesh, rows: &[f64]) {
        for (&e, &row) in mesh.elements.iter().zip(rows) {
            let e = e as usize;
            let patch = &mesh.patches[mesh.nodes[e].patch as usize];
            let rho = patch.reflectance.max_element();
            self.node_gain[e] = if rho * row > GAIN {
                GAIN / (rho * row)
            } else {
                1.0
            };
            let emits = patch.emission != Rgb::ZERO;
            let u = if !emits && row == 0.0 {
                0.0
            } else {
                self.node_probed[e].max(row).min(1.0)
            };
            self.node_open[e] = self.node_area[e] * u;
        }
        self.sum_open(mesh);
        self.pull_nodes(mesh);
    }

    /// The open area of every interior node from its children's, bottom up.
    fn sum_open(&mut self, mesh: &Mesh) {
        for k in (0..mesh.nodes.len()).rev() {
            if let Some(c) = mesh.nodes[k].children {
                self.node_open[k] = (c..c + 4).map(|j| self.node_open[j as usize]).sum();
            }
        }
    }

    /// One gather, push and pull. Returns Σ_e A_e ‖ΔB_e‖₁ over the elements.
    pub fn iterate(&mut self, mesh: &Mesh, clusters: &Clusters, links: &[Link]) -> f64 {
        self.gather(mesh, clusters, links, None);
        self.push(mesh, clusters);
        self.add_sky(mesh);
        // New element radiosities, in parallel (each from its own node only).
        let new: Vec<Rgb> = mesh
            .elements
            .par_iter()
            .map(|&n| {
                let node = &mesh.nodes[n as usize];
                let patch = &mesh.patches[node.patch as usize];
                patch.emission
                    + patch.reflectance * (self.node_h[n as usize] * self.node_gain[n as usize])
            })
            .collect();
        let mut change = 0.0;
        for (&n, b) in mesh.elements.iter().zip(new) {
            change +=
                self.node_area[n as usize] * (b - self.node_b[n as usize]).abs().element_sum();
            self.node_b[n as usize] = b;
        }
        self.pull(mesh, clusters);
        change
    }

    /// Adds every element's irradiance from the distant environment to what its links
    /// brought (after the push).
    fn add_sky(&mut self, mesh: &Mesh) {
        for &e in &mesh.elements {
            self.node_h[e as usize] += self.node_sky[e as usize];
        }
    }

    /// Push: clusters, then root faces, then quadtree nodes in index order.
    fn push(&mut self, mesh: &Mesh, clusters: &Clusters) {
        for c in 0..clusters.nodes.len() {
            let (down, q) = (self.cluster_h[c], self.cluster_q[c]);
            match clusters.nodes[c].children {
                Some([a, b]) => {
                    for k in [a as usize, b as usize] {
                        self.cluster_h[k] += down;
                        for (x, y) in self.cluster_q[k].iter_mut().zip(q) {
                            *x += y;
                        }
                    }
                }
                None => {
                    let range = clusters.nodes[c].faces.clone();
                    let range = range.start as usize..range.end as usize;
                    for (&f, weights) in clusters.faces[range.clone()]
                        .iter()
                        .zip(&clusters.face_facing[range])
                    {
                        let per_area = 1.0 / self.node_area[f as usize].max(f64::MIN_POSITIVE);
                        let facing: Rgb =
                            weights.iter().zip(q).map(|(w, q)| q * (w * per_area)).sum();
                        self.node_h[f as usize] += down + facing;
                    }
                }
            }
        }
        for n in 0..mesh.nodes.len() {
            if let Some(c) = mesh.nodes[n].children {
                let down = self.node_h[n];
                for k in c..c + 4 {
                    self.node_h[k as usize] += down;
                }
            }
        }
    }

    /// The irradiance each element gathers, through `links`, from the emission alone (every
    /// leaf's radiosity set to its E, pulled, gathered and pushed): the direct part of
    /// [`State::element_irradiance`], which the evaluated picture replaces by its own exact
    /// direct light (`Solution::reflected_irradiance`).
    /// With `rows`, the gather goes through the elements' own rows.
    #[must_use]
    pub fn emitted_irradiance(
        &self,
        mesh: &Mesh,
        clusters: &Clusters,
        links: &[Link],
        rows: Option<&LeafRows>,
    ) -> Vec<Rgb> {
        let mut lit = self.clone();
        for &n in &mesh.elements {
            let patch = &mesh.patches[mesh.nodes[n as usize].patch as usize];
            lit.node_b[n as usize] = patch.emission;
        }
        lit.pull(mesh, clusters);
        if let Some(rows) = rows {
            let h = lit.gather_rows(mesh, clusters, links, rows);
            return mesh
                .elements
                .iter()
                .zip(h)
                .map(|(&n, h)| h * self.node_gain[n as usize])
                .collect();
        }
        lit.gather(mesh, clusters, links, None);
        lit.push(mesh, clusters);
        lit.add_sky(mesh);
        lit.element_irradiance(mesh)
    }

    /// The irradiance that each element received in the last iteration (after the push), as
    /// its radiosity took it (times its gain factor).
    #[must_use]
    pub fn element_irradiance(&self, mesh: &Mesh) -> Vec<Rgb> {
        mesh.elements
            .iter()
            .map(|&n| self.node_h[n as usize] * self.node_gain[n as usize])
            .collect()
    }

    /// H of every handle from its own links (links sorted by receiver), with the direction of
    /// each cluster link (module docs).
    /// Links marked in `skip` (the rows' links, [`LeafRows::links`]) are left out.
    fn gather(&mut self, mesh: &Mesh, clusters: &Clusters, links: &[Link], skip: Option<&[bool]>) {
        self.node_h.fill(Rgb::ZERO);
        self.cluster_h.fill(Rgb::ZERO);
        self.cluster_q.fill([Rgb::ZERO; 6]);
        let groups = receiver_groups(links);
        let sums: Vec<(Rgb, Directional)> = groups
            .par_iter()
            .map(|g| {
                let r = links[g.start].receiver;
                let mut scalar = Rgb::ZERO;
                let mut q = [Rgb::ZERO; 6];
                for (i, l) in links[g.clone()].iter().enumerate() {
                    if skip.is_some_and(|skip| skip[g.start + i]) {
                        continue;
                    }
                    let out = direction(mesh, clusters, r, l.source);
                    let h = f64::from(l.factor) * self.shone(clusters, l.source, out);
                    let End::Cluster(c) = r.end() else {
                        scalar += h;
                        continue;
                    };
                    let w = axis_weights(-out);
                    match toward(clusters, c, &w) {
                        Some(den) => {
                            let power = h * clusters.nodes[c].area;
                            for (qk, wk) in q.iter_mut().zip(w) {
                                *qk += power * (wk / den);
                            }
                        }
                        None => scalar += h,
                    }
                }
                (scalar, q)
            })
            .collect();
        for (g, (h, q)) in groups.iter().zip(sums) {
            match links[g.start].receiver.end() {
                End::Cluster(c) => {
                    self.cluster_h[c] = h;
                    self.cluster_q[c] = q;
                }
                End::Node(n) => self.node_h[n] = h,
            }
        }
    }

    /// What `source` shines toward a receiver, `out` the unit direction from the source
    /// toward the receiver ([`direction`]): a node its open part's radiosity, a cluster the
    /// mean B of the faces that face `out` (module docs), nothing where none does.
    fn shone(&self, clusters: &Clusters, source: Handle, out: DVec3) -> Rgb {
        match source.end() {
            // An unresolved pair has no direction: the cluster shines its mean.
            End::Cluster(s) if out == DVec3::ZERO => self.cluster_b[s],
            End::Cluster(s) => {
                let w = axis_weights(out);
                toward(clusters, s, &w).map_or(Rgb::ZERO, |den| {
                    w.iter()
                        .zip(self.cluster_n[s])
                        .map(|(w, n)| n * *w)
                        .sum::<Rgb>()
                        / den
                })
            }
            End::Node(s) => self.node_shine[s],
        }
    }

    /// One gather through every element's own row ([`LeafRows`]) beside the push of the
    /// other links, and the pull: the iteration of [`State::iterate`] with the elements' own
    /// factors where they differ from their receivers'. Returns Σ_e A_e ‖ΔB_e‖₁ over the
    /// elements.
    pub fn iterate_rows(
        &mut self,
        mesh: &Mesh,
        clusters: &Clusters,
        links: &[Link],
        rows: &LeafRows,
    ) -> f64 {
        let h = self.gather_rows(mesh, clusters, links, rows);
        let mut change = 0.0;
        for (&n, h) in mesh.elements.iter().zip(h) {
            let n = n as usize;
            let patch = &mesh.patches[mesh.nodes[n].patch as usize];
            let b = patch.emission + patch.reflectance * (h * self.node_gain[n]);
            change += self.node_area[n] * (b - self.node_b[n]).abs().element_sum();
            self.node_b[n] = b;
            self.node_h[n] = h;
        }
        self.pull(mesh, clusters);
        change
    }

    /// Every element's irradiance from the current radiosity: the links outside the rows
    /// gathered and pushed, plus the rows.
    fn gather_rows(
        &mut self,
        mesh: &Mesh,
        clusters: &Clusters,
        links: &[Link],
        rows: &LeafRows,
    ) -> Vec<Rgb> {
        self.gather(mesh, clusters, links, Some(rows.links()));
        self.push(mesh, clusters);
        self.add_sky(mesh);
        let shone: Vec<Rgb> = links
            .par_iter()
            .zip(rows.links())
            .enumerate()
            .map(|(i, (l, &rowed))| {
                if !rowed {
                    return Rgb::ZERO;
                }
                match rows.pieces().of(i) {
                    [] => self.shone(
                        clusters,
                        l.source,
                        direction(mesh, clusters, l.receiver, l.source),
                    ),
                    pieces => self.shone_by_pieces(mesh, clusters, l.receiver, pieces),
                }
            })
            .collect();
        rows.gather(&shone)
            .into_iter()
            .zip(&mesh.elements)
            .map(|(h, &e)| h + self.node_h[e as usize])
            .collect()
    }

    /// What a source split into `pieces` (each with its weight w_c) shines toward `receiver`:
    /// Σ w_c P_c / Σ w_c O_c ([`super::source_pieces`]); nothing if no piece is seen.
    fn shone_by_pieces(
        &self,
        mesh: &Mesh,
        clusters: &Clusters,
        receiver: Handle,
        pieces: &[(Handle, f32)],
    ) -> Rgb {
        let (mut power, mut open) = (Rgb::ZERO, 0.0);
        for &(c, w) in pieces {
            let w = f64::from(w);
            let (p, o) = match c.end() {
                End::Node(n) => (self.node_open[n] * self.node_shine[n], self.node_open[n]),
                End::Cluster(k) => {
                    let a = clusters.nodes[k].area;
                    let out = direction(mesh, clusters, receiver, c);
                    (a * self.shone(clusters, c, out), a)
                }
            };
            power += w * p;
            open += w * o;
        }
        if open > 0.0 {
            power / open
        } else {
            Rgb::ZERO
        }
    }

    /// B of every interior node and cluster from its children, bottom up; and what every
    /// mesh node shines. A partly buried node (a floor node under the foot of a block) must
    /// shine only from its open part, with that part's radiosity: over its leaves e, whose
    /// B_e are whole-area means that are E_e on the buried parts (the gathering solvers'
    /// substructuring mean, [`crate::formfactor::exposure`]),
    ///
    /// ```text
    /// B_shine = Σ_e A_e (B_e − (1 − u_e) E_e) / Σ_e A_e u_e .
    /// ```
    ///
    /// Shining the whole-area mean instead lost the buried fraction of the light of every floor
    /// node straddling a footprint: the Cornell box's block sides came out 1–3 % dark.
    pub fn pull(&mut self, mesh: &Mesh, clusters: &Clusters) {
        self.pull_nodes(mesh);
        self.pull_clusters(clusters);
    }

    /// The mesh nodes' part of [`State::pull`].
    fn pull_nodes(&mut self, mesh: &Mesh) {
        // Backward: B and the shone power (in `node_shine`); forward: power over open area.
        for n in (0..mesh.nodes.len()).rev() {
            if let Some(c) = mesh.nodes[n].children {
                let sum: Rgb = (c..c + 4)
                    .map(|k| self.node_area[k as usize] * self.node_b[k as usize])
                    .sum();
                let area: f64 = (c..c + 4).map(|k| self.node_area[k as usize]).sum();
                self.node_b[n] = if area > 0.0 { sum / area } else { Rgb::ZERO };
                self.node_shine[n] = (c..c + 4).map(|k| self.node_shine[k as usize]).sum();
            } else {
                let node = &mesh.nodes[n];
                let emission = mesh.patches[node.patch as usize].emission;
                let buried = self.node_area[n] - self.node_open[n];
                self.node_shine[n] = self.node_area[n] * self.node_b[n] - emission * buried;
            }
        }
        for (shine, &open) in self.node_shine.iter_mut().zip(&self.node_open) {
            *shine = if open > 0.0 { *shine / open } else { Rgb::ZERO };
        }
    }

    /// The clusters' part of [`State::pull`].
    fn pull_clusters(&mut self, clusters: &Clusters) {
        for c in (0..clusters.nodes.len()).rev() {
            let cluster = &clusters.nodes[c];
            let mut n = [Rgb::ZERO; 6];
            let (sum, area): (Rgb, f64) = match cluster.children {
                Some([a, b]) => [a, b].iter().fold((Rgb::ZERO, 0.0), |(s, w), &k| {
                    for (x, y) in n.iter_mut().zip(self.cluster_n[k as usize]) {
                        *x += y;
                    }
                    let a = clusters.nodes[k as usize].area;
                    (s + a * self.cluster_b[k as usize], w + a)
                }),
                None => {
                    let range = cluster.faces.start as usize..cluster.faces.end as usize;
                    clusters.faces[range.clone()]
                        .iter()
                        .zip(&clusters.face_facing[range])
                        .fold((Rgb::ZERO, 0.0), |(s, w), (&f, facing)| {
                            let b = self.node_b[f as usize];
                            for (x, y) in n.iter_mut().zip(facing) {
                                *x += b * *y;
                            }
                            let a = self.node_area[f as usize];
                            (s + a * b, w + a)
                        })
                }
            };
            self.cluster_b[c] = if area > 0.0 { sum / area } else { Rgb::ZERO };
            self.cluster_n[c] = n;
        }
    }
}

/// The unit direction from the centre of `source` to `receiver`'s, where a cluster is at
/// either end (zero between two faces, which need no direction, and for an unresolved pair,
/// which has none: [`resolved`]).
fn direction(mesh: &Mesh, clusters: &Clusters, receiver: Handle, source: Handle) -> DVec3 {
    if !(source.is_cluster() || receiver.is_cluster())
        || !resolved(mesh, clusters, receiver, source)
    {
        return DVec3::ZERO;
    }
    let center = |h: Handle| -> DVec3 {
        match h.end() {
            End::Cluster(c) => clusters.nodes[c].center.as_dvec3(),
            End::Node(n) => mesh.nodes[n].centroid().as_dvec3(),
        }
    };
    (center(receiver) - center(source)).normalize_or_zero()
}

/// Σ_k w_k D_k of cluster `c` for the axis weights `w`, or `None` where nothing of it faces
/// that way.
fn toward(clusters: &Clusters, c: usize, w: &[f64; 6]) -> Option<f64> {
    let den: f64 = w
        .iter()
        .zip(clusters.nodes[c].facing)
        .map(|(a, b)| a * b)
        .sum();
    (den > 0.0).then_some(den)
}

#[cfg(test)]
mod tests {
    use super::super::link::Sight;
    use super::*;
    use crate::mesh::Subdivision;
    use crate::testing::Prepared;

    #[test]
    fn rows_that_overshoot_the_hemisphere_cannot_amplify_the_light() {
        // The closed cube's root faces, ρ 0.9, its floor (y0) emitting. The two walls x0 and
        // x1 face each other; links that say each gathers 1.5 of the other (Σ F > 1, as a
        // parent's mean factor can give a child) make a loop of gain (0.9 · 1.5)² per round
        // trip, which without the cap grows without bound.
        let scene = crate::testing::closed_cube(0.9, [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
        let mesh = Mesh::build(&scene, Subdivision::MaxArea(f64::INFINITY));
        let bvh = Bvh::build(&mesh.triangles);
        let clusters = Clusters::build(&mesh);
        let face = |k: usize| Handle::node(mesh.elements[k]);
        let link = |r, s, f| Link::new(face(r), face(s), f, 0.0, Sight::Unknown);
        let mut links = vec![link(0, 1, 1.5), link(1, 0, 1.5), link(0, 2, 0.1)];
        links.sort_unstable_by_key(|l| (l.receiver, l.source));
        let mut state = State::new(&mesh, &clusters, &bvh);
        state.bury(&mesh, &clusters, &links);
        // Rows of 1.6 (x0) and 1.5 (x1): each element's gain is capped.
        for (&e, row) in mesh.elements[..2].iter().zip([1.6, 1.5]) {
            let gain = 0.9 * row * state.node_gain[e as usize];
            assert!((gain - GAIN).abs() < 1e-6, "{gain}");
        }
        let mut change = f64::INFINITY;
        for _ in 0..4000 {
            change = state.iterate(&mesh, &clusters, &links);
        }
        // Converged (the loop's gain per round trip is 0.99² = 0.98), to a bounded radiosity:
        // x0 gathers 0.1 of the floor's π, and the loop multiplies that by 1 / (1 − 0.98).
        assert!(change < 1e-9, "{change}");
        let bound = 0.9 * 0.1 * std::f64::consts::PI / (1.0 - GAIN * GAIN);
        for &e in &mesh.elements[..2] {
            let b = state.node_b[e as usize].x;
            assert!(
                b.is_finite() && b > 0.0 && b <= bound * 1.000_001,
                "{b} vs {bound}"
            );
        }
    }

    #[test]
    fn partly_buried_nodes_shine_their_open_part() {
        // The Cornell box at 1 024 elements: its blocks stand on the floor, so some floor
        // leaves straddle a footprint (0 < u < 1) and some lie under a block (u = 0); nothing
        // else is buried.
        let scene = crate::scene::builtin::load("cornell").unwrap().unwrap();
        let p = Prepared::new(&scene, Subdivision::Elements(1024), 64);
        let clusters = Clusters::build(&p.mesh);
        let mut state = State::new(&p.mesh, &clusters, &p.bvh);
        let mut partly = 0;
        for &e in &p.mesh.elements {
            let (e, u) = (e as usize, state.node_probed[e as usize]);
            if u < 1.0 {
                assert_eq!(p.mesh.patches[p.mesh.nodes[e].patch as usize].object, 0);
            }
            partly += usize::from(u > 0.0 && u < 1.0);
        }
        assert!(partly > 0);
        // An open radiosity of 1 everywhere (the whole-area means are then B = u, the light
        // being wholly open) shines 1 from every node that has an open part, at every level.
        for &e in &p.mesh.elements {
            let e = e as usize;
            let emits = p.mesh.patches[p.mesh.nodes[e].patch as usize].emission != Rgb::ZERO;
            if emits {
                assert_eq!(state.node_probed[e], 1.0);
            }
            state.node_b[e] = Rgb::splat(if emits { 1.0 } else { state.node_probed[e] });
        }
        state.pull(&p.mesh, &clusters);
        for (n, shine) in state.node_shine.iter().enumerate() {
            if state.node_open[n] > 0.0 {
                assert!(
                    (*shine - Rgb::ONE).abs().max_element() < 1e-9,
                    "{n}: {shine}"
                );
            } else {
                assert_eq!(*shine, Rgb::ZERO);
            }
        }
    }
}
