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
//! mean), F(x → s) Lambert's exact factor to the node times the visibility of its centroid
//! (one shadow ray: a thin wall, such as a lamp housing lit inside, hides what lies behind it;
//! the point's own polygon, its back twin included, sends nothing; beyond two of the node's
//! diameters the point kernel A cosθ cosθ' / (π r²), `near_factor` in `near_field/mod.rs`;
//! nodes far from the point beside their size summed in clusters, `near_field/clusters.rs`),
//! w a weight falling from 1 to 0 between half and the whole of the reach
//! (`NEAR_REACH` diameters of the largest element of the point's surface: one reach for all
//! the patches whose lit-mesh vertices R is interpolated over, or a slightly non-planar quad,
//! two patches, steps along its diagonal), and N̄, S̄ the means over the element's pieces, so
//! that the element's mean is kept. The near surfaces hide the far ones: into a corner S(x)
//! grows and the far part shrinks (a first version that added the near part to an
//! interpolated far part made the corners brighter still).
//!
//! Next to the point, an element's mean B_s is still too coarse: the floor within a few
//! centimetres of a block is darker than the mean of its element, and the bottom of the block's
//! face, which sees mostly that strip, came out 20–30 % too bright. So each element is cut into
//! four *pieces* (one quadtree step), the evaluation above is taken once at each piece's
//! centroid before the picture, and a point within `OPEN_WITHIN` diameters of an element
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
//! R is interpolated over the lit mesh with its border vertices extrapolated, not averaged
//! ([`display::lit_mesh_faceted`]): R falls towards an open edge (the front of the Cornell
//! box) and into creases, and the averaged border vertices showed the border strips 4–14 %
//! too bright (Cornell box 1.41 → 0.98 % at 256², docs/raytracing.md). Its values are shared
//! only within a plane, not across the smoothing angle of the exported lit mesh: each facet of
//! a tessellated surface gathers its own indirect light, and smoothed over its neighbours the
//! shaded half of the closed-mesh scene's blob came out as one smooth gradient where Mitsuba 3
//! shows its facets (the blob's blocks 12 → 0.5 %).
//!
//! A floor element wholly or partly under a block (the blocks have no bottom face) has a
//! whole-area mean darkened by its buried part, and averaged in by its area it drew a dark
//! line along every contact of a block with the floor (the short block's side face against the
//! floor, 10–25 % too dark in the pixels on the line at 256²). So each vertex of R's lit mesh is
//! the mean of its elements weighted by their *open* areas (the open fraction u of
//! [`crate::formfactor::exposure`]), and an element's indirect light B_i is taken over its open
//! part, B_i / max(u, [`MIN_OPEN`]), as the buried part has none. The Cornell box at 256²
//! against Mitsuba 3, weights alone / and the division: hierarchical radiosity 1.195 → 0.940 /
//! 0.75 %, Gauss-Seidel 0.711 → 0.701 / 0.72 % (with the adaptive edge coverage 0.66 / 0.68 %:
//! the bottom of the short block's front face, already a few per cent too bright, grows brighter
//! as the floor in front of it does), the furnished room 0.36 → 0.36 / 0.35 %.
//!
//! The solve stays viewer-independent; only the picture is evaluated per point. Mirrors and
//! glass are traced as by [`super::raytrace::render`].

mod far;
mod luminaires;
pub mod measured;
pub mod meter;
mod near_field;
mod wanted;

use glam::Vec3;
use rayon::prelude::*;

use self::far::{far_radiosity, Far, Lighting};
use self::luminaires::{Luminaires, DISTANT_SIDE, PENUMBRA_REFINE, PIECE_PENUMBRA_REFINE};
use self::near_field::{NearField, PIECES};
use super::raytrace::sample::Sampler;
use super::raytrace::world::World;
use super::raytrace::{trace_image, PointEvaluation, RaytraceSettings};
use super::Watch;
use crate::accel::Bvh;
use crate::formfactor::exposure;
use crate::mesh::{display, LitMesh, Mesh};
use crate::progress::Work;
use crate::render::{Image, RasterSettings};
use crate::scene::Camera;
use crate::solve::Solution;
use crate::{Rgb, Scene};

