//! The first shot of the point luminaires: the direct light every element takes from them.
//!
//! A point luminaire ([`crate::scene::luminaire`]) has no area, so no form factor links it to
//! anything; its light enters the radiosity equation as a known irradiance of each element,
//! shot once before the interreflection is solved (the "first shot" of progressive
//! refinement, Cohen, Chen, Wallace & Greenberg 1988, for a source outside the system):
//!
//! ```text
//! B_i = E_i + ρ_i (H_ℓ,i + Σ_j F_ij B_j),
//! H_ℓ,i = (1 / A_i) ∫_i Σ_ℓ I_ℓ(ω) cos θ / r² · V(x, ℓ) dA
//!       ≈ (1 / N) Σ_k Σ_ℓ I_ℓ(ω_k) cos θ_k / r_k² · V(x_k, ℓ),
//! ```
//!
//! the mean over N = [`SIDE`]² points x_k stratified over the element (jittered in each cell),
//! each with one shadow ray to each luminaire. The solvers take ρ H_ℓ as part of the light the
//! element starts with; the evaluated picture recomputes the direct light exactly at every
//! point, so the points' noise reaches the picture only through the indirect light.

use glam::Vec3;
use rayon::prelude::*;

use crate::accel::{Bvh, Ray};
use crate::formfactor::visibility::jitter;
use crate::hash::mix;
use crate::mesh::Mesh;
use crate::Rgb;

/// Side of the grid of points per element (16 points).
pub const SIDE: u32 = 4;

/// Salt of the points, apart from every other estimator's.
const SALT: u64 = 0xF125_7500_0000_0000;

/// H_ℓ of every node in `nodes` (module docs): zero for nodes that reflect nothing, and
/// everywhere when the mesh has no luminaire.
#[must_use]
pub fn irradiance(mesh: &Mesh, bvh: &Bvh, nodes: &[u32]) -> Vec<Rgb> {
    if mesh.luminaires.is_empty() {
        return vec![Rgb::ZERO; nodes.len()];
    }
    let lift = bvh.lift();
    nodes
        .par_iter()
        .map(|&n| {
            let node = &mesh.nodes[n as usize];
            let patch = &mesh.patches[node.patch as usize];
            if patch.reflectance.max_element() <= 0.0 {
                return Rgb::ZERO;
            }
            let mut sum = Rgb::ZERO;
            for k in 0..SIDE * SIDE {
                let bits = mix(mix(u64::from(n) ^ SALT) ^ u64::from(k));
                let u = ((k % SIDE) as f32 + jitter(bits, 0)) / SIDE as f32;
                let v = ((k / SIDE) as f32 + jitter(bits, 1)) / SIDE as f32;
                let x = node.face.point(u, v);
                sum += at_point(mesh, bvh, x, patch.normal, lift);
            }
            sum / f64::from(SIDE * SIDE)
        })
        .collect()
}

/// Σ_ℓ I_ℓ cos θ / r² · V at `x` (unit normal `normal`): the visibility of each source of
/// each luminaire ([`crate::scene::Luminaire::arrivals`]: its position, the points over its
/// opening, or the direction of a directional light) by one ray from `x` lifted `lift` off
/// its surface.
fn at_point(mesh: &Mesh, bvh: &Bvh, x: Vec3, normal: Vec3, lift: f32) -> Rgb {
    let from = x + normal * lift;
    let mut sum = Rgb::ZERO;
    for l in &mesh.luminaires {
        for (source, e) in l.arrivals(x, normal) {
            if e == Rgb::ZERO {
                continue;
            }
            let w = source - from;
            let distance = w.length();
            if !bvh.occluded(&Ray::new(from, w / distance), distance - lift) {
                sum += e;
            }
        }
    }
    sum
}
