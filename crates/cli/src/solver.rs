//! `--solver`: the engine's solver registry ([`solve::Method`]) and the command line's one
//! value of its own, `auto`.

use clap::builder::PossibleValue;
use clap::ValueEnum;
use radiosity::solve;

/// `--solver`: one of the engine's solvers ([`solve::Method`], their help its doc comments), or
/// the automatic choice.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// One of the engine's solvers.
    Method(solve::Method),
    /// The automatic choice ([`solve::plan`]).
    Auto,
}

/// The values of `--solver`, in the order its help lists them: the engine's solvers, then
/// `auto`.
const SOLVERS: [Solver; solve::Method::ALL.len() + 1] = {
    let mut all = [Solver::Auto; solve::Method::ALL.len() + 1];
    let mut i = 0;
    while i < solve::Method::ALL.len() {
        all[i] = Solver::Method(solve::Method::ALL[i]);
        i += 1;
    }
    all
};

/// The help of `--solver auto`.
const AUTO_HELP: &str = "Hierarchical radiosity, unless `--elements`, `--max-element-area`, \
    `--sources` or a form-factor option asks for a uniform mesh and its matrix: then \
    Gauss-Seidel while the matrix fits the memory budget (hierarchical or progressive beyond \
    it; many small faces go hierarchical)";

impl ValueEnum for Solver {
    fn value_variants<'a>() -> &'a [Self] {
        &SOLVERS
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        match self {
            Solver::Method(m) => m.to_possible_value(),
            Solver::Auto => Some(PossibleValue::new("auto").help(AUTO_HELP)),
        }
    }
}

impl std::str::FromStr for Solver {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s == "auto" {
            return Ok(Solver::Auto);
        }
        s.parse::<solve::Method>()
            .map(Solver::Method)
            .map_err(|e| format!("{e} or auto"))
    }
}
