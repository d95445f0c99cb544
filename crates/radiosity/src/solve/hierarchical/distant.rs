//! Light from a distant environment, gathered along rays by every element.
//!
//! An environment ([`crate::scene::environment`]) is a cube of emitting tiles 16 diagonals
//! away. As sources of links, its hundreds of tiles each needed links to every element they
//! light, and to every element they do not: a link whose shadow rays are all blocked is kept
//! and refined until even its unoccluded factor moves little light, so a room lit through a
//! window linked each of its elements with each hidden tile (Bitterli's living room went past
//! 45 million links in its second pass). So the tiles are no link's source. Each element
//! gathers them instead, as Nusselt's analogue reads the irradiance: from points drawn over
//! the element, rays in cosine-distributed directions ω_k; a ray whose first hit is a tile
//! (on its side facing the ray) reads that tile's exitance M = π L, and
//!
//! ```text
//! H_env = ∫_Ω L(ω) V(ω) cos θ dω  ≈  (1/N) Σ_k M(hit_k)
//! ```
//!
//! over N = [`RAYS`] rays stratified over the square of directions. The visibility is that of
//! the rays, so no light crosses a wall, and the element's own H_env is added to what its links
//! bring ([`super::push_pull`]). The refinement splits an element while the power ρ A H_env
//! it takes this way exceeds the threshold, as it would split a link that moves that much
//! ([`split_lit`]). Its noise, √(p (1 − p) / N) for a fraction p of the rays that find sky,
//! enters the evaluated picture only through the indirect light: the picture's direct light
//! is evaluated exactly at every point ([`crate::render::evaluated`]).

use glam::Vec3;
use rayon::prelude::*;

use crate::accel::{Bvh, Ray};
use crate::formfactor::visibility::jitter;
use crate::hash::mix;
use crate::mesh::{Mesh, MAX_LEVEL};
use crate::sampling::cosine_direction;
use crate::Rgb;

/// Rays per element, a 16 × 16 stratification of the square of directions.
pub const RAYS: u32 = 256;

/// Salt of the rays, apart from every other estimator's.
const SALT: u64 = 0xD15_7A47_0000_0000;

/// Which patch a ray sees where it hits a scene polygon: the side facing it.
pub struct Sides {
    /// (polygon, patch) pairs, sorted.
    sorted: Vec<(u32, usize)>,
}

impl Sides {
    /// The lookup over `mesh`'s patches.
    #[must_use]
    pub fn new(mesh: &Mesh) -> Self {
        let mut sorted: Vec<(u32, usize)> = mesh
            .patches
            .iter()
            .enumerate()
            .map(|(i, p)| (p.polygon, i))
            .collect();
        sorted.sort_unstable();
        Self { sorted }
    }

    /// The patch of scene polygon `polygon` that a ray along `dir` meets: the one whose normal
    /// faces it.
    #[must_use]
    pub fn facing(&self, mesh: &Mesh, polygon: u32, dir: Vec3) -> Option<usize> {
        let start = self.sorted.partition_point(|&(q, _)| q < polygon);
        self.sorted[start..]
            .iter()
            .take_while(|&&(q, _)| q == polygon)
            .map(|&(_, p)| p)
            .find(|&p| mesh.patches[p].normal.dot(dir) < 0.0)
    }
}

/// Whether `mesh` has a distant environment at all.
#[must_use]
pub fn present(mesh: &Mesh) -> bool {
    mesh.patches.iter().any(|p| p.distant)
}

/// H_env of every node in `nodes` (module docs): zero for nodes that reflect nothing or are
/// part of the environment themselves, and everywhere when there is no environment.
#[must_use]
pub fn irradiance(mesh: &Mesh, bvh: &Bvh, nodes: &[u32]) -> Vec<Rgb> {
    if !present(mesh) {
        return vec![Rgb::ZERO; nodes.len()];
    }
    let sides = Sides::new(mesh);
    nodes
        .par_iter()
        .map(|&n| {
            let node = &mesh.nodes[n as usize];
            let patch = &mesh.patches[node.patch as usize];
            if patch.distant || patch.reflectance.max_element() <= 0.0 {
                return Rgb::ZERO;
            }
            let mut sum = Rgb::ZERO;
            for k in 0..RAYS {
                let bits = mix(mix(u64::from(n) ^ SALT) ^ u64::from(k));
                let (i, j) = (k % 16, k / 16);
                let u1 = (i as f32 + jitter(bits, 2)) / 16.0;
                let u2 = (j as f32 + jitter(bits, 3)) / 16.0;
                let from =
                    node.face.point(jitter(bits, 0), jitter(bits, 1)) + patch.normal * bvh.lift();
                let ray = Ray::new(from, cosine_direction(patch.normal, u1, u2));
                let seen = bvh
                    .closest_hit(&ray, f32::INFINITY)
                    .and_then(|hit| {
                        sides.facing(mesh, mesh.triangle_polygon[hit.triangle as usize], ray.dir)
                    })
                    .filter(|&p| mesh.patches[p].distant);
                if let Some(p) = seen {
                    sum += mesh.patches[p].emission;
                }
            }
            sum / f64::from(RAYS)
        })
        .collect()
}

/// The leaves (sorted) that take more than `threshold` of the environment's power,
/// ρ A H_env (largest channels), and may still be split (children of at least `min_area`,
/// below the deepest level). `sky` is H_env of every mesh node.
#[must_use]
pub fn split_lit(mesh: &Mesh, sky: &[Rgb], threshold: f64, min_area: f64) -> Vec<u32> {
    mesh.elements
        .iter()
        .copied()
        .filter(|&n| {
            let node = &mesh.nodes[n as usize];
            let rho = mesh.patches[node.patch as usize].reflectance.max_element();
            let area = node.area();
            rho * area * sky[n as usize].max_element() > threshold
                && node.level < MAX_LEVEL
                && area >= 4.0 * min_area
        })
        .collect()
}
