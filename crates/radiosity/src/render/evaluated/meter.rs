//! An irradiance meter: the light falling on a small surface at any point of the scene, in
//! the air or on a surface — what a lighting designer's lux meter reads on a calculation grid.
//!
//! ```text
//! E(x, n) = E_d(x, n) + E_i(x, n),
//! E_d = Σ_luminaires  E_ℓ · F(x → ℓ) · V̄(x, ℓ),
//! E_i = ∫_Ω L_r(y(x, ω)) cos θ dω  ≈  (π / N) Σ_k L_r(y_k),
//! ```
//!
//! - E_d: the direct light exactly as the evaluated picture takes it ([`super::luminaires`]):
//!   Lambert's point-to-polygon factor to every emitting face, times its visible fraction from
//!   a grid of shadow rays, sampled again finely in penumbrae;
//! - E_i: the light the solution's surfaces reflect, by N = [`GATHER_SIDE`]² rays drawn from
//!   x in cosine-weighted directions, stratified over an N-cell grid, each reading the reflected
//!   radiance L_r = (B − E)/π of the lit mesh where it first lands (Cohen & Wallace 1993,
//!   §9.3's final gather; the emitters' own light is E_d's, so it is left out here).
//!
//! The lit mesh the rays read carries B − E itself: each element's reflected radiosity
//! (B_e − E_e)⁺, averaged at the vertices and interpolated as B is. Interpolating B and taking
//! away the emission of the patch hit would not give it: a vertex shared by emitters of
//! different E (the tiles of a sky, [`crate::scene::environment::tiles`]; a lamp set into a
//! ceiling of the same object) carries the mean of their B, so B − E would come out positive
//! on one side of every such edge and negative on the other where nothing reflects at all, and
//! the positive side, clamped at 0, would be gathered as reflected light. Measured on a black
//! plane under the CIE skies (`under_a_sky_a_black_plane_reads_the_sky_alone` below), that
//! reads +0.93 % (overcast), +1.06 % (type 1) and +2.88 % (clear, type 12) above the sky's
//! direct light, which the meter now reads to 10⁻⁹.
//!
//! The rays of point k are seeded by (k, `seed`) alone: the readings do not depend on the
//! thread count, and another seed draws other rays.

use glam::Vec3;
use rayon::prelude::*;

use super::luminaires::{Luminaires, PENUMBRA_REFINE};
use crate::mesh::{display, Mesh};
use crate::render::raytrace::sample::Sampler;
use crate::render::raytrace::world::World;
use crate::sampling::cosine_direction;
use crate::solve::Solution;
use crate::{Rgb, Scene};

/// Side of the stratified grid of gather rays per point (4 096 rays: the indirect part's
/// noise about 1 % of it where the surroundings are uneven, measured in the tests below).
pub const GATHER_SIDE: u32 = 64;

/// Shadow rays per luminaire at each point (an 8 × 8 grid), refined in penumbrae.
const SHADOW_SAMPLES: u32 = 64;

/// The meter of a solved scene: the world its rays are traced in (over the lit mesh of the
/// solution's reflected radiosity B − E) and the emitters of the exact direct light, prepared
/// once for every reading.
pub struct Meter<'a> {
    world: World<'a>,
    luminaires: Luminaires,
}

/// Prepares the meter of the solved `scene` and hands it to `read`.
pub fn with_meter<R>(
    scene: &Scene,
    mesh: &Mesh,
    solution: &Solution,
    read: impl FnOnce(&Meter<'_>) -> R,
) -> R {
    // The reflected radiosity (B − E)⁺ per element, interpolated as one quantity (module docs).
    let reflected: Vec<Rgb> = solution
        .radiosity
        .iter()
        .enumerate()
        .map(|(e, &b)| (b - mesh.element_patch(e).emission).max(Rgb::ZERO))
        .collect();
    let lit = display::lit_mesh(mesh, &reflected);
    let meter = Meter {
        world: World::new(scene, mesh, &lit),
        luminaires: Luminaires::new(mesh, 0),
    };
    read(&meter)
}

impl Meter<'_> {
    /// The irradiance (W·m⁻² per channel) at each of `points` on a small surface facing the
    /// unit normal `normal`; `seed` tells apart the rays of different calls.
    #[must_use]
    pub fn irradiance(&self, points: &[Vec3], normal: Vec3, seed: u64) -> Vec<Rgb> {
        let facing: Vec<(Vec3, Vec3)> = points.iter().map(|&x| (x, normal)).collect();
        self.irradiance_facing(&facing, seed)
    }

    /// The irradiance (W·m⁻² per channel) at each of `points` on a small surface facing its
    /// own unit normal, (point, normal); `seed` as for [`Meter::irradiance`].
    #[must_use]
    pub fn irradiance_facing(&self, points: &[(Vec3, Vec3)], seed: u64) -> Vec<Rgb> {
        points
            .par_iter()
            .enumerate()
            .map(|(k, &(x, normal))| {
                let mut sampler = Sampler::new(k as u32, seed as u32, (seed >> 32) as u32);
                let direct = self.luminaires.irradiance(
                    &self.world,
                    x,
                    normal,
                    (SHADOW_SAMPLES, PENUMBRA_REFINE),
                    &mut sampler,
                );
                direct + gathered(&self.world, x, normal, &mut sampler)
            })
            .collect()
    }
}