/// Elements settled per report to the progress.
const SETTLED_BATCH: u64 = 256;

/// The far part's radiosity is divided by the share of the view left to it; never by less.
const MIN_FAR_SHARE: f64 = 0.05;

/// The indirect light of an element less open than this (a floor element all but buried under
/// a block) is divided by this, not by its open fraction: the open fraction is taken on a 4 × 4
/// grid of points and the solution's whole-area mean on the solver's own, so over a small open
/// share their ratio is mostly the two grids' disagreement.
const MIN_OPEN: f64 = 0.25;

/// What the evaluated render adds at a diffuse point: the exact direct light and the near part
/// of the indirect light.
#[derive(Debug)]
pub(super) struct Evaluation {
    luminaires: Luminaires,
    near: NearField,
    /// k of each element ([`far_radiosity`]), per vertex of the lit mesh as its radiosity is.
    scale: Vec<Rgb>,
    /// The split of the incident light, when [`prepare`] was asked for it.
    incident: Option<Incident>,
}

/// The split of each element's incident indirect light ([`far`]), per vertex of the lit mesh:
/// what evaluating the illuminance at points needs beside the near field.
#[derive(Debug)]
pub(super) struct Incident {
    /// R_H, interpolated as the far part's radiosity is (over the open parts of the elements).
    far: Vec<Rgb>,
    /// k_H.
    scale: Vec<Rgb>,
}

impl PointEvaluation for Evaluation {
    /// ρ · (E_d + k N) at a point of `patch` (at barycentrics `at` of a triangle of the far
    /// part's lit mesh, where k is interpolated), and the share of its view that the near
    /// field takes from the far part.
    fn radiosity(
        &self,
        world: &World,
        mesh: &Mesh,
        point: Vec3,
        normal: Vec3,
        (patch, at): (u32, (u32, f32, f32)),
        samples: u32,
        sampler: &mut Sampler,
    ) -> (Rgb, f64) {
        let rho = mesh.patches[patch as usize].reflectance;
        let (light, share) = self.light(
            world,
            mesh,
            point,
            normal,
            (patch, at),
            &self.scale,
            samples,
            sampler,
        );
        (rho * light, share)
    }
}

