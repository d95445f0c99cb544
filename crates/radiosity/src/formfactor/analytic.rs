//! The exact unoccluded form factor from a differential area to a polygon, and the closed forms
//! of the catalogue that tests compare against.
//!
//! # Lambert's contour integral
//!
//! By Stokes' theorem the area integral F_{dA→A} = ∫_A cosθ cosθ' / (π r²) dA becomes a sum over
//! the polygon's edges (Lambert 1760; Hottel & Sarofim 1967; Baum, Rushmeier & Winget 1989,
//! "Improving radiosity solutions through the use of analytically determined form-factors"):
//!
//! ```text
//! F_{dA→A} = (1/2π) Σ_i γ_i · n · (R_i × R_{i+1}) / |R_i × R_{i+1}|
//! ```
//!
//! where R_i runs from the point to corner i, n is the unit normal at the point and γ_i is the
//! angle that edge i subtends, atan2(|R_i × R_{i+1}|, R_i · R_{i+1}). The sum is the signed
//! projected solid angle of the polygon on the point's tangent plane, divided by π.
//!
//! The formula integrates cosθ over the whole polygon, *including* parts below the point's
//! horizon, where cosθ < 0 and a real surface sends no light. So the polygon is first clipped
//! to the half-space n · (y − x) ≥ 0 (one Sutherland–Hodgman step, done on the fly without
//! storing the clipped polygon). A point on the polygon's plane or behind its front gets 0:
//! polygons emit from their front only.
//!
//! Everything inside is `f64`: the terms of the sum cancel strongly for distant polygons.

use glam::DVec3;
use std::f64::consts::PI;

use super::{column_with, pair_unoccluded, row_with, FormFactors, Geometry};

/// Analytic form-factor options.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Settings {
    /// Side n of the n × n grid of quadrature points on each receiver (at least 1).
    pub quadrature: u32,
}

impl Default for Settings {
    /// 2 × 2 quadrature points, as ray casting (see [`super::raycast::Settings::default`]).
    fn default() -> Self {
        Self { quadrature: 2 }
    }
}

/// Unoccluded form factors: Lambert's formula at an n × n grid of points on each receiver, no
/// visibility. Exact (up to the receiver quadrature) in convex enclosures, where nothing can
/// block anything; shadows are missing everywhere else.
#[derive(Clone, Copy, Debug)]
pub struct Analytic {
    quadrature: u32,
}

impl Analytic {
    /// With an n × n grid of quadrature points per receiver (`n` at least 1).
    #[must_use]
    pub fn new(quadrature: u32) -> Self {
        Self {
            quadrature: quadrature.max(1),
        }
    }
}

impl FormFactors for Analytic {
    fn row(&self, g: &Geometry, element: usize, out: &mut [f32]) {
        row_with(g, self.quadrature, element, out, |r, s| {
            pair_unoccluded(g, r, element, s) as f32
        });
    }

    fn column(&self, g: &Geometry, source: usize, out: &mut [f32]) {
        column_with(g, self.quadrature, out, |r, e| {
            pair_unoccluded(g, r, e, source) as f32
        });
    }
}

/// The unoccluded form factor from a differential area at `point` with unit normal `normal`
/// to the planar `polygon` (corners counter-clockwise seen from its front, convex or not).
///
/// Zero when the point lies on the polygon's plane or behind it, or when the polygon lies
/// wholly below the point's tangent plane; the part of a polygon below that plane is clipped
/// away first. Fewer than three corners, or a degenerate polygon, give 0.
#[must_use]
pub fn point_to_polygon(point: DVec3, normal: DVec3, polygon: &[DVec3]) -> f64 {
    if polygon.len() < 3 {
        return 0.0;
    }
    // The polygon's front must face the point.
    let area_vector = newell(polygon);
    if area_vector.dot(point - polygon[0]) <= 0.0 {
        return 0.0;
    }
    // Clip to the point's upper half-space while summing the contour terms.
    let mut sum = 0.0;
    let mut first: Option<DVec3> = None;
    let mut previous = DVec3::ZERO;
    let mut emit = |r: DVec3| {
        match first {
            None => first = Some(r),
            Some(_) => sum += edge_term(normal, previous, r),
        }
        previous = r;
    };
    let rel = |p: DVec3| p - point;
    let mut a = rel(polygon[polygon.len() - 1]);
    let mut da = normal.dot(a);
    for &corner in polygon {
        let b = rel(corner);
        let db = normal.dot(b);
        if (da >= 0.0) != (db >= 0.0) {
            // The edge crosses the tangent plane: emit the crossing point.
            let t = da / (da - db);
            let mut c = a + (b - a) * t;
            // Put the crossing exactly on the plane (rounding may leave it a hair below).
            c -= normal * normal.dot(c);
            emit(c);
        }
        if db >= 0.0 {
            emit(b);
        }
        a = b;
        da = db;
    }
    if let Some(f) = first {
        sum += edge_term(normal, previous, f);
    }
    // Counter-clockwise seen from the front facing the point makes the sum negative.
    (-sum / (2.0 * PI)).max(0.0)
}

