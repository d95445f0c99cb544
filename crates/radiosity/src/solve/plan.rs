//! The choice of solver and of the number of sources, in one place.
//!
//! A gathering solver (Gauss-Seidel, Jacobi) stores a form-factor matrix of elements × sources
//! `f32`s; it is the most accurate on the reference suite (docs/validation.md) and the fastest
//! to converge, so the automatic choice takes Gauss-Seidel whenever its matrix fits in the
//! budget with at least [`MIN_GATHER_SOURCES`] sources (fewer if there are fewer elements, and
//! never fewer than the root faces). When it does not, the automatic choice takes hierarchical
//! radiosity, which stores links only where light moves: measured on the Cornell box with an
//! 82k-triangle sphere, Gauss-Seidel refuses (25 GiB) while hierarchical solves in 15 s and
//! 174 MB (docs/hierarchical.md). It also takes hierarchical radiosity when the uniform
//! subdivision would spread its elements thin: [`MANY_ROOTS`] root faces or more with fewer
//! than [`MIN_ELEMENTS_PER_ROOT`] elements each (furniture, tessellated meshes), where a few
//! elements per face cannot follow the light along contacts and shadows and hierarchical
//! radiosity refines where the light asks. Measured at 256² against Mitsuba 3
//! (docs/decisions/automatic-solver.md): the furnished room (3 742 root faces, 1.5 elements
//! each at the default budget) 0.80 % with Gauss-Seidel against 0.42 % hierarchical; the
//! closed-mesh scene (2 895 root faces) 1.29 % against 0.98 % away from its rims; the Cornell box (28 root faces,
//! 145 elements each) stays with Gauss-Seidel, 0.71 % against 1.22 %. The partitions of the
//! suite (277 root faces, 12.7 each) go hierarchical too: worst object +0.77 % against
//! +0.92 %. Both solvers are within 1 % per object on the reference suite at their defaults
//! (docs/validation.md).
//!
//! The choice is made twice: before meshing, from the estimated element count (to skip the
//! uniform subdivision when hierarchical radiosity will refine on its own), and after, from the
//! real count, which contact and shadow refinement raise. If the real mesh no longer leaves
//! room for enough sources, the automatic choice takes progressive refinement, which needs no
//! matrix and keeps the subdivision already made.
//!
//! The command line asks for hierarchical radiosity itself when no option sizes the uniform
//! mesh or sets up its matrix (`--elements`, `--max-element-area`, `--sources`, the
//! form-factor options; [`unsized_method`]): measured side by side
//! (docs/decisions/automatic-solver.md), hierarchical radiosity reaches a given picture error
//! sooner than Gauss-Seidel on the Cornell box as well (0.75 % in 3.7 s against 0.66 % in 6.5 s
//! at 256², where Mitsuba 3 needs 46 s and 60 s), and the furnished room and the tessellated
//! scenes were hierarchical already. Those options given, the choice above is made for the
//! mesh they ask for (and library callers, whose settings always hold a subdivision, get it).
//!
//! A solver the user names is kept: a gathering one gets as many sources as fit (down to
//! [`MIN_GATHER_SOURCES`]), or the requested number and then refuses with
//! [`super::SolveError::MatrixTooLarge`]. Checkpoints do not enter the choice.

use super::Method;

/// Fewest sources the automatic choice accepts for gathering: with 1024 sources the Cornell
/// box's object means stay within 1 % of the element-to-element solution (3792 elements; 256
/// sources are 3 % off).
pub const MIN_GATHER_SOURCES: usize = 1024;

/// Fewest elements per root face for which the automatic choice subdivides a scene of
/// [`MANY_ROOTS`] root faces or more uniformly; below it, hierarchical radiosity (module docs).
pub const MIN_ELEMENTS_PER_ROOT: f64 = 16.0;

/// Scenes with fewer root faces are subdivided whatever their element budget (a box of a few
/// walls at a few hundred elements is no furnished room).
pub const MANY_ROOTS: usize = 64;

/// What the choice is made from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Problem {
    /// The solver asked for, `None` for the automatic choice.
    pub requested: Option<Method>,
    /// Root faces of the scene (the fewest sources a cut can have).
    pub roots: usize,
    /// Elements, estimated before meshing or counted after.
    pub elements: f64,
    /// Whether the elements are counted (the mesh is built) rather than estimated.
    pub meshed: bool,
    /// The sources asked for.
    pub sources: usize,
    /// The most bytes the form-factor matrix may take.
    pub matrix_bytes: u64,
}

/// The choice.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Choice {
    /// Hierarchical radiosity, refining from the root faces.
    Hierarchical,
    /// `method` on the uniform subdivision, with at most `sources` sources, or up to `reach`
    /// where contact lines need more ([`crate::mesh::Mesh::sources`]).
    Subdivided {
        /// The solver.
        method: Method,
        /// Sources wanted.
        sources: usize,
        /// Most sources the matrix budget allows.
        reach: usize,
    },
}

/// The solver to take when none is named and no mesh size is given (`mesh_given` false):
/// hierarchical radiosity, which sizes its own mesh; `None` (the automatic choice of [`plan`])
/// for a given mesh size. See the module documentation.
#[must_use]
pub fn unsized_method(mesh_given: bool) -> Option<Method> {
    (!mesh_given).then_some(Method::Hierarchical)
}

