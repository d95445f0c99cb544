//! Hierarchical radiosity with clustering (Hanrahan, Salzman & Aupperle 1991; Smits, Arvo &
//! Greenberg 1994).
//!
//! The full-matrix solvers couple every element with every source: n² form factors. Most of
//! those couplings move almost no light, and a far group of elements can be treated as one.
//! Hierarchical radiosity keeps a *link* between two nodes of a hierarchy — quadtree nodes of
//! the patches ([`crate::mesh::Mesh`]) and, above them, clusters of root faces
//! ([`cluster`]) — only as fine as the light it carries requires:
//!
//! ```text
//! B_r = E_r + ρ_r Σ_{links (q, s), q ⊇ r} F_qs V_qs B_s
//! ```
//!
//! 1. **Refine** ([`refine`]): start from the root cluster linked with itself; split a link
//!    while B_s·F_rs·A_r > ε·Φ (BF refinement; Φ the power the emitters deliver to what reflects,
//!    [`delivered`], so ε is relative), with a
//!    lower threshold on how much F varies over the receiver; split leaves of the quadtrees on demand
//!    down to a minimum element area.
//! 2. **Solve** ([`push_pull`]): gather along the links, push irradiance down, pull radiosity
//!    up; iterate until the residual (the module [`crate::solve`]'s definition) falls below the
//!    tolerance.
//! 3. **Multigrid**: the first refinement uses B = E and a threshold 16ε, solved; then 4ε with
//!    the new B, solved from the previous solution; then ε, repeated until a round refines
//!    nothing (at most [`FINAL_PASSES`] times).
//! 4. **Display refinement**: where an element's radiosity differs from a sibling's by more
//!    than [`GRADIENT`] of the brightest radiosity (a shadow edge, say), the links it receives
//!    are split on the receiver side, once ([`DISPLAY_PASSES`]), and the system is solved
//!    again. The lit mesh ([`crate::mesh::display`]) anchors the T-vertices this leaves, so it
//!    stays crack-free.
//! 5. **Leaf rows** ([`leaf_rows`]): on the settled links, every element gathers each link
//!    above it with its own factor instead of its ancestor's mean, and the system is solved
//!    once more through those rows.
//!
//! Both directions of a pair are linked and refined independently (each gathers for its own
//! receiver); links never join a face with itself, two faces of one patch, or two faces that do not
//! face each other (those get no link at all).
//!
//! Memory: a link is 16 bytes ([`link::Link`]); an element costs its quadtree node
//! (`size_of::<Node>()`, 64 bytes), its index (4 bytes) and the solver state of
//! [`push_pull::State`] (56 bytes): [`BYTES_PER_NODE`] for each node of the hierarchy;
//! a cluster is 48 bytes plus its state (48 bytes), and 500 bytes more for the table of its
//! projected area when it has more than [`cluster::TABULATED`] faces.

pub mod cluster;
pub mod delivered;
pub mod distant;
pub mod handle;
pub mod leaf_rows;
pub mod link;
pub mod projected;
pub mod push_pull;
pub mod refine;
pub mod source_pieces;

use std::time::Instant;

use super::checkpoint::{Control, Hierarchy, Iterate, Problem, Session, Shape};
use super::solver::{Job, Solver};
use super::{Method, Refined, Sample, Solution, SolveError};
use crate::accel::Bvh;
use crate::mesh::{Mesh, Node};
use crate::progress::{Batched, Progress, Work};
use crate::stats::HierarchyStats;
use crate::Rgb;
use cluster::{Cluster, Clusters};
use leaf_rows::LeafRows;
use link::{Handle, Link, View};
use push_pull::State;
use refine::Oracle;

/// Refinement stages of the multigrid; stage k uses the threshold ε·4^(STAGES−1−k).
pub const STAGES: u32 = 3;

/// Extra refine-and-solve passes at the final ε while refinement still changes links.
pub const FINAL_PASSES: u32 = 3;

/// Receiver splits by the display criterion.
pub const DISPLAY_PASSES: u32 = 1;

/// Links examined per progress report of a refinement round ([`Batched`]): a round of 10⁶–10⁷
/// links reports a few thousand times.
const LINK_BATCH: u64 = 4096;

