//! The near field's sources gathered into a tree of clusters, so that the work at a point
//! follows the surfaces around it, not the number of nodes within its reach.
//!
//! A point sums the nodes of the cut within its reach (see [`super`]). Most are far from it
//! compared with their size, where each is seen with the point kernel
//!
//! ```text
//! f_s = w(|c_s − x|) · max(0, n_x·(c_s − x)) · A_s n_s·(x − c_s) / (π |c_s − x|⁴),
//! ```
//!
//! smooth in the node's centroid c_s. A real mesh puts thousands of them within the reach of
//! one point (a teapot of 50 000 triangles on a table, a patch whose largest element is a
//! sliver as long as the room, which sets the reach of every point of the patch), and the
//! render stage went by the count. So the nodes are gathered into a binary tree (median splits
//! of their centroids, or of their normals where these spread more), and a cluster of
//! bounding radius ρ at a distance D ≥ ρ / [`FAR_RATIO`] whose nodes all face the point is
//! taken as one source, the sums of its nodes at its area-weighted centroid c̄ (Barnes & Hut
//! 1986):
//!
//! ```text
//! Σ_s f_s (B_s − E_s) ≈ w(|c̄ − x|) · max(0, n_x·(c̄ − x)) · (V_B·(x − c̄) − M_B) / (π |c̄ − x|⁴),
//! V_B = Σ_s A_s (B_s − E_s) n_s,      M_B = Σ_s A_s (B_s − E_s) n_s·(c_s − c̄),
//! ```
//!
//! and V, M the same sums without B − E for the share S. The sums linear in the nodes' normals
//! are exact: Σ A n·(x − c) = V·(x − c̄) − M, where M, the cluster's bulge out of its mean
//! plane, is what a curved cluster (a cap of a ball) adds; without it a point 1.6 m from a
//! ball of radius 0.5 got 1.6 % too much of it. The rest, the change of the kernel across the
//! cluster, is second order in ρ / D about the centroid. That is why a cluster is taken whole
//! at [`FAR_RATIO`] only where every one of its nodes faces the point (max(0, ·) is linear only
//! on one side; a cluster across the point's horizon is, its cosine there clamped at zero, as
//! its nodes next to the horizon send little), and, across a bend of the weight w (half the
//! reach, the reach), only if it is small beside the reach ([`BEND_RATIO`]). One shadow ray, to the
//! node nearest its centroid, stands for its visibility. Clusters that no node of can send
//! anything (all behind the point, all in its plane, all below its horizon, all beyond its
//! reach) are skipped whole, whatever their distance. A point then visits the clusters of a
//! few shells around it, O(log n) of them, plus the nodes next to it that are opened
//! ([`super::NearField::irradiance_at`]). The test below holds a floor point next to a ball of
//! 5 120 triangles within 1 % of the node-by-node sum (2 % per channel), opening a tenth of
//! the nodes or fewer.

use glam::{DVec3, Vec3};

use super::Shape;
use crate::accel::{largest_axis, Aabb};
use crate::mesh::Mesh;
use crate::Rgb;

/// A cluster is taken whole at a point farther than its bounding radius over this. The
/// kernel's change across the cluster is second order in the ratio about its centroid.
const FAR_RATIO: f32 = 0.2;

/// A cluster across its own horizon (some nodes facing the point, some not: the silhouette of a
/// curved object) is taken whole, its sums clamped at zero, only at a point farther than its
/// bounding radius over this.
const MIXED_RATIO: f32 = 0.1;

/// A cluster across a bend of the near field's weight (half the reach, the reach) is taken
/// whole only if its bounding radius is at most this share of the reach.
const BEND_RATIO: f32 = 0.05;

/// A cluster is taken whole only if every node of it lies beyond this many of its own
/// diameters of the point, where each is seen with the point kernel and none is opened
/// (`EXACT_WITHIN` and `OPEN_WITHIN` of [`super`]).
const KERNEL_BEYOND: f32 = 2.0;

/// Most nodes under a leaf cluster.
const LEAF_NODES: usize = 4;

/// A normal's spread over a cluster weighs as much as this times the cluster's longest
/// extent when the split axis is chosen: a cluster whose nodes face opposite ways (a thin
/// box, a teapot) is split by its normals first, so that its children face one way.
const NORMAL_WEIGHT: f32 = 1.0;

