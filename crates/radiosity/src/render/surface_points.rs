//! The evaluated picture's radiosity at given points of the surfaces: what a baker stores at
//! each texel of a light map.
//!
//! A point x on a surface of unit normal n (the side that shows) is found on the far part's lit
//! mesh by the short ray from x + δ n towards −n (δ a few of the ray tracer's ε, [`LIFT`]),
//! which meets the surface at x from that side: the lit triangle and barycentrics there (a
//! two-sided polygon's back through its twin) are what the evaluated picture reads
//! ([`super::evaluated`]),
//!
//! ```text
//! B(x) = E(x) + ρ(x) · (E_d(x) + k N(x)) + R(x) · (1 − S(x)),
//! ```
//!
//! the same value a camera ray hitting x would show (display refinement takes it at vertices
//! the same way, [`super::display_refinement`]). A slightly non-planar polygon's elements lie
//! off its points by up to its warp, so there the probe starts beyond it. A point whose own
//! polygon is not met, or is met from a side that reflects nothing (a one-sided polygon's
//! back; a polygon dropped while loading), has no value; a
//! point buried in another object (a floor under a box) is met all the same, and its value is
//! what the solution says there: dark, its shadow rays blocked by the object around it.

use glam::Vec3;
use rayon::prelude::*;

use super::evaluated::prepare;
use super::raytrace::world::World;
use crate::mesh::Mesh;
use crate::progress::Work;
use crate::render::Watch;
use crate::solve::Solution;
use crate::{Rgb, Scene};

/// δ, the lift of the probing ray's start off the surface, in units of the ray tracer's ε.
const LIFT: f32 = 4.0;

/// Points handed out per parallel batch (and per progress report).
const BATCH: usize = 4096;

/// A point of a polygon's surface whose light is wanted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Where it is.
    pub point: Vec3,
    /// The unit normal of the side that shows.
    pub normal: Vec3,
    /// The polygon it lies on ([`Scene::polygons`]).
    pub polygon: u32,
    /// How far the polygon strays from its plane (scene units): a slightly non-planar
    /// polygon's elements lie up to this far from its points.
    pub warp: f32,
}

/// B at each of `points`, or `None` where its polygon is not met (module docs), with `samples`
/// shadow rays per luminaire. Reported to `watch` as the stage "texels"; `None` if it was
/// stopped.
#[must_use]
pub fn radiosity_at(
    scene: &Scene,
    mesh: &Mesh,
    solution: &Solution,
    points: &[SurfacePoint],
    samples: u32,
    watch: &Watch,
) -> Option<Vec<Option<Rgb>>> {
    let (evaluation, _, far) = prepare(scene, mesh, solution, (samples, false), None, watch)?;
    let world = World::new(scene, mesh, &far);
    let lift = LIFT * world.epsilon();
    // The probe from `x + d n` towards −n, if it meets the point's own polygon from the side
    // that shows.
    let probe = |p: &SurfacePoint, d: f32| {
        let hit = world.intersect(p.point + p.normal * d, -p.normal, 2.0 * d)?;
        let (t, u, v) = hit.diffuse?;
        let polygon = mesh.patches[world.patch(t) as usize].polygon;
        (polygon == p.polygon).then_some((t, [u, v]))
    };
    watch
        .progress
        .start("texels", Work::of(points.len() as u64, "points"));
    let mut values = Vec::with_capacity(points.len());
    for batch in points.chunks(BATCH) {
        if watch.stopped() {
            watch.progress.cut_short();
            return None;
        }
        values.par_extend(batch.par_iter().map(|p| {
            // From just off the surface; for a warped polygon, from beyond its warp (unless
            // something else lies that close in front, where the near probe decides).
            let found = probe(p, lift).or_else(|| {
                (p.warp > 0.0)
                    .then(|| probe(p, lift + 2.0 * p.warp))
                    .flatten()
            })?;
            Some(evaluation.radiosity_at(&world, mesh, p.point, found, samples))
        }));
        watch.progress.advance(batch.len() as u64);
    }
    watch.progress.finish();
    Some(values)
}