impl Evaluation {
    /// The illuminance the evaluated picture takes at a point of `patch` (at barycentrics `at`
    /// of a triangle of the lit mesh) facing `normal`, by the same terms as
    /// [`PointEvaluation::radiosity`] before the reflectance: E_d + k_H N, and the share of the
    /// point's view that the near field takes from the interpolated far part R_H
    /// ([`Evaluation::incident_far`]). `None` unless [`prepare`] was asked for the incident
    /// split.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn irradiance(
        &self,
        world: &World,
        mesh: &Mesh,
        point: Vec3,
        normal: Vec3,
        (patch, at): (u32, (u32, f32, f32)),
        samples: u32,
        sampler: &mut Sampler,
    ) -> Option<(Rgb, f64)> {
        let incident = self.incident.as_ref()?;
        Some(self.light(
            world,
            mesh,
            point,
            normal,
            (patch, at),
            &incident.scale,
            samples,
            sampler,
        ))
    }

    /// E_d + k N at a point of `patch` (at barycentrics `at`), k interpolated from `scale`
    /// per lit-mesh vertex, and the near field's share of the view: the terms both the
    /// picture's radiosity and its illuminance are made of.
    #[allow(clippy::too_many_arguments)]
    fn light(
        &self,
        world: &World,
        mesh: &Mesh,
        point: Vec3,
        normal: Vec3,
        (patch, at): (u32, (u32, f32, f32)),
        scale: &[Rgb],
        samples: u32,
        sampler: &mut Sampler,
    ) -> (Rgb, f64) {
        let direct =
            self.luminaires
                .irradiance(world, point, normal, (samples, PENUMBRA_REFINE), sampler);
        let (near, share, _) = self.near.irradiance(mesh, point, normal, patch);
        (direct + world.interpolated(scale, at) * near, share)
    }

    /// B at `point` of lit triangle `t` (barycentrics `at`) of the far part's lit mesh that
    /// `world` holds, as the picture shows it: E + ρ (E_d + k N) + R (1 − S), with `samples`
    /// shadow rays per luminaire. The sampler is seeded by the point, so the same point gets
    /// the same value whoever asks.
    pub(crate) fn radiosity_at(
        &self,
        world: &World,
        mesh: &Mesh,
        point: Vec3,
        (t, at): (u32, [f32; 2]),
        samples: u32,
    ) -> Rgb {
        let patch = world.patch(t);
        let normal = world.shading_normal(t, at[0], at[1]);
        let bits = |x: f32| x.to_bits();
        let seed = bits(point.x) ^ bits(point.y).rotate_left(11) ^ bits(point.z).rotate_left(22);
        let mut sampler = Sampler::new(seed, 0x0d15_91a7, 0);
        let (at_point, share) = self.radiosity(
            world,
            mesh,
            point,
            normal,
            (patch, (t, at[0], at[1])),
            samples,
            &mut sampler,
        );
        let far = world.radiance((t, at[0], at[1])) * std::f64::consts::PI;
        let emission = mesh.patches[patch as usize].emission;
        (emission + at_point + far * (1.0 - share)).max(Rgb::ZERO)
    }

    /// R_H, the far part of the incident light, interpolated at `at`; zero unless [`prepare`]
    /// was asked for the incident split.
    pub(super) fn incident_far(&self, world: &World, at: (u32, f32, f32)) -> Rgb {
        self.incident
            .as_ref()
            .map_or(Rgb::ZERO, |i| world.interpolated(&i.far, at))
    }
}

impl Evaluation {
    /// The far part R of every element's indirect light and B − E at its pieces (see
    /// [`far_radiosity`]), the pieces then shown to the near field; with the solution's
    /// irradiance in `lighting`, the incident split too (kept in `self`). Reported to `watch`
    /// as the stage "evaluation": the wanted elements, twice (the two passes); `None` if
    /// stopped.
    #[allow(clippy::too_many_arguments)]
    fn settle(
        &mut self,
        world: &World,
        mesh: &Mesh,
        lighting: Lighting<'_>,
        open: &[f64],
        samples: u32,
        wanted: Option<&[bool]>,
        watch: &Watch,
    ) -> Option<Vec<Rgb>> {
        let count = wanted.map_or(mesh.element_count(), |w| w.iter().filter(|&&w| w).count());
        watch
            .progress
            .start("evaluation", Work::of(2 * count as u64, "elements"));
        let direct: Vec<[Rgb; PIECES]> = (0..mesh.element_count())
            .into_par_iter()
            .map(|e| {
                if wanted.is_some_and(|w| !w[e]) {
                    return [Rgb::ZERO; PIECES];
                }
                let node = mesh.element(e);
                let patch = &mesh.patches[node.patch as usize];
                let mut sampler = Sampler::new(e as u32, u32::MAX, 0);
                self.near.pieces[e].centroids.map(|x| {
                    self.luminaires.irradiance(
                        world,
                        x,
                        patch.normal,
                        (samples, PIECE_PENUMBRA_REFINE),
                        &mut sampler,
                    )
                })
            })
            .collect();
        let first = far_radiosity(
            mesh,
            lighting,
            open,
            (&self.near, &direct),
            (None, wanted),
            watch,
        );
        if watch.stopped() {
            watch.progress.cut_short();
            return None;
        }
        self.near.values = first.iter().map(|f| f.pieces).collect();
        let first: Vec<Option<Far>> = first.iter().map(|f| (!f.by_pieces).then_some(*f)).collect();
        let split = far_radiosity(
            mesh,
            lighting,
            open,
            (&self.near, &direct),
            (Some(&first), wanted),
            watch,
        );
        if watch.stopped() {
            watch.progress.cut_short();
            return None;
        }
        watch.progress.tally(count as u64, "elements");
        watch.progress.finish();
        let scale: Vec<Rgb> = split.iter().map(|f| f.scale).collect();
        self.scale = display::lit_mesh_faceted(mesh, &scale, None).radiosity;
        let incident: Option<Vec<_>> = split.iter().map(|f| f.incident).collect();
        self.incident = incident.map(|incident| {
            let far: Vec<Rgb> = incident.iter().map(|i| i.far).collect();
            let scale: Vec<Rgb> = incident.iter().map(|i| i.scale).collect();
            Incident {
                far: display::lit_mesh_faceted(mesh, &far, Some(open)).radiosity,
                scale: display::lit_mesh_faceted(mesh, &scale, None).radiosity,
            }
        });
        Some(split.iter().map(|f| f.far).collect())
    }
}

