//! Convergence plots.
//!
//! Two panels share a logarithmic vertical axis, the residual r_k (the relative change of a
//! gathering sweep, or the unshot fraction of the emitted power after shot k in progressive
//! refinement; see [`crate::solve`]): on the left against the iteration k, on the right against
//! the time since the iterations began. An iterative solver with a contraction of spectral
//! radius ≈ ρ̄ (the mean reflectance) shows a straight line of slope log₁₀ ρ̄ per sweep on the
//! left panel (Cohen et al. 1988, Fig. 5 draws the same comparison).
//!
//! ```
//! use radiosity::solve::Sample;
//! let history = [(1, 0.1, 0.5), (2, 0.2, 0.05)].map(|(iteration, seconds, residual)| Sample {
//!     iteration,
//!     seconds,
//!     residual,
//! });
//! let svg = radiosity::plot::convergence_svg("cornell", &history);
//! assert!(svg.starts_with("<svg") && svg.contains("<polyline"));
//! ```

use std::fmt::Write as _;
use std::io;
use std::path::Path;

use super::escape;
use crate::io::atomic::write_atomic;
use crate::solve::Sample;

/// Width and height of the whole picture, in SVG user units (pixels).
const SIZE: (f64, f64) = (800.0, 360.0);
/// Margins of a panel: left, right, top, bottom.
const MARGIN: (f64, f64, f64, f64) = (64.0, 16.0, 40.0, 48.0);

/// The SVG document of a convergence history. Samples with a residual that is not positive
/// and finite are left out (a logarithmic axis cannot show them); an empty history gives the
/// axes and a note.
#[must_use]
pub fn convergence_svg(title: &str, history: &[Sample]) -> String {
    let points: Vec<(f64, f64, f64)> = history
        .iter()
        .filter(|p| p.residual.is_finite() && p.residual > 0.0 && p.seconds.is_finite())
        .map(|p| (p.iteration as f64, p.seconds, p.residual.log10()))
        .collect();
    let (mut lo, mut hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.2), hi.max(p.2))
        });
    if points.is_empty() {
        (lo, hi) = (-6.0, 0.0);
    }
    // Whole decades around the data, at least one.
    let (lo, hi) = (lo.floor(), hi.ceil().max(lo.floor() + 1.0));

    let mut svg = String::new();
    let _ = write!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12"><rect width="100%" height="100%" fill="white"/><text x="{cx}" y="20" text-anchor="middle" font-size="15">{t}: convergence</text>"#,
        w = SIZE.0,
        h = SIZE.1,
        cx = SIZE.0 / 2.0,
        t = escape(title)
    );
    let panel_w = SIZE.0 / 2.0;
    let max_k = points.iter().map(|p| p.0).fold(1.0, f64::max);
    let max_t = points.iter().map(|p| p.1).fold(0.0, f64::max);
    let max_t = if max_t > 0.0 { max_t } else { 1.0 };
    for (panel, (label, x_of, x_max)) in [("iteration", 0usize, max_k), ("time (s)", 1usize, max_t)]
        .into_iter()
        .enumerate()
    {
        let x0 = panel as f64 * panel_w + MARGIN.0;
        let x1 = (panel + 1) as f64 * panel_w - MARGIN.1;
        let (y0, y1) = (SIZE.1 - MARGIN.3, MARGIN.2);
        let sx = |x: f64| x0 + (x1 - x0) * x / x_max;
        let sy = |l: f64| y0 + (y1 - y0) * (l - lo) / (hi - lo);
        let _ = write!(
            svg,
            r##"<rect x="{x0}" y="{y1}" width="{}" height="{}" fill="none" stroke="#444"/>"##,
            x1 - x0,
            y0 - y1
        );
        // Decade ticks on the residual axis, five ticks on the other.
        let mut d = lo;
        while d <= hi + 0.5 {
            let y = sy(d);
            let _ = write!(
                svg,
                r##"<line x1="{x0}" y1="{y}" x2="{x1}" y2="{y}" stroke="#ddd"/><text x="{}" y="{}" text-anchor="end">1e{d}</text>"##,
                x0 - 4.0,
                y + 4.0
            );
            d += 1.0;
        }
        for i in 0..=4 {
            let v = x_max * f64::from(i) / 4.0;
            let text = if x_of == 0 {
                format!("{}", v.round())
            } else {
                format!("{v:.3}")
            };
            let _ = write!(
                svg,
                r#"<text x="{}" y="{}" text-anchor="middle">{text}</text>"#,
                sx(v),
                y0 + 16.0
            );
        }
        let _ = write!(
            svg,
            r#"<text x="{}" y="{}" text-anchor="middle">{label}</text><text transform="translate({},{}) rotate(-90)" text-anchor="middle">residual</text>"#,
            (x0 + x1) / 2.0,
            y0 + 36.0,
            x0 - 48.0,
            (y0 + y1) / 2.0
        );
        if points.is_empty() {
            let _ = write!(
                svg,
                r#"<text x="{}" y="{}" text-anchor="middle">no iterations recorded</text>"#,
                (x0 + x1) / 2.0,
                (y0 + y1) / 2.0
            );
            continue;
        }
        let line: Vec<String> = points
            .iter()
            .map(|p| {
                let x = if x_of == 0 { p.0 } else { p.1 };
                format!("{:.2},{:.2}", sx(x), sy(p.2))
            })
            .collect();
        let _ = write!(
            svg,
            r##"<polyline fill="none" stroke="#c03020" stroke-width="2" points="{}"/>"##,
            line.join(" ")
        );
    }
    svg.push_str("</svg>\n");
    svg
}

