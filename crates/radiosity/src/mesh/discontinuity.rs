//! Discontinuity meshing of shadows: the outlines of the umbra and the penumbra that each
//! emitter casts through each convex occluder become edges of the receivers' root faces.
//!
//! Across the boundary of a shadow the direct light is continuous but its derivative is not
//! (a D¹ or D² discontinuity: Heckbert 1992, "Discontinuity meshing for radiosity"), and an
//! element that straddles it averages the lit and the shadowed side: the lit mesh shows an
//! element-shaped step instead of the penumbra, and the element shines the average into the
//! room. Lischinski, Tampieri & Greenberg (1992) put element edges on those boundaries. The
//! boundaries come from the *visual events* between a light and an occluder: planes through an
//! edge of one and a vertex of the other (EV, VE), cut with the receiver's plane. This module
//! cuts the two that bound the shadow's regions, for a convex emitter L with corners l_j and a
//! convex occluder O (the convex hull of points p_i) wholly between L and the receiver's plane:
//!
//! ```text
//! shadow of O from l:   S(l) = hull{ x(l, p_i) },   x(l, p) = l + (p − l) · d_l / (d_l − d_p)
//! umbra    (L hidden):  U = ∩_j S(l_j)
//! penumbra (L partly):  P = hull ∪_j S(l_j)
//! ```
//!
//! with d the distance from the receiver's plane. A point x lies in the umbra when every
//! segment from x to L meets O; the light points it sees blocked are L ∩ (cone from x through
//! O), a convex set, which is all of L exactly when it holds L's corners: U is exact. A point
//! blocked for some light point y = Σ λ_j l_j behind some p lies in P: for fixed p the map
//! y ↦ x(y, p) is projective with a positive denominator (d_y > d_p), so it keeps convex
//! combinations convex, and x(y, p) lies in the hull of the x(l_j, p) ∈ S(l_j). The test below
//! samples both regions against shadow rays.
//!
//! Only the outer boundaries are cut, not the EV events inside the penumbra (where the visible
//! part of the light changes shape: weaker D² discontinuities); the quadtree's shadow refinement
//! ([`super::shadow`]) still splits the elements inside a penumbra. Occluders are the connected
//! parts of each object (polygons sharing corners) whose corners are in convex position: boxes,
//! icospheres, a planar convex polygon; a chair made of boxes is several. A non-convex part, an
//! occluder straddling the receiver's plane or reaching above the light, a light straddling the
//! plane: no cut, and the shadow refinement alone handles it. A cut only places element edges,
//! so an outline that is not a true boundary costs elements, never accuracy.

use glam::{DVec2, DVec3};

use super::imprint::{convex_normal, large_area, Piece};
use crate::scene::coincident::exact_bits;
use crate::Scene;

/// At most this many emitters cast outlines (the most powerful): a sky or an emissive mesh of
/// hundreds of polygons gives soft light without sharp boundaries worth a mesh edge each.
const MAX_EMITTERS: usize = 8;

/// Only shadows whose umbra is at least this share of their penumbra's area are outlined:
/// sharp ones. A soft shadow (a large window's, a thin leg's) changes slowly across its
/// penumbra, and its outlines only fragment the mesh (measured with every shadow outlined: the
/// furnished room's elements 7 576 → 22 371, its solve 17 → 619 s; at a quarter 13 015 and
/// 28 s; docs/decisions/discontinuity-meshing.md).
const SHARP: f64 = 0.25;

/// Relative tolerance (of the occluder's size) for a corner lying on the receiver's plane or on
/// a face plane of its part.
const FLAT: f64 = 1e-4;

/// A convex planar emitting polygon.
struct Emitter {
    polygon: usize,
    corners: Vec<DVec3>,
    normal: DVec3,
}

/// A convex occluder: the hull of `points`, made of `polygons`.
struct Occluder {
    polygons: Vec<usize>,
    points: Vec<DVec3>,
    /// A lower bound of its diameter, the scale of its tolerances.
    size: f64,
}

/// The receiver's plane with a 2D frame on it.
struct Plane {
    origin: DVec3,
    normal: DVec3,
    u: DVec3,
    v: DVec3,
}

