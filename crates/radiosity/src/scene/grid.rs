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
//!
//! A grid may instead lie **on an object** (`on = "desk"`): on the faces of that object whose
//! normal is within [`FACING_DEGREES`] of the grid's `normal` (by default up, so a box's top),
//! [`Grid::on`]. The parallelogram is then the rectangle around those faces seen along the
//! normal, its first axis along the longest edge of the largest face (a desk's long side) and
//! its second a = first × normal (so that the plan, first axis to the right and second down,
//! is the faces as seen from the side they face); a cell centre that falls on a face is
//! projected along the normal onto it (onto the uppermost where faces overlap) and lifted by
//! [`LIFT_METRES`] along the face's normal, which is the direction that point measures in;
//! cells beside the faces (an L-shaped top) have no point.

use glam::Vec3;

/// Most points one grid may hold.
pub const MAX_POINTS: u64 = 1_000_000;

/// The largest angle, in degrees, between a face's normal and an `on` grid's normal for the
/// face to carry points: a top that a tessellation or a transform tilts by a hair still
/// counts, a bevel does not.
pub const FACING_DEGREES: f32 = 1.0;

/// How far above its face a point of an `on` grid lies, in metres (a lux meter's cell on a
/// desk): off the surface, so that the meter's rays never start inside it.
pub const LIFT_METRES: f64 = 1e-3;

/// A face of an object an `on` grid lies on: a planar polygon, counter-clockwise seen from
/// its front, and its unit normal.
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    /// The corners.
    pub vertices: Vec<Vec3>,
    /// The unit normal of its front.
    pub normal: Vec3,
}

impl Face {
    /// The polygon's unit (Newell) normal and area; `None` if it has no area.
    #[must_use]
    pub fn of(vertices: &[Vec3]) -> Option<(Self, f32)> {
        let n = vertices.len();
        let twice = (0..n).fold(Vec3::ZERO, |sum, k| {
            sum + vertices[k].cross(vertices[(k + 1) % n])
        });
        let normal = twice.try_normalize()?;
        let face = Self {
            vertices: vertices.to_vec(),
            normal,
        };
        Some((face, twice.length() / 2.0))
    }
}

/// One point of a grid: where it is, the direction it measures in and its cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridPoint {
    /// The point, scene coordinates.
    pub position: Vec3,
    /// The unit normal of the small surface it measures on.
    pub normal: Vec3,
    /// Its cell (i along the first axis, j along the second).
    pub cell: (u32, u32),
}

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
    /// The unit normal of the measuring surface at every point (of an `on` grid: the normal
    /// its faces were chosen by; each point measures along its own face's).
    pub normal: Vec3,
    /// The faces an `on` grid lies on; empty for a grid of `corners`, where every cell centre
    /// is a point.
    pub faces: Vec<Face>,
    /// The height of an `on` grid's points above their faces, scene units.
    pub lift: f32,
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
            faces: Vec::new(),
            lift: 0.0,
        }
    }

    /// A grid on `faces` (module docs: the rectangle around them seen along the unit
    /// `normal`, the first axis along the longest edge of the largest face), its points
    /// `lift` above them. `None` without a face that has an area.
    #[must_use]
    pub fn on(name: &str, faces: Vec<Face>, spacing: f32, normal: Vec3, lift: f32) -> Option<Self> {
        let area = |f: &Face| Face::of(&f.vertices).map_or(0.0, |(_, a)| a);
        // The largest face, and its longest edge (the first of equals: `max_by` keeps the
        // last, so the lists are walked backwards).
        let largest = faces
            .iter()
            .filter(|f| area(f) > 0.0)
            .rev()
            .max_by(|a, b| area(a).total_cmp(&area(b)))?;
        let v = &largest.vertices;
        let edge = (0..v.len())
            .rev()
            .map(|k| v[(k + 1) % v.len()] - v[k])
            .max_by(|a, b| a.length().total_cmp(&b.length()))?;
        // The first axis along it, flattened onto the plane normal to the grid's normal.
        let along = (edge - normal * edge.dot(normal)).try_normalize()?;
        let across = along.cross(normal);
        let o = v[0];
        let (mut lo, mut hi) = (
            glam::Vec2::splat(f32::INFINITY),
            glam::Vec2::splat(f32::NEG_INFINITY),
        );
        for p in faces.iter().flat_map(|f| &f.vertices) {
            let uv = glam::Vec2::new((*p - o).dot(along), (*p - o).dot(across));
            lo = lo.min(uv);
            hi = hi.max(uv);
        }
        Some(Self {
            name: name.to_string(),
            origin: o + along * lo.x + across * lo.y,
            first: along * (hi.x - lo.x),
            second: across * (hi.y - lo.y),
            spacing,
            normal,
            faces,
            lift,
        })
    }

    /// The cells along each axis, n = ⌈|axis| / spacing⌉, at least 1.
    #[must_use]
    pub fn cells(&self) -> (u32, u32) {
        (
            cells(self.first.length(), self.spacing),
            cells(self.second.length(), self.spacing),
        )
    }

    /// The points' positions, row by row along the first axis (see [`Grid::layout`]).
    #[must_use]
    pub fn points(&self) -> Vec<Vec3> {
        self.layout().into_iter().map(|p| p.position).collect()
    }

    /// The points, row by row along the first axis: every cell centre of a grid of
    /// `corners`, facing its normal; the cell centres that fall on a face of an `on` grid,
    /// moved onto it and lifted, facing along the face's normal (module docs).
    #[must_use]
    pub fn layout(&self) -> Vec<GridPoint> {
        let (na, nb) = self.cells();
        let on = OnFaces::new(self);
        (0..nb)
            .flat_map(|j| (0..na).map(move |i| (i, j)))
            .filter_map(|(i, j)| {
                let u = (i as f32 + 0.5) / na as f32;
                let v = (j as f32 + 0.5) / nb as f32;
                let centre = self.origin + self.first * u + self.second * v;
                let Some(on) = &on else {
                    return Some(GridPoint {
                        position: centre,
                        normal: self.normal,
                        cell: (i, j),
                    });
                };
                let (position, normal) = on.place(centre, (u, v))?;
                Some(GridPoint {
                    position,
                    normal,
                    cell: (i, j),
                })
            })
            .collect()
    }
}

