//! Boundary representation: a half-edge solid (Mäntylä 1988, "An Introduction to Solid
//! Modeling", ch. 10–11) with Euler operators, and the Euler–Poincaré check of closed meshes.
//!
//! A solid has vertices, edges, faces, loops and shells. Each face is bounded by one outer loop
//! and any number of inner loops (rings); a loop is a cycle of half-edges (or a single vertex,
//! the state after MVFS); each edge is two twin half-edges running in opposite directions, one
//! in each adjacent loop. For a valid solid the counts satisfy the Euler–Poincaré formula
//!
//!   V − E + F − (L − F) = 2 (S − H),
//!
//! with L − F the number of rings, S the number of shells (connected components) and H the
//! number of through-holes (the genus, summed over shells). For a closed polygon mesh (no
//! rings) this is V − E + F = 2 (S − H), which gives the genus of each output of the toolkit:
//! a sphere 0, a torus 1.
//!
//! The Euler operators ([`euler`]) change the counts by one legal step each (MVFS, MEV, MEF,
//! KEMR, KFMRH and their inverses KVFS, KEV, KEF, MEKR, MFKRH), so the formula holds after
//! every step; an operator whose arguments do not fit is refused with a [`BrepError`] and
//! leaves the solid unchanged.

pub mod euler;

use std::collections::HashMap;
use std::fmt;

use glam::DVec3;

use crate::PolyMesh;

/// A vertex of a [`Solid`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct VertexId(pub(crate) usize);
/// A half-edge of a [`Solid`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct HalfEdgeId(pub(crate) usize);
/// A loop of a [`Solid`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LoopId(pub(crate) usize);
/// A face of a [`Solid`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FaceId(pub(crate) usize);

/// Why a mesh or an operation was refused.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum BrepError {
    /// An id that does not name a live element.
    Stale(&'static str),
    /// The arguments do not fit the operator (the message says why).
    Precondition(&'static str),
    /// A face of the mesh has fewer than three corners or an index out of range.
    BadFace(usize),
    /// A directed edge (from, to) is used by two faces: non-manifold or inconsistently
    /// oriented.
    DuplicateEdge(u32, u32),
    /// A directed edge (from, to) has no opposite: the mesh has a hole.
    OpenEdge(u32, u32),
}

impl fmt::Display for BrepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Stale(what) => write!(f, "no such {what}"),
            Self::Precondition(why) => f.write_str(why),
            Self::BadFace(i) => write!(f, "face {i} has fewer than 3 corners or a bad index"),
            Self::DuplicateEdge(a, b) => write!(
                f,
                "edge {a}→{b} is used twice (non-manifold or inconsistently oriented)"
            ),
            Self::OpenEdge(a, b) => write!(f, "edge {a}→{b} has no opposite edge (open mesh)"),
        }
    }
}

impl std::error::Error for BrepError {}

#[derive(Clone, Debug)]
pub(crate) struct HalfEdge {
    pub(crate) origin: usize,
    pub(crate) next: usize,
    pub(crate) prev: usize,
    pub(crate) twin: usize,
    pub(crate) lp: usize,
}

/// Where a loop starts: a lone vertex (no edges yet) or one of its half-edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Start {
    Vertex(usize),
    HalfEdge(usize),
}

#[derive(Clone, Debug)]
pub(crate) struct Loop {
    pub(crate) face: usize,
    pub(crate) start: Start,
}

#[derive(Clone, Debug)]
pub(crate) struct Face {
    pub(crate) outer: usize,
    pub(crate) rings: Vec<usize>,
}

/// The element counts of a solid and the Euler–Poincaré formula.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EulerCounts {
    /// Vertices V.
    pub vertices: usize,
    /// Edges E.
    pub edges: usize,
    /// Faces F.
    pub faces: usize,
    /// Loops L (outer loops and rings).
    pub loops: usize,
    /// Shells S (connected components).
    pub shells: usize,
    /// Through-holes H (genus).
    pub holes: usize,
}

