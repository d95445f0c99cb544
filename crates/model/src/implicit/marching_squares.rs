//! Marching squares: the contours f(x, y) = 0 of a planar field, as closed polylines, and an
//! SVG writer for them.
//!
//! The 2-D case of [`super::marching_cubes`]: a vertex on every grid edge whose ends differ in
//! sign (linear interpolation), and in each cell, walked counter-clockwise, segments from an
//! outside→inside crossing to an inside→outside crossing. The ambiguous saddle cell (corners
//! alternately in and out) is resolved by the asymptotic decider (Nielson & Hamann 1991): the inside corners
//! are joined when the bilinear interpolant's saddle value (f₀f₂ − f₁f₃)/(f₀ + f₂ − f₁ − f₃) is
//! negative. Samples on the grid's boundary count as outside, so every contour is closed; the
//! region f < 0 lies to the left of each contour (contours run counter-clockwise around it).

use std::collections::HashMap;
use std::fmt::Write;

use glam::DVec2;

/// Closed contours of `f` over the box `min..max` sampled with `resolution` square cells along
/// the longer side. Each contour lists its points once (the last joins the first).
#[must_use]
pub fn contours(
    f: impl Fn(DVec2) -> f64,
    min: DVec2,
    max: DVec2,
    resolution: u32,
) -> Vec<Vec<DVec2>> {
    let extent = max - min;
    if !(extent.min_element() > 0.0 && extent.is_finite() && resolution > 0) {
        return Vec::new();
    }
    let h = extent.max_element() / f64::from(resolution);
    let n = (extent / h).ceil().as_uvec2().max(glam::UVec2::ONE);
    let (nx, ny) = (n.x as usize, n.y as usize);
    let point = |x: usize, y: usize| min + DVec2::new(x as f64, y as f64) * h;
    let mut values = vec![0.0; (nx + 1) * (ny + 1)];
    for y in 0..=ny {
        for x in 0..=nx {
            let mut v = f(point(x, y));
            if v.is_nan() {
                v = 1.0;
            }
            if x == 0 || y == 0 || x == nx || y == ny {
                v = v.max(h * 1e-3);
            }
            values[x + (nx + 1) * y] = v;
        }
    }
    let mut points: Vec<DVec2> = Vec::new();
    let mut vertex: HashMap<(usize, usize, usize), usize> = HashMap::new();
    let mut next: HashMap<usize, usize> = HashMap::new();
    // Cell corners counter-clockwise: (0,0), (1,0), (1,1), (0,1).
    const CORNERS: [(usize, usize); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];
    for cy in 0..ny {
        for cx in 0..nx {
            let g = CORNERS.map(|(dx, dy)| (cx + dx, cy + dy));
            let v = g.map(|(x, y)| values[x + (nx + 1) * y]);
            let mut edge_point = |e: usize| {
                let (a, b) = (g[e], g[(e + 1) % 4]);
                let (lo, hi) = if a < b { (a, b) } else { (b, a) };
                let axis = usize::from(lo.1 != hi.1);
                *vertex.entry((lo.0, lo.1, axis)).or_insert_with(|| {
                    let fa = values[lo.0 + (nx + 1) * lo.1];
                    let fb = values[hi.0 + (nx + 1) * hi.1];
                    let t = fa / (fa - fb);
                    points.push(point(lo.0, lo.1).lerp(point(hi.0, hi.1), t));
                    points.len() - 1
                })
            };
            for (e, end) in square_segments(v) {
                let s = edge_point(e);
                let t = edge_point(end);
                next.insert(t, s);
            }
        }
    }
    // Chain the segments; every vertex starts exactly one segment and ends exactly one.
    let mut starts: Vec<usize> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut out = Vec::new();
    for s in starts {
        if !next.contains_key(&s) {
            continue;
        }
        let mut ring = Vec::new();
        let mut at = s;
        while let Some(t) = next.remove(&at) {
            ring.push(points[at]);
            at = t;
        }
        out.push(ring);
    }
    out
}