/// Whether the uniform subdivision spreads the elements too thin: many root faces, and fewer
/// than [`MIN_ELEMENTS_PER_ROOT`] elements for each.
fn thin(p: &Problem) -> bool {
    p.roots >= MANY_ROOTS && p.elements < MIN_ELEMENTS_PER_ROOT * p.roots as f64
}

/// The solver and sources for `p`: see the module documentation.
#[must_use]
pub fn plan(p: &Problem) -> Choice {
    let elements = p.elements.max(1.0);
    let per_source = elements * std::mem::size_of::<f32>() as f64;
    let fit = (p.matrix_bytes as f64 / per_source).floor();
    let enough = fit
        >= (MIN_GATHER_SOURCES as f64)
            .min(elements)
            .max(p.roots as f64);
    let fit = if fit >= usize::MAX as f64 {
        usize::MAX
    } else {
        fit as usize
    };
    let method = match p.requested {
        Some(Method::Hierarchical) => return Choice::Hierarchical,
        Some(method) => method,
        None if !p.meshed && thin(p) => return Choice::Hierarchical,
        None if enough => Method::GaussSeidel,
        None if !p.meshed => return Choice::Hierarchical,
        None => Method::Progressive,
    };
    let gathers = matches!(method, Method::Jacobi | Method::GaussSeidel);
    let (sources, reach) = if gathers && enough {
        (p.sources.min(fit), fit)
    } else {
        (p.sources, p.sources)
    };
    Choice::Subdivided {
        method,
        sources,
        reach,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GIB: u64 = 1 << 30;

    fn problem(requested: Option<Method>, elements: f64, meshed: bool, bytes: u64) -> Problem {
        Problem {
            requested,
            roots: 20,
            elements,
            meshed,
            sources: 8192,
            matrix_bytes: bytes,
        }
    }

    fn subdivided(method: Method, sources: usize, reach: usize) -> Choice {
        Choice::Subdivided {
            method,
            sources,
            reach,
        }
    }

    #[test]
    fn the_table_of_cases() {
        use Method::{GaussSeidel, Hierarchical, Jacobi, Progressive};
        // 1 GiB holds 4 096 elements × 65 536 sources, 60 000 × 4 473, 300 000 × 894.
        let cases = [
            // The automatic choice: Gauss-Seidel with every source asked for while it fits,
            (
                problem(None, 4096.0, false, GIB),
                subdivided(GaussSeidel, 8192, 65536),
            ),
            // fewer sources when the budget says so (≥ 1024),
            (
                problem(None, 60_000.0, true, GIB),
                subdivided(GaussSeidel, 4473, 4473),
            ),
            // hierarchical before meshing when fewer than 1024 would fit,
            (problem(None, 300_000.0, false, GIB), Choice::Hierarchical),
            // progressive once meshed (the subdivision is kept),
            (
                problem(None, 300_000.0, true, GIB),
                subdivided(Progressive, 8192, 8192),
            ),
            // and gathering from few elements even in a small budget (200 × 200 × 4 B).
            (
                problem(None, 200.0, false, 160_000),
                subdivided(GaussSeidel, 200, 200),
            ),
            // A named solver is kept: fewer sources when they fit,
            (
                problem(Some(Jacobi), 60_000.0, true, GIB),
                subdivided(Jacobi, 4473, 4473),
            ),
            // the number asked for when too few fit (the solver then refuses),
            (
                problem(Some(Jacobi), 300_000.0, true, GIB),
                subdivided(Jacobi, 8192, 8192),
            ),
            (
                problem(Some(Progressive), 300_000.0, true, GIB),
                subdivided(Progressive, 8192, 8192),
            ),
            (
                problem(Some(Hierarchical), 10.0, false, GIB),
                Choice::Hierarchical,
            ),
        ];
        for (p, expected) in cases {
            assert_eq!(plan(&p), expected, "{p:?}");
        }
    }

    #[test]
    fn hierarchical_when_the_elements_are_spread_thin_over_many_root_faces() {
        // The partitions: 277 root faces, about 3 508 elements (12.7 per face).
        let mut p = problem(None, 3508.0, false, GIB);
        p.roots = 277;
        assert_eq!(plan(&p), Choice::Hierarchical);
        // At 13 348 elements (48 per face) they are subdivided,
        p.elements = 13_348.0;
        assert!(matches!(plan(&p), Choice::Subdivided { .. }));
        // as is a box of 20 faces at 200 elements, and a solver the user names.
        let mut few = problem(None, 200.0, false, GIB);
        few.roots = 20;
        assert!(matches!(plan(&few), Choice::Subdivided { .. }));
        p.elements = 4096.0;
        p.requested = Some(Method::GaussSeidel);
        assert!(matches!(plan(&p), Choice::Subdivided { .. }));
    }

    #[test]
    fn never_fewer_sources_than_root_faces() {
        // 5 000 root faces, 100 000 elements (20 per face): 1 024 sources would fit in
        // 400 MB, but a cut holds at least every root face, so gathering needs 2 GB.
        let mut p = problem(None, 100_000.0, false, 400 << 20);
        p.roots = 5000;
        assert_eq!(plan(&p), Choice::Hierarchical);
        p.matrix_bytes = 2000 << 20;
        assert!(matches!(plan(&p), Choice::Subdivided { .. }));
    }
}