/// One node of the cluster tree.
#[derive(Clone, Debug)]
struct Cluster {
    /// Box of its nodes' centroids.
    centroids: Aabb,
    /// Box of its nodes' corners.
    bounds: Aabb,
    /// Centre and radius of a sphere around its nodes' corners.
    centre: Vec3,
    radius: f32,
    /// Largest and smallest diameter of its nodes.
    largest: f32,
    smallest: f32,
    /// Axis of its nodes' normals and the largest |n − axis| among them.
    axis: Vec3,
    spread: f32,
    /// Area-weighted centroid of its nodes.
    centroid: Vec3,
    /// V = Σ A n.
    vector_area: DVec3,
    /// V_B = Σ A (B − E) n, per channel.
    vector_reflected: [DVec3; 3],
    /// M = Σ A n·(c − c̄), how far its nodes stand out of their mean plane (positive for a
    /// convex cap): with it Σ A n·(x − c) = V·(x − c̄) − M holds exactly.
    bulge: f64,
    /// M_B = Σ A (B − E) n·(c − c̄), per channel.
    bulge_reflected: [f64; 3],
    /// The centroid and normal of the node nearest its centroid: where a shadow ray checks
    /// that the point sees the cluster (its centroid may lie behind a curved surface).
    target: (Vec3, Vec3),
    /// Its nodes, a range of [`Clusters::nodes`], for a leaf; otherwise its two children,
    /// `first` and `first + 1`.
    first: u32,
    count: u32,
    leaf: bool,
}

/// What the tree keeps of each node of the cut while it is built.
#[derive(Clone, Copy, Debug)]
struct Member {
    node: u32,
    centroid: Vec3,
    normal: Vec3,
    area: f64,
    diameter: f32,
    bounds: Aabb,
    reflected: Rgb,
}

/// The cluster tree over the nodes of the near field's cut (see the module docs).
#[derive(Clone, Debug, Default)]
pub(super) struct Clusters {
    /// Cluster 0 is the root (when there are nodes at all); children after their parent.
    clusters: Vec<Cluster>,
    /// The cut's node ids in tree order: every leaf's nodes are a contiguous range.
    nodes: Vec<u32>,
}

/// The sums of a point's near field over the clusters taken whole: Σ w F (B − E) and Σ w F.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Gathered {
    pub(super) sum: Rgb,
    pub(super) share: f64,
}

impl Clusters {
    /// The tree over `cut` (node ids of `mesh`), each node with its shape from `shapes` and its
    /// mean B − E from `reflected` (both by node id).
    pub(super) fn build(mesh: &Mesh, cut: &[u32], shapes: &[Shape], reflected: &[Rgb]) -> Self {
        let mut members: Vec<Member> = cut
            .iter()
            .map(|&n| {
                let shape = &shapes[n as usize];
                Member {
                    node: n,
                    centroid: shape.centroid,
                    normal: shape.normal,
                    area: shape.area,
                    diameter: shape.diameter,
                    bounds: Aabb::from_points(mesh.nodes[n as usize].face.corners()),
                    reflected: reflected[n as usize],
                }
            })
            .collect();
        let mut out = Self::default();
        if !members.is_empty() {
            out.clusters.push(summary(&members));
            out.split(0, &mut members, 0);
        }
        out.nodes = members.iter().map(|m| m.node).collect();
        debug_assert_eq!(out.validate(cut.len()), Ok(()));
        out
    }

    /// Splits cluster `c`, whose nodes are `members` (starting at `offset` of the tree's
    /// order), into two, and those again, down to leaves of at most [`LEAF_NODES`] nodes.
    fn split(&mut self, c: usize, members: &mut [Member], offset: usize) {
        if members.len() <= LEAF_NODES {
            let cluster = &mut self.clusters[c];
            (cluster.first, cluster.count, cluster.leaf) =
                (offset as u32, members.len() as u32, true);
            return;
        }
        // The axis of the widest spread: of the centroids, or of the normals weighed by the
        // cluster's extent.
        let normals: Aabb = members.iter().map(|m| m.normal).collect();
        let positions = self.clusters[c].centroids;
        let extent = positions.max - positions.min;
        let turn = (normals.max - normals.min) * (NORMAL_WEIGHT * extent.max_element());
        let (by_normal, axis) = if turn.max_element() > extent.max_element() {
            (true, largest_axis(turn))
        } else {
            (false, largest_axis(extent))
        };
        let key = |m: &Member| {
            if by_normal {
                m.normal[axis]
            } else {
                m.centroid[axis]
            }
        };
        let half = members.len() / 2;
        members.select_nth_unstable_by(half, |a, b| key(a).total_cmp(&key(b)));
        let (left, right) = members.split_at_mut(half);
        let first = self.clusters.len();
        self.clusters.push(summary(left));
        self.clusters.push(summary(right));
        let cluster = &mut self.clusters[c];
        (cluster.first, cluster.count, cluster.leaf) = (first as u32, 2, false);
        self.split(first, left, offset);
        self.split(first + 1, right, offset + half);
    }

