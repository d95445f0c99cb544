//! What a false-colour picture shows ([`crate::render::false_colour`]): the illuminance or the
//! luminance at the surface seen through each pixel, taken where and as the evaluated picture
//! ([`super`]) takes its light.
//!
//! | quantity | at a point x of a diffuse surface seen along a primary ray |
//! |---|---|
//! | illuminance | E(x) = E_d(x) + k_H N(x) + R_H(x) (1 − S(x)) |
//! | luminance | Y of the picture's radiance L_e + ρ (E_d + k N)/π + R (1 − S)/π, mirrors and glass traced |
//!
//! E_d is the exact direct light of the luminaires, N and S the near field, R_H and k_H the
//! split of the incident indirect light ([`super::far`]): the same terms as the picture's, before
//! the reflectance. So ρ · E(x) is the light the picture reflects at x wherever ρ > 0, and a
//! surface that reflects nothing (ρ = 0) still reads the light that falls on it, where
//! (B − E)/ρ would read 0/0. Every surface is measured as a diffuse one, mirrors and glass
//! included: the illuminance on a mirror is what falls on its surface.
//!
//! The primary rays are those of the picture (the same coverage, [`super::super::raytrace::coverage`]):
//! the costly terms are evaluated once per pixel and surface side, each ray adds its own
//! interpolated far part. A pixel holds the mean over the rays that meet a surface, or no
//! value where they are fewer than half of its weight (the background; for illuminance also
//! the back of a one-sided surface, which has no light of its own, and a sky's far tiles, whose
//! illuminance means nothing: the sky's luminance is the picture's there).

use super::prepare;
use crate::color::luminance;
use crate::mesh::Mesh;
use crate::render::false_colour::{Measurement, Quantity};
use crate::render::raytrace::coverage::render_covered_of;
use crate::render::raytrace::sample::{grid_side, Sampler};
use crate::render::raytrace::world::World;
use crate::render::raytrace::{evaluated_sum, group, probe, Probe, RaytraceSettings};
use crate::render::{Projection, RasterSettings, Watch};
use crate::scene::Camera;
use crate::solve::Solution;
use crate::{Rgb, Scene};

/// A pixel's mean over the part of it that surfaces cover, and that part's share.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Covered {
    mean: Rgb,
    coverage: f64,
}

/// A pixel needs surfaces over at least this share of it to hold a value.
const MIN_COVERAGE: f64 = 0.5;

