//! Binary space partitioning tree of convex polygons (Fuchs, Kedem & Naylor 1980), in the
//! form used for CSG by Naylor, Amanatides & Thibault (1990) and Wallace's csg.js.
//!
//! Each node holds a splitting plane n · x = w, the polygons lying in that plane, and two
//! subtrees: everything in front of the plane (n · x > w) and everything behind. A polygon that
//! straddles a plane is split along it. Points closer than [`EPSILON`] to a plane count as on it,
//! which is what makes coplanar faces (two boxes sharing a face) behave: a coplanar polygon goes
//! to the front or back list by whether its own normal agrees with the plane's.
//!
//! Nodes live in one vector and refer to their children by index, so building, clipping and
//! inverting are loops over a work stack rather than recursion: a convex mesh makes a tree as
//! deep as its face count.

use glam::DVec3;

/// Distance below which a point counts as lying on a plane (scene units).
pub const EPSILON: f64 = 1e-6;

/// The plane n · x = w.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Unit normal (front side).
    pub normal: DVec3,
    /// Offset along the normal.
    pub w: f64,
}

impl Plane {
    /// The plane through three points, front by the right-hand rule; `None` if collinear.
    #[must_use]
    pub fn through(a: DVec3, b: DVec3, c: DVec3) -> Option<Self> {
        let normal = (b - a).cross(c - a).try_normalize()?;
        Some(Self {
            normal,
            w: normal.dot(a),
        })
    }

    /// Signed distance of `p` (positive in front).
    #[must_use]
    pub fn distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.w
    }

    fn flip(&mut self) {
        self.normal = -self.normal;
        self.w = -self.w;
    }
}

/// A convex planar polygon, counter-clockwise seen from the front of its `plane`.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    /// Corners.
    pub vertices: Vec<DVec3>,
    /// Supporting plane, kept through splits so that pieces stay exactly coplanar.
    pub plane: Plane,
}

impl Polygon {
    /// A polygon on the plane of its corners (Newell normal); `None` if degenerate.
    #[must_use]
    pub fn new(vertices: Vec<DVec3>) -> Option<Self> {
        if vertices.len() < 3 {
            return None;
        }
        let mut n = DVec3::ZERO;
        for (i, a) in vertices.iter().enumerate() {
            n += a.cross(vertices[(i + 1) % vertices.len()]);
        }
        let normal = n.try_normalize()?;
        let centre = vertices.iter().sum::<DVec3>() / vertices.len() as f64;
        Some(Self {
            plane: Plane {
                normal,
                w: normal.dot(centre),
            },
            vertices,
        })
    }

    fn flip(&mut self) {
        self.vertices.reverse();
        self.plane.flip();
    }
}

/// Where [`split`] sends pieces.
#[derive(Default)]
struct Sides {
    coplanar_front: Vec<Polygon>,
    coplanar_back: Vec<Polygon>,
    front: Vec<Polygon>,
    back: Vec<Polygon>,
}

/// Classifies `poly` against `plane`, splitting it if it spans the plane.
fn split(plane: &Plane, poly: Polygon, out: &mut Sides) {
    const COPLANAR: u8 = 0;
    const FRONT: u8 = 1;
    const BACK: u8 = 2;
    let kinds: Vec<u8> = poly
        .vertices
        .iter()
        .map(|&v| {
            let t = plane.distance(v);
            if t < -EPSILON {
                BACK
            } else if t > EPSILON {
                FRONT
            } else {
                COPLANAR
            }
        })
        .collect();
    match kinds.iter().fold(0, |acc, k| acc | k) {
        COPLANAR => {
            if plane.normal.dot(poly.plane.normal) > 0.0 {
                out.coplanar_front.push(poly);
            } else {
                out.coplanar_back.push(poly);
            }
        }
        FRONT => out.front.push(poly),
        BACK => out.back.push(poly),
        _ => {
            let n = poly.vertices.len();
            let (mut f, mut b) = (Vec::with_capacity(n + 1), Vec::with_capacity(n + 1));
            for i in 0..n {
                let j = (i + 1) % n;
                let (ki, kj) = (kinds[i], kinds[j]);
                let (vi, vj) = (poly.vertices[i], poly.vertices[j]);
                if ki != BACK {
                    f.push(vi);
                }
                if ki != FRONT {
                    b.push(vi);
                }
                if ki | kj == FRONT | BACK {
                    // The crossing point, computed from the lower-sorted end so that the two
                    // polygons sharing this edge get the same point.
                    let (p, q) = if vi.to_array() < vj.to_array() {
                        (vi, vj)
                    } else {
                        (vj, vi)
                    };
                    let t = plane.distance(p) / (plane.distance(p) - plane.distance(q));
                    let v = p.lerp(q, t);
                    f.push(v);
                    b.push(v);
                }
            }
            if f.len() >= 3 {
                out.front.push(Polygon {
                    vertices: f,
                    plane: poly.plane,
                });
            }
            if b.len() >= 3 {
                out.back.push(Polygon {
                    vertices: b,
                    plane: poly.plane,
                });
            }
        }
    }
}

#[derive(Clone, Debug)]
struct Node {
    plane: Plane,
    polygons: Vec<Polygon>,
    front: Option<usize>,
    back: Option<usize>,
}

/// A BSP tree of convex polygons (see the module doc).
#[derive(Clone, Debug, Default)]
pub struct BspTree {
    nodes: Vec<Node>,
}

