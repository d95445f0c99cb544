//! Registries: the one list of a family of methods (solvers, form-factor methods, render modes,
//! display modes, export formats) from which their names, their parsing and the messages that
//! list them are generated.
//!
//! [`registry!`] declares a field-less enum whose variants each carry a name:
//!
//! ```text
//! registry! {
//!     /// The solvers.
//!     pub enum Method {
//!         /// Jacobi iteration (gathering).
//!         Jacobi = "jacobi",
//!         ...
//!     }
//!     /// An unknown solver name.
//!     pub struct UnknownMethod = "unknown solver";
//! }
//! ```
//!
//! and gives it `ALL` (every variant, in the order listed), `name`, `Display`, `FromStr`, the
//! parse error (`unknown solver `x` (choose jacobi, gauss-seidel, progressive or
//! hierarchical)`), and with the `clap` feature `clap::ValueEnum`, whose value names are the same
//! names and whose help is each variant's doc comment: the command line parses the engine's own
//! enum. Behaviour per variant stays in exhaustive `match`es beside the enum, so the compiler
//! names every place a new variant must go.

/// `a`, `a or b`, `a, b or c`: the names of a registry as its messages list them.
#[must_use]
pub fn choices(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [only] => (*only).to_owned(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

/// Declares a registry enum: see the module documentation.
macro_rules! registry {
    (
        $(#[$attr:meta])*
        $vis:vis enum $family:ident {
            $(
                $(#[$variant_attr:meta])*
                $variant:ident = $name:literal
            ),+ $(,)?
        }
        $(#[$error_attr:meta])*
        $error_vis:vis struct $error:ident = $unknown:literal;
    ) => {
        $(#[$attr])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
        $vis enum $family {
            $(
                $(#[$variant_attr])*
                #[cfg_attr(feature = "clap", value(name = $name))]
                $variant,
            )+
        }

        impl $family {
            /// Every variant, in the order the command line lists them.
            pub const ALL: [$family; [$($name),+].len()] = [$($family::$variant),+];

            /// The name used on the command line, in files and in stats.
            #[must_use]
            pub fn name(self) -> &'static str {
                match self {
                    $($family::$variant => $name,)+
                }
            }
        }

        impl ::std::fmt::Display for $family {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str(self.name())
            }
        }

        $(#[$error_attr])*
        #[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
        #[error(
            "{} `{}` (choose {})",
            $unknown,
            .0,
            $crate::registry::choices(&[$($name),+])
        )]
        $error_vis struct $error(pub String);

        impl ::std::str::FromStr for $family {
            type Err = $error;

            fn from_str(s: &str) -> Result<Self, Self::Err> {
                $family::ALL
                    .into_iter()
                    .find(|m| m.name() == s)
                    .ok_or_else(|| $error(s.to_owned()))
            }
        }
    };
}
pub(crate) use registry;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn choices_are_joined_with_commas_and_a_final_or() {
        assert_eq!(choices(&[]), "");
        assert_eq!(choices(&["a"]), "a");
        assert_eq!(choices(&["a", "b"]), "a or b");
        assert_eq!(choices(&["a", "b", "c"]), "a, b or c");
    }
}