/// The contour segments of one square cell with corner values `v` (counter-clockwise; inside
/// where v < 0), as pairs of edges (edge e joins corners e and e + 1 mod 4), each from an
/// out→in crossing to an in→out crossing; a saddle is resolved by the asymptotic decider (see
/// the module doc). Shared with the cube faces of marching cubes.
pub(crate) fn square_segments(v: [f64; 4]) -> Vec<(usize, usize)> {
    let ins = v.map(|x| x < 0.0);
    let crossing: Vec<usize> = (0..4).filter(|&e| ins[e] != ins[(e + 1) % 4]).collect();
    let joined_inside =
        crossing.len() == 4 && (v[0] * v[2] - v[1] * v[3]) / (v[0] + v[2] - v[1] - v[3]) < 0.0;
    crossing
        .iter()
        // An in→out crossing is the end of a segment, not its start.
        .filter(|&&e| !ins[e])
        .map(|&e| {
            let end = if crossing.len() == 2 {
                crossing.iter().copied().find(|&k| k != e).unwrap_or(e)
            } else if joined_inside {
                (e + 3) % 4
            } else {
                (e + 1) % 4
            };
            (e, end)
        })
        .collect()
}

/// An SVG document drawing `contours` (in field coordinates over `min..max`) as closed paths,
/// `width` pixels wide, y up.
#[must_use]
pub fn to_svg(contours: &[Vec<DVec2>], min: DVec2, max: DVec2, width: u32) -> String {
    let extent = (max - min).max(DVec2::splat(f64::MIN_POSITIVE));
    let scale = f64::from(width.max(1)) / extent.x;
    let height = (extent.y * scale).ceil();
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{height}\" \
         viewBox=\"0 0 {} {height}\">\n",
        width.max(1),
        width.max(1)
    );
    for ring in contours {
        let mut d = String::new();
        for (i, p) in ring.iter().enumerate() {
            let x = (p.x - min.x) * scale;
            let y = (max.y - p.y) * scale;
            let _ = write!(d, "{}{x:.3},{y:.3} ", if i == 0 { 'M' } else { 'L' });
        }
        d.push('Z');
        let _ = writeln!(
            svg,
            "  <path d=\"{d}\" fill=\"none\" stroke=\"black\" stroke-width=\"1\"/>"
        );
    }
    svg.push_str("</svg>\n");
    svg
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Twice the signed area of a closed polyline (shoelace formula).
    fn area(ring: &[DVec2]) -> f64 {
        (0..ring.len())
            .map(|i| ring[i].perp_dot(ring[(i + 1) % ring.len()]))
            .sum::<f64>()
            * 0.5
    }

    #[test]
    fn circle_contour_has_circle_length_and_area() {
        let c = contours(
            |p| p.length() - 1.0,
            DVec2::splat(-1.5),
            DVec2::splat(1.5),
            60,
        );
        assert_eq!(c.len(), 1);
        let ring = &c[0];
        let length: f64 = (0..ring.len())
            .map(|i| ring[i].distance(ring[(i + 1) % ring.len()]))
            .sum();
        // An inscribed polygon with ~ 0.05-long chords: both within 0.5 % of the circle.
        let pi = std::f64::consts::PI;
        assert!((length - 2.0 * pi).abs() / (2.0 * pi) < 5e-3, "{length}");
        let a = area(ring);
        assert!(a > 0.0, "contour must run counter-clockwise");
        assert!((a - pi).abs() / pi < 5e-3, "{a}");
        let svg = to_svg(&c, DVec2::splat(-1.5), DVec2::splat(1.5), 200);
        assert!(svg.starts_with("<svg") && svg.contains("<path d=\"M"));
    }

    #[test]
    fn saddle_between_nearly_touching_disks_keeps_them_apart() {
        // Disks of radius 0.66 centred at ±(0.5, 0.5), 0.094 apart. The grid cell
        // [−0.1, 0] × [0, 0.1] has one corner in each disk (f = −0.020) and two outside
        // (0.047, 0.061): a saddle whose bilinear saddle value is +0.017, so the asymptotic
        // decider keeps the disks apart (joining would give an outer contour and a hole).
        let (a, b, r) = (DVec2::splat(-0.5), DVec2::splat(0.5), 0.66);
        let f = |p: DVec2| (p.distance(a) - r).min(p.distance(b) - r);
        let c = contours(f, DVec2::splat(-1.5), DVec2::splat(1.5), 30);
        assert_eq!(c.len(), 2);
        let disk = std::f64::consts::PI * r * r;
        for ring in &c {
            // Inscribed polygons with 0.1-wide cells: within 2 % of the disk.
            let a = area(ring);
            assert!((a - disk).abs() / disk < 0.02, "{a} vs {disk}");
        }
    }
}
