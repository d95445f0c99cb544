//! `radiosity curve`: the lecture's picture of a Bézier curve — the curve, its control polygon
//! and the de Casteljau construction at a parameter t (every intermediate polygon of the
//! pyramid P_i^r = (1 − t) P_i^{r−1} + t P_{i+1}^{r−1}, and the point C(t)) — as an SVG file
//! written directly. With `--bspline DEGREE` it draws the clamped uniform B-spline of the same
//! control points instead (with its knot points marked), and no construction.

use std::fmt::Write as _;

use anyhow::{bail, Context, Result};
use model::curve::{BSpline, Bezier, Curve};
use radiosity::io::atomic::write_atomic;

use crate::args::CurveArgs;

/// Picture size in pixels.
const SIZE: f64 = 640.0;
/// Margin around the control points, pixels.
const MARGIN: f64 = 40.0;
/// Colours of the construction levels, cycled.
const LEVEL_COLOURS: &[&str] = &["#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"];

/// `radiosity curve`.
pub fn run(args: &CurveArgs) -> Result<()> {
    let points = parse_points(&args.points)?;
    if !(0.0..=1.0).contains(&args.t) {
        bail!("--t {}: the parameter must be in [0, 1]", args.t);
    }
    let svg = match args.bspline {
        Some(degree) => {
            let d = usize::try_from(degree).unwrap_or(usize::MAX);
            let curve = BSpline::clamped(d, points.clone()).with_context(|| {
                format!("--bspline {degree}: needs more than {degree} control points")
            })?;
            draw(&points, &curve, None, Some(&curve))
        }
        None => {
            let curve = Bezier::new(points.clone()).context("no control points")?;
            draw(&points, &curve, Some((&curve, args.t)), None)
        }
    };
    write_atomic(&args.output, |w| w.write_all(svg.as_bytes()))
        .with_context(|| format!("cannot write {}", args.output.display()))?;
    Ok(())
}

/// `x,y x,y ...` (or `;`-separated) into points in the z = 0 plane.
fn parse_points(text: &str) -> Result<Vec<glam::DVec3>> {
    let mut points = Vec::new();
    for item in text
        .split(|c: char| c.is_whitespace() || c == ';')
        .filter(|s| !s.is_empty())
    {
        let xy: Vec<f64> = item
            .split(',')
            .map(|s| s.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .with_context(|| format!("--points: `{item}` is not `x,y`"))?;
        match xy[..] {
            [x, y] if x.is_finite() && y.is_finite() => points.push(glam::DVec3::new(x, y, 0.0)),
            _ => bail!("--points: `{item}` is not `x,y` with finite numbers"),
        }
    }
    if points.len() < 2 {
        bail!("--points: give at least two points `x,y`");
    }
    Ok(points)
}

/// The SVG text: control polygon, construction (Bézier), knots (B-spline), curve.
fn draw(
    points: &[glam::DVec3],
    curve: &dyn Curve,
    construction: Option<(&Bezier, f64)>,
    knots: Option<&BSpline>,
) -> String {
    // Fit the control points (which bound the curve: convex hull property) into the picture,
    // y up.
    let (lo, hi) = points.iter().fold(
        (glam::DVec3::INFINITY, glam::DVec3::NEG_INFINITY),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let span = (hi - lo).max_element().max(1e-9);
    let scale = (SIZE - 2.0 * MARGIN) / span;
    let map = |p: glam::DVec3| {
        (
            MARGIN + (p.x - lo.x) * scale,
            SIZE - MARGIN - (p.y - lo.y) * scale,
        )
    };
    let polyline = |pts: &[glam::DVec3], style: &str| {
        let coords: Vec<String> = pts
            .iter()
            .map(|p| {
                let (x, y) = map(*p);
                format!("{x:.2},{y:.2}")
            })
            .collect();
        format!(
            "<polyline points=\"{}\" fill=\"none\" {style}/>\n",
            coords.join(" ")
        )
    };
    let dot = |p: glam::DVec3, r: f64, fill: &str| {
        let (x, y) = map(p);
        format!("<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"{r}\" fill=\"{fill}\"/>\n")
    };
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{SIZE}\" height=\"{SIZE}\" \
         viewBox=\"0 0 {SIZE} {SIZE}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>"
    );
    svg += &polyline(
        points,
        "stroke=\"#888\" stroke-width=\"1.5\" stroke-dasharray=\"6 4\"",
    );
    for (i, p) in points.iter().enumerate() {
        svg += &dot(*p, 4.0, "#444");
        let (x, y) = map(*p);
        let _ = writeln!(
            svg,
            "<text x=\"{:.2}\" y=\"{:.2}\" font-family=\"sans-serif\" font-size=\"14\">P{i}</text>",
            x + 6.0,
            y - 6.0
        );
    }
    svg += &polyline(
        &curve.polyline(400),
        "stroke=\"#d62728\" stroke-width=\"2.5\"",
    );
    if let Some((bezier, t)) = construction {
        let pyramid = bezier.de_casteljau(t);
        for (r, level) in pyramid.iter().enumerate().skip(1) {
            let colour = LEVEL_COLOURS[(r - 1) % LEVEL_COLOURS.len()];
            if level.len() > 1 {
                svg += &polyline(level, &format!("stroke=\"{colour}\" stroke-width=\"1.2\""));
            }
            for p in level {
                svg += &dot(*p, 3.0, colour);
            }
        }
        let c = bezier.point(t);
        svg += &dot(c, 6.0, "#d62728");
        let _ = writeln!(
            svg,
            "<text x=\"{MARGIN}\" y=\"{:.0}\" font-family=\"sans-serif\" font-size=\"16\">\
             Bézier, degree {}, de Casteljau at t = {t}</text>",
            MARGIN * 0.6,
            bezier.degree()
        );
    }
    if let Some(spline) = knots {
        let p = spline.degree();
        let interior = &spline.knots()[p..spline.knots().len() - p];
        for &u in interior {
            svg += &dot(spline.point(u), 4.0, "#d62728");
        }
        let _ = writeln!(
            svg,
            "<text x=\"{MARGIN}\" y=\"{:.0}\" font-family=\"sans-serif\" font-size=\"16\">\
             clamped uniform B-spline, degree {p} (dots: knots)</text>",
            MARGIN * 0.6
        );
    }
    svg += "</svg>\n";
    svg
}