impl BspTree {
    /// A tree of `polygons`, each node split by its first polygon's plane.
    #[must_use]
    pub fn new(polygons: Vec<Polygon>) -> Self {
        let mut t = Self::default();
        t.build(polygons);
        t
    }

    /// Adds `polygons` to the tree, splitting them (and growing leaves) as needed.
    pub fn build(&mut self, polygons: Vec<Polygon>) {
        if polygons.is_empty() {
            return;
        }
        if self.nodes.is_empty() {
            self.nodes.push(Node {
                plane: polygons[0].plane,
                polygons: Vec::new(),
                front: None,
                back: None,
            });
        }
        let mut work = vec![(0usize, polygons)];
        while let Some((n, polys)) = work.pop() {
            let plane = self.nodes[n].plane;
            let mut sides = Sides::default();
            for p in polys {
                split(&plane, p, &mut sides);
            }
            let node = &mut self.nodes[n];
            node.polygons.append(&mut sides.coplanar_front);
            node.polygons.append(&mut sides.coplanar_back);
            for (list, front) in [(sides.front, true), (sides.back, false)] {
                if list.is_empty() {
                    continue;
                }
                let child = if front {
                    self.nodes[n].front
                } else {
                    self.nodes[n].back
                };
                let child = child.unwrap_or_else(|| {
                    self.nodes.push(Node {
                        plane: list[0].plane,
                        polygons: Vec::new(),
                        front: None,
                        back: None,
                    });
                    let c = self.nodes.len() - 1;
                    if front {
                        self.nodes[n].front = Some(c);
                    } else {
                        self.nodes[n].back = Some(c);
                    }
                    c
                });
                work.push((child, list));
            }
        }
    }

    /// Turns the solid inside out: every plane and polygon flipped, front and back swapped.
    pub fn invert(&mut self) {
        for node in &mut self.nodes {
            node.plane.flip();
            for p in &mut node.polygons {
                p.flip();
            }
            std::mem::swap(&mut node.front, &mut node.back);
        }
    }

    /// The parts of `polygons` outside the solid this tree bounds (pieces reaching an empty
    /// back subtree are inside and dropped).
    #[must_use]
    pub fn clip_polygons(&self, polygons: Vec<Polygon>) -> Vec<Polygon> {
        if self.nodes.is_empty() {
            return polygons;
        }
        let mut kept = Vec::new();
        let mut work = vec![(0usize, polygons)];
        while let Some((n, polys)) = work.pop() {
            let node = &self.nodes[n];
            let mut sides = Sides::default();
            for p in polys {
                split(&node.plane, p, &mut sides);
            }
            let mut front = sides.front;
            front.append(&mut sides.coplanar_front);
            let mut back = sides.back;
            back.append(&mut sides.coplanar_back);
            match node.front {
                Some(c) => work.push((c, front)),
                None => kept.extend(front),
            }
            if let Some(c) = node.back {
                work.push((c, back));
            }
        }
        kept
    }

    /// Removes from this tree's polygons the parts inside `other`'s solid.
    pub fn clip_to(&mut self, other: &Self) {
        for i in 0..self.nodes.len() {
            let polys = std::mem::take(&mut self.nodes[i].polygons);
            self.nodes[i].polygons = other.clip_polygons(polys);
        }
    }

    /// Every polygon in the tree.
    #[must_use]
    pub fn all_polygons(&self) -> Vec<Polygon> {
        self.nodes
            .iter()
            .flat_map(|n| n.polygons.iter().cloned())
            .collect()
    }

    /// Number of nodes.
    #[must_use]
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the tree has no node.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Checks the invariants: child indices in range and every node reached exactly once from
    /// the root; every polygon of a node on its plane; every polygon of a front (back) subtree
    /// on or in front of (behind) each ancestor's plane, within a tolerance of a few
    /// [`EPSILON`].
    ///
    /// # Errors
    /// The first violation, as a message.
    pub fn validate(&self) -> Result<(), String> {
        if self.nodes.is_empty() {
            return Ok(());
        }
        let tol = 4.0 * EPSILON;
        let mut reached = vec![false; self.nodes.len()];
        // (node, constraints: (plane, +1 front / −1 back) of its ancestors)
        let mut work: Vec<(usize, Vec<(Plane, f64)>)> = vec![(0, Vec::new())];
        while let Some((n, constraints)) = work.pop() {
            let Some(node) = self.nodes.get(n) else {
                return Err(format!("child index {n} out of range"));
            };
            if std::mem::replace(&mut reached[n], true) {
                return Err(format!("node {n} reached twice"));
            }
            for p in &node.polygons {
                for v in &p.vertices {
                    if node.plane.distance(*v).abs() > tol {
                        return Err(format!("node {n}: a polygon is off the node's plane"));
                    }
                    for (plane, side) in &constraints {
                        if plane.distance(*v) * side < -tol {
                            return Err(format!("node {n}: a polygon on the wrong side"));
                        }
                    }
                }
            }
            for (child, side) in [(node.front, 1.0), (node.back, -1.0)] {
                if let Some(c) = child {
                    let mut cs = constraints.clone();
                    cs.push((node.plane, side));
                    work.push((c, cs));
                }
            }
        }
        if reached.iter().all(|&r| r) {
            Ok(())
        } else {
            Err("a node is not reachable from the root".into())
        }
    }
}
