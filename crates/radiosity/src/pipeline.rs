//! The pipeline: scene → patches and elements → form factors → solve → lit mesh.
//!
//! "Solve once, look from anywhere": [`solve`] never sees a camera. Its product, [`Solved`],
//! holds the lit mesh that every renderer and exporter reads, and the numbers for the
//! statistics file.

use std::time::Instant;

use crate::accel::Bvh;
use crate::formfactor::{self, Geometry};
use crate::mesh::{display, LitMesh, Mesh, Subdivision};
use crate::progress::{Progress, Work};
use crate::registry::registry;
use crate::render::display_refinement;
use crate::render::evaluated::measured;
use crate::render::false_colour::{Measurement, Quantity};
use crate::render::raytrace::RaytraceSettings;
use crate::render::{Image, Mode, RasterSettings, Watch};
use crate::scene::Camera;
use crate::solve::checkpoint::{hash_text, Control};
use crate::solve::{self, plan, Solution, SolveError};
use crate::stats::{Aggregate, Energy, SolverStats, Stats, Timings};
use crate::{Rgb, Scene};

/// Everything that decides a solution.
#[derive(Clone, Debug, Default)]
pub struct Settings {
    /// How finely patches are split into elements.
    pub subdivision: Subdivision,
    /// Whether the outlines of sharp shadows become element edges (discontinuity meshing,
    /// `mesh::discontinuity`); off by default (docs/decisions/discontinuity-meshing.md).
    pub discontinuity: bool,
    /// How form factors are computed.
    pub form_factors: formfactor::Settings,
    /// Tolerance and resource limits of the solver, and the hierarchical solver's options.
    pub solve: solve::Settings,
    /// The solver method, or `None` for the automatic choice ([`plan`]).
    pub method: Option<solve::Method>,
    /// How the lit mesh gets its vertex radiosity.
    pub display: Display,
}

/// How the lit mesh (exports, `--mode radiosity`) gets its vertex radiosity.
///
/// Adding a display mode is the code that makes the lit mesh, and here: its line in
/// [`DisplayKind`] (its doc comment is its help on the command line), its variant below and the
/// arms the compiler then asks for in this file.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Display {
    /// The area-weighted mean of the elements around each vertex (borders extrapolated).
    #[default]
    Averaged,
    /// Evaluated at each vertex, the triangles split where interpolation misses
    /// ([`display_refinement`]).
    Evaluated(display_refinement::Settings),
}

registry! {
    /// The display modes by name, without their settings: the registry of the family.
    pub enum DisplayKind {
        /// Evaluated at each vertex, the triangles split where interpolation misses.
        Evaluated = "evaluated",
        /// The area-weighted mean of the elements around each vertex.
        Averaged = "averaged",
    }
    /// An unknown display mode name.
    pub struct UnknownDisplay = "unknown display mode";
}

impl Display {
    /// The display mode `kind`, evaluated ones refined as `refinement` says.
    #[must_use]
    pub fn of(kind: DisplayKind, refinement: display_refinement::Settings) -> Self {
        match kind {
            DisplayKind::Evaluated => Display::Evaluated(refinement),
            DisplayKind::Averaged => Display::Averaged,
        }
    }

    /// Which display mode this is.
    #[must_use]
    pub fn kind(&self) -> DisplayKind {
        match self {
            Display::Evaluated(_) => DisplayKind::Evaluated,
            Display::Averaged => DisplayKind::Averaged,
        }
    }
}

/// Why a pipeline run failed.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The solver refused (e.g. the matrix would not fit in memory).
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// Stopped ([`Control::stop`]) while meshing, before there was anything to solve.
    #[error("stopped while meshing")]
    Interrupted,
    /// The requested subdivision would not fit in memory.
    #[error(
        "the subdivision asks for {elements:.0} elements, about {:.0} MiB, more than the limit of {:.1} MiB",
        (elements * BYTES_PER_ELEMENT / f64::from(1 << 20)).ceil(),
        *limit as f64 / f64::from(1 << 20)
    )]
    TooManyElements {
        /// Elements the subdivision would make.
        elements: f64,
        /// The memory limit in force, in bytes.
        limit: u64,
    },
}

/// Memory per element, measured from the structures: its quadtree node (~80 bytes, plus a third
/// more for interior nodes), its index, radiosity and residual vectors (~60 bytes), and its share
/// of the lit mesh (about one vertex and two triangles, ~90 bytes).
const BYTES_PER_ELEMENT: f64 = 260.0;

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
    solve_controlled(scene, settings, &Control::default(), progress)
}

