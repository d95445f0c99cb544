//! Volume clusters over the patches' root faces (Smits, Arvo & Greenberg 1994; Sillion 1995).
//!
//! Hierarchical radiosity alone starts from all k² pairs of input polygons, which for a mesh
//! of 100 k triangles is 10¹⁰ links before any refinement. Clusters put a tree *above* the
//! element quadtrees: a binary tree over the root faces, split at the median centroid of the
//! longest axis of the centroids' box, with up to [`LEAF_FACES`] faces under a leaf cluster.
//! The solve then starts from one link, the root cluster with itself, and the oracle opens
//! clusters only where the light they exchange is large enough to matter.
//!
//! Each cluster keeps its bounding sphere (centre and radius, from its box), its surface area
//! A (every face counted, both sides of a two-sided polygon separately) and its vector area
//! **V** = Σ A_f n_f. Light leaving or arriving at a cluster is modelled by its front-facing
//! projected area in direction ω,
//!
//! ```text
//! P(ω) = max(0, V·ω) + (A − |V|)/4 ,
//! ```
//!
//! the isotropic model of Smits et al. 1994 (§4: every direction sees A/4, the mean projected
//! area of uniformly oriented surfaces — exact for a closed convex object by Cauchy's formula,
//! where V = 0) corrected by the cluster's net orientation, which makes it exact for a flat
//! cluster (|V| = A) as well. Self-shadowing inside the cluster is ignored. See
//! [`super::link`] for what the model costs in accuracy.

use std::ops::Range;

use glam::Vec3;

use crate::mesh::Mesh;

/// Most root faces directly under a leaf cluster.
pub const LEAF_FACES: usize = 4;

/// One cluster: a node of the binary tree over root faces.
#[derive(Clone, Debug)]
pub struct Cluster {
    /// Centre of the bounding box of its faces' corners.
    pub center: Vec3,
    /// Half the diagonal of that box: a bounding sphere.
    pub radius: f32,
    /// Total area of its faces.
    pub area: f64,
    /// Σ A_f n_f over its faces.
    pub vector_area: glam::DVec3,
    /// Its faces: a range of [`Clusters::faces`].
    pub faces: Range<u32>,
    /// The two child clusters, or none for a leaf cluster (whose children are its faces).
    pub children: Option<[u32; 2]>,
}

/// The cluster tree; cluster 0 is the root (when there are any faces at all).
#[derive(Clone, Debug, Default)]
pub struct Clusters {
    /// All clusters, parents before children.
    pub nodes: Vec<Cluster>,
    /// Root-face node ids (into [`Mesh::nodes`]) in cluster order: every cluster's faces are a
    /// contiguous range.
    pub faces: Vec<u32>,
}

impl Clusters {
    /// Builds the tree over every root face of `mesh`.
    #[must_use]
    pub fn build(mesh: &Mesh) -> Self {
        let faces: Vec<u32> = mesh.roots.iter().flat_map(Clone::clone).collect();
        let centroids: Vec<Vec3> = faces
            .iter()
            .map(|&n| mesh.nodes[n as usize].face.centroid())
            .collect();
        let mut order: Vec<u32> = (0..faces.len() as u32).collect();
        let mut out = Clusters::default();
        if !faces.is_empty() {
            out.split(mesh, &faces, &centroids, &mut order, 0);
        }
        out.faces = order.iter().map(|&i| faces[i as usize]).collect();
        debug_assert_eq!(out.validate(mesh), Ok(()));
        out
    }

    /// The projected area P(ω) of cluster `c` toward the unit direction `w` (module docs).
    #[must_use]
    pub fn projected_area(&self, c: usize, w: glam::DVec3) -> f64 {
        let c = &self.nodes[c];
        c.vector_area.dot(w).max(0.0) + 0.25 * (c.area - c.vector_area.length()).max(0.0)
    }

