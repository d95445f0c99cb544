//! Texels: the surface point each texel of the atlas stands for.
//!
//! A texel belongs to a chart when its centre falls on one of the chart's faces: it stands for
//! the surface point there (the face's corners interpolated by the centre's barycentric
//! coordinates in the chart's plane, so a face of a slightly curved chart keeps its own 3-D
//! corners). A texel of the gutter around the faces ([`super::pack`]) whose centre p lies
//! within the gutter of a face stands for the light the surface would have at p if it went on:
//! extrapolated linearly from the nearest point q of the chart's faces and the point q' as far
//! inside as p is outside (q' = 2q − p, when it lies on the chart),
//!
//! ```text
//! L(p) ≈ 2 L(q) − L(q'),
//! ```
//!
//! so that a renderer's bilinear filter, which near an edge mixes texels on both sides of it,
//! reads at the edge the light of the edge itself: two charts that meet along an edge (a floor
//! made of two objects) show the same light there, and no seam shows. (Copying the nearest inner
//! texel outwards, the usual dilation, leaves each side a quarter texel's gradient off, in
//! opposite directions: a 2.5 % step across the seam of the test under a near lamp.) Where q'
//! leaves the chart (a chart thinner than the gutter), the gutter texel takes L(q). Texels
//! farther out stay empty.

use glam::{DVec2, DVec3, Vec2, Vec3};

use super::chart::{Chart, Face};
use super::pack::Atlas;
use crate::mesh::triangulate::triangulate;
use crate::Scene;

/// A texel and the surface point it stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Texel {
    /// Its index in the atlas, row by row from the top.
    pub index: u32,
    /// The surface point.
    pub point: Vec3,
    /// The unit normal of the side the point shows.
    pub normal: Vec3,
    /// The face it lies on (or nearest to).
    pub face: Face,
    /// Whether its centre lies on a face (not in the gutter).
    pub inside: bool,
    /// For a gutter texel, the point q' inside the chart its light is extrapolated from
    /// (module docs), with its normal and face.
    pub mirror: Option<(Vec3, Vec3, Face)>,
    /// The texel's square in the model's own texture coordinates (its polygon's `uv`,
    /// extended affinely past the polygon's edges), corner by corner, when the polygon has
    /// them: where a textured albedo is averaged over the texel.
    pub footprint: Option<[Vec2; 4]>,
}

/// A triangle of a chart: its corners in the chart's plane and in space.
struct Flat {
    plane: [DVec2; 3],
    space: [DVec3; 3],
    /// The model's texture coordinates at the corners, if the polygon has them.
    uv: Option<[Vec2; 3]>,
    normal: Vec3,
    face: Face,
}

/// The texels of every chart, chart after chart (module docs).
#[must_use]
pub fn texels(scene: &Scene, charts: &[Chart], atlas: &Atlas) -> Vec<Texel> {
    let mut out = Vec::new();
    for (c, chart) in charts.iter().enumerate() {
        let flats = triangles(scene, chart);
        let (x0, y0) = atlas.corners[c];
        let span = atlas.texel(charts, c, chart.max) + f64::from(atlas.padding);
        let reach = (f64::from(atlas.padding) + 0.5) * std::f64::consts::SQRT_2 / atlas.density;
        for y in y0..(span.y.ceil() as u32).min(atlas.size.1) {
            for x in x0..(span.x.ceil() as u32).min(atlas.size.0) {
                let centre = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
                let base = atlas.texel(charts, c, chart.min);
                let q = chart.min + (centre - base) / atlas.density;
                if let Some((texel, f)) = locate(&flats, q, reach) {
                    let half = 0.5 / atlas.density;
                    let footprint = flats[f].uv.map(|uv| {
                        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(s, t)| {
                            let w = barycentrics(flats[f].plane, q + DVec2::new(s, t) * half);
                            (uv[0].as_dvec2() * w[0]
                                + uv[1].as_dvec2() * w[1]
                                + uv[2].as_dvec2() * w[2])
                                .as_vec2()
                        })
                    });
                    out.push(Texel {
                        index: y * atlas.size.0 + x,
                        footprint,
                        ..texel
                    });
                }
            }
        }
    }
    out
}

/// The chart's faces cut into triangles.
fn triangles(scene: &Scene, chart: &Chart) -> Vec<Flat> {
    let mut flats = Vec::new();
    for (face, corners) in chart.faces.iter().zip(&chart.corners) {
        let vertices = face.vertices(scene);
        let normal = Face::normal(face, scene).as_vec3();
        let uv = scene.polygons[face.polygon as usize]
            .uv
            .clone()
            .map(|mut uv| {
                if face.back {
                    uv.reverse();
                }
                uv
            });
        for [a, b, c] in triangulate(&vertices, normal) {
            let pick = |i: u32| (corners[i as usize], vertices[i as usize].as_dvec3());
            let (pa, pb, pc) = (pick(a), pick(b), pick(c));
            flats.push(Flat {
                plane: [pa.0, pb.0, pc.0],
                space: [pa.1, pb.1, pc.1],
                uv: uv
                    .as_ref()
                    .filter(|uv| uv.len() == vertices.len())
                    .map(|uv| [a, b, c].map(|i| uv[i as usize])),
                normal,
                face: *face,
            });
        }
    }
    flats
}