/// The display criterion: a sibling difference above this fraction of the largest element
/// radiosity (largest channel) splits an element's links on the receiver side.
pub const GRADIENT: f64 = 0.05;

/// Default minimum element area, as a fraction of the area that reflects light.
pub const MIN_AREA_FRACTION: f64 = 1e-6;

/// Bytes per quadtree node: the node, its element index and its solver state.
pub const BYTES_PER_NODE: u64 = (std::mem::size_of::<Node>() + 4 + 56) as u64;

/// Bytes per cluster: the cluster, its face index and its solver state.
pub const BYTES_PER_CLUSTER: u64 = (std::mem::size_of::<Cluster>() + 4 + 48) as u64;

/// What a hierarchical solve returns.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// Radiosity of every node of the (refined) mesh: the element's for a leaf, the
    /// area-weighted mean below it for an interior node.
    pub node_radiosity: Vec<Rgb>,
    /// Irradiance of every element of the refined mesh in the last iteration.
    pub irradiance: Vec<Rgb>,
    /// The part of it from other surfaces' reflected light (the irradiance less what the same
    /// links carry from the emission alone).
    pub reflected_irradiance: Vec<Rgb>,
    /// Gather iterations over all stages.
    pub iterations: usize,
    /// The final residual.
    pub residual: f64,
    /// Seconds spent refining (estimating form factors and visibility).
    pub refine_seconds: f64,
    /// Seconds spent iterating.
    pub solve_seconds: f64,
    /// Links, levels and memory.
    pub stats: HierarchyStats,
    /// (iteration, seconds since the start, residual) after every gather iteration, over all
    /// stages — the order of every other solver's history and of [`crate::plot`] —: the
    /// residual jumps up where a stage's refinement changed the links.
    pub history: Vec<Sample>,
    /// Whether `control` stopped the run before it finished: the radiosity is then the last
    /// iterate on the links refined so far (push-pull keeps it consistent at every step).
    pub interrupted: bool,
}

impl Outcome {
    /// One more gather iteration, which left `residual`, at `seconds` since the start.
    fn record(&mut self, residual: f64, seconds: f64) {
        self.iterations += 1;
        self.residual = residual;
        self.history.push(Sample {
            iteration: self.iterations,
            seconds,
            residual,
        });
    }
}

/// Hierarchical radiosity as a [`Solver`] of a given mesh: it refines a copy (node ids stay,
/// so each given element reads its node's mean, and its irradiance is the area-weighted mean
/// of the refined elements below it), and hands the refined mesh back with its own solution
/// ([`Solution::refined`]), which the pipeline displays.
pub(super) struct Hierarchical;

impl Solver for Hierarchical {
    fn solve(&self, job: Job, solution: &mut Solution) -> Result<(), SolveError> {
        let Job {
            g,
            settings,
            control,
            progress,
            ..
        } = job;
        let mut mesh = g.mesh.clone();
        let run = run(&mut mesh, g.bvh, settings, control, progress)?;
        let given = &g.mesh.elements;
        solution.radiosity = given
            .iter()
            .map(|&n| run.node_radiosity[n as usize])
            .collect();
        solution.irradiance = given
            .iter()
            .map(|&n| {
                let (mut power, mut area) = (Rgb::ZERO, 0.0);
                for e in mesh.nodes[n as usize].elements.clone() {
                    let a = mesh.element(e as usize).area();
                    power += a * run.irradiance[e as usize];
                    area += a;
                }
                power / area.max(f64::MIN_POSITIVE)
            })
            .collect();
        solution.iterations = run.iterations;
        solution.residual = run.residual;
        solution.history = run.history;
        solution.interrupted = run.interrupted;
        solution.links = run.stats.links;
        solution.form_factor_seconds = run.refine_seconds;
        solution.solve_seconds = run.solve_seconds;
        solution.hierarchy = Some(run.stats);
        let radiosity = mesh
            .elements
            .iter()
            .map(|&n| run.node_radiosity[n as usize])
            .collect();
        solution.refined = Some(Box::new(Refined {
            mesh,
            radiosity,
            irradiance: run.irradiance,
            reflected_irradiance: Some(run.reflected_irradiance),
        }));
        Ok(())
    }

