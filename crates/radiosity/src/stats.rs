//! The statistics file (`--stats`): a public JSON contract (its fields are documented below).
//!
//! ```json
//! { "patches": 34, "elements": 4096, "links": 1234567,
//!   "solver": { "method": "gauss-seidel", "iterations": 12, "residual": 8e-5 },
//!   "timings": { "load": 0.001, "mesh": 0.01, "form_factors": 1.2, "solve": 0.1,
//!                "render": 0.2, "total": 1.5 },
//!   "energy": { "emitted": [r, g, b], "absorbed": [r, g, b],
//!               "emitted_w": [r, g, b], "absorbed_w": [r, g, b],
//!               "emitted_lm": 3141.6, "absorbed_lm": 3141.0 },
//!   "objects": [ { "name": "floor", "area": 309.4e3, "radiosity": [r, g, b] },
//!                { "name": "sheet", "area": 1.0, "radiosity": [..], "front": [..], "back": [..] } ],
//!   "materials": [ { "name": "white", "area": ..., "radiosity": [r, g, b] } ],
//!   "hierarchy": { "links": 52000, "levels": 7, "clusters": 15, "peak_memory_bytes": 4e6 } }
//! ```
//!
//! Units: seconds; watts per channel when lengths are metres (scene units² × W·m⁻² in general);
//! radiosity in W·m⁻². An object's `area` is its geometric area (a two-sided polygon counts
//! once) and its `radiosity` is the power leaving all its sides divided by that area — the
//! area-weighted mean B of a one-sided object, and for a two-sided sheet lit from one side the
//! mean B of the lit side. Objects with two-sided polygons also carry `front` and `back`, the
//! power leaving each side over the same area (so `radiosity = front + back`).

use serde::Serialize;

/// Everything `--stats` writes.
#[derive(Clone, Debug, Serialize)]
pub struct Stats {
    /// Number of patches (reflecting sides of input polygons).
    pub patches: usize,
    /// Number of elements (quadtree leaves).
    pub elements: usize,
    /// Number of element–source interactions (form factors) the solver used.
    pub links: u64,
    /// How the solve went.
    pub solver: SolverStats,
    /// Seconds per stage.
    pub timings: Timings,
    /// Power balance.
    pub energy: Energy,
    /// Per named object.
    pub objects: Vec<Aggregate>,
    /// Per material name.
    pub materials: Vec<Aggregate>,
    /// The hierarchical solver's figures (only when it ran).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hierarchy: Option<HierarchyStats>,
}

/// What the hierarchical solver built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct HierarchyStats {
    /// Links at the end.
    pub links: u64,
    /// Quadtree levels of the deepest element (1: unsplit root faces).
    pub levels: u32,
    /// Clusters above the root faces.
    pub clusters: usize,
    /// Peak bytes held by nodes, clusters and links (counted from the structures).
    pub peak_memory_bytes: u64,
}

/// Solver summary.
#[derive(Clone, Debug, Serialize)]
pub struct SolverStats {
    /// `jacobi`, `gauss-seidel` or `progressive`.
    pub method: String,
    /// Sweeps (gathering) or shots (progressive).
    pub iterations: usize,
    /// Final residual (see [`crate::solve`] for its definition).
    pub residual: f64,
    /// Whether the solve was stopped (Ctrl-C) before it converged: then `"interrupted": true`;
    /// the key is left out of a complete run's stats.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub interrupted: bool,
}

/// Wall-clock seconds per stage.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Timings {
    /// Reading and building the scene.
    pub load: f64,
    /// Patches, elements and the visibility structure.
    pub mesh: f64,
    /// Computing form factors (for progressive refinement: included in `solve`).
    pub form_factors: f64,
    /// The solver's iterations.
    pub solve: f64,
    /// Evaluating and refining the lit mesh for display (`render::display_refinement`); the key is left out where the lit mesh is the elements' averages
    /// (as for `render` in its default mode without `--export`, which does not show it).
    #[serde(skip_serializing_if = "no_time")]
    pub display: f64,
    /// Rendering images.
    pub render: f64,
    /// Everything, from start to the last file written.
    pub total: f64,
}

/// Whether a stage took no time at all (it did not run).
#[allow(clippy::trivially_copy_pass_by_ref)] // serde passes fields by reference
fn no_time(seconds: &f64) -> bool {
    *seconds == 0.0
}

/// Emitted and absorbed power per channel.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Energy {
    /// Σ A·E over emitting patches plus the point luminaires' flux, in scene units² × W·m⁻².
    pub emitted: [f64; 3],
    /// Σ A·(1 − ρ)·H, the power absorbed by all surfaces (H: irradiance), in the same units.
    pub absorbed: [f64; 3],
    /// `emitted` in watts per channel: the scene's length unit applied.
    pub emitted_w: [f64; 3],
    /// `absorbed` in watts per channel.
    pub absorbed_w: [f64; 3],
    /// The luminous flux emitted, lm: the Rec. 709 luminance of `emitted_w` (the channels of a
    /// white luminaire hold its lumens, as grids' lux are the luminance of the irradiance).
    pub emitted_lm: f64,
    /// The luminous flux absorbed, lm.
    pub absorbed_lm: f64,
}

impl Energy {
    /// The balance of `emitted` and `absorbed` power in a scene whose length unit is `metres`
    /// long.
    #[must_use]
    pub fn new(emitted: crate::Rgb, absorbed: crate::Rgb, metres: f64) -> Self {
        let (emitted_w, absorbed_w) = (emitted * metres * metres, absorbed * metres * metres);
        Self {
            emitted: emitted.to_array(),
            absorbed: absorbed.to_array(),
            emitted_w: emitted_w.to_array(),
            absorbed_w: absorbed_w.to_array(),
            emitted_lm: crate::color::luminance(emitted_w),
            absorbed_lm: crate::color::luminance(absorbed_w),
        }
    }
}

/// Area and mean radiosity of a named group of surfaces.
#[derive(Clone, Debug, Serialize)]
pub struct Aggregate {
    /// Object or material name.
    pub name: String,
    /// Geometric area.
    pub area: f64,
    /// Leaving power per unit area (W·m⁻²), per channel.
    pub radiosity: [f64; 3],
    /// For groups with two-sided polygons: the power leaving their fronts per unit area (the
    /// mean B of the front sides); `radiosity` is `front + back`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub front: Option<[f64; 3]>,
    /// For groups with two-sided polygons: the same for their backs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub back: Option<[f64; 3]>,
}
