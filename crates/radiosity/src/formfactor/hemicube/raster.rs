//! The hemicube's five item buffers: cell layout, exact delta form factors, and a z-buffer
//! rasterizer of convex polygons with frustum clipping.
//!
//! A hemicube of half-side 1 sits at the eye with its local axes (a, b, c), c the surface
//! normal. Face 0 is the top (view axis +c, x = a, y = b, both in [−1, 1]); faces 1–4 are the
//! half sides with view axes +a, +b, −a, −b, x across the side in [−1, 1] and y = c in [0, 1]
//! (the horizon is y = 0). A cell is 2/res on a side: the top has res × res cells, each side
//! res × res/2.

use glam::{DVec3, Vec3};

use crate::formfactor::analytic::point_to_polygon;

/// The item of a cell that sees nothing (or an occluder that carries no item).
pub const NOTHING: u32 = u32::MAX;

/// Number of faces of a hemicube.
pub const FACES: usize = 5;

/// The cell layout of a hemicube of side `resolution` (even, at least 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Cells along a full edge.
    pub resolution: u32,
}

impl Layout {
    /// Rows of face `face`: `resolution` for the top, half of it for the sides.
    #[must_use]
    pub fn rows(self, face: usize) -> u32 {
        if face == 0 {
            self.resolution
        } else {
            self.resolution / 2
        }
    }

    /// Index of the first cell of face `face`.
    #[must_use]
    pub fn start(self, face: usize) -> usize {
        let r = self.resolution as usize;
        if face == 0 {
            0
        } else {
            r * r + (face - 1) * r * (r / 2)
        }
    }

    /// Total cells: 3 res².
    #[must_use]
    pub fn cells(self) -> usize {
        self.start(FACES)
    }

    /// The cell in column `i` (along the face's x) and row `j` (along its y, from the horizon
    /// upward on the sides) of face `face`.
    #[must_use]
    pub fn index(self, face: usize, i: u32, j: u32) -> usize {
        self.start(face) + j as usize * self.resolution as usize + i as usize
    }

    /// Lowest y of face `face` in its view plane at distance 1: −1 for the top, 0 for sides.
    fn y0(face: usize) -> f64 {
        if face == 0 {
            -1.0
        } else {
            0.0
        }
    }

    /// The exact form factor from the eye to every cell (Lambert's contour integral over the
    /// cell's square), in cell order. They sum to 1 up to rounding.
    #[must_use]
    pub fn deltas(self) -> Vec<f64> {
        let h = 2.0 / f64::from(self.resolution);
        let mut out = Vec::with_capacity(self.cells());
        for face in 0..FACES {
            // In view coordinates the normal is +z on the top and +y on the sides.
            let normal = if face == 0 { DVec3::Z } else { DVec3::Y };
            for j in 0..self.rows(face) {
                for i in 0..self.resolution {
                    let x0 = -1.0 + h * f64::from(i);
                    let y0 = Self::y0(face) + h * f64::from(j);
                    let (x1, y1) = (x0 + h, y0 + h);
                    // Clockwise seen from the eye, i.e. counter-clockwise seen from the front
                    // that faces the eye.
                    let cell = [
                        DVec3::new(x0, y0, 1.0),
                        DVec3::new(x0, y1, 1.0),
                        DVec3::new(x1, y1, 1.0),
                        DVec3::new(x1, y0, 1.0),
                    ];
                    out.push(point_to_polygon(DVec3::ZERO, normal, &cell));
                }
            }
        }
        out
    }
}

/// A convex polygon (3 or 4 corners) in the hemicube's local frame, with its plane, ready to
/// rasterize.
#[derive(Clone, Copy, Debug)]
pub struct Polygon {
    /// Corners relative to the eye, in local (a, b, c) coordinates.
    pub corners: [Vec3; 4],
    /// 3 or 4.
    pub sides: u8,
    /// Plane: `normal · p = offset` for points p of the polygon (local coordinates).
    pub normal: Vec3,
    /// See `normal`.
    pub offset: f32,
    /// Item written into the cells it wins ([`NOTHING`] for a pure occluder).
    pub item: u32,
    /// Slot of its unoccluded coverage (near items only), or [`NOTHING`].
    pub slot: u32,
}