/// [`solve`] under `control`: stopping early, checkpoints and resuming (see
/// [`solve::checkpoint`]). The form-factor settings are folded into the checkpoints'
/// fingerprint.
///
/// # Errors
/// Those of [`solve`]; a checkpoint that belongs to another run.
pub fn solve_controlled(
    scene: Scene,
    settings: &Settings,
    control: &Control,
    progress: &dyn Progress,
) -> Result<Solved, PipelineError> {
    let mut timings = Timings::default();
    let start = Instant::now();
    let (roots, elements) = Mesh::plan(&scene, settings.subdivision, settings.discontinuity);
    let limit = settings.solve.max_matrix_bytes;
    let problem = |requested, elements: f64, meshed: bool| plan::Problem {
        requested,
        roots,
        elements,
        meshed,
        sources: settings.solve.max_sources,
        matrix_bytes: limit,
    };
    // A subdivision beyond memory is refused, unless hierarchical radiosity was asked for:
    // it refines from the root faces by its own oracle, and the requested uniform subdivision
    // does not apply to it.
    let asked = settings.method;
    if asked != Some(solve::Method::Hierarchical) && elements * BYTES_PER_ELEMENT > limit as f64 {
        return Err(PipelineError::TooManyElements { elements, limit });
    }
    let (subdivision, requested) = match plan::plan(&problem(asked, elements, false)) {
        plan::Choice::Hierarchical => (
            Subdivision::MaxArea(f64::INFINITY),
            Some(solve::Method::Hierarchical),
        ),
        plan::Choice::Subdivided { .. } => (settings.subdivision, asked),
    };
    // The meshing stage reports its passes as phases (Mesh::build_unless), then the BVH.
    progress.start("meshing", Work::open_ended("elements"));
    let stop = || control.stopped();
    let Some(mesh) =
        Mesh::build_unless(&scene, subdivision, settings.discontinuity, &stop, progress)
    else {
        progress.cut_short();
        return Err(PipelineError::Interrupted);
    };
    progress.phase("bvh", Work::of(mesh.triangles.len() as u64, "triangles"));
    let bvh = Bvh::build(&mesh.triangles);
    progress.advance(mesh.triangles.len() as u64);
    let counted = mesh.element_count() as f64;
    let (method, sources) = match plan::plan(&problem(requested, counted, true)) {
        plan::Choice::Hierarchical => (solve::Method::Hierarchical, mesh.elements.clone()),
        plan::Choice::Subdivided {
            method,
            sources,
            reach,
        } => (method, mesh.sources(sources, reach)),
    };
    progress.tally(mesh.patches.len() as u64, "patches");
    progress.tally(counted as u64, "elements");
    progress.finish();
    timings.mesh = start.elapsed().as_secs_f64();

    let geometry = Geometry::new(&mesh, &bvh, &sources);
    let form_factors = formfactor::build(&settings.form_factors);
    // The settings that decide the answer besides the problem must match a checkpoint's: the
    // form factors, or the hierarchical solver's own refinement settings.
    let decisive = match method {
        solve::Method::Hierarchical => {
            format!(
                "{:?}",
                (settings.solve.epsilon, settings.solve.min_element_area)
            )
        }
        _ => format!("{:?}", settings.form_factors),
    };
    let control = Control {
        context: hash_text(&decisive),
        ..control.clone()
    };
    let solution = solve::solve_controlled(
        &geometry,
        form_factors.as_ref(),
        method,
        &settings.solve,
        &control,
        progress,
    )?;
    timings.form_factors = solution.form_factor_seconds;
    timings.solve = solution.solve_seconds;
    let (mesh, mut solution) = solution.on_finest(mesh);
    let absorbed = absorbed_power(&mesh, &solution);
    let averaged = || display::lit_mesh_extrapolating_borders(&mesh, &solution.radiosity);
    let lit = match settings.display {
        Display::Evaluated(refinement) if !solution.interrupted => {
            let start = Instant::now();
            let watch = Watch {
                progress,
                stop: control.stop.as_deref(),
            };
            let refined =
                display_refinement::lit_mesh(&scene, &mesh, &solution, &refinement, &watch);
            timings.display = start.elapsed().as_secs_f64();
            // Stopped there, the run is interrupted as if in the solve.
            solution.interrupted |= refined.is_none();
            refined.unwrap_or_else(averaged)
        }
        Display::Evaluated(_) | Display::Averaged => averaged(),
    };
    Ok(Solved {
        scene,
        mesh,
        solution,
        lit,
        timings,
        absorbed,
    })
}

/// Σ_e A_e (1 − ρ_e) H_e. Where ρ > 0 the irradiance follows from the solution as
/// H = (B − E)/ρ; where a channel's ρ is zero that says nothing, and the irradiance the solver
/// gathered ([`Solution::irradiance`]) is used.
fn absorbed_power(mesh: &Mesh, solution: &Solution) -> Rgb {
    (0..mesh.element_count())
        .map(|e| {
            let patch = mesh.element_patch(e);
            let rho = patch.reflectance;
            let mut h = (solution.radiosity[e] - patch.emission) / rho;
            for c in 0..3 {
                if rho[c] <= 0.0 {
                    h[c] = solution.irradiance[e][c];
                }
            }
            mesh.element(e).area() * (Rgb::ONE - rho) * h
        })
        .sum()
}

