//! Euler operators on a [`Solid`] (Mäntylä 1988, ch. 9; Baumgart's winged-edge operators).
//!
//! Each operator changes (V, E, F, L, S, H) by one of the generators of the solutions of
//! V − E + F − (L − F) = 2 (S − H), so the formula holds after every step:
//!
//! | operator | ΔV | ΔE | ΔF | ΔL | ΔS | ΔH | inverse |
//! |---|---|---|---|---|---|---|---|
//! | MVFS  make vertex, face, shell | +1 | 0 | +1 | +1 | +1 | 0 | KVFS |
//! | MEV   make edge and vertex     | +1 | +1 | 0 | 0 | 0 | 0 | KEV |
//! | MEF   make edge and face       | 0 | +1 | +1 | +1 | 0 | 0 | KEF |
//! | KEMR  kill edge, make ring     | 0 | −1 | 0 | +1 | 0 | 0 | MEKR |
//! | KFMRH kill face, make ring and hole | 0 | 0 | −1 | 0 | 0 | +1 (or S −1) | MFKRH |
//!
//! Operators that do not apply (ids of dead elements, half-edges in the wrong loops, a vertex
//! that is not free) return [`BrepError`] and change nothing.

use glam::DVec3;

use super::{BrepError, Face, FaceId, HalfEdge, HalfEdgeId, Loop, LoopId, Solid, Start, VertexId};

/// A place in a loop where an operator attaches: the origin of a half-edge (in its loop), or the
/// single vertex of a loop without edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Corner {
    /// The origin vertex of this half-edge, in the half-edge's loop.
    At(HalfEdgeId),
    /// The lone vertex of an edge-less loop.
    Lone(LoopId),
}

const FREE: usize = usize::MAX;

impl Solid {
    /// MVFS: a new shell of one vertex at `p`, one face and its (edge-less) loop.
    pub fn mvfs(&mut self, p: DVec3) -> (VertexId, FaceId, LoopId) {
        let v = self.push_vertex(p);
        let (f, l) = (self.faces.len(), self.loops.len());
        self.loops.push(Some(Loop {
            face: f,
            start: Start::Vertex(v),
        }));
        self.faces.push(Some(Face {
            outer: l,
            rings: Vec::new(),
        }));
        (VertexId(v), FaceId(f), LoopId(l))
    }

    /// KVFS: removes a shell made of a single vertex and face (the inverse of MVFS).
    ///
    /// # Errors
    /// `f` is dead, has rings or edges.
    pub fn kvfs(&mut self, f: FaceId) -> Result<(), BrepError> {
        let face = self.face(f.0)?;
        let l = face.outer;
        let Start::Vertex(v) = self.lp(l)?.start else {
            return Err(BrepError::Precondition("KVFS needs a face with no edges"));
        };
        if !face.rings.is_empty() {
            return Err(BrepError::Precondition("KVFS needs a face without rings"));
        }
        self.vertices[v] = None;
        self.loops[l] = None;
        self.faces[f.0] = None;
        Ok(())
    }

    /// MEV: a new edge from the vertex at `at` to a new vertex at `p`, in `at`'s loop.
    /// Returns the new vertex and the half-edge running to it.
    ///
    /// # Errors
    /// `at` names a dead element or a loop that has edges.
    pub fn mev(&mut self, at: Corner, p: DVec3) -> Result<(VertexId, HalfEdgeId), BrepError> {
        let (l, v, h) = self.corner(at)?;
        let w = self.push_vertex(p);
        let (a, b) = self.push_edge(v, w, l);
        match h {
            Some(h) => {
                let pr = self.he(h)?.prev;
                self.link(pr, a);
                self.link(a, b);
                self.link(b, h);
            }
            None => {
                self.link(a, b);
                self.link(b, a);
                self.set_start(l, Start::HalfEdge(a));
            }
        }
        Ok((VertexId(w), HalfEdgeId(a)))
    }

    /// KEV: removes the edge of `h` and the vertex it runs to, which must have no other edge
    /// (the inverse of MEV).
    ///
    /// # Errors
    /// `h` is dead or its end vertex has other edges.
    pub fn kev(&mut self, h: HalfEdgeId) -> Result<(), BrepError> {
        let a = h.0;
        let ha = self.he(a)?.clone();
        let b = ha.twin;
        if ha.next != b {
            return Err(BrepError::Precondition(
                "KEV needs a half-edge to a vertex with no other edge",
            ));
        }
        let w = self.he(b)?.origin;
        let hb = self.he(b)?.clone();
        if hb.next == a {
            self.set_start(ha.lp, Start::Vertex(ha.origin));
        } else {
            self.link(ha.prev, hb.next);
            self.set_start(ha.lp, Start::HalfEdge(hb.next));
        }
        self.half_edges[a] = None;
        self.half_edges[b] = None;
        self.vertices[w] = None;
        Ok(())
    }