    /// Makes the cluster over `order[offset..offset + order.len()]` and its descendants.
    fn split(
        &mut self,
        mesh: &Mesh,
        faces: &[u32],
        centroids: &[Vec3],
        order: &mut [u32],
        offset: usize,
    ) -> u32 {
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        let (mut area, mut vector_area) = (0.0, glam::DVec3::ZERO);
        for &i in order.iter() {
            let face = &mesh.nodes[faces[i as usize] as usize].face;
            for &c in face.corners() {
                lo = lo.min(c);
                hi = hi.max(c);
            }
            area += face.area();
            vector_area += face.vector_area();
        }
        let index = self.nodes.len() as u32;
        self.nodes.push(Cluster {
            center: 0.5 * (lo + hi),
            radius: 0.5 * (hi - lo).length(),
            area,
            vector_area,
            faces: offset as u32..(offset + order.len()) as u32,
            children: None,
        });
        if order.len() > LEAF_FACES {
            // Median split on the longest axis of the centroids' box; ties broken by index so
            // the tree does not depend on the sort's stability.
            let (mut clo, mut chi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
            for &i in order.iter() {
                clo = clo.min(centroids[i as usize]);
                chi = chi.max(centroids[i as usize]);
            }
            let extent = chi - clo;
            let axis = if extent.x >= extent.y && extent.x >= extent.z {
                0
            } else if extent.y >= extent.z {
                1
            } else {
                2
            };
            let mid = order.len() / 2;
            order.select_nth_unstable_by(mid, |&a, &b| {
                centroids[a as usize][axis]
                    .total_cmp(&centroids[b as usize][axis])
                    .then(a.cmp(&b))
            });
            let (left, right) = order.split_at_mut(mid);
            let a = self.split(mesh, faces, centroids, left, offset);
            let b = self.split(mesh, faces, centroids, right, offset + mid);
            self.nodes[index as usize].children = Some([a, b]);
        }
        index
    }

    /// Checks the tree: children partition their parent's faces and lie inside its bounding
    /// sphere, areas add up, and every root face of `mesh` appears exactly once.
    ///
    /// # Errors
    /// A description of the first broken invariant.
    pub fn validate(&self, mesh: &Mesh) -> Result<(), String> {
        let mut seen = vec![false; mesh.nodes.len()];
        for &f in &self.faces {
            let node = mesh.nodes.get(f as usize).ok_or("face out of range")?;
            if node.level != 0 || std::mem::replace(&mut seen[f as usize], true) {
                return Err(format!("face {f} is not a root face listed once"));
            }
        }
        let roots: usize = mesh.roots.iter().map(|r| r.len()).sum();
        if roots != self.faces.len() {
            return Err("not every root face is clustered".into());
        }
        for (i, c) in self.nodes.iter().enumerate() {
            let faces = &self.faces[c.faces.start as usize..c.faces.end as usize];
            let area: f64 = faces
                .iter()
                .map(|&f| mesh.nodes[f as usize].face.area())
                .sum();
            if (area - c.area).abs() > 1e-6 * c.area.max(1e-30) {
                return Err(format!("cluster {i}: area does not add up"));
            }
            let slack = 1e-4 * c.radius.max(1e-6);
            for &f in faces {
                for &p in mesh.nodes[f as usize].face.corners() {
                    if p.distance(c.center) > c.radius + slack {
                        return Err(format!("cluster {i}: a face sticks out of its sphere"));
                    }
                }
            }
            match c.children {
                None if faces.len() > LEAF_FACES => {
                    return Err(format!("leaf cluster {i} has too many faces"))
                }
                None => {}
                Some([a, b]) => {
                    let (a, b) = (&self.nodes[a as usize], &self.nodes[b as usize]);
                    if a.faces.start != c.faces.start
                        || a.faces.end != b.faces.start
                        || b.faces.end != c.faces.end
                        || a.faces.is_empty()
                        || b.faces.is_empty()
                    {
                        return Err(format!("children of cluster {i} do not partition it"));
                    }
                }
            }
        }
        Ok(())
    }
}
