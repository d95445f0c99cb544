//! The two queries of [`Bvh`] — closest hit and occlusion — one ray at a time or several
//! interleaved.
//!
//! A traversal is a [`Walk`]: the ray, its best hit so far, a stack of subtrees still to visit
//! and the subtree it is in. One [`Walk::step`] visits one node or one leaf:
//!
//! - at a node, the slab tests of its eight children give the mask of those the ray enters
//!   below the best distance; for a closest hit, one child is entered directly, of two the
//!   nearer is entered and the other pushed, of more all are sorted by entry distance, the
//!   nearest entered and the others pushed (leaves are ordered with interior children;
//!   walking the mask's bits measured faster here than a branch per child, 1.28 against
//!   0.91 Mrays/s interleaved on the teapot); when several are entered, all of them are
//!   prefetched first (`isa::prefetch`), so that their cache misses overlap;
//! - for occlusion, the leaf children are tested at once (cheap, and the large triangles of
//!   shallow leaves are the likeliest blockers) and interior children are visited largest box
//!   first: any hit ends the query, and the chance that a random ray crossing a box hits
//!   something in it grows with the box's area (the surface-area order of Ize & Hansen 2011,
//!   "RTSAH traversal order for occlusion rays"); measured 6× faster than nearest-first on
//!   the closed 1M-triangle scene, whose walls sit high in the tree. The order does not
//!   depend on the ray, so each node stores it (`Node::by_area`) and a step neither computes
//!   areas nor sorts (1M triangles, one thread: the open field's incoherent and primary
//!   occlusion 1.2× and 1.4× faster, the teapot's 1.1×; `benches/README.md`);
//! - when nothing is entered, the stack is popped, skipping subtrees whose entry distance is
//!   beyond a hit found since.
//!
//! On large scenes nearly every node a ray visits is a cache miss, and each step needs the
//! node the previous one chose: one ray's walk is a chain of dependent loads, and the core
//! waits for memory most of the time (measured with `perf` on the 1M-triangle teapot: half of
//! the closest-hit time sits on the first load of a node or a packet). [`Bvh::closest_hits`]
//! and [`Bvh::occluded_many`] therefore walk [`INTERLEAVE`] rays in turn, one step each, so
//! that the loads of different rays are in flight together (the software counterpart of the
//! latency hiding of GPU ray tracers; Aila & Laine 2009 run a warp's rays the same way). On a
//! hierarchy larger than a core's cache (`IN_CACHE`), each step of theirs also prefetches
//! every child it enters, and an occlusion step leaves its leaves to steps of their own, so
//! that a leaf's misses overlap with the other rays' steps too (1M triangles, incoherent
//! occlusion: teapot 1.13 → 1.86, open field 1.01 → 1.44 Mrays/s; `benches/README.md`).
//! The rays do not interact: each gets exactly what the one-ray query gives.

use glam::Vec3;

use super::bvh::{Bvh, DEEP_STACK, MID_STACK, SHALLOW_STACK};
use super::isa;
use super::node::{is_leaf, leaf_range, Node, WIDTH};
use super::packet::{Tri4, LANES};
use super::ray::{Hit, Ray};

/// Size of a hierarchy that stays in a core's cache (a typical L2): up to it the interleaved
/// queries walk their rays in turn without prefetching.
const IN_CACHE: usize = 1 << 20;

/// Rays walked in turn by the batched queries (2 and 8 measured slower than 4; see
/// `benches/README.md`).
pub const INTERLEAVE: usize = 4;

/// One ray's traversal in progress, less its stack (kept apart so that the compiler can hold
/// these fields in registers: measured 10 % faster than one struct on coherent rays).
#[derive(Clone, Copy)]
struct Walk {
    o: Vec3,
    d: Vec3,
    /// 1/d, made finite.
    inv: Vec3,
    /// Index of each axis' near plane in a node's `bounds`.
    near: [usize; 3],
    best_t: f32,
    /// Packet slot, u and v of the best hit.
    best: Option<(usize, f32, f32)>,
    /// Entries of the stack in use.
    sp: usize,
    /// Occlusion only: visit interior children largest first (the ray runs at least the
    /// scene's diagonal) rather than nearest first (a shorter segment).
    by_area: bool,
    cur: u32,
}

