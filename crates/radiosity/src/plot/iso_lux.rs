//! The plan of a calculation grid: its cells in false colour and its iso-lux lines, the way
//! lighting reports show the illuminance on a work plane.
//!
//! The plan is drawn in the grid's own frame: the first axis runs right, the second down, the
//! origin corner at the top left, at one scale for both axes. Each cell is filled with the colour
//! of its point's illuminance on a linear scale from blue (E_min) through cyan, green and yellow
//! to red (E_max), the colour map of every false-colour plot and picture
//! ([`crate::color::scale`]). The iso-lux lines are those of the "nice" levels 1, 2 or 5 × 10^k
//! apart that cut the range into five to ten steps, traced by *marching squares* (Lorensen &
//! Cline's marching cubes in two dimensions): on each square of four neighbouring points, a level
//! crosses every edge whose ends lie on either side of it, at the point linear interpolation
//! puts it, and the crossings are joined in pairs; where the four corners alternate (a saddle),
//! the mean of the four decides which pairs join.

use std::fmt::Write as _;

use super::escape;
use crate::color::scale::{hex, label, levels};
use crate::grids::rounded;

/// Largest width and height of the plan itself, SVG user units (pixels).
const PLAN: (f64, f64) = (560.0, 420.0);

/// Margins: left, right (the legend), top (the title), bottom (the axis lengths).
const MARGIN: (f64, f64, f64, f64) = (24.0, 120.0, 56.0, 40.0);

/// What a plan shows: a grid of n_a × n_b values at the cells' centres, row by row along the
/// first axis, over a parallelogram whose axes are `size` long; NaN where a cell has no point
/// (beside the faces of a grid `on` an object), left empty.
#[derive(Clone, Copy, Debug)]
pub struct Plan<'a> {
    /// The title (the grid's name).
    pub name: &'a str,
    /// The illuminance at each point, lx.
    pub lux: &'a [f64],
    /// Cells along the first and the second axis.
    pub cells: (u32, u32),
    /// The axes' lengths, scene units.
    pub size: (f64, f64),
    /// The name of the scene's length unit.
    pub unit: &'a str,
}

/// The SVG document of `plan`.
#[must_use]
pub fn plan_svg(plan: &Plan) -> String {
    let (na, nb) = (plan.cells.0 as usize, plan.cells.1 as usize);
    assert_eq!(plan.lux.len(), na * nb, "one value per cell");
    let scale = (PLAN.0 / plan.size.0).min(PLAN.1 / plan.size.1);
    let (w, h) = (plan.size.0 * scale, plan.size.1 * scale);
    let (left, right, top, bottom) = MARGIN;
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" font-family="sans-serif" font-size="12">"#,
        left + w + right,
        top + h + bottom
    );
    let (lo, hi) = plan
        .lux
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    let measured: Vec<f64> = plan.lux.iter().copied().filter(|v| !v.is_nan()).collect();
    let mean = measured.iter().sum::<f64>() / measured.len().max(1) as f64;
    let _ = writeln!(
        svg,
        r#"<text x="{left}" y="22" font-size="15">{}</text><text x="{left}" y="42">E_avg {} lx, E_min {} lx, E_max {} lx, U₀ {:.2}</text>"#,
        escape(plan.name),
        rounded(mean),
        rounded(lo),
        rounded(hi),
        if mean > 0.0 { lo / mean } else { 0.0 }
    );
    // The cells.
    let (cw, ch) = (w / na as f64, h / nb as f64);
    for j in 0..nb {
        for i in 0..na {
            if plan.lux[j * na + i].is_nan() {
                continue;
            }
            let _ = writeln!(
                svg,
                r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{}"/>"#,
                left + i as f64 * cw,
                top + j as f64 * ch,
                cw + 0.2,
                ch + 0.2,
                hex(share(plan.lux[j * na + i], lo, hi))
            );
        }
    }
    // The iso-lux lines, through the points (the cells' centres).
    let at = |i: f64, j: f64| (left + (i + 0.5) * cw, top + (j + 0.5) * ch);
    for level in levels(lo, hi) {
        let segments = contour(plan.lux, na, nb, level);
        if segments.is_empty() {
            continue;
        }
        let mut d = String::new();
        for ((i0, j0), (i1, j1)) in &segments {
            let ((x0, y0), (x1, y1)) = (at(*i0, *j0), at(*i1, *j1));
            let _ = write!(d, "M{x0:.2} {y0:.2}L{x1:.2} {y1:.2}");
        }
        let _ = writeln!(
            svg,
            r#"<path class="iso" data-lux="{level}" d="{d}" fill="none" stroke="black" stroke-width="1"/>"#
        );
        let ((i0, j0), (i1, j1)) = segments[segments.len() / 2];
        let (x, y) = at((i0 + i1) / 2.0, (j0 + j1) / 2.0);
        let _ = writeln!(
            svg,
            r#"<text x="{x:.1}" y="{y:.1}" font-size="10" text-anchor="middle" stroke="white" stroke-width="3" paint-order="stroke">{}</text>"#,
            label(level)
        );
    }
    let _ = writeln!(
        svg,
        r#"<rect x="{left}" y="{top}" width="{w:.2}" height="{h:.2}" fill="none" stroke="black"/>"#
    );
    let unit = escape(plan.unit);
    let _ = writeln!(
        svg,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">first axis {} {unit}</text><text x="{:.1}" y="{:.1}" text-anchor="middle" transform="rotate(-90 {:.1} {:.1})">second axis {} {unit}</text>"#,
        left + w / 2.0,
        top + h + 24.0,
        plan.size.0,
        left - 8.0,
        top + h / 2.0,
        left - 8.0,
        top + h / 2.0,
        plan.size.1,
    );
    legend(&mut svg, (left + w + 24.0, top), h.max(120.0), (lo, hi));
    svg.push_str("</svg>\n");
    svg
}

