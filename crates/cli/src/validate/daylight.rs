//! Daylight through an opening onto a black interior (the CIE 171:2006 §5.9–5.13 family): a
//! closed 4 × 4 m room, 3 m high, of one-sided inward-facing walls that reflect nothing, lit by
//! a sky through one rectangular opening. Nothing inside reflects, so the illuminance at a
//! floor point p (normal n) is the sky's direct light alone,
//!
//! ```text
//! E(p) = ∫_opening L(ω) cos θ_p dω = ∫_opening L(ω) (n · r)(m · r) / r⁴ dA,   r = q − p,
//! ```
//!
//! q running over the opening (unit normal m), ω = r / |r|. The engine reads E at the points
//! with its calculation grids ([`radiosity::grids::measure`]: the sky's tiles are emitting
//! faces, their light exact per point); the reference is the integral above by a 64 × 64
//! Gauss–Legendre rule over the opening, with the skies written here from their standards
//! rather than taken from `cie_sky.rs`; each row is accepted within [`TOLERANCE`] of it (up =
//! +y, Z the zenith angle, L_z = [`ZENITH`]):
//!
//! - CIE standard overcast sky (Moon & Spencer): L = L_z (1 + 2 cos Z) / 3;
//! - CIE standard clear sky, ISO 15469:2004 type 12: L = L_z f(χ) φ(Z) / (f(Z_s) φ(0)),
//!   φ(Z) = 1 − exp(−0.32 / cos Z), f(χ) = 1 + 10 (exp(−3χ) − exp(−3π/2)) + 0.45 cos² χ,
//!   χ the angle to the sun and Z_s the sun's zenith angle; the sun, 30° high, is out of sight
//!   of every point, so this is sky light only.
//!
//! A uniform sky (a Mitsuba `constant` environment: the close box of the default sky) is left
//! out: its one large face per side, seen through the opening, leaves the meter's visible
//! fraction to the few of its 32 × 32 shadow rays that pass, and single points scatter by 4–11 %
//! around the closed form π L F (`docs/validation.md`).
//!
//! Both skies send nothing from below the horizon, and the ground is black (the tiles there
//! are left out). Every direction from the floor through the roof opening or the window
//! (sill 1 m up) rises above the horizon, so the whole opening counts.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};
use radiosity::formfactor;
use radiosity::grids;
use radiosity::mesh::Subdivision;
use radiosity::pipeline::{self, Settings};
use radiosity::progress::Silent;
use radiosity::scene::environment::{CieSky, CieSkyKind, Environment};
use radiosity::scene::grid::Grid;
use radiosity::Scene;
use report::check::Check;

use super::{add, quad, settings};

/// The room's extent along x, y (up) and z, m.
const ROOM: Vec3 = Vec3::new(4.0, 3.0, 4.0);

/// The skies' zenith luminance, cd·m⁻² (so E is in lx).
const ZENITH: f64 = 10_000.0;

/// Gauss–Legendre nodes per side of the opening.
const NODES: usize = 64;

/// Largest accepted relative error of a point's illuminance, under either sky: the tightest
/// the measured errors allow (`docs/validation.md`). Read with 64 seeds of the meter, a row's
/// systematic error is at most 1.29 % (the sky's tiles, clear sky, room corner) and the
/// scatter of one reading σ ≤ 0.37 % (the shadow rays through the opening); the mean plus
/// 3σ of the worst row is 1.66 %.
const TOLERANCE: f64 = 0.02;

/// A rectangle: `corner + s u + t v`, s, t ∈ [0, 1].
#[derive(Clone, Copy, Debug)]
struct Rectangle {
    corner: Vec3,
    u: Vec3,
    v: Vec3,
}

impl Rectangle {
    /// The part [s₀, s₁] × [t₀, t₁] of it, in metres along u and v.
    fn part(self, (s0, s1): (f32, f32), (t0, t1): (f32, f32)) -> Self {
        let (u, v) = (self.u.normalize(), self.v.normalize());
        Self {
            corner: self.corner + s0 * u + t0 * v,
            u: (s1 - s0) * u,
            v: (t1 - t0) * v,
        }
    }
}

