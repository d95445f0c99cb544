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
//! The rays of point k are seeded by (k, `seed`) alone: the readings do not depend on the
//! thread count.

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

/// The meter of a solved scene: the world its rays are traced in (over the solution's lit
/// mesh) and the emitters of the exact direct light, prepared once for every reading.
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
    let lit = display::lit_mesh(mesh, &solution.radiosity);
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
    pub fn irradiance(&self, points: &[Vec3], normal: Vec3, seed: u32) -> Vec<Rgb> {
        let facing: Vec<(Vec3, Vec3)> = points.iter().map(|&x| (x, normal)).collect();
        self.irradiance_facing(&facing, seed)
    }

    /// The irradiance (W·m⁻² per channel) at each of `points` on a small surface facing its
    /// own unit normal, (point, normal); `seed` as for [`Meter::irradiance`].
    #[must_use]
    pub fn irradiance_facing(&self, points: &[(Vec3, Vec3)], seed: u32) -> Vec<Rgb> {
        points
            .par_iter()
            .enumerate()
            .map(|(k, &(x, normal))| {
                let mut sampler = Sampler::new(k as u32, seed, 0);
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
                sum += (world.radiance(d) - world.emitted(&y)).max(Rgb::ZERO);
            }
        }
    }
    sum * (std::f64::consts::PI / f64::from(GATHER_SIDE * GATHER_SIDE))
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::formfactor::analytic::point_to_parallel_rectangle_corner;
    use crate::pipeline::{self, Settings};
    use crate::progress::Silent;
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