    /// The refined hierarchy only: its links and push-pull state hold the radiosity.
    fn checkpoint_shape(&self, _elements: usize) -> Shape {
        Shape {
            hierarchy: true,
            ..Shape::default()
        }
    }
}

/// Refines `mesh` and solves it hierarchically with the options of `settings` (`epsilon`,
/// `min_element_area`, `tolerance`, `max_iterations`), stopping early when `control`'s stop
/// flag is set (checked between refinement rounds and between iterations). `control`'s
/// checkpoints are taken at the end of a pass (see [`super::checkpoint`]); a resumed run
/// replays the checkpoint's refinement on the unrefined `mesh` and goes on from the pass after.
///
/// A scene that emits nothing gives B = 0 at once, with no links.
///
/// # Errors
/// [`SolveError::NotPositive`] when `epsilon` or `min_element_area` is zero, negative or not
/// finite; [`SolveError::CheckpointMismatch`] when the checkpoint to resume from belongs to
/// another run.
pub fn run(
    mesh: &mut Mesh,
    bvh: &Bvh,
    settings: &super::Settings,
    control: &Control,
    progress: &dyn Progress,
) -> Result<Outcome, SolveError> {
    let began = Instant::now();
    let positive = [
        ("epsilon", Some(settings.epsilon)),
        ("min_element_area", settings.min_element_area),
    ];
    for (name, value) in positive {
        if let Some(value) = value.filter(|v| !(*v > 0.0 && v.is_finite())) {
            return Err(SolveError::NotPositive { name, value });
        }
    }
    let problem = Problem::new(mesh, &[], Method::Hierarchical, control.context);
    let mut session = Session::new(control, problem, Method::Hierarchical)?;
    let clusters = Clusters::build(mesh);
    let mut state = State::new(mesh, &clusters, bvh);
    // Σ A·|E| over the elements, each channel reduced by `channels`.
    let power = |channels: fn(Rgb) -> f64| -> f64 {
        mesh.elements
            .iter()
            .map(|&n| {
                let patch = &mesh.patches[mesh.nodes[n as usize].patch as usize];
                state.node_area[n as usize] * channels(patch.emission.abs())
            })
            .sum()
    };
    let emitted = power(Rgb::element_sum) + delivered::luminaire_power(mesh, Rgb::element_sum);
    let reference = delivered::reference_power(mesh, bvh, Rgb::element_sum);
    let peak_power = delivered::reference_power(mesh, bvh, Rgb::max_element);
    let mut out = Outcome {
        node_radiosity: Vec::new(),
        irradiance: vec![Rgb::ZERO; mesh.element_count()],
        reflected_irradiance: vec![Rgb::ZERO; mesh.element_count()],
        iterations: 0,
        residual: 0.0,
        refine_seconds: 0.0,
        solve_seconds: 0.0,
        stats: HierarchyStats {
            clusters: clusters.nodes.len(),
            ..HierarchyStats::default()
        },
        history: Vec::new(),
        interrupted: false,
    };
    if !(emitted > 0.0 && emitted.is_finite()) {
        out.node_radiosity = state.node_b;
        out.stats.peak_memory_bytes = memory(mesh, &clusters, 0);
        return Ok(out);
    }
    let epsilon = settings.epsilon;
    let min_area = settings
        .min_element_area
        .unwrap_or_else(|| reflecting_area(mesh) * MIN_AREA_FRACTION);
    let mut links: Vec<Link> = Vec::new();
    let mut splits: Vec<u32> = Vec::new();
    let mut peak = 0;
    let (mut done, mut clock) = (0, 0.0);
    // The state at the end of the last whole pass, for the checkpoint taken on a stop.
    let mut last: Option<Iterate> = None;
    if let Some(it) = session.resume() {
        let snap = it
            .hierarchy
            .as_ref()
            .unwrap_or_else(|| unreachable!("checked by Session::new"));
        mesh.refine(&snap.splits);
        state.grow(mesh, bvh);
        let fits =
            snap.node_b.len() == mesh.nodes.len() && snap.cluster_b.len() == clusters.nodes.len();
        if !fits {
            return Err(SolveError::CheckpointMismatch(
                "its refinement does not fit this scene".to_owned(),
            ));
        }
        state = State {
            node_area: std::mem::take(&mut state.node_area),
            node_probed: std::mem::take(&mut state.node_probed),
            node_open: std::mem::take(&mut state.node_open),
            node_shine: std::mem::take(&mut state.node_shine),
            node_sky: std::mem::take(&mut state.node_sky),
            node_gain: std::mem::take(&mut state.node_gain),
            node_b: snap.node_b.clone(),
            node_h: snap.node_h.clone(),
            cluster_b: snap.cluster_b.clone(),
            cluster_n: snap.cluster_n.clone(),
            cluster_h: snap.cluster_h.clone(),
            cluster_q: snap.cluster_q.clone(),
        };
        links = snap.links.iter().copied().map(Link::from_bits).collect();
        (splits, peak) = (snap.splits.clone(), snap.peak);
        state.bury(mesh, &clusters, &links);
        (out.iterations, out.residual) = (it.iterations, it.residual);
        (out.refine_seconds, out.solve_seconds) = snap.seconds;
        out.history.clone_from(&snap.history);
        clock = snap.history.last().map_or(0.0, |h| h.seconds);
        done = snap.passes;
        last = Some(it);
    }
    let passes = STAGES + FINAL_PASSES + DISPLAY_PASSES;
    progress.start("hierarchical", Work::of(u64::from(passes) + 1, "passes"));
    progress.advance(u64::from(done));
    'passes: for pass in done..passes {
        let stage = pass.min(STAGES - 1);
        let threshold = epsilon * 4f64.powi((STAGES - 1 - stage) as i32) * peak_power;
        let display = pass >= STAGES + FINAL_PASSES;
        let force = if display {
            gradient_receivers(mesh, &state)
        } else {
            Vec::new()
        };
        // Refine until no leaf needs splitting, reporting the links examined (the stop
        // question is asked before each).
        let start = Instant::now();
        progress.phase(
            &format!("pass {}/{passes}, refining", pass + 1),
            Work::open_ended("links"),
        );
        let examined = Batched::new(progress, LINK_BATCH);
        let mut first = pass == 0;
        let mut refined = 0;
        loop {
            if control.stopped() {
                out.interrupted = true;
                break 'passes;
            }
            let (node_b, cluster_b) = brightness(&state);
            let node_spread = spread(mesh, &node_b);
            let oracle = Oracle {
                threshold,
                min_area,
                node_b: &node_b,
                node_spread: &node_spread,
                cluster_b: &cluster_b,
            };
            let view = View::new(mesh, &clusters, bvh);
            let stop = || {
                examined.one();
                control.stopped()
            };
            let round = if first {
                refine::start(&view, &oracle, &stop)
            } else {
                refine::round(
                    &view,
                    &oracle,
                    &links,
                    if display { &force } else { &[] },
                    &stop,
                )
            };
            if control.stopped() {
                // The round was cut short: keep the links and mesh of the last whole one.
                out.interrupted = true;
                break 'passes;
            }
            first = false;
            refined += round.refined;
            peak = peak.max(memory(mesh, &clusters, links.len() + round.links.len()));
            links = round.links;
            let mut leaves = round.splits;
            if !display {
                // Elements that take too much of the environment's or the luminaires' light
                // ([`distant`], [`crate::solve::first_shot`]).
                leaves.extend(distant::split_lit(
                    mesh,
                    &state.node_sky,
                    threshold,
                    min_area,
                ));
                leaves.sort_unstable();
                leaves.dedup();
            }
            if leaves.is_empty() {
                break;
            }
            mesh.refine(&leaves);
            state.grow(mesh, bvh);
            splits.extend_from_slice(&leaves);
            refined += leaves.len() as u64;
            if display {
                // Forced receivers are split once; their children are judged by the oracle.
                break;
            }
        }
        links.sort_unstable_by_key(|l| (l.receiver, l.source));
        state.bury(mesh, &clusters, &links);
        out.refine_seconds += start.elapsed().as_secs_f64();
        drop(examined);
        // Solve from the current radiosity, unless the links did not change.
        let start = Instant::now();
        progress.phase(
            &format!("pass {}/{passes}, gathering", pass + 1),
            Work::open_ended("iterations"),
        );
        while (pass == 0 || refined > 0) && out.iterations < settings.max_iterations {
            if control.stopped() {
                out.interrupted = true;
                out.solve_seconds += start.elapsed().as_secs_f64();
                break 'passes;
            }
            let change = state.iterate(mesh, &clusters, &links);
            progress.advance(1);
            out.record(change / reference, clock + began.elapsed().as_secs_f64());
            if out.residual < settings.tolerance {
                break;
            }
        }
        out.solve_seconds += start.elapsed().as_secs_f64();
        if session.saving() {
            let snap = Hierarchy {
                passes: pass + 1,
                splits: splits.clone(),
                links: links.iter().map(Link::to_bits).collect(),
                node_b: state.node_b.clone(),
                node_h: state.node_h.clone(),
                cluster_b: state.cluster_b.clone(),
                cluster_n: state.cluster_n.clone(),
                cluster_h: state.cluster_h.clone(),
                cluster_q: state.cluster_q.clone(),
                history: out.history.clone(),
                seconds: (out.refine_seconds, out.solve_seconds),
                peak,
            };
            let it = Iterate {
                iterations: out.iterations,
                residual: out.residual,
                hierarchy: Some(snap),
                ..Iterate::default()
            };
            session.after_iteration(false, || it.clone());
            last = Some(it);
        }
    }
    let rows = if out.interrupted {
        None
    } else {
        let seconds = || clock + began.elapsed().as_secs_f64();
        let problem = (mesh as &Mesh, bvh, &clusters, links.as_slice());
        progress.phase("leaf solve", Work::of(1, "solves"));
        let rows = leaf_solve(
            problem, &mut state, emitted, settings, control, &seconds, &mut out,
        );
        progress.advance(1);
        rows
    };
    if let Some(rows) = &rows {
        peak = peak.max(memory(mesh, &clusters, links.len()) + rows.bytes());
    }
    if let Some(it) = last.filter(|_| out.interrupted) {
        session.after_iteration(true, || it);
    }
    progress.tally(mesh.element_count() as u64, "elements");
    progress.tally(links.len() as u64, "links");
    progress.tally(out.iterations as u64, "iterations");
    progress.end(out.interrupted);
    out.irradiance = state.element_irradiance(mesh);
    let direct = state.emitted_irradiance(mesh, &clusters, &links, rows.as_ref());
    out.reflected_irradiance = out
        .irradiance
        .iter()
        .zip(&direct)
        .map(|(&h, &d)| h - d)
        .collect();
    out.stats.links = links.len() as u64;
    out.stats.levels = mesh
        .elements
        .iter()
        .map(|&n| u32::from(mesh.nodes[n as usize].level) + 1)
        .max()
        .unwrap_or(0);
    out.stats.peak_memory_bytes = peak;
    out.node_radiosity = state.node_b;
    Ok(out)
}