/// The colour bar at `origin`, `height` tall, labelled at the levels.
fn legend(svg: &mut String, origin: (f64, f64), height: f64, (lo, hi): (f64, f64)) {
    let (x, y) = origin;
    let steps = 64;
    for k in 0..steps {
        let t = 1.0 - (k as f64 + 0.5) / f64::from(steps);
        let _ = writeln!(
            svg,
            r#"<rect x="{x:.1}" y="{:.2}" width="16" height="{:.2}" fill="{}"/>"#,
            y + height * k as f64 / f64::from(steps),
            height / f64::from(steps) + 0.2,
            hex(t)
        );
    }
    let _ = writeln!(
        svg,
        r#"<rect x="{x:.1}" y="{y:.1}" width="16" height="{height:.1}" fill="none" stroke="black"/><text x="{x:.1}" y="{:.1}">lx</text>"#,
        y - 8.0
    );
    for level in levels(lo, hi) {
        let ty = y + height * (1.0 - share(level, lo, hi));
        let _ = writeln!(
            svg,
            r#"<line x1="{x:.1}" x2="{:.1}" y1="{ty:.1}" y2="{ty:.1}" stroke="black"/><text x="{:.1}" y="{:.1}">{}</text>"#,
            x + 20.0,
            x + 24.0,
            ty + 4.0,
            label(level)
        );
    }
}

