//! Solvers: bringing the radiosity equation to equilibrium.
//!
//! With receivers i (the elements) and sources j (a cut through the element quadtrees, see
//! [`crate::mesh::Mesh::sources`]), the discrete radiosity equation is
//!
//! ```text
//! B_i = E_i + ρ_i Σ_j F_ij B̄_j ,     B̄_j = Σ_{i ∈ j} A_i B_i / A_j
//! ```
//!
//! (Goral et al. 1984): a source shoots the area-weighted mean radiosity of its elements, which
//! is the substructuring of Cohen, Greenberg, Immel & Brock 1986. With as many sources as
//! elements it is the classic n × n system. Four ways to solve it:
//!
//! - [`Method::Jacobi`] ([`jacobi`]): gather into a new vector from the old one, all elements in
//!   parallel, with the form factors stored in a [`matrix::Matrix`].
//! - [`Method::GaussSeidel`] ([`gauss_seidel`]): gather in place, each element seeing the
//!   updates already made in the same sweep; about twice as fast to converge, one thread.
//! - [`Method::Progressive`] ([`progressive`]): shoot the source with the most unshot power,
//!   computing one column of form factors on the fly (Cohen, Chen, Wallace & Greenberg 1988):
//!   no n² storage, and a usable picture after a few shots.
//! - [`Method::Hierarchical`] ([`hierarchical`]): links between clusters and quadtree nodes
//!   only as fine as the light they carry (Hanrahan, Salzman & Aupperle 1991; Smits, Arvo &
//!   Greenberg 1994), refining the elements on demand: near-linear in the elements.
//!
//! # Residual
//!
//! All four report the same measure: the power that the last step still had to move, relative
//! to the emitted power,
//!
//! ```text
//! r = Σ_i A_i ‖ΔB_i‖₁ / Σ_i A_i ‖E_i‖₁     (‖·‖₁ sums the three channels)
//! ```
//!
//! where ΔB is the change of the last sweep for the gathering methods (B^{k+1} − B^k, which from
//! B⁰ = E is exactly the light of bounce k + 1) and the unshot radiosity of every source for
//! progressive refinement. Both are the power not yet distributed, so r = 1 before any work and
//! the solvers stop when r < [`Settings::tolerance`]. In a scene of reflectance ρ the error left
//! in the total power is about r·ρ/(1 − ρ) of the emitted power.
//!
//! # Interruption
//!
//! [`solve_controlled`] takes a [`checkpoint::Control`]: a stop flag checked between
//! iterations (the solution so far is returned, marked [`Solution::interrupted`]), periodic
//! checkpoints, and a checkpoint to resume from (see [`checkpoint`]).

mod balance;
pub mod checkpoint;
pub mod first_shot;
mod gathering;
pub mod gauss_seidel;
pub mod hierarchical;
pub mod jacobi;
pub mod matrix;
pub mod opened_sources;
pub mod plan;
pub mod progressive;
mod solver;

use std::ops::Range;

use rayon::prelude::*;

use crate::formfactor::{FormFactors, Geometry};
use crate::mesh::Mesh;
use crate::progress::Progress;
use crate::registry::registry;
use crate::Rgb;

registry! {
    /// The solvers: the registry of the family. Adding one is a file with its `solver::Solver`
    /// and a line here, whose doc comment is its help on the command line; the compiler then
    /// asks for its arm in `Method::solver`.
    #[derive(Default)]
    pub enum Method {
        /// Jacobi iteration (gathering).
        Jacobi = "jacobi",
        /// Gauss-Seidel iteration (gathering).
        #[default]
        GaussSeidel = "gauss-seidel",
        /// Progressive refinement (shooting).
        Progressive = "progressive",
        /// Hierarchical radiosity with clustering; refines the elements on demand (`--epsilon`,
        /// `--min-element-area`).
        Hierarchical = "hierarchical",
    }
    /// An unknown solver name.
    pub struct UnknownMethod = "unknown solver";
}

