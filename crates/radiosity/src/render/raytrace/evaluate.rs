//! Render-time evaluation of the radiosity solution: the direct light exactly at each visible
//! point, the indirect light from the solution.
//!
//! A constant (or vertex-interpolated) radiosity per element shows the mesh: shadows as soft as
//! the elements are large, halos around contact shadows, steps along shadow edges. Most of what
//! changes fast across a surface is the *direct* light; what the other surfaces reflect varies
//! slowly (Lischinski, Tampieri & Greenberg 1993; Smits, Arvo & Greenberg 1994 split the two
//! the same way). So at each point x the eye sees,
//!
//! ```text
//! B(x) = E(x) + ρ(x) · E_d(x) + B_i(x),
//! E_d(x) = Σ_luminaires  E_ℓ · F(x → ℓ) · V̄(x, ℓ),
//! B_i(e) = B(e) − E(e) − ρ(e) · Ē_d(e),
//! ```
//!
//! - F(x → ℓ): Lambert's exact point-to-polygon factor to each emitting root face
//!   ([`crate::formfactor::analytic::point_to_polygon`]), so fully lit points get the exact
//!   direct light, with no noise at all.
//! - V̄(x, ℓ): the kernel-weighted visible fraction of the luminaire, from an n × n jittered grid
//!   of shadow rays (n² = [`RaytraceSettings::shadow_samples`]) and rays to its corners: 1 in
//!   the open, 0 in umbrae; in penumbrae, where they disagree, sampled again by a grid 4 times
//!   finer on each side (no visible grain).
//! - B_i: the indirect radiosity of each element, the solution less its emission and its own
//!   direct light Ē_d(e) (the same estimator at a 4 × 4 grid of the element's points).
//!
//! The indirect light is smooth except next to another surface: into a corner it darkens within
//! one element, and interpolated it left a bright band along every corner of a room. So it is
//! split once more, into a *near* part gathered at the point with the exact kernel and a *far*
//! part interpolated (the near field of Lischinski, Tampieri & Greenberg 1993):
//!
//! ```text
//! B_i(x) = R_interpolated(x) · (1 − S(x)) + ρ(x) · N(x),
//! N(x) = Σ_{nodes s near x}  w(x, s) · F(x → s) · (B_s − E_s),     S(x) = Σ w F,
//! R(e) = (B_i(e) − ρ(e) · N̄(e)) / (1 − S̄(e)),
//! ```
//!
//! the nodes s those of each patch's uniform level (deeper leaves merged into them, B_s their
//! mean), F(x → s) Lambert's exact factor to the node (unoccluded: near surfaces see each other;
//! beyond two of the node's diameters the point kernel A cosθ cosθ' / (π r²), [`near_factor`]),
//! w a weight falling from 1 to 0 between half and the whole of the reach
//! ([`NEAR_REACH`] element diameters), and N̄, S̄ the means over the element's pieces, so that
//! the element's mean is kept. The near surfaces hide the far ones: into a corner S(x) grows
//! and the far part shrinks (a first version that added the near part to an interpolated far
//! part made the corners brighter still).
//!
//! Next to the point, an element's mean B_s is still too coarse: the floor within a few
//! centimetres of a block is darker than the mean of its element, and the bottom of the block's
//! face, which sees mostly that strip, came out 20–30 % too bright. So each element is cut into
//! four *pieces* (one quadtree step), the evaluation above is taken once at each piece's
//! centroid before the picture, and a point within [`OPEN_WITHIN`] diameters of an element
//! sees its pieces instead of its mean (nodes coarser than the elements open the same way).
//! The pieces are shifted to keep their element's mean, and R is taken a second time with them
//! in the near field, so that a point's far part and its neighbours' pieces agree (with R from
//! the first pass only, the furnished room's shelf, 5 cm from a wall, came out 1.5 % dark).
//! The direct light at the pieces is computed once for both passes. Measured at 256² against
//! Mitsuba 3, sixteen pieces (two steps) at a near-field reach of 3: the furnished room
//! 1.96 → 1.25 %, the Cornell box at 2 048 elements 2.56 → 2.10 % (at its default 6 082
//! elements 1.94 → 1.95 %). Four pieces instead of sixteen, at reach 5 and four rays per pair
//! in the solve: the Cornell box 1.53 → 1.50 %, the furnished room 1.20 → 1.25 %, for a
//! render stage of 1.4 s instead of 3.1 s and 3.1 s instead of 9.7 s.
//!
//! The solve stays viewer-independent; only the picture is evaluated per point. Mirrors and
//! glass are traced as by [`super::render`].

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::sample::Sampler;
use super::world::World;
use super::{trace_image, RaytraceSettings, Watch};
use crate::accel::{Aabb, Bvh};
use crate::formfactor::analytic::point_to_polygon;
use crate::mesh::{display, Face, Mesh};
use crate::render::{Image, RasterSettings};
use crate::scene::Camera;
use crate::{Rgb, Scene};

