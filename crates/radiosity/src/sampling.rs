//! Sampling distributions: maps from uniform numbers in [0, 1) to the directions the engine
//! shoots rays in. The uniform numbers come from [`crate::hash`]; this module only shapes them.
//!
//! **Cosine-weighted hemisphere** (Malley's method; Pharr, Jakob & Humphreys, *Physically Based
//! Rendering*, §13.6.3): a point of the unit disk uniform in area, r = √u₁, φ = 2πu₂, lifted
//! straight up onto the hemisphere, z = √(1 − u₁), has density
//!
//! p(ω) = cos θ / π
//!
//! over solid angle, because the projection of the hemisphere onto the disk has Jacobian
//! cos θ. It is the density of the irradiance integral's kernel, so a gather with it weighs
//! every ray alike. The final gather of the ray tracer and the incoherent rays of the ray
//! benchmark both draw their directions here.

use glam::Vec3;

/// A unit vector in the hemisphere around unit `n`, with density cos θ / π, from (u₁, u₂) ∈
/// [0, 1)² (Malley's method, see the module docs). u₁ sets the angle from `n` (stratify it to
/// stratify the cosines), u₂ the turn about `n`. Should rounding leave the sum without
/// a length, `n` itself is returned.
///
/// ```
/// use glam::Vec3;
/// use radiosity::sampling::cosine_direction;
/// // u₁ = 0 is the pole: the normal itself.
/// assert!((cosine_direction(Vec3::Z, 0.0, 0.3) - Vec3::Z).length() < 1e-6);
/// ```
#[must_use]
pub fn cosine_direction(n: Vec3, u1: f32, u2: f32) -> Vec3 {
    let r = u1.sqrt();
    let phi = std::f32::consts::TAU * u2;
    let (t, b) = n.any_orthonormal_pair();
    let z = (1.0 - u1).max(0.0).sqrt();
    (t * (r * phi.cos()) + b * (r * phi.sin()) + n * z).normalize_or(n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::{mix, unit_f32};

    /// The k-th number in [0, 1) of a hashed stream (24 bits, exact in f32).
    fn unit(k: u64) -> f32 {
        unit_f32(mix(k))
    }

    #[test]
    fn cosine_directions_have_mean_cosine_two_thirds() {
        // E[cos θ] under the density cos θ / π is 2/3; 4096 stratified samples, tolerance 0.01.
        let n = Vec3::new(1.0, 2.0, -0.5).normalize();
        let mut sum = 0.0;
        for k in 0..4096u64 {
            let u1 = (k as f32 + unit(2 * k)) / 4096.0;
            let d = cosine_direction(n, u1, unit(2 * k + 1));
            assert!((d.length() - 1.0).abs() < 1e-5 && d.dot(n) >= 0.0);
            sum += d.dot(n);
        }
        assert!((sum / 4096.0 - 2.0 / 3.0).abs() < 0.01, "{}", sum / 4096.0);
    }
}