impl EulerCounts {
    /// Whether V − E + F − (L − F) = 2 (S − H).
    #[must_use]
    pub fn holds(&self) -> bool {
        let lhs =
            self.vertices as i64 - self.edges as i64 + 2 * self.faces as i64 - self.loops as i64;
        lhs == 2 * (self.shells as i64 - self.holes as i64)
    }
}

/// A half-edge boundary representation (see the module doc).
#[derive(Clone, Debug, Default)]
pub struct Solid {
    pub(crate) vertices: Vec<Option<DVec3>>,
    pub(crate) half_edges: Vec<Option<HalfEdge>>,
    pub(crate) loops: Vec<Option<Loop>>,
    pub(crate) faces: Vec<Option<Face>>,
    /// Through-holes, kept by the operators that make and kill them.
    pub(crate) holes: usize,
}

impl Solid {
    /// An empty solid; start it with [`Solid::mvfs`].
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// A closed polygon mesh as a solid: one face and one loop per polygon, twins matched by
    /// their vertex indices, the genus from the Euler–Poincaré formula.
    ///
    /// # Errors
    /// A face with fewer than three corners or a bad index, a directed edge used twice, or an
    /// edge without its opposite (the mesh is not a closed, oriented 2-manifold).
    pub fn from_polymesh(mesh: &PolyMesh) -> Result<Self, BrepError> {
        let mut s = Self {
            vertices: mesh.positions.iter().map(|p| Some(p.as_dvec3())).collect(),
            ..Self::default()
        };
        let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
        for (fi, face) in mesh.faces.iter().enumerate() {
            let n = face.len();
            if n < 3 || face.iter().any(|&i| i as usize >= mesh.positions.len()) {
                return Err(BrepError::BadFace(fi));
            }
            let (f, l, base) = (s.faces.len(), s.loops.len(), s.half_edges.len());
            for k in 0..n {
                let (a, b) = (face[k], face[(k + 1) % n]);
                if a == b || directed.insert((a, b), base + k).is_some() {
                    return Err(if a == b {
                        BrepError::BadFace(fi)
                    } else {
                        BrepError::DuplicateEdge(a, b)
                    });
                }
                s.half_edges.push(Some(HalfEdge {
                    origin: a as usize,
                    next: base + (k + 1) % n,
                    prev: base + (k + n - 1) % n,
                    twin: usize::MAX,
                    lp: l,
                }));
            }
            s.loops.push(Some(Loop {
                face: f,
                start: Start::HalfEdge(base),
            }));
            s.faces.push(Some(Face {
                outer: l,
                rings: Vec::new(),
            }));
        }
        for (&(a, b), &h) in &directed {
            let &t = directed.get(&(b, a)).ok_or(BrepError::OpenEdge(a, b))?;
            if let Some(he) = s.half_edges[h].as_mut() {
                he.twin = t;
            }
        }
        // Unused positions are not vertices of the solid.
        let mut used = vec![false; s.vertices.len()];
        for he in s.half_edges.iter().flatten() {
            used[he.origin] = true;
        }
        for (v, u) in s.vertices.iter_mut().zip(used) {
            if !u {
                *v = None;
            }
        }
        let c = s.count_elements(0);
        let chi = c.vertices as i64 - c.edges as i64 + c.faces as i64;
        s.holes = usize::try_from(c.shells as i64 - chi / 2).unwrap_or(0);
        Ok(s)
    }

    /// V, E, F, L, S and H.
    #[must_use]
    pub fn counts(&self) -> EulerCounts {
        self.count_elements(self.holes)
    }

    fn count_elements(&self, holes: usize) -> EulerCounts {
        EulerCounts {
            vertices: self.vertices.iter().flatten().count(),
            edges: self.half_edges.iter().flatten().count() / 2,
            faces: self.faces.iter().flatten().count(),
            loops: self.loops.iter().flatten().count(),
            shells: self.shells(),
            holes,
        }
    }

    /// The genus H (through-holes, summed over shells).
    #[must_use]
    pub fn genus(&self) -> usize {
        self.holes
    }