    /// MEF: a new edge from the origin of `h1` to the origin of `h2` (distinct half-edges of
    /// one loop) that splits the loop and its face in two. Returns the new face and the new
    /// half-edge bounding it.
    ///
    /// # Errors
    /// A dead half-edge, `h1 == h2`, or half-edges in different loops.
    pub fn mef(
        &mut self,
        h1: HalfEdgeId,
        h2: HalfEdgeId,
    ) -> Result<(FaceId, HalfEdgeId), BrepError> {
        let (e1, e2) = (self.he(h1.0)?.clone(), self.he(h2.0)?.clone());
        if h1 == h2 || e1.lp != e2.lp {
            return Err(BrepError::Precondition(
                "MEF needs two distinct half-edges of one loop",
            ));
        }
        let l = e1.lp;
        let (a, b) = self.push_edge(e1.origin, e2.origin, l);
        self.link(e1.prev, a);
        self.link(a, h2.0);
        self.link(e2.prev, b);
        self.link(b, h1.0);
        self.set_start(l, Start::HalfEdge(a));
        let (f, nl) = (self.faces.len(), self.loops.len());
        self.loops.push(Some(Loop {
            face: f,
            start: Start::HalfEdge(b),
        }));
        self.faces.push(Some(Face {
            outer: nl,
            rings: Vec::new(),
        }));
        for e in self.cycle(nl) {
            if let Some(he) = self.half_edges[e].as_mut() {
                he.lp = nl;
            }
        }
        Ok((FaceId(f), HalfEdgeId(b)))
    }

    /// KEF: removes the edge of `h` and merges the face on its twin's side into the face on
    /// `h`'s side (the inverse of MEF).
    ///
    /// # Errors
    /// `h` is dead, both sides are in the same face, or the twin's loop is a ring.
    pub fn kef(&mut self, h: HalfEdgeId) -> Result<(), BrepError> {
        let a = h.0;
        let ha = self.he(a)?.clone();
        let b = ha.twin;
        let hb = self.he(b)?.clone();
        let (fa, fb) = (self.lp(ha.lp)?.face, self.lp(hb.lp)?.face);
        if fa == fb {
            return Err(BrepError::Precondition(
                "KEF needs an edge between two different faces",
            ));
        }
        let kill = self.face(fb)?.clone();
        if kill.outer != hb.lp {
            return Err(BrepError::Precondition(
                "KEF needs the twin in its face's outer loop",
            ));
        }
        let x = self.cycle_from(a);
        let y = self.cycle_from(b);
        let merged: Vec<usize> = x[1..].iter().chain(&y[1..]).copied().collect();
        self.half_edges[a] = None;
        self.half_edges[b] = None;
        self.relink(ha.lp, &merged, ha.origin);
        for &r in &kill.rings {
            if let Some(lp) = self.loops[r].as_mut() {
                lp.face = fa;
            }
        }
        if let Some(face) = self.faces[fa].as_mut() {
            face.rings.extend(kill.rings);
        }
        self.loops[hb.lp] = None;
        self.faces[fb] = None;
        Ok(())
    }

    /// KEMR: removes the edge of `h`, both of whose half-edges lie in one loop, splitting the
    /// loop in two: the part at `h`'s origin stays, the part at its end becomes a new ring of
    /// the same face (returned).
    ///
    /// # Errors
    /// `h` is dead or its twin is in another loop.
    pub fn kemr(&mut self, h: HalfEdgeId) -> Result<LoopId, BrepError> {
        let a = h.0;
        let ha = self.he(a)?.clone();
        let b = ha.twin;
        let hb = self.he(b)?.clone();
        if ha.lp != hb.lp {
            return Err(BrepError::Precondition(
                "KEMR needs an edge with both sides in one loop",
            ));
        }
        let l = ha.lp;
        let cycle = self.cycle_from(a);
        let k = cycle.iter().position(|&e| e == b).unwrap_or(cycle.len());
        let x: Vec<usize> = cycle[1..k].to_vec();
        let y: Vec<usize> = cycle.get(k + 1..).unwrap_or_default().to_vec();
        let face = self.lp(l)?.face;
        let ring = self.loops.len();
        self.loops.push(Some(Loop {
            face,
            start: Start::Vertex(hb.origin),
        }));
        if let Some(f) = self.faces[face].as_mut() {
            f.rings.push(ring);
        }
        self.half_edges[a] = None;
        self.half_edges[b] = None;
        self.relink(l, &y, ha.origin);
        self.relink(ring, &x, hb.origin);
        Ok(LoopId(ring))
    }

