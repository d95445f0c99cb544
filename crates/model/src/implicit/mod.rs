//! Implicit surfaces: a small vocabulary of signed distance functions (SDFs) and the polygonizers
//! that turn them into meshes.
//!
//! A solid is the set {p : f(p) < 0} of a scalar field f; its surface is the zero set f = 0.
//! For the primitives f is the exact Euclidean signed distance (Hart 1996, "Sphere tracing"),
//! negative inside:
//!
//! * sphere: |p − c| − r
//! * box: with q = |p − c| − h (h the half size), |max(q, 0)| + min(max(qx, qy, qz), 0)
//! * torus about the y axis: |(√(x² + z²) − R, y)| − r
//! * capped cylinder about y: the box formula in the 2-D (radial, height) plane
//! * half-space: n · p − d
//!
//! Boolean set operations on fields are the min/max of Ricci (1973): A ∪ B = min(fA, fB),
//! A ∩ B = max(fA, fB), A ∖ B = max(fA, −fB). The smooth union is Quilez's polynomial smooth
//! minimum, h = clamp(½ + ½(fB − fA)/k, 0, 1), f = mix(fB, fA, h) − k h (1 − h).
//! Metaballs are Wyvill, McPheeters and Wyvill's (1986) soft objects: a field
//! F = Σ (1 − d²/R²)³ (zero beyond R) and the surface F = T, so f = T − F.
//!
//! [`marching_cubes`] polygonizes a field into a closed, consistently oriented mesh;
//! [`marching_squares`] traces the contours of a planar field and writes them as SVG.

pub mod marching_cubes;
pub mod marching_squares;

use glam::{DAffine3, DQuat, DVec2, DVec3, EulerRot};

/// A scalar field, negative inside the solid, built from primitives and operations.
#[derive(Clone, Debug, PartialEq)]
pub enum Sdf {
    /// A ball.
    Sphere {
        /// Centre.
        center: DVec3,
        /// Radius.
        radius: f64,
    },
    /// An axis-aligned box.
    Box {
        /// Lower corner.
        min: DVec3,
        /// Upper corner.
        max: DVec3,
    },
    /// A torus around the y axis through `center`.
    Torus {
        /// Centre.
        center: DVec3,
        /// Distance from the axis to the centre of the tube.
        major: f64,
        /// Tube radius.
        minor: f64,
    },
    /// A capped cylinder along the y axis.
    Cylinder {
        /// Centre (half-way up).
        center: DVec3,
        /// Radius.
        radius: f64,
        /// Half the height.
        half_height: f64,
    },
    /// The half-space n · p < d.
    Plane {
        /// Outward unit normal.
        normal: DVec3,
        /// Offset d along the normal.
        offset: f64,
    },
    /// Soft objects: the surface Σ (1 − d²/R²)³ = `threshold`.
    Metaballs {
        /// (centre, radius of influence R) of each ball.
        balls: Vec<(DVec3, f64)>,
        /// Iso-value T, in (0, 1).
        threshold: f64,
    },
    /// The union of all operands (minimum).
    Union(Vec<Sdf>),
    /// The intersection of all operands (maximum).
    Intersection(Vec<Sdf>),
    /// The first operand minus the second.
    Difference(Box<Sdf>, Box<Sdf>),
    /// A union whose seam is rounded over a width `k`.
    SmoothUnion {
        /// First operand.
        a: Box<Sdf>,
        /// Second operand.
        b: Box<Sdf>,
        /// Blend width (> 0).
        k: f64,
    },
    /// An operand moved by an affine map (see [`Sdf::transformed`]).
    Transformed {
        /// The operand in its own frame.
        inner: Box<Sdf>,
        /// World → operand frame.
        to_local: DAffine3,
        /// Smallest scale factor: multiplies the operand's value so that it stays a lower
        /// bound of the distance.
        scale: f64,
    },
}

