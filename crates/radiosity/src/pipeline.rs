//! The pipeline: scene → patches and elements → form factors → solve → lit mesh.
//!
//! "Solve once, look from anywhere": [`solve`] never sees a camera. Its product, [`Solved`],
//! holds the lit mesh that every renderer and exporter reads, and the numbers for the
//! statistics file.

use std::time::Instant;

use crate::accel::Bvh;
use crate::formfactor::{self, Geometry};
use crate::mesh::{display, LitMesh, Mesh, Subdivision};
use crate::progress::Progress;
use crate::solve::matrix::Matrix;
use crate::solve::{self, Solution, SolveError};
use crate::stats::{Aggregate, Energy, SolverStats, Stats, Timings};
use crate::{Rgb, Scene};

/// Everything that decides a solution.
#[derive(Clone, Debug, Default)]
pub struct Settings {
    /// How finely patches are split into elements.
    pub subdivision: Subdivision,
    /// How form factors are computed.
    pub form_factors: formfactor::Settings,
    /// Solver, tolerance and resource limits. The method `None` means automatic: gathering
    /// (Gauss-Seidel) when the form-factor matrix fits in memory, progressive refinement
    /// otherwise.
    pub solve: solve::Settings,
    /// The solver method, or `None` for the automatic choice.
    pub method: Option<solve::Method>,
}

/// Why a pipeline run failed.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The solver refused (e.g. the matrix would not fit in memory).
    #[error(transparent)]
    Solve(#[from] SolveError),
}

/// A solved scene: the mesh, its radiosity, and the lit mesh for display.
#[derive(Debug)]
pub struct Solved {
    /// The scene as loaded.
    pub scene: Scene,
    /// Patches and elements.
    pub mesh: Mesh,
    /// Per-element radiosity and solver figures.
    pub solution: Solution,
    /// Per-vertex radiosity for renderers and exporters.
    pub lit: LitMesh,
    /// Seconds spent meshing, computing form factors and solving.
    pub timings: Timings,
    /// Power absorbed by all surfaces, per channel.
    absorbed: Rgb,
}