/// The last stage: the settled links solved again through every element's own row
/// ([`leaf_rows`]), from the push-pull solution, to the same tolerance; as many links go
/// through the rows as the matrix budget (`max_matrix_bytes`) holds, the rest are pushed.
/// Skipped (`None`) when no iteration is left; a stop during it sets `out.interrupted`
/// and leaves the last iterate. `emitted` scales the residual as in the passes, `seconds` is
/// the run's clock for the history.
fn leaf_solve(
    (mesh, bvh, clusters, links): (&Mesh, &Bvh, &Clusters, &[Link]),
    state: &mut State,
    emitted: f64,
    settings: &super::Settings,
    control: &Control,
    seconds: &dyn Fn() -> f64,
    out: &mut Outcome,
) -> Option<LeafRows> {
    let began = Instant::now();
    if links.is_empty() || out.iterations >= settings.max_iterations {
        return None;
    }
    let view = View::new(mesh, clusters, bvh);
    let rowed = LeafRows::rowed(mesh, clusters, links, settings.max_matrix_bytes);
    let Some(rows) = LeafRows::build(&view, links, rowed, &|| control.stopped()) else {
        out.interrupted = true;
        return None;
    };
    let pushed = state.link_rows(mesh, clusters, links, Some(rows.links()));
    let sums: Vec<f64> = pushed.iter().zip(rows.sums()).map(|(a, b)| a + b).collect();
    state.bury_rows(mesh, &sums);
    out.refine_seconds += began.elapsed().as_secs_f64();
    let start = Instant::now();
    while out.iterations < settings.max_iterations {
        if control.stopped() {
            out.interrupted = true;
            break;
        }
        let change = state.iterate_rows(mesh, clusters, links, &rows);
        out.record(change / emitted, seconds());
        if out.residual < settings.tolerance {
            break;
        }
    }
    out.solve_seconds += start.elapsed().as_secs_f64();
    Some(rows)
}

