//! The environment's cube, split into tiles that each emit the mean radiance of the directions
//! they cover.
//!
//! ## The cube
//!
//! Centred on the scene's bounds (with the cameras' eyes), half-side [`DISTANCE`] times their
//! diagonal, its axes the environment's frame — a map's `to_world`, the sky's zenith — so that
//! a map's equator and the sky's horizon fall on tile edges. Its faces are the enclosure's
//! ([`crate::scene::enclosure::box_faces_inward`] of the unit cube, turned and scaled).
//!
//! ## Tiles
//!
//! Each face is split into [`TILES`] × [`TILES`] tiles, and a tile further into four while the
//! luminance across it varies by more than [`SPLIT`] times the mean tile's power
//! (Ω (L_max − L_min) > [`SPLIT`] · P / (6 [`TILES`]²), P = ∫ L dω), at most [`DEPTH`] times:
//! bright features (a sun in a photograph, a horizon) get small tiles, a smooth sky large
//! ones. A tile emits
//!
//! ```text
//! L_tile = Σ_k L(ω_k) Ω_k / Σ_k Ω_k
//! ```
//!
//! over n × n sub-rectangles k of the tile, ω_k through each one's centre, Ω_k its exact solid
//! angle from the cube's centre: for the rectangle [x₀, x₁] × [y₀, y₁] on the plane at
//! distance h (coordinates from the foot of the perpendicular),
//!
//! ```text
//! Ω = G(x₁, y₁) − G(x₀, y₁) − G(x₁, y₀) + G(x₀, y₀),   G(x, y) = atan(x y / (h √(x² + y² + h²)))
//! ```
//!
//! so the tiles' solid angles add up to 4π exactly and their power Σ L_tile Ω_tile is ∫ L dω
//! to quadrature. n resolves the map: two sub-rectangles per pixel ([`MAX_SUBCELLS`] at most),
//! [`SMOOTH_SUBCELLS`] for the sky model. Black tiles (the ground under the sky) are left
//! out: a hole emits and reflects what they would, nothing.
//!
//! ## The sun's disc
//!
//! A concentrated source ([`super::Disc`]) is a regular [`DISC_SIDES`]-gon facing the centre,
//! [`DISC_DISTANCE`] of the way to the cube's inscribed sphere (clear of the faces, so it never
//! lies on a tile), its size such that it covers exactly the disc's solid angle (found by
//! bisection on [`crate::formfactor::analytic::solid_angle`]). It emits the mean of L_env over
//! the disc, sky and sun; the tiles behind it the mean over their directions outside it.
//!
//! ## Distance and parallax
//!
//! Tiles at a finite distance are seen from a point p off the centre under other directions and
//! solid angles than from the centre: the direction error is at most |p| / R (R the distance
//! to the tile), the sun's irradiance changes by about 2 p·s / R. With p at most half the
//! diagonal and R ≥ [`DISTANCE`] diagonals, both are below 1/(2 [`DISTANCE`]) — the measured
//! figures, and why the cube is not farther, are in `docs/environment.md`.

use glam::{DMat3, DVec3, Vec3};
use rayon::prelude::*;

use super::{CieSky, Disc, Distant, Environment, SunSky};
use crate::color::luminance;
use crate::formfactor::analytic::solid_angle;
use crate::scene::enclosure;
use crate::Rgb;

/// The cube's half-side, in diagonals of the scene's bounds.
pub const DISTANCE: f64 = 16.0;

/// Tiles per face side before refinement.
pub const TILES: u32 = 8;

/// How many times a tile may be split in four.
pub const DEPTH: u32 = 3;

/// The refinement threshold, relative to the mean tile's power (module docs).
pub const SPLIT: f64 = 0.5;

/// Sides of the sun's polygon.
pub const DISC_SIDES: usize = 16;

/// Where the sun's polygon sits, as a fraction of the distance to the cube's inscribed sphere.
pub const DISC_DISTANCE: f64 = 0.9;

/// Sub-rectangles per tile side for the smooth sky model.
pub const SMOOTH_SUBCELLS: u32 = 8;