/// The pieces of an element at which the evaluation is taken once before the picture: its
/// children one quadtree step below it.
const PIECES: usize = 4;

/// The reach of the near field, in diameters of the largest element of the receiving patch.
/// Measured at 256² against Mitsuba 3 (`radiosity render --width 256 --height 256`,
/// `benches/image/error.py`, 4 × 4-pixel blocks), with sixteen pieces per element (now four:
/// the same errors within 0.05 points, module docs) and the ray-cast pilot of the time:
///
/// | reach | Cornell, 2 527 elements | Cornell, 6 082 | furnished room, 7 576 | teapot's render stage |
/// |---|---|---|---|---|
/// | 3 | 2.28 % | 1.95 % | 1.25 % | 7.3 s |
/// | 4 | 1.90 % | 1.69 % | 1.10 % | |
/// | 5 | 1.76 % | 1.52 % | 0.96 % | 12.9 s |
/// | 6 | 2.09 % | | 1.01 % | 21.0 s |
/// | 8 | 4.37 % | | 1.77 % | 32.2 s |
///
/// Short of the reach, the blocks' faces come out 20–30 % too bright over the last few pixels
/// above the floor, where the floor in their shadow darkens them: too little of the floor they
/// see there is near. Beyond it, surfaces that another one hides count in the near field (it
/// has no visibility): at reach 8 the tall block's face towards the red wall came out up to
/// 48 % too bright. The absolute reach grows with the elements, so coarse meshes meet that
/// limit sooner (the furnished room at `--elements 2048`: 1.42 % at reach 3, 2.18 % at 5).
const NEAR_REACH: f32 = 5.0;

/// The far part's radiosity is divided by the share of the view left to it; never by less.
const MIN_FAR_SHARE: f64 = 0.05;

/// A near node below the cut (along a contact line or a shadow) is opened into its children
/// within this many of its diameters of the point.
const OPEN_WITHIN: f32 = 2.0;

/// Beyond this many face diameters, a near node's factor is the point kernel
/// ([`near_factor`]).
const EXACT_WITHIN: f32 = 2.0;

/// How much finer, on each side, the shadow-ray grid is where the first grid's rays disagree.
const PENUMBRA_REFINE: u32 = 4;

/// One emitting root face.
#[derive(Debug)]
struct Luminaire {
    face: Face,
    corners: Vec<DVec3>,
    normal: Vec3,
    exitance: Rgb,
}

/// The emitters of a mesh, for the exact direct light.
#[derive(Debug)]
pub(super) struct Luminaires {
    list: Vec<Luminaire>,
}

