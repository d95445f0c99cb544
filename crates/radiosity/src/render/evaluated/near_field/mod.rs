//! The near field of the evaluated picture: the quadtree nodes within reach of a point, seen
//! with Lambert's exact factor (or the point kernel further off), the nodes next to the point
//! opened into their children and the elements into their pieces (see the module docs of
//! [`super`]), and the pieces right next to the point into quarters whose values follow the
//! slope of their element's pieces, a linear reconstruction that keeps each piece's mean
//! ([`split_piece`]): across a crease the light of the other surface changes fastest where the
//! point weighs it most. Nodes far from the point compared with their size are taken in
//! clusters, one source each ([`clusters`]), so that the work at a point follows the surfaces
//! around it rather than the count of nodes within its reach.

mod clusters;

use glam::Vec3;

use self::clusters::Clusters;
use crate::accel::{Bvh, Ray};
use crate::formfactor::analytic::point_to_polygon;
use crate::mesh::{display, Face, Mesh};
use crate::Rgb;

/// The pieces of an element at which the evaluation is taken once before the picture: its
/// children one quadtree step below it.
pub(super) const PIECES: usize = 4;

/// The reach of the near field, in diameters of the largest element of the receiving surface
/// (its patches that share the lit mesh's vertices, [`display::surfaces`]).
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
/// see there is near. The table was measured with the near field's factors unoccluded, where
/// beyond the reach surfaces that another one hides counted (at reach 8 the tall block's face
/// towards the red wall came out up to 48 % too bright); each term now has its visibility
/// ray ([`NearField::sees`]), and the reach stays where the table put it. The absolute reach
/// grows with the elements (the furnished room at `--elements 2048`: 1.42 % at reach 3,
/// 2.18 % at 5).
pub(super) const NEAR_REACH: f32 = 5.0;

/// A near node below the cut (along a contact line or a shadow) is opened into its children
/// within this many of its diameters of the point.
const OPEN_WITHIN: f32 = 2.0;

/// A piece within this many of its diameters of the point is split along the slope of its
/// element's pieces ([`split_piece`]), and each quarter again, down to [`SPLIT_DEPTH`] levels.
/// Measured on the furnished room at 256² against Mitsuba 3 (default solver): the bright line
/// along the crease of the window wall and the ceiling, +29 % at its worst pixel, is +16.5 %
/// at one level and +15.2 % at three; the picture 0.95 → 0.80 / 0.79 %, for a render stage
/// 20 % / 35 % longer when every near piece is split; one level, steep pieces only
/// ([`SPLIT_CHANGE`]): 0.80 %, 16 % longer (docs/raytracing.md).
const SPLIT_WITHIN: f32 = 1.5;

/// Levels of [`split_piece`] below a piece.
const SPLIT_DEPTH: u32 = 1;

/// A piece is split only where its element's slope changes B − E across it by more than this
/// share of its value (a flat wall is not).
const SPLIT_CHANGE: f64 = 0.05;

/// Beyond this many face diameters, a near node's factor is the point kernel
/// ([`near_factor`]).
const EXACT_WITHIN: f32 = 2.0;

/// The near field's sources: each patch cut at its uniform level (its shallowest elements;
/// deeper leaves, along contact lines and shadows, are merged into their ancestor at that level,
/// so that the count within reach stays small), found by position, with their mean reflected
/// radiosity B − E.
#[derive(Debug)]
pub(super) struct NearField {
    /// The nodes of the cut gathered into clusters, each taken as one source where it is far
    /// from the point compared with its size ([`clusters`]).
    clusters: Clusters,
    /// Mean B − E of the elements below each node of the mesh, by node index.
    reflected: Vec<Rgb>,
    /// The centroid, diameter and area of each node's face, by node index (computed once:
    /// every pixel asks).
    shapes: Vec<Shape>,
    /// The lit-mesh surface of each patch ([`display::surfaces`]).
    surfaces: Vec<u32>,
    /// The reach per patch: [`NEAR_REACH`] times the largest element diameter of its surface
    /// ([`surface_reach`]).
    reach: Vec<f32>,
    /// The [`pieces`] of each element: their centroids, areas and largest diameter.
    pub(super) pieces: Vec<Pieces>,
    /// B − E evaluated at each element's pieces, once the far part is known.
    pub(super) values: Vec<[Rgb; PIECES]>,
    /// The mesh's surfaces, for the visibility of each near term ([`NearField::sees`]).
    occluders: Bvh,
}

