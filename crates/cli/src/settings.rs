//! From command-line options to the engine's settings.

use radiosity::formfactor;
use radiosity::mesh::Subdivision;
use radiosity::pipeline;
use radiosity::solve;

use crate::args::{CommonArgs, FormFactors, Solver};

/// Largest rendered image when `--max-memory` is not given, in bytes (8 GiB).
const DEFAULT_IMAGE_BUDGET: u64 = 8 << 30;

/// The pipeline settings the options ask for; what they leave out keeps the engine's default.
pub fn pipeline_settings(common: &CommonArgs) -> pipeline::Settings {
    let mut settings = pipeline::Settings::default();
    if let Some(n) = common.elements {
        settings.subdivision = Subdivision::Elements(usize::try_from(n).unwrap_or(usize::MAX));
    }
    if let Some(a) = common.max_element_area {
        settings.subdivision = Subdivision::MaxArea(a);
    }
    if let Some(method) = common.form_factors {
        settings.form_factors.method = match method {
            FormFactors::Analytic => formfactor::Method::Analytic,
            FormFactors::Raycast => formfactor::Method::RayCast,
            FormFactors::Hemicube => formfactor::Method::Hemicube,
        };
    }
    if let Some(n) = common.sources {
        settings.solve.max_sources = usize::try_from(n).unwrap_or(usize::MAX);
    }
    if let Some(n) = common.hemicube_resolution {
        settings.form_factors.hemicube_resolution = n;
    }
    if let Some(n) = common.quadrature {
        settings.form_factors.quadrature = n;
    }
    if let Some(rays) = common.rays {
        settings.form_factors.rays = rays;
    }
    if let Some(seed) = common.seed {
        settings.form_factors.seed = seed;
    }
    settings.method = match common.solver {
        Solver::Jacobi => Some(solve::Method::Jacobi),
        Solver::GaussSeidel => Some(solve::Method::GaussSeidel),
        Solver::Progressive => Some(solve::Method::Progressive),
        Solver::Hierarchical => Some(solve::Method::Hierarchical),
        Solver::Auto => None,
    };
    if let Some(epsilon) = common.epsilon {
        settings.solve.epsilon = epsilon;
    }
    if let Some(area) = common.min_element_area {
        settings.solve.min_element_area = Some(area);
    }
    if let Some(tolerance) = common.tolerance {
        settings.solve.tolerance = tolerance;
    }
    if let Some(n) = common.max_iterations {
        settings.solve.max_iterations = usize::try_from(n).unwrap_or(usize::MAX);
    }
    if let Some(bytes) = common.max_memory {
        settings.solve.max_matrix_bytes = bytes;
    }
    settings
}

/// The most memory a rendered image may take: `--max-memory`, or 8 GiB.
pub fn memory_budget(common: &CommonArgs) -> u64 {
    common.max_memory.unwrap_or(DEFAULT_IMAGE_BUDGET)
}