impl Plane {
    fn new(origin: DVec3, normal: DVec3) -> Self {
        let u = normal.any_orthonormal_vector();
        Self {
            origin,
            normal,
            u,
            v: normal.cross(u),
        }
    }

    fn distance(&self, x: DVec3) -> f64 {
        self.normal.dot(x - self.origin)
    }

    fn flat(&self, x: DVec3) -> DVec2 {
        DVec2::new(self.u.dot(x - self.origin), self.v.dot(x - self.origin))
    }

    fn lift(&self, x: DVec2) -> DVec3 {
        self.origin + x.x * self.u + x.y * self.v
    }
}

/// Cuts the root faces of every large piece along the umbra and penumbra outlines that the
/// emitters cast on its plane through the scene's convex occluders.
pub(super) fn cut_shadows(scene: &Scene, pieces: &mut [Piece]) {
    let large = large_area(pieces);
    let emitters = emitters(scene, large);
    if emitters.is_empty() {
        return;
    }
    let occluders = occluders(scene, large);
    for piece in pieces.iter_mut().filter(|p| p.area() >= large) {
        let two_sided = scene.materials[scene.polygons[piece.polygon].material].two_sided;
        let corners: Vec<DVec3> = piece
            .roots
            .iter()
            .flat_map(|f| f.corners().iter().map(|c| c.as_dvec3()))
            .collect();
        let front = Plane::new(corners[0], piece.normal.as_dvec3());
        for e in &emitters {
            // The side of the plane the light is on; a light straddling it casts no outline.
            let d: Vec<f64> = e.corners.iter().map(|&c| front.distance(c)).collect();
            let plane = if d.iter().all(|&x| x > 0.0) {
                Plane::new(front.origin, front.normal)
            } else if two_sided && d.iter().all(|&x| x < 0.0) {
                Plane::new(front.origin, -front.normal)
            } else {
                continue;
            };
            if corners
                .iter()
                .all(|&c| e.normal.dot(c - e.corners[0]) <= 0.0)
            {
                continue;
            }
            for o in &occluders {
                if o.polygons.contains(&piece.polygon) || o.polygons.contains(&e.polygon) {
                    continue;
                }
                let Some((umbra, penumbra)) = shadow(&plane, e, o) else {
                    continue;
                };
                if area_2d(&umbra) < SHARP * area_2d(&penumbra) {
                    continue;
                }
                for outline in [penumbra, umbra] {
                    if area_2d(&outline) < large {
                        continue;
                    }
                    let q: Vec<DVec3> = outline.iter().map(|&x| plane.lift(x)).collect();
                    piece.cut(&q);
                }
            }
        }
    }
}

/// The umbra and the penumbra outline of occluder `o` lit by emitter `e` on `plane` (the light
/// on its positive side), in the plane's frame; `None` unless `o` lies wholly between them.
fn shadow(plane: &Plane, e: &Emitter, o: &Occluder) -> Option<(Vec<DVec2>, Vec<DVec2>)> {
    let tolerance = FLAT * o.size;
    let lowest_light = e
        .corners
        .iter()
        .map(|&c| plane.distance(c))
        .fold(f64::INFINITY, f64::min);
    let mut heights = Vec::with_capacity(o.points.len());
    let mut rises = false;
    for &p in &o.points {
        let h = plane.distance(p);
        if h < -tolerance
            || h >= lowest_light - tolerance
            || e.normal.dot(p - e.corners[0]) < -tolerance
        {
            return None;
        }
        rises |= h > tolerance;
        heights.push(h.max(0.0));
    }
    if !rises {
        return None;
    }
    let mut union = Vec::new();
    let mut umbra: Option<Vec<DVec2>> = None;
    for &l in &e.corners {
        let dl = plane.distance(l);
        let cast: Vec<DVec2> = o
            .points
            .iter()
            .zip(&heights)
            .map(|(&p, &h)| plane.flat(l + (p - l) * (dl / (dl - h))))
            .collect();
        union.extend_from_slice(&cast);
        let s = hull(cast);
        umbra = Some(match umbra {
            None => s,
            Some(u) => intersect(&u, &s),
        });
    }
    Some((umbra.unwrap_or_default(), hull(union)))
}

