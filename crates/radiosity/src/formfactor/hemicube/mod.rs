//! Hemicube form factors (Cohen & Greenberg 1985, "The hemi-cube: a radiosity solution for
//! complex environments").
//!
//! By Nusselt's analogue, the form factor from a differential area to a polygon is the area of
//! the polygon's projection onto the unit hemisphere above the point, projected again onto the
//! tangent plane, divided by π. Any surface enclosing the point gives the same answer, and the
//! hemicube — the top face and four half side faces of a cube of half-side 1 around the point —
//! is one that a z-buffer can draw into. Each cell k of the hemicube carries its *delta form
//! factor* ΔF_k, the form factor from the point to that cell; then
//!
//! ```text
//! F_{dA→j} ≈ Σ_{cells k that see j} ΔF_k ,   ΔF_top = ΔA / π(x² + y² + 1)² ,
//!                                            ΔF_side = z ΔA / π(y² + z² + 1)² .
//! ```
//!
//! Here ΔF_k is the exact form factor of the cell's square (Lambert's contour integral,
//! [`super::analytic::point_to_polygon`]) rather than the midpoint formula above, so the deltas
//! sum to 1 to rounding at any resolution. Each face is an *item buffer*: the rasterizer
//! ([`raster`]) writes into each cell the id of the nearest polygon, with a z-buffer of 1/z.
//!
//! - **Gathering** ([`FormFactors::row`]): a hemicube at the element's centroid, drawing the
//!   sources, gives F_{e→s} for every source s at once.
//! - **Shooting** ([`FormFactors::column`]): a hemicube at the source's centroid, drawing the
//!   elements, gives F_{s→e}; reciprocity turns it into F_{e→s} = A_s F_{s→e} / A_e. Its five
//!   faces are drawn in parallel. A column is an estimate from the source's side, so it agrees
//!   with the row's value to the method's accuracy, not bit for bit.
//!
//! What is drawn: polygons facing the eye carry their id. A one-sided polygon seen from behind
//! still hides what lies beyond it but carries no id. A two-sided polygon has two coincident
//! patches; the one seen from behind is skipped, so its twin that faces the eye wins. Polygons
//! coplanar with the eye (the receiver's own patch, its back twin) are culled. Results are the
//! same at any thread count: every hemicube depends on its own element only.
//!
//! # Failure modes and what is done about them
//!
//! - **Near neighbours.** A hemicube measures from one point, which is good only while the
//!   distance is large against the element's size; at a shared edge the centroid's view can
//!   be off by tens of percent. So the receiver is integrated like in the other methods: one
//!   hemicube at each of its n × n quadrature points (`quadrature`), weighted by area, and for
//!   a row's receiver twice as many along each side where another surface is near
//!   (`Node::near`, as ray casting refines its grid): with one grid everywhere, the furnished
//!   room's window, whose light the walls beside it see edge-on, gave the elements 1.0022
//!   times its area in a column sum that should be 1 (ray casting 1.0005), and the room
//!   absorbed 1.0019 times what it emits; with the finer grid 1.0011 and 1.0014. And in each
//!   hemicube, sources whose centre lies within `near` × the mean of the two diameters
//!   ([`DEFAULT_NEAR`]) get Lambert's exact point-to-polygon factor
//!   ([`super::analytic::point_to_polygon`]) times the fraction of the source's cells that the
//!   z-buffer left visible, instead of the cell count. So the row stays consistent, the far
//!   values are scaled so that far sources and empty sky keep their share of what the near
//!   ones leave: by (1 − Σ_near F_exact) / (1 − Σ_near F_hemicube), which keeps a closed
//!   scene's row summing to 1.
//! - **Thin openings seen from a strip of the face.** Light that leaves a wall through a 1 mm
//!   slit (an emitter facing the wall just in front of it) is seen only from the wall's first
//!   millimetres beside the slit, where it fills a band of tens of degrees; from the cell
//!   centres of a midpoint rule a few centimetres in, the band is a fraction of a degree at
//!   the horizon and the emitter hides it. Progressive refinement shoots from such walls, so a
//!   shooter's hemicubes stand at jittered points of their cells (a stratified rule, unbiased
//!   whatever the integrand; [`super::Receiver::set_jittered`]): the suite's emitter facing a
//!   wall, ceiling −3.43 % → within 0.6 % (docs/decisions/hemicube-shooter.md). A row
//!   keeps the cell centres: jittered, the rows took the furnished room's shelf from +1.09 to
//!   +0.92 % but the partitions' right ceiling from +0.93 to +1.35 % and their power balance
//!   from 1.0010 to 0.9988 (Gauss-Seidel), noisier rather than better.
//! - **Aliasing.** A polygon smaller than a cell falls between the cell centres or takes a
//!   whole cell, and regular scenes line up with the grid, so the errors of neighbouring
//!   elements agree instead of cancelling. Every hemicube is turned about the normal by an
//!   angle from a hash of its element and the seed (deterministic, independent of threads),
//!   and the resolution is set by measurement ([`DEFAULT_RESOLUTION`]).
//! - **Polygons crossing the hemicube's plane** (or passing beside the eye) are clipped
//!   against the view frustum of each face — a near plane and the four sides, the horizon
//!   y ≥ 0 being a side of each half face — before projection, so only their part above the
//!   horizon is drawn and nothing divides by a depth of zero.