/// Renders `mesh` (built from `scene`, solved to `solution`) with the direct light evaluated
/// at each visible point and the indirect light from the solution (see the module docs).
/// `None` if `watch` stopped it.
#[must_use]
pub fn render(
    scene: &Scene,
    mesh: &Mesh,
    solution: &Solution,
    camera: &Camera,
    image: &RasterSettings,
    settings: &RaytraceSettings,
    watch: &Watch,
) -> Option<Image> {
    let view = Some((camera, image));
    let (evaluation, _, lit) = prepare(
        scene,
        mesh,
        solution,
        (settings.shadow_samples, false),
        view,
        watch,
    )?;
    let world = World::new(scene, mesh, &lit);
    trace_image(&world, Some(&evaluation), camera, image, settings, watch)
}

/// What evaluating `radiosity` at points needs: the exact direct light (`samples` shadow
/// rays per luminaire at the pieces) and the near field settled on the pieces, the solution's
/// lit mesh (averaged), and the lit mesh of the far part R with its border vertices
/// extrapolated. The two lit meshes have the same triangles. With `incident`, the split of the
/// incident light too, for [`Evaluation::irradiance`]. With a `view` (camera and image), only
/// the elements its picture can read are settled ([`wanted`]); without one (the exported
/// mesh), all. Reported to `watch` as the stage "evaluation", in elements settled; `None` if
/// its stop flag was set.
pub(super) fn prepare(
    scene: &Scene,
    mesh: &Mesh,
    solution: &Solution,
    (samples, incident): (u32, bool),
    view: Option<(&Camera, &RasterSettings)>,
    watch: &Watch,
) -> Option<(Evaluation, LitMesh, LitMesh)> {
    let radiosity = &solution.radiosity;
    let mut evaluation = Evaluation {
        luminaires: Luminaires::new(mesh, DISTANT_SIDE),
        near: NearField::new(mesh, radiosity),
        scale: Vec::new(),
        incident: None,
    };
    // The geometry of the lit mesh does not depend on the values it carries: a world over the
    // solution's lit mesh finds each element's direct light, one over the far part shades.
    let full = display::lit_mesh(mesh, radiosity);
    let world = World::new(scene, mesh, &full);
    let reflected = solution.reflected_irradiance.as_deref();
    let open = exposure::open_fraction(mesh, &Bvh::build(&mesh.triangles), &mesh.elements);
    // The cheap split of an unwanted element needs the solution's reflected light.
    let wanted = view
        .filter(|_| reflected.is_some())
        .and_then(|view| wanted::wanted(scene, &world, mesh, &evaluation.near, view));
    let lighting = Lighting {
        radiosity,
        reflected,
        irradiance: incident.then_some(solution.irradiance.as_slice()),
    };
    let far = evaluation.settle(
        &world,
        mesh,
        lighting,
        &open,
        samples,
        wanted.as_deref(),
        watch,
    )?;
    let lit = display::lit_mesh_faceted(mesh, &far, Some(&open));
    Some((evaluation, full, lit))
}

