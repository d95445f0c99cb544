//! Properties of the course's curves, each with a stated tolerance. Exact identities in f64
//! are checked to 1e-12 times the size of the data; numerical derivatives to 1e-6.

use glam::{DMat3, DVec3};
use model::curve::bessel_overhauser::bessel_overhauser;
use model::curve::bezier::bernstein;
use model::curve::bspline::basis;
use model::curve::catmull_rom::catmull_rom;
use model::curve::{BSpline, Bezier, Curve, Hermite, Lagrange, Nurbs, RationalBezier};

const EXACT: f64 = 1e-12;

fn pts() -> Vec<DVec3> {
    vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 2.0, 0.5),
        DVec3::new(3.0, 3.0, -1.0),
        DVec3::new(4.0, 0.0, 2.0),
        DVec3::new(6.0, 1.0, 0.0),
        DVec3::new(7.0, -1.0, 1.0),
    ]
}

fn params(c: &dyn Curve, n: usize) -> Vec<f64> {
    let (a, b) = c.domain();
    (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect()
}

/// Central difference with h = 1e-5: error O(h²) ≈ 1e-10 · |C‴|, plus rounding 1e-16/h.
fn assert_derivative(c: &dyn Curve) {
    let (a, b) = c.domain();
    let h = 1e-5 * (b - a);
    for t in params(c, 37) {
        let t = t.clamp(a + h, b - h);
        let fd = (c.point(t + h) - c.point(t - h)) / (2.0 * h);
        let d = c.derivative(t);
        assert!(
            (fd - d).length() <= 1e-6 * (1.0 + d.length()),
            "t={t}: {fd} vs {d}"
        );
    }
}

#[test]
fn bezier_interpolates_ends_with_tangents_n_times_first_leg() {
    let p = pts();
    let c = Bezier::new(p.clone()).unwrap();
    let n = 5.0;
    assert!((c.point(0.0) - p[0]).length() < EXACT);
    assert!((c.point(1.0) - p[5]).length() < EXACT);
    assert!((c.derivative(0.0) - n * (p[1] - p[0])).length() < 1e-10);
    assert!((c.derivative(1.0) - n * (p[5] - p[4])).length() < 1e-10);
    assert_derivative(&c);
}

#[test]
fn bezier_equals_bernstein_sum_and_de_casteljau_apex() {
    let p = pts();
    let c = Bezier::new(p.clone()).unwrap();
    for t in params(&c, 20) {
        let sum: DVec3 = (0..6).map(|i| bernstein(5, i, t) * p[i]).sum();
        let pyramid = c.de_casteljau(t);
        assert_eq!(pyramid.len(), 6);
        assert!((c.point(t) - sum).length() < 1e-12 * 10.0);
        assert!((pyramid[5][0] - sum).length() < 1e-12 * 10.0);
    }
}

#[test]
fn bezier_subdivision_reproduces_the_curve() {
    let c = Bezier::new(pts()).unwrap();
    let t0 = 0.3;
    let (l, r) = c.split(t0);
    for s in params(&c, 20) {
        assert!((l.point(s) - c.point(s * t0)).length() < 1e-12 * 10.0);
        assert!((r.point(s) - c.point(t0 + s * (1.0 - t0))).length() < 1e-12 * 10.0);
    }
}

#[test]
fn degree_elevation_leaves_the_curve_unchanged() {
    let c = Bezier::new(pts()).unwrap();
    let mut e = c.clone();
    for _ in 0..3 {
        e = e.elevate();
    }
    assert_eq!(e.degree(), 8);
    for t in params(&c, 50) {
        assert!((e.point(t) - c.point(t)).length() < 1e-12 * 10.0, "t={t}");
    }
}

#[test]
fn affine_invariance_of_bezier_and_bspline() {
    // Mapping the control points maps the curve: exact up to rounding (1e-12 of the size).
    let m = DMat3::from_cols(
        DVec3::new(1.0, 0.5, 0.0),
        DVec3::new(-0.3, 2.0, 0.1),
        DVec3::new(0.0, 0.2, 0.7),
    );
    let shift = DVec3::new(3.0, -2.0, 5.0);
    let f = |p: DVec3| m * p + shift;
    let p = pts();
    let q: Vec<DVec3> = p.iter().map(|&x| f(x)).collect();
    let (a, b) = (
        Bezier::new(p.clone()).unwrap(),
        Bezier::new(q.clone()).unwrap(),
    );
    let (c, d) = (
        BSpline::uniform(3, p).unwrap(),
        BSpline::uniform(3, q).unwrap(),
    );
    for t in params(&a, 30) {
        assert!((f(a.point(t)) - b.point(t)).length() < 1e-11);
    }
    for t in params(&c, 30) {
        assert!((f(c.point(t)) - d.point(t)).length() < 1e-11);
    }
}

#[test]
fn convex_hull_property() {
    // Every curve point is a convex combination of the control points: check it against
    // every supporting half-space of the hull's directions we sample (a point outside the hull
    // is separated by some direction; 200 directions with tolerance 1e-12).
    let p = pts();
    let curves: Vec<Box<dyn Curve>> = vec![
        Box::new(Bezier::new(p.clone()).unwrap()),
        Box::new(BSpline::clamped(3, p.clone()).unwrap()),
    ];
    for c in &curves {
        for k in 0..200 {
            let phi = k as f64 * 2.399963;
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / 200.0;
            let r = (1.0 - z * z).sqrt();
            let dir = DVec3::new(r * phi.cos(), r * phi.sin(), z);
            let max = p.iter().map(|x| x.dot(dir)).fold(f64::MIN, f64::max);
            for t in params(c.as_ref(), 40) {
                assert!(c.point(t).dot(dir) <= max + 1e-12);
            }
        }
    }
}

#[test]
fn bspline_basis_partition_of_unity_and_local_support() {
    let knots = [0.0, 0.0, 0.0, 0.0, 0.5, 1.2, 1.2, 2.0, 3.5, 3.5, 3.5, 3.5];
    let p = 3;
    let n = knots.len() - p - 1; // 8 basis functions
    for k in 0..=700 {
        let t = 3.5 * k as f64 / 700.0;
        let values: Vec<f64> = (0..n).map(|i| basis(&knots, p, i, t)).collect();
        let sum: f64 = values.iter().sum();
        assert!((sum - 1.0).abs() < 1e-12, "t={t}: sum {sum}");
        for (i, v) in values.iter().enumerate() {
            assert!(*v >= 0.0);
            if t < knots[i] || t > knots[i + p + 1] {
                assert_eq!(*v, 0.0, "N_{i} at {t} outside its support");
            }
        }
        // At most p + 1 non-zero functions at any t.
        assert!(values.iter().filter(|v| **v > 0.0).count() <= p + 1);
    }
}

#[test]
fn de_boor_equals_basis_sum_for_non_uniform_knots() {
    let p = pts();
    let knots = vec![0.0, 0.0, 0.0, 0.7, 1.0, 2.5, 4.0, 4.0, 4.0];
    let c = BSpline::new(2, knots.clone(), p.clone()).unwrap();
    for t in params(&c, 40) {
        let sum: DVec3 = (0..6).map(|i| basis(&knots, 2, i, t) * p[i]).sum();
        assert!((c.point(t) - sum).length() < 1e-12 * 10.0, "t={t}");
    }
    assert_derivative(&c);
    assert_derivative(&BSpline::uniform(3, pts()).unwrap());
}

#[test]
fn knot_insertion_leaves_the_curve_unchanged() {
    let c = BSpline::new(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.5, 2.0, 2.0, 2.0, 2.0],
        pts(),
    )
    .unwrap();
    let d = c.insert_knot(0.9).insert_knot(0.9).insert_knot(1.7);
    assert_eq!(d.points().len(), c.points().len() + 3);
    for t in params(&c, 60) {
        assert!((d.point(t) - c.point(t)).length() < 1e-12 * 10.0, "t={t}");
    }
    let circle = Nurbs::circle(DVec3::ZERO, 2.0, DVec3::X, DVec3::Y);
    let more = circle.insert_knot(0.1).insert_knot(0.6);
    for t in params(&circle, 60) {
        assert!((more.point(t) - circle.point(t)).length() < 1e-12 * 10.0);
    }
}

