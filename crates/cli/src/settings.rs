//! From command-line options to the engine's settings.

use radiosity::formfactor;
use radiosity::mesh::Subdivision;
use radiosity::pipeline;
use radiosity::render::display_refinement;
use radiosity::solve;

use crate::args::{CommonArgs, Quality};
use crate::solver::Solver;

/// Elements of `--quality final` (gathering and progressive solvers).
const FINAL_ELEMENTS: usize = 16_000;

/// ε of `--quality final` (hierarchical radiosity), against the default 10⁻⁴: measured
/// figures, docs/figures.md.
const FINAL_EPSILON: f64 = 3e-5;

/// Largest rendered image when `--max-memory` is not given, in bytes (8 GiB).
const DEFAULT_IMAGE_BUDGET: u64 = 8 << 30;

/// The pipeline settings the options ask for; what they leave out keeps the engine's default.
///
/// # Errors
/// A form-factor option that the chosen method has no use for.
pub fn pipeline_settings(common: &CommonArgs) -> anyhow::Result<pipeline::Settings> {
    let mut settings = pipeline::Settings::default();
    if common.mesh.quality == Quality::Final {
        settings.subdivision = Subdivision::Elements(FINAL_ELEMENTS);
        settings.solve.epsilon = FINAL_EPSILON;
    }
    if let Some(n) = common.mesh.elements {
        settings.subdivision = Subdivision::Elements(usize::try_from(n).unwrap_or(usize::MAX));
    }
    if let Some(a) = common.mesh.max_element_area {
        settings.subdivision = Subdivision::MaxArea(a);
    }
    settings.discontinuity = common.mesh.discontinuity_meshing;
    let refinement = display_refinement::Settings {
        tolerance: common.outputs.display_tolerance / 100.0,
        ..display_refinement::Settings::default()
    };
    settings.display = pipeline::Display::of(common.outputs.display, refinement);
    settings.form_factors = form_factor_settings(common)?;
    if let Some(n) = common.mesh.sources {
        settings.solve.max_sources = usize::try_from(n).unwrap_or(usize::MAX);
    }
    settings.method = match common.solver.solver {
        Solver::Method(method) => Some(method),
        Solver::Auto => solve::plan::unsized_method(asks_for_a_mesh(common)),
    };
    if let Some(epsilon) = common.solver.epsilon {
        settings.solve.epsilon = epsilon;
    }
    if let Some(area) = common.solver.min_element_area {
        settings.solve.min_element_area = Some(area);
    }
    if let Some(tolerance) = common.solver.tolerance {
        settings.solve.tolerance = tolerance;
    }
    if let Some(n) = common.solver.max_iterations {
        settings.solve.max_iterations = usize::try_from(n).unwrap_or(usize::MAX);
    }
    if let Some(bytes) = common.solver.max_memory {
        settings.solve.max_matrix_bytes = bytes;
    }
    Ok(settings)
}

/// Whether the options size the uniform mesh or set up its form-factor matrix (`--elements`,
/// `--max-element-area`, `--sources`, the form-factor options): then the automatic choice is
/// made for that mesh ([`solve::plan`]); otherwise hierarchical radiosity sizes its own.
fn asks_for_a_mesh(common: &CommonArgs) -> bool {
    let (mesh, ff) = (&common.mesh, &common.form_factors);
    mesh.elements.is_some()
        || mesh.max_element_area.is_some()
        || mesh.sources.is_some()
        || ff.form_factors.is_some()
        || ff.quadrature.is_some()
        || ff.rays.is_some()
        || ff.hemicube_resolution.is_some()
}

/// The form-factor method's settings: its defaults, with the options given. An option that
/// the method has no use for is refused rather than ignored.
fn form_factor_settings(common: &CommonArgs) -> anyhow::Result<formfactor::Settings> {
    let method = common
        .form_factors
        .form_factors
        .unwrap_or_else(|| formfactor::Settings::default().method());
    let mut settings = formfactor::Settings::of(method);
    let formfactor::Options {
        quadrature,
        rays,
        seed,
        resolution,
    } = settings.options();
    set(
        quadrature,
        common.form_factors.quadrature,
        "--quadrature",
        method,
    )?;
    set(rays, common.form_factors.rays, "--rays", method)?;
    // The seed also draws the grids' meter rays: with `--grids` it has a use under any method.
    let meter_seed = common.outputs.grids.is_some() && seed.is_none();
    set(
        seed,
        common.form_factors.seed.filter(|_| !meter_seed),
        "--seed",
        method,
    )?;
    set(
        resolution,
        common.form_factors.hemicube_resolution,
        "--hemicube-resolution",
        method,
    )?;
    Ok(settings)
}