/// The most sub-rectangles per tile side for a map.
pub const MAX_SUBCELLS: u32 = 256;

/// One polygon of the environment.
#[derive(Clone, Debug, PartialEq)]
pub struct Tile {
    /// Corners, counter-clockwise seen from the centre.
    pub vertices: Vec<Vec3>,
    /// Emitted radiance.
    pub radiance: Rgb,
    /// Solid angle seen from the centre.
    pub solid_angle: f64,
}

/// The environment's cube: where it is, how large and how turned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cube {
    /// Its centre.
    pub centre: DVec3,
    /// Half its side.
    pub half: f64,
    /// Its axes in world space (a rotation).
    pub frame: DMat3,
}

/// A rectangle [s₀, s₁] × [t₀, t₁] of a face's parameters (see
/// [`enclosure::box_faces_inward`]).
#[derive(Clone, Copy, Debug)]
struct Rect {
    face: usize,
    s: (f64, f64),
    t: (f64, f64),
    depth: u32,
}

/// What a rectangle's quadrature found.
struct Quadrature {
    /// Σ L Ω and Σ Ω over the sub-rectangles outside the disc.
    sum: Rgb,
    omega: f64,
    /// The same over all of them.
    sum_all: Rgb,
    omega_all: f64,
    /// The extreme luminances seen.
    lum: (f64, f64),
}

/// A rotation whose y axis is `up` and whose x axis is as close as can be to the world axis
/// most perpendicular to it.
fn frame_with_up(up: DVec3, x: DVec3) -> DMat3 {
    let Some(ey) = up.try_normalize() else {
        return DMat3::IDENTITY;
    };
    let seed = if (x - x.dot(ey) * ey).length() > 1e-6 {
        x
    } else {
        [DVec3::X, DVec3::Y, DVec3::Z]
            .into_iter()
            .min_by(|a, b| a.dot(ey).abs().total_cmp(&b.dot(ey).abs()))
            .unwrap_or(DVec3::X)
    };
    let ex = (seed - seed.dot(ey) * ey).normalize();
    DMat3::from_cols(ex, ey, ex.cross(ey))
}

impl Cube {
    /// The cube for `env` around `bounds` (module docs).
    #[must_use]
    pub fn around((lo, hi): (Vec3, Vec3), env: &Environment) -> Self {
        let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
        let diagonal = (hi - lo).length().max(f64::from(f32::MIN_POSITIVE).sqrt());
        let frame = match env {
            Environment::Constant { .. } => DMat3::IDENTITY,
            Environment::Map { to_world, .. } => {
                let m = to_world.as_dmat4();
                frame_with_up(m.y_axis.truncate(), m.x_axis.truncate())
            }
            Environment::SunSky(SunSky { up, .. }) | Environment::Cie(CieSky { up, .. }) => {
                let up = up.as_dvec3();
                let axis = [DVec3::X, DVec3::Y, DVec3::Z]
                    .into_iter()
                    .min_by(|a, b| a.dot(up).abs().total_cmp(&b.dot(up).abs()))
                    .unwrap_or(DVec3::X);
                frame_with_up(up, axis)
            }
        };
        Self {
            centre: 0.5 * (lo + hi),
            half: DISTANCE * diagonal,
            frame,
        }
    }

    /// A face's corners a, b, d in the cube's own coordinates (the unit cube [−1, 1]³).
    fn face(face: usize) -> (DVec3, DVec3, DVec3) {
        let f = enclosure::box_faces_inward(Vec3::NEG_ONE, Vec3::ONE)[face];
        (f[0].as_dvec3(), f[1].as_dvec3(), f[3].as_dvec3())
    }

    /// The point (s, t) of `face`, in the cube's own coordinates.
    fn local(face: usize, s: f64, t: f64) -> DVec3 {
        let (a, b, d) = Self::face(face);
        a + s * (b - a) + t * (d - a)
    }

    /// A point in the cube's own coordinates, in world space.
    fn world(&self, local: DVec3) -> DVec3 {
        self.centre + self.half * (self.frame * local)
    }