/// The area of the patches that reflect light (ρ > 0 on some channel), or of all when none
/// does: what the default minimum element area is a fraction of. An environment's far cube,
/// 10³–10⁶ times the scene's area, would otherwise set it (a 6 × 4 × 3 m room under a map
/// could not have elements below 0.37 m²).
fn reflecting_area(mesh: &Mesh) -> f64 {
    let area: f64 = mesh
        .patches
        .iter()
        .filter(|p| p.reflectance.max_element() > 0.0)
        .map(|p| p.area)
        .sum();
    if area > 0.0 {
        area
    } else {
        mesh.total_area()
    }
}

/// The largest channel of B of every node and cluster, for the oracle.
fn brightness(state: &State) -> (Vec<f64>, Vec<f64>) {
    let max = |b: &Vec<Rgb>| b.iter().map(|b| b.max_element()).collect();
    (max(&state.node_b), max(&state.cluster_b))
}

/// For every mesh node, max − min of `b` over the leaves below it (0 for a leaf). Parents
/// precede their children in the arena, so one backward pass suffices.
fn spread(mesh: &Mesh, b: &[f64]) -> Vec<f64> {
    let (mut lo, mut hi) = (b.to_vec(), b.to_vec());
    for n in (0..mesh.nodes.len()).rev() {
        if let Some(c) = mesh.nodes[n].children {
            lo[n] = (c..c + 4)
                .map(|k| lo[k as usize])
                .fold(f64::INFINITY, f64::min);
            hi[n] = (c..c + 4)
                .map(|k| hi[k as usize])
                .fold(f64::NEG_INFINITY, f64::max);
        }
    }
    hi.iter().zip(&lo).map(|(h, l)| h - l).collect()
}