/// Where `value` lies between `lo` and `hi`, in [0, 1] (0 when they are equal).
fn share(value: f64, lo: f64, hi: f64) -> f64 {
    if hi > lo {
        ((value - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The segments of the iso-line at `level` through the `na` × `nb` values (row by row), in
/// point coordinates (i, j): marching squares (module docs); squares with a NaN corner have
/// none.
#[must_use]
pub fn contour(values: &[f64], na: usize, nb: usize, level: f64) -> Vec<((f64, f64), (f64, f64))> {
    let v = |i: usize, j: usize| values[j * na + i];
    let mut out = Vec::new();
    for j in 0..nb.saturating_sub(1) {
        for i in 0..na.saturating_sub(1) {
            // Corners counter-clockwise from (i, j); edge k joins corner k and corner k + 1.
            let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let value = corners.map(|(a, b)| v(a, b));
            if value.iter().any(|x| x.is_nan()) {
                continue;
            }
            let above = value.map(|x| x >= level);
            let crossing = |k: usize| {
                let (a, b) = (k, (k + 1) % 4);
                if above[a] == above[b] {
                    return None;
                }
                let t = (level - value[a]) / (value[b] - value[a]);
                let (pa, pb) = (corners[a], corners[b]);
                Some((
                    pa.0 as f64 + t * (pb.0 as f64 - pa.0 as f64),
                    pa.1 as f64 + t * (pb.1 as f64 - pa.1 as f64),
                ))
            };
            let cut: Vec<(usize, (f64, f64))> =
                (0..4).filter_map(|k| crossing(k).map(|p| (k, p))).collect();
            match cut.len() {
                2 => out.push((cut[0].1, cut[1].1)),
                4 => {
                    // A saddle: with the centre on corner 0's side, corners 0 and 2 join
                    // across it and the lines cut off corners 1 and 3; else they cut off 0
                    // and 2.
                    let centre = value.iter().sum::<f64>() / 4.0 >= level;
                    if centre == above[0] {
                        out.push((cut[0].1, cut[1].1));
                        out.push((cut[2].1, cut[3].1));
                    } else {
                        out.push((cut[3].1, cut[0].1));
                        out.push((cut[1].1, cut[2].1));
                    }
                }
                _ => {}
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// E = 10·i + j on a 6 × 3 grid: the line of level L is where 10 i + j = L, a straight
    /// line crossing each square's horizontal edges at i = (L − j)/10.
    #[test]
    fn a_linear_field_contours_along_straight_lines() {
        let (na, nb) = (6, 3);
        let values: Vec<f64> = (0..nb)
            .flat_map(|j| (0..na).map(move |i| 10.0 * i as f64 + j as f64))
            .collect();
        let segments = contour(&values, na, nb, 25.0);
        assert_eq!(
            segments.len(),
            2,
            "one segment in each of the two rows of squares"
        );
        for (a, b) in segments {
            for (i, j) in [a, b] {
                assert!((10.0 * i + j - 25.0).abs() < 1e-9, "({i}, {j})");
            }
        }
    }

    /// Cells without a value (NaN) are left empty and no line crosses their squares.
    #[test]
    fn holes_are_left_empty() {
        let lux = [100.0, 200.0, f64::NAN, 300.0];
        assert!(contour(&lux, 2, 2, 150.0).is_empty());
        let plan = Plan {
            name: "l",
            lux: &lux,
            cells: (2, 2),
            size: (1.0, 1.0),
            unit: "m",
        };
        let svg = plan_svg(&plan);
        assert!(!svg.contains("NaN"), "{svg}");
        assert!(svg.contains("E_avg 200 lx"), "{svg}");
    }

    /// A saddle is cut into two segments that never cross, and a level outside the values
    /// makes none.
    #[test]
    fn saddles_give_two_segments_and_missing_levels_none() {
        let values = [1.0, 0.0, 0.0, 1.0];
        let s = contour(&values, 2, 2, 0.5);
        assert_eq!(s.len(), 2);
        assert!(contour(&values, 2, 2, 2.0).is_empty());
    }

    #[test]
    fn the_plan_is_a_well_formed_svg_with_its_lines_and_legend() {
        let (na, nb) = (8, 4);
        let lux: Vec<f64> = (0..nb)
            .flat_map(|j| (0..na).map(move |i| 100.0 + 40.0 * i as f64 + 5.0 * j as f64))
            .collect();
        let plan = Plan {
            name: "desk <A&B>",
            lux: &lux,
            cells: (na as u32, nb as u32),
            size: (2.0, 1.0),
            unit: "m",
        };
        let svg = plan_svg(&plan);
        let doc = roxmltree::Document::parse(&svg).expect("well-formed");
        let iso = doc
            .descendants()
            .filter(|n| n.attribute("class") == Some("iso"))
            .count();
        assert_eq!(iso, levels(100.0, 395.0).len());
        let cells = doc.descendants().filter(|n| n.has_tag_name("rect")).count();
        assert!(cells >= na * nb, "{cells}");
        assert!(svg.contains("desk &lt;A&amp;B&gt;"));
    }
}
