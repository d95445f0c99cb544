//! Ideal specular reflection and refraction at a smooth interface.
//!
//! With a unit incident direction d travelling towards the surface and the unit normal n on its
//! side (d·n < 0):
//!
//! - **Mirror reflection**: r = d − 2 (d·n) n.
//! - **Snell's law**: η₁ sin θ₁ = η₂ sin θ₂. With η = η₁/η₂ and cos θ₁ = −d·n, the refracted
//!   direction is t = η d + (η cos θ₁ − cos θ₂) n, cos θ₂ = √(1 − η² (1 − cos² θ₁)).
//! - **Total internal reflection**: when η sin θ₁ > 1 (only possible going from the denser
//!   medium, past the critical angle θ_c = asin(η₂/η₁)) there is no refracted ray and all the
//!   light is reflected.
//! - **Fresnel reflectance** of unpolarised light at a dielectric interface, exact:
//!   R_s = ((η₁ cos θ₁ − η₂ cos θ₂)/(η₁ cos θ₁ + η₂ cos θ₂))²,
//!   R_p = ((η₁ cos θ₂ − η₂ cos θ₁)/(η₁ cos θ₂ + η₂ cos θ₁))², F = (R_s + R_p)/2.
//!   At normal incidence F = ((η₁ − η₂)/(η₁ + η₂))², 0.04 for glass (η = 1.5) in air. The
//!   transmitted fraction is 1 − F (no absorption at the interface itself).
//!
//! Reference: Hecht, *Optics*, §4.6; Whitted 1980 uses the same two rays per hit.

use glam::Vec3;

/// The mirror reflection of direction `d` about unit normal `n`: d − 2(d·n)n.
#[must_use]
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// The refracted direction of unit `d` through an interface with unit normal `n` on the side
/// `d` comes from (d·n < 0), with `eta` = η₁/η₂ (incident over transmitted index); `None` past
/// the critical angle (total internal reflection).
#[must_use]
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = (-d.dot(n)).clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((eta * d + (eta * cos_i - cos_t) * n).normalize_or_zero())
}

/// Fresnel reflectance of unpolarised light arriving at angle cos θ₁ = `cos_i` from a medium of
/// index `eta_i` onto one of index `eta_t` (exact dielectric formula); 1 past the critical angle.
#[must_use]
pub fn fresnel_dielectric(cos_i: f64, eta_i: f64, eta_t: f64) -> f64 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin_t = eta_i / eta_t * (1.0 - cos_i * cos_i).sqrt();
    if sin_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t * sin_t).sqrt();
    let rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
    let rp = (eta_i * cos_t - eta_t * cos_i) / (eta_i * cos_t + eta_t * cos_i);
    if !(rs.is_finite() && rp.is_finite()) {
        return 1.0; // grazing incidence with η₁ = η₂ = 0 or similar nonsense: reflect.
    }
    0.5 * (rs * rs + rp * rp)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflection_keeps_the_angle_and_flips_the_normal_part() {
        let n = Vec3::Y;
        let d = Vec3::new(0.6, -0.8, 0.0);
        let r = reflect(d, n);
        assert!((r - Vec3::new(0.6, 0.8, 0.0)).length() < 1e-6);
    }

    #[test]
    fn fresnel_is_continuous_and_reaches_one_at_grazing_incidence() {
        // At 89.9° incidence F ≈ 0.990 (F → 1 as θ → 90°, linearly in cos θ).
        assert!(fresnel_dielectric(0.001_745, 1.0, 1.5) > 0.985);
        let mut last = 0.0;
        for k in (0..=100).rev() {
            let f = fresnel_dielectric(f64::from(k) / 100.0, 1.0, 1.5);
            assert!(f >= last - 1e-12, "F must grow as the angle grows");
            last = f;
        }
    }
}
