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
//! A (every face counted, both sides of a two-sided polygon separately), its vector area
//! **V** = Σ A_f n_f and its front-facing projected area P(ω) = Σ_f A_f max(0, n_f·ω) in every
//! direction, tabulated ([`super::projected`]); light leaves and reaches it through P(ω).
//! Self-shadowing inside the cluster is ignored. See [`super::link`] for what the model
//! costs in accuracy.

use std::ops::Range;

use glam::Vec3;

use super::projected::{self, Projected};
use crate::accel::Aabb;
use crate::mesh::Mesh;

/// Most root faces directly under a leaf cluster.
pub const LEAF_FACES: usize = 4;

/// Clusters of more faces than this keep a table of their projected area (500 bytes); smaller
/// ones sum their faces when asked.
pub const TABULATED: usize = 32;

// Leaf clusters are never tabulated ([`Clusters::tabulate`] reads only children).
const _: () = assert!(LEAF_FACES <= TABULATED);

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
    /// Its projected area P(ω), tabulated when it has more than [`TABULATED`] faces.
    pub projected: Option<Projected>,
    /// D_k = Σ A_f max(0, n_f·e_k) over its faces, for the six axis directions e_k of
    /// [`axis_weights`]: how much of it faces each way (see [`super::push_pull`]).
    pub facing: [f64; 6],
    /// Its faces: a range of [`Clusters::faces`].
    pub faces: Range<u32>,
    /// The two child clusters, or none for a leaf cluster (whose children are its faces).
    pub children: Option<[u32; 2]>,
    /// The plane all its faces lie in, as a unit normal n and n·x (its faces may face either
    /// way along n), or none when they do not share one (`View::coplanar` reads it).
    pub plane: Option<(Vec3, f32)>,
}

/// The cluster tree; cluster 0 is the root (when there are any faces at all).
#[derive(Clone, Debug, Default)]
pub struct Clusters {
    /// All clusters, parents before children.
    pub nodes: Vec<Cluster>,
    /// Root-face node ids (into [`Mesh::nodes`]) in cluster order: every cluster's faces are a
    /// contiguous range.
    pub faces: Vec<u32>,
    /// For each entry of `faces`: A_f max(0, n_f·e_k), its [`axis_weights`], which the push
    /// and pull of every iteration read.
    pub face_facing: Vec<[f64; 6]>,
    /// Running sums of the areas of `faces`: entry k is the area of the first k, so that a
    /// cluster's faces can be drawn in proportion to their areas ([`Clusters::draw_face`]).
    pub area_before: Vec<f64>,
    /// Running counts of the faces of `faces` that reflect light (ρ > 0 on some channel):
    /// entry k counts the first k, so that whether a cluster holds any is a difference
    /// ([`Clusters::reflects`]).
    pub reflecting_before: Vec<u32>,
    /// The same for the faces of a distant environment ([`Clusters::distant`]).
    pub distant_before: Vec<u32>,
    /// For each root-face node id, its index in `faces` ([`u32::MAX`] for other nodes): which
    /// clusters hold a face is a range test ([`Clusters::holds`]).
    pub slot: Vec<u32>,
    /// Root-face node ids of each scene polygon (both sides, every planar piece):
    /// polygon k's are `polygon_roots[polygon_start[k]..polygon_start[k + 1]]`. A ray's hit
    /// names a polygon; this finds the root face it lies on.
    pub polygon_roots: Vec<u32>,
    /// Start of each polygon's run in `polygon_roots`.
    pub polygon_start: Vec<u32>,
}