/// The six faces of the room, facing inward (u × v points in).
fn faces() -> [Rectangle; 6] {
    let (w, h, d) = (ROOM.x, ROOM.y, ROOM.z);
    let face = |corner, u, v| Rectangle { corner, u, v };
    [
        face(Vec3::ZERO, d * Vec3::Z, w * Vec3::X),  // floor, +y
        face(h * Vec3::Y, w * Vec3::X, d * Vec3::Z), // roof, −y
        face(Vec3::ZERO, h * Vec3::Y, d * Vec3::Z),  // wall x = 0, +x
        face(w * Vec3::X, d * Vec3::Z, h * Vec3::Y), // wall x = 4, −x
        face(Vec3::ZERO, w * Vec3::X, h * Vec3::Y),  // wall z = 0, +z
        face(d * Vec3::Z, h * Vec3::Y, w * Vec3::X), // wall z = 4, −z
    ]
}

/// Where the light comes in: a face of [`faces`] and the hole's [s₀, s₁] × [t₀, t₁] in it.
#[derive(Clone, Copy, Debug)]
enum Opening {
    /// 1 × 1 m in the middle of the roof.
    Roof,
    /// 2 m wide, 1 m high, sill 1 m up, in the middle of the wall x = 0.
    Window,
}

impl Opening {
    /// The face and the hole.
    fn hole(self) -> (usize, (f32, f32), (f32, f32)) {
        match self {
            Self::Roof => (1, (1.5, 2.5), (1.5, 2.5)),
            Self::Window => (2, (1.0, 2.0), (1.0, 3.0)),
        }
    }

    /// The hole as a rectangle in the scene.
    fn rectangle(self) -> Rectangle {
        let (face, s, t) = self.hole();
        faces()[face].part(s, t)
    }

    /// The black room with this opening: the opening's face cut into the (up to) four
    /// rectangles around the hole.
    fn room(self) -> Scene {
        let mut scene = Scene {
            name: "daylight room".into(),
            ..Scene::default()
        };
        let (open, (s0, s1), (t0, t1)) = self.hole();
        for (k, face) in faces().into_iter().enumerate() {
            let (lu, lv) = (face.u.length(), face.v.length());
            let parts = if k == open {
                vec![
                    ((0.0, lu), (0.0, t0)),
                    ((0.0, lu), (t1, lv)),
                    ((0.0, s0), (t0, t1)),
                    ((s1, lu), (t0, t1)),
                ]
            } else {
                vec![((0.0, lu), (0.0, lv))]
            };
            for (s, t) in parts {
                let r = face.part(s, t);
                add(&mut scene, "room", quad(r.corner, r.u, r.v), 0.0, 0.0);
            }
        }
        scene
    }
}

/// The skies of the cases, written from their standards (module docs).
#[derive(Clone, Copy, Debug)]
enum Sky {
    /// The CIE standard overcast sky.
    Overcast,
    /// ISO 15469 type 12 with the sun towards the unit vector.
    Clear(DVec3),
}

impl Sky {
    /// The luminance towards unit `dir`, cd·m⁻² (0 below the horizon).
    fn luminance(self, dir: DVec3) -> f64 {
        let cos_z = dir.y;
        match self {
            _ if cos_z <= 0.0 => 0.0,
            Self::Overcast => ZENITH * (1.0 + 2.0 * cos_z) / 3.0,
            Self::Clear(sun) => {
                let gradation = |cos: f64| 1.0 - (-0.32 / cos).exp();
                let indicatrix = |chi: f64| {
                    1.0 + 10.0 * ((-3.0 * chi).exp() - (-1.5 * PI).exp()) + 0.45 * chi.cos().powi(2)
                };
                let chi = dir.dot(sun).clamp(-1.0, 1.0).acos();
                let z_sun = sun.y.clamp(-1.0, 1.0).acos();
                ZENITH * indicatrix(chi) * gradation(cos_z) / (indicatrix(z_sun) * gradation(1.0))
            }
        }
    }

    /// The engine's sky.
    fn environment(self) -> Environment {
        let (kind, sun) = match self {
            Self::Overcast => (CieSkyKind::Overcast, DVec3::Y),
            Self::Clear(sun) => (CieSkyKind::Type12, sun),
        };
        Environment::Cie(CieSky {
            kind,
            zenith_luminance: ZENITH,
            sun_direction: sun.as_vec3(),
            up: Vec3::Y,
        })
    }
}