/// Writes [`convergence_svg`] at `path` (atomically).
///
/// # Errors
/// I/O errors.
pub fn write_convergence_svg(path: &Path, title: &str, history: &[Sample]) -> io::Result<()> {
    let svg = convergence_svg(title, history);
    write_atomic(path, |w| w.write_all(svg.as_bytes()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The points of the first polyline.
    fn polyline(svg: &str) -> Vec<(f64, f64)> {
        let start = svg.find("points=\"").expect("polyline") + 8;
        let end = start + svg[start..].find('"').expect("end");
        svg[start..end]
            .split(' ')
            .map(|p| {
                let (x, y) = p.split_once(',').expect("pair");
                (x.parse().expect("x"), y.parse().expect("y"))
            })
            .collect()
    }

    #[test]
    fn geometric_decay_is_a_straight_line_on_the_log_axis() {
        // r_k = 10^-k: equal steps down per iteration, from the top decade to the bottom.
        let history: Vec<_> = (1..=4)
            .map(|k| Sample {
                iteration: k,
                seconds: 0.5 * k as f64,
                residual: 10f64.powi(-(k as i32)),
            })
            .collect();
        let svg = convergence_svg("box", &history);
        let pts = polyline(&svg);
        assert_eq!(pts.len(), 4);
        let steps: Vec<f64> = pts.windows(2).map(|w| w[1].1 - w[0].1).collect();
        for s in &steps {
            // Three decades over the panel's 272-unit height: 272/3 per decade, ±0.01 rounding.
            assert!((s - 272.0 / 3.0).abs() < 0.02, "{steps:?}");
        }
        // The last iteration sits at the right edge of the left panel.
        assert!((pts[3].0 - (400.0 - MARGIN.1)).abs() < 0.01);
        assert!(svg.contains("1e-4") && svg.contains("1e-1"));
    }

    #[test]
    fn odd_input_still_gives_a_document() {
        let sample = |iteration, seconds, residual| Sample {
            iteration,
            seconds,
            residual,
        };
        let svg = convergence_svg("a<b&c", &[sample(1, f64::NAN, 0.0), sample(2, 1.0, -1.0)]);
        assert!(svg.contains("a&lt;b&amp;c"));
        assert!(!svg.contains("<polyline"));
        assert!(svg.contains("no iterations recorded"));
        assert!(svg.ends_with("</svg>\n"));
    }
}