/// E_i at `x` facing `n` (module docs).
fn gathered(world: &World, x: Vec3, n: Vec3, sampler: &mut Sampler) -> Rgb {
    let origin = x + n * world.epsilon();
    let mut sum = Rgb::ZERO;
    for j in 0..GATHER_SIDE {
        for i in 0..GATHER_SIDE {
            let u1 = (i as f32 + sampler.next_f32()) / GATHER_SIDE as f32;
            let u2 = (j as f32 + sampler.next_f32()) / GATHER_SIDE as f32;
            let dir = cosine_direction(n, u1, u2);
            let Some(y) = world.intersect(origin, dir, f32::INFINITY) else {
                continue;
            };
            if let Some(d) = y.diffuse {
                // The world's lit mesh carries B − E: its radiance is L_r.
                sum += world.radiance(d);
            }
        }
    }
    sum * (std::f64::consts::PI / f64::from(GATHER_SIDE * GATHER_SIDE))
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use glam::DVec3;

    use super::*;
    use crate::formfactor::analytic::{point_to_parallel_rectangle_corner, point_to_polygon};
    use crate::pipeline::{self, Settings};
    use crate::progress::Silent;
    use crate::scene::environment::{self, CieSky, CieSkyKind, Environment};
    use crate::scene::{Material, Object, Polygon};
    use crate::testing::closed_cube;

    /// A closed unit cube whose ceiling alone emits (radiance 1) and reflects nothing, the
    /// other faces black: at the floor's centre the meter reads only the ceiling's direct
    /// light, π·L·F with F four corner factors of a 0.5 × 0.5 rectangle 1 above, and at a point
    /// in the middle facing a wall it reads the ceiling edge-on: half of the factor of a point
    /// to a perpendicular square it touches the plane of, π·L·F⊥.
    #[test]
    fn direct_light_is_the_closed_form_factor() {
        let scene = closed_cube(0.0, [0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
        let solved = pipeline::solve(scene, &Settings::default(), &Silent).expect("solves");
        let (scene, mesh, solution) = (&solved.scene, &solved.mesh, &solved.solution);
        let floor = Vec3::new(0.5, 1e-3, 0.5);
        let (up, near) = with_meter(scene, mesh, solution, |m| {
            let under = [Vec3::new(0.5, 0.999, 0.5)];
            (
                m.irradiance(&[floor], Vec3::Y, 1)[0],
                m.irradiance(&under, Vec3::Y, 1)[0],
            )
        });
        let exact = PI * 4.0 * point_to_parallel_rectangle_corner(0.5, 0.5, 1.0 - 1e-3);
        assert!((up.y / exact - 1.0).abs() < 1e-3, "{} {exact}", up.y);
        // Facing up from just under the ceiling's centre: the whole hemisphere is the
        // ceiling, E = πL.
        assert!((near.y / PI - 1.0).abs() < 1e-2, "{}", near.y);
    }

    /// In a closed cube of uniform ρ whose every face emits E, every element has
    /// B = E/(1 − ρ) (the energy identity of a closed scene), so every point sees radiance
    /// B/π in every direction and reads E_irr = B at any orientation: the direct part E (the
    /// factors to the six faces sum to 1) plus the gathered part B − E = ρB. It checks the
    /// gather against the solution and the split between the two (a gather that also counted
    /// the emitters' own light would read B + E).
    #[test]
    fn in_a_uniform_closed_cube_every_point_reads_its_radiosity() {
        let (rho, radiance) = (0.5, 1.0);
        let scene = closed_cube(rho, [radiance; 6]);
        let solved = pipeline::solve(scene, &Settings::default(), &Silent).expect("solves");
        let b = PI * radiance / (1.0 - rho);
        let points = [
            Vec3::new(0.5, 0.5, 0.5),
            Vec3::new(0.1, 0.2, 0.9),
            Vec3::new(0.95, 0.05, 0.5),
        ];
        for normal in [Vec3::Y, Vec3::NEG_X, Vec3::new(1.0, 1.0, 1.0).normalize()] {
            let e = with_meter(&solved.scene, &solved.mesh, &solved.solution, |m| {
                m.irradiance(&points, normal, 7)
            });
            for (x, e) in points.iter().zip(e) {
                assert!((e.y / b - 1.0).abs() < 0.01, "{x} {normal}: {} vs {b}", e.y);
            }
        }
    }

    /// A black unit square facing +y at the origin under the sky `sky`.
    fn black_plane_under(sky: &Environment) -> Scene {
        let mut scene = Scene {
            name: "black plane".into(),
            materials: vec![Material {
                reflectance: Rgb::ZERO,
                ..Material::default()
            }],
            objects: vec![Object {
                name: "plane".into(),
            }],
            polygons: vec![Polygon {
                vertices: vec![Vec3::ZERO, Vec3::Z, Vec3::new(1.0, 0.0, 1.0), Vec3::X],
                material: 0,
                object: 0,
                uv: None,
            }],
            ..Scene::default()
        };
        scene.add_environment(sky).expect("a sky");
        scene
    }

    /// Nothing reflects in a black plane under a sky (the sky's faces reflect nothing either),
    /// so the gathered part is exactly 0 and a point on the plane reads the sky's direct light
    /// alone: Σ π L_k F(x → k) over the sky's faces k, Lambert's exact factor to each (the
    /// plane hides none of them from its own points). Tolerance 10⁻⁹: f64 sums of the same
    /// factors. In closed form, a uniform sky of radiance L gives πL (its box is exact), and
    /// the CIE overcast sky 7π L_z / 9, which its tiles meet to 0.22 % (`docs/validation.md`);
    /// the general skies have no closed form. A gather that interpolated B across the tiles and
    /// took away each tile's own E reads 0.93–2.88 % more here (module docs).
    #[test]
    fn under_a_sky_a_black_plane_reads_the_sky_alone() {
        let cie = |kind| {
            Environment::Cie(CieSky {
                kind,
                zenith_luminance: 10_000.0,
                sun_direction: Vec3::new(0.0, 0.5, 0.75f32.sqrt()),
                up: Vec3::Y,
            })
        };
        let uniform = Environment::Constant {
            radiance: Rgb::splat(1_000.0),
        };
        let skies = [
            (uniform, Some((PI * 1_000.0, 1e-6))),
            (
                cie(CieSkyKind::Overcast),
                Some((7.0 * PI * 10_000.0 / 9.0, 3e-3)),
            ),
            (cie(CieSkyKind::Type1), None),
            (cie(CieSkyKind::Type12), None),
        ];
        for (sky, closed) in skies {
            let solved = pipeline::solve(black_plane_under(&sky), &Settings::default(), &Silent)
                .expect("solves");
            let x = Vec3::new(0.5, 0.0, 0.5);
            let faces: f64 = solved
                .scene
                .polygons
                .iter()
                .filter(|p| solved.scene.objects[p.object].name == environment::NAME)
                .map(|p| {
                    let corners: Vec<_> = p.vertices.iter().map(|v| v.as_dvec3()).collect();
                    let l = solved.scene.materials[p.material].emission.y;
                    PI * l * point_to_polygon(x.as_dvec3(), DVec3::Y, &corners)
                })
                .sum();
            let (reading, gathered) =
                with_meter(&solved.scene, &solved.mesh, &solved.solution, |m| {
                    let mut sampler = Sampler::new(0, 0, 0);
                    (
                        m.irradiance(&[x], Vec3::Y, 5)[0].y,
                        gathered(&m.world, x, Vec3::Y, &mut sampler).y,
                    )
                });
            assert_eq!(gathered, 0.0, "{sky:?}: the sky reflects nothing");
            assert!(
                (reading / faces - 1.0).abs() < 1e-9,
                "{sky:?}: {reading} against the faces' {faces} ({:+.3} %)",
                100.0 * (reading / faces - 1.0)
            );
            if let Some((exact, tolerance)) = closed {
                assert!(
                    (reading / exact - 1.0).abs() < tolerance,
                    "{sky:?}: {reading} against {exact}"
                );
            }
        }
    }

    /// The same call gives the same bits, whatever the thread count.
    #[test]
    fn readings_do_not_depend_on_the_thread_count() {
        let scene = closed_cube(0.5, [0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
        let solved = pipeline::solve(scene, &Settings::default(), &Silent).expect("solves");
        let points: Vec<Vec3> = (0..16)
            .map(|k| Vec3::new(0.5, 0.05 * k as f32, 0.3))
            .collect();
        let read = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    with_meter(&solved.scene, &solved.mesh, &solved.solution, |m| {
                        m.irradiance(&points, Vec3::Y, 3)
                    })
                })
        };
        assert_eq!(read(1), read(2));
    }
}