impl Clusters {
    /// Builds the tree over every root face of `mesh`: a tree over the scene's objects
    /// (median splits of their boxes' centres), each object's leaf holding the tree over its
    /// own faces. Splitting all faces at once would cut objects apart, leaving clusters of
    /// pieces of neighbouring objects whose bounding spheres overlap their neighbours', which
    /// the oracle can only open (a field of 200 spheres kept 7× more links that way).
    #[must_use]
    pub fn build(mesh: &Mesh) -> Self {
        let faces: Vec<u32> = mesh.roots.iter().flat_map(Clone::clone).collect();
        let object = |f: u32| mesh.patches[mesh.nodes[f as usize].patch as usize].object;
        let centroids: Vec<Vec3> = faces
            .iter()
            .map(|&n| mesh.nodes[n as usize].centroid())
            .collect();
        // Faces grouped by object (stable: ties keep the patches' order).
        let mut order: Vec<u32> = (0..faces.len() as u32).collect();
        order.sort_by_key(|&i| object(faces[i as usize]));
        let mut groups: Vec<Group> = Vec::new();
        for (k, &i) in order.iter().enumerate() {
            match groups.last_mut() {
                Some(g) if g.object == object(faces[i as usize]) => g.faces.end = k + 1,
                _ => groups.push(Group {
                    object: object(faces[i as usize]),
                    distant: mesh.patches[mesh.nodes[faces[i as usize] as usize].patch as usize]
                        .distant,
                    faces: k..k + 1,
                    center: Vec3::ZERO,
                }),
            }
        }
        for g in &mut groups {
            let b: Aabb = order[g.faces.clone()]
                .iter()
                .map(|&i| centroids[i as usize])
                .collect();
            g.center = 0.5 * (b.min + b.max);
        }
        let mut out = Clusters::default();
        let mut placed = Vec::with_capacity(faces.len());
        if !groups.is_empty() {
            let mut build = Build {
                mesh,
                faces: &faces,
                centroids: &centroids,
                order: &mut order,
                placed: &mut placed,
            };
            build.objects(&mut out, &mut groups);
        }
        out.faces = placed.iter().map(|&i| faces[i as usize]).collect();
        out.face_facing = out
            .faces
            .iter()
            .map(|&f| axis_weights(mesh.nodes[f as usize].face.vector_area()))
            .collect();
        out.area_before = std::iter::once(0.0)
            .chain(out.faces.iter().scan(0.0, |sum, &f| {
                *sum += mesh.nodes[f as usize].area();
                Some(*sum)
            }))
            .collect();
        out.reflecting_before = std::iter::once(0)
            .chain(out.faces.iter().scan(0, |count, &f| {
                let patch = &mesh.patches[mesh.nodes[f as usize].patch as usize];
                *count += u32::from(patch.reflectance.max_element() > 0.0);
                Some(*count)
            }))
            .collect();
        out.distant_before = std::iter::once(0)
            .chain(out.faces.iter().scan(0, |count, &f| {
                *count += u32::from(mesh.patches[mesh.nodes[f as usize].patch as usize].distant);
                Some(*count)
            }))
            .collect();
        out.slot = vec![u32::MAX; faces.iter().map(|&f| f as usize + 1).max().unwrap_or(0)];
        for (k, &f) in out.faces.iter().enumerate() {
            out.slot[f as usize] = k as u32;
        }
        let polygon = |f: u32| mesh.patches[mesh.nodes[f as usize].patch as usize].polygon;
        let mut by_polygon = faces.clone();
        by_polygon.sort_by_key(|&f| (polygon(f), f));
        // Polygons past the last one with a root face have none ([`Clusters::roots_of`]).
        let polygons = by_polygon.last().map_or(0, |&f| polygon(f) as usize + 1);
        out.polygon_start = (0..=polygons as u32)
            .map(|p| by_polygon.partition_point(|&f| polygon(f) < p) as u32)
            .collect();
        out.polygon_roots = by_polygon;
        out.tabulate();
        debug_assert_eq!(out.validate(mesh), Ok(()));
        out
    }

    /// The face of cluster `c` (a root-face node id) at the fraction `u` ∈ [0, 1) of its area:
    /// for a uniform `u`, each face with probability A_f / A.
    #[must_use]
    pub fn draw_face(&self, c: usize, u: f64) -> u32 {
        let range = &self.nodes[c].faces;
        let (lo, hi) = (range.start as usize, range.end as usize);
        let target = self.area_before[lo] + u * (self.area_before[hi] - self.area_before[lo]);
        // The first face whose running sum passes the target.
        let k = self.area_before[lo + 1..=hi].partition_point(|&sum| sum <= target);
        self.faces[(lo + k).min(hi - 1)]
    }

    /// Whether any face of cluster `c` reflects light.
    #[must_use]
    pub fn reflects(&self, c: usize) -> bool {
        let range = &self.nodes[c].faces;
        self.reflecting_before[range.end as usize] > self.reflecting_before[range.start as usize]
    }

    /// Whether every face of cluster `c` is part of a distant environment.
    #[must_use]
    pub fn distant(&self, c: usize) -> bool {
        let range = &self.nodes[c].faces;
        let count =
            self.distant_before[range.end as usize] - self.distant_before[range.start as usize];
        count == range.end - range.start
    }

    /// Whether cluster `c` holds the root face `f` (a node id).
    #[must_use]
    pub fn holds(&self, c: usize, f: u32) -> bool {
        self.slot
            .get(f as usize)
            .is_some_and(|&k| self.nodes[c].faces.contains(&k))
    }

    /// The root faces (node ids) of scene polygon `p`.
    #[must_use]
    pub fn roots_of(&self, p: u32) -> &[u32] {
        let p = p as usize;
        match (self.polygon_start.get(p), self.polygon_start.get(p + 1)) {
            (Some(&a), Some(&b)) => &self.polygon_roots[a as usize..b as usize],
            _ => &[],
        }
    }