/// Meshes and solves `scene`.
///
/// # Errors
/// When the solver refuses its input (see [`SolveError`]).
pub fn solve(
    scene: Scene,
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<Solved, PipelineError> {
    let mut timings = Timings::default();
    let start = Instant::now();
    let mesh = Mesh::build(&scene, settings.subdivision);
    let bvh = Bvh::build(&mesh.triangles);
    let sources = mesh.sources(settings.solve.max_sources);
    timings.mesh = start.elapsed().as_secs_f64();

    let geometry = Geometry::new(&mesh, &bvh, &sources);
    let form_factors = formfactor::build(&settings.form_factors);
    let mut solve_settings = settings.solve;
    solve_settings.method = settings.method.unwrap_or_else(|| {
        let bytes = Matrix::bytes(mesh.element_count(), sources.len());
        if bytes <= settings.solve.max_matrix_bytes {
            solve::Method::GaussSeidel
        } else {
            solve::Method::Progressive
        }
    });
    let solution = solve::solve(&geometry, form_factors.as_ref(), &solve_settings, progress)?;
    timings.form_factors = solution.form_factor_seconds;
    timings.solve = solution.solve_seconds;
    let absorbed = absorbed_power(&geometry, form_factors.as_ref(), &solution);

    let lit = display::lit_mesh(&mesh, &solution.radiosity);
    Ok(Solved {
        scene,
        mesh,
        solution,
        lit,
        timings,
        absorbed,
    })
}

/// Σ_e A_e (1 − ρ_e) H_e. The irradiance follows from the solution as H = (B − E)/ρ; where a
/// channel's ρ is zero that says nothing, so the element gathers H = Σ_s F_es B_s directly.
fn absorbed_power(
    geometry: &Geometry,
    form_factors: &dyn formfactor::FormFactors,
    solution: &Solution,
) -> Rgb {
    let mesh = geometry.mesh;
    let source_radiosity: Vec<Rgb> = geometry
        .sources
        .iter()
        .map(|&s| {
            let range = mesh.nodes[s as usize].elements.clone();
            let (mut power, mut area) = (Rgb::ZERO, 0.0);
            for e in range {
                let a = mesh.element(e as usize).face.area();
                power += a * solution.radiosity[e as usize];
                area += a;
            }
            power / area.max(f64::MIN_POSITIVE)
        })
        .collect();
    let mut row = vec![0.0; geometry.sources.len()];
    let mut total = Rgb::ZERO;
    for e in 0..mesh.element_count() {
        let patch = mesh.element_patch(e);
        let area = mesh.element(e).face.area();
        let rho = patch.reflectance;
        let mut h = (solution.radiosity[e] - patch.emission) / rho;
        if rho.min_element() <= 0.0 {
            form_factors.row(geometry, e, &mut row);
            let gathered: Rgb = row
                .iter()
                .zip(&source_radiosity)
                .map(|(&f, &b)| f64::from(f) * b)
                .sum();
            for c in 0..3 {
                if rho[c] <= 0.0 {
                    h[c] = gathered[c];
                }
            }
        }
        total += area * (Rgb::ONE - rho) * h;
    }
    total
}

impl Solved {
    /// The statistics of DESIGN.md §5. `timings` supplies the stages measured outside the
    /// pipeline (`load`, `render`, `total`); the others come from the solve.
    #[must_use]
    pub fn stats(&self, timings: &Timings) -> Stats {
        let emitted: Rgb = self.mesh.patches.iter().map(|p| p.area * p.emission).sum();
        Stats {
            patches: self.mesh.patches.len(),
            elements: self.mesh.element_count(),
            links: self.solution.links,
            solver: SolverStats {
                method: self.solution.method.to_string(),
                iterations: self.solution.iterations,
                residual: self.solution.residual,
            },
            timings: Timings {
                mesh: self.timings.mesh,
                form_factors: self.timings.form_factors,
                solve: self.timings.solve,
                ..*timings
            },
            energy: Energy {
                emitted: emitted.to_array(),
                absorbed: self.absorbed.to_array(),
            },
            objects: self.aggregate(
                |polygon| self.scene.polygons[polygon].object,
                |o| self.scene.objects[o].name.clone(),
            ),
            materials: self.aggregate(
                |polygon| self.scene.polygons[polygon].material,
                |m| self.scene.materials[m].name.clone(),
            ),
        }
    }

    /// Groups polygons by `group(polygon)`, named by `name(group)`, in order of first
    /// appearance; area counts each polygon once, power counts every side.
    fn aggregate(
        &self,
        group: impl Fn(usize) -> usize,
        name: impl Fn(usize) -> String,
    ) -> Vec<Aggregate> {
        let mut order: Vec<usize> = Vec::new();
        let mut area = std::collections::HashMap::<usize, f64>::new();
        let mut power = std::collections::HashMap::<usize, Rgb>::new();
        for (p, patch) in self.mesh.patches.iter().enumerate() {
            let g = group(patch.polygon as usize);
            if !area.contains_key(&g) {
                order.push(g);
            }
            let a = area.entry(g).or_default();
            if !patch.back {
                *a += patch.area;
            }
            let elements = self.mesh.roots[p]
                .clone()
                .map(|r| self.mesh.nodes[r as usize].elements.clone());
            let pw = power.entry(g).or_default();
            for range in elements {
                for e in range {
                    *pw += self.mesh.element(e as usize).face.area()
                        * self.solution.radiosity[e as usize];
                }
            }
        }
        // Merge groups that share a name (e.g. two materials called the same in different files).
        let mut merged: Vec<Aggregate> = Vec::new();
        for g in order {
            let n = name(g);
            let (a, pw) = (area[&g], power[&g]);
            if let Some(m) = merged.iter_mut().find(|m| m.name == n) {
                let total = m.area + a;
                let sum = Rgb::from_array(m.radiosity) * m.area + pw;
                m.area = total;
                m.radiosity = (sum / total.max(f64::MIN_POSITIVE)).to_array();
            } else {
                merged.push(Aggregate {
                    name: n,
                    area: a,
                    radiosity: (pw / a.max(f64::MIN_POSITIVE)).to_array(),
                });
            }
        }
        merged
    }
}
