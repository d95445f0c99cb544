//! Four triangles tested against one ray at once.
//!
//! A leaf of the hierarchy stores its triangles in packets of [`LANES`], each coordinate of
//! the vertex and the two edges Möller–Trumbore reads (see [`super::ray`]) as four
//! consecutive floats: `v0[axis][lane]`, `e1[axis][lane]`, `e2[axis][lane]` (Embree's
//! `Triangle4` uses the same layout; the wide nodes of Wald et al. 2008, "Getting rid of
//! packets", test a node's children the same way). Every step of the
//! test is then one arithmetic operation on four lanes — the loops over `lane` below compile
//! to packed SSE (`mulps`, `subps`, `divps`, `cmpps`) — and the four triangles cost about what
//! one costs in scalar code, with no branch until the lanes are combined.
//!
//! Each lane runs the scalar test's operations in the scalar test's order (glam's `cross` and
//! `dot` spelled out, no fused multiply–add), so a lane's (t, u, v) is bit for bit what
//! [`super::ray::intersect`] gives for that triangle, and the hierarchy agrees exactly with a
//! brute-force loop. Of several lanes hit, the nearest wins and, at equal distance, the first —
//! what the scalar loop over the same triangles in lane order keeps.
//!
//! A packet not filled by its leaf is padded with zero-area triangles (all edges zero), which
//! the determinant test never hits.

use glam::Vec3;

use super::node::RAYS;

/// Triangles per packet.
pub(super) const LANES: usize = 4;

/// Four triangles in structure-of-arrays form; see the module docs.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(16))]
pub(super) struct Tri4 {
    v0: [[f32; LANES]; 3],
    e1: [[f32; LANES]; 3],
    e2: [[f32; LANES]; 3],
}

impl Tri4 {
    /// A packet of no triangle (every lane zero-area at the origin).
    pub(super) const EMPTY: Self = Self {
        v0: [[0.0; LANES]; 3],
        e1: [[0.0; LANES]; 3],
        e2: [[0.0; LANES]; 3],
    };

    /// Stores the triangle (v0, e1 = v1 − v0, e2 = v2 − v0) in `lane`.
    pub(super) fn set(&mut self, lane: usize, v0: Vec3, e1: Vec3, e2: Vec3) {
        for axis in 0..3 {
            self.v0[axis][lane] = v0[axis];
            self.e1[axis][lane] = e1[axis];
            self.e2[axis][lane] = e2[axis];
        }
    }

    /// The vertices of the triangle in `lane`.
    pub(super) fn vertices(&self, lane: usize) -> [Vec3; 3] {
        let get = |a: &[[f32; LANES]; 3]| Vec3::new(a[0][lane], a[1][lane], a[2][lane]);
        let v0 = get(&self.v0);
        [v0, v0 + get(&self.e1), v0 + get(&self.e2)]
    }

    /// Whether `lane` holds a triangle of zero edges (padding, or a degenerate input).
    pub(super) fn is_point(&self, lane: usize) -> bool {
        (0..3).all(|a| self.e1[a][lane] == 0.0 && self.e2[a][lane] == 0.0)
    }