/// The near field's sources: each patch cut at its uniform level (its shallowest elements;
/// deeper leaves, along contact lines and shadows, are merged into their ancestor at that level,
/// so that the count within reach stays small), found by position, with their mean reflected
/// radiosity B − E.
#[derive(Debug)]
pub(super) struct NearField {
    /// One degenerate triangle per node of the cut, from one corner of the node's bounding box
    /// to the opposite one, so that box queries find each node once.
    bvh: Bvh,
    /// The nodes of the cut.
    nodes: Vec<u32>,
    /// Mean B − E of the elements below each node of the mesh, by node index.
    reflected: Vec<Rgb>,
    /// The centroid, diameter and area of each node's face, by node index (computed once:
    /// every pixel asks).
    shapes: Vec<Shape>,
    /// The reach per patch: [`NEAR_REACH`] times its largest element's diameter.
    reach: Vec<f32>,
    /// The [`pieces`] of each element: their centroids, areas and largest diameter.
    pieces: Vec<Pieces>,
    /// B − E evaluated at each element's pieces, once the far part is known.
    values: Vec<[Rgb; PIECES]>,
}

/// An element's [`pieces`], as the near field needs them.
#[derive(Clone, Copy, Debug)]
struct Pieces {
    centroids: [Vec3; PIECES],
    areas: [f64; PIECES],
    diameter: f32,
}

impl Pieces {
    fn of(face: &Face) -> Self {
        let faces = pieces(face);
        Self {
            centroids: faces.map(|f| f.centroid()),
            areas: faces.map(|f| f.area()),
            diameter: faces.iter().map(Face::diameter).fold(0.0, f32::max),
        }
    }
}

impl NearField {
    fn new(mesh: &Mesh, radiosity: &[Rgb]) -> Self {
        let uniform = mesh.uniform_levels();
        let mut reach = vec![0.0f32; mesh.patches.len()];
        for e in 0..mesh.element_count() {
            let node = mesh.element(e);
            let r = &mut reach[node.patch as usize];
            *r = r.max(NEAR_REACH * node.face.diameter());
        }
        let reflected: Vec<Rgb> = mesh
            .nodes
            .iter()
            .map(|node| {
                let emission = mesh.patches[node.patch as usize].emission;
                let (mut area, mut sum) = (0.0, Rgb::ZERO);
                for e in node.elements.clone() {
                    let a = mesh.element(e as usize).face.area();
                    area += a;
                    sum += (radiosity[e as usize] - emission) * a;
                }
                if area > 0.0 {
                    sum / area
                } else {
                    Rgb::ZERO
                }
            })
            .collect();
        let shapes = mesh
            .nodes
            .iter()
            .map(|node| Shape::of(&node.face))
            .collect();
        let (mut boxes, mut nodes) = (Vec::new(), Vec::new());
        for (p, roots) in mesh.roots.iter().enumerate() {
            let mut stack: Vec<u32> = roots.clone().collect();
            while let Some(n) = stack.pop() {
                let node = &mesh.nodes[n as usize];
                match node.children {
                    Some(c) if node.level < uniform[p] => stack.extend(c..c + 4),
                    _ => {
                        nodes.push(n);
                        let b = Aabb::from_points(node.face.corners());
                        boxes.push([b.min, b.max, b.min]);
                    }
                }
            }
        }
        Self {
            bvh: Bvh::build(&boxes),
            nodes,
            reflected,
            shapes,
            reach,
            pieces: (0..mesh.element_count())
                .map(|e| Pieces::of(&mesh.element(e).face))
                .collect(),
            values: Vec::new(),
        }
    }

