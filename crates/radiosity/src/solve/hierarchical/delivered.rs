//! The power the refinement threshold is a fraction of: what the emitters deliver to the
//! surfaces that reflect.
//!
//! BF refinement splits a link while it moves more than ε·Φ (Hanrahan, Salzman & Aupperle
//! 1991, §4), Φ standing for the light the solution is made of. Taking Φ as the emitted power
//! is right when the emitters light the scene, wrong when most of what they emit never reaches
//! a surface that reflects it. A distant environment is the case in point: an inward-facing
//! box [`crate::scene::environment::tiles::DISTANCE`] = 16 diagonals away whose tiles mostly
//! see each other, emitting some 10³–10⁶ times what the scene receives. Against that Φ every
//! link inside a house is "weak", none is refined, and the light that crosses a cluster link
//! or an unresolved pair whose source is a cluster of lit outside walls and dark inside walls
//! shows up indoors: a closed room under a uniform sky read 1.6 on a box inside it where the
//! answer is 0.
//!
//! So an emitter that reflects nothing (an environment's tile, the default sky, a Mitsuba area
//! light) counts only the power it delivers to reflecting surfaces, estimated from their side:
//! from points drawn over the reflecting root faces in proportion to area, rays in
//! cosine-distributed directions ω_k; each ray that first hits such an emitter reads its
//! exitance M (the largest channel), and
//!
//! ```text
//! Φ_delivered = ∫_reflecting ∫_Ω L_e cos θ dω dA  ≈  A_reflecting · (1/N) Σ_k M(hit_k)
//! ```
//!
//! (cosine sampling has density cos θ / π, and M = π L_e for a diffuse emitter). Emitters that
//! also reflect (a lamp's diffuser) keep their whole emitted power, as before: they are among
//! the surfaces the solution is about, and so do the point luminaires, whose whole flux is shot to
//! the surfaces ([`crate::solve::first_shot`]). The estimate's noise, √(1/hits), only moves the
//! threshold, and its rays are seeded by their index, so it is the same on every run.

use rayon::prelude::*;

use super::distant::Sides;

use crate::accel::{Bvh, Ray};
use crate::formfactor::visibility::jitter;
use crate::hash::{mix, unit_f64};
use crate::mesh::Mesh;
use crate::sampling::cosine_direction;
use crate::Rgb;

/// Rays of the estimate.
pub const RAYS: u32 = 1 << 14;

/// Salt of the rays, apart from every other estimator's.
const SALT: u64 = 0xDE1_0000_0000_0000;

/// The reference power Φ (module docs), each patch's emission reduced by `channel`: Σ A·E
/// over the elements of emitters that reflect, plus what the emitters that do not deliver to
/// surfaces that do. Falls back to the whole emitted power when that is zero (nothing that
/// reflects is lit, so no threshold matters).
#[must_use]
pub fn reference_power(mesh: &Mesh, bvh: &Bvh, channel: fn(Rgb) -> f64) -> f64 {
    let pure = |p: usize| {
        let patch = &mesh.patches[p];
        patch.reflectance.max_element() <= 0.0 && channel(patch.emission.abs()) > 0.0
    };
    let (mut reflecting_emitters, mut emitted) = (0.0, 0.0);
    for &n in &mesh.elements {
        let node = &mesh.nodes[n as usize];
        let power = node.area() * channel(mesh.patches[node.patch as usize].emission.abs());
        emitted += power;
        if !pure(node.patch as usize) {
            reflecting_emitters += power;
        }
    }
    let luminaires = luminaire_power(mesh, channel);
    reflecting_emitters += luminaires;
    emitted += luminaires;
    if reflecting_emitters == emitted {
        return emitted;
    }
    let delivered = delivered(mesh, bvh, channel, &pure);
    let reference = reflecting_emitters + delivered;
    if reference > 0.0 {
        reference
    } else {
        emitted
    }
}

/// The power the point luminaires emit (their flux in the scene's power units), each reduced
/// by `channel`: all of it counts, as their light is shot to the surfaces that reflect it
/// ([`crate::solve::first_shot`]).
#[must_use]
pub fn luminaire_power(mesh: &Mesh, channel: fn(Rgb) -> f64) -> f64 {
    mesh.luminaires
        .iter()
        .map(|l| channel(l.scene_power()))
        .sum()
}

/// Φ_delivered of the module docs: the power that emitters for which `pure` holds send to the
/// root faces that reflect.
fn delivered(
    mesh: &Mesh,
    bvh: &Bvh,
    channel: fn(Rgb) -> f64,
    pure: &(dyn Fn(usize) -> bool + Sync),
) -> f64 {
    let faces: Vec<u32> = mesh
        .roots
        .iter()
        .flat_map(Clone::clone)
        .filter(|&f| {
            let patch = mesh.nodes[f as usize].patch as usize;
            mesh.patches[patch].reflectance.max_element() > 0.0
        })
        .collect();
    let before: Vec<f64> = std::iter::once(0.0)
        .chain(faces.iter().scan(0.0, |sum, &f| {
            *sum += mesh.nodes[f as usize].area();
            Some(*sum)
        }))
        .collect();
    let area = before.last().copied().unwrap_or(0.0);
    if faces.is_empty() || area <= 0.0 {
        return 0.0;
    }
    let sides = Sides::new(mesh);
    let reads: Vec<f64> = (0..RAYS)
        .into_par_iter()
        .map(|k| {
            let bits = mix(SALT ^ u64::from(k));
            let target = unit_f64(mix(bits ^ 1)) * area;
            let i = before[1..]
                .partition_point(|&s| s <= target)
                .min(faces.len() - 1);
            let node = &mesh.nodes[faces[i] as usize];
            let normal = mesh.patches[node.patch as usize].normal;
            let from = node.face.point(jitter(bits, 0), jitter(bits, 1)) + normal * bvh.lift();
            let ray = Ray::new(
                from,
                cosine_direction(normal, jitter(bits, 2), jitter(bits, 3)),
            );
            bvh.closest_hit(&ray, f32::INFINITY)
                .and_then(|hit| {
                    sides.facing(mesh, mesh.triangle_polygon[hit.triangle as usize], ray.dir)
                })
                .filter(|&p| pure(p))
                .map_or(0.0, |p| channel(mesh.patches[p].emission.abs()))
        })
        .collect();
    // Summed in ray order, so the bits do not depend on the thread count.
    area * reads.iter().sum::<f64>() / f64::from(RAYS)
}