/// γ · n · (a × b)/|a × b| for one edge a → b (vectors from the point); 0 for a degenerate edge.
fn edge_term(normal: DVec3, a: DVec3, b: DVec3) -> f64 {
    let cross = a.cross(b);
    let length = cross.length();
    if length == 0.0 {
        return 0.0;
    }
    let gamma = angle(length, a.dot(b));
    gamma * normal.dot(cross) / length
}

/// tan(π/8) = √2 − 1, the end of [`atan_small`]'s interval.
const TAN_PI_8: f64 = std::f64::consts::SQRT_2 - 1.0;

/// The angle between two vectors from |a × b| = `y` ≥ 0 and a · b = `x`: atan2(y, x) in
/// [0, π], to within 10⁻¹² (the edge term of every point-to-polygon factor takes one, and
/// the library's `atan2` was a tenth of the hierarchical solve). Reduced to atan(t) for
/// t = min/max of |x| and y in [0, 1], and for t > tan(π/8) by atan t = π/4 +
/// atan((t − 1)/(t + 1)) to |u| ≤ tan(π/8), where [`atan_small`] holds.
fn angle(y: f64, x: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};
    let ax = x.abs();
    let (small, large, swapped) = if y <= ax {
        (y, ax, false)
    } else {
        (ax, y, true)
    };
    if large == 0.0 {
        return 0.0;
    }
    let t = small / large;
    let a = if t > TAN_PI_8 {
        FRAC_PI_4 + atan_small((t - 1.0) / (t + 1.0))
    } else {
        atan_small(t)
    };
    let a = if swapped { FRAC_PI_2 - a } else { a };
    if x < 0.0 {
        PI - a
    } else {
        a
    }
}

/// atan u for |u| ≤ tan(π/8): u · P(u²), P of degree 7 fitted by least squares at 4 000
/// Chebyshev nodes of u² (close to the minimax polynomial); largest error 3·10⁻¹³.
fn atan_small(u: f64) -> f64 {
    const P: [f64; 8] = [
        0.999_999_999_999_270_7,
        -0.333_333_332_783_848_8,
        0.199_999_931_889_277_17,
        -0.142_853_912_609_431_37,
        0.111_035_349_429_659_37,
        -0.089_932_175_218_773_49,
        0.069_770_063_158_248_63,
        -0.037_701_756_929_010_73,
    ];
    let x = u * u;
    u * P.iter().rev().fold(0.0, |acc, &c| acc * x + c)
}

/// Vector area of a polygon (Newell's method): normal direction times area.
fn newell(polygon: &[DVec3]) -> DVec3 {
    let mut sum = DVec3::ZERO;
    let mut a = polygon[polygon.len() - 1];
    for &b in polygon {
        sum += a.cross(b);
        a = b;
    }
    0.5 * sum
}

/// The solid angle (sr) a convex polygon subtends at `point`, seen from the polygon's front
/// (0 from behind or on its plane): a fan of triangles, each by Van Oosterom & Strackee's
/// formula tan(Ω/2) = |a·(b×c)| / (abc + (a·b)c + (a·c)b + (b·c)a) (IEEE Trans. Biomed. Eng.
/// 1983), a, b, c the vectors to the corners. An isotropic receiver (a cluster of surfaces
/// facing every way) gathers from a source in proportion to it.
#[must_use]
pub fn solid_angle(point: DVec3, polygon: &[DVec3]) -> f64 {
    if polygon.len() < 3 {
        return 0.0;
    }
    let normal = (1..polygon.len() - 1)
        .map(|k| (polygon[k] - polygon[0]).cross(polygon[k + 1] - polygon[0]))
        .sum::<DVec3>();
    if normal.dot(point - polygon[0]) <= 0.0 {
        return 0.0;
    }
    let a = polygon[0] - point;
    (1..polygon.len() - 1)
        .map(|k| {
            let (b, c) = (polygon[k] - point, polygon[k + 1] - point);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let numerator = a.dot(b.cross(c)).abs();
            let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
            2.0 * numerator.atan2(denominator)
        })
        .sum()
}

/// Closed-form form factor between two coaxial parallel rectangles `a × b`, `distance` apart
/// (Howell's catalogue C-11). Two unit squares one apart: 0.1998249.
#[must_use]
pub fn parallel_rectangles(a: f64, b: f64, distance: f64) -> f64 {
    let (x, y) = (a / distance, b / distance);
    let (x1, y1) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    let log = ((1.0 + x * x) * (1.0 + y * y) / (1.0 + x * x + y * y))
        .sqrt()
        .ln();
    2.0 / (PI * x * y)
        * (log + x * y1 * (x / y1).atan() + y * x1 * (y / x1).atan() - x * x.atan() - y * y.atan())
}