    /// N(x) at `point` (unit normal `normal`) on patch `patch`, Σ w F, the share of the view
    /// that the near elements take (see the module docs), and whether an element the point
    /// sees is close enough to be shown by its pieces.
    fn irradiance(&self, mesh: &Mesh, point: Vec3, normal: Vec3, patch: u32) -> (Rgb, f64, bool) {
        let reach = self.reach[patch as usize];
        if reach <= 0.0 {
            return (Rgb::ZERO, 0.0, false);
        }
        let query = Aabb {
            min: point - Vec3::splat(reach),
            max: point + Vec3::splat(reach),
        };
        // The nodes within reach, each once, in the order of the (fixed) traversal.
        let mut near: Vec<(u32, f32)> = Vec::new();
        self.bvh.overlapping(&query, |k| {
            let distance = self.shapes[self.nodes[k] as usize].centroid.distance(point);
            if distance < reach {
                near.push((k as u32, distance));
            }
        });
        let (mut sum, mut share, mut by_pieces) = (Rgb::ZERO, 0.0, false);
        let mut open = Vec::new();
        for (k, distance) in near {
            let d = distance / reach;
            let w = f64::from((2.0 - 2.0 * d).clamp(0.0, 1.0));
            if w <= 0.0 {
                continue;
            }
            open.push(self.nodes[k as usize]);
            while let Some(n) = open.pop() {
                let shape = &self.shapes[n as usize];
                let node = &mesh.nodes[n as usize];
                let opened = shape.centroid.distance(point) < OPEN_WITHIN * shape.diameter;
                let facing = mesh.patches[node.patch as usize].normal;
                match node.children {
                    Some(c) if opened => open.extend(c..c + 4),
                    None if opened && !self.values.is_empty() => {
                        by_pieces = true;
                        let e = node.elements.start as usize;
                        let (at, values) = (&self.pieces[e], &self.values[e]);
                        for (k, value) in values.iter().enumerate() {
                            let shape = Shape {
                                centroid: at.centroids[k],
                                diameter: at.diameter,
                                area: at.areas[k],
                            };
                            let f = near_factor(
                                || pieces(&node.face)[k],
                                facing,
                                &shape,
                                point,
                                normal,
                            );
                            sum += *value * (w * f);
                            share += w * f;
                        }
                    }
                    _ => {
                        let f = near_factor(|| node.face, facing, shape, point, normal);
                        by_pieces |= opened && f > 0.0;
                        sum += self.reflected[n as usize] * (w * f);
                        share += w * f;
                    }
                }
            }
        }
        (sum, share.min(1.0), by_pieces)
    }
}

/// A near-field face, as the evaluation needs it.
#[derive(Clone, Copy, Debug)]
struct Shape {
    centroid: Vec3,
    diameter: f32,
    area: f64,
}

impl Shape {
    fn of(face: &Face) -> Self {
        Self {
            centroid: face.centroid(),
            diameter: face.diameter(),
            area: face.area(),
        }
    }
}

/// The four pieces of an element one quadtree step below it, in a fixed order.
fn pieces(face: &Face) -> [Face; PIECES] {
    face.split()
}

/// The form factor from `point` (unit normal `normal`) to a face (front normal `facing`, shape
/// `shape`): Lambert's exact factor within [`EXACT_WITHIN`] diameters of the face (which
/// `face` then gives), the point-to-area kernel A cosθ cosθ' / (π r²) beyond, where it is
/// within a few per cent of it and costs a tenth.
fn near_factor(
    face: impl FnOnce() -> Face,
    facing: Vec3,
    shape: &Shape,
    point: Vec3,
    normal: Vec3,
) -> f64 {
    let w = shape.centroid - point;
    let r2 = w.length_squared();
    if r2 > (EXACT_WITHIN * shape.diameter).powi(2) {
        let (cos_x, cos_y) = (normal.dot(w), -facing.dot(w));
        if cos_x <= 0.0 || cos_y <= 0.0 {
            return 0.0;
        }
        return shape.area * f64::from(cos_x * cos_y / (r2 * r2)) / std::f64::consts::PI;
    }
    let (corners, sides) = face().corners_f64();
    point_to_polygon(point.as_dvec3(), normal.as_dvec3(), &corners[..sides])
}

/// What the evaluated render adds at a diffuse point: the exact direct light and the near part
/// of the indirect light.
#[derive(Debug)]
pub(super) struct Evaluation {
    luminaires: Luminaires,
    near: NearField,
}