/// One case: a sky through an opening, read at named floor points (x, z).
struct Case {
    name: &'static str,
    opening: Opening,
    sky: Sky,
    points: &'static [(&'static str, f32, f32)],
}

/// Floor points of the roof cases.
const UNDER_ROOF: &[(&str, f32, f32)] = &[
    ("floor centre", 2.0, 2.0),
    ("under the opening's edge", 2.0, 1.5),
    ("room corner", 0.5, 0.5),
];

/// Floor points of the window case.
const BY_WINDOW: &[(&str, f32, f32)] = &[
    ("0.5 m from the window", 0.5, 2.0),
    ("room centre", 2.0, 2.0),
    ("far corner", 3.5, 0.5),
];

/// The cases' rows: our illuminance at each point against the quadrature.
pub(super) fn rows() -> anyhow::Result<Vec<Check>> {
    let sun = DVec3::new(0.0, 30f64.to_radians().sin(), 30f64.to_radians().cos());
    let cases = [
        Case {
            name: "roof opening 1 × 1 m, CIE overcast sky",
            opening: Opening::Roof,
            sky: Sky::Overcast,
            points: UNDER_ROOF,
        },
        Case {
            name: "roof opening 1 × 1 m, CIE clear sky (type 12), sun 30° high",
            opening: Opening::Roof,
            sky: Sky::Clear(sun),
            points: UNDER_ROOF,
        },
        Case {
            name: "window 2 × 1 m, sill 1 m, CIE overcast sky",
            opening: Opening::Window,
            sky: Sky::Overcast,
            points: BY_WINDOW,
        },
    ];
    let mut rows = Vec::new();
    for case in cases {
        let ours = measured(&case)?;
        let window = case.opening.rectangle();
        for (&(label, x, z), ours) in case.points.iter().zip(ours) {
            let p = DVec3::new(f64::from(x), 0.0, f64::from(z));
            let reference = through(window, p, DVec3::Y, |dir| case.sky.luminance(dir));
            rows.push(Check {
                case: format!("{}: {label}", case.name),
                quantity: "illuminance (lx)",
                reference,
                ours,
                tolerance: TOLERANCE,
            });
        }
    }
    Ok(rows)
}

/// Our illuminance at the case's points: the room under the sky, solved, each point a grid of
/// one 0.5 m cell centred on it.
fn measured(case: &Case) -> anyhow::Result<Vec<f64>> {
    let mut scene = case.opening.room();
    let h = 0.25;
    scene.grids = case
        .points
        .iter()
        .map(|&(label, x, z)| {
            let p = Vec3::new(x, 0.0, z);
            let corners = [
                p - Vec3::new(h, 0.0, h),
                p + Vec3::new(h, 0.0, -h),
                p + Vec3::new(-h, 0.0, h),
            ];
            Grid::new(label, corners, 2.0 * h, None)
        })
        .collect();
    scene.add_environment(&case.sky.environment())?;
    // One element per root face: nothing inside reflects, so the mesh carries no light, and
    // the direct light comes from the sky's root faces however they are subdivided (the far
    // tiles at the default budget would be tens of thousands of elements).
    let settings = Settings {
        subdivision: Subdivision::MaxArea(f64::INFINITY),
        ..settings(0, formfactor::Method::RayCast)
    };
    let solved = pipeline::solve(scene, &settings, &Silent)?;
    let readings = grids::measure(&solved.scene, &solved.mesh, &solved.solution, 0);
    Ok(readings.iter().map(|r| r.lux[0]).collect())
}

/// ∫ L(ω) cos θ_p dω over the rectangle `r` seen from `p` (unit normal `n`): the module
/// docs' integral by the [`NODES`]² Gauss–Legendre rule.
fn through(r: Rectangle, p: DVec3, n: DVec3, luminance: impl Fn(DVec3) -> f64) -> f64 {
    let (corner, u, v) = (r.corner.as_dvec3(), r.u.as_dvec3(), r.v.as_dvec3());
    let m = u.cross(v);
    let area = m.length();
    let m = m / area;
    let rule = gauss_legendre(NODES);
    let mut sum = 0.0;
    for &(s, ws) in &rule {
        for &(t, wt) in &rule {
            let d = corner + s * u + t * v - p;
            let r2 = d.length_squared();
            let cos_p = n.dot(d);
            if cos_p <= 0.0 {
                continue;
            }
            sum += ws * wt * luminance(d / r2.sqrt()) * cos_p * m.dot(d).abs() / (r2 * r2);
        }
    }
    sum * area
}