/// The faces of an `on` grid in the grid's frame, for placing its points.
struct OnFaces<'a> {
    grid: &'a Grid,
    /// Each face's corners at (u, v) ∈ the unit square of the grid's parallelogram, and
    /// their bounds (to pass over the faces far from a point at the cost of four
    /// comparisons).
    outlines: Vec<(Vec<glam::Vec2>, glam::Vec2, glam::Vec2)>,
    /// How far outside its outline a point still counts as on a face, in (u, v): a cell
    /// centre on the diagonal between a quad's two triangles belongs to both.
    slack: f32,
}

impl<'a> OnFaces<'a> {
    /// `None` for a grid of `corners`.
    fn new(grid: &'a Grid) -> Option<Self> {
        if grid.faces.is_empty() {
            return None;
        }
        let (a, b) = (grid.first, grid.second);
        let uv = |p: Vec3| {
            let d = p - grid.origin;
            glam::Vec2::new(
                d.dot(a) / a.length_squared().max(f32::MIN_POSITIVE),
                d.dot(b) / b.length_squared().max(f32::MIN_POSITIVE),
            )
        };
        let slack = 1e-5;
        let outlines = grid
            .faces
            .iter()
            .map(|f| {
                let outline: Vec<glam::Vec2> = f.vertices.iter().map(|&p| uv(p)).collect();
                let lo = outline.iter().fold(glam::Vec2::INFINITY, |m, &p| m.min(p));
                let hi = outline
                    .iter()
                    .fold(glam::Vec2::NEG_INFINITY, |m, &p| m.max(p));
                (outline, lo - slack, hi + slack)
            })
            .collect();
        Some(Self {
            grid,
            outlines,
            slack,
        })
    }

    /// The point of the uppermost face under `centre` (at (u, v) of the parallelogram),
    /// lifted off it, and the face's normal; `None` where no face is.
    fn place(&self, centre: Vec3, (u, v): (f32, f32)) -> Option<(Vec3, Vec3)> {
        let n = self.grid.normal;
        let at = glam::Vec2::new(u, v);
        self.grid
            .faces
            .iter()
            .zip(&self.outlines)
            .filter(|(f, (outline, lo, hi))| {
                at.cmpge(*lo).all()
                    && at.cmple(*hi).all()
                    && f.normal.dot(n) > 0.0
                    && within(outline, at, self.slack)
            })
            .map(|(f, _)| {
                // Along the normal from the centre to the face's plane.
                let t = f.normal.dot(f.vertices[0] - centre) / f.normal.dot(n);
                (t, f.normal)
            })
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(t, normal)| (centre + n * t + normal * self.grid.lift, normal))
    }
}

