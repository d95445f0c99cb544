//! A luminaire's object into a [`Luminaire`]: its distribution from its photometric file or its
//! shorthand, placed by the object's transform; or a directional light, turned by it.

use std::sync::Arc;

use model::Transform;

use super::super::check::fail;
use super::super::description::{Field, LightDesc, LuminaireDesc, SceneDesc, Strength};
use super::super::luminaire::{isotropic, spot, Falloff, Luminaire};
use super::super::SceneError;
use crate::color::luminance;
use crate::photometry;
use crate::Rgb;

/// The luminaire `name` of the checked keys `l`, its position and aim mapped by `transform`;
/// `metres` is the scene's length unit.
///
/// # Errors
/// The photometric file cannot be read or is malformed: the message names the scene's key
/// and the file's line.
pub(super) fn build(
    desc: &SceneDesc,
    name: &str,
    l: &LuminaireDesc,
    transform: &Transform,
    metres: f64,
) -> Result<Luminaire, SceneError> {
    let tint = l
        .colour
        .as_ref()
        .map_or(Rgb::ONE, |c| c.value / luminance(c.value))
        * l.multiplier.value;
    let mut opening = None;
    let distribution = match &l.light {
        LightDesc::Directional(illuminance) => {
            let aim = transform.vector(l.aim.value);
            return Ok(Luminaire::directional(
                name,
                aim,
                tint * illuminance.value,
                metres,
            ));
        }
        LightDesc::File(path, use_opening) => {
            let file = read(desc, path)?;
            if use_opening.value {
                let o = file.opening;
                if o.length <= 0.0 || o.length.is_nan() {
                    let message =
                        format!("`{}` declares no luminous opening", path.value.display());
                    return Err(fail(desc, use_opening, message));
                }
                let width = if o.width > 0.0 { o.width } else { o.length };
                opening = Some((o.length / metres, width / metres, o.round));
            }
            file.distribution
        }
        LightDesc::Point(strength) => {
            // Φ = 4π I.
            isotropic(candela(strength, 4.0 * std::f64::consts::PI))
        }
        LightDesc::Spot {
            strength,
            cone,
            beam,
        } => {
            let beam = beam.as_ref().map_or(0.75 * cone.value, |b| b.value);
            let falloff = Falloff::SquaredCosineRamp;
            let unit = spot(1.0, beam, cone.value, falloff);
            spot(candela(strength, unit.flux()), beam, cone.value, falloff)
        }
    };
    let luminaire = Luminaire::new(
        name,
        transform.point(l.position.value),
        transform.vector(l.aim.value),
        l.rotation.value,
        Arc::new(distribution),
        tint,
        metres,
    );
    Ok(match opening {
        Some((length, width, round)) => luminaire.with_opening(length, width, round),
        None => luminaire,
    })
}

/// The intensity of a shorthand light, cd: as given, or its flux over `flux_per_candela`.
fn candela(strength: &Strength, flux_per_candela: f64) -> f64 {
    match strength {
        Strength::Intensity(i) => i.value,
        Strength::Flux(f) => f.value / flux_per_candela,
    }
}

/// The photometric file at `path` (relative to the scene file; a built-in
/// scene's own files are compiled in, [`super::super::builtin::bundled`]).
fn read(
    desc: &SceneDesc,
    path: &Field<std::path::PathBuf>,
) -> Result<photometry::PhotometricFile, SceneError> {
    let full = super::beside(desc, &path.value);
    let file = match (
        super::super::builtin::bundled(&full),
        photometry::Format::from_path(&full),
    ) {
        (Some(text), Some(format)) => photometry::parse(format, text, &full),
        _ => photometry::read(&full),
    };
    file.map_err(|e| fail(desc, path, e.to_string()))
}