#[cfg(test)]
pub(super) mod tests {
    use std::path::Path;

    use super::*;
    use crate::mesh::Subdivision;

    /// A 0.2 × 0.2 light at y = 2 facing down, a 0.6 × 0.6 blocker at y = 1, a floor at y = 0.
    pub(in crate::render) const SHADOW: &str = r#"
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

    /// A 0.6 × 0.8 light at y = 2 over a trapezoid floor whose corner (-1, 0, 1) is lifted by
    /// 1 cm (about 0.1 % of its size off its plane: one polygon, cut into two triangles of
    /// areas 1.2 and 2), and a wall along its edge x = -1.
    const FOLDED_FLOOR: &str = r#"
[materials.grey]
reflectance = 0.6
[materials.light]
reflectance = 0.0
emission = 5.0
[[objects]]
name = "floor"
material = "grey"
shape = "polygon"
vertices = [[-1, 0, -1], [-1, 0.01, 1], [0.2, 0, 1], [1, 0, -1]]
[[objects]]
name = "wall"
material = "grey"
shape = "polygon"
vertices = [[-1, 0, -1], [-1, 1, -1], [-1, 1, 1], [-1, 0, 1]]
[[objects]]
name = "light"
material = "light"
shape = "polygon"
vertices = [[-0.3, 2, -0.4], [0.3, 2, -0.4], [0.3, 2, 0.4], [-0.3, 2, 0.4]]
"#;

    #[test]
    fn a_slightly_folded_quad_shows_no_step_at_its_diagonal() {
        // The floor's two triangles are patches of their own, meshed apart (the larger one
        // with larger elements); its light is smooth across the diagonal (the fold turns the
        // lifted triangle by 0.56°, which changes its cosine to the light, 11° off the
        // vertical, by under 0.2 %). Seen from just above, points 1 mm either side of the
        // diagonal's midpoint must agree: the near field's reach was the largest element's of
        // each triangle, and the two triangles split the indirect light between the near and
        // the far part differently (a step of 10–25 % in the evaluated picture of the blocks
        // in benches/corpus/probes/nonplanar-quads).
        let scene = Scene::from_toml_str(FOLDED_FLOOR, Path::new("folded.toml")).expect("loads");
        let settings = crate::pipeline::Settings {
            subdivision: Subdivision::MaxArea(0.1),
            method: Some(crate::solve::Method::GaussSeidel),
            ..crate::pipeline::Settings::default()
        };
        let solved =
            crate::pipeline::solve(scene, &settings, &crate::progress::Silent).expect("solves");
        let (scene, mesh) = (&solved.scene, &solved.mesh);
        let floor = mesh.patches.iter().filter(|p| p.object == 0).count();
        assert_eq!(floor, 2, "the folded floor is two patches");
        let (evaluation, _, lit) = prepare(
            scene,
            mesh,
            &solved.solution,
            (16, false),
            None,
            &Watch::SILENT,
        )
        .unwrap();
        let world = World::new(scene, mesh, &lit);
        let radiance = |x: f32, z: f32| {
            let eye = Vec3::new(x, 0.5, z);
            let hit = world
                .intersect(eye, Vec3::NEG_Y, 1.0)
                .expect("hits the floor");
            let at = hit.diffuse.expect("the floor's front");
            let mut sampler = Sampler::new(0, 0, 0);
            let (at_point, share) = evaluation.radiosity(
                &world,
                mesh,
                hit.point,
                hit.normal,
                (world.patch(at.0), at),
                16,
                &mut sampler,
            );
            (
                world.patch(at.0),
                super::super::raytrace::evaluated_radiance(
                    Rgb::ZERO,
                    at_point,
                    world.radiance(at),
                    share,
                ),
            )
        };
        // The diagonal runs from (x, z) = (-1, -1) to (0.2, 1); its midpoint is (-0.4, 0), and
        // (0.857, -0.514) the unit vector across it.
        let (a, left) = radiance(-0.4 - 0.857e-3, 0.514e-3);
        let (b, right) = radiance(-0.4 + 0.857e-3, -0.514e-3);
        assert_ne!(a, b, "the two points lie on the two triangles");
        // Across the fold the light changes by under 0.2 % (0.006 % measured); the two
        // reaches of the triangles (largest elements 0.58 and 0.29 across) made it 2.3 %.
        let step = (left.x / right.x - 1.0).abs();
        assert!(
            step < 0.005,
            "step {:.2} % ({left:?} | {right:?})",
            step * 100.0
        );
    }