    /// The nearest hit of the ray o + t·d among the four triangles with t in (0, `t_max`), as
    /// (lane, t, u, v); `None` when no lane is hit.
    #[inline(always)]
    pub(super) fn intersect(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<(usize, f32, f32, f32)> {
        let (t, u, v, hits) = self.lanes(o, d, t_max);
        nearest_lane(&t, &u, &v, hits)
    }

    /// The nearest hit of the ray o + t·d with t in (0, `t_max`) among the eight triangles
    /// of two packets, tested together (one 8-wide operation per step with AVX2), as (lane,
    /// t, u, v) with lanes 4–7 those of `pair[1]`: what [`Tri4::intersect`] on `pair[0]`
    /// then on `pair[1]` below the first's hit gives (the nearest, the first of equals).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)]
    pub(super) fn intersect_pair(
        pair: &[Tri4; 2],
        o: Vec3,
        d: Vec3,
        t_max: f32,
    ) -> Option<(usize, f32, f32, f32)> {
        let mut t = [0f32; 2 * LANES];
        let mut u = [0f32; 2 * LANES];
        let mut v = [0f32; 2 * LANES];
        let mut hits = [false; 2 * LANES];
        for l in 0..2 * LANES {
            let (p, pl) = (&pair[l / LANES], l % LANES);
            let corner = |a: &[[f32; LANES]; 3]| [a[0][pl], a[1][pl], a[2][pl]];
            let triangle = (corner(&p.v0), corner(&p.e1), corner(&p.e2));
            let (tl, ul, vl, hit) = moller_trumbore((o.to_array(), d.to_array()), triangle, t_max);
            t[l] = if hit { tl } else { f32::INFINITY };
            u[l] = ul;
            v[l] = vl;
            hits[l] = hit;
        }
        let mut mask = 0u32;
        for (l, &hit) in hits.iter().enumerate() {
            mask |= u32::from(hit) << l;
        }
        nearest_lane(&t, &u, &v, mask)
    }

    /// Möller–Trumbore of the triangle in `lane` against [`RAYS`] rays at once (ray r: origin
    /// `o[axis][r]`, direction `d[axis][r]`, far end `t_max[r]`), lane by lane over the rays:
    /// (t, u, v) per ray and the mask of the rays that hit it. Each ray's lane runs the very
    /// operations of [`Tri4::lanes`] (and so of the scalar test) for this triangle.
    #[inline(always)]
    #[allow(clippy::needless_range_loop, clippy::manual_range_contains)]
    pub(super) fn lane_rays(
        &self,
        lane: usize,
        o: &[[f32; RAYS]; 3],
        d: &[[f32; RAYS]; 3],
        t_max: &[f32; RAYS],
    ) -> ([f32; RAYS], [f32; RAYS], [f32; RAYS], u32) {
        let corner = |a: &[[f32; LANES]; 3]| [a[0][lane], a[1][lane], a[2][lane]];
        let (v0, e1, e2) = (corner(&self.v0), corner(&self.e1), corner(&self.e2));
        let mut t = [0f32; RAYS];
        let mut u = [0f32; RAYS];
        let mut v = [0f32; RAYS];
        let mut hits = [false; RAYS];
        for r in 0..RAYS {
            let ray = ([o[0][r], o[1][r], o[2][r]], [d[0][r], d[1][r], d[2][r]]);
            let (tl, ul, vl, hit) = moller_trumbore(ray, (v0, e1, e2), t_max[r]);
            t[r] = tl;
            u[r] = ul;
            v[r] = vl;
            hits[r] = hit;
        }
        let mut mask = 0;
        for (r, &hit) in hits.iter().enumerate() {
            mask |= u32::from(hit) << r;
        }
        (t, u, v, mask)
    }

    /// Möller–Trumbore on all lanes: (t, u, v) per lane, t = +∞ where the lane misses, and
    /// the mask of the lanes hit.
    #[inline(always)]
    // Lane loops and non-short-circuit `&` are what vectorizes (with `&&` the lanes branch).
    #[allow(clippy::needless_range_loop, clippy::manual_range_contains)]
    fn lanes(
        &self,
        o: Vec3,
        d: Vec3,
        t_max: f32,
    ) -> ([f32; LANES], [f32; LANES], [f32; LANES], u32) {
        let mut t = [0f32; LANES];
        let mut u = [0f32; LANES];
        let mut v = [0f32; LANES];
        let mut hits = [false; LANES];
        for l in 0..LANES {
            let corner = |a: &[[f32; LANES]; 3]| [a[0][l], a[1][l], a[2][l]];
            let triangle = (corner(&self.v0), corner(&self.e1), corner(&self.e2));
            let (tl, ul, vl, hit) = moller_trumbore((o.to_array(), d.to_array()), triangle, t_max);
            t[l] = if hit { tl } else { f32::INFINITY };
            u[l] = ul;
            v[l] = vl;
            hits[l] = hit;
        }
        let mut mask = 0;
        for (l, &hit) in hits.iter().enumerate() {
            mask |= u32::from(hit) << l;
        }
        (t, u, v, mask)
    }
}

/// Of the lanes set in `hits`, the nearest by `t` and the first of equals, as (lane, t, u, v);
/// `None` when no lane is set.
#[inline(always)]
fn nearest_lane(t: &[f32], u: &[f32], v: &[f32], hits: u32) -> Option<(usize, f32, f32, f32)> {
    if hits == 0 {
        return None;
    }
    let mut best = hits.trailing_zeros() as usize;
    let mut rest = hits & (hits - 1);
    while rest != 0 {
        let lane = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        if t[lane] < t[best] {
            best = lane;
        }
    }
    Some((best, t[best], u[best], v[best]))
}

/// Möller–Trumbore for one ray (origin, direction) and one triangle (v0, e1, e2): (t, u, v)
/// and whether it is hit with t in (0, `t_max`). The one lane of both packet loops
/// ([`Tri4::lanes`]: one ray, four triangles; [`Tri4::lane_rays`]: one triangle, [`RAYS`] rays),
/// written with the scalar test's operations in its order so every lane gives its bits; the
/// non-short-circuit `&` keeps the lanes free of branches, so the loops vectorize.
#[inline(always)]
#[allow(clippy::manual_range_contains)]
fn moller_trumbore(
    (o, d): ([f32; 3], [f32; 3]),
    (v0, e1, e2): ([f32; 3], [f32; 3], [f32; 3]),
    t_max: f32,
) -> (f32, f32, f32, bool) {
    // p = d × e2, det = e1 · p.
    let px = d[1] * e2[2] - e2[1] * d[2];
    let py = d[2] * e2[0] - e2[2] * d[0];
    let pz = d[0] * e2[1] - e2[0] * d[1];
    let det = (e1[0] * px) + (e1[1] * py) + (e1[2] * pz);
    let inv_det = 1.0 / det;
    // s = o − v0, u = (s · p) / det.
    let sx = o[0] - v0[0];
    let sy = o[1] - v0[1];
    let sz = o[2] - v0[2];
    let u = ((sx * px) + (sy * py) + (sz * pz)) * inv_det;
    // q = s × e1, v = (d · q) / det, t = (e2 · q) / det.
    let qx = sy * e1[2] - e1[1] * sz;
    let qy = sz * e1[0] - e1[2] * sx;
    let qz = sx * e1[1] - e1[0] * sy;
    let v = ((d[0] * qx) + (d[1] * qy) + (d[2] * qz)) * inv_det;
    let t = ((e2[0] * qx) + (e2[1] * qy) + (e2[2] * qz)) * inv_det;
    // The scalar test's conditions; NaN fails every comparison and so misses.
    let hit = (det != 0.0)
        & (u >= 0.0)
        & (u <= 1.0)
        & (v >= 0.0)
        & (u + v <= 1.0)
        & (t > 0.0)
        & (t < t_max);
    (t, u, v, hit)
}

#[cfg(test)]
mod tests {
    use super::super::ray::intersect;
    use super::*;
    use crate::hash::SplitMix;