    /// The solid angle of `r` from the centre (module docs: h = 1, x = 2s − 1, y = 2t − 1).
    fn solid_angle(r: &Rect) -> f64 {
        let g = |s: f64, t: f64| {
            let (x, y) = (2.0 * s - 1.0, 2.0 * t - 1.0);
            (x * y / (1.0 + x * x + y * y).sqrt()).atan()
        };
        g(r.s.1, r.t.1) - g(r.s.0, r.t.1) - g(r.s.1, r.t.0) + g(r.s.0, r.t.0)
    }

    /// Sub-rectangles per side that resolve `distant` over `r`.
    fn subcells(r: &Rect, distant: &Distant) -> u32 {
        match distant {
            Distant::Constant(_) => 1,
            Distant::Daylight(_) | Distant::Cie(_) => SMOOTH_SUBCELLS,
            Distant::Map(map) => {
                let n = (2.0 * Self::solid_angle(r).sqrt() / map.pixel_angle()).ceil();
                (n as u32).clamp(4, MAX_SUBCELLS)
            }
        }
    }

    /// The quadrature of `distant` over `r` (module docs).
    fn integrate(&self, r: &Rect, distant: &Distant) -> Quadrature {
        let n = Self::subcells(r, distant) as usize;
        let disc = distant.disc();
        let s = |k: usize| r.s.0 + (r.s.1 - r.s.0) * k as f64 / n as f64;
        let t = |k: usize| r.t.0 + (r.t.1 - r.t.0) * k as f64 / n as f64;
        // G at the grid's nodes, so each sub-rectangle's Ω is four lookups.
        let g: Vec<f64> = (0..=n)
            .flat_map(|i| {
                (0..=n).map(move |j| {
                    let (x, y) = (2.0 * s(i) - 1.0, 2.0 * t(j) - 1.0);
                    (x * y / (1.0 + x * x + y * y).sqrt()).atan()
                })
            })
            .collect();
        let node = |i: usize, j: usize| g[i * (n + 1) + j];
        let mut q = Quadrature {
            sum: Rgb::ZERO,
            omega: 0.0,
            sum_all: Rgb::ZERO,
            omega_all: 0.0,
            lum: (f64::INFINITY, f64::NEG_INFINITY),
        };
        for i in 0..n {
            for j in 0..n {
                let omega = node(i + 1, j + 1) - node(i, j + 1) - node(i + 1, j) + node(i, j);
                let mid = Self::local(r.face, 0.5 * (s(i) + s(i + 1)), 0.5 * (t(j) + t(j + 1)));
                let dir = (self.frame * mid).normalize();
                let l = distant.radiance(dir);
                q.sum_all += l * omega;
                q.omega_all += omega;
                if disc.is_none_or(|d| !d.contains(dir)) {
                    q.sum += l * omega;
                    q.omega += omega;
                    let y = luminance(l);
                    q.lum = (q.lum.0.min(y), q.lum.1.max(y));
                }
            }
        }
        q
    }

    /// The tile of `r` with its radiance.
    fn make_tile(&self, r: &Rect, q: &Quadrature) -> Tile {
        let corners = [
            (r.s.0, r.t.0),
            (r.s.1, r.t.0),
            (r.s.1, r.t.1),
            (r.s.0, r.t.1),
        ];
        Tile {
            vertices: corners
                .iter()
                .map(|&(s, t)| self.world(Self::local(r.face, s, t)).as_vec3())
                .collect(),
            radiance: if q.omega > 0.0 {
                q.sum / q.omega
            } else {
                q.sum_all / q.omega_all
            },
            solid_angle: Self::solid_angle(r),
        }
    }