/// Closed-form form factor from a rectangle `width × edge` to a perpendicular rectangle
/// `height × edge` that shares its edge of length `edge` (Howell's catalogue C-14). Two unit
/// squares: 0.2000438.
#[must_use]
pub fn perpendicular_rectangles(width: f64, height: f64, edge: f64) -> f64 {
    let (h, w) = (height / edge, width / edge);
    let (h2, w2) = (h * h, w * w);
    let hw = (h2 + w2).sqrt();
    let a = (1.0 + w2) * (1.0 + h2) / (1.0 + w2 + h2);
    let b = (w2 * (1.0 + w2 + h2) / ((1.0 + w2) * (w2 + h2))).powf(w2);
    let c = (h2 * (1.0 + h2 + w2) / ((1.0 + h2) * (h2 + w2))).powf(h2);
    (w * (1.0 / w).atan() + h * (1.0 / h).atan() - hw * (1.0 / hw).atan() + 0.25 * (a * b * c).ln())
        / (PI * w)
}

/// Closed-form form factor from a differential area to a parallel `a × b` rectangle whose
/// corner lies on the area's normal at `distance` (Howell's catalogue B-3). Four of these give
/// the centre of a face of the unit cube to the opposite face: 4 · F(½, ½, 1) = 0.2394565.
#[must_use]
pub fn point_to_parallel_rectangle_corner(a: f64, b: f64, distance: f64) -> f64 {
    let (x, y) = (a / distance, b / distance);
    let (x1, y1) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / x1 * (y / x1).atan() + y / y1 * (x / y1).atan()) / (2.0 * PI)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_angle_is_atan2_to_within_1e_12() {
        // Every octant, both ends of each reduction, and random pairs (a fixed LCG).
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut cases = vec![(0.0, 1.0), (0.0, -1.0), (1.0, 0.0), (0.0, 0.0), (1.0, 1.0)];
        cases.push((TAN_PI_8, 1.0));
        cases.push((1.0, -TAN_PI_8));
        for _ in 0..100_000 {
            let (y, x) = (next() * 10.0, (next() - 0.5) * 20.0);
            cases.push((y, x));
            cases.push((y * 1e-9, x));
        }
        for (y, x) in cases {
            let (got, want) = (angle(y, x), f64::atan2(y, x));
            assert!(
                (got - want).abs() < 1e-12,
                "atan2({y}, {x}): {got} vs {want}"
            );
        }
    }

    /// The unit square at height `z`, facing down (counter-clockwise seen from below).
    fn square_facing_down(z: f64) -> Vec<DVec3> {
        vec![
            DVec3::new(-0.5, -0.5, z),
            DVec3::new(-0.5, 0.5, z),
            DVec3::new(0.5, 0.5, z),
            DVec3::new(0.5, -0.5, z),
        ]
    }

    #[test]
    fn closed_forms_match_catalogue_values() {
        // Values printed in Howell's catalogue to 7 digits.
        assert!((parallel_rectangles(1.0, 1.0, 1.0) - 0.199_824_9).abs() < 1e-7);
        assert!((perpendicular_rectangles(1.0, 1.0, 1.0) - 0.200_043_8).abs() < 1e-7);
        assert!(
            (4.0 * point_to_parallel_rectangle_corner(0.5, 0.5, 1.0) - 0.239_456_5).abs() < 1e-7
        );
    }

    #[test]
    fn lambert_matches_closed_form_at_face_centre() {
        let f = point_to_polygon(DVec3::ZERO, DVec3::Z, &square_facing_down(1.0));
        assert!((f - 0.239_456_5).abs() < 1e-6, "{f}");
    }

    #[test]
    fn back_side_and_coplanar_points_see_nothing() {
        let mut up = square_facing_down(1.0);
        up.reverse();
        assert_eq!(point_to_polygon(DVec3::ZERO, DVec3::Z, &up), 0.0);
        let f = point_to_polygon(
            DVec3::new(3.0, 0.0, 1.0),
            DVec3::NEG_X,
            &square_facing_down(1.0),
        );
        assert_eq!(f, 0.0);
        // Wholly below the horizon.
        assert_eq!(
            point_to_polygon(DVec3::ZERO, -DVec3::Z, &square_facing_down(1.0)),
            0.0
        );
    }

    #[test]
    fn solid_angle_of_a_square_and_its_far_field() {
        // A unit square seen from distance 1/2 above its centre: one sixth of the sphere
        // (a face of the cube around the point), 4π/6; from behind, nothing; far away, A/d².
        let square =
            [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(x, y)| DVec3::new(x, y, 0.0));
        let above = DVec3::new(0.5, 0.5, 0.5);
        assert!((solid_angle(above, &square) - 4.0 * PI / 6.0).abs() < 1e-12);
        assert_eq!(solid_angle(DVec3::new(0.5, 0.5, -0.5), &square), 0.0);
        let far = solid_angle(DVec3::new(0.5, 0.5, 1e3), &square);
        assert!((far - 1e-6).abs() < 1e-12, "{far}");
    }
}
