//! Colour: linear RGB, three independent channels, in double precision.
//!
//! Radiometric quantities (radiance, radiosity, exitance, reflectance) are accumulated over many
//! bounces and many elements, so they are kept in `f64`; geometry is `f32` (see ARCHITECTURE.md).

/// A linear RGB triple: reflectance, radiance (W·m⁻²·sr⁻¹) or radiosity (W·m⁻²) per channel.
pub type Rgb = glam::DVec3;

/// Rec. 709 luminance weights of a linear RGB triple.
#[must_use]
pub fn luminance(c: Rgb) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}
