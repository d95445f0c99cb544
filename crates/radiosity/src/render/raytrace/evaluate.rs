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
//!   of shadow rays (n² = [`RaytraceSettings::shadow_samples`]): 1 in the open, 0 in umbrae,
//!   sampled only in penumbrae.
//! - B_i: the indirect radiosity of each element, the solution less its emission and its own
//!   direct light Ē_d(e) (the same estimator at a 4 × 4 grid of the element's points),
//!   interpolated over the lit mesh. It is smooth, so the interpolation shows no mesh.
//!
//! The solve stays viewer-independent; only the picture is evaluated per point. Mirrors and
//! glass are traced as by [`super::render`].

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::sample::Sampler;
use super::world::World;
use super::{render_primary, RaytraceSettings, Tracer, Watch};
use crate::formfactor::analytic::point_to_polygon;
use crate::mesh::{display, Face, Mesh};
use crate::render::{Image, RasterSettings};
use crate::scene::Camera;
use crate::{Rgb, Scene};

/// Side of the grid of points at which an element's own direct light is averaged.
const ELEMENT_GRID: u32 = 4;

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
    pub(super) fn irradiance(
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
            let (mut all, mut seen) = (0.0, 0.0);
            for j in 0..n {
                for i in 0..n {
                    let u = (i as f32 + sampler.next_f32()) / n as f32;
                    let v = (j as f32 + sampler.next_f32()) / n as f32;
                    let y = l.face.point(u, v) + l.normal * world.epsilon();
                    let w = y - origin;
                    let r2 = w.length_squared();
                    let (cos_x, cos_y) = (normal.dot(w), -l.normal.dot(w));
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
                sum += l.exitance * (f * seen / all);
            }
        }
        sum
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
    let luminaires = Luminaires::new(mesh);
    // The geometry of the lit mesh does not depend on the values it carries: a world over the
    // solution's lit mesh finds each element's direct light, one over the indirect part shades.
    let full = display::lit_mesh(mesh, radiosity);
    let indirect = {
        let world = World::new(scene, mesh, &full);
        indirect_radiosity(
            &world,
            mesh,
            radiosity,
            &luminaires,
            settings.shadow_samples,
        )
    };
    let lit = display::lit_mesh(mesh, &indirect);
    let world = World::new(scene, mesh, &lit);
    let tracer = Tracer {
        world: &world,
        settings,
        luminaires: Some(&luminaires),
    };
    render_primary(
        camera,
        image,
        settings.jitter,
        watch,
        |origin, dir, sampler| tracer.trace(origin, dir, 0, Rgb::ONE, sampler),
    )
}

/// B_i(e) = B(e) − E(e) − ρ(e) · Ē_d(e) for every element (see the module docs); the same
/// sample streams for any thread count.
fn indirect_radiosity(
    world: &World,
    mesh: &Mesh,
    radiosity: &[Rgb],
    luminaires: &Luminaires,
    samples: u32,
) -> Vec<Rgb> {
    (0..mesh.element_count())
        .into_par_iter()
        .map(|e| {
            let node = mesh.element(e);
            let patch = &mesh.patches[node.patch as usize];
            let mut sampler = Sampler::new(e as u32, u32::MAX, 0);
            let g = ELEMENT_GRID as f32;
            let mut direct = Rgb::ZERO;
            for j in 0..ELEMENT_GRID {
                for i in 0..ELEMENT_GRID {
                    let x = node.face.point((i as f32 + 0.5) / g, (j as f32 + 0.5) / g);
                    direct += luminaires.irradiance(world, x, patch.normal, samples, &mut sampler);
                }
            }
            direct /= f64::from(ELEMENT_GRID * ELEMENT_GRID);
            radiosity[e] - patch.emission - patch.reflectance * direct
        })
        .collect()
}