    /// Adds the tiles of `r`, split while its luminance varies by more than `threshold`
    /// (Ω (L_max − L_min), module docs).
    fn refine(
        &self,
        r: Rect,
        q: Quadrature,
        distant: &Distant,
        threshold: f64,
        out: &mut Vec<Tile>,
    ) {
        let varies = q.omega * (q.lum.1 - q.lum.0) > threshold;
        if !(varies && r.depth < DEPTH) {
            out.push(self.make_tile(&r, &q));
            return;
        }
        let (sm, tm) = (0.5 * (r.s.0 + r.s.1), 0.5 * (r.t.0 + r.t.1));
        for (s, t) in [
            ((r.s.0, sm), (r.t.0, tm)),
            ((sm, r.s.1), (r.t.0, tm)),
            ((r.s.0, sm), (tm, r.t.1)),
            ((sm, r.s.1), (tm, r.t.1)),
        ] {
            let child = Rect {
                s,
                t,
                depth: r.depth + 1,
                ..r
            };
            let q = self.integrate(&child, distant);
            self.refine(child, q, distant, threshold, out);
        }
    }

    /// The tiles of `distant` and, if it has a disc, the disc's polygon last; black tiles left
    /// out (module docs).
    #[must_use]
    pub fn tile(&self, distant: &Distant) -> Vec<Tile> {
        let step = 1.0 / f64::from(TILES);
        let base: Vec<Rect> = (0..6)
            .flat_map(|face| {
                (0..TILES).flat_map(move |i| {
                    (0..TILES).map(move |j| Rect {
                        face,
                        s: (f64::from(i) * step, f64::from(i + 1) * step),
                        t: (f64::from(j) * step, f64::from(j + 1) * step),
                        depth: 0,
                    })
                })
            })
            .collect();
        let quadratures: Vec<Quadrature> = base
            .par_iter()
            .map(|r| self.integrate(r, distant))
            .collect();
        let power: f64 = quadratures.iter().map(|q| luminance(q.sum)).sum();
        let threshold = SPLIT * power / base.len() as f64;
        let mut tiles: Vec<Tile> = base
            .into_par_iter()
            .zip(quadratures)
            .flat_map_iter(|(r, q)| {
                let mut out = Vec::new();
                self.refine(r, q, distant, threshold, &mut out);
                out
            })
            .collect();
        tiles.retain(|t| t.radiance.max_element() > 0.0);
        if let Some(disc) = distant.disc() {
            tiles.push(self.disc(disc, distant));
        }
        tiles
    }