impl Evaluation {
    /// ρ · (E_d + N) at a point of `patch`, and the share of its view that the near field
    /// takes from the far part.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn radiosity(
        &self,
        world: &World,
        mesh: &Mesh,
        point: Vec3,
        normal: Vec3,
        patch: u32,
        samples: u32,
        sampler: &mut Sampler,
    ) -> (Rgb, f64) {
        let rho = mesh.patches[patch as usize].reflectance;
        let direct = self
            .luminaires
            .irradiance(world, point, normal, samples, sampler);
        let (near, share, _) = self.near.irradiance(mesh, point, normal, patch);
        (rho * (direct + near), share)
    }

    /// The far part R of every element's indirect light and B − E at its pieces (see
    /// [`far_radiosity`]), the pieces then shown to the near field.
    fn settle(&mut self, world: &World, mesh: &Mesh, radiosity: &[Rgb], samples: u32) -> Vec<Rgb> {
        let direct: Vec<[Rgb; PIECES]> = (0..mesh.element_count())
            .into_par_iter()
            .map(|e| {
                let node = mesh.element(e);
                let patch = &mesh.patches[node.patch as usize];
                let mut sampler = Sampler::new(e as u32, u32::MAX, 0);
                self.near.pieces[e].centroids.map(|x| {
                    patch.reflectance
                        * self
                            .luminaires
                            .irradiance(world, x, patch.normal, samples, &mut sampler)
                })
            })
            .collect();
        let first = far_radiosity(mesh, radiosity, &self.near, &direct, None);
        self.near.values = first.iter().map(|f| f.1).collect();
        let first: Vec<Option<Rgb>> = first
            .iter()
            .map(|&(r, _, near)| (!near).then_some(r))
            .collect();
        far_radiosity(mesh, radiosity, &self.near, &direct, Some(&first))
            .into_iter()
            .map(|f| f.0)
            .collect()
    }
}

impl Luminaires {
    /// Every root face of every emitting front patch of `mesh`.
    fn new(mesh: &Mesh) -> Self {
        let mut list = Vec::new();
        for (p, patch) in mesh.patches.iter().enumerate() {
            if patch.back || patch.emission.max_element() <= 0.0 {
                continue;
            }
            for r in mesh.roots[p].clone() {
                let face = mesh.nodes[r as usize].face;
                let (corners, sides) = face.corners_f64();
                list.push(Luminaire {
                    face,
                    corners: corners[..sides].to_vec(),
                    normal: patch.normal,
                    exitance: patch.emission,
                });
            }
        }
        Self { list }
    }

    /// The direct irradiance E_d at `point` (unit normal `normal`): see the module docs.
    /// Each luminaire's visibility is first sampled by an n × n grid (n² = `samples`) and by
    /// rays to its corners; where they disagree (a penumbra) it is sampled again by a grid
    /// [`PENUMBRA_REFINE`] times finer on each side, so that soft shadows come out without
    /// visible grain. (An occluder's edge that hides a sliver of the light from a point at
    /// the rim of its penumbra passes between the grid's rays, but not between the corners.)
    fn irradiance(
        &self,
        world: &World,
        point: Vec3,
        normal: Vec3,
        samples: u32,
        sampler: &mut Sampler,
    ) -> Rgb {
        let n = f64::from(samples.max(1)).sqrt().round().max(1.0) as u32;
        let origin = point + normal * world.epsilon();
        let mut sum = Rgb::ZERO;
        for l in &self.list {
            let f = point_to_polygon(point.as_dvec3(), normal.as_dvec3(), &l.corners);
            if f <= 0.0 {
                continue;
            }
            let mut seen = l.visible(world, origin, normal, n, sampler);
            if (seen > 0.0 && seen < 1.0) || l.corner_differs(world, origin, seen > 0.0) {
                seen = l.visible(world, origin, normal, n * PENUMBRA_REFINE, sampler);
            }
            sum += l.exitance * (f * seen);
        }
        sum
    }
}