#[test]
fn clamped_bspline_interpolates_its_ends() {
    let p = pts();
    let c = BSpline::clamped(3, p.clone()).unwrap();
    assert!((c.point(0.0) - p[0]).length() < EXACT);
    assert!((c.point(1.0) - p[5]).length() < EXACT);
}

#[test]
fn nurbs_circle_has_exact_radius_everywhere() {
    let center = DVec3::new(1.0, 2.0, 3.0);
    let (x, y) = (DVec3::new(0.6, 0.8, 0.0), DVec3::new(0.0, 0.0, 1.0));
    let c = Nurbs::circle(center, 2.5, x, y);
    for t in params(&c, 997) {
        let r = (c.point(t) - center).length();
        assert!((r - 2.5).abs() < 1e-12 * 10.0, "t={t}: r={r}");
        // The tangent is perpendicular to the radius.
        let d = c.derivative(t);
        assert!(d.dot(c.point(t) - center).abs() < 1e-9 * d.length());
    }
    assert_derivative(&c);
}

#[test]
fn rational_bezier_conics() {
    // A 90° arc is exact; w = 1 gives the parabola (polynomial Bézier).
    let arc = RationalBezier::circular_arc(DVec3::ZERO, 3.0, DVec3::X, DVec3::Y, 1.2).unwrap();
    for t in params(&arc, 100) {
        assert!(((arc.point(t)).length() - 3.0).abs() < 1e-12 * 10.0);
    }
    assert_derivative(&arc);
    let (a, b, c) = (
        DVec3::ZERO,
        DVec3::new(1.0, 2.0, 0.0),
        DVec3::new(2.0, 0.0, 0.0),
    );
    let parabola = RationalBezier::conic(a, b, c, 1.0).unwrap();
    let poly = Bezier::new(vec![a, b, c]).unwrap();
    for t in params(&poly, 20) {
        assert!((parabola.point(t) - poly.point(t)).length() < EXACT);
    }
    // An ellipse (affine image of the circle) satisfies its implicit equation.
    let e = Nurbs::ellipse(
        DVec3::ZERO,
        DVec3::new(3.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
    );
    for t in params(&e, 200) {
        let p = e.point(t);
        assert!((p.x * p.x / 9.0 + p.y * p.y - 1.0).abs() < 1e-12 * 10.0);
    }
    let rb = Nurbs::from_rational_bezier(&arc);
    assert!((rb.point(0.37) - arc.point(0.37)).length() < EXACT);
}

#[test]
fn catmull_rom_passes_through_points_with_central_tangents() {
    let p = pts();
    let c = catmull_rom(&p).unwrap();
    for i in 0..p.len() {
        assert!((c.point(i as f64) - p[i]).length() < EXACT);
        if i > 0 && i < p.len() - 1 {
            let m = (p[i + 1] - p[i - 1]) / 2.0;
            assert!((c.derivative(i as f64) - m).length() < 1e-12 * 10.0);
        }
    }
    assert_derivative(&c);
}

#[test]
fn bessel_overhauser_interpolates_with_parabola_tangents() {
    let p = pts();
    let c = bessel_overhauser(&p).unwrap();
    let t = c.params().to_vec();
    for i in 0..p.len() {
        assert!((c.point(t[i]) - p[i]).length() < 1e-12 * 10.0);
    }
    // The tangent equals the derivative of the Lagrange parabola through three neighbours.
    for i in 1..p.len() - 1 {
        let parabola = Lagrange::new(t[i - 1..=i + 1].to_vec(), p[i - 1..=i + 1].to_vec()).unwrap();
        assert!((c.derivative(t[i]) - parabola.derivative(t[i])).length() < 1e-10);
    }
    assert_derivative(&c);
}

#[test]
fn lagrange_and_hermite_interpolate() {
    let p = pts();
    let l = Lagrange::uniform(p.clone()).unwrap();
    for (i, q) in p.iter().enumerate() {
        assert!((l.point(i as f64) - *q).length() < 1e-12 * 100.0);
    }
    assert_derivative(&l);
    // Lagrange reproduces a polynomial of its degree: points on t ↦ (t, t², t³).
    let cubic = |t: f64| DVec3::new(t, t * t, t * t * t);
    let l3 = Lagrange::new(
        vec![0.0, 0.5, 1.5, 2.0],
        [0.0, 0.5, 1.5, 2.0].map(cubic).to_vec(),
    )
    .unwrap();
    assert!((l3.point(1.1) - cubic(1.1)).length() < 1e-12 * 10.0);
    let h = Hermite {
        p0: p[0],
        m0: p[1],
        p1: p[2],
        m1: p[3],
    };
    assert!((h.point(0.0) - p[0]).length() < EXACT && (h.point(1.0) - p[2]).length() < EXACT);
    assert!(
        (h.derivative(0.0) - p[1]).length() < EXACT && (h.derivative(1.0) - p[3]).length() < EXACT
    );
    assert_derivative(&h);
}

#[test]
fn bad_input_is_rejected_not_panicking() {
    assert!(Bezier::new(vec![]).is_none());
    assert!(BSpline::new(3, vec![0.0; 5], pts()).is_none());
    assert!(BSpline::new(
        2,
        vec![0.0, 0.0, 0.0, 1.0, f64::NAN, 2.0, 3.0, 3.0, 3.0],
        pts()
    )
    .is_none());
    assert!(Lagrange::new(vec![0.0, 0.0], vec![DVec3::ZERO; 2]).is_none());
    assert!(catmull_rom(&[DVec3::ZERO]).is_none());
    assert!(RationalBezier::new(&[DVec3::ZERO], &[-1.0]).is_none());
    let c = Bezier::new(pts()).unwrap();
    assert!(c.point(f64::NAN).is_finite() && c.point(7.0).is_finite());
}
