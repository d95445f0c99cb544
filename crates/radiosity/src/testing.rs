//! Scenes built in code, whose form factors and radiosities are known in closed form, for tests
//! and benchmarks that must not depend on asset files.
//!
//! All squares have unit side. The form-factor values quoted are from Howell's catalogue (see
//! [`crate::formfactor::analytic`] for the formulas).

use glam::{DVec3, Vec3};

use crate::accel::Bvh;
use crate::formfactor::Geometry;
use crate::mesh::{Mesh, Subdivision};
use crate::scene::{Camera, Material, Object, Polygon};
use crate::{Rgb, Scene};

/// A scene made ready for form factors: its mesh, the BVH over the mesh's triangles, and the
/// sources.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// Patches and elements.
    pub mesh: Mesh,
    /// Visibility structure over `mesh.triangles`.
    pub bvh: Bvh,
    /// Source node ids, `mesh.sources(max_sources, max_sources)`.
    pub sources: Vec<u32>,
}

impl Prepared {
    /// Meshes `scene` as `subdivision` says and cuts at most `max_sources` sources.
    #[must_use]
    pub fn new(scene: &Scene, subdivision: Subdivision, max_sources: usize) -> Self {
        let mesh = Mesh::build(scene, subdivision);
        let bvh = Bvh::build(&mesh.triangles);
        let sources = mesh.sources(max_sources, max_sources);
        Self { mesh, bvh, sources }
    }

    /// The geometry that form factors and solvers take.
    #[must_use]
    pub fn geometry(&self) -> Geometry<'_> {
        Geometry::new(&self.mesh, &self.bvh, &self.sources)
    }
}

/// Reflectance of the squares of the two-square scenes.
pub const SQUARE_REFLECTANCE: f64 = 0.5;

/// Two coaxial parallel unit squares `distance` apart, facing each other: object 0 ("bottom")
/// is `[0,1]² × {0}` facing +z, object 1 ("top") is the same square at z = `distance` facing −z.
/// Neither emits. At distance 1 the form factor between them is 0.1998249.
#[must_use]
pub fn parallel_squares(distance: f32) -> Scene {
    let centre = Vec3::new(0.5, 0.5, 0.0);
    let mut b = Builder::default();
    b.add("bottom", square(centre, Vec3::Z), SQUARE_REFLECTANCE, 0.0);
    b.add(
        "top",
        square(centre + distance * Vec3::Z, -Vec3::Z),
        SQUARE_REFLECTANCE,
        0.0,
    );
    b.finish("parallel squares")
}

/// [`parallel_squares`] at distance 1 with a blocker half-way between them that hides exactly
/// half of the light: the one-sided polygon [−0.1, 0.5] × [−0.1, 1.1] in the plane z = 0.5,
/// facing +z, object 2 ("blocker"). (Every segment between the squares crosses that plane
/// inside [0, 1]², so the blocker is as good as the half-plane x ≤ 0.5.)
///
/// A segment from (x₀, y₀, 0) to (x₁, y₁, 1) crosses the plane at x = (x₀ + x₁)/2, so it is
/// blocked when x₀ + x₁ < 1. The point reflection (x, y) ↦ (1 − x, 1 − y) of both squares keeps
/// the form-factor kernel and swaps blocked with free segments: the form factor is exactly
/// half of the unblocked 0.1998249.
#[must_use]
pub fn half_blocked_squares() -> Scene {
    let mut b = Builder::from(parallel_squares(1.0));
    b.add(
        "blocker",
        vec![
            Vec3::new(-0.1, -0.1, 0.5),
            Vec3::new(0.5, -0.1, 0.5),
            Vec3::new(0.5, 1.1, 0.5),
            Vec3::new(-0.1, 1.1, 0.5),
        ],
        SQUARE_REFLECTANCE,
        0.0,
    );
    b.finish("half-blocked squares")
}

/// Two perpendicular unit squares sharing an edge: object 0 ("floor") is `[0,1]² × {0}` facing
/// +z, object 1 ("wall") is `{0} × [0,1]²` facing +x; they meet along the y axis. The form
/// factor between them is 0.2000438.
#[must_use]
pub fn perpendicular_squares() -> Scene {
    let mut b = Builder::default();
    b.add(
        "floor",
        square(Vec3::new(0.5, 0.5, 0.0), Vec3::Z),
        SQUARE_REFLECTANCE,
        0.0,
    );
    b.add(
        "wall",
        square(Vec3::new(0.0, 0.5, 0.5), Vec3::X),
        SQUARE_REFLECTANCE,
        0.0,
    );
    b.finish("perpendicular squares")
}

