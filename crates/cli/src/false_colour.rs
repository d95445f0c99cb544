//! `render --false-colour`: its flags, checked before any work, and its files — the picture
//! in false colour with its legend for `.png`, the values themselves for the float formats
//! ([`radiosity::render::false_colour`]).

use std::path::Path;

use anyhow::{anyhow, bail, Result};
use radiosity::color::scale::{label, Scale, ScaleError, Spacing};
use radiosity::pipeline::Solved;
use radiosity::render::false_colour::Quantity;
use radiosity::render::{Image, ModeKind, RasterSettings};
use radiosity::scene::Camera;

use crate::args::RenderArgs;
use crate::picture;

/// Checks the false-colour flags: `--false-colour-scale` and `--false-colour-range` only with
/// `--false-colour`, which measures the evaluated picture (`--mode final`) and takes no
/// exposure; returns the scale `--false-colour-range` gives, if any.
pub fn scale(args: &RenderArgs) -> Result<Option<Scale>> {
    let Some(quantity) = args.false_colour else {
        if args.false_colour_scale.is_some() {
            bail!("--false-colour-scale applies to --false-colour only");
        }
        if args.false_colour_range.is_some() {
            bail!("--false-colour-range applies to --false-colour only");
        }
        return Ok(None);
    };
    if args.mode != ModeKind::Final {
        bail!(
            "--false-colour {quantity} measures the light as the evaluated picture takes it: \
             leave out --mode {}",
            args.mode
        );
    }
    if args.exposure.is_some() {
        bail!("--exposure does not apply to --false-colour (its colours follow the scale)");
    }
    let spacing = args.false_colour_scale.unwrap_or(Spacing::Log);
    args.false_colour_range
        .map(|(lo, hi)| {
            Scale::new(lo, hi, spacing).map_err(|e| match e {
                ScaleError::LogOfZero { .. } => {
                    anyhow!("--false-colour-range: {e} (or --false-colour-scale linear)")
                }
                ScaleError::Order { .. } => anyhow!("--false-colour-range: {e}"),
            })
        })
        .transpose()
}

/// A false-colour render's images, and the line that says its scale.
pub struct Pictures {
    /// The picture in false colour with its legend (for `.png`).
    pub colours: Image,
    /// The values on all three channels (for `.exr`, `.hdr`, `.pfm`).
    pub values: Image,
    /// `false colour: lux on a log scale from 20 to 1000 lx (fitted)`.
    pub note: String,
}

impl Pictures {
    /// The image a file at `path` holds: the colours in a PNG, the values in a float format.
    pub fn for_path(&self, path: &Path) -> &Image {
        let png = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if png {
            &self.colours
        } else {
            &self.values
        }
    }
}

/// Measures `quantity` in the solved scene through `camera` at the size of `raster`, on the
/// scale `--false-colour-range` gives or one fitted to the values.
pub fn pictures(
    args: &RenderArgs,
    quantity: Quantity,
    (solved, camera, raster): (&Solved, &Camera, &RasterSettings),
) -> Result<Pictures> {
    let reporting = args.common.run.reporting();
    let measurement = picture::measure(solved, camera, quantity, raster, reporting)?;
    let spacing = args.false_colour_scale.unwrap_or(Spacing::Log);
    let (scale, how) = match scale(args)? {
        Some(scale) => (scale, "given"),
        None => (Scale::fitted(measurement.seen(), spacing), "fitted"),
    };
    let note = format!(
        "false colour: {quantity} on a {} scale from {} to {} {} ({how})",
        scale.spacing,
        label(scale.lo),
        label(scale.hi),
        quantity.unit()
    );
    Ok(Pictures {
        colours: measurement.picture(&scale),
        values: measurement.data(),
        note,
    })
}
