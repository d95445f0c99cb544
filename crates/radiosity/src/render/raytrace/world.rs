//! The scene as ray tracers see it: the lit mesh's triangles in a BVH, with their materials,
//! smooth shading normals, the emitters to sample, and the radiosity to read at any hit.
//!
//! **Hits index the lit mesh.** The hierarchy is built over the lit mesh's own triangles, so a
//! hit (triangle t, barycentrics u, v) reads the radiosity solution directly by interpolating
//! its vertex radiosity, B(x) = (1 − u − v)B₀ + uB₁ + vB₂, exactly the world-space linear
//! interpolation the rasterizer performs (Gouraud, perspective-correct). The radiance of the
//! diffuse part is B(x)/π.
//!
//! **Sides.** Only the triangles of front patches enter the main hierarchy. A triangle hit from
//! behind shows nothing diffuse unless its material is two-sided; then its reversed twin (a
//! back patch, in a second hierarchy) is looked up at the same point.
//!
//! **Shading normals.** Tessellated curved objects (spheres) would reflect and refract in
//! facets. Each triangle corner gets the area-weighted mean normal of the triangles of the same
//! object meeting at that point whose normals lie within [`CREASE_DEGREES`] of its own, so
//! spheres look smooth and box edges stay sharp (the usual crease-angle rule).
//!
//! **Direct light.** The emitters' triangles are sampled uniformly in area (a triangle by the
//! cumulative area, then a uniform point in it). The irradiance from emitters of radiance L_e is
//!
//! E(x) = ∫_A L_e cos θ_x cos θ_y V(x, y) / r² dA_y ≈ (A/N) Σ_k L_e cos θ_x cos θ_y V / r²,
//!
//! with the N samples stratified in the first dimension (soft shadows: penumbrae come from the
//! visibility V varying over the emitter).

use std::collections::HashMap;

use glam::{IVec3, Vec3};

use super::sample::{triangle_point, Sampler};
use crate::accel::{Bvh, Ray};
use crate::mesh::{LitMesh, Mesh};
use crate::scene::Material;
use crate::{Rgb, Scene};

/// Normals further apart than this (degrees) meet at a crease and are not averaged.
pub const CREASE_DEGREES: f32 = 40.0;

/// A ray's hit on the lit mesh, with what shading needs.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    /// The lit-mesh triangle hit.
    pub triangle: u32,
    /// Distance along the (unit) ray.
    pub t: f32,
    /// The hit point.
    pub point: Vec3,
    /// Unit geometric normal, on the side the ray came from.
    pub normal: Vec3,
    /// Unit shading (interpolated) normal, on the side the ray came from.
    pub shading: Vec3,
    /// Whether the ray hit the triangle's front.
    pub front: bool,
    /// The lit-mesh triangle and barycentrics (u, v) whose radiosity this side shows: the hit
    /// triangle from the front, its two-sided twin from behind, `None` for a one-sided back.
    pub diffuse: Option<(u32, f32, f32)>,
}

/// An emitting triangle.
#[derive(Clone, Copy, Debug)]
struct Emitter {
    tri: [Vec3; 3],
    normal: Vec3,
    radiance: Rgb,
}

/// The scene prepared for ray tracing over a lit mesh.
#[derive(Debug)]
pub struct World<'a> {
    lit: &'a LitMesh,
    mesh: &'a Mesh,
    materials: &'a [Material],
    /// Front triangles; `front_ids` maps its triangle numbers to lit-mesh triangles.
    front: Bvh,
    front_ids: Vec<u32>,
    /// Back (two-sided twin) triangles, likewise.
    back: Bvh,
    back_ids: Vec<u32>,
    /// Per lit triangle: unit shading normal at each corner (front side).
    normals: Vec<[Vec3; 3]>,
    /// Per object: the largest side of its bounding box (the reference thickness of glass).
    object_size: Vec<f32>,
    emitters: Vec<Emitter>,
    /// Cumulative emitter area, one entry per emitter.
    emitter_cdf: Vec<f64>,
    /// Distance rays start off surfaces.
    eps: f32,
}

