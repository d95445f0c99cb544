//! Interval bounds of a ray packet: one test that rules a node's child out for every ray of
//! the packet at once.
//!
//! The packet traversal ([`super::coherent`]) tests each child box a packet meets against
//! each of its rays. Coherent rays mostly agree, and most children are missed by all of them:
//! those can be recognized without testing ray by ray. Wald, Boulos and Shirley (2007, "Ray
//! tracing deformable scenes using dynamic bounding volume hierarchies") bound the packet by
//! intervals — the origins' coordinates o ∈ [o_lo, o_hi] and the reciprocal directions
//! 1/d ∈ [i_lo, i_hi] per axis — and evaluate the slab test in interval arithmetic (Boulos
//! et al. 2006, "Geometric and arithmetic culling methods for entire ray packets"): on an axis
//! where every 1/d is positive, each ray's distance to the near plane p,
//! t = (p − o)·(1/d), is at least min((p − o_hi)·i_lo, (p − o_hi)·i_hi), and its distance to
//! the far plane at most the max of the products with o_lo (the other way round where every
//! 1/d is negative). A child whose largest entry bound over the axes (and 0) exceeds its
//! smallest exit bound (and the packet's largest far end), widened by the slab test's
//! 1 + 2γ₃, is entered by no ray. Here the test runs on the eight children in lanes.
//!
//! The bounds hold for the rounded arithmetic, not only for the real one: every step (a
//! subtraction, a product with a factor of known sign, a min, a max) is monotone in each
//! operand under round-to-nearest, so the same operations on the interval's ends bound what
//! each ray's own operations give. The cull therefore never drops a child that a ray's slab
//! test ([`super::node::slab_rays`]) would accept, and the packet's results stay those of the
//! one-ray queries bit for bit.
//!
//! On an axis where the rays' directions differ in sign the near plane differs from ray to
//! ray and the interval bounds nothing; such packets get no bounds. (Measured on the
//! 1M-triangle benchmark scenes, one thread, `benches/README.md`: with the bounds
//! a camera's packets test 1.6–2.0 of a node's 7.5 children against their rays instead of
//! all, 0.99–1.07× the rays per second; shadow-ray packets towards a light, whose directions
//! often straddle an axis and whose origins spread, kept 4 of 7.4 with the axes that do
//! bound, and were 0.89–0.99× as fast with the cull as without it.)

use super::isa::le_mask;
use super::node::{max, min, Planes, RAYS, ROBUST_FAR, WIDTH};

/// The interval bounds of some rays of a packet (see the module docs).
#[derive(Clone, Copy, Debug)]
pub(super) struct Frustum {
    /// Per axis, the plane ([`Planes`] index) every ray enters the slab by: the min plane for
    /// a positive 1/d.
    near: [usize; 3],
    /// Per axis, the origin coordinate that bounds the entry distances from below: the
    /// largest for a positive 1/d, the smallest for a negative one.
    o_entry: [f32; 3],
    /// Per axis, the origin coordinate that bounds the exit distances from above.
    o_exit: [f32; 3],
    /// Per axis, the smallest and the largest 1/d.
    inv_lo: [f32; 3],
    inv_hi: [f32; 3],
}

impl Frustum {
    /// The bounds of the rays of `mask` (at least one) among [`RAYS`] given by origin `o` and
    /// 1/d `inv` by axis (`o[axis][ray]`), 1/d finite and nonzero; `None` when the signs of
    /// 1/d differ along some axis.
    #[inline(always)]
    pub(super) fn new(o: &[[f32; RAYS]; 3], inv: &[[f32; RAYS]; 3], mask: u32) -> Option<Self> {
        debug_assert!(mask != 0 && mask >> RAYS == 0);
        let mut f = Self {
            near: [0, 2, 4],
            o_entry: [0.0; 3],
            o_exit: [0.0; 3],
            inv_lo: [0.0; 3],
            inv_hi: [0.0; 3],
        };
        for a in 0..3 {
            let (mut o_lo, mut o_hi) = (f32::INFINITY, f32::NEG_INFINITY);
            let (mut i_lo, mut i_hi) = (f32::INFINITY, f32::NEG_INFINITY);
            for r in 0..RAYS {
                if mask >> r & 1 != 0 {
                    o_lo = min(o_lo, o[a][r]);
                    o_hi = max(o_hi, o[a][r]);
                    i_lo = min(i_lo, inv[a][r]);
                    i_hi = max(i_hi, inv[a][r]);
                }
            }
            let positive = i_lo > 0.0;
            if !positive && i_hi >= 0.0 {
                return None;
            }
            f.near[a] = 2 * a + usize::from(!positive);
            (f.o_entry[a], f.o_exit[a]) = if positive { (o_hi, o_lo) } else { (o_lo, o_hi) };
            (f.inv_lo[a], f.inv_hi[a]) = (i_lo, i_hi);
        }
        Some(f)
    }

