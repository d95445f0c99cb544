//! The choice of solver and of the number of sources, in one place.
//!
//! A gathering solver (Gauss-Seidel, Jacobi) stores a form-factor matrix of elements × sources
//! `f32`s; it is the most accurate on the reference suite (docs/validation.md) and the fastest
//! to converge, so the automatic choice takes Gauss-Seidel whenever its matrix fits in the
//! budget with at least [`MIN_GATHER_SOURCES`] sources (fewer if there are fewer elements, and
//! never fewer than the root faces). When it does not, the automatic choice takes hierarchical
//! radiosity, which stores links only where light moves: measured on the Cornell box with an
//! 82k-triangle sphere, Gauss-Seidel refuses (25 GiB) while hierarchical solves in 15 s and
//! 174 MB (docs/hierarchical.md). Hierarchical radiosity is not taken merely because a scene is
//! large: on the reference suite both are within 1 % per object at their defaults (worst
//! +0.98 % against +0.92 %, docs/validation.md, fifteenth round), but the Gauss-Seidel
//! solution's evaluated picture of the Cornell box is the closer one (0.71 % against 1.22 % at
//! 256², docs/raytracing.md); on the furnished room it is the other way round (0.80 % against
//! 0.42 %), which no rule here captures yet.
//!
//! The choice is made twice: before meshing, from the estimated element count (to skip the
//! uniform subdivision when hierarchical radiosity will refine on its own), and after, from the
//! real count, which contact and shadow refinement raise. If the real mesh no longer leaves
//! room for enough sources, the automatic choice takes progressive refinement, which needs no
//! matrix and keeps the subdivision already made.
//!
//! A solver the user names is kept: a gathering one gets as many sources as fit (down to
//! [`MIN_GATHER_SOURCES`]), or the requested number and then refuses with
//! [`super::SolveError::MatrixTooLarge`]. Checkpoints do not enter the choice.

use super::Method;

/// Fewest sources the automatic choice accepts for gathering: with 1024 sources the Cornell
/// box's object means stay within 1 % of the element-to-element solution (3792 elements; 256
/// sources are 3 % off).
pub const MIN_GATHER_SOURCES: usize = 1024;

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
    fn never_fewer_sources_than_root_faces() {
        // 5 000 root faces, 20 000 elements: 1 024 sources would fit in 80 MB, but a cut holds
        // at least every root face, so gathering needs 400 MB.
        let mut p = problem(None, 20_000.0, false, 100 << 20);
        p.roots = 5000;
        assert_eq!(plan(&p), Choice::Hierarchical);
        p.matrix_bytes = 400 << 20;
        assert!(matches!(plan(&p), Choice::Subdivided { .. }));
    }
}
