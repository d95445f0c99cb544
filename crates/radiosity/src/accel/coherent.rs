//! Ray packets: [`PACKET`] coherent rays (neighbouring pixels of a camera, shadow rays from
//! neighbouring points to one light) walked through the hierarchy together.
//!
//! One traversal serves the whole packet (Wald et al. 2001, "Interactive rendering with
//! coherent ray tracing"; here in the masked form of Wald et al. 2008 for wide nodes): each
//! stack entry carries, besides the subtree, the mask of the rays that entered its box, and a
//! visit runs the one-ray slab test of [`super::node`] for those rays only, each with its own
//! best distance as the far end. A child is entered by the rays whose slab test accepts it;
//! the children are ordered by the smallest entry distance over those rays (closest hit) or
//! as the one-ray occlusion query orders them (largest box first for long rays, nearest first
//! for segments), and a leaf tests its triangle packets for each of its rays with the one-ray
//! test. A ray leaves the packet as soon as it is occluded (occlusion); a popped subtree is
//! skipped for every ray whose best distance is below the subtree's entry distance (closest
//! hit), and for the whole packet when that is all of them.
//!
//! What the rays share is the node: it is fetched once and its children are ordered once for
//! eight rays, where one-ray queries fetch and decide the same node eight times in a row
//! (coherent rays visit nearly the same nodes: 23 steps per packet on the closed 1M-triangle
//! field's primary rays, 18.8 per ray alone). With [`RAY_SIMD_MIN`] rays or more active, a
//! node's planes are dequantized once (`Node::planes`), the children that the packet's
//! interval bounds rule out for every ray are dropped at once ([`super::frustum`], for
//! packets whose directions agree in sign on every axis, such as a camera's), and the others
//! are tested one at a time with the rays in the lanes (`slab_rays`); closest-hit leaves
//! likewise, triangle by triangle. Each ray still runs exactly the slab and triangle
//! arithmetic of the one-ray query, so the results are the same: the same occlusion answer,
//! the same closest distance t bit for bit (the nearest of the triangles hit, whatever the
//! order of visit), and the same triangle, u and v except where two triangles are hit at
//! exactly the same t (a shared edge), where either may be reported, as with the one-ray
//! query. The packets are the slice's consecutive groups of [`PACKET`] from its start, so the
//! result depends on the slice only, not on threads or the instruction set.
//!
//! Measured (`benches/README.md`, 1M triangles, one thread): closest hit on a 512²
//! camera's primary rays 1.22–1.99× the one-ray query (closed field 2.92 → 5.81 Mrays/s), on
//! shadow rays 1.07–1.35×; incoherent rays are slower in packets (0.73–0.85×): use
//! [`Bvh::closest_hits`].

use super::bvh::{Bvh, DEEP_STACK, SHALLOW_STACK};
use super::frustum::Frustum;
use super::isa::{self, le_mask};
use super::node::{is_leaf, leaf_range, slab_rays, RAYS, WIDTH};
use super::packet::{Tri4, LANES};
use super::ray::{Hit, Ray};
use super::traverse::{slabs, worst_first};
use glam::Vec3;

/// Rays per packet (4 and 16 measured against 8: see `benches/README.md`).
pub const PACKET: usize = RAYS;

/// Active rays from which a node is tested child by child with the rays in lanes
/// (`slab_rays`) rather than ray by ray with the children in lanes (`Node::slabs`)
/// (measured 1, 3 and 5 on the 1M-triangle scenes' primary and shadow rays: 1 is 2–27 %
/// slower than 3 on 11 of 12; 3 and 5 within noise of each other).
const RAY_SIMD_MIN: usize = 3;

/// Active rays from which a leaf is tested triangle by triangle with the rays in lanes
/// (`Tri4::lane_rays`) rather than ray by ray with the triangles in lanes (`Tri4::intersect`),
/// closest hits only (measured against never, 1M-triangle scenes, primary and shadow rays:
/// closest hit 1.03–1.12× on all six, occlusion 0.8–1.25×, within noise).
const LEAF_RAY_SIMD_MIN: usize = 3;

/// The smallest of `entry` plus `bias` ([`bias`]: +∞ for the lanes to leave out).
#[inline(always)]
fn nearest(entry: &[f32; RAYS], bias: &[f32; RAYS]) -> f32 {
    let mut e = [0f32; RAYS];
    for r in 0..RAYS {
        // A max, not a sum: the same for 0 and +∞ (entries are ≥ 0), and never NaN.
        e[r] = if entry[r] > bias[r] {
            entry[r]
        } else {
            bias[r]
        };
    }
    // A fixed tree of comparisons (vectorizes; the order does not matter for a minimum of
    // non-NaN values, and entries are never NaN).
    let m = |a: f32, b: f32| if a < b { a } else { b };
    let a = [m(e[0], e[4]), m(e[1], e[5]), m(e[2], e[6]), m(e[3], e[7])];
    let b = [m(a[0], a[2]), m(a[1], a[3])];
    m(b[0], b[1])
}