    #[test]
    fn packet_is_bit_identical_to_the_scalar_test() {
        let mut rng = SplitMix(11);
        let mut unit = || rng.next_f32() * 2.0 - 1.0;
        for _ in 0..2000 {
            let mut packet = Tri4::EMPTY;
            let mut tris = [(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO); LANES];
            for (lane, tri) in tris.iter_mut().enumerate().take(1 + lane_count(unit())) {
                let v0 = Vec3::new(unit(), unit(), unit());
                *tri = (
                    v0,
                    Vec3::new(unit(), unit(), unit()),
                    Vec3::new(unit(), unit(), 0.5),
                );
                packet.set(lane, tri.0, tri.1, tri.2);
            }
            let o = Vec3::new(unit(), unit(), 3.0 + unit());
            let d = Vec3::new(unit() * 0.5, unit() * 0.5, -1.0);
            let t_max = 4.0 + 2.0 * unit();
            // The scalar loop in lane order, keeping strictly nearer hits.
            let mut expected = None;
            let mut best_t = t_max;
            for (lane, &(v0, e1, e2)) in tris.iter().enumerate() {
                if let Some((t, u, v)) = intersect(o, d, v0, e1, e2, best_t) {
                    best_t = t;
                    expected = Some((lane, t, u, v));
                }
            }
            assert_eq!(packet.intersect(o, d, t_max), expected);
        }
    }