/// Local (a, b, c) coordinates to face `face`'s view coordinates (x, y, depth).
fn view(face: usize, l: Vec3) -> Vec3 {
    match face {
        0 => l,
        1 => Vec3::new(l.y, l.z, l.x),
        2 => Vec3::new(-l.x, l.z, l.y),
        3 => Vec3::new(-l.y, l.z, -l.x),
        _ => Vec3::new(l.x, l.z, -l.y),
    }
}

/// One face's cells: the item and the inverse depth (1/z, larger is nearer) of each.
pub struct FaceBuffer<'a> {
    /// Items of the face's cells.
    pub items: &'a mut [u32],
    /// Inverse depths of the face's cells.
    pub depth: &'a mut [f32],
}

/// Sutherland–Hodgman: keeps the part of `input` where `distance` is not negative.
fn clip(input: &[Vec3], output: &mut Vec<Vec3>, distance: impl Fn(Vec3) -> f32) {
    output.clear();
    let Some(&last) = input.last() else { return };
    let (mut a, mut da) = (last, distance(last));
    for &b in input {
        let db = distance(b);
        if (da >= 0.0) != (db >= 0.0) {
            let t = da / (da - db);
            output.push(a + (b - a) * t);
        }
        if db >= 0.0 {
            output.push(b);
        }
        a = b;
        da = db;
    }
}