    /// The disc's polygon (module docs).
    fn disc(&self, disc: &Disc, distant: &Distant) -> Tile {
        let target = disc.solid_angle();
        // e1 × e2 = −axis: counter-clockwise seen from the centre.
        let (p, q) = disc.axis.any_orthonormal_pair();
        let (e1, e2) = if p.cross(q).dot(disc.axis) < 0.0 {
            (p, q)
        } else {
            (q, p)
        };
        let polygon = |tan_r: f64| -> Vec<DVec3> {
            (0..DISC_SIDES)
                .map(|k| {
                    let (sin, cos) =
                        (std::f64::consts::TAU * k as f64 / DISC_SIDES as f64).sin_cos();
                    disc.axis + tan_r * (e1 * cos + e2 * sin)
                })
                .collect()
        };
        // The corners' angular radius: the inscribed n-gon of the cone covers less, the
        // circumscribed one more; bisect between them on the solid angle.
        let (mut lo, mut hi) = (
            disc.radius.tan(),
            disc.radius.tan() / (std::f64::consts::PI / DISC_SIDES as f64).cos(),
        );
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if solid_angle(DVec3::ZERO, &polygon(mid)) < target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let tan_r = 0.5 * (lo + hi);
        // Its farthest corner on the inscribed sphere's DISC_DISTANCE.
        let along = DISC_DISTANCE * self.half / (1.0 + tan_r * tan_r).sqrt();
        let vertices = polygon(tan_r)
            .iter()
            .map(|&v| (self.centre + along * v).as_vec3())
            .collect();
        // Mean of L_env over the disc: equal solid angles, stratified in (cos θ, φ).
        let side = 32;
        let cos_r = disc.radius.cos();
        let mut sum = Rgb::ZERO;
        for a in 0..side {
            for b in 0..side {
                let cos_t = 1.0 - (1.0 - cos_r) * (f64::from(a) + 0.5) / f64::from(side);
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                let (sin_p, cos_p) =
                    (std::f64::consts::TAU * (f64::from(b) + 0.5) / f64::from(side)).sin_cos();
                sum += distant.radiance(disc.axis * cos_t + (e1 * cos_p + e2 * sin_p) * sin_t);
            }
        }
        Tile {
            vertices,
            radiance: sum / f64::from(side * side),
            solid_angle: target,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formfactor::analytic::point_to_polygon;

    fn cube() -> Cube {
        Cube {
            centre: DVec3::new(1.0, 2.0, 3.0),
            half: 10.0,
            frame: frame_with_up(DVec3::new(0.2, 1.0, 0.1), DVec3::X),
        }
    }

    fn dvec(t: &Tile) -> Vec<DVec3> {
        t.vertices.iter().map(|v| v.as_dvec3()).collect()
    }

    #[test]
    fn tiles_cover_the_sphere_facing_the_centre() {
        let c = cube();
        let tiles = c.tile(&Distant::Constant(Rgb::ONE));
        assert_eq!(tiles.len(), 6 * (TILES * TILES) as usize);
        let total: f64 = tiles.iter().map(|t| t.solid_angle).sum();
        assert!(
            (total - 4.0 * std::f64::consts::PI).abs() < 1e-12,
            "{total}"
        );
        for t in &tiles {
            // The analytic solid angle of the polygon (f32 corners) agrees, and it is
            // counter-clockwise seen from the centre (a positive form factor towards it).
            let v = dvec(t);
            assert!((solid_angle(c.centre, &v) / t.solid_angle - 1.0).abs() < 1e-4);
            let normal = (v[1] - v[0]).cross(v[2] - v[0]);
            assert!(normal.dot(c.centre - v[0]) > 0.0);
        }
    }

    #[test]
    fn the_disc_covers_its_solid_angle_in_front_of_the_tiles() {
        let c = cube();
        let disc = Disc {
            axis: DVec3::new(0.5, 0.7, -0.2).normalize(),
            radius: 2f64.to_radians(),
            radiance: Rgb::splat(100.0),
        };
        let tile = c.disc(&disc, &Distant::Constant(Rgb::ONE));
        let v = dvec(&tile);
        assert_eq!(v.len(), DISC_SIDES);
        // f32 corners at ten units: the solid angle to 10⁻⁴.
        assert!((solid_angle(c.centre, &v) / disc.solid_angle() - 1.0).abs() < 1e-4);
        // Facing the centre, inside the inscribed sphere.
        let normal = (v[1] - v[0]).cross(v[2] - v[0]);
        assert!(normal.dot(c.centre - v[0]) > 0.0);
        assert!(v.iter().all(|p| (*p - c.centre).length() < c.half));
        // A constant environment: the disc emits it too.
        assert!((tile.radiance - Rgb::ONE).abs().max_element() < 1e-12);
    }

    #[test]
    fn a_point_at_the_centre_sees_the_upper_half_bright() {
        // A map-like function bright above the frame's horizon: the tiles' irradiance on an
        // up-facing point at the centre is πL (the horizon on tile edges), on a side-facing
        // point πL/2.
        let c = cube();
        let up = c.frame.y_axis;
        let distant = Distant::Constant(Rgb::ONE);
        let tiles: Vec<Tile> = c
            .tile(&distant)
            .into_iter()
            .filter(|t| dvec(t).iter().all(|p| (*p - c.centre).dot(up) > -1e-3))
            .collect();
        let irradiance = |n: DVec3| -> f64 {
            tiles
                .iter()
                .map(|t| std::f64::consts::PI * point_to_polygon(c.centre, n, &dvec(t)))
                .sum()
        };
        let pi = std::f64::consts::PI;
        assert!((irradiance(up) - pi).abs() < 1e-4, "{}", irradiance(up));
        assert!((irradiance(c.frame.x_axis) - pi / 2.0).abs() < 1e-4);
    }
}