/// An element's [`pieces`], as the near field needs them.
#[derive(Clone, Copy, Debug)]
pub(super) struct Pieces {
    pub(super) centroids: [Vec3; PIECES],
    pub(super) areas: [f64; PIECES],
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
    /// How close to its centroid a point reads the pieces of an element of diameter
    /// `diameter`: it opens the element within `OPEN_WITHIN` of its diameters
    /// ([`NearField::irradiance_at`]).
    pub(super) fn open_radius(&self, diameter: f32) -> f32 {
        OPEN_WITHIN * diameter
    }

    /// The lit-mesh surface of patch `patch` ([`display::surfaces`]).
    pub(super) fn surface(&self, patch: u32) -> u32 {
        self.surfaces[patch as usize]
    }

    /// The centroid and diameter of element `e`.
    pub(super) fn element_shape(&self, mesh: &Mesh, e: usize) -> (Vec3, f32) {
        let shape = &self.shapes[mesh.elements[e] as usize];
        (shape.centroid, shape.diameter)
    }

    pub(super) fn new(mesh: &Mesh, radiosity: &[Rgb]) -> Self {
        let uniform = mesh.uniform_levels();
        let surfaces = display::surfaces(mesh);
        let reach = surface_reach(mesh, &surfaces);
        let reflected: Vec<Rgb> = mesh
            .nodes
            .iter()
            .map(|node| {
                let emission = mesh.patches[node.patch as usize].emission;
                let (mut area, mut sum) = (0.0, Rgb::ZERO);
                for e in node.elements.clone() {
                    let a = mesh.element(e as usize).area();
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
        let shapes: Vec<Shape> = mesh
            .nodes
            .iter()
            .map(|node| Shape {
                centroid: node.centroid(),
                diameter: node.diameter(),
                area: node.area(),
                normal: mesh.patches[node.patch as usize].normal,
            })
            .collect();
        let mut nodes = Vec::new();
        for (p, roots) in mesh.roots.iter().enumerate() {
            let mut stack: Vec<u32> = roots.clone().collect();
            while let Some(n) = stack.pop() {
                let node = &mesh.nodes[n as usize];
                match node.children {
                    Some(c) if node.level < uniform[p] => stack.extend(c..c + 4),
                    _ => nodes.push(n),
                }
            }
        }
        Self {
            clusters: Clusters::build(mesh, &nodes, &shapes, &reflected),
            reflected,
            shapes,
            surfaces,
            reach,
            pieces: (0..mesh.element_count())
                .map(|e| Pieces::of(&mesh.element(e).face))
                .collect(),
            values: Vec::new(),
            occluders: Bvh::build(&mesh.triangles),
        }
    }

    /// Whether the segment from `point` (unit normal `normal`) to `target` on a face of normal
    /// `target_normal` is clear, both ends lifted off their surfaces. The near field's factors
    /// are Lambert's without visibility, and a thin wall between a point and a near face
    /// (a lamp housing lit inside, the wall behind it outside) must stop that face's light.
    fn sees(&self, point: Vec3, normal: Vec3, target: Vec3, target_normal: Vec3) -> bool {
        let lift = self.occluders.lift();
        let from = point + normal * lift;
        let to = target + target_normal * lift;
        !self
            .occluders
            .occluded(&Ray::new(from, to - from), 1.0 - 1e-4)
    }

    /// N(x) at `point` (unit normal `normal`) on patch `patch`, Σ w F, the share of the view
    /// that the near elements take (see the module docs), and whether an element the point
    /// sees is close enough to be shown by its pieces.
    pub(super) fn irradiance(
        &self,
        mesh: &Mesh,
        point: Vec3,
        normal: Vec3,
        patch: u32,
    ) -> (Rgb, f64, bool) {
        let [at] = self.irradiance_at(mesh, [point], normal, patch);
        at
    }

    /// [`NearField::irradiance`] at several points of one patch (an element's pieces).
    pub(super) fn irradiance_at<const K: usize>(
        &self,
        mesh: &Mesh,
        points: [Vec3; K],
        normal: Vec3,
        patch: u32,
    ) -> [(Rgb, f64, bool); K] {
        let reach = self.reach[patch as usize];
        let polygon = mesh.patches[patch as usize].polygon;
        points.map(|point| {
            let mut near = (Rgb::ZERO, 0.0, false);
            if reach <= 0.0 {
                return near;
            }
            let mut open = Vec::new();
            let sees = |target, target_normal| self.sees(point, normal, target, target_normal);
            let far = self.clusters.gather(point, normal, reach, sees, |cut| {
                let d = self.shapes[cut as usize].centroid.distance(point) / reach;
                if d >= 1.0 {
                    return;
                }
                let w = f64::from((2.0 - 2.0 * d).clamp(0.0, 1.0));
                open.push(cut);
                while let Some(n) = open.pop() {
                    self.add_node(mesh, n, w, (point, normal, polygon), &mut open, &mut near);
                }
            });
            let (sum, share, by_pieces) = near;
            (sum + far.sum, (share + far.share).min(1.0), by_pieces)
        })
    }

    /// Adds node `n` of weight `w` to the near field `(sum, share, by_pieces)` of `point`
    /// (unit normal `normal`, on polygon `polygon`): Lambert's factor or the point kernel to
    /// it, to its pieces (an element next to the point, once their values are known), or its
    /// children pushed on `open` (a node above the elements next to the point).
    fn add_node(
        &self,
        mesh: &Mesh,
        n: u32,
        w: f64,
        (point, normal, polygon): (Vec3, Vec3, u32),
        open: &mut Vec<u32>,
        (sum, share, by_pieces): &mut (Rgb, f64, bool),
    ) {
        let shape = &self.shapes[n as usize];
        let node = &mesh.nodes[n as usize];
        // A planar polygon sends nothing to its own points, on either side: its back twin lies
        // in the point's plane, and the rounding of a hit point can put the point a hair in
        // front of it.
        if !in_front(shape, point) || mesh.patches[node.patch as usize].polygon == polygon {
            return;
        }
        let opened = shape.centroid.distance(point) < OPEN_WITHIN * shape.diameter;
        match node.children {
            Some(c) if opened => open.extend(c..c + 4),
            None if opened && !self.values.is_empty() => {
                *by_pieces = true;
                let e = node.elements.start as usize;
                let (at, values) = (&self.pieces[e], &self.values[e]);
                let slope = Slope::fit(at, values, shape.normal);
                for (k, value) in values.iter().enumerate() {
                    let piece = Shape {
                        centroid: at.centroids[k],
                        diameter: at.diameter,
                        area: at.areas[k],
                        normal: shape.normal,
                    };
                    let near = piece.centroid.distance(point) < SPLIT_WITHIN * piece.diameter;
                    if near && slope.steep(*value, piece.diameter) {
                        if !self.sees(point, normal, piece.centroid, shape.normal) {
                            continue;
                        }
                        let face = pieces(&node.face)[k];
                        let (s, f) = split_piece(
                            (&face, shape.normal),
                            *value,
                            &slope,
                            (point, normal),
                            SPLIT_DEPTH,
                        );
                        *sum += s * w;
                        *share += w * f;
                    } else {
                        let f = near_factor(|| pieces(&node.face)[k], &piece, point, normal);
                        if f <= 0.0 || !self.sees(point, normal, piece.centroid, shape.normal) {
                            continue;
                        }
                        *sum += *value * (w * f);
                        *share += w * f;
                    }
                }
            }
            _ => {
                let f = near_factor(|| node.face, shape, point, normal);
                if f <= 0.0 || !self.sees(point, normal, shape.centroid, shape.normal) {
                    return;
                }
                *by_pieces |= opened;
                *sum += self.reflected[n as usize] * (w * f);
                *share += w * f;
            }
        }
    }
}

/// The near field's reach on each patch: [`NEAR_REACH`] times the diameter of the largest
/// element of the patch's surface ([`display::surfaces`]), one reach for all its patches.
///
/// A point's near part N(x) and its far part R(x), interpolated from the vertices of the lit
/// mesh, add up to its indirect light only if the elements around those vertices split their
/// light at the point's reach. The vertices are shared within a surface, and a surface can hold
/// several patches meshed apart: the planar pieces of a slightly non-planar polygon (a block's
/// quad with a corner a millimetre off its plane is two triangles) or the coplanar polygons of
/// one object. With a reach per patch, hierarchical refinement that left one triangle of a
/// Cornell block's face a level coarser than the other gave that triangle twice the reach;
/// both its N and, through the shared vertices, the other triangle's R changed, and the face
/// showed a step of 10–25 % along its diagonal where Mitsuba 3 shows none (4 × 4-block RMS of
/// `benches/corpus/probes/nonplanar-quads` 1.59 → 0.87 %, the planar box 0.94 %).
fn surface_reach(mesh: &Mesh, surfaces: &[u32]) -> Vec<f32> {
    let count = surfaces.iter().map(|&s| s as usize + 1).max().unwrap_or(0);
    let mut largest = vec![0.0f32; count];
    for e in 0..mesh.element_count() {
        let node = mesh.element(e);
        let r = &mut largest[surfaces[node.patch as usize] as usize];
        *r = r.max(node.diameter());
    }
    surfaces
        .iter()
        .map(|&s| NEAR_REACH * largest[s as usize])
        .collect()
}

/// A near-field face, as the evaluation needs it (held by node: every pixel asks).
#[derive(Clone, Copy, Debug)]
struct Shape {
    centroid: Vec3,
    diameter: f32,
    area: f64,
    /// The front normal of the face's patch.
    normal: Vec3,
}

impl Shape {
    fn of(face: &Face, normal: Vec3) -> Self {
        Self {
            centroid: face.centroid(),
            diameter: face.diameter(),
            area: face.area(),
            normal,
        }
    }
}

/// The gradient of B − E over an element's plane, fitted to its pieces: the least-squares
/// plane through the four pieces' values at their centroids, per channel.
struct Slope {
    /// Two orthonormal directions in the element's plane.
    axes: [Vec3; 2],
    /// dB/ds along each axis, per channel.
    gradient: [Rgb; 2],
}

impl Slope {
    fn fit(at: &Pieces, values: &[Rgb; PIECES], normal: Vec3) -> Self {
        let u = (at.centroids[1] - at.centroids[0]).normalize_or_zero();
        let u = if u == Vec3::ZERO {
            normal.any_orthonormal_vector()
        } else {
            u
        };
        let axes = [u, normal.cross(u).normalize_or_zero()];
        let mean_c = at.centroids.iter().sum::<Vec3>() / PIECES as f32;
        let mean_v = values.iter().sum::<Rgb>() / PIECES as f64;
        // Normal equations of the fit: M g = b, M = Σ d dᵀ over the centroids' offsets d.
        let (mut m, mut b) = ([[0.0f64; 2]; 2], [Rgb::ZERO; 2]);
        for (c, v) in at.centroids.iter().zip(values) {
            let d = axes.map(|a| f64::from(a.dot(*c - mean_c)));
            for i in 0..2 {
                for j in 0..2 {
                    m[i][j] += d[i] * d[j];
                }
                b[i] += (*v - mean_v) * d[i];
            }
        }
        let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        let gradient = if det.abs() > 1e-12 * (m[0][0] * m[1][1]).max(f64::MIN_POSITIVE) {
            [
                (b[0] * m[1][1] - b[1] * m[0][1]) / det,
                (b[1] * m[0][0] - b[0] * m[1][0]) / det,
            ]
        } else {
            [Rgb::ZERO; 2]
        };
        Self { axes, gradient }
    }

    /// Whether B − E changes along the slope by more than [`SPLIT_CHANGE`] of `value` (per
    /// channel, its largest) across a piece of diameter `diameter`.
    fn steep(&self, value: Rgb, diameter: f32) -> bool {
        let across = (self.gradient[0].abs() + self.gradient[1].abs()) * f64::from(diameter);
        across
            .cmpgt(SPLIT_CHANGE * value.max(Rgb::splat(1e-12)))
            .any()
    }

    /// The change of B − E from `from` to `to`.
    fn change(&self, from: Vec3, to: Vec3) -> Rgb {
        let d = to - from;
        self.gradient[0] * f64::from(self.axes[0].dot(d))
            + self.gradient[1] * f64::from(self.axes[1].dot(d))
    }
}

/// The near part Σ F (B − E) and Σ F that `point` gets from `face`, a piece of mean B − E
/// `value` (patch normal `front`), split into its four quarters with values along `slope`
/// (each quarter's value shifted by the slope from the face's centroid to its own, at least
/// zero; the shifts of the four quarters cancel, so the face keeps its mean), and split again,
/// `depth` more times, where the point is within [`SPLIT_WITHIN`] of a quarter's diameter.
/// Next to a crease the light of the surface across it changes fast (the ceiling lit by a
/// window below it: nothing at the wall, the most 30 cm off), and a wall point within a few
/// centimetres of the ceiling weighs the ceiling's first centimetres the most: a constant
/// value per piece showed a bright band along the crease.
fn split_piece(
    (face, front): (&Face, Vec3),
    value: Rgb,
    slope: &Slope,
    (point, normal): (Vec3, Vec3),
    depth: u32,
) -> (Rgb, f64) {
    let centre = face.centroid();
    let (mut sum, mut share) = (Rgb::ZERO, 0.0);
    for quarter in face.split() {
        let shape = Shape::of(&quarter, front);
        let v = (value + slope.change(centre, shape.centroid)).max(Rgb::ZERO);
        if depth > 0 && shape.centroid.distance(point) < SPLIT_WITHIN * shape.diameter {
            let (s, f) = split_piece((&quarter, front), v, slope, (point, normal), depth - 1);
            sum += s;
            share += f;
        } else {
            let f = near_factor(|| quarter, &shape, point, normal);
            sum += v * f;
            share += f;
        }
    }
    (sum, share)
}

/// The four pieces of an element one quadtree step below it, in a fixed order.
fn pieces(face: &Face) -> [Face; PIECES] {
    face.split()
}

/// Whether `point` lies in front of the plane of a face of shape `shape`. A face whose plane
/// holds the point (the point's own surface) or turns away from it sends it nothing, and no
/// more do its children, in the same plane: such nodes are neither opened nor summed (their
/// terms were zeros, or within rounding of zero for a point on the plane).
fn in_front(shape: &Shape, point: Vec3) -> bool {
    shape.normal.dot(point - shape.centroid) > 1e-5 * shape.diameter
}

/// The form factor from `point` (unit normal `normal`) to a face (shape `shape`): Lambert's
/// exact factor within [`EXACT_WITHIN`] diameters of the face (which `face` then gives), the
/// point-to-area kernel A cosθ cosθ' / (π r²) beyond, where it is within a few per cent of it
/// and costs a tenth.
fn near_factor(face: impl FnOnce() -> Face, shape: &Shape, point: Vec3, normal: Vec3) -> f64 {
    let w = shape.centroid - point;
    let r2 = w.length_squared();
    if r2 > (EXACT_WITHIN * shape.diameter).powi(2) {
        let (cos_x, cos_y) = (normal.dot(w), -shape.normal.dot(w));
        if cos_x <= 0.0 || cos_y <= 0.0 {
            return 0.0;
        }
        return shape.area * f64::from(cos_x * cos_y / (r2 * r2)) / std::f64::consts::PI;
    }
    let (corners, sides) = face().corners_f64();
    point_to_polygon(point.as_dvec3(), normal.as_dvec3(), &corners[..sides])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square in z = 0, facing +z.
    fn square() -> Face {
        Face::quad(Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y)
    }

    #[test]
    fn only_faces_turned_to_the_point_are_visited_and_they_alone_send_light() {
        let face = square();
        let shape = Shape::of(&face, Vec3::Z);
        let corners = face.corners_f64();
        let f = |p: Vec3, n: Vec3| {
            point_to_polygon(p.as_dvec3(), n.as_dvec3(), &corners.0[..corners.1])
        };
        // On the face's plane (its own surface), behind it, and in front of it.
        for (p, n, front) in [
            (Vec3::new(2.0, 0.5, 0.0), Vec3::Z, false),
            (Vec3::new(1.5, 0.5, 0.0), -Vec3::X, false),
            (Vec3::new(0.5, 0.5, -1.0), -Vec3::Z, false),
            (Vec3::new(1.5, 0.5, 0.5), -Vec3::X, true),
        ] {
            assert_eq!(in_front(&shape, p), front, "{p}");
            assert_eq!(f(p, n) > 0.0, front, "{p}: {}", f(p, n));
        }
    }

    #[test]
    fn a_linear_field_is_fitted_exactly_from_the_pieces() {
        let at = Pieces::of(&square());
        let field = |c: Vec3| Rgb::splat(1.0 + 2.0 * f64::from(c.x) + 0.5 * f64::from(c.y));
        let values = at.centroids.map(field);
        let slope = Slope::fit(&at, &values, Vec3::Z);
        let (from, to) = (Vec3::new(0.1, 0.2, 0.0), Vec3::new(0.7, 0.9, 0.0));
        let change = slope.change(from, to);
        let exact = field(to) - field(from);
        assert!(
            (change - exact).abs().max_element() < 1e-6,
            "{change} vs {exact}"
        );
    }

    #[test]
    fn split_pieces_keep_their_mean_and_see_a_rising_field_across_a_crease() {
        // A ceiling piece rising from nothing at a crease (B − E = y), seen from a wall point
        // 1 cm from the crease: the wall point weighs the piece's first centimetres the most.
        let face = square();
        let slope = Slope {
            axes: [Vec3::X, Vec3::Y],
            gradient: [Rgb::ZERO, Rgb::ONE],
        };
        let (point, normal) = (Vec3::new(0.5, 0.0, 0.01), Vec3::Y);
        let factor = |f: &Face| {
            let (corners, sides) = f.corners_f64();
            point_to_polygon(point.as_dvec3(), normal.as_dvec3(), &corners[..sides])
        };
        // The exact near part: the field at the centres of a 128 × 128 grid of cells.
        let n = 128;
        let mut exact = 0.0;
        for i in 0..n {
            for j in 0..n {
                let (x0, y0, h) = (i as f32 / n as f32, j as f32 / n as f32, 1.0 / n as f32);
                let cell = Face::quad(
                    Vec3::new(x0, y0, 0.0),
                    Vec3::new(x0 + h, y0, 0.0),
                    Vec3::new(x0 + h, y0 + h, 0.0),
                    Vec3::new(x0, y0 + h, 0.0),
                );
                exact += factor(&cell) * f64::from(y0 + 0.5 * h);
            }
        }
        let constant = factor(&face) * 0.5;
        assert!(constant > 1.3 * exact, "the constant piece overstates it");
        let (split, share) = split_piece(
            (&face, Vec3::Z),
            Rgb::splat(0.5),
            &slope,
            (point, normal),
            3,
        );
        // The quarters tile it; those beyond EXACT_WITHIN of their diameters are seen with the
        // point kernel, within a few per cent of Lambert's factor.
        let whole = factor(&face);
        assert!((share - whole).abs() < 0.02 * whole, "{share} vs {whole}");
        let error = (split.x - exact).abs() / exact;
        assert!(
            error < 0.25 * (constant - exact) / exact,
            "split {} exact {exact}",
            split.x
        );
        // With no slope the quarters keep the piece's value: the constant estimate again.
        let flat = Slope {
            gradient: [Rgb::ZERO; 2],
            ..slope
        };
        let (same, _) = split_piece((&face, Vec3::Z), Rgb::splat(0.5), &flat, (point, normal), 3);
        assert!(
            (same.x - 0.5 * share).abs() < 1e-9,
            "{} vs {}",
            same.x,
            0.5 * share
        );
    }

    /// A lamp housing: a thin two-sided box 0.2 m wide, open at the bottom, 3 cm in front of
    /// a wall (z = 0, facing +z), hung over a floor.
    const HOUSING: &str = r#"
[materials.wall]
reflectance = 0.5
[materials.metal]
reflectance = 0.5
two_sided = true
[[objects]]
name = "wall"
material = "wall"
shape = "polygon"
vertices = [[-1, 0, 0], [1, 0, 0], [1, 2, 0], [-1, 2, 0]]
[[objects]]
name = "housing"
material = "metal"
shape = "polygon"
vertices = [[-0.1, 1.2, 0.03], [0.1, 1.2, 0.03], [0.1, 1.4, 0.03], [-0.1, 1.4, 0.03]]
[[objects]]
name = "housing"
material = "metal"
shape = "polygon"
vertices = [[-0.1, 1.2, 0.23], [-0.1, 1.4, 0.23], [0.1, 1.4, 0.23], [0.1, 1.2, 0.23]]
[[objects]]
name = "housing"
material = "metal"
shape = "polygon"
vertices = [[-0.1, 1.2, 0.03], [-0.1, 1.4, 0.03], [-0.1, 1.4, 0.23], [-0.1, 1.2, 0.23]]
[[objects]]
name = "housing"
material = "metal"
shape = "polygon"
vertices = [[0.1, 1.2, 0.03], [0.1, 1.2, 0.23], [0.1, 1.4, 0.23], [0.1, 1.4, 0.03]]
[[objects]]
name = "housing"
material = "metal"
shape = "polygon"
vertices = [[-0.1, 1.4, 0.03], [0.1, 1.4, 0.03], [0.1, 1.4, 0.23], [-0.1, 1.4, 0.23]]
"#;

    #[test]
    fn a_housing_lit_inside_sends_nothing_through_its_walls() {
        // Every inner side of the housing glows (B − E = 100), every outer side and the wall
        // are dark: the wall behind the housing and the housing's outer sides see only dark
        // surfaces. Without visibility the inner side of the housing's front panel, facing the
        // wall through the back panel, lit a halo on the wall (N = 63 at share 1); and a point
        // of an outer side, a rounding error behind its plane, saw its own inner twin at
        // distance zero (white speckles on a dark housing), which both the skip of the point's
        // own polygon and the visibility test stop.
        let scene =
            crate::Scene::from_toml_str(HOUSING, std::path::Path::new("housing.toml")).unwrap();
        let mesh = Mesh::build(&scene, crate::mesh::Subdivision::Elements(400));
        let radiosity: Vec<Rgb> = (0..mesh.element_count())
            .map(|e| {
                // The panels face in: their fronts are the inner sides.
                let p = mesh.element_patch(e);
                let inner = p.object != 0 && !p.back;
                Rgb::splat(if inner { 100.0 } else { 0.0 })
            })
            .collect();
        assert!(
            radiosity.iter().any(|b| b.x > 0.0),
            "the housing has inner sides"
        );
        let near = NearField::new(&mesh, &radiosity);
        let wall = (0..mesh.patches.len())
            .find(|&p| mesh.patches[p].object == 0)
            .unwrap();
        for x in [-0.05, 0.0, 0.08] {
            for y in [1.25, 1.3, 1.38] {
                let (n, share, _) =
                    near.irradiance(&mesh, Vec3::new(x, y, 0.0), Vec3::Z, wall as u32);
                assert!(
                    n.max_element() < 1e-9,
                    "wall at ({x}, {y}): N = {n:?}, share {share}"
                );
            }
        }
        // The front panel's outer side (its patch facing +z), at a point a rounding error
        // inside the housing.
        let front = (0..mesh.patches.len())
            .find(|&p| {
                let patch = &mesh.patches[p];
                patch.object != 0 && patch.normal.z > 0.9
            })
            .unwrap();
        let inside = Vec3::new(0.02, 1.3, 0.23 - 1e-6);
        let (n, share, _) = near.irradiance(&mesh, inside, Vec3::Z, front as u32);
        assert!(
            n.max_element() < 1e-9,
            "outer side: N = {n:?}, share {share}"
        );
    }
}