/// The convex planar emitters of at least `large` area, the [`MAX_EMITTERS`] most powerful.
fn emitters(scene: &Scene, large: f64) -> Vec<Emitter> {
    let mut found: Vec<(f64, Emitter)> = scene
        .polygons
        .iter()
        .enumerate()
        .filter_map(|(polygon, p)| {
            let material = &scene.materials[p.material];
            if !material.is_emitter() {
                return None;
            }
            convex_normal(&p.vertices, large).map(|normal| {
                let area = f64::from(model::polymesh::vector_area(&p.vertices).length());
                let power = area * material.emission.max_element();
                let corners = p.vertices.iter().map(|v| v.as_dvec3()).collect();
                let normal = normal.as_dvec3();
                (
                    power,
                    Emitter {
                        polygon,
                        corners,
                        normal,
                    },
                )
            })
        })
        .collect();
    found.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.polygon.cmp(&b.1.polygon)));
    found.truncate(MAX_EMITTERS);
    found.into_iter().map(|(_, e)| e).collect()
}

/// The connected parts of each object (polygons joined by shared corners) whose corners are in
/// convex position (every part's face plane has all of them on one side), of at least `large`
/// area; a single planar polygon is a part when it is convex.
fn occluders(scene: &Scene, large: f64) -> Vec<Occluder> {
    let parts = connected_parts(scene);
    parts
        .into_iter()
        .filter_map(|polygons| {
            let mut bits = std::collections::HashSet::new();
            let mut points = Vec::new();
            let mut area = 0.0;
            for &k in &polygons {
                let vs = &scene.polygons[k].vertices;
                area += f64::from(model::polymesh::vector_area(vs).length());
                for &v in vs {
                    if bits.insert(exact_bits(v)) {
                        points.push(v.as_dvec3());
                    }
                }
            }
            // Its box's diagonal over √3: never above the diameter, and linear in the points
            // (the diameter is quadratic: hours for a scanned mesh of 10⁵ corners).
            let (lo, hi) = points.iter().fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), &p| (lo.min(p), hi.max(p)),
            );
            let size = (hi - lo).length() / 3f64.sqrt();
            let tolerance = FLAT * size;
            let convex = polygons.iter().all(|&k| {
                let vs = &scene.polygons[k].vertices;
                let normal = model::polymesh::vector_area(vs).normalize_or_zero();
                if normal == glam::Vec3::ZERO {
                    return true;
                }
                if polygons.len() == 1 && !super::triangulate::is_convex(vs, normal) {
                    return false;
                }
                let (n, a) = (normal.as_dvec3(), vs[0].as_dvec3());
                let above = points.iter().any(|&p| n.dot(p - a) > tolerance);
                let below = points.iter().any(|&p| n.dot(p - a) < -tolerance);
                !(above && below)
            });
            (convex && area >= large && size > 0.0).then_some(Occluder {
                polygons,
                points,
                size,
            })
        })
        .collect()
}

/// The polygons of each object grouped into connected parts (sharing an exact corner), in
/// order of their first polygon.
fn connected_parts(scene: &Scene) -> Vec<Vec<usize>> {
    let n = scene.polygons.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut k: usize) -> usize {
        while parent[k] != k {
            parent[k] = parent[parent[k]];
            k = parent[k];
        }
        k
    }
    let mut first = std::collections::HashMap::new();
    for (k, p) in scene.polygons.iter().enumerate() {
        for &v in &p.vertices {
            let other = *first.entry((p.object, exact_bits(v))).or_insert(k);
            let (a, b) = (root(&mut parent, k), root(&mut parent, other));
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut parts: Vec<Vec<usize>> = Vec::new();
    let mut index = std::collections::HashMap::new();
    for k in 0..n {
        let r = root(&mut parent, k);
        let i = *index.entry(r).or_insert_with(|| {
            parts.push(Vec::new());
            parts.len() - 1
        });
        parts[i].push(k);
    }
    parts
}

/// The convex hull of some points, counter-clockwise (Andrew's monotone chain, 1979).
fn hull(mut points: Vec<DVec2>) -> Vec<DVec2> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let turn = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
    let mut out: Vec<DVec2> = Vec::with_capacity(2 * points.len());
    for pass in [
        &points[..],
        &points.iter().rev().copied().collect::<Vec<_>>()[..],
    ] {
        let start = out.len();
        for &p in pass {
            while out.len() >= start + 2 && turn(out[out.len() - 2], out[out.len() - 1], p) <= 0.0 {
                out.pop();
            }
            out.push(p);
        }
        out.pop();
    }
    out
}