impl Method {
    /// The solver of this method.
    fn solver(self) -> &'static dyn solver::Solver {
        match self {
            Method::Jacobi => &jacobi::Jacobi,
            Method::GaussSeidel => &gauss_seidel::GaussSeidel,
            Method::Progressive => &progressive::Progressive,
            Method::Hierarchical => &hierarchical::Hierarchical,
        }
    }
}

/// Solver options, for every [`Method`] (the method itself is an argument of [`solve`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Stop when the residual (see the module documentation) falls below this.
    pub tolerance: f64,
    /// Stop after this many sweeps (gathering) or shots (progressive) in any case.
    pub max_iterations: usize,
    /// Largest form-factor matrix the gathering solvers may allocate, in bytes.
    pub max_matrix_bytes: u64,
    /// Most sources the caller should cut the quadtrees into ([`crate::mesh::Mesh::sources`]);
    /// the matrix is elements × sources.
    pub max_sources: usize,
    /// Hierarchical solver: a link is refined while it moves more than this fraction of the
    /// emitted power; positive ([`DEFAULT_EPSILON`] by default).
    pub epsilon: f64,
    /// Hierarchical solver: the smallest element area refinement may create, in scene units²,
    /// positive; `None` for a millionth of the area that reflects light ([`hierarchical::MIN_AREA_FRACTION`]).
    pub min_element_area: Option<f64>,
}

/// The hierarchical solver's default ε (see [`Settings::epsilon`]), measured on the built-in
/// Cornell box: see `docs/hierarchical.md`.
pub const DEFAULT_EPSILON: f64 = 1e-4;

impl Default for Settings {
    /// Gauss-Seidel to a residual of 10⁻⁴, a 1 GiB matrix at most (16 384² form factors) and
    /// 8192 sources. Measured on the built-in Cornell box at 3792 elements with the default
    /// form factors (release build, 2 threads): Gauss-Seidel takes 9 sweeps (0.13 s) and
    /// Jacobi 15 (0.21 s) after 19 s of form factors; progressive refinement needs 23 654 shots
    /// and 121 s to reach the same residual, because it recomputes a column per shot and must
    /// shoot every source once per bounce. At 10⁻⁴ the power still unaccounted for is below
    /// what the form factors' own error (0.2 %) leaves.
    fn default() -> Self {
        Self {
            tolerance: 1e-4,
            max_iterations: 100_000,
            max_matrix_bytes: 1 << 30,
            max_sources: 8192,
            epsilon: DEFAULT_EPSILON,
            min_element_area: None,
        }
    }
}

/// One point of a solve's convergence history.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Sweeps, shots or gather iterations done.
    pub iteration: usize,
    /// Seconds since the iterations began.
    pub seconds: f64,
    /// The residual after them (the module documentation's definition).
    pub residual: f64,
}