/// Writes `given` into `field`, or refuses `flag` when `method` has no such field.
fn set<T>(
    field: Option<&mut T>,
    given: Option<T>,
    flag: &str,
    method: formfactor::Method,
) -> anyhow::Result<()> {
    match (field, given) {
        (Some(field), Some(value)) => *field = value,
        (None, Some(_)) => {
            anyhow::bail!("{flag} has no use with `--form-factors {method}`")
        }
        (_, None) => {}
    }
    Ok(())
}

/// The most memory a rendered image may take: `--max-memory`, or 8 GiB.
pub fn memory_budget(common: &CommonArgs) -> u64 {
    common.solver.max_memory.unwrap_or(DEFAULT_IMAGE_BUDGET)
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;
    use crate::args::{Cli, Command};

    /// The settings that `radiosity solve cornell ARGS` asks for.
    fn settings(args: &[&str]) -> pipeline::Settings {
        let cli = Cli::try_parse_from(["radiosity", "solve", "cornell"].iter().chain(args))
            .expect("parses");
        let Command::Solve(solve) = cli.command else {
            panic!("not a solve: {cli:?}");
        };
        pipeline_settings(&solve.common).expect("valid settings")
    }

    /// The subdivision that `radiosity solve cornell ARGS` asks for.
    fn subdivision(args: &[&str]) -> Subdivision {
        settings(args).subdivision
    }

    #[test]
    fn every_registered_value_is_parsed_into_the_engines_settings() {
        for m in solve::Method::ALL {
            assert_eq!(settings(&["--solver", m.name()]).method, Some(m));
        }
        for m in formfactor::Method::ALL {
            let asked = settings(&["--form-factors", m.name()]);
            assert_eq!(asked.form_factors.method(), m);
        }
        for kind in pipeline::DisplayKind::ALL {
            assert_eq!(settings(&["--display", kind.name()]).display.kind(), kind);
        }
        for kind in radiosity::render::ModeKind::ALL {
            let cli = Cli::try_parse_from(["radiosity", "render", "--mode", kind.name()])
                .expect("parses");
            let Command::Render(render) = cli.command else {
                panic!("not a render: {cli:?}");
            };
            assert_eq!(render.mode, kind);
        }
    }

    #[test]
    fn quality_final_is_a_smaller_epsilon_unless_one_is_given() {
        let epsilon = |args: &[&str]| settings(args).solve.epsilon;
        assert_eq!(epsilon(&[]), solve::Settings::default().epsilon);
        assert_eq!(epsilon(&["--quality", "final"]), FINAL_EPSILON);
        assert_eq!(epsilon(&["--quality", "final", "--epsilon", "0.001"]), 1e-3);
    }

    #[test]
    fn hierarchical_radiosity_unless_a_mesh_or_its_matrix_is_asked_for() {
        let method = |args: &[&str]| settings(args).method;
        let hierarchical = Some(solve::Method::Hierarchical);
        assert_eq!(method(&[]), hierarchical);
        assert_eq!(
            method(&["--quality", "final", "--epsilon", "1e-5"]),
            hierarchical
        );
        for asked in [
            &["--elements", "500"][..],
            &["--max-element-area", "2"],
            &["--sources", "1024"],
            &["--form-factors", "hemicube"],
            &["--rays", "16"],
            &["--quadrature", "3"],
        ] {
            assert_eq!(method(asked), None, "{asked:?}: the automatic choice");
        }
        assert_eq!(
            method(&["--elements", "500", "--solver", "jacobi"]),
            Some(solve::Method::Jacobi)
        );
    }

    #[test]
    fn quality_final_is_a_finer_mesh_unless_the_elements_are_given() {
        assert_eq!(subdivision(&[]), Subdivision::default());
        assert_eq!(
            subdivision(&["--quality", "final"]),
            Subdivision::Elements(FINAL_ELEMENTS)
        );
        assert_eq!(
            subdivision(&["--quality", "final", "--elements", "500"]),
            Subdivision::Elements(500)
        );
        assert_eq!(
            subdivision(&["--quality", "final", "--max-element-area", "2"]),
            Subdivision::MaxArea(2.0)
        );
    }
}
