//! The split of each element's indirect light into the near part, gathered at every point
//! ([`super::near_field`]), and the far part, interpolated over the lit mesh (see the module
//! docs of [`super`]):
//!
//! ```text
//! R = (B_i − ρ N̄) / (1 − S̄),   k = 1          where ρ N̄ ≤ B_i,
//! R = 0,                        k = B_i / (ρ N̄) where the near part alone exceeds B_i,
//! ```
//!
//! per channel. The same split of the *incident* indirect light, the irradiance H_i that
//! falls on the element rather than the radiosity ρ H_i it reflects, is taken on request
//! (false-colour pictures of illuminance, [`super::measured`]):
//!
//! ```text
//! R_H = (H_i − N̄) / (1 − S̄),   k_H = 1          where N̄ ≤ H_i,
//! R_H = 0,                      k_H = H_i / N̄    where N̄ exceeds H_i.
//! ```
//!
//! Where ρ > 0 the two are one split (R = ρ R_H, k = k_H: the comparisons and ratios do not
//! depend on ρ), so ρ times the illuminance evaluated at a point is the reflected light the
//! picture shows there; where ρ = 0 the picture carries no trace of the light falling on the
//! surface, and R_H is still read from the solution's irradiance.

use super::near_field::{NearField, PIECES};
use super::{MIN_FAR_SHARE, MIN_OPEN, SETTLED_BATCH};
use crate::mesh::Mesh;
use crate::progress::Batched;
use crate::render::Watch;
use crate::Rgb;
use rayon::prelude::*;

/// What the split reads of the solution.
#[derive(Clone, Copy, Debug)]
pub(super) struct Lighting<'a> {
    /// B per element.
    pub radiosity: &'a [Rgb],
    /// The irradiance from reflected light per element ([`crate::solve::Solution::reflected_irradiance`]),
    /// where the solver keeps it.
    pub reflected: Option<&'a [Rgb]>,
    /// The whole irradiance H per element ([`crate::solve::Solution::irradiance`]): given when
    /// the incident split is asked for.
    pub irradiance: Option<&'a [Rgb]>,
}

/// A split of indirect light between the near and the far part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Split {
    /// R: the far part per share of the view left to it.
    pub far: Rgb,
    /// k: the factor of the near part (1 unless the near part alone exceeds the indirect
    /// light).
    pub scale: Rgb,
}

/// The split of `indirect` light whose near part has the mean `near` over the element and
/// takes the share `share` of its view (module docs).
fn split(indirect: Rgb, near: Rgb, share: f64) -> Split {
    let left = (1.0 - share).max(MIN_FAR_SHARE);
    let (mut far, mut scale) = (Rgb::ZERO, Rgb::ONE);
    for c in 0..3 {
        if near[c] > indirect[c] {
            scale[c] = (indirect[c] / near[c]).max(0.0);
        } else {
            far[c] = (indirect[c] - near[c]) / left;
        }
    }
    Split { far, scale }
}

/// An element's split of its indirect light (see [`far_radiosity`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Far {
    /// R: the far part per share of the view left to it.
    pub far: Rgb,
    /// k: the factor of the near part (1 unless the near part alone exceeds the indirect
    /// light).
    pub scale: Rgb,
    /// B − E at each piece.
    pub pieces: [Rgb; PIECES],
    /// Whether some piece sees an element close enough to be shown by its pieces.
    pub by_pieces: bool,
    /// The split of the incident indirect light, when asked for (module docs).
    pub incident: Option<Split>,
}

impl Far {
    /// All of `indirect` in the far part, no near part; likewise the incident light
    /// `incident`, if given.
    fn flat(indirect: Rgb, incident: Option<Rgb>) -> Self {
        Self {
            far: indirect,
            scale: Rgb::ONE,
            pieces: [indirect; PIECES],
            by_pieces: false,
            incident: incident.map(|far| Split {
                far,
                scale: Rgb::ONE,
            }),
        }
    }
}