/// 0 in the lanes set in `mask`, +∞ in the others: what [`nearest`] adds to leave the rays
/// outside `mask` out.
#[inline(always)]
fn bias(mask: u32) -> [f32; RAYS] {
    std::array::from_fn(|r| {
        if mask >> r & 1 != 0 {
            0.0
        } else {
            f32::INFINITY
        }
    })
}

/// The largest of `t` over the lanes set in `mask` (at least one; `t` is never negative).
#[inline(always)]
fn farthest(t: &[f32; RAYS], mask: u32) -> f32 {
    let mut e = [0f32; RAYS];
    for r in 0..RAYS {
        if mask >> r & 1 != 0 {
            e[r] = t[r];
        }
    }
    let m = |a: f32, b: f32| if a > b { a } else { b };
    let a = [m(e[0], e[4]), m(e[1], e[5]), m(e[2], e[6]), m(e[3], e[7])];
    let b = [m(a[0], a[2]), m(a[1], a[3])];
    m(b[0], b[1])
}

/// The rays of one packet, one slot per ray.
struct Rays {
    o: [Vec3; PACKET],
    d: [Vec3; PACKET],
    /// 1/d, made finite as the one-ray query does.
    inv: [Vec3; PACKET],
    /// Index of each axis' near plane in a node's planes.
    near: [[usize; 3]; PACKET],
    best_t: [f32; PACKET],
    /// The origins and 1/d by axis, ray by ray (for `slab_rays`).
    o_soa: [[f32; PACKET]; 3],
    d_soa: [[f32; PACKET]; 3],
    inv_soa: [[f32; PACKET]; 3],
    /// Packet slot, u and v of each ray's best hit.
    best: [Option<(usize, f32, f32)>; PACKET],
}

impl Rays {
    #[inline(always)]
    fn new(rays: &[Ray], t_max: &[f32]) -> Self {
        let mut p = Self {
            o: [Vec3::ZERO; PACKET],
            d: [Vec3::X; PACKET],
            inv: [Vec3::ONE; PACKET],
            near: [[0, 2, 4]; PACKET],
            best_t: [0.0; PACKET],
            o_soa: [[0.0; PACKET]; 3],
            d_soa: [[0.0; PACKET]; 3],
            inv_soa: [[1.0; PACKET]; 3],
            best: [None; PACKET],
        };
        for (r, (ray, &t)) in rays.iter().zip(t_max).enumerate() {
            let d = ray.dir;
            let (inv, near) = slabs(d);
            p.o[r] = ray.origin;
            p.d[r] = d;
            p.inv[r] = inv;
            p.near[r] = near;
            p.best_t[r] = t;
            for a in 0..3 {
                p.o_soa[a][r] = ray.origin[a];
                p.d_soa[a][r] = d[a];
                p.inv_soa[a][r] = inv[a];
            }
        }
        p
    }

    /// Tests the packets of leaf `leaf` for the rays of `mask`, each keeping its nearest hit
    /// below its best distance (with `ANY` a ray stops at its first); returns the mask of the
    /// rays that hit something. For closest hits of [`LEAF_RAY_SIMD_MIN`] rays or more (for
    /// occlusion it measured no faster), triangle by triangle with
    /// the rays in lanes (`Tri4::lane_rays`; the triangles in the one-ray test's order, a ray's
    /// best replaced only by a strictly nearer hit, so each ray keeps what its one-ray test
    /// keeps), else ray by ray.
    #[inline(always)]
    fn leaf_rays<const ANY: bool>(&mut self, bvh: &Bvh, leaf: u32, mask: u32) -> u32 {
        let mut hit = 0;
        if ANY || (mask.count_ones() as usize) < LEAF_RAY_SIMD_MIN {
            let mut m = mask;
            while m != 0 {
                let r = m.trailing_zeros() as usize;
                m &= m - 1;
                if self.leaf::<ANY>(bvh, leaf, r) {
                    hit |= 1 << r;
                }
            }
            return hit;
        }
        let (first, count) = leaf_range(leaf);
        #[cfg(feature = "count")]
        crate::accel::COUNT_PACKETS.fetch_add(
            (count * mask.count_ones() as usize) as u64,
            std::sync::atomic::Ordering::Relaxed,
        );
        let mut m = mask;
        for (k, packet) in bvh.packets[first..first + count].iter().enumerate() {
            for lane in 0..LANES {
                let (t, u, v, h) = packet.lane_rays(lane, &self.o_soa, &self.d_soa, &self.best_t);
                let h = h & m;
                if h == 0 {
                    continue;
                }
                let slot = (first + k) * LANES + lane;
                let mut b = h;
                while b != 0 {
                    let r = b.trailing_zeros() as usize;
                    b &= b - 1;
                    self.best_t[r] = t[r];
                    self.best[r] = Some((slot, u[r], v[r]));
                }
                hit |= h;
                if ANY {
                    m &= !h;
                    if m == 0 {
                        return hit;
                    }
                }
            }
        }
        hit
    }