impl<'a> World<'a> {
    /// Prepares `lit` (the lit mesh of `mesh`, which was built from `scene`) for ray tracing.
    /// Triangles whose patch or material index is out of range are left out.
    #[must_use]
    pub fn new(scene: &'a Scene, mesh: &'a Mesh, lit: &'a LitMesh) -> Self {
        let corners = |t: usize| lit.triangles[t].map(|i| lit.positions[i as usize]);
        let valid = |t: usize| {
            lit.triangles[t]
                .iter()
                .all(|&i| (i as usize) < lit.positions.len() && (i as usize) < lit.radiosity.len())
                && lit
                    .triangle_patch
                    .get(t)
                    .and_then(|&p| mesh.patches.get(p as usize))
                    .is_some_and(|p| (p.material as usize) < scene.materials.len())
        };
        let (mut front_ids, mut back_ids) = (Vec::new(), Vec::new());
        for t in 0..lit.triangles.len() {
            if !valid(t) {
                continue;
            }
            if mesh.patches[lit.triangle_patch[t] as usize].back {
                back_ids.push(t as u32);
            } else {
                front_ids.push(t as u32);
            }
        }
        let tris = |ids: &[u32]| ids.iter().map(|&t| corners(t as usize)).collect::<Vec<_>>();
        let front = Bvh::build(&tris(&front_ids));
        let back = Bvh::build(&tris(&back_ids));
        let bounds = front.bounds();
        let diagonal = if front.triangle_count() > 0 {
            (bounds.max - bounds.min).length()
        } else {
            1.0
        };
        let eps = front.lift();

        let mut world = Self {
            lit,
            mesh,
            materials: &scene.materials,
            front,
            front_ids,
            back,
            back_ids,
            normals: Vec::new(),
            object_size: Vec::new(),
            emitters: Vec::new(),
            emitter_cdf: Vec::new(),
            eps,
        };
        world.normals = world.shading_normals(diagonal);
        world.object_size = world.object_sizes();
        world.collect_emitters();
        world
    }

    /// Per-corner shading normals by the crease-angle rule.
    fn shading_normals(&self, diagonal: f32) -> Vec<[Vec3; 3]> {
        let lit = self.lit;
        let cell = 1e6 / f64::from(diagonal.max(f32::MIN_POSITIVE));
        let key = |p: Vec3| (p.as_dvec3() * cell).round().as_ivec3();
        let mut face = vec![Vec3::ZERO; lit.triangles.len()];
        let mut around: HashMap<(u32, IVec3), Vec<u32>> = HashMap::new();
        for ids in [&self.front_ids, &self.back_ids] {
            for &t in ids {
                let [a, b, c] = lit.triangles[t as usize].map(|i| lit.positions[i as usize]);
                // Twice the area times the unit normal.
                face[t as usize] = (b - a).cross(c - a);
                let object = lit.triangle_object.get(t as usize).copied().unwrap_or(0);
                for p in [a, b, c] {
                    around.entry((object, key(p))).or_default().push(t);
                }
            }
        }
        let cos_crease = CREASE_DEGREES.to_radians().cos();
        let mut normals = vec![[Vec3::Z; 3]; lit.triangles.len()];
        for ids in [&self.front_ids, &self.back_ids] {
            for &t in ids {
                let own = face[t as usize].normalize_or_zero();
                let object = lit.triangle_object.get(t as usize).copied().unwrap_or(0);
                let tri = lit.triangles[t as usize];
                for (k, &v) in tri.iter().enumerate() {
                    let p = lit.positions[v as usize];
                    let sum: Vec3 = around
                        .get(&(object, key(p)))
                        .into_iter()
                        .flatten()
                        .map(|&o| face[o as usize])
                        .filter(|n| n.normalize_or_zero().dot(own) >= cos_crease)
                        .sum();
                    normals[t as usize][k] = sum.try_normalize().unwrap_or(own);
                }
            }
        }
        normals
    }

    /// Largest bounding-box side per object.
    fn object_sizes(&self) -> Vec<f32> {
        let lit = self.lit;
        let mut lo: Vec<Vec3> = Vec::new();
        let mut hi: Vec<Vec3> = Vec::new();
        for &t in self.front_ids.iter().chain(&self.back_ids) {
            let o = lit.triangle_object.get(t as usize).copied().unwrap_or(0) as usize;
            if lo.len() <= o {
                lo.resize(o + 1, Vec3::INFINITY);
                hi.resize(o + 1, Vec3::NEG_INFINITY);
            }
            for &i in &lit.triangles[t as usize] {
                lo[o] = lo[o].min(lit.positions[i as usize]);
                hi[o] = hi[o].max(lit.positions[i as usize]);
            }
        }
        lo.iter()
            .zip(&hi)
            .map(|(l, h)| (*h - *l).max_element().max(0.0))
            .collect()
    }