    /// The projected area P(ω) of cluster `c` toward the unit direction `w` (module docs).
    /// P(ω) = Σ_f A_f max(0, n_f·ω) of cluster `c` for a unit direction ω (module docs): from
    /// its table, or summed over its faces.
    #[must_use]
    pub fn projected_area(&self, c: usize, w: glam::DVec3) -> f64 {
        let c = &self.nodes[c];
        match &c.projected {
            Some(table) => table.along(w),
            None => projected::exact(
                self.face_facing[c.faces.start as usize..c.faces.end as usize]
                    .iter()
                    .map(vector_area),
                w,
            ),
        }
    }

    /// Bytes held by the tables of projected area.
    #[must_use]
    pub fn table_bytes(&self) -> u64 {
        let tables = self.nodes.iter().filter(|c| c.projected.is_some()).count();
        tables as u64 * Projected::BYTES
    }

    /// Tables of P for the clusters of more than [`TABULATED`] faces, bottom up: a parent's
    /// is the sum of its children's (or of a small child's faces).
    fn tabulate(&mut self) {
        for c in (0..self.nodes.len()).rev() {
            let cluster = &self.nodes[c];
            // Leaf clusters hold at most LEAF_FACES faces: never tabulated.
            let Some(children) = cluster.children.filter(|_| cluster.faces.len() > TABULATED)
            else {
                continue;
            };
            let mut table = Projected::default();
            for k in children {
                let child = &self.nodes[k as usize];
                match &child.projected {
                    Some(t) => table.add(t),
                    None => {
                        let range = child.faces.start as usize..child.faces.end as usize;
                        for f in &self.face_facing[range] {
                            table.add_face(vector_area(f));
                        }
                    }
                }
            }
            self.nodes[c].projected = Some(table);
        }
    }

    /// Appends a cluster over the faces `ids` (indices into `faces`) placed at `offset` of
    /// the final face order, without children; returns its index.
    fn push(&mut self, mesh: &Mesh, faces: &[u32], ids: &[u32], offset: usize) -> u32 {
        let face = |i: &u32| &mesh.nodes[faces[*i as usize] as usize].face;
        let b: Aabb = ids
            .iter()
            .flat_map(|i| face(i).corners().iter().copied())
            .collect();
        let (mut area, mut vector_area, mut facing) = (0.0, glam::DVec3::ZERO, [0.0; 6]);
        for i in ids {
            area += face(i).area();
            vector_area += face(i).vector_area();
            for (d, w) in facing.iter_mut().zip(axis_weights(face(i).vector_area())) {
                *d += w;
            }
        }
        let index = self.nodes.len() as u32;
        let radius = 0.5 * (b.max - b.min).length();
        self.nodes.push(Cluster {
            center: 0.5 * (b.min + b.max),
            radius,
            area,
            vector_area,
            projected: None,
            facing,
            faces: offset as u32..(offset + ids.len()) as u32,
            children: None,
            plane: common_plane(mesh, ids.iter().map(|&i| faces[i as usize]), radius),
        });
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
            let area: f64 = faces.iter().map(|&f| mesh.nodes[f as usize].area()).sum();
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

/// The faces of one object: a range of the object-sorted face order.
struct Group {
    object: u32,
    /// Whether its faces are a distant environment's ([`super::distant`]).
    distant: bool,
    faces: Range<usize>,
    center: Vec3,
}

/// The state of one tree construction.
struct Build<'a> {
    mesh: &'a Mesh,
    faces: &'a [u32],
    centroids: &'a [Vec3],
    /// Face indices grouped by object; each object's part is permuted by its face tree.
    order: &'a mut [u32],
    /// Face indices in the final cluster order, appended depth first.
    placed: &'a mut Vec<u32>,
}

impl Build<'_> {
    /// The cluster over the objects `groups` (at least one): their face trees, under median
    /// splits of the objects' centres.
    fn objects(&mut self, out: &mut Clusters, groups: &mut [Group]) -> u32 {
        if let [one] = groups {
            let range = one.faces.clone();
            let offset = self.placed.len();
            let index = {
                let mut ids = self.order[range.clone()].to_vec();
                let index = self.split(out, &mut ids, offset);
                self.placed.extend_from_slice(&ids);
                index
            };
            return index;
        }
        let offset = self.placed.len();
        let index = out.nodes.len() as u32;
        // A placeholder, completed once the children have placed their faces.
        out.nodes.push(Cluster {
            center: Vec3::ZERO,
            radius: 0.0,
            area: 0.0,
            vector_area: glam::DVec3::ZERO,
            projected: None,
            facing: [0.0; 6],
            faces: 0..0,
            children: None,
            plane: None,
        });
        let distant = groups.iter().filter(|g| g.distant).count();
        let mid = if distant > 0 && distant < groups.len() {
            // A distant environment apart from the rest at the top, so that every cluster
            // below is wholly of it or wholly not ([`super::distant`]).
            groups.sort_by_key(|g| (!g.distant, g.object));
            distant
        } else {
            let axis = longest_axis(groups.iter().map(|g| g.center));
            let mid = groups.len() / 2;
            groups.select_nth_unstable_by(mid, |a, b| {
                a.center[axis]
                    .total_cmp(&b.center[axis])
                    .then(a.object.cmp(&b.object))
            });
            mid
        };
        let (left, right) = groups.split_at_mut(mid);
        let a = self.objects(out, left);
        let b = self.objects(out, right);
        let whole = out.push(self.mesh, self.faces, &self.placed[offset..], offset);
        let mut node = out.nodes.pop().unwrap_or_else(|| unreachable!());
        debug_assert_eq!(whole as usize, out.nodes.len());
        node.children = Some([a, b]);
        out.nodes[index as usize] = node;
        index
    }