/// What the slab tests of a ray of direction `d` need: 1/d (a zero component becomes ±10⁻²⁰,
/// its sign kept, so that 1/d is finite), and for each axis the index of the near plane among
/// a box's six (min x, max x, min y, …): the max plane where the ray runs backwards. Shared by
/// the one-ray walk and the packets of [`super::coherent`], which must agree bit for bit.
#[inline(always)]
pub(super) fn slabs(d: Vec3) -> (Vec3, [usize; 3]) {
    let safe = |x: f32| {
        if x.abs() < 1e-20 {
            1e-20f32.copysign(x)
        } else {
            x
        }
    };
    let inv = Vec3::new(1.0 / safe(d.x), 1.0 / safe(d.y), 1.0 / safe(d.z));
    let near = [
        usize::from(inv.x < 0.0),
        2 + usize::from(inv.y < 0.0),
        4 + usize::from(inv.z < 0.0),
    ];
    (inv, near)
}

/// Subtrees still to visit, with their entry distances.
type Stack<const STACK: usize> = [(u32, f32); STACK];

impl Walk {
    /// A walk of `ray` with t in (0, `t_max`) from the root of `bvh`.
    #[inline(always)]
    fn new(ray: &Ray, t_max: f32, bvh: &Bvh) -> Self {
        let d = ray.dir;
        let (inv, near) = slabs(d);
        Self {
            o: ray.origin,
            d,
            inv,
            near,
            best_t: t_max,
            best: None,
            sp: 0,
            by_area: t_max * d.length() >= bvh.diagonal,
            cur: bvh.root,
        }
    }

    /// Visits the current node or leaf and moves to the next; returns `true` when the walk is
    /// over (with `ANY`, as soon as anything is hit). With `DEFER` (the interleaved queries),
    /// a step prefetches every child it enters, and an occlusion step leaves its leaves to
    /// steps of their own, so that their cache misses overlap with the other rays' steps
    /// instead of stalling this one; alone, a ray gains nothing from that and tests leaves at
    /// once. (Measured on the closed room, whose walls every ray finds in the first leaves it
    /// meets, the deferral makes interleaved occlusion 0.5–0.6× as fast; the one-ray query is the
    /// one to use there.)
    #[inline(always)]
    fn step<const ANY: bool, const STACK: usize, const DEFER: bool>(
        &mut self,
        bvh: &Bvh,
        stack: &mut Stack<STACK>,
    ) -> bool {
        let cur = self.cur;
        #[cfg(feature = "count")]
        crate::accel::COUNT_STEPS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        if is_leaf(cur) {
            if self.leaf::<ANY>(bvh, cur) && ANY {
                return true;
            }
        } else {
            let node = &bvh.nodes[cur as usize];
            let (near, mask) = node.slabs(self.o, self.inv, self.near, self.best_t);
            if ANY {
                if DEFER {
                    // Interleaved: ask for every child entered now, and visit leaves as steps
                    // of their own, so that the misses overlap with the other rays' steps.
                    prefetch_mask(bvh, node, mask);
                }
                if self.by_area {
                    // Leaves are tested at once (or, with `DEFER`, visited first), interior
                    // children visited largest box first, both in the node's precomputed area
                    // order (no areas computed, no sort).
                    let mut todo = [0u32; WIDTH];
                    let mut n = 0;
                    let mut leaves = [0u32; WIDTH];
                    let mut n_leaves = 0;
                    for k in node.by_area() {
                        if mask >> k & 1 == 0 {
                            continue;
                        }
                        let c = node.child[k];
                        if is_leaf(c) {
                            if DEFER {
                                leaves[n_leaves] = c;
                                n_leaves += 1;
                            } else if self.leaf::<ANY>(bvh, c) {
                                return true;
                            }
                            continue;
                        }
                        todo[n] = c;
                        n += 1;
                    }
                    // The order of visit: the deferred leaves, then the interior children
                    // largest first. Go on with the first and push the others, the last on
                    // the bottom.
                    let mut order = leaves;
                    order[n_leaves..n_leaves + n].copy_from_slice(&todo[..n]);
                    let count = n_leaves + n;
                    if count > 0 {
                        for &c in order[1..count].iter().rev() {
                            stack[self.sp] = (c, 0.0);
                            self.sp += 1;
                        }
                        self.cur = order[0];
                        return false;
                    }
                } else {
                    // Leaves are tested at once (with `DEFER`, ordered with the interior
                    // children), interior children visited nearest first. A branch per
                    // child: measured 1.1–1.5× faster than walking the mask's bits on the
                    // Cornell box (primary rays 23 against 16 Mrays/s), 20 % slower on the
                    // teapot's interleaved occlusion (1.14 against 1.44).
                    let mut todo = [(0u32, 0f32); WIDTH];
                    let mut n = 0;
                    for (k, &entry) in near.iter().enumerate() {
                        if mask >> k & 1 == 0 {
                            continue;
                        }
                        let c = node.child[k];
                        if is_leaf(c) && !DEFER {
                            if self.leaf::<ANY>(bvh, c) {
                                return true;
                            }
                            continue;
                        }
                        todo[n] = (c, entry);
                        n += 1;
                    }
                    if n > 0 {
                        // Worst first: push all but the best, go on with it.
                        worst_first(&mut todo[..n], |c| c.1);
                        stack[self.sp..self.sp + n - 1].copy_from_slice(&todo[..n - 1]);
                        self.sp += n - 1;
                        self.cur = todo[n - 1].0;
                        return false;
                    }
                }
            } else if mask != 0 {
                let k0 = mask.trailing_zeros() as usize;
                let rest = mask & (mask - 1);
                if rest != 0 || DEFER {
                    // Several children to visit: bring all of them in at once rather than
                    // one miss after another; interleaved, even one child gains, as the
                    // other rays' steps run before it is visited (1M triangles, incoherent
                    // rays: 1.16–1.45× faster).
                    prefetch_mask(bvh, node, mask);
                }
                if rest == 0 {
                    self.cur = node.child[k0];
                    return false;
                }
                if rest & (rest - 1) == 0 {
                    let k1 = rest.trailing_zeros() as usize;
                    let (a, b) = if near[k1] < near[k0] {
                        (k1, k0)
                    } else {
                        (k0, k1)
                    };
                    stack[self.sp] = (node.child[b], near[b]);
                    self.sp += 1;
                    self.cur = node.child[a];
                    return false;
                }
                let n = gather(node, mask, &mut stack[self.sp..], |k| near[k]);
                self.sp += n - 1;
                self.cur = stack[self.sp].0;
                return false;
            }
        }
        // Pop the next subtree that may still hold a closer hit.
        while self.sp > 0 {
            self.sp -= 1;
            let (next, t) = stack[self.sp];
            if ANY || t <= self.best_t {
                self.cur = next;
                return false;
            }
        }
        true
    }

