//! Solvers (in progress).