    /// The cluster over the faces `ids` of one object (placed at `offset`) and its
    /// descendants: median splits on the longest axis of the centroids' box, down to
    /// [`LEAF_FACES`] faces. `ids` is left in the order the tree places them.
    fn split(&mut self, out: &mut Clusters, ids: &mut [u32], offset: usize) -> u32 {
        let index = out.push(self.mesh, self.faces, ids, offset);
        if ids.len() > LEAF_FACES {
            let centroids = self.centroids;
            let axis = longest_axis(ids.iter().map(|&i| centroids[i as usize]));
            let mid = ids.len() / 2;
            // Ties broken by index so the tree does not depend on the sort's stability.
            ids.select_nth_unstable_by(mid, |&a, &b| {
                centroids[a as usize][axis]
                    .total_cmp(&centroids[b as usize][axis])
                    .then(a.cmp(&b))
            });
            let (left, right) = ids.split_at_mut(mid);
            let a = self.split(out, left, offset);
            let b = self.split(out, right, offset + mid);
            out.nodes[index as usize].children = Some([a, b]);
        }
        index
    }
}

/// The positive parts of a vector's components along +x, −x, +y, −y, +z, −z: for a face's
/// vector area A n, the areas it turns toward each axis direction, A max(0, n·e_k); for a unit
/// direction ω, the weights with which max(0, n·ω) ≈ Σ_k max(0, ω·e_k) max(0, n·e_k) (exact
/// when n or ω lies along an axis, and positive exactly when n·ω is, up to a face or direction
/// in a coordinate plane).
#[must_use]
pub fn axis_weights(v: glam::DVec3) -> [f64; 6] {
    [
        v.x.max(0.0),
        (-v.x).max(0.0),
        v.y.max(0.0),
        (-v.y).max(0.0),
        v.z.max(0.0),
        (-v.z).max(0.0),
    ]
}

/// The plane of a face (a quadtree node): its patch's unit normal n and n·x at a corner.
#[must_use]
pub fn face_plane(mesh: &Mesh, node: u32) -> (Vec3, f32) {
    let node = &mesh.nodes[node as usize];
    let n = mesh.patches[node.patch as usize].normal;
    (n, n.dot(node.face.corners()[0]))
}

/// Whether two planes (unit normal, offset) are one, either way round, to `tolerance` in the
/// offset (and 10⁻⁶ in the normals' cosine).
#[must_use]
pub fn same_plane(a: (Vec3, f32), b: (Vec3, f32), tolerance: f32) -> bool {
    let cos = a.0.dot(b.0);
    let offset = if cos < 0.0 { -b.1 } else { b.1 };
    cos.abs() >= 1.0 - 1e-6 && (a.1 - offset).abs() <= tolerance
}

/// The plane every one of `faces` (root-face node ids) lies in, to 10⁻⁵ of `size` at their
/// corners, or none.
fn common_plane(
    mesh: &Mesh,
    mut faces: impl Iterator<Item = u32>,
    size: f32,
) -> Option<(Vec3, f32)> {
    let plane = face_plane(mesh, faces.next()?);
    let tolerance = 1e-5 * size;
    faces
        .all(|f| {
            let (n, _) = face_plane(mesh, f);
            n.dot(plane.0).abs() >= 1.0 - 1e-6
                && mesh.nodes[f as usize]
                    .face
                    .corners()
                    .iter()
                    .all(|&q| (plane.0.dot(q) - plane.1).abs() <= tolerance)
        })
        .then_some(plane)
}

/// The axis (0, 1, 2) along which `points` spread the most.
fn longest_axis(points: impl Iterator<Item = Vec3>) -> usize {
    let b: Aabb = points.collect();
    crate::accel::largest_axis(b.max - b.min)
}

/// The vector area A n of a face from its [`axis_weights`].
fn vector_area(w: &[f64; 6]) -> glam::DVec3 {
    glam::DVec3::new(w[0] - w[1], w[2] - w[3], w[4] - w[5])
}