    /// MEKR: a new edge from corner `c1` to corner `c2`, in two different loops of one face,
    /// one of them a ring; the ring is merged into the other loop (the inverse of KEMR).
    /// Returns the half-edge from `c1` to `c2`.
    ///
    /// # Errors
    /// Dead elements, one loop, loops of different faces, or neither loop a ring.
    pub fn mekr(&mut self, c1: Corner, c2: Corner) -> Result<HalfEdgeId, BrepError> {
        let (l1, v1, h1) = self.corner(c1)?;
        let (l2, v2, h2) = self.corner(c2)?;
        let face = self.lp(l1)?.face;
        if l1 == l2 || self.lp(l2)?.face != face {
            return Err(BrepError::Precondition(
                "MEKR needs two different loops of one face",
            ));
        }
        let f = self.face(face)?.clone();
        let (keep, kill) = if f.rings.contains(&l2) {
            (l1, l2)
        } else if f.rings.contains(&l1) {
            (l2, l1)
        } else {
            return Err(BrepError::Precondition(
                "MEKR needs one of the loops to be a ring",
            ));
        };
        let x = h2.map(|h| self.cycle_from(h)).unwrap_or_default();
        let y = h1.map(|h| self.cycle_from(h)).unwrap_or_default();
        let (a, b) = self.push_edge(v1, v2, keep);
        let merged: Vec<usize> = std::iter::once(a)
            .chain(x)
            .chain(std::iter::once(b))
            .chain(y)
            .collect();
        self.relink(keep, &merged, v1);
        if let Some(face) = self.faces[face].as_mut() {
            face.rings.retain(|&r| r != kill);
        }
        self.loops[kill] = None;
        Ok(HalfEdgeId(a))
    }

    /// KFMRH: face `kill` (without rings) becomes a ring of face `keep`. Within one shell this
    /// makes a through-hole (H + 1); across two shells it joins them (S − 1).
    ///
    /// # Errors
    /// Dead faces, the same face twice, or `kill` has rings.
    pub fn kfmrh(&mut self, keep: FaceId, kill: FaceId) -> Result<(), BrepError> {
        self.face(keep.0)?;
        let k = self.face(kill.0)?.clone();
        if keep == kill || !k.rings.is_empty() {
            return Err(BrepError::Precondition(
                "KFMRH needs two different faces, the killed one without rings",
            ));
        }
        let before = self.shells();
        if let Some(lp) = self.loops[k.outer].as_mut() {
            lp.face = keep.0;
        }
        if let Some(f) = self.faces[keep.0].as_mut() {
            f.rings.push(k.outer);
        }
        self.faces[kill.0] = None;
        if self.shells() == before {
            self.holes += 1;
        }
        Ok(())
    }

    /// MFKRH: ring `ring` becomes the outer loop of a new face (returned), removing a
    /// through-hole or splitting a shell (the inverse of KFMRH).
    ///
    /// # Errors
    /// `ring` is dead or an outer loop, or the split would need a hole the solid does not have.
    pub fn mfkrh(&mut self, ring: LoopId) -> Result<FaceId, BrepError> {
        let face = self.lp(ring.0)?.face;
        if !self.face(face)?.rings.contains(&ring.0) {
            return Err(BrepError::Precondition("MFKRH needs a ring"));
        }
        let before = self.shells();
        let f = self.faces.len();
        self.faces.push(Some(Face {
            outer: ring.0,
            rings: Vec::new(),
        }));
        if let Some(old) = self.faces[face].as_mut() {
            old.rings.retain(|&r| r != ring.0);
        }
        if let Some(lp) = self.loops[ring.0].as_mut() {
            lp.face = f;
        }
        if self.shells() == before {
            if self.holes == 0 {
                // Undo: without a hole to remove the formula would break.
                self.faces.pop();
                if let Some(lp) = self.loops[ring.0].as_mut() {
                    lp.face = face;
                }
                if let Some(old) = self.faces[face].as_mut() {
                    old.rings.push(ring.0);
                }
                return Err(BrepError::Precondition(
                    "MFKRH would neither split a shell nor remove a hole",
                ));
            }
            self.holes -= 1;
        }
        Ok(FaceId(f))
    }

    /// The origin vertex of `h`.
    ///
    /// # Errors
    /// `h` is dead.
    pub fn origin(&self, h: HalfEdgeId) -> Result<VertexId, BrepError> {
        Ok(VertexId(self.he(h.0)?.origin))
    }

    /// The next half-edge of `h`'s loop.
    ///
    /// # Errors
    /// `h` is dead.
    pub fn next(&self, h: HalfEdgeId) -> Result<HalfEdgeId, BrepError> {
        Ok(HalfEdgeId(self.he(h.0)?.next))
    }

    /// The opposite half-edge of `h`'s edge.
    ///
    /// # Errors
    /// `h` is dead.
    pub fn twin(&self, h: HalfEdgeId) -> Result<HalfEdgeId, BrepError> {
        Ok(HalfEdgeId(self.he(h.0)?.twin))
    }

