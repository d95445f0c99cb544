//! What the `radiosity` program and the developer tools (`cargo xtask`) both report, so that
//! neither keeps a copy of the other's:
//!
//! - [`Bars`]: progress bars on a terminal for the engine's stages (`radiosity render`,
//!   `cargo xtask bench`, `cargo xtask suite`).
//! - [`check`]: one quantity checked against its reference with a tolerance ([`Check`]), and
//!   the Markdown table and JSON rows of `radiosity validate` and `cargo xtask suite`.
#![forbid(unsafe_code)]

mod bars;
pub mod check;

pub use bars::Bars;
pub use check::Check;