    /// Tests the packets of leaf `r`, keeping the nearest hit below the best distance; with
    /// `ANY` stops at the first. Returns whether anything was hit.
    #[inline(always)]
    fn leaf<const ANY: bool>(&mut self, bvh: &Bvh, r: u32) -> bool {
        let (first, count) = leaf_range(r);
        let mut found = false;
        #[cfg(feature = "count")]
        crate::accel::COUNT_PACKETS.fetch_add(count as u64, std::sync::atomic::Ordering::Relaxed);
        if !ANY && count == 2 {
            // A closest hit tests both packets anyway: as eight lanes at once.
            let pair: &[Tri4; 2] = bvh.packets[first..first + 2]
                .try_into()
                .expect("two packets");
            if let Some((lane, t, u, v)) = Tri4::intersect_pair(pair, self.o, self.d, self.best_t) {
                self.best_t = t;
                self.best = Some((first * LANES + lane, u, v));
                return true;
            }
            return false;
        }
        for (k, packet) in bvh.packets[first..first + count].iter().enumerate() {
            if let Some((lane, t, u, v)) = packet.intersect(self.o, self.d, self.best_t) {
                self.best_t = t;
                self.best = Some(((first + k) * LANES + lane, u, v));
                found = true;
                if ANY {
                    break;
                }
            }
        }
        found
    }

    /// The walk's result.
    fn hit(&self, bvh: &Bvh) -> Option<Hit> {
        self.best.map(|(slot, u, v)| Hit {
            t: self.best_t,
            triangle: bvh.ids[slot],
            u,
            v,
        })
    }
}

/// Prefetches every child of `node` named by the bits of `mask` ([`prefetch_child`]).
#[inline(always)]
fn prefetch_mask(bvh: &Bvh, node: &Node, mut mask: u32) {
    while mask != 0 {
        let k = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        prefetch_child(bvh, node.child[k]);
    }
}

