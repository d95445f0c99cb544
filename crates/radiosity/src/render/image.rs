//! An image of linear radiance.
//!
//! Pixels hold radiance L (W·m⁻²·sr⁻¹) per channel, linear, before any tone mapping. A diffuse
//! surface of radiosity B has radiance L = B/π, so an image rendered from the lit mesh matches a
//! path tracer's image of the same scene pixel for pixel.

use crate::Rgb;

/// A row-major image of linear radiance; pixel (x, y) is column x (to the right) of row y
/// (downward), and covers the square [x, x+1) × [y, y+1) of the image plane.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width · height` pixels, row by row from the top, radiance per channel.
    pub pixels: Vec<Rgb>,
}

impl Image {
    /// A black image of the given size, or `None` if `stopped()` turns true while it is made:
    /// the pixels are zeroed a slice of 2²¹ at a time (a 16384² image is 6 GiB, seconds of
    /// writing), so a stop is heard within one slice.
    #[must_use]
    pub fn new_unless(width: u32, height: u32, stopped: impl Fn() -> bool) -> Option<Self> {
        const SLICE: usize = 1 << 21;
        let n = width as usize * height as usize;
        let mut pixels = Vec::with_capacity(n);
        while pixels.len() < n {
            if stopped() {
                return None;
            }
            let more = SLICE.min(n - pixels.len());
            pixels.extend(std::iter::repeat_n(Rgb::ZERO, more));
        }
        Some(Self {
            width,
            height,
            pixels,
        })
    }

    /// A black image of the given size.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Rgb::ZERO; width as usize * height as usize],
        }
    }

    /// The radiance of pixel (x, y).
    ///
    /// # Panics
    /// If x ≥ width or y ≥ height.
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> Rgb {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside a {}×{} image",
            self.width,
            self.height
        );
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// The mean radiance over all pixels (zero for an empty image).
    #[must_use]
    pub fn mean(&self) -> Rgb {
        if self.pixels.is_empty() {
            return Rgb::ZERO;
        }
        self.pixels.iter().sum::<Rgb>() / self.pixels.len() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn get_is_row_major_and_mean_averages() {
        let mut image = Image::new(3, 2);
        image.pixels[4] = Rgb::new(6.0, 0.0, 12.0); // x = 1, y = 1
        assert_eq!(image.get(1, 1), Rgb::new(6.0, 0.0, 12.0));
        assert_eq!(image.get(1, 0), Rgb::ZERO);
        assert_eq!(image.mean(), Rgb::new(1.0, 0.0, 2.0));
        assert_eq!(Image::new(0, 5).mean(), Rgb::ZERO);
    }

    #[test]
    fn an_image_made_unless_stopped_is_black_or_none() {
        // More than one slice of pixels, so the stop is asked more than once.
        let calls = std::cell::Cell::new(0);
        let image = Image::new_unless(2048, 1100, || {
            calls.set(calls.get() + 1);
            false
        });
        assert_eq!(image, Some(Image::new(2048, 1100)));
        assert_eq!(calls.get(), 2);
        assert_eq!(Image::new_unless(2048, 1100, || true), None);
    }
}
