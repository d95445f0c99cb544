//! Packing: the charts' boxes placed side by side in one texture, the light map's atlas.
//!
//! Each chart ([`super::chart`]) is scaled by the texel density (texels per scene unit) and
//! takes the box around it grown by a gutter of `padding` texels on every side, so two charts
//! are at least 2 × `padding` texels apart and bilinear filtering never mixes one chart's texels
//! into another's (mip levels would, which is why the textures have none: [`crate::io::baked`]).
//! The boxes are placed by *shelves* (the "next fit decreasing height" strip packing of Coffman
//! et al. 1980, the heuristic many light-map packers start from): tallest first, left to right
//! along a shelf as wide as the atlas, a new shelf above the tallest box of the last one when
//! the next box does not fit.
//!
//! Given a density, the atlas is made about square: as wide as the square root of the boxes'
//! total area, or the widest box, in multiples of 4 texels. Given a size instead
//! (`--lightmap-size`), the density is the largest that fits, found by bisection.

use glam::DVec2;

use super::chart::Chart;

/// Where the charts went.
#[derive(Clone, Debug, PartialEq)]
pub struct Atlas {
    /// Width and height, texels.
    pub size: (u32, u32),
    /// Texels per scene unit.
    pub density: f64,
    /// Texels between a chart's box and its content, on every side.
    pub padding: u32,
    /// Per chart: its box's lower corner in the atlas, texels (x right, y down).
    pub corners: Vec<(u32, u32)>,
}

impl Atlas {
    /// The atlas position, in texels, of `q` of chart `c` (`q` in the chart's plane, scene
    /// units).
    #[must_use]
    pub fn texel(&self, charts: &[Chart], c: usize, q: DVec2) -> DVec2 {
        let (x, y) = self.corners[c];
        DVec2::new(f64::from(x), f64::from(y))
            + f64::from(self.padding)
            + (q - charts[c].min) * self.density
    }
}

/// The charts packed at `density` texels per scene unit with `padding` texels around each,
/// in an about square atlas (module docs).
#[must_use]
pub fn at_density(charts: &[Chart], density: f64, padding: u32) -> Atlas {
    let boxes = boxes(charts, density, padding);
    let area: f64 = boxes
        .iter()
        .map(|&(w, h)| f64::from(w) * f64::from(h))
        .sum();
    let widest = boxes.iter().map(|b| b.0).max().unwrap_or(1);
    let width = round4(widest.max(area.sqrt().ceil() as u32));
    let (corners, height) = shelves(&boxes, width);
    Atlas {
        size: (width, round4(height.max(1))),
        density,
        padding,
        corners,
    }
}

/// The charts packed into a `size` × `size` atlas at the largest density that fits (module
/// docs); `None` when not even a density near zero does (more charts than gutters fit).
#[must_use]
pub fn into_size(charts: &[Chart], size: u32, padding: u32) -> Option<Atlas> {
    let fits = |density: f64| {
        let boxes = boxes(charts, density, padding);
        boxes.iter().all(|b| b.0 <= size) && shelves(&boxes, size).1 <= size
    };
    let extent = charts
        .iter()
        .map(|c| (c.max - c.min).max_element())
        .fold(0.0, f64::max);
    if extent <= 0.0 {
        return None;
    }
    let (mut lo, mut hi) = (0.0, f64::from(size) / extent);
    if !fits(lo) {
        return None;
    }
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let boxes = boxes(charts, lo, padding);
    let (corners, _) = shelves(&boxes, size);
    Some(Atlas {
        size: (size, size),
        density: lo,
        padding,
        corners,
    })
}

/// Each chart's box at `density`, texels: its extent rounded up, one texel more so that a
/// texel centre lies beyond each edge, and the gutter on both sides.
fn boxes(charts: &[Chart], density: f64, padding: u32) -> Vec<(u32, u32)> {
    charts
        .iter()
        .map(|c| {
            let e = (c.max - c.min) * density;
            // Saturating: an absurd density makes an atlas too large, never a wrapped small one.
            let side = |x: f64| {
                (x.ceil().min(f64::from(u32::MAX / 4)) as u32).saturating_add(1 + 2 * padding)
            };
            (side(e.x), side(e.y))
        })
        .collect()
}

/// Shelf placement of `boxes` in an atlas `width` wide: each box's corner and the height used.
fn shelves(boxes: &[(u32, u32)], width: u32) -> (Vec<(u32, u32)>, u32) {
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by_key(|&i| (std::cmp::Reverse(boxes[i].1), i));
    let mut corners = vec![(0, 0); boxes.len()];
    let (mut x, mut y, mut shelf) = (0u32, 0u32, 0u32);
    for i in order {
        let (w, h) = boxes[i];
        if x.saturating_add(w) > width && x > 0 {
            y = y.saturating_add(shelf);
            x = 0;
            shelf = 0;
        }
        corners[i] = (x, y);
        x = x.saturating_add(w);
        shelf = shelf.max(h);
    }
    (corners, y.saturating_add(shelf))
}

/// `n` rounded up to a multiple of 4.
fn round4(n: u32) -> u32 {
    n.div_ceil(4).saturating_mul(4)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::chart;
    use crate::testing;

    /// No two charts' boxes overlap, every box lies in the atlas.
    fn check(charts: &[Chart], atlas: &Atlas) {
        let boxes = boxes(charts, atlas.density, atlas.padding);
        for (i, (&(x, y), &(w, h))) in atlas.corners.iter().zip(&boxes).enumerate() {
            assert!(x + w <= atlas.size.0 && y + h <= atlas.size.1, "box {i}");
            for (j, (&(a, b), &(u, v))) in atlas.corners.iter().zip(&boxes).enumerate() {
                if i != j {
                    let apart = x + w <= a || a + u <= x || y + h <= b || b + v <= y;
                    assert!(apart, "boxes {i} and {j} overlap");
                }
            }
        }
    }

    #[test]
    fn a_density_gives_each_unit_that_many_texels() {
        let scene = testing::closed_cube(0.5, [0.0; 6]);
        let charts = chart::charts(&scene);
        let atlas = at_density(&charts, 32.0, 2);
        check(&charts, &atlas);
        // A unit face spans 32 texels; its content starts `padding` texels into its box.
        let c = &charts[0];
        let (a, b) = (
            atlas.texel(&charts, 0, c.min),
            atlas.texel(&charts, 0, c.max),
        );
        assert!(((b - a) - DVec2::splat(32.0)).abs().max_element() < 1e-9);
        let (x, y) = atlas.corners[0];
        assert_eq!(a, DVec2::new(f64::from(x) + 2.0, f64::from(y) + 2.0));
        assert_eq!((atlas.size.0 % 4, atlas.size.1 % 4), (0, 0));
    }

    #[test]
    fn a_size_is_filled_at_the_largest_density_that_fits() {
        let scene = testing::closed_cube(0.5, [0.0; 6]);
        let charts = chart::charts(&scene);
        let atlas = into_size(&charts, 256, 2).unwrap();
        check(&charts, &atlas);
        assert_eq!(atlas.size, (256, 256));
        // Six unit squares in 256²: three to a shelf of 256 texels, two shelves, each box
        // ⌈d⌉ + 1 + 4 wide: d just under 80.
        assert!(
            atlas.density > 79.9 && atlas.density <= 80.0,
            "{}",
            atlas.density
        );
    }
}