    /// Tests the packets of leaf `leaf` for ray `r`, keeping its nearest hit below its best
    /// distance; with `ANY` stops at the first. Returns whether anything was hit.
    #[inline(always)]
    fn leaf<const ANY: bool>(&mut self, bvh: &Bvh, leaf: u32, r: usize) -> bool {
        let (first, count) = leaf_range(leaf);
        let mut found = false;
        #[cfg(feature = "count")]
        crate::accel::COUNT_PACKETS.fetch_add(count as u64, std::sync::atomic::Ordering::Relaxed);
        if !ANY && count == 2 {
            // Both packets as eight lanes, as the one-ray closest hit does.
            let pair: &[Tri4; 2] = bvh.packets[first..first + 2]
                .try_into()
                .expect("two packets");
            let hit = Tri4::intersect_pair(pair, self.o[r], self.d[r], self.best_t[r]);
            if let Some((lane, t, u, v)) = hit {
                self.best_t[r] = t;
                self.best[r] = Some((first * LANES + lane, u, v));
            }
            return hit.is_some();
        }
        for (k, packet) in bvh.packets[first..first + count].iter().enumerate() {
            if let Some((lane, t, u, v)) = packet.intersect(self.o[r], self.d[r], self.best_t[r]) {
                self.best_t[r] = t;
                self.best[r] = Some(((first + k) * LANES + lane, u, v));
                found = true;
                if ANY {
                    break;
                }
            }
        }
        found
    }
}

/// A subtree still to visit: its reference, the rays that entered its box, and its sort key
/// (the smallest entry distance over those rays, or minus its half area).
type Entry = (u32, u32, f32);

impl Bvh {
    /// [`Bvh::closest_hit`] of every ray k of `rays` with t in (0, `t_max[k]`), written to
    /// `out[k]`, the rays traced in packets of [`PACKET`] consecutive ones (see the module
    /// docs: faster when neighbouring rays are coherent, such as a camera's rays row by row;
    /// the same t and the same hit or miss as the one-ray query).
    ///
    /// # Panics
    /// When the three slices differ in length.
    pub fn closest_hits_coherent(&self, rays: &[Ray], t_max: &[f32], out: &mut [Option<Hit>]) {
        self.packets::<_, false>(rays, t_max, out, |o, h| *o = h);
    }

    /// [`Bvh::occluded`] of every ray k of `rays` with t in (0, `t_max[k]`), written to
    /// `out[k]`, the rays traced in packets of [`PACKET`] consecutive ones (see the module
    /// docs); the same answers as the one-ray query.
    ///
    /// # Panics
    /// When the three slices differ in length.
    pub fn occluded_coherent(&self, rays: &[Ray], t_max: &[f32], out: &mut [bool]) {
        self.packets::<_, true>(rays, t_max, out, |o, h| *o = h.is_some());
    }

    /// Both queries: `rays` cut into packets of [`PACKET`] consecutive ones, each traced with
    /// the stack the hierarchy's depth needs, under the instruction set in effect.
    #[inline(always)]
    fn packets<T, const ANY: bool>(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        out: &mut [T],
        done: impl Fn(&mut T, Option<Hit>) + Copy,
    ) {
        assert!(rays.len() == t_max.len() && rays.len() == out.len());
        isa::run(
            #[inline(always)]
            || {
                for ((rays, t_max), out) in rays
                    .chunks(PACKET)
                    .zip(t_max.chunks(PACKET))
                    .zip(out.chunks_mut(PACKET))
                {
                    if self.stack_need < SHALLOW_STACK {
                        self.packet::<_, ANY, SHALLOW_STACK>(rays, t_max, out, done);
                    } else {
                        self.packet::<_, ANY, DEEP_STACK>(rays, t_max, out, done);
                    }
                }
            },
        );
    }