    /// Walks the tree for `point` (unit normal `normal`, near-field reach `reach`): the
    /// clusters taken whole that the point `sees` (at the centroid and normal of their node
    /// nearest their centroid) are summed into the result, and every node of the cut that a
    /// cluster left open is handed to `open`, in a fixed order.
    pub(super) fn gather(
        &self,
        point: Vec3,
        normal: Vec3,
        reach: f32,
        sees: impl Fn(Vec3, Vec3) -> bool,
        mut open: impl FnMut(u32),
    ) -> Gathered {
        let mut out = Gathered::default();
        if self.clusters.is_empty() {
            return out;
        }
        let mut stack = vec![0u32];
        while let Some(c) = stack.pop() {
            let cluster = &self.clusters[c as usize];
            match cluster.seen_from(point, normal, reach) {
                Seen::Nothing => {}
                Seen::Whole => cluster.add(point, normal, reach, &sees, &mut out),
                Seen::Parts if cluster.leaf => {
                    let range = cluster.first as usize..(cluster.first + cluster.count) as usize;
                    self.nodes[range].iter().for_each(|&n| open(n));
                }
                Seen::Parts => stack.extend([cluster.first + 1, cluster.first]),
            }
        }
        out
    }

    /// Checks the tree: every node of the cut under exactly one leaf, each cluster's boxes
    /// holding its children's, children after their parents.
    fn validate(&self, nodes: usize) -> Result<(), String> {
        if self.nodes.len() != nodes {
            return Err(format!(
                "{} nodes in the tree, {nodes} in the cut",
                self.nodes.len()
            ));
        }
        let mut seen = vec![false; nodes];
        for (c, cluster) in self.clusters.iter().enumerate() {
            let range = cluster.first as usize..(cluster.first + cluster.count) as usize;
            if cluster.leaf {
                for k in range {
                    let slot = seen.get_mut(k).ok_or("leaf range out of the nodes")?;
                    if std::mem::replace(slot, true) {
                        return Err(format!("node {k} under two leaves"));
                    }
                }
            } else {
                if cluster.count != 2 || range.start <= c || range.end > self.clusters.len() {
                    return Err(format!("cluster {c}: children {range:?}"));
                }
                for child in &self.clusters[range] {
                    let holds = |outer: &Aabb, inner: &Aabb| {
                        outer.min.cmple(inner.min).all() && outer.max.cmpge(inner.max).all()
                    };
                    if !holds(&cluster.bounds, &child.bounds)
                        || !holds(&cluster.centroids, &child.centroids)
                    {
                        return Err(format!("cluster {c}: a child's box outside its own"));
                    }
                }
            }
        }
        match seen.iter().position(|s| !s) {
            Some(k) => Err(format!("node {k} under no leaf")),
            None => Ok(()),
        }
    }
}

/// How a point sees a cluster.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Seen {
    /// No node of it sends the point anything.
    Nothing,
    /// Far enough and facing the point: one source.
    Whole,
    /// Its children (or nodes) one by one.
    Parts,
}