/// Whether `p` lies inside the polygon `outline` (even-odd rule) or within `slack` of its
/// border.
fn within(outline: &[glam::Vec2], p: glam::Vec2, slack: f32) -> bool {
    let n = outline.len();
    let mut inside = false;
    for k in 0..n {
        let (a, b) = (outline[k], outline[(k + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
        || (0..n).any(|k| {
            let (a, b) = (outline[k], outline[(k + 1) % n]);
            let ab = b - a;
            let t = ((p - a).dot(ab) / ab.length_squared().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
            (a + ab * t - p).length() <= slack
        })
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
    if let Some(message) = spacing_problem(spacing) {
        return Some((Fault::Spacing, message));
    }
    let size = first.length().max(second.length());
    if first.cross(second).length() <= 1e-6 * size * size || size <= 0.0 {
        let message = "the three corners lie on one line: no parallelogram";
        return Some((Fault::Corners, message.into()));
    }
    count_problem(first, second, spacing).map(|message| (Fault::Spacing, message))
}

/// Why `spacing` is no spacing: not a positive number.
#[must_use]
pub fn spacing_problem(spacing: f32) -> Option<String> {
    (!(spacing > 0.0 && spacing.is_finite())).then(|| format!("spacing {spacing} must be positive"))
}

/// Why axes `first` and `second` cut at `spacing` make too many points.
#[must_use]
pub fn count_problem(first: Vec3, second: Vec3, spacing: f32) -> Option<String> {
    let count = |axis: Vec3| u64::from(cells(axis.length(), spacing));
    let points = count(first) * count(second);
    (points > MAX_POINTS).then(|| {
        format!("spacing {spacing} makes {points} points, more than {MAX_POINTS}: widen it")
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

    /// The six faces of the box [0, 2] × [0, 0.75] × [0, 1], outward.
    fn desk() -> Vec<Face> {
        let (x, y, z) = (2.0, 0.75, 1.0);
        let quads = [
            [[0.0, y, 0.0], [0.0, y, z], [x, y, z], [x, y, 0.0]],
            [[0.0, 0.0, 0.0], [x, 0.0, 0.0], [x, 0.0, z], [0.0, 0.0, z]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, z], [0.0, y, z], [0.0, y, 0.0]],
            [[x, 0.0, 0.0], [x, y, 0.0], [x, y, z], [x, 0.0, z]],
            [[0.0, 0.0, 0.0], [0.0, y, 0.0], [x, y, 0.0], [x, 0.0, 0.0]],
            [[0.0, 0.0, z], [x, 0.0, z], [x, y, z], [0.0, y, z]],
        ];
        quads
            .iter()
            .map(|q| Face::of(&q.map(Vec3::from)).unwrap().0)
            .collect()
    }

    /// On a desk's top (its one face facing up), the points are the centres of the cells of
    /// the top, 1 mm above it, the first axis along its long side.
    #[test]
    fn a_grid_on_a_box_top_covers_the_top() {
        let top: Vec<Face> = desk().into_iter().filter(|f| f.normal.y > 0.99).collect();
        assert_eq!(top.len(), 1);
        let g = Grid::on("desk", top, 0.25, Vec3::Y, 1e-3).unwrap();
        assert_eq!(g.cells(), (8, 4));
        // The top's first longest edge runs along +x from its first corner.
        assert_eq!(g.origin, Vec3::new(0.0, 0.75, 0.0));
        assert_eq!((g.first, g.second), (Vec3::X * 2.0, Vec3::Z));
        let points = g.layout();
        assert_eq!(points.len(), 32);
        for p in &points {
            assert!((p.position.y - 0.751).abs() < 1e-6, "{p:?}");
            assert_eq!(p.normal, Vec3::Y);
            let (fx, fz) = (p.position.x / 0.25 - 0.5, p.position.z / 0.25 - 0.5);
            assert!((fx - fx.round()).abs() < 1e-4 && (fz - fz.round()).abs() < 1e-4);
        }
    }

    /// Two triangles of an L: the cells of the missing corner have no point, those on the
    /// triangles' shared diagonal have one; an upper face hides a lower one under it.
    #[test]
    fn a_grid_on_several_faces_keeps_the_cells_on_them() {
        let tri = |v: [[f32; 3]; 3]| Face::of(&v.map(Vec3::from)).unwrap().0;
        // A unit square as two triangles (counter-clockwise seen from above), plus a square
        // beside it along x: an L missing [1, 2] × [1, 2] of its 2 × 2 bounds.
        let faces = vec![
            tri([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 1.0]]),
            tri([[0.0, 0.0, 0.0], [1.0, 0.0, 1.0], [1.0, 0.0, 0.0]]),
            Face::of(&[
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 1.0),
                Vec3::new(2.0, 0.0, 1.0),
                Vec3::new(2.0, 0.0, 0.0),
            ])
            .unwrap()
            .0,
            Face::of(&[
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(0.0, 0.0, 2.0),
                Vec3::new(1.0, 0.0, 2.0),
                Vec3::new(1.0, 0.0, 1.0),
            ])
            .unwrap()
            .0,
            // A shelf above the first square's half.
            Face::of(&[
                Vec3::new(0.0, 0.5, 0.0),
                Vec3::new(0.0, 0.5, 1.0),
                Vec3::new(0.5, 0.5, 1.0),
                Vec3::new(0.5, 0.5, 0.0),
            ])
            .unwrap()
            .0,
        ];
        let g = Grid::on("l", faces, 0.25, Vec3::Y, 0.0).unwrap();
        assert_eq!(g.cells(), (8, 8));
        let points = g.layout();
        assert_eq!(points.len(), 64 - 16, "the missing quarter has no points");
        let high = points.iter().filter(|p| p.position.y > 0.25).count();
        assert_eq!(high, 8, "the shelf's 2 × 4 cells");
        assert!(points
            .iter()
            .all(|p| !(p.position.x > 1.0 && p.position.z > 1.0)));
        assert!(Grid::on("none", Vec::new(), 0.25, Vec3::Y, 0.0).is_none());
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