/// Elements whose radiosity differs from a sibling's by more than [`GRADIENT`] of the
/// brightest reflected radiosity B − E of any element (largest channel), sorted. Emission is
/// left out of the scale: a light source is far brighter than anything it lights, and would
/// hide every shadow boundary.
fn gradient_receivers(mesh: &Mesh, state: &State) -> Vec<Handle> {
    let brightest = mesh
        .elements
        .iter()
        .map(|&n| {
            let emission = mesh.patches[mesh.nodes[n as usize].patch as usize].emission;
            (state.node_b[n as usize] - emission).max_element()
        })
        .fold(0.0, f64::max);
    let limit = GRADIENT * brightest;
    let mut out = Vec::new();
    for node in &mesh.nodes {
        let Some(c) = node.children else { continue };
        for k in c..c + 4 {
            if mesh.nodes[k as usize].children.is_some() {
                continue;
            }
            let b = state.node_b[k as usize];
            let steep =
                (c..c + 4).any(|j| (state.node_b[j as usize] - b).abs().max_element() > limit);
            if steep {
                out.push(Handle::node(k));
            }
        }
    }
    out.sort_unstable();
    out
}

/// Bytes held by the hierarchy with `links` links alive.
fn memory(mesh: &Mesh, clusters: &Clusters, links: usize) -> u64 {
    mesh.nodes.len() as u64 * BYTES_PER_NODE
        + clusters.nodes.len() as u64 * BYTES_PER_CLUSTER
        + clusters.table_bytes()
        + links as u64 * std::mem::size_of::<Link>() as u64
}