    /// The SHADOW scene beside a second floor 20 units away that the camera does not see: the
    /// picture settles only the elements it can read, and is bit for bit the picture that
    /// settles them all.
    #[test]
    fn a_picture_settles_only_what_it_reads_and_is_the_same_for_it() {
        let far_floor = r#"
[[objects]]
name = "far floor"
material = "floor"
shape = "polygon"
vertices = [[19, 0, 1], [21, 0, 1], [21, 0, -1], [19, 0, -1]]
"#;
        let text = format!("{SHADOW}{far_floor}");
        let scene = Scene::from_toml_str(&text, Path::new("two.toml")).expect("loads");
        let settings = crate::pipeline::Settings {
            method: Some(crate::solve::Method::Hierarchical),
            ..crate::pipeline::Settings::default()
        };
        let solved =
            crate::pipeline::solve(scene, &settings, &crate::progress::Silent).expect("solves");
        let (scene, mesh, solution) = (&solved.scene, &solved.mesh, &solved.solution);
        let camera = Camera {
            name: "near".to_owned(),
            eye: Vec3::new(0.0, 1.5, 2.5),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y: 40.0,
        };
        let image = RasterSettings {
            width: 40,
            height: 30,
            samples_per_pixel: 4,
        };
        let raytrace = RaytraceSettings::default();
        let (evaluation, full, lit) =
            prepare(scene, mesh, solution, (16, false), None, &Watch::SILENT).unwrap();
        let world = World::new(scene, mesh, &full);
        let wanted = wanted::wanted(scene, &world, mesh, &evaluation.near, (&camera, &image))
            .expect("no mirrors");
        let object = |e: usize| mesh.patches[mesh.element(e).patch as usize].object;
        let far_floor: Vec<usize> = (0..mesh.element_count())
            .filter(|&e| object(e) == 3)
            .collect();
        assert!(!far_floor.is_empty() && far_floor.iter().all(|&e| !wanted[e]));
        assert!((0..mesh.element_count()).any(|e| object(e) == 0 && wanted[e]));
        let all = trace_image(
            &World::new(scene, mesh, &lit),
            Some(&evaluation),
            &camera,
            &image,
            &raytrace,
            &Watch::SILENT,
        )
        .expect("not stopped");
        let some = render(
            scene,
            mesh,
            solution,
            &camera,
            &image,
            &raytrace,
            &Watch::SILENT,
        )
        .expect("not stopped");
        assert!(all.pixels.iter().any(|p| p.max_element() > 0.0));
        assert_eq!(all.pixels, some.pixels);
    }

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
            luminaires: Luminaires::new(&mesh, DISTANT_SIDE),
            near: NearField::new(&mesh, &radiosity),
            scale: Vec::new(),
            incident: None,
        };
        let open = vec![1.0; mesh.element_count()];
        let far = evaluation
            .settle(
                &world,
                &mesh,
                Lighting {
                    radiosity: &radiosity,
                    reflected: None,
                    irradiance: None,
                },
                &open,
                16,
                None,
                &Watch::SILENT,
            )
            .unwrap();
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
            // Under the plate the near field counts the plate's light as seen from every
            // point; where that exceeds the element's indirect light the near part is scaled
            // down rather than the far part made negative.
            assert!(
                far[e].is_finite() && far[e].min_element() >= 0.0,
                "element {e}: far part {:?}",
                far[e]
            );
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
}