/// Measures `quantity` at the surface seen through each pixel of `camera`'s `image` of the
/// solved scene (module docs); `settings` as for the evaluated picture. `None` if `watch`
/// stopped it.
#[must_use]
pub fn measure(
    (scene, mesh, solution): (&Scene, &Mesh, &Solution),
    quantity: Quantity,
    camera: &Camera,
    image: &RasterSettings,
    settings: &RaytraceSettings,
    watch: &Watch,
) -> Option<Measurement> {
    let view = Some((camera, image));
    let incident = quantity == Quantity::Lux;
    let (evaluation, _, lit) = prepare(
        scene,
        mesh,
        solution,
        (settings.shadow_samples, incident),
        view,
        watch,
    )?;
    let world = World::new(scene, mesh, &lit);
    let proj = Projection::new(camera, image.width, image.height);
    let shoot = |px: f32, py: f32, sampler: Sampler| probe(&world, &proj, (px, py), sampler);
    let shade = |probes: Vec<(Probe, u32)>, total: u32| {
        let (sum, covered) = match quantity {
            Quantity::Luminance => evaluated_sum(&world, &evaluation, settings, probes),
            Quantity::Lux => {
                // Every surface of the scene; the tiles of a distant sky are its background.
                let (groups, _) = group(&world, probes, |hit| {
                    !mesh.patches[world.patch(hit.triangle) as usize].distant
                });
                let mut sum = Rgb::ZERO;
                let mut covered = 0;
                for mut g in groups {
                    let (at_point, share) = evaluation
                        .irradiance(
                            &world,
                            mesh,
                            g.point(),
                            g.normal(),
                            (g.patch, g.rays[0].0),
                            settings.shadow_samples,
                            &mut g.sampler,
                        )
                        .expect("prepared with the incident split");
                    covered += g.weight;
                    for (d, _, w) in g.rays {
                        let far = evaluation.incident_far(&world, d);
                        sum += (at_point + far * (1.0 - share)).max(Rgb::ZERO) * f64::from(w);
                    }
                }
                (sum, covered)
            }
        };
        Covered {
            mean: if covered > 0 {
                sum / f64::from(covered)
            } else {
                Rgb::ZERO
            },
            coverage: f64::from(covered) / f64::from(total),
        }
    };
    let pixels = render_covered_of(
        (image.width, image.height),
        grid_side(image.samples_per_pixel),
        settings.jitter,
        watch,
        shoot,
        shade,
    )?;
    Some(Measurement {
        quantity,
        width: image.width,
        height: image.height,
        values: pixels
            .into_iter()
            .map(|p| (p.coverage >= MIN_COVERAGE).then(|| luminance(p.mean)))
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;
    use std::path::Path;

    use glam::Vec3;

    use super::*;
    use crate::formfactor::analytic::point_to_parallel_rectangle_corner;
    use crate::pipeline::{self, Settings, Solved};
    use crate::progress::Silent;
    use crate::render::evaluated::meter::with_meter;
    use crate::render::evaluated::render;
    use crate::testing::closed_cube;

    /// A 4 × 4 floor of reflectance `rho` and a 0.5 × 0.5 lamp of radiance 100 (white, ρ 0)
    /// facing it from 1 above its centre.
    fn under_a_lamp(rho: f64) -> Solved {
        let text = format!(
            r#"
[materials.floor]
reflectance = {rho}
[materials.lamp]
emission = 100.0
[[objects]]
name = "floor"
material = "floor"
shape = "polygon"
vertices = [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]
[[objects]]
name = "lamp"
material = "lamp"
shape = "polygon"
vertices = [[-0.25, 1, -0.25], [0.25, 1, -0.25], [0.25, 1, 0.25], [-0.25, 1, 0.25]]
"#
        );
        let scene = Scene::from_toml_str(&text, Path::new("lamp.toml")).expect("loads");
        pipeline::solve(scene, &Settings::default(), &Silent).expect("solves")
    }

    /// A 2 × 2 × 2 room, walls and ceiling of reflectance 0.6, the floor `rho`, a 0.5 × 0.5
    /// lamp of radiance 20 just under the ceiling's centre.
    fn room(rho: f64) -> Solved {
        let quad = |name: &str, material: &str, v: &str| {
            format!(
                "[[objects]]\nname = \"{name}\"\nmaterial = \"{material}\"\nshape = \"polygon\"\n\
                 vertices = {v}\n"
            )
        };
        let mut text = format!(
            "[materials.floor]\nreflectance = {rho}\n[materials.paint]\nreflectance = 0.6\n\
             [materials.lamp]\nemission = 20.0\n"
        );
        for (name, material, v) in [
            ("floor", "floor", "[[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]]"),
            ("ceiling", "paint", "[[-1, 2, -1], [1, 2, -1], [1, 2, 1], [-1, 2, 1]]"),
            ("west", "paint", "[[-1, 0, -1], [-1, 2, -1], [-1, 2, 1], [-1, 0, 1]]"),
            ("east", "paint", "[[1, 0, -1], [1, 0, 1], [1, 2, 1], [1, 2, -1]]"),
            ("north", "paint", "[[-1, 0, -1], [1, 0, -1], [1, 2, -1], [-1, 2, -1]]"),
            ("south", "paint", "[[-1, 0, 1], [-1, 2, 1], [1, 2, 1], [1, 0, 1]]"),
            (
                "lamp",
                "lamp",
                "[[-0.25, 1.99, -0.25], [0.25, 1.99, -0.25], [0.25, 1.99, 0.25], [-0.25, 1.99, 0.25]]",
            ),
        ] {
            text += &quad(name, material, v);
        }
        let scene = Scene::from_toml_str(&text, Path::new("room.toml")).expect("loads");
        pipeline::solve(scene, &Settings::default(), &Silent).expect("solves")
    }

    fn camera(eye: Vec3, target: Vec3, fov_y: f32) -> Camera {
        Camera {
            name: "test".into(),
            eye,
            target,
            up: Vec3::Y,
            fov_y,
        }
    }

    fn raster(side: u32) -> RasterSettings {
        RasterSettings {
            width: side,
            height: side,
            samples_per_pixel: 16,
        }
    }

    fn measure_in(solved: &Solved, quantity: Quantity, camera: &Camera, side: u32) -> Measurement {
        let parts = (&solved.scene, &solved.mesh, &solved.solution);
        let settings = RaytraceSettings::default();
        measure(
            parts,
            quantity,
            camera,
            &raster(side),
            &settings,
            &Watch::SILENT,
        )
        .expect("not stopped")
    }

    /// The centre pixel looks at the floor's centre under the lamp, which sends it
    /// E = π L F, F the factor of the point to the square above it (four corner rectangles
    /// 0.25 × 0.25 at height 1); the floor sees nothing that reflects, so that is all. It
    /// reads so whatever the floor reflects, black included: with ρ = 0 the picture shows
    /// nothing of it, (B − E)/ρ is 0/0. The direct light is exact and taken once, at the mean
    /// of the pixel's rays on the floor, the centre itself (measured: 6 · 10⁻⁸ off, the f32
    /// points' rounding).
    #[test]
    fn the_illuminance_under_a_lamp_is_the_closed_form_whatever_the_floor_reflects() {
        let exact = PI * 100.0 * 4.0 * point_to_parallel_rectangle_corner(0.25, 0.25, 1.0);
        let view = camera(Vec3::new(0.0, 0.6, 1.2), Vec3::ZERO, 10.0);
        for rho in [0.0, 0.5] {
            let solved = under_a_lamp(rho);
            let m = measure_in(&solved, Quantity::Lux, &view, 33);
            let centre = m.get(16, 16).expect("the floor");
            assert!(
                (centre / exact - 1.0).abs() < 1e-5,
                "ρ {rho}: {centre} lx against {exact}"
            );
            assert!(m.seen().all(|e| e > 0.0 && e <= exact * 1.001));
        }
    }

    /// In a closed cube of uniform ρ whose every face emits, every point receives E_irr = B
    /// at any orientation (see the meter's test of the same case): every pixel of the
    /// picture's surfaces reads B, through the direct light (E, the six faces' factors summing
    /// to 1) and the near and far parts of the indirect light (ρB). Measured: 0.02 % at worst,
    /// the solution's residual and the near field's factors; asserted within 0.2 %.
    #[test]
    fn in_a_uniform_closed_cube_every_pixel_reads_the_radiosity() {
        let (rho, radiance) = (0.5, 1.0);
        let solved = pipeline::solve(
            closed_cube(rho, [radiance; 6]),
            &Settings::default(),
            &Silent,
        )
        .expect("solves");
        let b = PI * radiance / (1.0 - rho);
        let view = camera(Vec3::new(0.5, 0.6, 0.9), Vec3::new(0.3, 0.2, 0.05), 70.0);
        let m = measure_in(&solved, Quantity::Lux, &view, 24);
        assert_eq!(m.seen().count(), 24 * 24, "every pixel sees a face");
        let worst = m.seen().map(|e| (e / b - 1.0).abs()).fold(0.0, f64::max);
        assert!(worst < 2e-3, "worst pixel {:.3} % off B", worst * 100.0);
    }

    /// Where ρ > 0, ρ times the illuminance at a pixel of the floor is the light the picture
    /// reflects there, π times its luminance: the two are taken by the same terms (the floor
    /// does not emit; measured equal to the last bit). With the floor black, its illuminance
    /// agrees with the irradiance meter of the grids at the point seen (4 096 gathered rays:
    /// about 1 % noise on the indirect part, a third of the light here; measured 0.03 %).
    #[test]
    fn the_illuminance_is_the_light_the_picture_reflects_and_the_meter_reads() {
        let view = camera(Vec3::new(0.0, 1.2, 0.9), Vec3::ZERO, 30.0);
        let grey = room(0.5);
        let m = measure_in(&grey, Quantity::Lux, &view, 31);
        let image = render(
            &grey.scene,
            &grey.mesh,
            &grey.solution,
            &view,
            &raster(31),
            &RaytraceSettings::default(),
            &Watch::SILENT,
        )
        .expect("not stopped");
        for (x, y) in [(15, 15), (10, 20), (20, 12)] {
            let lux = m.get(x, y).expect("the floor");
            let reflected = PI * luminance(image.get(x, y));
            assert!(
                (0.5 * lux / reflected - 1.0).abs() < 1e-6,
                "({x}, {y}): ρE = {} against πL = {reflected}",
                0.5 * lux
            );
        }
        let black = room(0.0);
        let m = measure_in(&black, Quantity::Lux, &view, 31);
        let lux = m.get(15, 15).expect("the floor");
        let read = with_meter(&black.scene, &black.mesh, &black.solution, |meter| {
            meter.irradiance(&[Vec3::new(0.0, 1e-3, 0.0)], Vec3::Y, 0)[0]
        });
        let read = luminance(read);
        assert!(
            (lux / read - 1.0).abs() < 0.01,
            "black floor: {lux} lx evaluated, {read} lx metered"
        );
    }

    /// Under a CIE sky, the pixels that see the sky's far tiles above the horizon have no
    /// illuminance (it would be the tiles' own, meaningless) but the sky's luminance; the
    /// ground open to the sky reads its illuminance E_h = 7π L_z / 9 within the tiles' 1 %.
    #[test]
    fn the_sky_has_a_luminance_and_no_illuminance() {
        let text = r#"
[sky]
type = "cie-overcast"
zenith_luminance = 1000.0
[materials.ground]
reflectance = 0.2
[[objects]]
name = "ground"
material = "ground"
shape = "polygon"
vertices = [[-20, 0, -20], [-20, 0, 20], [20, 0, 20], [20, 0, -20]]
"#;
        let scene = Scene::from_toml_str(text, Path::new("sky.toml")).expect("loads");
        let solved = pipeline::solve(scene, &Settings::default(), &Silent).expect("solves");
        let view = camera(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 1.0, -5.0), 60.0);
        let lux = measure_in(&solved, Quantity::Lux, &view, 16);
        let luminance = measure_in(&solved, Quantity::Luminance, &view, 16);
        // Row 2 looks above the horizon, row 13 at the ground.
        assert_eq!(lux.get(8, 2), None, "the sky");
        assert!(luminance.get(8, 2).is_some_and(|l| l > 0.0));
        let ground = lux.get(8, 13).expect("the ground");
        let exact = 7.0 * PI * 1000.0 / 9.0;
        assert!(
            (ground / exact - 1.0).abs() < 0.01,
            "{ground} lx against {exact}"
        );
    }

    /// Luminance is the picture's own: at a pixel that one surface covers, exactly the
    /// luminance of the picture's pixel; the background has no value.
    #[test]
    fn the_luminance_is_the_pictures() {
        let solved = under_a_lamp(0.5);
        let view = camera(Vec3::new(0.0, 0.6, 1.2), Vec3::new(0.0, 0.3, 0.0), 60.0);
        let m = measure_in(&solved, Quantity::Luminance, &view, 32);
        let image = render(
            &solved.scene,
            &solved.mesh,
            &solved.solution,
            &view,
            &raster(32),
            &RaytraceSettings::default(),
            &Watch::SILENT,
        )
        .expect("not stopped");
        assert_eq!(m.get(16, 0), None, "above the floor's far edge: nothing");
        for (x, y) in [(16, 28), (5, 30), (25, 25)] {
            assert_eq!(m.get(x, y), Some(luminance(image.get(x, y))), "({x}, {y})");
        }
    }
}
