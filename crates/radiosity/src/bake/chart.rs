//! Charts: the surfaces cut into pieces that lie flat in a light map.
//!
//! A light map needs every surface point to own a texel, so the surfaces are cut into *charts*,
//! each laid flat in the plane (parameterised) and packed beside the others
//! ([`super::pack`]). The cut here is the planar one of the xatlas approach's first stage and of
//! Lévy et al. 2002 ("Least squares conformal maps", §5, the charts grown from seeds): faces
//! join a chart across a shared edge while their normals stay within [`MAX_ANGLE_DEG`] of the
//! chart's first face, and the chart is laid flat by projecting it orthographically onto that
//! face's plane. A chart of coplanar faces (a wall, a floor made of many polygons) is then flat
//! without distortion at all; a chart on a gently curved surface is stretched by at most
//! 1 / cos [`MAX_ANGLE_DEG`]. A face that would land reversed in the plane starts a chart of its
//! own.
//!
//! Faces are the scene's polygons, each side on its own: the front of every polygon, and the
//! back of a two-sided one (its light differs from the front's: a partition lit on one side),
//! whose chart is the mirror image. Charts never cross objects. The enclosures that stand for
//! distant light (the default sky, an environment's far cube) are not surfaces of the model and
//! are left out.
//!
//! In the plane the first axis runs along the longest edge of the chart's first face, so a
//! rectangular wall lies along the texel rows instead of diagonally across them.

use std::collections::HashMap;

use glam::{DVec2, DVec3, Vec3};

use crate::Scene;

/// Largest angle between the normal of a chart's face and its first face's, degrees.
pub const MAX_ANGLE_DEG: f64 = 20.0;

/// One side of one polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Face {
    /// Index into [`Scene::polygons`].
    pub polygon: u32,
    /// Whether this is the back of a two-sided polygon.
    pub back: bool,
}

/// A chart: faces laid flat in one plane.
#[derive(Clone, Debug)]
pub struct Chart {
    /// Its faces.
    pub faces: Vec<Face>,
    /// Each face's corners in the plane, scene units, counter-clockwise seen from the side
    /// the face shows (the polygon's order, reversed for a back).
    pub corners: Vec<Vec<DVec2>>,
    /// The lower corner of the box around `corners`.
    pub min: DVec2,
    /// The upper corner.
    pub max: DVec2,
    /// The plane the chart is laid flat in.
    frame: Frame,
}

impl Chart {
    /// `p` (a point of one of the chart's faces) laid flat in the chart's plane.
    #[must_use]
    pub fn flat(&self, p: Vec3) -> DVec2 {
        self.frame.flat(p)
    }
}

impl Face {
    /// The face's corners in 3-D, counter-clockwise seen from the side it shows.
    #[must_use]
    pub fn vertices(&self, scene: &Scene) -> Vec<Vec3> {
        let mut v = scene.polygons[self.polygon as usize].vertices.clone();
        if self.back {
            v.reverse();
        }
        v
    }

    /// The unit normal of the side it shows.
    #[must_use]
    pub fn normal(&self, scene: &Scene) -> DVec3 {
        newell(&self.vertices(scene))
    }
}

/// The faces of `scene` cut into charts (module docs), in a deterministic order: by the
/// first face's polygon, fronts before backs.
#[must_use]
pub fn charts(scene: &Scene) -> Vec<Chart> {
    let distant = |object: usize| {
        let name = &scene.objects[object].name;
        name == crate::scene::sky::NAME || name == crate::scene::environment::NAME
    };
    let faces: Vec<Face> = scene
        .polygons
        .iter()
        .enumerate()
        .filter(|(_, p)| !distant(p.object))
        .flat_map(|(i, p)| {
            let two_sided = scene.materials[p.material].two_sided;
            let polygon = i as u32;
            std::iter::once(Face {
                polygon,
                back: false,
            })
            .chain(two_sided.then_some(Face {
                polygon,
                back: true,
            }))
        })
        .collect();
    let neighbours = adjacency(scene, &faces);
    let normals: Vec<DVec3> = faces.iter().map(|f| f.normal(scene)).collect();
    let cos_max = MAX_ANGLE_DEG.to_radians().cos();
    let mut taken = vec![false; faces.len()];
    let mut charts = Vec::new();
    for seed in 0..faces.len() {
        if taken[seed] || normals[seed] == DVec3::ZERO {
            continue;
        }
        let frame = Frame::of(&faces[seed].vertices(scene), normals[seed]);
        taken[seed] = true;
        let mut members = vec![seed];
        let mut k = 0;
        while k < members.len() {
            for &n in &neighbours[members[k]] {
                if taken[n] || normals[n].dot(normals[seed]) < cos_max {
                    continue;
                }
                if frame.area(&faces[n].vertices(scene)) <= 0.0 {
                    continue;
                }
                taken[n] = true;
                members.push(n);
            }
            k += 1;
        }
        members.sort_unstable();
        let corners: Vec<Vec<DVec2>> = members
            .iter()
            .map(|&m| {
                faces[m]
                    .vertices(scene)
                    .iter()
                    .map(|&v| frame.flat(v))
                    .collect()
            })
            .collect();
        let (min, max) = corners.iter().flatten().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), &c| (lo.min(c), hi.max(c)),
        );
        charts.push(Chart {
            faces: members.iter().map(|&m| faces[m]).collect(),
            corners,
            min,
            max,
            frame,
        });
    }
    charts
}