impl Cluster {
    fn seen_from(&self, point: Vec3, normal: Vec3, reach: f32) -> Seen {
        // Every centroid beyond the reach.
        let nearest = point
            .clamp(self.centroids.min, self.centroids.max)
            .distance(point);
        if nearest >= reach {
            return Seen::Nothing;
        }
        // The weight w(d) bends at half the reach and at the reach: a cluster across a bend is
        // taken whole only if it is small beside the reach.
        let farthest = (point - self.centroids.min)
            .abs()
            .max((point - self.centroids.max).abs())
            .length();
        let across = |bend: f32| nearest < bend && farthest > bend;
        let bent = across(reach) || across(0.5 * reach);
        // Every corner below the point's horizon: Lambert's factor and the kernel are zero.
        let (low, high) = (self.bounds.min - point, self.bounds.max - point);
        if normal.max(Vec3::ZERO).dot(high) + normal.min(Vec3::ZERO).dot(low) <= 0.0 {
            return Seen::Nothing;
        }
        // The range of n_s·(x − c_s) over the nodes: the axis's over the centroids' box,
        // widened by the normals' spread times the farthest centroid.
        let (low, high) = (point - self.centroids.max, point - self.centroids.min);
        let a = self.axis;
        let least = a.max(Vec3::ZERO).dot(low) + a.min(Vec3::ZERO).dot(high);
        let most = a.max(Vec3::ZERO).dot(high) + a.min(Vec3::ZERO).dot(low);
        let farthest = low.abs().max(high.abs()).length();
        let slack = self.spread * farthest;
        // None in front of its plane (`super::in_front`, within its tolerance).
        if most + slack <= 1e-5 * self.smallest {
            return Seen::Nothing;
        }
        let distance = self.centre.distance(point);
        let far = self.radius <= FAR_RATIO * distance
            && distance - self.radius >= KERNEL_BEYOND * self.largest
            && (!bent || self.radius <= BEND_RATIO * reach);
        let facing = least - slack > 1e-5 * self.largest;
        if far && (facing || self.radius <= MIXED_RATIO * distance) {
            Seen::Whole
        } else {
            Seen::Parts
        }
    }

    /// Adds the cluster as one source at its centroid (see the module docs), if the point
    /// `sees` its target.
    fn add(
        &self,
        point: Vec3,
        normal: Vec3,
        reach: f32,
        sees: impl Fn(Vec3, Vec3) -> bool,
        out: &mut Gathered,
    ) {
        let w = self.centroid - point;
        let d = w.length() / reach;
        let weight = f64::from((2.0 - 2.0 * d).clamp(0.0, 1.0));
        let cos_x = f64::from(normal.dot(w));
        if weight <= 0.0 || cos_x <= 0.0 || !sees(self.target.0, self.target.1) {
            return;
        }
        let w = w.as_dvec3();
        let r2 = w.length_squared();
        let kernel = weight * cos_x / (std::f64::consts::PI * r2 * r2);
        out.share += kernel * (-self.vector_area.dot(w) - self.bulge).max(0.0);
        for c in 0..3 {
            out.sum[c] +=
                kernel * (-self.vector_reflected[c].dot(w) - self.bulge_reflected[c]).max(0.0);
        }
    }
}

/// A cluster over `members`, its tree links not set yet.
fn summary(members: &[Member]) -> Cluster {
    let bounds = members.iter().fold(Aabb::EMPTY, |b, m| b.union(&m.bounds));
    let centroids: Aabb = members.iter().map(|m| m.centroid).collect();
    let (mut area, mut moment) = (0.0, DVec3::ZERO);
    let (mut vector_area, mut vector_reflected) = (DVec3::ZERO, [DVec3::ZERO; 3]);
    let (mut largest, mut smallest) = (0.0f32, f32::INFINITY);
    for m in members {
        let n = m.normal.as_dvec3() * m.area;
        area += m.area;
        moment += m.centroid.as_dvec3() * m.area;
        vector_area += n;
        for (c, v) in vector_reflected.iter_mut().enumerate() {
            *v += n * m.reflected[c];
        }
        largest = largest.max(m.diameter);
        smallest = smallest.min(m.diameter);
    }
    let centroid = if area > 0.0 {
        (moment / area).as_vec3()
    } else {
        0.5 * (centroids.min + centroids.max)
    };
    let (mut bulge, mut bulge_reflected) = (0.0, [0.0; 3]);
    for m in members {
        let b = m.area * f64::from(m.normal.dot(m.centroid - centroid));
        bulge += b;
        for (c, v) in bulge_reflected.iter_mut().enumerate() {
            *v += b * m.reflected[c];
        }
    }
    let axis = vector_area
        .as_vec3()
        .try_normalize()
        .unwrap_or(members[0].normal);
    let spread = members
        .iter()
        .map(|m| (m.normal - axis).length())
        .fold(0.0, f32::max);
    let nearest = members
        .iter()
        .min_by(|a, b| {
            a.centroid
                .distance_squared(centroid)
                .total_cmp(&b.centroid.distance_squared(centroid))
        })
        .map_or((centroid, axis), |m| (m.centroid, m.normal));
    let centre = 0.5 * (bounds.min + bounds.max);
    Cluster {
        centroids,
        bounds,
        centre,
        radius: 0.5 * (bounds.max - bounds.min).length(),
        largest,
        smallest,
        axis,
        spread,
        centroid,
        vector_area,
        vector_reflected,
        bulge,
        bulge_reflected,
        target: nearest,
        first: 0,
        count: 0,
        leaf: false,
    }
}