    /// The emitting front triangles and their cumulative areas.
    fn collect_emitters(&mut self) {
        let mut total = 0.0;
        for &t in &self.front_ids {
            let patch = &self.mesh.patches[self.lit.triangle_patch[t as usize] as usize];
            if patch.emission.max_element() <= 0.0 {
                continue;
            }
            let tri = self.lit.triangles[t as usize].map(|i| self.lit.positions[i as usize]);
            let cross = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
            let area = 0.5 * f64::from(cross.length());
            if !(area > 0.0 && area.is_finite()) {
                continue;
            }
            total += area;
            self.emitters.push(Emitter {
                tri,
                normal: cross.normalize(),
                radiance: patch.emission / std::f64::consts::PI,
            });
            self.emitter_cdf.push(total);
        }
    }

    /// The distance rays start off surfaces.
    #[must_use]
    pub fn epsilon(&self) -> f32 {
        self.eps
    }

    /// The nearest surface along the unit direction `dir` from `origin`, within `t_max`.
    #[must_use]
    pub fn intersect(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<SurfaceHit> {
        let ray = Ray::new(origin, dir);
        let hit = self.front.closest_hit(&ray, t_max)?;
        let t = self.front_ids[hit.triangle as usize];
        let [a, b, c] = self.lit.triangles[t as usize].map(|i| self.lit.positions[i as usize]);
        let geometric = (b - a).cross(c - a).normalize_or_zero();
        let front = dir.dot(geometric) < 0.0;
        let w = [1.0 - hit.u - hit.v, hit.u, hit.v];
        let n = self.normals[t as usize];
        let shading = (n[0] * w[0] + n[1] * w[1] + n[2] * w[2]).normalize_or(geometric);
        let side = if front { 1.0 } else { -1.0 };
        let diffuse = if front {
            Some((t, hit.u, hit.v))
        } else if self
            .lit
            .has_back_twin
            .get(t as usize)
            .copied()
            .unwrap_or(false)
        {
            // The twin lies in the same plane: it is hit at the same distance, give or take.
            self.back
                .closest_hit(&ray, hit.t + 4.0 * self.eps)
                .filter(|h| (h.t - hit.t).abs() <= 4.0 * self.eps)
                .map(|h| (self.back_ids[h.triangle as usize], h.u, h.v))
        } else {
            None
        };
        Some(SurfaceHit {
            triangle: t,
            t: hit.t,
            point: ray.at(hit.t),
            normal: geometric * side,
            shading: shading * side,
            front,
            diffuse,
        })
    }

    /// Whether anything lies on the segment from `from` to `to` (ends excluded).
    #[must_use]
    pub fn occluded(&self, from: Vec3, to: Vec3) -> bool {
        self.front.occluded(&Ray::new(from, to - from), 1.0 - 1e-4)
    }

    /// The mesh the lit mesh was built from.
    #[must_use]
    pub fn mesh(&self) -> &Mesh {
        self.mesh
    }

    /// The patch of lit triangle `t`.
    #[must_use]
    pub fn patch(&self, t: u32) -> u32 {
        self.lit.triangle_patch[t as usize]
    }

    /// The corners of lit triangle `t`.
    #[must_use]
    pub fn lit_triangle(&self, t: u32) -> [Vec3; 3] {
        self.lit.triangles[t as usize].map(|v| self.lit.positions[v as usize])
    }

    /// The material of lit triangle `t`.
    ///
    /// # Panics
    /// If `t` is not a triangle of the lit mesh with a valid patch.
    #[must_use]
    pub fn material(&self, t: u32) -> &Material {
        let patch = &self.mesh.patches[self.lit.triangle_patch[t as usize] as usize];
        &self.materials[patch.material as usize]
    }

    /// The object of lit triangle `t`.
    #[must_use]
    pub fn object(&self, t: u32) -> u32 {
        self.lit
            .triangle_object
            .get(t as usize)
            .copied()
            .unwrap_or(0)
    }

    /// The size (largest bounding-box side) of object `o`; zero if unknown.
    #[must_use]
    pub fn object_size(&self, o: u32) -> f32 {
        self.object_size.get(o as usize).copied().unwrap_or(0.0)
    }

    /// The unit shading normal at barycentrics (u, v) of lit triangle `t`, on its front.
    #[must_use]
    pub fn shading_normal(&self, t: u32, u: f32, v: f32) -> Vec3 {
        let n = self.normals[t as usize];
        let [a, b, c] = self.lit.triangles[t as usize].map(|i| self.lit.positions[i as usize]);
        let geometric = (b - a).cross(c - a).normalize_or_zero();
        (n[0] * (1.0 - u - v) + n[1] * u + n[2] * v).normalize_or(geometric)
    }

    /// The radiosity solution's radiance B(x)/π at barycentrics (u, v) of lit triangle `t`.
    #[must_use]
    pub fn radiance(&self, at: (u32, f32, f32)) -> Rgb {
        self.interpolated(&self.lit.radiosity, at) / std::f64::consts::PI
    }

    /// `values` (one per lit-mesh vertex) interpolated at barycentrics (u, v) of lit triangle
    /// `t`.
    #[must_use]
    pub fn interpolated(&self, values: &[Rgb], (t, u, v): (u32, f32, f32)) -> Rgb {
        let b = self.lit.triangles[t as usize].map(|i| values[i as usize]);
        let (u, v) = (f64::from(u), f64::from(v));
        b[0] * (1.0 - u - v) + b[1] * u + b[2] * v
    }

    /// Radiance emitted toward the ray that made `hit`: L_e = E/π of the triangle hit from its
    /// front, nothing from behind (emitters shine from their front only).
    #[must_use]
    pub fn emitted(&self, hit: &SurfaceHit) -> Rgb {
        if !hit.front {
            return Rgb::ZERO;
        }
        let patch = &self.mesh.patches[self.lit.triangle_patch[hit.triangle as usize] as usize];
        patch.emission / std::f64::consts::PI
    }

    /// Σ over `samples` stratified emitter samples of `brdf(ω) · L_e cos θ_x cos θ_y / r²`
    /// (times A/N): the light reflected at `point` (unit normal `normal`) toward the viewer
    /// directly from the emitters, for a BRDF `brdf` of the direction ω to the light; with
    /// `brdf` ≡ 1 it is the direct irradiance. With `shadows`, samples hidden by any surface
    /// count zero.
    pub fn direct(
        &self,
        point: Vec3,
        normal: Vec3,
        samples: u32,
        shadows: bool,
        sampler: &mut Sampler,
        brdf: impl Fn(Vec3) -> Rgb,
    ) -> Rgb {
        let points = self.point_lights(point, normal, shadows, &brdf);
        let Some(&total) = self.emitter_cdf.last() else {
            return points;
        };
        let n = samples.max(1);
        let origin = point + normal * self.eps;
        let mut sum = Rgb::ZERO;
        for k in 0..n {
            // Stratified in the first dimension, which picks the emitter by area.
            let u = (f64::from(k) + f64::from(sampler.next_f32())) / f64::from(n) * total;
            let e = self
                .emitter_cdf
                .partition_point(|&c| c <= u)
                .min(self.emitters.len() - 1);
            let below = if e == 0 { 0.0 } else { self.emitter_cdf[e - 1] };
            let span = (self.emitter_cdf[e] - below).max(f64::MIN_POSITIVE);
            let u1 = (((u - below) / span) as f32).clamp(0.0, 1.0 - f32::EPSILON);
            let emitter = &self.emitters[e];
            let y = triangle_point(&emitter.tri, u1, sampler.next_f32());
            let w = y - origin;
            let r2 = w.length_squared();
            if r2.is_nan() || r2 <= 0.0 {
                continue;
            }
            let dir = w / r2.sqrt();
            let (cos_x, cos_y) = (normal.dot(dir), -emitter.normal.dot(dir));
            if cos_x <= 0.0 || cos_y <= 0.0 || (shadows && self.occluded(origin, y)) {
                continue;
            }
            let g = f64::from(cos_x) * f64::from(cos_y) / f64::from(r2);
            sum += brdf(dir) * emitter.radiance * g;
        }
        points + sum * (total / f64::from(n))
    }

    /// Σ over the luminaires ([`crate::scene::luminaire`]) of `brdf(ω) · I(ω) cos θ / r²`
    /// (`brdf(ω) · E⊥ cos θ` for a directional light): their light reflected at `point` (unit
    /// normal `normal`) toward the viewer, exact but for the shadow (one ray per source, when
    /// `shadows`): a point or a directional light casts hard shadows, a luminous opening soft
    /// ones.
    pub fn point_lights(
        &self,
        point: Vec3,
        normal: Vec3,
        shadows: bool,
        brdf: &impl Fn(Vec3) -> Rgb,
    ) -> Rgb {
        let origin = point + normal * self.eps;
        let mut sum = Rgb::ZERO;
        for l in &self.mesh.luminaires {
            for (from, e) in l.arrivals(point, normal) {
                if e == Rgb::ZERO || (shadows && self.occluded(origin, from)) {
                    continue;
                }
                sum += brdf((from - point).normalize()) * e;
            }
        }
        sum
    }

    /// Total emitting area.
    #[must_use]
    pub fn emitter_area(&self) -> f64 {
        self.emitter_cdf.last().copied().unwrap_or(0.0)
    }
}