/// The result of a solve.
#[derive(Clone, Debug)]
pub struct Solution {
    /// Radiosity B per element, W·m⁻² per channel (progressive: without the ambient term).
    pub radiosity: Vec<Rgb>,
    /// Irradiance H per element, the light each element gathered (B = E + ρH): what the
    /// absorbed power Σ A (1 − ρ) H is made of, also where ρ = 0 says nothing of it.
    pub irradiance: Vec<Rgb>,
    /// The part of `irradiance` that came from other surfaces' reflected light, Σ_s F_es
    /// (B̄_s − Ē_s): the irradiance less the light straight from the emitters, through the same
    /// form factors, so that the error of those form factors (shadow rays in penumbrae) stays
    /// in the direct part, which the evaluated picture recomputes exactly
    /// (`render::evaluated`). `None` where the solver does not keep it (progressive
    /// refinement; hierarchical radiosity keeps it for its refined mesh, [`Refined`]).
    pub reflected_irradiance: Option<Vec<Rgb>>,
    /// The solver used.
    pub method: Method,
    /// Sweeps (gathering) or shots (progressive) done.
    pub iterations: usize,
    /// The final residual (see the module documentation).
    pub residual: f64,
    /// Non-zero form factors used: stored (gathering) or computed over all shots (progressive).
    pub links: u64,
    /// Progressive refinement's ambient term (Cohen et al. 1988): the unshot power spread
    /// evenly, times the mean interreflection 1/(1 − ρ̄). For display only, add ρ_i · ambient to
    /// B_i; zero for the gathering methods.
    pub ambient: Rgb,
    /// Time spent computing form factors, in seconds.
    pub form_factor_seconds: f64,
    /// Time spent solving apart from form factors, in seconds.
    pub solve_seconds: f64,
    /// The hierarchical solver's links, levels and memory (`None` for the others).
    pub hierarchy: Option<crate::stats::HierarchyStats>,
    /// Convergence: a [`Sample`] after each sweep, shot or gather iteration.
    pub history: Vec<Sample>,
    /// Whether the solve was stopped (see [`checkpoint::Control::stop`]) before it converged:
    /// the radiosity is then the last iterate, or E when the form factors were not complete.
    pub interrupted: bool,
    /// The mesh the solver refined, for a solver that refines it (hierarchical radiosity),
    /// with the solution on its own elements; `radiosity` and `irradiance` above are then the
    /// given elements' means of it. See [`Solution::on_finest`].
    pub refined: Option<Box<Refined>>,
}

/// A mesh refined by the solver, and the solution on its elements.
#[derive(Clone, Debug)]
pub struct Refined {
    /// The refined mesh: the given one's nodes keep their ids, with children below.
    pub mesh: Mesh,
    /// Radiosity B per element of `mesh`.
    pub radiosity: Vec<Rgb>,
    /// Irradiance H per element of `mesh`.
    pub irradiance: Vec<Rgb>,
    /// Its part from reflected light (see [`Solution::reflected_irradiance`]).
    pub reflected_irradiance: Option<Vec<Rgb>>,
}

impl Solution {
    /// The solution on the finest mesh there is: the refined mesh with its own elements'
    /// radiosity and irradiance when the solver refined `given`, else `given` itself.
    #[must_use]
    pub fn on_finest(mut self, given: Mesh) -> (Mesh, Self) {
        match self.refined.take() {
            Some(refined) => {
                let Refined {
                    mesh,
                    radiosity,
                    irradiance,
                    reflected_irradiance,
                } = *refined;
                self.radiosity = radiosity;
                self.irradiance = irradiance;
                self.reflected_irradiance = reflected_irradiance;
                (mesh, self)
            }
            None => (given, self),
        }
    }
}

/// Why a solve failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// The stored form-factor matrix would exceed the memory limit.
    #[error(
        "the form-factor matrix needs {} MiB, more than the limit of {} MiB (max_matrix_bytes)",
        mib(*bytes),
        mib(*limit)
    )]
    MatrixTooLarge {
        /// Bytes the matrix would take.
        bytes: u64,
        /// The limit in force.
        limit: u64,
    },
    /// The checkpoint to resume from was made by another solver, scene or settings.
    #[error("the checkpoint does not belong to this run: {0}")]
    CheckpointMismatch(String),
    /// A setting outside its range.
    #[error("{name} must be positive and finite, not {value}")]
    NotPositive {
        /// The setting's name in [`Settings`].
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// The sources are not a cut through the quadtrees.
    #[error("the sources do not cover element {element} exactly once")]
    BadSources {
        /// The first element covered by no source or by two.
        element: usize,
    },
}

/// Bytes in MiB, rounded up.
fn mib(bytes: u64) -> u64 {
    bytes.div_ceil(1 << 20)
}