impl Luminaire {
    /// Whether a ray from `origin` to some corner of the luminaire (pulled in by a thousandth
    /// of its size) facing it is free when `lit` is false or blocked when it is true: the
    /// corners see what the first grid missed.
    fn corner_differs(&self, world: &World, origin: Vec3, lit: bool) -> bool {
        const IN: f32 = 1e-3;
        [
            (IN, IN),
            (1.0 - IN, IN),
            (1.0 - IN, 1.0 - IN),
            (IN, 1.0 - IN),
        ]
        .into_iter()
        .any(|(u, v)| {
            let y = self.face.point(u, v) + self.normal * world.epsilon();
            let w = y - origin;
            -self.normal.dot(w) > 0.0 && world.occluded(origin, y) == lit
        })
    }

    /// The kernel-weighted fraction of an n × n jittered grid of shadow rays from `origin`
    /// (on a surface of unit normal `normal`) to the luminaire that arrive; 0 when none of
    /// the grid's points faces the origin.
    fn visible(
        &self,
        world: &World,
        origin: Vec3,
        normal: Vec3,
        n: u32,
        sampler: &mut Sampler,
    ) -> f64 {
        let (mut all, mut seen) = (0.0, 0.0);
        for j in 0..n {
            for i in 0..n {
                let u = (i as f32 + sampler.next_f32()) / n as f32;
                let v = (j as f32 + sampler.next_f32()) / n as f32;
                let y = self.face.point(u, v) + self.normal * world.epsilon();
                let w = y - origin;
                let r2 = w.length_squared();
                let (cos_x, cos_y) = (normal.dot(w), -self.normal.dot(w));
                if r2 <= 0.0 || cos_x <= 0.0 || cos_y <= 0.0 {
                    continue;
                }
                let kernel = f64::from(cos_x * cos_y / (r2 * r2));
                all += kernel;
                if !world.occluded(origin, y) {
                    seen += kernel;
                }
            }
        }
        if all > 0.0 {
            seen / all
        } else {
            0.0
        }
    }
}

/// Renders `mesh` (built from `scene`, solved to the per-element `radiosity`) with the direct
/// light evaluated at each visible point and the indirect light from the solution (see the
/// module docs). `None` if `watch` stopped it.
#[must_use]
pub fn render(
    scene: &Scene,
    mesh: &Mesh,
    radiosity: &[Rgb],
    camera: &Camera,
    image: &RasterSettings,
    settings: &RaytraceSettings,
    watch: &Watch,
) -> Option<Image> {
    let mut evaluation = Evaluation {
        luminaires: Luminaires::new(mesh),
        near: NearField::new(mesh, radiosity),
    };
    // The geometry of the lit mesh does not depend on the values it carries: a world over the
    // solution's lit mesh finds each element's direct light, one over the far part shades.
    let full = display::lit_mesh(mesh, radiosity);
    let far = evaluation.settle(
        &World::new(scene, mesh, &full),
        mesh,
        radiosity,
        settings.shadow_samples,
    );
    let lit = display::lit_mesh(mesh, &far);
    let world = World::new(scene, mesh, &lit);
    trace_image(&world, Some(&evaluation), camera, image, settings, watch)
}

