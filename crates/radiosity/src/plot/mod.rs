//! Plots written directly as SVG (no plotting library, no font files: the text is SVG `<text>`
//! that the viewer sets in its own sans-serif face).

mod convergence;
pub mod iso_lux;

pub use convergence::{convergence_svg, write_convergence_svg};

/// Text made safe inside SVG (XML) content.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