impl Sdf {
    /// The field at `p` (negative inside).
    #[must_use]
    pub fn eval(&self, p: DVec3) -> f64 {
        match self {
            Self::Sphere { center, radius } => (p - *center).length() - radius,
            Self::Box { min, max } => {
                let c = (*min + *max) * 0.5;
                let h = (*max - *min) * 0.5;
                let q = (p - c).abs() - h;
                q.max(DVec3::ZERO).length() + q.max_element().min(0.0)
            }
            Self::Torus {
                center,
                major,
                minor,
            } => {
                let d = p - *center;
                DVec2::new(DVec2::new(d.x, d.z).length() - major, d.y).length() - minor
            }
            Self::Cylinder {
                center,
                radius,
                half_height,
            } => {
                let d = p - *center;
                let q = DVec2::new(
                    DVec2::new(d.x, d.z).length() - radius,
                    d.y.abs() - half_height,
                );
                q.max(DVec2::ZERO).length() + q.max_element().min(0.0)
            }
            Self::Plane { normal, offset } => normal.dot(p) - offset,
            Self::Metaballs { balls, threshold } => {
                let field: f64 = balls
                    .iter()
                    .map(|(c, r)| {
                        let t = (p - *c).length_squared() / (r * r);
                        if t < 1.0 {
                            (1.0 - t).powi(3)
                        } else {
                            0.0
                        }
                    })
                    .sum();
                threshold - field
            }
            Self::Union(items) => items
                .iter()
                .map(|s| s.eval(p))
                .fold(f64::INFINITY, f64::min),
            Self::Intersection(items) => items
                .iter()
                .map(|s| s.eval(p))
                .fold(f64::NEG_INFINITY, f64::max),
            Self::Difference(a, b) => a.eval(p).max(-b.eval(p)),
            Self::SmoothUnion { a, b, k } => {
                let (fa, fb) = (a.eval(p), b.eval(p));
                let h = (0.5 + 0.5 * (fb - fa) / k).clamp(0.0, 1.0);
                fb + (fa - fb) * h - k * h * (1.0 - h)
            }
            Self::Transformed {
                inner,
                to_local,
                scale,
            } => inner.eval(to_local.transform_point3(p)) * scale,
        }
    }

    /// `self` scaled, rotated about x, then y, then z (degrees), then translated — the order of
    /// [`crate::Transform::from_srt`]. `None` if a scale factor is zero or not finite.
    #[must_use]
    pub fn transformed(self, scale: DVec3, rotate_deg: DVec3, translate: DVec3) -> Option<Self> {
        let s = scale.abs().min_element();
        if !(s > 0.0 && scale.is_finite() && rotate_deg.is_finite() && translate.is_finite()) {
            return None;
        }
        let r = rotate_deg * (std::f64::consts::PI / 180.0);
        let rotation = DQuat::from_euler(EulerRot::ZYX, r.z, r.y, r.x);
        let map = DAffine3::from_scale_rotation_translation(scale, rotation, translate);
        Some(Self::Transformed {
            inner: Box::new(self),
            to_local: map.inverse(),
            scale: s,
        })
    }

    /// Whether |f(p)| never exceeds the distance from p to the surface (f is 1-Lipschitz), so
    /// that a cell of half-diagonal ρ with |f(centre)| > ρ holds no surface. True for the
    /// distance primitives and their min/max combinations; false for metaballs and smooth
    /// unions.
    #[must_use]
    pub fn is_distance_bound(&self) -> bool {
        match self {
            Self::Metaballs { .. } | Self::SmoothUnion { .. } => false,
            Self::Union(items) | Self::Intersection(items) => {
                items.iter().all(Self::is_distance_bound)
            }
            Self::Difference(a, b) => a.is_distance_bound() && b.is_distance_bound(),
            Self::Transformed { inner, .. } => inner.is_distance_bound(),
            _ => true,
        }
    }

    /// A box that contains the solid, if the solid is bounded (`None` for half-spaces and for
    /// differences and intersections whose every operand is unbounded).
    #[must_use]
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        match self {
            Self::Sphere { center, radius } => Some((*center - *radius, *center + *radius)),
            Self::Box { min, max } => Some((*min, *max)),
            Self::Torus {
                center,
                major,
                minor,
            } => {
                let e = DVec3::new(major + minor, *minor, major + minor);
                Some((*center - e, *center + e))
            }
            Self::Cylinder {
                center,
                radius,
                half_height,
            } => {
                let e = DVec3::new(*radius, *half_height, *radius);
                Some((*center - e, *center + e))
            }
            Self::Plane { .. } => None,
            Self::Metaballs { balls, .. } => balls
                .iter()
                .fold(None, |acc, (c, r)| merge(acc, Some((*c - *r, *c + *r)))),
            Self::Union(items) => items
                .iter()
                .try_fold(None, |acc, s| s.bounds().map(|b| merge(acc, Some(b))))?,
            Self::Intersection(items) => items
                .iter()
                .filter_map(Self::bounds)
                .reduce(|a, b| (a.0.max(b.0), a.1.min(b.1))),
            Self::Difference(a, _) => a.bounds(),
            Self::SmoothUnion { a, b, k } => {
                let (a, b) = (a.bounds()?, b.bounds()?);
                Some((a.0.min(b.0) - *k, a.1.max(b.1) + *k))
            }
            Self::Transformed {
                inner, to_local, ..
            } => {
                let (lo, hi) = inner.bounds()?;
                let to_world = to_local.inverse();
                let corners = (0..8).map(|i| {
                    to_world.transform_point3(DVec3::new(
                        if i & 1 == 0 { lo.x } else { hi.x },
                        if i & 2 == 0 { lo.y } else { hi.y },
                        if i & 4 == 0 { lo.z } else { hi.z },
                    ))
                });
                corners.fold(None, |acc, c| merge(acc, Some((c, c))))
            }
        }
    }
}