/// The intersection of two convex counter-clockwise polygons (`a` clipped by each edge of `b`:
/// Sutherland & Hodgman 1974).
fn intersect(a: &[DVec2], b: &[DVec2]) -> Vec<DVec2> {
    let mut out = a.to_vec();
    for (k, &p) in b.iter().enumerate() {
        let q = b[(k + 1) % b.len()];
        let side = |x: DVec2| (q - p).perp_dot(x - p);
        let input = std::mem::take(&mut out);
        for (i, &x) in input.iter().enumerate() {
            let y = input[(i + 1) % input.len()];
            let (sx, sy) = (side(x), side(y));
            if sx >= 0.0 {
                out.push(x);
            }
            if (sx >= 0.0) != (sy >= 0.0) {
                out.push(x + (y - x) * (sx / (sx - sy)));
            }
        }
        if out.len() < 3 {
            return Vec::new();
        }
    }
    out
}

/// The area of a polygon in the plane.
fn area_2d(p: &[DVec2]) -> f64 {
    if p.len() < 3 {
        return 0.0;
    }
    let twice: f64 = (0..p.len())
        .map(|k| p[k].perp_dot(p[(k + 1) % p.len()]))
        .sum();
    0.5 * twice.abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Face;
    use crate::scene::{Material, Object, Polygon};
    use crate::Rgb;
    use glam::Vec3;

    const LO: Vec3 = Vec3::new(-0.2876, 0.5, -0.3141);
    const HI: Vec3 = Vec3::new(0.3124, 1.1, 0.2859);

    /// Half the side of the light.
    const LIGHT: f32 = 0.15;

    /// A floor of 4 × 4 at y = 0, a closed box floating over it, a square light of half side
    /// `half` at y = 2 facing down.
    fn scene(half: f32) -> Scene {
        let white = Material {
            reflectance: Rgb::splat(0.5),
            ..Material::default()
        };
        let light = Material {
            emission: Rgb::splat(1.0),
            ..Material::default()
        };
        let object = |name: &str| Object { name: name.into() };
        let polygon = |vertices: Vec<Vec3>, material, object| Polygon {
            vertices,
            material,
            object,
            uv: None,
        };
        let v = Vec3::new;
        let (a, b) = (LO, HI);
        let c = |x: f32, y: f32, z: f32| v(x, y, z);
        let mut polygons = vec![
            polygon(
                vec![
                    v(-2., 0., 2.),
                    v(2., 0., 2.),
                    v(2., 0., -2.),
                    v(-2., 0., -2.),
                ],
                0,
                0,
            ),
            polygon(
                vec![
                    v(-half, 2., -half),
                    v(half, 2., -half),
                    v(half, 2., half),
                    v(-half, 2., half),
                ],
                1,
                1,
            ),
        ];
        for f in [
            [
                c(a.x, a.y, a.z),
                c(b.x, a.y, a.z),
                c(b.x, a.y, b.z),
                c(a.x, a.y, b.z),
            ],
            [
                c(a.x, b.y, a.z),
                c(a.x, b.y, b.z),
                c(b.x, b.y, b.z),
                c(b.x, b.y, a.z),
            ],
            [
                c(a.x, a.y, a.z),
                c(a.x, b.y, a.z),
                c(b.x, b.y, a.z),
                c(b.x, a.y, a.z),
            ],
            [
                c(a.x, a.y, b.z),
                c(b.x, a.y, b.z),
                c(b.x, b.y, b.z),
                c(a.x, b.y, b.z),
            ],
            [
                c(a.x, a.y, a.z),
                c(a.x, a.y, b.z),
                c(a.x, b.y, b.z),
                c(a.x, b.y, a.z),
            ],
            [
                c(b.x, a.y, a.z),
                c(b.x, b.y, a.z),
                c(b.x, b.y, b.z),
                c(b.x, a.y, b.z),
            ],
        ] {
            polygons.push(polygon(f.to_vec(), 0, 2));
        }
        Scene {
            materials: vec![white, light],
            objects: vec![object("floor"), object("light"), object("box")],
            polygons,
            ..Scene::default()
        }
    }

    /// The share of a 48 × 48 grid of light points that the box hides from `x`.
    fn blocked(x: DVec3) -> f64 {
        let (lo, hi) = (LO.as_dvec3(), HI.as_dvec3());
        let n = 48;
        let mut hidden = 0;
        for i in 0..n {
            for j in 0..n {
                let y = DVec3::new(
                    f64::from(LIGHT) * (2.0 * (i as f64 + 0.5) / n as f64 - 1.0),
                    2.0,
                    f64::from(LIGHT) * (2.0 * (j as f64 + 0.5) / n as f64 - 1.0),
                );
                let d = y - x;
                let (mut t0, mut t1) = (0.0f64, 1.0f64);
                for k in 0..3 {
                    let (a, b) = ((lo[k] - x[k]) / d[k], (hi[k] - x[k]) / d[k]);
                    t0 = t0.max(a.min(b));
                    t1 = t1.min(a.max(b));
                }
                if t0 <= t1 {
                    hidden += 1;
                }
            }
        }
        f64::from(hidden) / f64::from(n * n)
    }

    /// 0 lit, 1 penumbra, 2 umbra.
    fn class(x: DVec3) -> u8 {
        match blocked(x) {
            b if b <= 0.0 => 0,
            b if b >= 1.0 => 2,
            _ => 1,
        }
    }

    #[test]
    fn no_floor_face_straddles_an_umbra_or_penumbra_outline() {
        let pieces = super::super::patch::patches(&scene(LIGHT), true);
        let (floor, roots) = &pieces[0];
        assert_eq!(floor.polygon, 0);
        let area: f64 = roots.iter().map(Face::area).sum();
        assert!((area - 16.0).abs() < 1e-4, "area kept: {area}");
        let mut seen = [0.0; 3];
        for f in roots {
            let centre = f.centroid().as_dvec3();
            let points: Vec<DVec3> = f
                .corners()
                .iter()
                .map(|c| centre + 0.6 * (c.as_dvec3() - centre))
                .chain([centre])
                .collect();
            let k = class(centre);
            for p in &points {
                assert_eq!(class(*p), k, "{f:?} straddles an outline at {p}");
            }
            seen[k as usize] += f.area();
        }
        // The three regions are there, and the floor is cut where they meet.
        assert!(seen.iter().all(|&a| a > 0.05), "{seen:?}");
        assert!(roots.len() > 8, "{} roots", roots.len());
    }

    #[test]
    fn the_floor_is_whole_when_the_box_reaches_above_the_light() {
        let mut s = scene(LIGHT);
        for p in &mut s.polygons[2..] {
            for v in &mut p.vertices {
                if v.y > 1.0 {
                    v.y = 2.5;
                }
            }
        }
        let pieces = super::super::patch::patches(&s, true);
        assert_eq!(pieces[0].1.len(), 1);
    }

    #[test]
    fn a_soft_shadow_is_not_outlined() {
        // A light wider than the box: the umbra is small beside the penumbra.
        let pieces = super::super::patch::patches(&scene(0.4), true);
        assert_eq!(pieces[0].1.len(), 1);
    }

    #[test]
    fn hull_and_intersection_of_squares() {
        let square = |x: f64, y: f64| {
            vec![
                DVec2::new(x, y),
                DVec2::new(x + 1.0, y),
                DVec2::new(x + 1.0, y + 1.0),
                DVec2::new(x, y + 1.0),
            ]
        };
        let mut both = square(0.0, 0.0);
        both.extend(square(0.5, 0.5));
        both.push(DVec2::new(0.5, 0.5));
        let h = hull(both);
        assert_eq!(h.len(), 6);
        assert!((area_2d(&h) - 2.0).abs() < 1e-12);
        let i = intersect(&square(0.0, 0.0), &square(0.5, 0.5));
        assert!((area_2d(&i) - 0.25).abs() < 1e-12);
        assert!(intersect(&square(0.0, 0.0), &square(2.0, 0.0)).is_empty());
    }
}