/// For each face, the faces of the same object and side that share an edge with it (both
/// ends at the same points).
fn adjacency(scene: &Scene, faces: &[Face]) -> Vec<Vec<usize>> {
    let key = |v: Vec3| v.to_array().map(f32::to_bits);
    // (object, side, one end, the other end) → the faces along that edge.
    type Edge = (u32, bool, [u32; 3], [u32; 3]);
    let mut by_edge: HashMap<Edge, Vec<usize>> = HashMap::new();
    for (i, f) in faces.iter().enumerate() {
        let object = scene.polygons[f.polygon as usize].object as u32;
        let v = f.vertices(scene);
        for k in 0..v.len() {
            let (a, b) = (key(v[k]), key(v[(k + 1) % v.len()]));
            by_edge
                .entry((object, f.back, a.min(b), a.max(b)))
                .or_default()
                .push(i);
        }
    }
    let mut neighbours = vec![Vec::new(); faces.len()];
    let mut edges: Vec<_> = by_edge.into_values().collect();
    edges.sort_unstable();
    for sharing in edges {
        for &a in &sharing {
            for &b in &sharing {
                if a != b && !neighbours[a].contains(&b) {
                    neighbours[a].push(b);
                }
            }
        }
    }
    for n in &mut neighbours {
        n.sort_unstable();
    }
    neighbours
}

/// The unit normal of a planar polygon by Newell's method (zero for a degenerate one).
pub(crate) fn newell(v: &[Vec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for k in 0..v.len() {
        let (a, b) = (v[k].as_dvec3(), v[(k + 1) % v.len()].as_dvec3());
        n += DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    n.normalize_or_zero()
}

/// A plane's frame: an origin and two axes along it, the normal their cross product.
#[derive(Clone, Debug)]
struct Frame {
    origin: DVec3,
    axes: [DVec3; 2],
}

impl Frame {
    /// The frame of the face with corners `v` and unit normal `normal`: its first axis along
    /// the face's longest edge.
    fn of(v: &[Vec3], normal: DVec3) -> Self {
        let mut longest = DVec3::ZERO;
        for k in 0..v.len() {
            let e = (v[(k + 1) % v.len()] - v[k]).as_dvec3();
            if e.length_squared() > longest.length_squared() {
                longest = e;
            }
        }
        let u = (longest - normal * longest.dot(normal)).normalize();
        Self {
            origin: v[0].as_dvec3(),
            axes: [u, normal.cross(u)],
        }
    }

    /// `p` projected into the plane, in its axes.
    fn flat(&self, p: Vec3) -> DVec2 {
        let d = p.as_dvec3() - self.origin;
        DVec2::new(d.dot(self.axes[0]), d.dot(self.axes[1]))
    }

    /// The signed area of the face with corners `v` projected into the plane (negative when
    /// it lands reversed).
    fn area(&self, v: &[Vec3]) -> f64 {
        let p: Vec<DVec2> = v.iter().map(|&x| self.flat(x)).collect();
        0.5 * (0..p.len())
            .map(|k| p[k].perp_dot(p[(k + 1) % p.len()]))
            .sum::<f64>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing;

    #[test]
    fn a_closed_cube_makes_six_undistorted_charts() {
        let scene = testing::closed_cube(0.5, [0.0; 6]);
        let charts = charts(&scene);
        assert_eq!(charts.len(), 6);
        for c in &charts {
            // Each face is a unit square laid flat unchanged: a 1 × 1 box, its corners counter-
            // clockwise (positive area).
            let size = c.max - c.min;
            assert!((size - DVec2::ONE).abs().max_element() < 1e-6, "{size}");
            let p = &c.corners[0];
            let area: f64 = 0.5
                * (0..p.len())
                    .map(|k| p[k].perp_dot(p[(k + 1) % p.len()]))
                    .sum::<f64>();
            assert!((area - 1.0).abs() < 1e-6, "{area}");
        }
    }

    #[test]
    fn coplanar_neighbours_share_a_chart_and_a_fold_splits_it() {
        // Two unit squares side by side in the floor, a third folded up by 90° along the far
        // edge of the second: the floor pair is one chart, the folded square its own.
        let square = |v: &str| {
            format!("[[objects]]\nname = \"strip\"\nmaterial = \"m\"\nshape = \"polygon\"\nvertices = {v}\n")
        };
        let toml = format!(
            "[materials.m]\nreflectance = 0.5\n{}{}{}",
            square("[[0, 0, 0], [0, 0, 1], [1, 0, 1], [1, 0, 0]]"),
            square("[[1, 0, 0], [1, 0, 1], [2, 0, 1], [2, 0, 0]]"),
            square("[[2, 0, 0], [2, 0, 1], [2, 1, 1], [2, 1, 0]]"),
        );
        let scene = Scene::from_toml_str(&toml, std::path::Path::new("strip.toml")).unwrap();
        let charts = charts(&scene);
        let sizes: Vec<usize> = charts.iter().map(|c| c.faces.len()).collect();
        assert_eq!(sizes, vec![2, 1], "{charts:?}");
        let size = charts[0].max - charts[0].min;
        assert!((size.max_element() - 2.0).abs() < 1e-6 && (size.min_element() - 1.0).abs() < 1e-6);
    }
}