/// Rasterizes `polygons` into face `face` of a hemicube of side `resolution`, keeping in each
/// cell the nearest polygon (the first one on a tie). `near_z` is the near plane. Adds to
/// `coverage[slot]` the delta of every cell that a near polygon covers, hidden or not.
pub fn rasterize(
    face: usize,
    resolution: u32,
    near_z: f32,
    polygons: &[Polygon],
    buffer: FaceBuffer,
    deltas: &[f64],
    coverage: &mut [f64],
) {
    let layout = Layout { resolution };
    let rows = layout.rows(face);
    let res = resolution as f32;
    let half = 0.5 * res;
    let y0 = Layout::y0(face) as f32;
    buffer.items.fill(NOTHING);
    buffer.depth.fill(0.0);
    let (mut a, mut b) = (Vec::with_capacity(12), Vec::with_capacity(12));
    let mut projected: Vec<(f32, f32)> = Vec::with_capacity(12);
    for polygon in polygons {
        // Corners in view coordinates; reject polygons wholly outside one frustum plane.
        let mut corners = [Vec3::ZERO; 4];
        let n = usize::from(polygon.sides);
        for (o, &c) in corners.iter_mut().zip(&polygon.corners[..n]) {
            *o = view(face, c);
        }
        let corners = &corners[..n];
        let planes: [&dyn Fn(Vec3) -> f32; 5] = [
            &|p: Vec3| p.z - near_z,
            &|p: Vec3| p.z - p.x,
            &|p: Vec3| p.z + p.x,
            &|p: Vec3| p.z - p.y,
            &|p: Vec3| if face == 0 { p.z + p.y } else { p.y },
        ];
        let mut outside = false;
        let mut straddles = [false; 5];
        for (k, plane) in planes.iter().enumerate() {
            let inside = corners.iter().filter(|&&p| plane(p) >= 0.0).count();
            outside |= inside == 0;
            straddles[k] = inside < n;
        }
        if outside {
            continue;
        }
        // Clip where needed (the near plane first, so nothing divides by zero).
        a.clear();
        a.extend_from_slice(corners);
        for (k, plane) in planes.iter().enumerate() {
            if straddles[k] {
                clip(&a, &mut b, plane);
                std::mem::swap(&mut a, &mut b);
            }
        }
        if a.len() < 3 {
            continue;
        }
        // Project to cell units: column u = (x/z + 1)·res/2, row v = (y/z − y0)·res/2.
        projected.clear();
        projected.extend(
            a.iter()
                .map(|p| ((p.x / p.z + 1.0) * half, (p.y / p.z - y0) * half)),
        );
        // Inverse depth is affine in the view-plane position (x', y') = (x/z, y/z):
        // 1/z = (m · (x', y', 1)) / offset for the plane m · p = offset.
        let m = view(face, polygon.normal);
        if polygon.offset == 0.0 {
            continue;
        }
        let (wx, wy, w0) = (
            m.x / polygon.offset,
            m.y / polygon.offset,
            m.z / polygon.offset,
        );
        let (vmin, vmax) = projected.iter().fold((f32::MAX, f32::MIN), |(lo, hi), p| {
            (lo.min(p.1), hi.max(p.1))
        });
        let first_row = ((vmin - 0.5).ceil().max(0.0)) as u32;
        let last_row = ((vmax - 0.5).floor()).min(rows as f32 - 1.0);
        if last_row < 0.0 {
            continue;
        }
        for j in first_row..=last_row as u32 {
            // Span of the row's centre line, inclusive (no cracks between neighbours).
            let vc = j as f32 + 0.5;
            let (mut ul, mut ur) = (f32::MAX, f32::MIN);
            let mut p = projected[projected.len() - 1];
            for &q in &projected {
                if (p.1 <= vc && vc <= q.1) || (q.1 <= vc && vc <= p.1) {
                    let u = if q.1 == p.1 {
                        ul = ul.min(p.0.min(q.0));
                        p.0.max(q.0)
                    } else {
                        p.0 + (vc - p.1) * (q.0 - p.0) / (q.1 - p.1)
                    };
                    ul = ul.min(u);
                    ur = ur.max(u);
                }
                p = q;
            }
            if ul > ur {
                continue;
            }
            let first = (ul - 0.5).ceil().max(0.0) as u32;
            let last = (ur - 0.5).floor().min(res - 1.0);
            if last < first as f32 {
                continue;
            }
            let yv = vc / half + y0;
            let row = j as usize * resolution as usize;
            for i in first..=last as u32 {
                let xv = (i as f32 + 0.5) / half - 1.0;
                let w = wx * xv + wy * yv + w0;
                let cell = row + i as usize;
                if polygon.slot != NOTHING {
                    coverage[polygon.slot as usize] += deltas[cell];
                }
                if w > buffer.depth[cell] {
                    buffer.depth[cell] = w;
                    buffer.items[cell] = polygon.item;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_counts_three_res_squared_cells() {
        let l = Layout { resolution: 8 };
        assert_eq!(l.cells(), 3 * 64);
        assert_eq!(l.index(4, 7, 3), l.cells() - 1);
        assert_eq!(l.deltas().len(), l.cells());
    }

    #[test]
    fn a_wall_in_front_of_face_one_fills_it() {
        // The plane a = 0.5 facing −a covers the whole +a side face.
        let wall = Polygon {
            corners: [
                Vec3::new(0.5, -5.0, -5.0),
                Vec3::new(0.5, -5.0, 5.0),
                Vec3::new(0.5, 5.0, 5.0),
                Vec3::new(0.5, 5.0, -5.0),
            ],
            sides: 4,
            normal: Vec3::X,
            offset: 0.5,
            item: 7,
            slot: 0,
        };
        let l = Layout { resolution: 8 };
        let deltas = l.deltas();
        let mut items = vec![0; 32];
        let mut depth = vec![0.0; 32];
        let mut coverage = [0.0];
        let cells = &deltas[l.start(1)..l.start(2)];
        rasterize(
            1,
            8,
            1e-6,
            &[wall],
            FaceBuffer {
                items: &mut items,
                depth: &mut depth,
            },
            cells,
            &mut coverage,
        );
        assert!(items.iter().all(|&i| i == 7));
        assert!(depth.iter().all(|&w| (w - 2.0).abs() < 1e-5), "1/z = 2");
        let side: f64 = cells.iter().sum();
        assert!((coverage[0] - side).abs() < 1e-12);
    }
}