    /// The mask of the children (of a node with planes `planes`) that some ray of the packet
    /// may enter with t in (0, `t_max`), `t_max` at least every ray's far end: a superset of
    /// the children that [`super::node::slab_rays`] accepts for any of the rays.
    #[inline(always)]
    pub(super) fn cull(&self, planes: &Planes, t_max: f32) -> u32 {
        let mut entry = [0f32; WIDTH];
        let mut exit = [t_max; WIDTH];
        for a in 0..3 {
            let (near, far) = (&planes[self.near[a]], &planes[self.near[a] ^ 1]);
            let (lo, hi) = (self.inv_lo[a], self.inv_hi[a]);
            for k in 0..WIDTH {
                let n = near[k] - self.o_entry[a];
                let f = far[k] - self.o_exit[a];
                entry[k] = max(entry[k], min(n * lo, n * hi));
                exit[k] = min(exit[k], max(f * lo, f * hi));
            }
        }
        for x in &mut exit {
            *x *= ROBUST_FAR;
        }
        le_mask(&entry, &exit)
    }
}

#[cfg(test)]
mod tests {
    use super::super::node::{slab_rays, Aabb, Node};
    use super::super::traverse::slabs;
    use super::*;
    use crate::hash::SplitMix;
    use glam::Vec3;

    /// Packets of rays with nearby origins and directions (some rays left out of the mask)
    /// against random nodes: every child some ray of the mask enters passes the cull, and
    /// coherent packets cull most; packets whose directions straddle an axis get no bounds.
    #[test]
    fn cull_keeps_every_child_a_ray_enters() {
        let mut rng = SplitMix(17);
        let mut v = || rng.next_f32() * 2.0 - 1.0;
        let (mut culled, mut missed, mut unbounded) = (0, 0, 0);
        for case in 0..3000 {
            let boxes: Vec<Aabb> = (0..1 + case % WIDTH)
                .map(|_| {
                    let c = Vec3::new(v(), v(), v()) * 4.0;
                    let h = Vec3::new(v(), v(), v()).abs() * 0.5;
                    Aabb::from_points(&[c - h, c + h])
                })
                .collect();
            let node = Node::new(&boxes, &[0; WIDTH]);
            let planes = node.planes();
            // Spread of the origins and directions: tight, loose, or anything.
            let spread = [0.01, 0.3, 3.0][case % 3];
            let o0 = Vec3::new(v(), v(), v()) * 6.0;
            let d0 = Vec3::new(v(), v(), v());
            let (mut o, mut inv, mut t_max) = ([[0f32; RAYS]; 3], [[0f32; RAYS]; 3], [0f32; RAYS]);
            for r in 0..RAYS {
                let origin = o0 + Vec3::new(v(), v(), v()) * spread;
                let mut d = d0 + Vec3::new(v(), v(), v()) * spread;
                if case % 7 == 0 {
                    // A zero component, made ±10⁻²⁰ by `slabs`.
                    d.y = 0.0;
                }
                let (i, _) = slabs(d);
                for a in 0..3 {
                    o[a][r] = origin[a];
                    inv[a][r] = i[a];
                }
                t_max[r] = if case % 2 == 0 { 1e30 } else { v().abs() * 8.0 };
            }
            let mask = (case as u32 * 37 % 255) + 1;
            let far = (0..RAYS)
                .filter(|r| mask >> r & 1 != 0)
                .map(|r| t_max[r])
                .fold(0.0, f32::max);
            let Some(frustum) = Frustum::new(&o, &inv, mask) else {
                let signs = |a: usize| {
                    let s = (0..RAYS)
                        .filter(|r| mask >> r & 1 != 0)
                        .map(|r| inv[a][r] > 0.0);
                    (s.clone().any(|p| p), s.clone().any(|p| !p))
                };
                assert!((0..3).any(|a| signs(a) == (true, true)), "case {case}");
                unbounded += 1;
                continue;
            };
            let kept = frustum.cull(&planes, far);
            for k in 0..WIDTH {
                let (_, hit) = slab_rays(&planes, k, &o, &inv, &t_max);
                let entered = node.has_child(k) && hit & mask != 0;
                assert!(
                    !entered || kept >> k & 1 != 0,
                    "case {case}: child {k} culled"
                );
                if node.has_child(k) && !entered {
                    missed += 1;
                    culled += usize::from(kept >> k & 1 == 0);
                }
            }
        }
        // Not a property, a sanity check that the test culls at all: most children missed by
        // every ray are ruled out by the bounds.
        assert!(culled * 2 > missed, "culled {culled} of {missed}");
        assert!(
            unbounded > 0 && unbounded < 1500,
            "{unbounded} of 3000 unbounded"
        );
    }
}