    /// Traces up to [`PACKET`] rays together; `done` gets each ray's output slot and result.
    #[inline(always)]
    fn packet<T, const ANY: bool, const STACK: usize>(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        out: &mut [T],
        done: impl Fn(&mut T, Option<Hit>),
    ) {
        let n = rays.len();
        debug_assert!(n <= PACKET);
        if self.packets.is_empty() {
            out.iter_mut().for_each(|o| done(o, None));
            return;
        }
        let mut p = Rays::new(rays, t_max);
        // Rays still looking (occlusion: not yet occluded).
        let mut live: u32 = (1 << n) - 1;
        // The packet's interval bounds, when its directions agree in sign on every axis.
        let frustum = Frustum::new(&p.o_soa, &p.inv_soa, live);
        // Occlusion: largest box first when the first ray runs the scene's diagonal.
        let by_area = ANY && t_max[0] * rays[0].dir.length() >= self.diagonal;
        let mut stack: [Entry; STACK] = [(0, 0, 0.0); STACK];
        let mut sp = 0;
        let mut cur = self.root;
        let mut mask = live;
        'walk: loop {
            #[cfg(feature = "count")]
            crate::accel::COUNT_STEPS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            if is_leaf(cur) {
                let hit = p.leaf_rays::<ANY>(self, cur, mask);
                if ANY {
                    live &= !hit;
                }
                if ANY && live == 0 {
                    break 'walk;
                }
            } else {
                let node = &self.nodes[cur as usize];
                // Which rays enter each child, and the nearest entry.
                let mut rays_in = [0u32; WIDTH];
                let mut key = [f32::INFINITY; WIDTH];
                if mask.count_ones() as usize >= RAY_SIMD_MIN {
                    // Child by child, the rays in lanes, for the children that the packet's
                    // bounds do not rule out.
                    let planes = node.planes();
                    let bias = bias(mask);
                    let mut may = node.children();
                    if let Some(f) = &frustum {
                        may &= f.cull(&planes, farthest(&p.best_t, mask));
                    }
                    while may != 0 {
                        let k = may.trailing_zeros() as usize;
                        may &= may - 1;
                        let (entry, hit) = slab_rays(&planes, k, &p.o_soa, &p.inv_soa, &p.best_t);
                        let hit = hit & mask;
                        rays_in[k] = hit;
                        if hit != 0 {
                            key[k] = nearest(&entry, &bias);
                        }
                    }
                } else {
                    // Ray by ray, the children in lanes.
                    let mut m = mask;
                    while m != 0 {
                        let r = m.trailing_zeros() as usize;
                        m &= m - 1;
                        let (entry, hit) = node.slabs(p.o[r], p.inv[r], p.near[r], p.best_t[r]);
                        for k in 0..WIDTH {
                            let h = hit >> k & 1;
                            rays_in[k] |= h << r;
                            let e = if h != 0 { entry[k] } else { f32::INFINITY };
                            key[k] = if e < key[k] { e } else { key[k] };
                        }
                    }
                }
                let mut todo: [Entry; WIDTH] = [(0, 0, 0.0); WIDTH];
                let mut count = 0;
                for k in 0..WIDTH {
                    if rays_in[k] == 0 {
                        continue;
                    }
                    let c = node.child[k];
                    if ANY && is_leaf(c) {
                        // Leaves at once, as the one-ray occlusion query does.
                        live &= !p.leaf_rays::<ANY>(self, c, rays_in[k] & live);
                        if live == 0 {
                            break 'walk;
                        }
                        continue;
                    }
                    let sort = if by_area { -node.half_area(k) } else { key[k] };
                    todo[count] = (c, rays_in[k], sort);
                    count += 1;
                }
                if count > 0 {
                    // Worst first: push all but the best, go on with it.
                    worst_first(&mut todo[..count], |c| c.2);
                    stack[sp..sp + count - 1].copy_from_slice(&todo[..count - 1]);
                    sp += count - 1;
                    cur = todo[count - 1].0;
                    mask = todo[count - 1].1 & live;
                    if mask != 0 {
                        continue 'walk;
                    }
                }
            }
            // Pop the next subtree that some ray may still need.
            loop {
                if sp == 0 {
                    break 'walk;
                }
                sp -= 1;
                let (next, rays_in, t) = stack[sp];
                let mut m = rays_in & live;
                if !ANY {
                    // A ray whose best hit is nearer than every entry into the box is done
                    // with it.
                    m &= le_mask(&[t; RAYS], &p.best_t);
                }
                if m != 0 {
                    cur = next;
                    mask = m;
                    continue 'walk;
                }
            }
        }
        for (r, o) in out.iter_mut().enumerate().take(n) {
            let hit = if ANY {
                (live >> r & 1 == 0).then_some(Hit {
                    t: p.best_t[r],
                    triangle: 0,
                    u: 0.0,
                    v: 0.0,
                })
            } else {
                p.best[r].map(|(slot, u, v)| Hit {
                    t: p.best_t[r],
                    triangle: self.ids[slot],
                    u,
                    v,
                })
            };
            done(o, hit);
        }
    }
}