    #[test]
    fn pair_is_what_the_two_packets_give_in_turn() {
        let mut rng = SplitMix(13);
        let mut unit = || rng.next_f32() * 2.0 - 1.0;
        for _ in 0..2000 {
            let mut pair = [Tri4::EMPTY; 2];
            for lane in 0..2 * LANES {
                if unit() < 0.6 {
                    let v0 = Vec3::new(unit(), unit(), unit());
                    let e1 = Vec3::new(unit(), unit(), unit());
                    // Some triangles repeated, for ties in t.
                    let e2 = if lane > 0 && unit() < -0.8 {
                        pair[0].set(lane % LANES, v0, e1, Vec3::new(0.3, 0.2, 0.5));
                        Vec3::new(0.3, 0.2, 0.5)
                    } else {
                        Vec3::new(unit(), unit(), 0.5)
                    };
                    pair[lane / LANES].set(lane % LANES, v0, e1, e2);
                }
            }
            let o = Vec3::new(unit() * 0.3, unit() * 0.3, 3.0 + unit());
            let d = Vec3::new(unit() * 0.5, unit() * 0.5, -1.0);
            let t_max = 4.0 + 2.0 * unit();
            let first = pair[0].intersect(o, d, t_max);
            let below = first.map_or(t_max, |h| h.1);
            let expected = match pair[1].intersect(o, d, below) {
                Some((lane, t, u, v)) => Some((LANES + lane, t, u, v)),
                None => first,
            };
            assert_eq!(Tri4::intersect_pair(&pair, o, d, t_max), expected);
        }
    }

    #[test]
    fn rays_in_lanes_are_bit_identical_to_the_scalar_test() {
        let mut rng = SplitMix(12);
        let mut unit = || rng.next_f32() * 2.0 - 1.0;
        for _ in 0..500 {
            let mut packet = Tri4::EMPTY;
            let tri = (
                Vec3::new(unit(), unit(), unit()),
                Vec3::new(unit(), unit(), unit()),
                Vec3::new(unit(), unit(), 0.5),
            );
            let lane = (unit().abs() * 3.99) as usize;
            packet.set(lane, tri.0, tri.1, tri.2);
            let (mut o, mut d, mut t_max) = ([[0f32; RAYS]; 3], [[0f32; RAYS]; 3], [0f32; RAYS]);
            for r in 0..RAYS {
                for a in 0..3 {
                    o[a][r] = unit() + if a == 2 { 3.0 } else { 0.0 };
                    d[a][r] = if a == 2 { -1.0 } else { unit() * 0.5 };
                }
                t_max[r] = 4.0 + 2.0 * unit();
            }
            let (t, u, v, mask) = packet.lane_rays(lane, &o, &d, &t_max);
            for r in 0..RAYS {
                let ray = |x: &[[f32; RAYS]; 3]| Vec3::new(x[0][r], x[1][r], x[2][r]);
                let expected = intersect(ray(&o), ray(&d), tri.0, tri.1, tri.2, t_max[r]);
                let got = (mask >> r & 1 != 0).then_some((t[r], u[r], v[r]));
                assert_eq!(got, expected);
            }
        }
    }

    /// 0..=3 from a number in [−1, 1).
    fn lane_count(x: f32) -> usize {
        ((x + 1.0) * 2.0) as usize
    }

    #[test]
    fn empty_lanes_never_hit() {
        let packet = Tri4::EMPTY;
        assert!(packet.is_point(0) && packet.is_point(3));
        // Straight through the origin, where every empty lane sits.
        assert!(packet
            .intersect(Vec3::new(0.0, 0.0, -1.0), Vec3::Z, 10.0)
            .is_none());
    }
}