#[cfg(test)]
mod tests {
    use super::super::NearField;
    use super::*;
    use crate::mesh::Subdivision;

    /// A floor, a wall and a ball of 5 120 triangles standing on the floor next to the wall.
    const BALL: &str = r#"
[materials.white]
reflectance = 0.5
[[objects]]
name = "floor"
material = "white"
shape = "polygon"
vertices = [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]
[[objects]]
name = "wall"
material = "white"
shape = "polygon"
vertices = [[-2, 0, -2], [2, 0, -2], [2, 2, -2], [-2, 2, -2]]
[[objects]]
name = "ball"
material = "white"
shape = "sphere"
center = [0, 0.6, -1.2]
radius = 0.5
subdivisions = 4
"#;

    #[test]
    fn far_clusters_send_what_their_nodes_send_for_a_fraction_of_the_work() {
        let scene = crate::Scene::from_toml_str(BALL, std::path::Path::new("ball.toml")).unwrap();
        let mesh = crate::mesh::Mesh::build(&scene, Subdivision::Elements(2000));
        // B − E varying over the scene, so that the clusters' vector sums are put to the test.
        let radiosity: Vec<Rgb> = (0..mesh.element_count())
            .map(|e| {
                let c = mesh.element(e).centroid();
                Rgb::new(
                    1.0 + 0.5 * f64::from((3.0 * c.x).sin()),
                    1.0 + 0.5 * f64::from(c.y),
                    0.2,
                )
            })
            .collect();
        let near = NearField::new(&mesh, &radiosity);
        assert!(
            near.clusters.nodes.len() > 5000,
            "{} nodes",
            near.clusters.nodes.len()
        );
        let reach = 3.0;
        let kernel = |n: u32, point: Vec3, normal: Vec3| {
            let shape = &near.shapes[n as usize];
            let w = shape.centroid - point;
            let d = w.length() / reach;
            let weight = f64::from((2.0 - 2.0 * d).clamp(0.0, 1.0));
            let (cos_x, cos_y) = (normal.dot(w), -shape.normal.dot(w));
            if cos_x <= 0.0 || cos_y <= 0.0 {
                return 0.0;
            }
            let r2 = w.length_squared();
            weight * shape.area * f64::from(cos_x * cos_y / (r2 * r2)) / std::f64::consts::PI
        };
        // Points on the floor and on the wall, a ball's radius and more from the ball.
        for (point, normal) in [
            (Vec3::new(1.0, 0.0, -1.0), Vec3::Y),
            (Vec3::new(-1.4, 0.0, 0.3), Vec3::Y),
            (Vec3::new(0.9, 1.5, -2.0), Vec3::Z),
            // On the ball's side: the floor and the wall across its horizon.
            (Vec3::new(0.5, 0.6, -1.2), Vec3::X),
        ] {
            let (mut every, mut share) = (Rgb::ZERO, 0.0);
            for &n in &near.clusters.nodes {
                let f = kernel(n, point, normal);
                every += near.reflected[n as usize] * f;
                share += f;
            }
            let mut opened = 0;
            let mut sum = Rgb::ZERO;
            let mut open_share = 0.0;
            let gathered = near.clusters.gather(
                point,
                normal,
                reach,
                |_, _| true,
                |n| {
                    opened += 1;
                    let f = kernel(n, point, normal);
                    sum += near.reflected[n as usize] * f;
                    open_share += f;
                },
            );
            let (sum, total) = (sum + gathered.sum, open_share + gathered.share);
            assert!(
                share > 0.01,
                "{point}: the point sees its surroundings ({share})"
            );
            assert!(
                (total - share).abs() < 0.01 * share,
                "{point}: share {total} against {share} node by node"
            );
            for c in 0..3 {
                assert!(
                    (sum[c] - every[c]).abs() < 0.02 * every[c],
                    "{point}: channel {c}: {} against {} node by node",
                    sum[c],
                    every[c]
                );
            }
            assert!(
                opened < near.clusters.nodes.len() / 10,
                "{point}: {opened} of {} nodes opened one by one",
                near.clusters.nodes.len()
            );
        }
    }
}
