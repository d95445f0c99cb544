//! Euler operators: the Euler–Poincaré formula after every step, inverses undo, and invalid
//! sequences are refused without change.

use glam::DVec3;
use model::brep::euler::Corner;
use model::brep::{BrepError, HalfEdgeId, Solid};

/// Validates the structure and the formula; returns (V, E, F, L, S, H).
fn check(s: &Solid) -> (usize, usize, usize, usize, usize, usize) {
    s.validate().unwrap_or_else(|e| panic!("{e}"));
    let c = s.counts();
    (c.vertices, c.edges, c.faces, c.loops, c.shells, c.holes)
}

/// A cube by Euler operators: a square lamina (MVFS, 3 MEV, MEF), swept by 4 MEV and 4 MEF.
/// Returns the solid and the half-edges bounding the four side faces along the top.
fn cube() -> (Solid, Vec<HalfEdgeId>) {
    let mut s = Solid::new();
    let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let (_, _, l) = s.mvfs(p(0.0, 0.0, 0.0));
    check(&s);
    let (_, e0) = s.mev(Corner::Lone(l), p(1.0, 0.0, 0.0)).unwrap();
    check(&s);
    let (_, e1) = s
        .mev(Corner::At(s.twin(e0).unwrap()), p(1.0, 0.0, 1.0))
        .unwrap();
    check(&s);
    let (_, e2) = s
        .mev(Corner::At(s.twin(e1).unwrap()), p(0.0, 0.0, 1.0))
        .unwrap();
    check(&s);
    // Close the square: from the last vertex (origin of twin(e2)) to the first (origin of e0).
    let (_, _) = s.mef(s.twin(e2).unwrap(), e0).unwrap();
    assert_eq!(check(&s), (4, 4, 2, 2, 1, 0));
    // Sweep up: a vertical edge at each bottom corner, in the face whose loop runs e0 → e1 → e2.
    let bottom = [e0, e1, e2, s.next(e2).unwrap()];
    let mut up = Vec::new();
    for (k, &h) in bottom.iter().enumerate() {
        let q = s.position(s.origin(h).unwrap()).unwrap() + DVec3::Y;
        let (_, u) = s.mev(Corner::At(h), q).unwrap();
        up.push(u);
        assert_eq!(check(&s).0, 5 + k);
    }
    // Join consecutive top vertices: MEF between twin(up[k]) ends, around the loop.
    let mut tops = Vec::new();
    for k in 0..4 {
        let a = s.twin(up[k]).unwrap();
        // The top of the next post: twin(up[k + 1]) while it is still in the growing loop; for
        // the last side, the first top edge's twin, which now leaves the first post's top.
        let b = if k == 3 {
            s.twin(tops[0]).unwrap()
        } else {
            s.twin(up[k + 1]).unwrap()
        };
        let (_, h) = s.mef(a, b).unwrap_or_else(|e| panic!("side {k}: {e}"));
        tops.push(h);
        check(&s);
    }
    assert_eq!(check(&s), (8, 12, 6, 6, 1, 0));
    (s, tops)
}

#[test]
fn a_cube_built_by_euler_operators() {
    let (s, _) = cube();
    assert_eq!(s.genus(), 0);
}

#[test]
fn inverse_operators_undo() {
    let mut s = Solid::new();
    let (_, f, l) = s.mvfs(DVec3::ZERO);
    let (_, e) = s.mev(Corner::Lone(l), DVec3::X).unwrap();
    let (_, e2) = s.mev(Corner::At(s.twin(e).unwrap()), DVec3::Y).unwrap();
    let (_, h) = s.mef(s.twin(e2).unwrap(), e).unwrap();
    assert_eq!(check(&s), (3, 3, 2, 2, 1, 0));
    // KEF keeps the face on the side of the half-edge it is given: the first one.
    s.kef(s.twin(h).unwrap()).unwrap();
    assert_eq!(check(&s), (3, 2, 1, 1, 1, 0));
    s.kev(e2).unwrap();
    assert_eq!(check(&s), (2, 1, 1, 1, 1, 0));
    s.kev(e).unwrap();
    assert_eq!(check(&s), (1, 0, 1, 1, 1, 0));
    s.kvfs(f).unwrap();
    assert_eq!(check(&s), (0, 0, 0, 0, 0, 0));
}

#[test]
fn a_ring_and_a_hole() {
    let (mut s, _) = cube();
    // A free-floating square inside a face: MEV from a corner to a new vertex, three more MEVs,
    // MEF to close it, then KEMR on the bridge makes the square a ring of the face.
    let top = s.faces()[0];
    let h0 = s.outer_half_edge(top).unwrap();
    let c = s.position(s.origin(h0).unwrap()).unwrap();
    let (_, bridge) = s
        .mev(Corner::At(h0), c + DVec3::new(0.1, 0.0, 0.1))
        .unwrap();
    let (_, a) = s
        .mev(
            Corner::At(s.twin(bridge).unwrap()),
            c + DVec3::new(0.2, 0.0, 0.1),
        )
        .unwrap();
    let (_, b) = s
        .mev(
            Corner::At(s.twin(a).unwrap()),
            c + DVec3::new(0.2, 0.0, 0.2),
        )
        .unwrap();
    let (_, d) = s
        .mev(
            Corner::At(s.twin(b).unwrap()),
            c + DVec3::new(0.1, 0.0, 0.2),
        )
        .unwrap();
    check(&s);
    let (inner, _) = s.mef(a, s.twin(d).unwrap()).unwrap();
    assert_eq!(check(&s), (12, 17, 7, 7, 1, 0));
    let ring = s.kemr(bridge).unwrap();
    assert_eq!(check(&s), (12, 16, 7, 8, 1, 0));
    // KFMRH: the inner square face becomes a second ring of the bottom face: a through-hole.
    let keep = s
        .faces()
        .into_iter()
        .find(|&f| f != top && f != inner)
        .unwrap();
    s.kfmrh(keep, inner).unwrap();
    assert_eq!(check(&s), (12, 16, 6, 8, 1, 1));
    // Invalid steps are refused and change nothing.
    let before = check(&s);
    assert!(matches!(
        s.kfmrh(keep, keep),
        Err(BrepError::Precondition(_))
    ));
    assert!(s.kev(s.next(h0).unwrap()).is_err());
    assert!(s.mef(h0, h0).is_err());
    assert!(s.kemr(s.next(h0).unwrap()).is_err());
    assert_eq!(check(&s), before);
    // MEKR joins the ring back to its face's outer loop; KEMR splits it again.
    let e = s
        .mekr(Corner::At(h0), Corner::At(s.loop_half_edge(ring).unwrap()))
        .unwrap();
    assert_eq!(check(&s), (12, 17, 6, 7, 1, 1));
    s.kemr(e).unwrap();
    assert_eq!(check(&s), (12, 16, 6, 8, 1, 1));
}

#[test]
fn stale_ids_are_refused() {
    let mut s = Solid::new();
    let (_, _, l) = s.mvfs(DVec3::ZERO);
    let (_, e) = s.mev(Corner::Lone(l), DVec3::X).unwrap();
    s.kev(e).unwrap();
    assert!(matches!(s.kev(e), Err(BrepError::Stale(_))));
    assert!(s.mev(Corner::At(e), DVec3::Y).is_err());
    check(&s);
}