/// Prefetches what visiting child reference `c` reads first: a node's two cache lines, or
/// every line of a leaf's packets.
#[inline(always)]
fn prefetch_child(bvh: &Bvh, c: u32) {
    if is_leaf(c) {
        let (first, count) = leaf_range(c);
        if let Some(p) = bvh.packets.get(first..first + count) {
            isa::prefetch(p);
        }
    } else if let Some(n) = bvh.nodes.get(c as usize) {
        isa::prefetch(n);
    }
}

/// Writes the children of `node` named by the bits of `mask` (at least one) to `out` with
/// their sort keys, worst (largest key) first, and returns how many there are: the caller
/// pushes all but the last and goes on with the last.
#[inline(always)]
fn gather(node: &Node, mut mask: u32, out: &mut [(u32, f32)], key: impl Fn(usize) -> f32) -> usize {
    let mut n = 0;
    while mask != 0 {
        let k = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let entry = (node.child[k], key(k));
        // Insertion sort of at most eight, descending by key.
        let mut j = n;
        while j > 0 && out[j - 1].1 < entry.1 {
            out[j] = out[j - 1];
            j -= 1;
        }
        out[j] = entry;
        n += 1;
    }
    n
}

impl Bvh {
    /// The nearest hit with t in (0, `t_max`), if any.
    #[must_use]
    pub fn closest_hit(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        isa::run(
            #[inline(always)]
            || {
                if self.stack_need < SHALLOW_STACK {
                    self.walk::<false, SHALLOW_STACK>(ray, t_max)
                } else if self.stack_need < MID_STACK {
                    self.walk::<false, MID_STACK>(ray, t_max)
                } else {
                    self.walk::<false, DEEP_STACK>(ray, t_max)
                }
            },
        )
    }

    /// Whether anything is hit with t in (0, `t_max`) (stops at the first hit found).
    #[must_use]
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        isa::run(
            #[inline(always)]
            || {
                if self.stack_need < SHALLOW_STACK {
                    self.walk::<true, SHALLOW_STACK>(ray, t_max).is_some()
                } else if self.stack_need < MID_STACK {
                    self.walk::<true, MID_STACK>(ray, t_max).is_some()
                } else {
                    self.walk::<true, DEEP_STACK>(ray, t_max).is_some()
                }
            },
        )
    }

    /// [`Bvh::closest_hit`] of every ray k of `rays` with t in (0, `t_max[k]`), written to
    /// `out[k]`; [`INTERLEAVE`] rays are walked at once (see the module docs).
    ///
    /// # Panics
    /// When the three slices differ in length.
    pub fn closest_hits(&self, rays: &[Ray], t_max: &[f32], out: &mut [Option<Hit>]) {
        assert!(rays.len() == t_max.len() && rays.len() == out.len());
        let done = |k: usize, hit: Option<Hit>| out[k] = hit;
        isa::run(
            #[inline(always)]
            || match (self.stack_need < SHALLOW_STACK, self.in_cache()) {
                (true, true) => self.interleave::<false, SHALLOW_STACK, false>(rays, t_max, done),
                (true, false) => self.interleave::<false, SHALLOW_STACK, true>(rays, t_max, done),
                (false, true) => self.interleave::<false, DEEP_STACK, false>(rays, t_max, done),
                (false, false) => self.interleave::<false, DEEP_STACK, true>(rays, t_max, done),
            },
        );
    }

    /// [`Bvh::occluded`] of every ray k of `rays` with t in (0, `t_max[k]`), written to
    /// `out[k]`; [`INTERLEAVE`] rays are walked at once (see the module docs).
    ///
    /// # Panics
    /// When the three slices differ in length.
    pub fn occluded_many(&self, rays: &[Ray], t_max: &[f32], out: &mut [bool]) {
        assert!(rays.len() == t_max.len() && rays.len() == out.len());
        let done = |k: usize, hit: Option<Hit>| out[k] = hit.is_some();
        isa::run(
            #[inline(always)]
            || match (self.stack_need < SHALLOW_STACK, self.in_cache()) {
                (true, true) => self.interleave::<true, SHALLOW_STACK, false>(rays, t_max, done),
                (true, false) => self.interleave::<true, SHALLOW_STACK, true>(rays, t_max, done),
                (false, true) => self.interleave::<true, DEEP_STACK, false>(rays, t_max, done),
                (false, false) => self.interleave::<true, DEEP_STACK, true>(rays, t_max, done),
            },
        );
    }

    /// Whether the whole hierarchy fits in [`IN_CACHE`] bytes: then a walk waits for no
    /// memory, and the interleaved queries neither prefetch nor defer leaves (`Walk::step`'s
    /// `DEFER`), which would only add work (the Cornell box's interleaved occlusion at 0.6×).
    fn in_cache(&self) -> bool {
        self.memory_bytes() <= IN_CACHE
    }

    /// One ray's walk to its end.
    #[inline(always)]
    fn walk<const ANY: bool, const STACK: usize>(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        if self.packets.is_empty() {
            return None;
        }
        let mut walk = Walk::new(ray, t_max, self);
        let mut stack = [(0, 0.0); STACK];
        while !walk.step::<ANY, STACK, false>(self, &mut stack) {}
        walk.hit(self)
    }

    /// The walks of all `rays`, [`INTERLEAVE`] at a time, one step each in turn; `done` gets
    /// each ray's index and result.
    #[inline(always)]
    fn interleave<const ANY: bool, const STACK: usize, const DEFER: bool>(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        mut done: impl FnMut(usize, Option<Hit>),
    ) {
        if self.packets.is_empty() {
            (0..rays.len()).for_each(|k| done(k, None));
            return;
        }
        let idle = Walk::new(&Ray::new(Vec3::ZERO, Vec3::X), 0.0, self);
        let mut walks = [idle; INTERLEAVE];
        let mut stacks = [[(0, 0.0); STACK]; INTERLEAVE];
        let mut owner = [usize::MAX; INTERLEAVE];
        let mut next = 0;
        let mut active = 0;
        for (walk, owner) in walks.iter_mut().zip(&mut owner) {
            if next < rays.len() {
                *walk = Walk::new(&rays[next], t_max[next], self);
                *owner = next;
                next += 1;
                active += 1;
            }
        }
        while active > 0 {
            for ((walk, owner), stack) in walks.iter_mut().zip(&mut owner).zip(&mut stacks) {
                if *owner == usize::MAX || !walk.step::<ANY, STACK, DEFER>(self, stack) {
                    continue;
                }
                done(*owner, walk.hit(self));
                if next < rays.len() {
                    *walk = Walk::new(&rays[next], t_max[next], self);
                    *owner = next;
                    next += 1;
                } else {
                    *owner = usize::MAX;
                    active -= 1;
                }
            }
        }
    }
}

