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
use super::link::{End, Handle, Link};
use crate::mesh::Mesh;
use crate::Rgb;

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
    pub fn new(mesh: &Mesh, clusters: &Clusters) -> Self {
        let n = clusters.nodes.len();
        let mut s = State {
            cluster_b: vec![Rgb::ZERO; n],
            cluster_n: vec![[Rgb::ZERO; 6]; n],
            cluster_h: vec![Rgb::ZERO; n],
            cluster_q: vec![[Rgb::ZERO; 6]; n],
            ..State::default()
        };
        s.grow(mesh);
        for &n in &mesh.elements {
            let node = &mesh.nodes[n as usize];
            s.node_b[n as usize] = mesh.patches[node.patch as usize].emission;
        }
        s.pull(mesh, clusters);
        s
    }

    /// Extends the arrays to new nodes of `mesh`; a new node starts with its parent's B.
    pub fn grow(&mut self, mesh: &Mesh) {
        let old = self.node_b.len();
        let n = mesh.nodes.len();
        self.node_b.resize(n, Rgb::ZERO);
        self.node_h.resize(n, Rgb::ZERO);
        self.node_area
            .extend(mesh.nodes[old..].iter().map(|k| k.face.area()));
        for p in 0..old {
            if let Some(c) = mesh.nodes[p].children {
                if c as usize >= old {
                    for k in c..c + 4 {
                        self.node_b[k as usize] = self.node_b[p];
                    }
                }
            }
        }
    }

    /// One gather, push and pull. Returns Σ_e A_e ‖ΔB_e‖₁ over the elements.
    pub fn iterate(&mut self, mesh: &Mesh, clusters: &Clusters, links: &[Link]) -> f64 {
        self.gather(mesh, clusters, links);
        // Push: clusters, then root faces, then quadtree nodes in index order.
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
        // New element radiosities, in parallel (each from its own node only).
        let new: Vec<Rgb> = mesh
            .elements
            .par_iter()
            .map(|&n| {
                let node = &mesh.nodes[n as usize];
                let patch = &mesh.patches[node.patch as usize];
                patch.emission + patch.reflectance * self.node_h[n as usize]
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

    /// The irradiance that each element received in the last iteration (after the push).
    #[must_use]
    pub fn element_irradiance(&self, mesh: &Mesh) -> Vec<Rgb> {
        mesh.elements
            .iter()
            .map(|&n| self.node_h[n as usize])
            .collect()
    }

    /// H of every handle from its own links (links sorted by receiver), with the direction of
    /// each cluster link (module docs).
    fn gather(&mut self, mesh: &Mesh, clusters: &Clusters, links: &[Link]) {
        self.node_h.fill(Rgb::ZERO);
        self.cluster_h.fill(Rgb::ZERO);
        self.cluster_q.fill([Rgb::ZERO; 6]);
        let mut groups = Vec::new();
        let mut start = 0;
        for i in 1..=links.len() {
            if i == links.len() || links[i].receiver != links[start].receiver {
                groups.push(start..i);
                start = i;
            }
        }
        let center = |h: Handle| -> DVec3 {
            match h.end() {
                End::Cluster(c) => clusters.nodes[c].center.as_dvec3(),
                End::Node(n) => mesh.nodes[n].face.centroid().as_dvec3(),
            }
        };
        // Σ_k w_k X_k / Σ_k w_k D_k, or None where nothing of the cluster faces ω.
        let toward = |c: usize, w: &[f64; 6]| {
            let den: f64 = w
                .iter()
                .zip(clusters.nodes[c].facing)
                .map(|(a, b)| a * b)
                .sum();
            (den > 0.0).then_some(den)
        };
        let (node_b, cluster_n) = (&self.node_b, &self.cluster_n);
        let sums: Vec<(Rgb, Directional)> = groups
            .par_iter()
            .map(|g| {
                let r = links[g.start].receiver;
                let mut scalar = Rgb::ZERO;
                let mut q = [Rgb::ZERO; 6];
                for l in &links[g.clone()] {
                    let involves_cluster = l.source.is_cluster() || r.is_cluster();
                    let out = if involves_cluster {
                        (center(r) - center(l.source)).normalize_or_zero()
                    } else {
                        DVec3::ZERO
                    };
                    let b = match l.source.end() {
                        End::Cluster(s) => {
                            let w = axis_weights(out);
                            toward(s, &w).map_or(Rgb::ZERO, |den| {
                                w.iter().zip(cluster_n[s]).map(|(w, n)| n * *w).sum::<Rgb>() / den
                            })
                        }
                        End::Node(s) => node_b[s],
                    };
                    let h = f64::from(l.factor) * b;
                    let End::Cluster(c) = r.end() else {
                        scalar += h;
                        continue;
                    };
                    let w = axis_weights(-out);
                    match toward(c, &w) {
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

    /// B of every interior node and cluster from its children, bottom up.
    fn pull(&mut self, mesh: &Mesh, clusters: &Clusters) {
        for n in (0..mesh.nodes.len()).rev() {
            if let Some(c) = mesh.nodes[n].children {
                let sum: Rgb = (c..c + 4)
                    .map(|k| self.node_area[k as usize] * self.node_b[k as usize])
                    .sum();
                let area: f64 = (c..c + 4).map(|k| self.node_area[k as usize]).sum();
                self.node_b[n] = if area > 0.0 { sum / area } else { Rgb::ZERO };
            }
        }
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