    /// Connected components: vertices joined by edges and by sharing a face.
    #[must_use]
    pub fn shells(&self) -> usize {
        let mut parent: Vec<usize> = (0..self.vertices.len()).collect();
        fn find(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        let union = |p: &mut Vec<usize>, a: usize, b: usize| {
            let (ra, rb) = (find(p, a), find(p, b));
            p[ra] = rb;
        };
        for he in self.half_edges.iter().flatten() {
            let end = self.half_edges[he.next]
                .as_ref()
                .map_or(he.origin, |n| n.origin);
            union(&mut parent, he.origin, end);
        }
        for face in self.faces.iter().flatten() {
            let first = self.loop_vertex(face.outer);
            for &r in &face.rings {
                if let (Some(a), Some(b)) = (first, self.loop_vertex(r)) {
                    union(&mut parent, a, b);
                }
            }
        }
        (0..self.vertices.len())
            .filter(|&v| self.vertices[v].is_some() && find(&mut parent, v) == v)
            .count()
    }

    /// A vertex of loop `l`.
    fn loop_vertex(&self, l: usize) -> Option<usize> {
        match self.loops.get(l)?.as_ref()?.start {
            Start::Vertex(v) => Some(v),
            Start::HalfEdge(h) => self.half_edges[h].as_ref().map(|h| h.origin),
        }
    }

    /// The half-edges of loop `l` in order (empty for a lone-vertex loop).
    pub(crate) fn cycle(&self, l: usize) -> Vec<usize> {
        let Some(Some(lp)) = self.loops.get(l) else {
            return Vec::new();
        };
        let Start::HalfEdge(first) = lp.start else {
            return Vec::new();
        };
        let mut out = vec![first];
        let mut h = first;
        while let Some(he) = self.half_edges[h].as_ref() {
            h = he.next;
            if h == first || out.len() > self.half_edges.len() {
                break;
            }
            out.push(h);
        }
        out
    }

    /// Checks every structural invariant: live references, next/prev inverse, twins are an
    /// involution joining opposite directions, loops are closed cycles whose half-edges name
    /// them, faces and loops agree, and the Euler–Poincaré formula holds.
    ///
    /// # Errors
    /// The first invariant that fails, as a message.
    pub fn validate(&self) -> Result<(), String> {
        let live = |h: usize| self.half_edges.get(h).is_some_and(Option::is_some);
        for (i, he) in self.half_edges.iter().enumerate() {
            let Some(he) = he else { continue };
            if !(live(he.next) && live(he.prev) && live(he.twin)) || he.twin == i {
                return Err(format!("half-edge {i} has a dead or self neighbour"));
            }
            let (next, twin) = (&self.half_edges[he.next], &self.half_edges[he.twin]);
            let (Some(next), Some(twin)) = (next, twin) else {
                return Err(format!("half-edge {i}: dead neighbour"));
            };
            if self.half_edges[he.prev].as_ref().map(|p| p.next) != Some(i) {
                return Err(format!("half-edge {i}: prev.next is not itself"));
            }
            if twin.twin != i || twin.origin != next.origin {
                return Err(format!("half-edge {i}: twin does not run back"));
            }
            if self
                .vertices
                .get(he.origin)
                .and_then(|v| v.as_ref())
                .is_none()
            {
                return Err(format!("half-edge {i}: dead origin"));
            }
            if !self.loops.get(he.lp).is_some_and(Option::is_some) {
                return Err(format!("half-edge {i}: dead loop"));
            }
        }
        let mut seen = 0;
        for (l, lp) in self.loops.iter().enumerate() {
            let Some(lp) = lp else { continue };
            let Some(Some(face)) = self.faces.get(lp.face) else {
                return Err(format!("loop {l}: dead face"));
            };
            if face.outer != l && !face.rings.contains(&l) {
                return Err(format!("loop {l}: not listed by its face"));
            }
            if let Start::Vertex(v) = lp.start {
                if self.vertices.get(v).and_then(|v| v.as_ref()).is_none() {
                    return Err(format!("loop {l}: dead lone vertex"));
                }
            }
            for h in self.cycle(l) {
                if self.half_edges[h].as_ref().map(|he| he.lp) != Some(l) {
                    return Err(format!("loop {l}: half-edge {h} names another loop"));
                }
                seen += 1;
            }
        }
        if seen != self.half_edges.iter().flatten().count() {
            return Err("a half-edge is in no loop cycle".into());
        }
        for (f, face) in self.faces.iter().enumerate() {
            let Some(face) = face else { continue };
            for &l in std::iter::once(&face.outer).chain(&face.rings) {
                if self.loops.get(l).and_then(|l| l.as_ref()).map(|l| l.face) != Some(f) {
                    return Err(format!("face {f}: loop {l} does not name it"));
                }
            }
        }
        let c = self.counts();
        if !c.holds() {
            return Err(format!("Euler–Poincaré formula fails: {c:?}"));
        }
        Ok(())
    }
}

/// Topology of a closed mesh: counts, genus and the formula's check, or why it is not closed.
///
/// # Errors
/// As [`Solid::from_polymesh`], or a structure or formula failure from [`Solid::validate`].
pub fn closed_topology(mesh: &PolyMesh) -> Result<EulerCounts, BrepError> {
    let s = Solid::from_polymesh(mesh)?;
    let c = s.counts();
    let chi = c.vertices as i64 - c.edges as i64 + c.faces as i64;
    if chi % 2 != 0 || chi > 2 * c.shells as i64 || s.validate().is_err() {
        return Err(BrepError::Precondition("not an orientable closed surface"));
    }
    Ok(c)
}

/// Volume enclosed by a closed, outward-oriented mesh, by the divergence theorem:
/// V = ⅙ Σ over triangles (fans of each face) of a · (b × c).
#[must_use]
pub fn signed_volume(mesh: &PolyMesh) -> f64 {
    let p = |i: u32| {
        mesh.positions
            .get(i as usize)
            .map_or(DVec3::ZERO, |v| v.as_dvec3())
    };
    mesh.faces
        .iter()
        .filter(|f| f.len() >= 3)
        .map(|f| {
            let a = p(f[0]);
            (1..f.len() - 1)
                .map(|k| a.dot(p(f[k]).cross(p(f[k + 1]))))
                .sum::<f64>()
        })
        .sum::<f64>()
        / 6.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::{cuboid, icosphere};
    use glam::Vec3;

    #[test]
    fn cube_and_sphere_are_genus_zero() {
        let cube = cuboid(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        let c = closed_topology(&cube).unwrap();
        assert_eq!(
            (c.vertices, c.edges, c.faces, c.shells, c.holes),
            (8, 12, 6, 1, 0)
        );
        assert!((signed_volume(&cube) - 6.0).abs() < 1e-9);
        let s = closed_topology(&icosphere(Vec3::ZERO, 1.0, 2)).unwrap();
        assert_eq!((s.shells, s.holes), (1, 0));
    }

    #[test]
    fn open_and_flipped_meshes_are_refused() {
        let mut cube = cuboid(Vec3::ZERO, Vec3::ONE);
        cube.faces.pop();
        assert!(matches!(
            Solid::from_polymesh(&cube),
            Err(BrepError::OpenEdge(..))
        ));
        let mut cube = cuboid(Vec3::ZERO, Vec3::ONE);
        cube.faces[0].reverse();
        assert!(matches!(
            Solid::from_polymesh(&cube),
            Err(BrepError::DuplicateEdge(..))
        ));
    }

    #[test]
    fn two_cubes_are_two_shells() {
        let mut m = cuboid(Vec3::ZERO, Vec3::ONE);
        let other = cuboid(Vec3::splat(3.0), Vec3::splat(4.0));
        let base = m.positions.len() as u32;
        m.positions.extend(other.positions);
        m.faces.extend(
            other
                .faces
                .iter()
                .map(|f| f.iter().map(|i| i + base).collect()),
        );
        let c = closed_topology(&m).unwrap();
        assert_eq!((c.shells, c.holes), (2, 0));
        assert!((signed_volume(&m) - 2.0).abs() < 1e-9);
    }
}
