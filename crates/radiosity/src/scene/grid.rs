//! Calculation grids: the points at which lighting standards ask for illuminance.
//!
//! A lighting design is judged by the illuminance on *task areas* — a desk, the floor of a
//! corridor, a wall with paintings — read at a grid of points (EN 12464-1 §4.4, CIE 171:2006
//! §2). A grid here is a parallelogram given by three corners,
//!
//! ```text
//! o = corners[0],   a = corners[1] − o,   b = corners[2] − o,
//! ```
//!
//! cut into n_a × n_b equal cells, n = ⌈|axis| / spacing⌉ (at least 1), so that no cell is
//! wider than the spacing asked; the points are the cells' centres,
//!
//! ```text
//! p_ij = o + (i + ½)/n_a · a + (j + ½)/n_b · b,
//! ```
//!
//! as the standard places them (a point on the border of a room would sit in the wall's contact
//! shadow). Each point measures the illuminance on a small surface facing `normal`: by default
//! straight up (+y, the horizontal illuminance of a work plane) when the grid is horizontal,
//! else the right-hand normal a × b / |a × b|.

use glam::Vec3;

/// Most points one grid may hold.
pub const MAX_POINTS: u64 = 1_000_000;

/// A calculation grid in scene coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// The grid's name (its output files are named for it).
    pub name: String,
    /// The first corner, o.
    pub origin: Vec3,
    /// The first axis a (from o to the second corner).
    pub first: Vec3,
    /// The second axis b (from o to the third corner).
    pub second: Vec3,
    /// The widest cell side asked for.
    pub spacing: f32,
    /// The unit normal of the measuring surface at every point.
    pub normal: Vec3,
}

impl Grid {
    /// A grid from its three corners, its spacing and an optional normal (normalised; the
    /// default one of the module docs when `None`).
    #[must_use]
    pub fn new(name: &str, corners: [Vec3; 3], spacing: f32, normal: Option<Vec3>) -> Self {
        let [origin, a, b] = corners;
        let (first, second) = (a - origin, b - origin);
        let normal = normal.map_or_else(|| default_normal(first, second), Vec3::normalize);
        Self {
            name: name.to_string(),
            origin,
            first,
            second,
            spacing,
            normal,
        }
    }

    /// The cells along each axis, n = ⌈|axis| / spacing⌉, at least 1.
    #[must_use]
    pub fn cells(&self) -> (u32, u32) {
        (
            cells(self.first.length(), self.spacing),
            cells(self.second.length(), self.spacing),
        )
    }

    /// The points, cell centres, row by row along the first axis.
    #[must_use]
    pub fn points(&self) -> Vec<Vec3> {
        let (na, nb) = self.cells();
        (0..nb)
            .flat_map(|j| {
                (0..na).map(move |i| {
                    let u = (i as f32 + 0.5) / na as f32;
                    let v = (j as f32 + 0.5) / nb as f32;
                    self.origin + self.first * u + self.second * v
                })
            })
            .collect()
    }
}

/// Cells of at most `spacing` along a side of length `length`: at least one.
fn cells(length: f32, spacing: f32) -> u32 {
    let n = (f64::from(length) / f64::from(spacing) * (1.0 - 1e-6)).ceil();
    n.clamp(1.0, f64::from(u32::MAX)) as u32
}

/// +y for a horizontal grid (a × b along ±y), else a × b normalised.
fn default_normal(first: Vec3, second: Vec3) -> Vec3 {
    let n = first.cross(second).normalize_or_zero();
    if n.y.abs() > 1.0 - 1e-4 {
        Vec3::Y
    } else {
        n
    }
}

/// The key of a grid that [`problem`] finds at fault.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fault {
    /// `corners`.
    Corners,
    /// `spacing`.
    Spacing,
}

/// Why corners and a spacing make no grid (checked when the scene is loaded): the key at fault
/// and the message.
#[must_use]
pub fn problem(corners: [Vec3; 3], spacing: f32) -> Option<(Fault, String)> {
    let [o, a, b] = corners;
    let (first, second) = (a - o, b - o);
    if !(spacing > 0.0 && spacing.is_finite()) {
        return Some((
            Fault::Spacing,
            format!("spacing {spacing} must be positive"),
        ));
    }
    let size = first.length().max(second.length());
    if first.cross(second).length() <= 1e-6 * size * size || size <= 0.0 {
        let message = "the three corners lie on one line: no parallelogram";
        return Some((Fault::Corners, message.into()));
    }
    let count = |axis: Vec3| u64::from(cells(axis.length(), spacing));
    let points = count(first) * count(second);
    (points > MAX_POINTS).then(|| {
        let message =
            format!("spacing {spacing} makes {points} points, more than {MAX_POINTS}: widen it");
        (Fault::Spacing, message)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 × 1 desk at 0.8 m with a 0.5 spacing: 4 × 2 cells, centres a quarter in.
    #[test]
    fn points_are_the_cell_centres_and_the_normal_points_up() {
        let corners = [
            Vec3::new(0.0, 0.8, 0.0),
            Vec3::new(2.0, 0.8, 0.0),
            Vec3::new(0.0, 0.8, 1.0),
        ];
        let g = Grid::new("desk", corners, 0.5, None);
        assert_eq!(g.cells(), (4, 2));
        let p = g.points();
        assert_eq!(p.len(), 8);
        assert!((p[0] - Vec3::new(0.25, 0.8, 0.25)).length() < 1e-6);
        assert!((p[7] - Vec3::new(1.75, 0.8, 0.75)).length() < 1e-6);
        // a × b points down here; a horizontal grid still measures on the upper side.
        assert_eq!(g.normal, Vec3::Y);
    }

    /// A wall grid takes the right-hand normal; a given normal is normalised.
    #[test]
    fn a_vertical_grid_faces_along_its_right_hand_normal() {
        let corners = [Vec3::ZERO, Vec3::X, Vec3::Y];
        assert_eq!(Grid::new("wall", corners, 0.1, None).normal, Vec3::Z);
        let given = Grid::new("wall", corners, 0.1, Some(Vec3::new(0.0, 0.0, -2.0)));
        assert_eq!(given.normal, Vec3::NEG_Z);
        // 1 / 0.1 cells, not 11 from rounding.
        assert_eq!(given.cells(), (10, 10));
    }

    #[test]
    fn collinear_corners_a_bad_spacing_and_too_many_points_are_refused() {
        let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        let fault = |corners, spacing| problem(corners, spacing).unwrap();
        let (at, message) = fault(line, 0.1);
        assert!(at == Fault::Corners && message.contains("one line"));
        let square = [Vec3::ZERO, Vec3::X, Vec3::Z];
        let (at, message) = fault(square, 0.0);
        assert!(at == Fault::Spacing && message.contains("positive"));
        assert!(fault(square, f32::NAN).1.contains("positive"));
        let (at, message) = fault(square, 1e-4);
        assert!(at == Fault::Spacing && message.contains("more than"));
        assert_eq!(problem(square, 0.01), None);
    }
}
