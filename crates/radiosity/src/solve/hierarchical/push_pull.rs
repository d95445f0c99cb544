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

use rayon::prelude::*;

use super::cluster::Clusters;
use super::link::{Link, CLUSTER};
use crate::mesh::Mesh;
use crate::Rgb;

/// Radiosity and irradiance of every node and cluster.
#[derive(Clone, Debug, Default)]
pub struct State {
    /// B of every mesh node (leaves: the element's; others: the mean below).
    pub node_b: Vec<Rgb>,
    /// Irradiance gathered by every mesh node's own links, then pushed (total) during an
    /// iteration.
    pub node_h: Vec<Rgb>,
    /// Area of every mesh node.
    pub node_area: Vec<f64>,
    /// B of every cluster.
    pub cluster_b: Vec<Rgb>,
    /// Irradiance of every cluster.
    pub cluster_h: Vec<Rgb>,
}

impl State {
    /// B = E everywhere, pulled up.
    #[must_use]
    pub fn new(mesh: &Mesh, clusters: &Clusters) -> Self {
        let mut s = State {
            cluster_b: vec![Rgb::ZERO; clusters.nodes.len()],
            cluster_h: vec![Rgb::ZERO; clusters.nodes.len()],
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
        self.gather(links);
        // Push: clusters, then root faces, then quadtree nodes in index order.
        for c in 0..clusters.nodes.len() {
            let down = self.cluster_h[c];
            match clusters.nodes[c].children {
                Some([a, b]) => {
                    self.cluster_h[a as usize] += down;
                    self.cluster_h[b as usize] += down;
                }
                None => {
                    let range = clusters.nodes[c].faces.clone();
                    for &f in &clusters.faces[range.start as usize..range.end as usize] {
                        self.node_h[f as usize] += down;
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

    /// H of every handle from its own links (links sorted by receiver).
    fn gather(&mut self, links: &[Link]) {
        self.node_h.fill(Rgb::ZERO);
        self.cluster_h.fill(Rgb::ZERO);
        let mut groups = Vec::new();
        let mut start = 0;
        for i in 1..=links.len() {
            if i == links.len() || links[i].receiver != links[start].receiver {
                groups.push(start..i);
                start = i;
            }
        }
        let (node_b, cluster_b) = (&self.node_b, &self.cluster_b);
        let sums: Vec<Rgb> = groups
            .par_iter()
            .map(|g| {
                links[g.clone()]
                    .iter()
                    .map(|l| {
                        let b = if l.source & CLUSTER != 0 {
                            cluster_b[(l.source & !CLUSTER) as usize]
                        } else {
                            node_b[l.source as usize]
                        };
                        f64::from(l.factor) * b
                    })
                    .sum()
            })
            .collect();
        for (g, h) in groups.iter().zip(sums) {
            let r = links[g.start].receiver;
            if r & CLUSTER != 0 {
                self.cluster_h[(r & !CLUSTER) as usize] = h;
            } else {
                self.node_h[r as usize] = h;
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
            let (sum, area): (Rgb, f64) = match cluster.children {
                Some([a, b]) => [a, b].iter().fold((Rgb::ZERO, 0.0), |(s, w), &k| {
                    let a = clusters.nodes[k as usize].area;
                    (s + a * self.cluster_b[k as usize], w + a)
                }),
                None => clusters.faces[cluster.faces.start as usize..cluster.faces.end as usize]
                    .iter()
                    .fold((Rgb::ZERO, 0.0), |(s, w), &f| {
                        let a = self.node_area[f as usize];
                        (s + a * self.node_b[f as usize], w + a)
                    }),
            };
            self.cluster_b[c] = if area > 0.0 { sum / area } else { Rgb::ZERO };
        }
    }
}