/// Solves the radiosity equation on `g` by `method`, with form factors from `ff`.
///
/// A scene that emits nothing (or has no elements) is solved at once: B = 0, zero iterations,
/// no form factors computed.
///
/// # Errors
/// [`SolveError::MatrixTooLarge`] when a gathering solver's matrix would exceed
/// `settings.max_matrix_bytes` (checked before anything is allocated), and
/// [`SolveError::BadSources`] when `g.sources` is not a cut through the quadtrees.
pub fn solve(
    g: &Geometry,
    ff: &dyn FormFactors,
    method: Method,
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<Solution, SolveError> {
    let control = checkpoint::Control::default();
    solve_controlled(g, ff, method, settings, &control, progress)
}

/// [`solve`] under `control`: stopping early, saving checkpoints, resuming from one (see
/// [`checkpoint`]).
///
/// # Errors
/// Those of [`solve`]; [`SolveError::CheckpointMismatch`] when the checkpoint to resume from
/// was made for another system or method.
pub fn solve_controlled(
    g: &Geometry,
    ff: &dyn FormFactors,
    method: Method,
    settings: &Settings,
    control: &checkpoint::Control,
    progress: &dyn Progress,
) -> Result<Solution, SolveError> {
    let system = System::new(g)?;
    let mut solution = Solution {
        radiosity: system.emission.clone(),
        irradiance: vec![Rgb::ZERO; system.area.len()],
        reflected_irradiance: None,
        method,
        iterations: 0,
        residual: 0.0,
        links: 0,
        ambient: Rgb::ZERO,
        form_factor_seconds: 0.0,
        solve_seconds: 0.0,
        hierarchy: None,
        history: Vec::new(),
        interrupted: false,
        refined: None,
    };
    if system.emitted <= 0.0 || !system.emitted.is_finite() {
        return Ok(solution);
    }
    let job = solver::Job {
        g,
        ff,
        method,
        settings,
        control,
        progress,
        system,
    };
    method.solver().solve(job, &mut solution)?;
    Ok(solution)
}

/// What an iterative solver returns.
pub(crate) struct Run {
    radiosity: Vec<Rgb>,
    iterations: usize,
    residual: f64,
    /// A sample after each sweep.
    history: Vec<Sample>,
    /// Whether the session was stopped before convergence.
    interrupted: bool,
}

/// The linear system in solver-friendly arrays.
pub(crate) struct System {
    /// Area of each element.
    area: Vec<f64>,
    /// ρ of each element.
    reflectance: Vec<Rgb>,
    /// The light each element starts with: its emission E plus the first shot ρ H_ℓ of the
    /// point luminaires ([`first_shot`]).
    emission: Vec<Rgb>,
    /// H_ℓ of each element, the irradiance of the luminaires' first shot.
    first_shot: Vec<Rgb>,
    /// Source (index into the sources) of each element.
    source_of: Vec<u32>,
    /// Elements of each source.
    source_elements: Vec<Range<usize>>,
    /// Open fraction u of each element ([`crate::formfactor::exposure`]).
    exposure: Vec<f64>,
    /// Open area of each source: Σ A_e u_e over its elements.
    source_area: Vec<f64>,
    /// Emitted power of each source's buried parts, Σ A_e (1 − u_e) E_e, which its open part
    /// does not shine.
    hidden_emission: Vec<Rgb>,
    /// The open area Σ A_e u_e and the hidden emission Σ A_e (1 − u_e) E_e of the elements
    /// before each element (and of all of them, last): an opened piece's are differences.
    open_before: Vec<f64>,
    hidden_before: Vec<Rgb>,
    /// The weights of each element's row (what it gathers) and each source's column (what it
    /// shines), from [`balance`]; 1 unless [`System::balance`] is called.
    weights: balance::Weights,
    /// Σ A ‖E‖₁, the denominator of the residual.
    emitted: f64,
}

impl System {
    fn new(g: &Geometry) -> Result<Self, SolveError> {
        let mesh = g.mesh;
        let n = mesh.element_count();
        let area: Vec<f64> = (0..n).map(|e| mesh.element(e).area()).collect();
        let reflectance = (0..n).map(|e| mesh.element_patch(e).reflectance).collect();
        let first_shot = first_shot::irradiance(mesh, g.bvh, &mesh.elements);
        let emission: Vec<Rgb> = (0..n)
            .map(|e| {
                let patch = mesh.element_patch(e);
                patch.emission + patch.reflectance * first_shot[e]
            })
            .collect();
        let mut source_of = vec![u32::MAX; n];
        let mut source_elements = Vec::with_capacity(g.sources.len());
        for (s, &node) in g.sources.iter().enumerate() {
            let range = mesh.nodes[node as usize].elements.clone();
            let range = range.start as usize..range.end as usize;
            for e in range.clone() {
                if source_of[e] != u32::MAX {
                    return Err(SolveError::BadSources { element: e });
                }
                source_of[e] = s as u32;
            }
            source_elements.push(range);
        }
        if let Some(e) = source_of.iter().position(|&s| s == u32::MAX) {
            return Err(SolveError::BadSources { element: e });
        }
        let emitted = power(&area, &emission);
        let mut system = Self {
            exposure: vec![1.0; n],
            area,
            reflectance,
            emission,
            first_shot,
            source_of,
            source_elements,
            source_area: Vec::new(),
            hidden_emission: Vec::new(),
            open_before: Vec::new(),
            hidden_before: Vec::new(),
            weights: balance::Weights::none(n, g.sources.len()),
            emitted,
        };
        system.weigh_sources();
        Ok(system)
    }

    /// H_e = H_ℓ,e + Σ_s F_es B̄_s for every element, with the source means of `b`: the light
    /// each element takes from the luminaires' first shot and gathers from the solution `b`
    /// through the matrix the solve used.
    fn irradiance(&self, matrix: &matrix::Matrix, b: &[Rgb]) -> Vec<Rgb> {
        let mut shine = Shine::default();
        self.shine(b, &mut shine);
        (0..b.len())
            .map(|e| self.first_shot[e] + self.gather(matrix, e, &shine))
            .collect()
    }

    /// The emission E of each element alone, without the luminaires' first shot.
    fn emitted_only(&self) -> Vec<Rgb> {
        self.emission
            .iter()
            .zip(&self.reflectance)
            .zip(&self.first_shot)
            .map(|((&e, &rho), &h)| e - rho * h)
            .collect()
    }

    /// The open area and hidden emission of every source, from the elements' exposure (the
    /// buried parts emit, but the luminaires do not reach them).
    fn weigh_sources(&mut self) {
        let emission = self.emitted_only();
        let (area, exposure, emission) = (&self.area, &self.exposure, &emission);
        let hidden = |e: usize| emission[e] * (area[e] * (1.0 - exposure[e]));
        self.source_area = self
            .source_elements
            .iter()
            .map(|r| r.clone().map(|e| area[e] * exposure[e]).sum())
            .collect();
        self.hidden_emission = self
            .source_elements
            .iter()
            .map(|r| r.clone().map(hidden).sum())
            .collect();
        self.open_before = running_sum((0..area.len()).map(|e| area[e] * exposure[e]));
        self.hidden_before = running_sum((0..area.len()).map(hidden));
    }

    /// Reads the elements' exposure for gathering: the probes of
    /// [`crate::formfactor::exposure`], never below the element's row sum Σ_s F_es (an element
    /// cannot receive from more than its open part, and with u ≥ Σ F the gain ρ Σ F / u of every
    /// element stays below 1, so the iteration converges however the probes and the shadow
    /// rays disagree), and 0 where the row is all zero: such an element sees nothing at all, as
    /// the floor under a block standing on it. (The Cornell box with each block face an object
    /// at 60 000 elements, whose sources the memory budget keeps coarse: the blocks' sides next
    /// to the floor were 2.6 % dark while a source straddling the footprint shone its
    /// whole-area mean.)
    fn bury(&mut self, g: &Geometry, matrix: &matrix::Matrix) {
        let probed = crate::formfactor::exposure::exposure(g);
        for (e, u) in self.exposure.iter_mut().enumerate() {
            let row = matrix.row_sum(e);
            *u = if self.emission[e] == Rgb::ZERO && row == 0.0 {
                0.0
            } else {
                probed[e].max(row).min(1.0)
            };
        }
        self.weigh_sources();
    }

    /// Weighs every source's column so that it gives away what its own rows send, and every
    /// row back to its sum ([`balance`]).
    fn balance(&mut self, matrix: &matrix::Matrix) {
        self.weights = balance::weights(matrix, &self.area, &self.source_of);
    }

    /// The share of element `e`'s radiosity in what its source shines, w_s A_e / Σ A u.
    fn share(&self, e: usize) -> f64 {
        let s = self.source_of[e] as usize;
        if self.source_area[s] > 0.0 {
            self.weights.column[s] * self.area[e] / self.source_area[s]
        } else {
            0.0
        }
    }

    /// What the sources shine with the radiosities `b`, into `out`: the radiosity each shared
    /// source shines from its open part, with B the whole-area means of its elements (E on
    /// their buried parts),
    ///
    /// ```text
    /// B̄_s = w_s (Σ_e A_e B_e − Σ_e A_e (1 − u_e) E_e) / Σ_e A_e u_e ,
    /// ```
    ///
    /// the substructuring mean of Cohen et al. 1986 taken over the open area only (see
    /// [`crate::formfactor::exposure`]), times its column's weight w_s ([`balance`]); and the
    /// running sums of A_e B_e from which the same mean of an opened piece is read (and
    /// weighed by its source's w_s in [`System::gather`]). Means in parallel, each a sequential sum, so the
    /// result does not depend on the thread count.
    fn shine(&self, b: &[Rgb], out: &mut Shine) {
        let w = &self.weights.column;
        out.sources.resize(self.source_area.len(), Rgb::ZERO);
        out.sources
            .par_iter_mut()
            .enumerate()
            .for_each(|(s, mean)| {
                let range = self.source_elements[s].clone();
                let sum: Rgb = range.map(|e| b[e] * self.area[e]).sum();
                *mean = if self.source_area[s] > 0.0 {
                    (sum - self.hidden_emission[s]) * w[s] / self.source_area[s]
                } else {
                    Rgb::ZERO
                };
            });
        out.before = running_sum(b.iter().zip(&self.area).map(|(&b, &a)| b * a));
    }

    /// H_e = x_e (Σ_s F_es B̄_s + Σ_p w_s(p) F_ep B̄_p): the light element `e` gathers from
    /// the shared sources and from the pieces of those it opened, with the weights of
    /// [`balance`].
    fn gather(&self, matrix: &matrix::Matrix, e: usize, shine: &Shine) -> Rgb {
        let shared = matrix
            .row(e)
            .iter()
            .zip(&shine.sources)
            .fold(Rgb::ZERO, |acc, (&f, &m)| acc + m * f64::from(f));
        let gathered = matrix.pieces(e).iter().fold(shared, |acc, p| {
            let (a, b) = (p.elements.start as usize, p.elements.end as usize);
            let open = self.open_before[b] - self.open_before[a];
            if open > 0.0 {
                let power = shine.before[b]
                    - shine.before[a]
                    - (self.hidden_before[b] - self.hidden_before[a]);
                let weight = self.weights.column[self.source_of[a] as usize];
                acc + power * (weight * f64::from(p.factor) / open)
            } else {
                acc
            }
        });
        gathered * self.weights.row[e]
    }

    /// The residual of a change from `old` to `new`: Σ A ‖new − old‖₁ / Σ A ‖E‖₁.
    fn residual(&self, old: &[Rgb], new: &[Rgb]) -> f64 {
        let sum: f64 = old
            .iter()
            .zip(new)
            .zip(&self.area)
            .map(|((a, b), area)| area * l1(*b - *a))
            .sum();
        sum / self.emitted
    }
}

/// What the sources shine in a sweep ([`System::shine`]).
#[derive(Debug, Default)]
pub(crate) struct Shine {
    /// The mean radiosity each shared source shines from its open part.
    pub sources: Vec<Rgb>,
    /// Σ A_e B_e over the elements before each element (and over all, last).
    pub before: Vec<Rgb>,
}

/// The sums of `x` before each item, and of all of them last.
fn running_sum<T: Copy + Default + std::ops::Add<Output = T>>(
    x: impl Iterator<Item = T>,
) -> Vec<T> {
    let mut sum = T::default();
    let mut out = vec![sum];
    for v in x {
        sum = sum + v;
        out.push(sum);
    }
    out
}

/// Σ A ‖x‖₁.
fn power(area: &[f64], x: &[Rgb]) -> f64 {
    area.iter().zip(x).map(|(a, x)| a * l1(*x)).sum()
}

/// Sum of the absolute values of the channels.
fn l1(x: Rgb) -> f64 {
    x.abs().element_sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_method_is_named_parsed_and_has_a_solver() {
        let err = "wavelet".parse::<Method>().unwrap_err().to_string();
        assert!(err.starts_with("unknown solver `wavelet` (choose "));
        for m in Method::ALL {
            assert_eq!(m.name().parse::<Method>(), Ok(m));
            assert!(err.contains(m.name()), "{err}");
            let shape = m.solver().checkpoint_shape(7);
            assert!(shape.radiosity == 7 || shape.hierarchy, "{m}: {shape:?}");
        }
    }

    #[test]
    fn buried_elements_leave_their_sources_mean() {
        // The Cornell box at 1 024 elements and 64 sources: the floor under the blocks sees
        // nothing (all-zero rows), so it is weighed out of its sources' means; the exposure
        // probes find it buried too, partly along the footprints, and nothing else.
        let scene = crate::scene::builtin::load("cornell").unwrap().unwrap();
        let p = crate::testing::Prepared::new(&scene, crate::mesh::Subdivision::Elements(1024), 64);
        let g = p.geometry();
        let ff = crate::formfactor::build(&crate::formfactor::Settings::default());
        let matrix =
            matrix::Matrix::compute(&g, ff.as_ref(), u64::MAX, &crate::progress::Silent).unwrap();
        let system = System::new(&g).unwrap();
        let mut gathering = System::new(&g).unwrap();
        gathering.bury(&g, &matrix);
        let dark: Vec<usize> = (0..system.area.len())
            .filter(|&e| matrix.row_sum(e) == 0.0)
            .collect();
        assert!(!dark.is_empty());
        for e in 0..system.area.len() {
            if dark.contains(&e) {
                assert_eq!(gathering.exposure[e], 0.0);
            }
            if gathering.exposure[e] < 1.0 {
                assert_eq!(
                    g.mesh.element_patch(e).object,
                    0,
                    "only floor elements are buried"
                );
            }
        }
        let partly = gathering.exposure.iter().filter(|&&u| u > 0.0 && u < 1.0);
        assert!(partly.count() > 0);
        // An open radiosity of 1 everywhere (the whole-area means are then B_e = u_e, the
        // scene's only emitter being wholly open) gives means of 1 wherever a source is open.
        let b: Vec<Rgb> = gathering
            .exposure
            .iter()
            .zip(&gathering.emission)
            .map(|(&u, &e)| {
                if e == Rgb::ZERO {
                    Rgb::splat(u)
                } else {
                    Rgb::ONE
                }
            })
            .collect();
        let mut shine = Shine::default();
        gathering.shine(&b, &mut shine);
        for (s, m) in shine.sources.iter().enumerate() {
            if gathering.source_area[s] > 0.0 {
                assert!((*m - Rgb::ONE).abs().max_element() < 1e-12);
            }
        }
        assert!(gathering.source_area.iter().sum::<f64>() < system.source_area.iter().sum::<f64>());
    }

    #[test]
    fn matrix_error_names_the_sizes_and_the_setting() {
        let e = SolveError::MatrixTooLarge {
            bytes: 3 << 30,
            limit: 1 << 30,
        };
        let msg = e.to_string();
        assert!(
            msg.contains("max_matrix_bytes") && !msg.contains("--"),
            "{msg}"
        );
        assert!(
            msg.contains("3072 MiB") && msg.contains("1024 MiB"),
            "{msg}"
        );
    }
}