    /// The face of `h`'s loop.
    ///
    /// # Errors
    /// `h` is dead.
    pub fn face_of(&self, h: HalfEdgeId) -> Result<FaceId, BrepError> {
        Ok(FaceId(self.lp(self.he(h.0)?.lp)?.face))
    }

    /// The position of `v`.
    ///
    /// # Errors
    /// `v` is dead.
    pub fn position(&self, v: VertexId) -> Result<DVec3, BrepError> {
        self.vertices
            .get(v.0)
            .copied()
            .flatten()
            .ok_or(BrepError::Stale("vertex"))
    }

    /// The live faces, in creation order.
    #[must_use]
    pub fn faces(&self) -> Vec<FaceId> {
        (0..self.faces.len())
            .filter(|&f| self.faces[f].is_some())
            .map(FaceId)
            .collect()
    }

    /// A half-edge of face `f`'s outer loop (`None` if dead or edge-less).
    #[must_use]
    pub fn outer_half_edge(&self, f: FaceId) -> Option<HalfEdgeId> {
        self.loop_half_edge(LoopId(self.face(f.0).ok()?.outer))
    }

    /// A half-edge of loop `l` (`None` if dead or edge-less).
    #[must_use]
    pub fn loop_half_edge(&self, l: LoopId) -> Option<HalfEdgeId> {
        match self.lp(l.0).ok()?.start {
            Start::HalfEdge(h) => Some(HalfEdgeId(h)),
            Start::Vertex(_) => None,
        }
    }

    fn he(&self, h: usize) -> Result<&HalfEdge, BrepError> {
        self.half_edges
            .get(h)
            .and_then(Option::as_ref)
            .ok_or(BrepError::Stale("half-edge"))
    }

    fn lp(&self, l: usize) -> Result<&Loop, BrepError> {
        self.loops
            .get(l)
            .and_then(Option::as_ref)
            .ok_or(BrepError::Stale("loop"))
    }

    fn face(&self, f: usize) -> Result<&Face, BrepError> {
        self.faces
            .get(f)
            .and_then(Option::as_ref)
            .ok_or(BrepError::Stale("face"))
    }

    /// (loop, vertex, half-edge at the vertex if the loop has edges).
    fn corner(&self, c: Corner) -> Result<(usize, usize, Option<usize>), BrepError> {
        match c {
            Corner::At(h) => {
                let he = self.he(h.0)?;
                Ok((he.lp, he.origin, Some(h.0)))
            }
            Corner::Lone(l) => match self.lp(l.0)?.start {
                Start::Vertex(v) => Ok((l.0, v, None)),
                Start::HalfEdge(_) => Err(BrepError::Precondition(
                    "a loop with edges is entered at a half-edge",
                )),
            },
        }
    }

    fn push_vertex(&mut self, p: DVec3) -> usize {
        self.vertices.push(Some(p));
        self.vertices.len() - 1
    }

    /// Two twin half-edges v→w and w→v in loop `l`, not yet linked into it.
    fn push_edge(&mut self, v: usize, w: usize, l: usize) -> (usize, usize) {
        let a = self.half_edges.len();
        let he = |origin, twin| HalfEdge {
            origin,
            next: FREE,
            prev: FREE,
            twin,
            lp: l,
        };
        self.half_edges.push(Some(he(v, a + 1)));
        self.half_edges.push(Some(he(w, a)));
        (a, a + 1)
    }

    fn link(&mut self, from: usize, to: usize) {
        if let Some(h) = self.half_edges[from].as_mut() {
            h.next = to;
        }
        if let Some(h) = self.half_edges[to].as_mut() {
            h.prev = from;
        }
    }

    fn set_start(&mut self, l: usize, start: Start) {
        if let Some(lp) = self.loops[l].as_mut() {
            lp.start = start;
        }
    }

    /// The cycle of half-edges starting at `h`.
    fn cycle_from(&self, h: usize) -> Vec<usize> {
        let mut out = vec![h];
        let mut e = h;
        while let Ok(he) = self.he(e) {
            e = he.next;
            if e == h || out.len() > self.half_edges.len() {
                break;
            }
            out.push(e);
        }
        out
    }

    /// Makes `hes` the cycle of loop `l` (or, if empty, the loop's lone vertex `lone`).
    fn relink(&mut self, l: usize, hes: &[usize], lone: usize) {
        if hes.is_empty() {
            self.set_start(l, Start::Vertex(lone));
            return;
        }
        for (i, &h) in hes.iter().enumerate() {
            self.link(h, hes[(i + 1) % hes.len()]);
            if let Some(he) = self.half_edges[h].as_mut() {
                he.lp = l;
            }
        }
        self.set_start(l, Start::HalfEdge(hes[0]));
    }
}