impl Solved {
    /// The picture of this scene seen by `camera` in `mode`, at the size and samples of
    /// `raster`; `None` when `watch` was told to stop first.
    #[must_use]
    pub fn render(
        &self,
        mode: &Mode,
        camera: &Camera,
        raster: &RasterSettings,
        watch: &Watch,
    ) -> Option<Image> {
        let (scene, mesh, lit) = (&self.scene, &self.mesh, &self.lit);
        mode.render(scene, mesh, lit, &self.solution, camera, raster, watch)
    }

    /// The false-colour measurement of `quantity` at the surface seen through each pixel of
    /// `camera`'s picture ([`crate::render::evaluated::measured`]), at the size and samples of
    /// `raster`; `None` when `watch` was told to stop first.
    #[must_use]
    pub fn measure(
        &self,
        quantity: Quantity,
        camera: &Camera,
        raster: &RasterSettings,
        watch: &Watch,
    ) -> Option<Measurement> {
        let solved = (&self.scene, &self.mesh, &self.solution);
        let settings = RaytraceSettings::default();
        measured::measure(solved, quantity, camera, raster, &settings, watch)
    }

    /// The statistics of `--stats` ([`crate::stats`]). `timings` supplies the stages measured outside the
    /// pipeline (`load`, `render`, `total`); the others come from the solve.
    #[must_use]
    pub fn stats(&self, timings: &Timings) -> Stats {
        let emitted = self.mesh.emitted_power();
        Stats {
            patches: self.mesh.patches.len(),
            elements: self.mesh.element_count(),
            links: self.solution.links,
            solver: SolverStats {
                method: self.solution.method.to_string(),
                iterations: self.solution.iterations,
                residual: self.solution.residual,
                interrupted: self.solution.interrupted,
            },
            timings: Timings {
                mesh: self.timings.mesh,
                form_factors: self.timings.form_factors,
                solve: self.timings.solve,
                display: self.timings.display,
                ..*timings
            },
            energy: Energy::new(emitted, self.absorbed, self.scene.units.metres()),
            objects: self.aggregate(
                |polygon| self.scene.polygons[polygon].object,
                |o| self.scene.objects[o].name.clone(),
            ),
            materials: self.aggregate(
                |polygon| self.scene.polygons[polygon].material,
                |m| self.scene.materials[m].name.clone(),
            ),
            hierarchy: self.solution.hierarchy,
        }
    }

    /// Groups polygons by `group(polygon)`, named by `name(group)`, in order of first
    /// appearance; area counts each polygon once, power counts every side. Groups with
    /// two-sided patches also get their front and back radiosity apart (power leaving the
    /// polygons' fronts, resp. backs, over the same area).
    fn aggregate(
        &self,
        group: impl Fn(usize) -> usize,
        name: impl Fn(usize) -> String,
    ) -> Vec<Aggregate> {
        /// Area (fronts), power leaving fronts and backs, and whether any patch is two-sided.
        #[derive(Default)]
        struct Sum {
            area: f64,
            front: Rgb,
            back: Rgb,
            two_sided: bool,
        }
        let mut order: Vec<String> = Vec::new();
        let mut sums = std::collections::HashMap::<String, Sum>::new();
        for (p, patch) in self.mesh.patches.iter().enumerate() {
            // Groups that share a name are one (e.g. two materials called the same in
            // different files).
            let n = name(group(patch.polygon as usize));
            if !sums.contains_key(&n) {
                order.push(n.clone());
            }
            let sum = sums.entry(n).or_default();
            sum.two_sided |= patch.two_sided;
            if !patch.back {
                sum.area += patch.area;
            }
            let power: Rgb = self.mesh.roots[p]
                .clone()
                .flat_map(|r| self.mesh.nodes[r as usize].elements.clone())
                .map(|e| self.mesh.element(e as usize).area() * self.solution.radiosity[e as usize])
                .sum();
            if patch.back {
                sum.back += power;
            } else {
                sum.front += power;
            }
        }
        order
            .into_iter()
            .map(|n| {
                let sum = &sums[&n];
                let per_area = |power: Rgb| (power / sum.area.max(f64::MIN_POSITIVE)).to_array();
                Aggregate {
                    area: sum.area,
                    radiosity: per_area(sum.front + sum.back),
                    front: sum.two_sided.then(|| per_area(sum.front)),
                    back: sum.two_sided.then(|| per_area(sum.back)),
                    name: n,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_display_mode_is_named_parsed_and_built() {
        let err = "flat".parse::<DisplayKind>().unwrap_err().to_string();
        assert!(err.starts_with("unknown display mode `flat` (choose "));
        for kind in DisplayKind::ALL {
            assert_eq!(kind.name().parse::<DisplayKind>(), Ok(kind));
            assert!(err.contains(kind.name()), "{err}");
            let refinement = display_refinement::Settings::default();
            assert_eq!(Display::of(kind, refinement).kind(), kind);
        }
    }
}
