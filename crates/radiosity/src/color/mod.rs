//! Colour: linear RGB, three independent channels, in double precision.
//!
//! Radiometric quantities (radiance, radiosity, exitance, reflectance) are accumulated over many
//! bounces and many elements, so they are kept in `f64`; geometry is `f32` (see ARCHITECTURE.md).
//!
//! [`scale`] holds the false-colour scale that plots and pictures of light share.

pub mod scale;

/// A linear RGB triple: reflectance, radiance (W·m⁻²·sr⁻¹) or radiosity (W·m⁻²) per channel.
pub type Rgb = glam::DVec3;

/// Rec. 709 luminance weights of a linear RGB triple.
#[must_use]
pub fn luminance(c: Rgb) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// The linear value of an sRGB-encoded one in [0, 1], the inverse of the sRGB transfer
/// function (IEC 61966-2-1): L = V/12.92 for V ≤ 0.040 45, ((V + 0.055)/1.055)^2.4 otherwise.
/// The one decoder of 8- and 16-bit images, hex colours and texture texels.
#[must_use]
pub fn srgb_to_linear(encoded: f64) -> f64 {
    if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear sRGB (Rec. 709 primaries, D65 white) of CIE 1931 XYZ tristimulus values, the
/// matrix of IEC 61966-2-1.
#[must_use]
pub fn xyz_to_linear_srgb(xyz: glam::DVec3) -> Rgb {
    Rgb::new(
        3.240_479 * xyz.x - 1.537_150 * xyz.y - 0.498_535 * xyz.z,
        -0.969_256 * xyz.x + 1.875_991 * xyz.y + 0.041_556 * xyz.z,
        0.055_648 * xyz.x - 0.204_043 * xyz.y + 1.057_311 * xyz.z,
    )
}

/// The CIE 1931 2° colour-matching functions (x̄, ȳ, z̄) at wavelength `nm`, in the
/// multi-lobe fit of Wyman, Sloan & Shirley 2013, "Simple Analytic Approximations to the CIE
/// XYZ Color Matching Functions" (JCGT 2(2)): sums of piecewise Gaussians
/// g(λ; μ, σ₁, σ₂) = exp(−½ ((λ − μ)/σ)²), σ = σ₁ below μ and σ₂ above, within about 1 % of
/// the tabulated functions where they matter.
#[must_use]
pub fn cie_1931(nm: f64) -> glam::DVec3 {
    let g = |mu: f64, below: f64, above: f64| {
        let t = (nm - mu) / if nm < mu { below } else { above };
        (-0.5 * t * t).exp()
    };
    glam::DVec3::new(
        1.056 * g(599.8, 37.9, 31.0) + 0.362 * g(442.0, 16.0, 26.7) - 0.065 * g(501.1, 20.4, 26.2),
        0.821 * g(568.8, 46.9, 40.5) + 0.286 * g(530.9, 16.3, 31.1),
        1.217 * g(437.0, 11.8, 36.0) + 0.681 * g(459.0, 26.0, 13.8),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_d65_white_point_is_white() {
        // D65: x = 0.3127, y = 0.3290, Y = 1.
        let (x, y) = (0.3127, 0.3290);
        let rgb = xyz_to_linear_srgb(glam::DVec3::new(x / y, 1.0, (1.0 - x - y) / y));
        assert!((rgb - Rgb::ONE).abs().max_element() < 1e-3, "{rgb}");
        assert!((luminance(rgb) - 1.0).abs() < 1e-3);
    }

    #[test]
    fn the_colour_matching_fit_has_the_tabulated_areas() {
        // CIE 1931 at 1 nm from 360 to 830 nm: Σx̄ = 106.866, Σȳ = 106.857, Σz̄ = 106.892;
        // the fit is within 0.5 % of each.
        let sum: glam::DVec3 = (360..=830).map(|nm| cie_1931(f64::from(nm))).sum();
        for (fit, table) in sum.to_array().into_iter().zip([106.866, 106.857, 106.892]) {
            assert!((fit / table - 1.0).abs() < 5e-3, "{fit} vs {table}");
        }
        // ȳ peaks at 1 near 555 nm.
        assert!((cie_1931(555.0).y - 1.0).abs() < 0.01);
    }
}