/// The `n`-point Gauss–Legendre rule on [0, 1]: nodes and weights. The nodes are the roots of
/// the Legendre polynomial P_n, found by Newton's method from cos(π (i + ¾) / (n + ½)); the
/// weights are 2 / ((1 − x²) P_n′(x)²) on [−1, 1], halved.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    // P_n(x) and P_n′(x) by Bonnet's recurrence.
    let legendre = |x: f64| {
        let (mut p0, mut p1) = (1.0, x);
        for k in 2..=n {
            let k = k as f64;
            (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
        }
        (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
    };
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (p, dp) = legendre(x);
                let step = p / dp;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            let (_, dp) = legendre(x);
            (0.5 * (1.0 - x), 1.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use radiosity::formfactor::analytic;

    /// Howell's factor B-3 from `p` (facing +y) to the horizontal rectangle `r` above it: the
    /// corner factors F(a, b, h) of the four rectangles from p's foot to each corner, with signs.
    fn roof_factor(r: Rectangle, p: DVec3) -> f64 {
        let (lo, hi) = (r.corner.as_dvec3(), (r.corner + r.u + r.v).as_dvec3());
        let h = lo.y - p.y;
        let corner = |x: f64, z: f64| {
            let (a, b) = (x - p.x, z - p.z);
            a.signum()
                * b.signum()
                * analytic::point_to_parallel_rectangle_corner(a.abs(), b.abs(), h)
        };
        corner(hi.x, hi.z) - corner(lo.x, hi.z) - corner(hi.x, lo.z) + corner(lo.x, lo.z)
    }

    /// The rule integrates polynomials of degree 2n − 1 exactly: x^k to 1/(k + 1).
    #[test]
    fn gauss_legendre_is_exact_for_polynomials() {
        let rule = gauss_legendre(NODES);
        for k in [0, 1, 2, 10, 63, 127] {
            let sum: f64 = rule.iter().map(|&(x, w)| w * x.powi(k)).sum();
            assert!((sum * f64::from(k + 1) - 1.0).abs() < 1e-12, "x^{k}: {sum}");
        }
    }

    /// Under a uniform sky the quadrature is π L F, F by Howell B-3, at every point: from
    /// under the opening's middle, under its edge and from far aside.
    #[test]
    fn the_quadrature_meets_howell_through_the_roof() {
        let roof = Opening::Roof.rectangle();
        for (_, x, z) in UNDER_ROOF {
            let p = DVec3::new(f64::from(*x), 0.0, f64::from(*z));
            let quadrature = through(roof, p, DVec3::Y, |_| 1.0);
            let exact = PI * roof_factor(roof, p);
            assert!((quadrature / exact - 1.0).abs() < 1e-12, "{p}");
        }
    }

    /// The overcast sky is L_z at the zenith and L_z/3 at the horizon; the clear sky is L_z at
    /// the zenith and brighter towards the sun than away from it; both are black below.
    #[test]
    fn the_skies_follow_their_formulas() {
        let sun = DVec3::new(0.0, 0.5, 0.75f64.sqrt());
        for sky in [Sky::Overcast, Sky::Clear(sun)] {
            assert!((sky.luminance(DVec3::Y) / ZENITH - 1.0).abs() < 1e-12);
            assert_eq!(sky.luminance(-DVec3::Y), 0.0);
        }
        let horizon = DVec3::new(1.0, 1e-9, 0.0).normalize();
        assert!((Sky::Overcast.luminance(horizon) * 3.0 / ZENITH - 1.0).abs() < 1e-6);
        let away = DVec3::new(0.0, 0.5, -0.75f64.sqrt());
        assert!(Sky::Clear(sun).luminance(sun) > 3.0 * Sky::Clear(sun).luminance(away));
    }
}