pub mod raster;

use std::cell::RefCell;
use std::fmt;
use std::sync::Arc;

use glam::Vec3;
use rayon::prelude::*;

use self::raster::{rasterize, FaceBuffer, Layout, Polygon, FACES, NOTHING};
use super::analytic::point_to_polygon;
use super::{node_grid, FormFactors, Geometry, Receiver};
use crate::hash::mix;
use crate::mesh::Face;

/// Cells along a full edge when the user asks for nothing else (see `docs/hemicube.md` for the
/// measurement).
pub const DEFAULT_RESOLUTION: u32 = 128;

/// Hemicube form-factor options.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Settings {
    /// Cells along a full edge of a hemicube (even, at least 2).
    pub resolution: u32,
    /// Side n of the n × n grid of hemicubes on each receiver (at least 1).
    pub quadrature: u32,
    /// Seed of the hemicubes' rotations.
    pub seed: u64,
}

impl Default for Settings {
    /// [`DEFAULT_RESOLUTION`] cells, and 2 × 2 hemicubes per receiver as ray casting's 2 × 2
    /// quadrature points.
    fn default() -> Self {
        Self {
            resolution: DEFAULT_RESOLUTION,
            quadrature: 2,
            seed: 0,
        }
    }
}

/// Sources closer than this many mean diameters get the area-to-area kernel.
pub const DEFAULT_NEAR: f32 = 2.0;

/// The near plane, relative to the receiver's diameter.
const NEAR_PLANE: f32 = 1e-5;

/// Item-buffer hemicube form factors (see the module documentation).
#[derive(Clone)]
pub struct Hemicube {
    layout: Layout,
    deltas: Arc<[f64]>,
    quadrature: u32,
    seed: u64,
    rotate: bool,
    near: f32,
}

impl fmt::Debug for Hemicube {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Hemicube")
            .field("resolution", &self.layout.resolution)
            .field("quadrature", &self.quadrature)
            .field("seed", &self.seed)
            .field("rotate", &self.rotate)
            .field("near", &self.near)
            .finish()
    }
}

/// What one hemicube saw: the item of every cell and the cells' delta form factors.
#[derive(Clone, Debug)]
pub struct View {
    /// Cell layout (see [`Layout::index`]).
    pub layout: Layout,
    /// Per cell, the index of the source it sees (into `Geometry::sources`), or [`NOTHING`].
    pub items: Vec<u32>,
    /// Per cell, its delta form factor.
    pub deltas: Vec<f64>,
}

impl Hemicube {
    /// A hemicube of `resolution` cells along a full edge (rounded up to even, at least 2),
    /// one hemicube at each point of an n × n receiver quadrature (`quadrature`, at least 1),
    /// and the rotation seed `seed`. Rotation is on and the near distance is [`DEFAULT_NEAR`].
    #[must_use]
    pub fn new(resolution: u32, quadrature: u32, seed: u64) -> Self {
        let resolution = resolution.clamp(2, 1 << 14).next_multiple_of(2);
        let layout = Layout { resolution };
        Self {
            layout,
            deltas: layout.deltas().into(),
            quadrature: quadrature.max(1),
            seed,
            rotate: true,
            near: DEFAULT_NEAR,
        }
    }