/// The box around two optional boxes.
fn merge(a: Option<(DVec3, DVec3)>, b: Option<(DVec3, DVec3)>) -> Option<(DVec3, DVec3)> {
    match (a, b) {
        (Some(a), Some(b)) => Some((a.0.min(b.0), a.1.max(b.1))),
        (a, None) => a,
        (None, b) => b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primitives_are_signed_distances() {
        let s = Sdf::Sphere {
            center: DVec3::ONE,
            radius: 2.0,
        };
        assert!((s.eval(DVec3::new(1.0, 4.0, 1.0)) - 1.0).abs() < 1e-12);
        assert!((s.eval(DVec3::ONE) + 2.0).abs() < 1e-12);
        let b = Sdf::Box {
            min: DVec3::ZERO,
            max: DVec3::ONE,
        };
        // Corner region: distance to the corner (1,1,1) from (2,2,2) is √3.
        assert!((b.eval(DVec3::splat(2.0)) - 3f64.sqrt()).abs() < 1e-12);
        assert!((b.eval(DVec3::splat(0.5)) + 0.5).abs() < 1e-12);
        let t = Sdf::Torus {
            center: DVec3::ZERO,
            major: 2.0,
            minor: 0.5,
        };
        assert!((t.eval(DVec3::new(2.0, 0.0, 0.0)) + 0.5).abs() < 1e-12);
        assert!((t.eval(DVec3::ZERO) - 1.5).abs() < 1e-12);
        let c = Sdf::Cylinder {
            center: DVec3::ZERO,
            radius: 1.0,
            half_height: 1.0,
        };
        assert!((c.eval(DVec3::new(0.0, 3.0, 0.0)) - 2.0).abs() < 1e-12);
        assert!((c.eval(DVec3::new(3.0, 0.0, 0.0)) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn transform_moves_and_scales() {
        let s = Sdf::Sphere {
            center: DVec3::ZERO,
            radius: 1.0,
        }
        .transformed(
            DVec3::splat(2.0),
            DVec3::new(0.0, 90.0, 0.0),
            DVec3::X * 5.0,
        )
        .unwrap();
        // A radius-2 ball at (5,0,0): distance from the origin is 3.
        assert!((s.eval(DVec3::ZERO) - 3.0).abs() < 1e-9);
        let (lo, hi) = s.bounds().unwrap();
        assert!((lo - DVec3::new(3.0, -2.0, -2.0)).length() < 1e-9, "{lo}");
        assert!((hi - DVec3::new(7.0, 2.0, 2.0)).length() < 1e-9, "{hi}");
        assert!(Sdf::Plane {
            normal: DVec3::Y,
            offset: 0.0
        }
        .transformed(DVec3::ZERO, DVec3::ZERO, DVec3::ZERO)
        .is_none());
    }

    #[test]
    fn smooth_union_is_below_union_within_k() {
        let a = Sdf::Sphere {
            center: DVec3::ZERO,
            radius: 1.0,
        };
        let b = Sdf::Sphere {
            center: DVec3::X * 1.5,
            radius: 1.0,
        };
        let k = 0.3;
        let u = Sdf::Union(vec![a.clone(), b.clone()]);
        let s = Sdf::SmoothUnion {
            a: Box::new(a),
            b: Box::new(b),
            k,
        };
        for i in 0..50 {
            let p = DVec3::new(-2.0 + 0.1 * f64::from(i), 0.3, 0.0);
            let (fu, fs) = (u.eval(p), s.eval(p));
            // The polynomial smooth minimum lies in [min − k/4, min].
            assert!(
                fs <= fu + 1e-12 && fs >= fu - k / 4.0 - 1e-12,
                "{p}: {fs} vs {fu}"
            );
        }
    }
}