/// Sorts a node's children to visit worst first by `key` (larger is worse), by insertion: at
/// most eight, and equal keys keep their order, so the walk is deterministic. The one-ray walk
/// and the packet walk ([`super::coherent`]) both push all but the last and go on with it.
#[inline(always)]
pub(super) fn worst_first<T>(todo: &mut [T], key: impl Fn(&T) -> f32) {
    for i in 1..todo.len() {
        let mut j = i;
        while j > 0 && key(&todo[j - 1]) < key(&todo[j]) {
            todo.swap(j - 1, j);
            j -= 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deep_and_shallow_stacks_agree() {
        // Triangles on a helix: a tree that needs a few stack entries but far fewer than 64.
        let tris: Vec<[Vec3; 3]> = (0..2000)
            .map(|i| {
                let a = i as f32 * 0.05;
                let o = Vec3::new(a.cos() * 3.0, i as f32 * 0.01, a.sin() * 3.0);
                [
                    o,
                    o + Vec3::new(0.2, 0.0, 0.0),
                    o + Vec3::new(0.0, 0.2, 0.1),
                ]
            })
            .collect();
        let bvh = Bvh::build(&tris);
        assert!(bvh.stack_need > 0 && bvh.stack_need <= SHALLOW_STACK);
        for i in 0..500 {
            let a = i as f32 * 0.37;
            let ray = Ray::new(
                Vec3::new(0.0, i as f32 * 0.04, 0.0),
                Vec3::new(a.cos(), (a * 3.0).sin() * 0.3, a.sin()),
            );
            assert_eq!(
                bvh.walk::<false, SHALLOW_STACK>(&ray, f32::INFINITY),
                bvh.walk::<false, DEEP_STACK>(&ray, f32::INFINITY)
            );
            assert_eq!(
                bvh.walk::<true, SHALLOW_STACK>(&ray, 2.0).is_some(),
                bvh.walk::<true, DEEP_STACK>(&ray, 2.0).is_some()
            );
        }
    }
}