    /// Turns the random rotation about the normal on or off.
    #[must_use]
    pub fn with_rotation(mut self, rotate: bool) -> Self {
        self.rotate = rotate;
        self
    }

    /// Sets the near distance in mean diameters (0 turns the near-neighbour kernel off).
    #[must_use]
    pub fn with_near(mut self, near: f32) -> Self {
        self.near = near.max(0.0);
        self
    }

    /// Cells along a full edge.
    #[must_use]
    pub fn resolution(&self) -> u32 {
        self.layout.resolution
    }

    /// The delta form factors of all cells, in [`Layout`] order.
    #[must_use]
    pub fn deltas(&self) -> &[f64] {
        &self.deltas
    }

    /// The hemicube of element `element` drawing the sources (what [`FormFactors::row`] sums),
    /// for pictures and tests.
    #[must_use]
    pub fn view(&self, g: &Geometry, element: usize) -> View {
        let mut scratch = Scratch::default();
        let node = g.mesh.element(element);
        let (centre, normal) = (node.centroid(), node.normal());
        let eye = self.eye(centre, normal, node.diameter(), node.patch, [0, element, 0]);
        self.draw(g, &eye, sources_of(g), &mut scratch, false);
        View {
            layout: self.layout,
            items: scratch.items,
            deltas: self.deltas.to_vec(),
        }
    }

    /// The eye of a hemicube at `centre` with unit `normal`, on a face of diameter `size` of
    /// patch `patch`, turned by an angle from the hash of `key` and the seed.
    fn eye(&self, centre: Vec3, normal: Vec3, size: f32, patch: u32, key: [usize; 3]) -> Eye {
        let (u, v) = normal.any_orthonormal_pair();
        let (a, b) = if self.rotate {
            let hash = key.iter().fold(mix(self.seed), |h, &k| mix(h ^ k as u64));
            let angle = (hash >> 11) as f32 * (std::f32::consts::TAU / (1u64 << 53) as f32);
            let (sin, cos) = angle.sin_cos();
            (u * cos + v * sin, v * cos - u * sin)
        } else {
            (u, v)
        };
        Eye {
            centre,
            axes: [a, b, normal],
            size,
            patch,
        }
    }