/// Every element's split of its indirect light B_i = B − E − ρ Ē_d into the near part and the
/// far part, the means taken over its pieces (`direct`: E_d at each, the irradiance straight
/// from the luminaires), as the module docs say, per channel. The near field takes every
/// surface within reach as seen, so in a narrow space (a shelf's compartment, the gap behind
/// it) it can count more light than the solution's visibility lets the element gather; a
/// negative R there made points of the element swing far from its mean (to zero and below), so
/// the near part is scaled down to the indirect light instead, keeping the mean. B − E at each
/// piece is ρ E_d + k ρ N + R (1 − S) there, which the near field shows to the points next to
/// the element. Where `known` holds an element's split already (none of its pieces sees an
/// element close enough to be shown by its pieces, so the pieces change nothing), that is
/// taken instead. An element that `wanted` leaves out (no point of the picture reads it,
/// [`super::wanted`]) gets R = B_i with no near part, from the solution's reflected light.
/// With the solution's irradiance in `lighting`, the incident split is taken too, from
/// H_i = H_r (the reflected irradiance) or H − Ē_d, over the element's open part.
pub(super) fn far_radiosity(
    mesh: &Mesh,
    lighting: Lighting<'_>,
    open: &[f64],
    (near_field, direct): (&NearField, &[[Rgb; PIECES]]),
    (known, wanted): (Option<&[Option<Far>]>, Option<&[bool]>),
    watch: &Watch,
) -> Vec<Far> {
    let settled = Batched::new(watch.progress, SETTLED_BATCH);
    let far = (0..mesh.element_count())
        .into_par_iter()
        .map(|e| {
            if wanted.is_none_or(|w| w[e]) {
                settled.one();
            }
            if let Some(far) = known.and_then(|k| k[e]) {
                return far;
            }
            let incident = lighting.irradiance.is_some();
            if watch.stopped() {
                return Far::flat(Rgb::ZERO, incident.then_some(Rgb::ZERO));
            }
            let node = mesh.element(e);
            let patch = &mesh.patches[node.patch as usize];
            let within = open[e].max(MIN_OPEN);
            // H_i and B_i over the element's open part, from the solution's reflected light.
            let received = lighting.reflected.map(|h| h[e] / within);
            let reflected = lighting
                .reflected
                .map(|h| patch.reflectance * h[e] / within);
            if let (Some(false), Some(indirect)) = (wanted.map(|w| w[e]), reflected) {
                return Far::flat(indirect, received.filter(|_| incident));
            }
            let at = &near_field.pieces[e];
            let mut parts = [(Rgb::ZERO, Rgb::ZERO, 0.0); PIECES];
            let (mut lit, mut near, mut share, mut area) = (Rgb::ZERO, Rgb::ZERO, 0.0, 0.0);
            // The same means before the reflectance: E_d and N.
            let (mut lit_in, mut near_in) = (Rgb::ZERO, Rgb::ZERO);
            let mut by_pieces = false;
            let seen = near_field.irradiance_at(mesh, at.centroids, patch.normal, node.patch);
            for (k, &(n, s, p)) in seen.iter().enumerate() {
                parts[k] = (patch.reflectance * direct[e][k], patch.reflectance * n, s);
                let a = at.areas[k];
                lit += parts[k].0 * a;
                near += parts[k].1 * a;
                share += s * a;
                area += a;
                by_pieces |= p;
                if incident {
                    lit_in += direct[e][k] * a;
                    near_in += n * a;
                }
            }
            let (lit, near, share) = (lit / area, near / area, share / area);
            let indirect = reflected
                .unwrap_or_else(|| (lighting.radiosity[e] - patch.emission - lit) / within);
            let Split { far, scale } = split(indirect, near, share);
            // Where the far share was clamped (or B_i < 0) the pieces' mean is not the
            // element's: shifted back, so that the pieces only redistribute its light.
            let shift = indirect - (scale * near + far * (1.0 - share));
            let incident = lighting.irradiance.map(|h| {
                let received = received.unwrap_or_else(|| (h[e] - lit_in / area) / within);
                split(received, near_in / area, share)
            });
            Far {
                far,
                scale,
                pieces: parts.map(|(d, n, s)| d + scale * n + far * (1.0 - s) + shift),
                by_pieces,
                incident,
            }
        })
        .collect();
    drop(settled);
    far
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where ρ > 0 the incident split is the reflected one divided by ρ, channel by channel,
    /// also where the near part is scaled down.
    #[test]
    fn the_incident_split_is_the_reflected_one_over_rho() {
        let rho = Rgb::new(0.7, 0.25, 0.5);
        let h = Rgb::new(3.0, 1.0, 0.2);
        let n = Rgb::new(1.0, 0.5, 0.4);
        let share = 0.3;
        let reflected = split(rho * h, rho * n, share);
        let incident = split(h, n, share);
        for c in 0..3 {
            let far = reflected.far[c] / rho[c];
            assert!((far - incident.far[c]).abs() <= 1e-12 * far.abs().max(1.0));
            assert!((reflected.scale[c] - incident.scale[c]).abs() <= 1e-12);
        }
        // The third channel's near part exceeds its indirect light: scaled, no far part.
        assert_eq!(incident.far.z, 0.0);
        assert!((incident.scale.z - 0.5).abs() < 1e-12);
        // Where ρ = 0 the reflected split says nothing; the incident one still does.
        let black = split(Rgb::ZERO, Rgb::ZERO, share);
        assert_eq!(black.far, Rgb::ZERO);
        assert!(incident.far.x > 0.0);
    }
}