/// (B(e) − E(e) − ρ(e) · (Ē_d(e) + N̄(e))) / (1 − S̄(e)) for every element: the far part of
/// its indirect light per share of the view left to it (see the module docs), the means taken
/// over its pieces (`direct`: ρ E_d at each); B − E at each piece, ρ (E_d + N) + R (1 − S)
/// there, which the near field shows to the points next to the element; and whether some
/// piece sees an element close enough to be shown by its pieces. Where `known` holds an
/// element's R already (none of its pieces sees such an element, so that the pieces change
/// nothing), that is taken instead.
fn far_radiosity(
    mesh: &Mesh,
    radiosity: &[Rgb],
    near_field: &NearField,
    direct: &[[Rgb; PIECES]],
    known: Option<&[Option<Rgb>]>,
) -> Vec<(Rgb, [Rgb; PIECES], bool)> {
    (0..mesh.element_count())
        .into_par_iter()
        .map(|e| {
            if let Some(far) = known.and_then(|k| k[e]) {
                return (far, [Rgb::ZERO; PIECES], false);
            }
            let node = mesh.element(e);
            let patch = &mesh.patches[node.patch as usize];
            let at = &near_field.pieces[e];
            let mut parts = [(Rgb::ZERO, 0.0); PIECES];
            let (mut near, mut share, mut area, mut by_pieces) = (Rgb::ZERO, 0.0, 0.0, false);
            for k in 0..PIECES {
                let (n, s, p) =
                    near_field.irradiance(mesh, at.centroids[k], patch.normal, node.patch);
                parts[k] = (direct[e][k] + patch.reflectance * n, s);
                let a = at.areas[k];
                near += parts[k].0 * a;
                share += s * a;
                area += a;
                by_pieces |= p;
            }
            let reflected = radiosity[e] - patch.emission;
            let left = (1.0 - share / area).max(MIN_FAR_SHARE);
            let far = (reflected - near / area) / left;
            // Where the far share was clamped the pieces' mean is not the element's: shifted
            // back, so that the pieces only redistribute the element's light.
            let shift = reflected - (near / area + far * (1.0 - share / area));
            (
                far,
                parts.map(|(b, s)| b + far * (1.0 - s) + shift),
                by_pieces,
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::mesh::Subdivision;

    /// A 0.2 × 0.2 light at y = 2 facing down, a 0.6 × 0.6 blocker at y = 1, a floor at y = 0.
    const SHADOW: &str = r#"
[materials.floor]
reflectance = 0.5
[materials.light]
reflectance = 0.0
emission = 10.0
[[objects]]
name = "floor"
material = "floor"
shape = "polygon"
vertices = [[-1, 0, 1], [1, 0, 1], [1, 0, -1], [-1, 0, -1]]
[[objects]]
name = "blocker"
material = "floor"
shape = "polygon"
vertices = [[-0.3, 1, 0.3], [0.3, 1, 0.3], [0.3, 1, -0.3], [-0.3, 1, -0.3]]
[[objects]]
name = "light"
material = "light"
shape = "polygon"
vertices = [[-0.1, 2, -0.1], [0.1, 2, -0.1], [0.1, 2, 0.1], [-0.1, 2, 0.1]]
"#;

    #[test]
    fn the_pieces_keep_their_elements_mean_where_the_far_share_is_clamped() {
        // A plate 2 cm above a floor, facing it: under the plate the floor's near field takes
        // nearly all of its view, so its far share is clamped at MIN_FAR_SHARE; the pieces
        // must still redistribute exactly the element's B − E, whatever the radiosity.
        // The SHADOW scene with its blocker lowered to 2 cm, widened and turned to the floor.
        let blocker = "vertices = [[-0.3, 1, 0.3], [0.3, 1, 0.3], [0.3, 1, -0.3], [-0.3, 1, -0.3]]";
        assert!(SHADOW.contains(blocker));
        let slit = SHADOW.replace(
            blocker,
            "vertices = [[-0.8, 0.02, -0.8], [0.8, 0.02, -0.8], [0.8, 0.02, 0.8], [-0.8, 0.02, 0.8]]",
        );
        let scene = Scene::from_toml_str(&slit, Path::new("slit.toml")).expect("loads");
        let mesh = Mesh::build(&scene, Subdivision::Elements(200));
        let radiosity: Vec<Rgb> = (0..mesh.element_count())
            .map(|e| mesh.element_patch(e).emission + Rgb::splat(0.2 + 0.01 * (e % 7) as f64))
            .collect();
        let lit = display::lit_mesh(&mesh, &radiosity);
        let world = World::new(&scene, &mesh, &lit);
        let mut evaluation = Evaluation {
            luminaires: Luminaires::new(&mesh),
            near: NearField::new(&mesh, &radiosity),
        };
        let far = evaluation.settle(&world, &mesh, &radiosity, 16);
        let mut clamped = 0;
        for e in 0..mesh.element_count() {
            let at = &evaluation.near.pieces[e];
            let area: f64 = at.areas.iter().sum();
            let mean = at
                .areas
                .iter()
                .zip(&evaluation.near.values[e])
                .fold(Rgb::ZERO, |sum, (a, v)| sum + *v * *a)
                / area;
            let want = radiosity[e] - mesh.element_patch(e).emission;
            assert!(
                (mean - want).abs().max_element() < 1e-9 * want.max_element().max(1.0),
                "element {e}: pieces' mean {mean:?}, element {want:?}"
            );
            assert!(far[e].is_finite(), "element {e}: far part {:?}", far[e]);
            let node = mesh.element(e);
            let share: f64 = (0..PIECES)
                .map(|k| {
                    let (_, s, _) =
                        evaluation
                            .near
                            .irradiance(&mesh, at.centroids[k], Vec3::Y, node.patch);
                    s * at.areas[k]
                })
                .sum::<f64>()
                / area;
            clamped += usize::from(
                mesh.patches[node.patch as usize].normal.y > 0.5 && 1.0 - share < MIN_FAR_SHARE,
            );
        }
        assert!(clamped > 0, "no element under the plate was clamped");
    }

    #[test]
    fn penumbrae_follow_the_exact_visible_part_of_the_light() {
        // The blocker's edge x = 0.3, half-way up, hides the light's points with e_x ≤ 0.6 − x
        // from the floor point (x, 0, 0): the visible part of the light is the rectangle
        // e_x ∈ [max(−0.1, 0.6 − x), 0.1], |e_z| ≤ 0.1, and the exact direct irradiance is
        // π L F to it, Lambert's factor. Across the penumbra (x from 0.5 to 0.7) the 4 × 4 grid
        // of shadow rays alone is off by up to 11.7 % of the full light (at the penumbra's rims,
        // where the edge hides a sliver that passes between its rays); with the corner rays and
        // the 16 × 16 grid where they disagree, by 1.5 % (the jitter of 16 cells along the
        // edge, which runs along a column of the grid here: the worst case).
        let scene = Scene::from_toml_str(SHADOW, Path::new("shadow.toml")).expect("loads");
        let mesh = Mesh::build(&scene, Subdivision::Elements(100));
        let radiosity: Vec<Rgb> = (0..mesh.element_count())
            .map(|e| mesh.element_patch(e).emission)
            .collect();
        let lit = display::lit_mesh(&mesh, &radiosity);
        let world = World::new(&scene, &mesh, &lit);
        let luminaires = Luminaires::new(&mesh);
        let light = |from: f64| {
            [
                [from, 2.0, -0.1],
                [0.1, 2.0, -0.1],
                [0.1, 2.0, 0.1],
                [from, 2.0, 0.1],
            ]
            .map(DVec3::from_array)
        };
        let (mut worst, mut worst_coarse) = (0.0f64, 0.0f64);
        for k in 1..40 {
            let x = 0.5 + 0.005 * f64::from(k);
            let point = DVec3::new(x, 0.0, 0.0);
            let full =
                std::f64::consts::PI * 10.0 * point_to_polygon(point, DVec3::Y, &light(-0.1));
            let edge = (0.6 - x).clamp(-0.1, 0.1);
            let exact =
                std::f64::consts::PI * 10.0 * point_to_polygon(point, DVec3::Y, &light(edge));
            let mut sampler = Sampler::new(k, 0, 0);
            let got = luminaires.irradiance(&world, point.as_vec3(), Vec3::Y, 16, &mut sampler);
            worst = worst.max((got.x - exact).abs() / full);
            // The first grid alone, as before the penumbra refinement.
            let l = &luminaires.list[0];
            let origin = point.as_vec3() + Vec3::Y * world.epsilon();
            let coarse = l.visible(&world, origin, Vec3::Y, 4, &mut sampler) * full;
            worst_coarse = worst_coarse.max((coarse - exact).abs() / full);
        }
        println!(
            "worst: {:.3} %, first grid alone {:.3} %",
            100.0 * worst,
            100.0 * worst_coarse
        );
        assert!(worst < 0.02, "{worst}");
        assert!(worst_coarse > 4.0 * worst, "{worst_coarse} vs {worst}");
    }
}