    /// Draws `candidates` (id, face, patch) into the scratch's item buffers, filling its
    /// per-item sums `acc` (indexed by id, `count` long) and its near list.
    fn draw<'g>(
        &self,
        g: &Geometry<'g>,
        eye: &Eye,
        candidates: (usize, impl Fn(usize) -> (&'g Face, u32) + Copy),
        scratch: &mut Scratch,
        parallel: bool,
    ) {
        let (count, candidate) = candidates;
        scratch.reset(self.layout.cells(), count);
        let [a, b, c] = eye.axes;
        let local = |p: Vec3| {
            let d = p - eye.centre;
            Vec3::new(a.dot(d), b.dot(d), c.dot(d))
        };
        for id in 0..count {
            let (face, patch) = candidate(id);
            if patch == eye.patch {
                continue;
            }
            let info = &g.mesh.patches[patch as usize];
            let corners = face.corners();
            let to_eye = eye.centre - corners[0];
            let height = info.normal.dot(to_eye);
            let scale = to_eye.length() + corners[0].distance(corners[2]);
            if height.abs() <= 1e-5 * scale {
                continue;
            }
            let item = if height > 0.0 {
                id as u32
            } else if info.two_sided {
                continue;
            } else {
                NOTHING
            };
            let mut polygon = Polygon {
                corners: [Vec3::ZERO; 4],
                sides: corners.len() as u8,
                normal: local(eye.centre + info.normal),
                offset: 0.0,
                item,
                slot: NOTHING,
            };
            for (o, &p) in polygon.corners.iter_mut().zip(corners) {
                *o = local(p);
            }
            polygon.offset = polygon.normal.dot(polygon.corners[0]);
            if item != NOTHING && self.near > 0.0 {
                let centre = corners.iter().copied().sum::<Vec3>() / corners.len() as f32;
                let reach = self.near * 0.5 * (eye.size + corners[0].distance(corners[2]));
                if centre.distance(eye.centre) < reach {
                    polygon.slot = scratch.near.len() as u32;
                    scratch.near.push(id as u32);
                }
            }
            scratch.polygons.push(polygon);
        }
        // Rasterize the five faces, each with its own coverage of the near items.
        let slots = scratch.near.len().max(1);
        scratch.coverage.clear();
        scratch.coverage.resize(FACES * slots, 0.0);
        let near_z = NEAR_PLANE * eye.size.max(f32::MIN_POSITIVE);
        let mut jobs = Vec::with_capacity(FACES);
        let (mut items, mut depth) = (&mut scratch.items[..], &mut scratch.depth[..]);
        let mut coverage = &mut scratch.coverage[..];
        let mut deltas = &self.deltas[..];
        for face in 0..FACES {
            let n = self.layout.start(face + 1) - self.layout.start(face);
            let (i, rest_i) = items.split_at_mut(n);
            let (d, rest_d) = depth.split_at_mut(n);
            let (cv, rest_c) = coverage.split_at_mut(slots);
            let (dl, rest_dl) = deltas.split_at(n);
            jobs.push((face, i, d, cv, dl));
            (items, depth, coverage, deltas) = (rest_i, rest_d, rest_c, rest_dl);
        }
        let polygons = &scratch.polygons;
        let run = |(face, items, depth, coverage, deltas): (usize, _, _, &mut [f64], &[f64])| {
            rasterize(
                face,
                self.layout.resolution,
                near_z,
                polygons,
                FaceBuffer { items, depth },
                deltas,
                coverage,
            );
        };
        if parallel {
            jobs.into_par_iter().for_each(run);
        } else {
            jobs.into_iter().for_each(run);
        }
        // Sum the deltas of each item's cells.
        for (&item, &delta) in scratch.items.iter().zip(self.deltas.iter()) {
            if item != NOTHING {
                scratch.acc[item as usize] += delta;
            }
        }
    }

    /// Replaces the near items' sums by `exact(id, visible fraction)` (their share of the
    /// eye's hemisphere) and rescales the far ones so the row stays consistent.
    fn near_field(&self, scratch: &mut Scratch, mut exact: impl FnMut(usize, f64) -> f64) {
        if scratch.near.is_empty() {
            return;
        }
        let slots = scratch.near.len();
        let mut values = Vec::with_capacity(slots);
        for (k, &id) in scratch.near.iter().enumerate() {
            let id = id as usize;
            let unoccluded: f64 = (0..FACES).map(|f| scratch.coverage[f * slots + k]).sum();
            let visible = if unoccluded > 0.0 {
                (scratch.acc[id] / unoccluded).min(1.0)
            } else {
                0.0
            };
            values.push(exact(id, visible));
        }
        // The hemicube's share of the near items, and the exact one that replaces it.
        let hemicube: f64 = scratch
            .near
            .iter()
            .map(|&id| scratch.acc[id as usize])
            .sum();
        let replaced: f64 = values.iter().sum();
        let (near_scale, far_scale) = if replaced > 1.0 {
            (1.0 / replaced, 0.0)
        } else if 1.0 - hemicube > 1e-9 {
            (1.0, ((1.0 - replaced) / (1.0 - hemicube)).max(0.0))
        } else {
            (1.0, 1.0)
        };
        for f in &mut scratch.acc {
            *f *= far_scale;
        }
        for (&id, value) in scratch.near.iter().zip(values) {
            scratch.acc[id as usize] = value * near_scale;
        }
    }
}

/// The position and axes (a, b, normal) of a hemicube.
struct Eye {
    centre: Vec3,
    axes: [Vec3; 3],
    size: f32,
    patch: u32,
}

/// Reusable buffers of one hemicube.
#[derive(Default)]
struct Scratch {
    polygons: Vec<Polygon>,
    items: Vec<u32>,
    depth: Vec<f32>,
    coverage: Vec<f64>,
    near: Vec<u32>,
    acc: Vec<f64>,
    total: Vec<f64>,
    receiver: Receiver,
}

impl Scratch {
    fn reset(&mut self, cells: usize, count: usize) {
        self.polygons.clear();
        self.near.clear();
        self.items.resize(cells, NOTHING);
        self.depth.resize(cells, 0.0);
        self.acc.clear();
        self.acc.resize(count, 0.0);
    }
}

thread_local! {
    /// One scratch per thread, reused by every hemicube the thread draws.
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// Runs `f` with this thread's scratch, or a fresh one if it is in use (a column's parallel
/// faces can let this thread steal another hemicube while it waits).
fn with_scratch<T>(f: impl FnOnce(&mut Scratch) -> T) -> T {
    SCRATCH.with(|cell| match cell.try_borrow_mut() {
        Ok(mut scratch) => f(&mut scratch),
        Err(_) => f(&mut Scratch::default()),
    })
}

/// The sources as drawing candidates.
fn sources_of<'g>(g: &Geometry<'g>) -> (usize, impl Fn(usize) -> (&'g Face, u32) + Copy + 'g) {
    let (mesh, sources) = (g.mesh, g.sources);
    (sources.len(), move |s: usize| {
        let node = &mesh.nodes[sources[s] as usize];
        (&node.face, node.patch)
    })
}

impl Hemicube {
    /// Σ_k w_k F(x_k → item) over hemicubes at the `quadrature` × `quadrature` points x_k of
    /// `face` (of patch `patch`), drawing `candidates`; the near items of each hemicube get
    /// Lambert's exact point-to-polygon factor times their visible fraction. Leaves the sums
    /// in `scratch.total`.
    fn integrate<'g>(
        &self,
        g: &Geometry<'g>,
        (face, patch, key, quadrature, jitter): (&Face, u32, [usize; 2], u32, bool),
        candidates: (usize, impl Fn(usize) -> (&'g Face, u32) + Copy),
        scratch: &mut Scratch,
        parallel: bool,
    ) {
        let normal = face.normal();
        let mut receiver = std::mem::take(&mut scratch.receiver);
        let seed = jitter.then(|| mix(self.seed ^ mix(key[0] as u64 ^ mix(key[1] as u64))));
        receiver.set_jittered(face, quadrature, seed);
        let size = face.diameter() / quadrature as f32;
        scratch.total.clear();
        scratch.total.resize(candidates.0, 0.0);
        for (k, &(x, weight)) in receiver.points.iter().enumerate() {
            let eye = self.eye(x.as_vec3(), normal, size, patch, [key[0], key[1], k]);
            self.draw(g, &eye, candidates, scratch, parallel);
            self.near_field(scratch, |id, visible| {
                let polygon: Vec<_> = candidates.1(id)
                    .0
                    .corners()
                    .iter()
                    .map(|c| c.as_dvec3())
                    .collect();
                point_to_polygon(x, receiver.normal, &polygon) * visible
            });
            for (t, &f) in scratch.total.iter_mut().zip(&scratch.acc) {
                *t += weight * f;
            }
        }
        scratch.receiver = receiver;
    }
}

impl FormFactors for Hemicube {
    fn row(&self, g: &Geometry, element: usize, out: &mut [f32]) {
        let node = g.mesh.element(element);
        with_scratch(|scratch| {
            let quadrature = node_grid(node, self.quadrature);
            let receiver = (&node.face, node.patch, [0, element], quadrature, false);
            self.integrate(g, receiver, sources_of(g), scratch, false);
            for (o, &f) in out.iter_mut().zip(&scratch.total) {
                *o = f as f32;
            }
        });
    }

    fn occluded_only_by_sources(&self) -> bool {
        true
    }

    fn rows_tile_the_hemisphere(&self) -> bool {
        true
    }

    fn column(&self, g: &Geometry, source: usize, out: &mut [f32]) {
        let node = &g.mesh.nodes[g.sources[source] as usize];
        let source_area = node.area();
        let mesh = g.mesh;
        let elements = (mesh.element_count(), |e: usize| {
            let n = mesh.element(e);
            (&n.face, n.patch)
        });
        with_scratch(|scratch| {
            // The shooter's own grid, jittered (module docs). Refined near another surface as
            // the rows' receivers are, it made progressive refinement three times longer on
            // the bare OBJ room and moved the emitter facing a wall only from −3.43 to −3.06 %.
            let shooter = (&node.face, node.patch, [1, source], self.quadrature, true);
            self.integrate(g, shooter, elements, scratch, true);
            // Reciprocity: F_{e→s} = A_s F_{s→e} / A_e.
            for (e, (o, &f)) in out.iter_mut().zip(&scratch.total).enumerate() {
                let area = mesh.element(e).area();
                *o = if area > 0.0 {
                    (f * source_area / area) as f32
                } else {
                    0.0
                };
            }
        });
    }
}