/// The closed unit cube `[0,1]³` seen from inside: six faces facing inward, all of reflectance
/// `reflectance` (grey), face k emitting radiance `emission[k]` (grey, W·m⁻²·sr⁻¹; exitance is
/// π times that). Faces, objects and materials are in the order −x, +x, −y, +y, −z, +z (the
/// face at x = 0 first), named "x0", "x1", "y0", "y1", "z0", "z1".
///
/// Every row of its form-factor matrix sums to 1; with uniform ρ the total radiosity power is
/// Σ A E / (1 − ρ), and with every face emitting E every element has B = E / (1 − ρ).
#[must_use]
pub fn closed_cube(reflectance: f64, emission: [f64; 6]) -> Scene {
    let names = ["x0", "x1", "y0", "y1", "z0", "z1"];
    let mut b = Builder::default();
    for (k, name) in names.iter().enumerate() {
        let axis = k / 2;
        let mut centre = Vec3::splat(0.5);
        let mut normal = Vec3::ZERO;
        if k % 2 == 0 {
            centre[axis] = 0.0;
            normal[axis] = 1.0;
        } else {
            centre[axis] = 1.0;
            normal[axis] = -1.0;
        }
        b.add(name, square(centre, normal), reflectance, emission[k]);
    }
    b.finish("closed cube")
}

/// A point and a polygon for the point-to-polygon form factor: the centre of the bottom face of
/// the unit cube with normal +z, and the top face (centred above it at height 1, facing down),
/// as `(point, normal, polygon)`. The form factor is 4 · F_corner(½, ½, 1) = 0.2394565.
#[must_use]
pub fn point_to_square() -> (DVec3, DVec3, Vec<DVec3>) {
    let top = square(Vec3::new(0.5, 0.5, 1.0), -Vec3::Z);
    (
        DVec3::new(0.5, 0.5, 0.0),
        DVec3::Z,
        top.iter().map(|p| p.as_dvec3()).collect(),
    )
}

/// The unit square centred on `centre` with unit axis normal `normal`, counter-clockwise seen
/// from the front.
fn square(centre: Vec3, normal: Vec3) -> Vec<Vec3> {
    // Pick u, v with u × v = normal.
    let a = normal.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    let sign = normal[axis].signum();
    let mut u = Vec3::ZERO;
    let mut v = Vec3::ZERO;
    u[(axis + 1) % 3] = 0.5;
    v[(axis + 2) % 3] = 0.5 * sign;
    vec![
        centre - u - v,
        centre + u - v,
        centre + u + v,
        centre - u + v,
    ]
}

/// Collects polygons, one object and one material each.
#[derive(Default)]
struct Builder {
    scene: Scene,
}

impl From<Scene> for Builder {
    fn from(scene: Scene) -> Self {
        Self { scene }
    }
}

impl Builder {
    fn add(&mut self, name: &str, vertices: Vec<Vec3>, reflectance: f64, radiance: f64) {
        let s = &mut self.scene;
        s.materials.push(Material {
            name: name.into(),
            reflectance: Rgb::splat(reflectance),
            emission: Rgb::splat(radiance),
            ..Material::default()
        });
        s.objects.push(Object { name: name.into() });
        s.polygons.push(Polygon {
            vertices,
            material: s.materials.len() - 1,
            object: s.objects.len() - 1,
            uv: None,
        });
    }

    fn finish(mut self, name: &str) -> Scene {
        self.scene.name = name.into();
        if self.scene.cameras.is_empty() {
            self.scene.cameras.push(Camera {
                name: "default".into(),
                eye: Vec3::new(0.5, 0.5, 3.0),
                target: Vec3::splat(0.5),
                up: Vec3::Y,
                fov_y: 45.0,
            });
        }
        self.scene
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cube_faces_point_inward() {
        let cube = closed_cube(0.5, [0.0; 6]);
        for p in &cube.polygons {
            let n = model::polymesh::vector_area(&p.vertices);
            let centre = p.vertices.iter().copied().sum::<Vec3>() / 4.0;
            assert!((n.length() - 1.0).abs() < 1e-6, "unit area");
            assert!(n.dot(Vec3::splat(0.5) - centre) > 0.49, "faces the centre");
        }
    }
}