/// The texel at chart point `q` and the triangle it was found on: on the triangle holding it,
/// else at the nearest point of the triangles if within `reach`, with its mirror point inside
/// (module docs); `None` beyond.
fn locate(flats: &[Flat], q: DVec2, reach: f64) -> Option<(Texel, usize)> {
    let mut nearest: Option<(f64, usize, [f64; 3])> = None;
    for (i, f) in flats.iter().enumerate() {
        let w = barycentrics(f.plane, q);
        if w.iter().all(|&x| x >= -1e-12) {
            return Some((at(f, w, true), i));
        }
        let (d, w) = closest(f.plane, q);
        if nearest.is_none_or(|(best, _, _)| d < best) {
            nearest = Some((d, i, w));
        }
    }
    let (d, i, w) = nearest?;
    let f = &flats[i];
    if d > reach {
        return None;
    }
    let edge = f.plane[0] * w[0] + f.plane[1] * w[1] + f.plane[2] * w[2];
    let inner = edge * 2.0 - q;
    let mirror = flats.iter().find_map(|g| {
        let w = barycentrics(g.plane, inner);
        w.iter().all(|&x| x >= -1e-12).then(|| {
            let t = at(g, w, true);
            (t.point, t.normal, t.face)
        })
    });
    Some((
        Texel {
            mirror,
            ..at(f, w, false)
        },
        i,
    ))
}

/// The texel of triangle `f` at barycentrics `w` (its index filled in by the caller). A point
/// of the gutter, on the triangle's edge, is drawn a millionth of the way to its centre, so
/// that the probe that finds its element ([`crate::render::surface_points`]) does not meet
/// the edge itself.
fn at(f: &Flat, w: [f64; 3], inside: bool) -> Texel {
    let pull = if inside { 0.0 } else { 1e-6 };
    let w = w.map(|x| x * (1.0 - pull) + pull / 3.0);
    let p = f.space[0] * w[0] + f.space[1] * w[1] + f.space[2] * w[2];
    Texel {
        index: 0,
        point: p.as_vec3(),
        normal: f.normal,
        face: f.face,
        inside,
        mirror: None,
        footprint: None,
    }
}

/// The barycentric coordinates of `q` in triangle `t` (all zero for a degenerate one).
fn barycentrics(t: [DVec2; 3], q: DVec2) -> [f64; 3] {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], q - t[0]);
    let det = e1.perp_dot(e2);
    if det.abs() < 1e-300 {
        return [-1.0; 3];
    }
    let u = d.perp_dot(e2) / det;
    let v = e1.perp_dot(d) / det;
    [1.0 - u - v, u, v]
}

/// The distance from `q` to triangle `t` and the barycentrics of its nearest point: the
/// nearest of the three edges' nearest points (`q` lies outside).
fn closest(t: [DVec2; 3], q: DVec2) -> (f64, [f64; 3]) {
    let mut best = (f64::INFINITY, [1.0, 0.0, 0.0]);
    for k in 0..3 {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let e = b - a;
        let s = if e.length_squared() > 0.0 {
            ((q - a).dot(e) / e.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = (a + e * s).distance(q);
        if d < best.0 {
            let mut w = [0.0; 3];
            w[k] = 1.0 - s;
            w[(k + 1) % 3] = s;
            best = (d, w);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::{chart, pack};
    use crate::testing;

    #[test]
    fn every_texel_lies_on_its_face_or_at_its_edge() {
        let scene = testing::closed_cube(0.5, [0.0; 6]);
        let charts = chart::charts(&scene);
        let atlas = pack::at_density(&charts, 16.0, 2);
        let texels = texels(&scene, &charts, &atlas);
        // 16 × 16 centres fall on each unit face; around it a gutter ring two texels deep
        // (the corners of the ring beyond the reach of √2 · 2.5 / 16 excepted).
        let inside = texels.iter().filter(|t| t.inside).count();
        assert_eq!(inside, 6 * 16 * 16);
        let gutter = texels.len() - inside;
        assert!(gutter > 6 * 4 * 16 * 2 && gutter < 6 * 20 * 20, "{gutter}");
        let mut seen = std::collections::HashSet::new();
        for t in &texels {
            assert!(seen.insert(t.index), "texel {} twice", t.index);
            // On the cube's surface, and the normal pointing in (its faces face inward).
            let p = t.point;
            let on = p.abs().min_element() < 1e-6 || (p - Vec3::ONE).abs().min_element() < 1e-6;
            assert!(
                on && p.min_element() > -1e-6 && p.max_element() < 1.0 + 1e-6,
                "{p}"
            );
            assert!((p + t.normal * 0.01 - Vec3::splat(0.5)).abs().max_element() < 0.5);
        }
    }
}
