//! A z-buffer rasterizer with Gouraud shading of the lit mesh.
//!
//! Hidden surfaces are removed per sample by a depth buffer (Catmull 1974), and the vertex
//! radiosity B is interpolated across each triangle (Gouraud 1971). The image holds radiance,
//! L = B/π, so it is directly comparable with a path tracer's.
//!
//! **Perspective-correct interpolation.** Screen-space barycentrics λᵢ are not the world-space
//! ones; but 1/w and L/w (w = view depth) are affine in screen space, so
//!
//! L(p) = Σᵢ λᵢ Lᵢ/wᵢ / Σᵢ λᵢ /wᵢ,
//!
//! and the depth test compares 1/w = Σᵢ λᵢ/wᵢ (larger is nearer). λᵢ are the integer edge
//! functions of the snapped triangle divided by its doubled area, which they sum to exactly.
//!
//! **Clipping.** Triangles are clipped in homogeneous clip space (Sutherland & Hodgman 1974;
//! Blinn & Newell 1978) against a near plane w ≥ w_near and a guard band |x|, |y| ≤ G·w wide
//! enough that nothing inside the image is lost, so triangles crossing the camera plane are
//! cut, never dropped nor projected through the eye. The intersection on an edge is always
//! computed from its inside end, so neighbours sharing the edge get bit-identical vertices.
//!
//! **Coverage.** Vertices are snapped to a fixed-point grid (1024 steps between samples) and
//! coverage is decided by exact `i64` edge functions with the top-left fill rule: a sample on
//! an edge belongs to the triangle for which the edge is a top or left edge, so a mesh covers
//! each sample exactly once — no cracks, no double blending (Pineda 1988).
//!
//! **Sides.** A triangle whose front (counter-clockwise side) faces the eye shows its radiance;
//! seen from behind it is skipped if a reversed twin carries its back side
//! ([`LitMesh::has_back_twin`]), and otherwise drawn black: a one-sided surface reflects
//! nothing from its back but still hides what lies behind it.
//!
//! **Antialiasing.** Each pixel takes an s × s stratified grid of samples at the centres of its
//! sub-squares, averaged with a box filter.
//!
//! **Parallelism.** Triangles are binned by the bands of pixel rows their bounds overlap; bands
//! are rasterized in parallel, each drawing its triangles in mesh order. Every sample therefore
//! sees the same sequence of depth tests whatever the number of threads, and the image is
//! bit-identical for any thread count.

use glam::DVec3;
use rayon::prelude::*;

use super::camera::Projection;
use super::image::Image;
use super::watch::Watch;
use crate::mesh::LitMesh;
use crate::progress::Work;
use crate::scene::Camera;
use crate::Rgb;

/// Largest side of the sample grid per pixel (64 samples).
const MAX_GRID_SIDE: u32 = 8;
/// Largest image width or height; larger requests are clamped to it.
pub const MAX_DIMENSION: u32 = 1 << 16;
/// Fixed-point steps between neighbouring samples.
const SAMPLE_STEP: i64 = 1024;
/// How far (in pixels) the guard band reaches: keeps the fixed-point coordinates below
/// 2¹⁶ · 8 · 1024 = 2²⁹ (with at most 8 samples per pixel side), so edge functions (sums of
/// two products of differences) stay below 2⁶¹. [`MAX_DIMENSION`] is within it.
const GUARD_PIXELS: f64 = (1 << 16) as f64;
/// The near plane, as a fraction of the farthest vertex depth.
const NEAR_FRACTION: f64 = 1e-7;
/// Pixel rows per parallel band.
const BAND_ROWS: u32 = 8;
/// Source triangles per parallel setup chunk.
const SETUP_CHUNK: usize = 4096;

/// Options of the rasterizer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RasterSettings {
    /// Image width in pixels (clamped to [`MAX_DIMENSION`]).
    pub width: u32,
    /// Image height in pixels (clamped to [`MAX_DIMENSION`]).
    pub height: u32,
    /// Samples per pixel, taken as an s × s stratified grid: s is the largest integer with
    /// s² ≤ `samples_per_pixel`, between 1 and 8 (so 1, 4, 9, 16, ... 64).
    pub samples_per_pixel: u32,
}

impl Default for RasterSettings {
    fn default() -> Self {
        Self {
            width: 512,
            height: 512,
            samples_per_pixel: 4,
        }
    }
}

impl RasterSettings {
    /// The side s of the s × s sample grid in each pixel.
    #[must_use]
    pub fn grid_side(&self) -> u32 {
        let mut s = 1;
        while s < MAX_GRID_SIDE && (s + 1) * (s + 1) <= self.samples_per_pixel {
            s += 1;
        }
        s
    }
}

/// Renders the radiance image of `lit` seen by `camera`.
///
/// Never panics: triangles with out-of-range vertex indices or non-finite positions are
/// skipped, missing radiosity counts as zero, a zero size gives an empty image.
#[must_use]
pub fn render(lit: &LitMesh, camera: &Camera, settings: &RasterSettings) -> Image {
    render_watched(lit, camera, settings, &Watch::SILENT).unwrap_or_else(|| unreachable!())
}

/// [`render`], reporting the bands of [`BAND_ROWS`] rows done to `watch` and giving up
/// (`None`) when its stop flag is set (read before each band: a 16384² image at 64 samples per
/// pixel takes minutes).
#[must_use]
pub fn render_watched(
    lit: &LitMesh,
    camera: &Camera,
    settings: &RasterSettings,
    watch: &Watch,
) -> Option<Image> {
    let setup = Setup::new(lit, camera, settings);
    let mut image = Image::new_unless(setup.width, setup.height, || watch.stopped())?;
    if image.pixels.is_empty() {
        return Some(image);
    }
    let bins = setup.bins();
    let band_len = setup.width as usize * BAND_ROWS as usize;
    watch
        .progress
        .start("render", Work::of(bins.len() as u64, "bands"));
    image
        .pixels
        .par_chunks_mut(band_len)
        .zip(bins.par_iter())
        .enumerate()
        .for_each(|(band, (pixels, bin))| {
            if !watch.stopped() {
                setup.shade_band(band as u32, bin, pixels);
                watch.progress.advance(1);
            }
        });
    if !watch.stopped() {
        let pixels = u64::from(setup.width) * u64::from(setup.height);
        watch.progress.tally(pixels, "pixels");
    }
    watch.progress.end(watch.stopped());
    (!watch.stopped()).then_some(image)
}

/// A triangle ready for scan conversion: snapped, counter-clockwise in the edge-function sense
/// (positive doubled area), with its attributes divided by w.
#[derive(Clone, Copy, Debug)]
struct RasterTri {
    /// Fixed-point vertex positions (`SAMPLE_STEP` per sample spacing), y downward.
    v: [[i64; 2]; 3],
    /// 1/w per vertex.
    inv_w: [f64; 3],
    /// Radiance / w per vertex.
    l_over_w: [DVec3; 3],
    /// Inclusive range of sample rows the triangle may cover.
    rows: (i64, i64),
}

/// A clip-space vertex (x, y, w) with its radiance.
#[derive(Clone, Copy, Debug)]
struct ClipVertex {
    c: DVec3,
    l: Rgb,
}

/// A clipping plane: inside where `k · (x, y, w) + offset ≥ 0`.
#[derive(Clone, Copy, Debug)]
struct Plane {
    k: DVec3,
    offset: f64,
}

impl Plane {
    fn distance(&self, c: DVec3) -> f64 {
        self.k.dot(c) + self.offset
    }
}

/// Everything the bands share: the prepared triangles and the sample grid.
struct Setup {
    tris: Vec<RasterTri>,
    width: u32,
    height: u32,
    /// Sample grid side per pixel.
    side: u32,
}

impl Setup {
    fn new(lit: &LitMesh, camera: &Camera, settings: &RasterSettings) -> Self {
        let width = settings.width.min(MAX_DIMENSION);
        let height = settings.height.min(MAX_DIMENSION);
        let side = settings.grid_side();
        let proj = Projection::new(camera, width, height);
        let clip: Vec<DVec3> = lit.positions.par_iter().map(|&p| proj.to_clip(p)).collect();
        let far = clip.iter().map(|c| c.z).fold(0.0, f64::max);
        let near = (far * NEAR_FRACTION).max(f64::MIN_POSITIVE);
        let guard = (2.0 * GUARD_PIXELS / f64::from(width.max(height).max(1)) - 1.0).max(1.0);
        let planes = [
            Plane {
                k: DVec3::Z,
                offset: -near,
            },
            Plane {
                k: DVec3::new(-1.0, 0.0, guard),
                offset: 0.0,
            },
            Plane {
                k: DVec3::new(1.0, 0.0, guard),
                offset: 0.0,
            },
            Plane {
                k: DVec3::new(0.0, -1.0, guard),
                offset: 0.0,
            },
            Plane {
                k: DVec3::new(0.0, 1.0, guard),
                offset: 0.0,
            },
        ];
        let ctx = TriangleContext {
            lit,
            proj: &proj,
            clip: &clip,
            planes: &planes,
            unit: SAMPLE_STEP as f64 * f64::from(side),
            rows: i64::from(height) * i64::from(side),
        };
        let indices: Vec<usize> = (0..lit.triangles.len()).collect();
        let tris = indices
            .par_chunks(SETUP_CHUNK)
            .map(|chunk| {
                let mut out = Vec::with_capacity(chunk.len());
                let mut poly = Vec::with_capacity(8);
                let mut scratch = Vec::with_capacity(8);
                for &t in chunk {
                    ctx.prepare(t, &mut poly, &mut scratch, &mut out);
                }
                out
            })
            .collect::<Vec<_>>()
            .concat();
        Self {
            tris,
            width,
            height,
            side,
        }
    }

    /// Sample rows per band.
    fn band_sample_rows(&self) -> i64 {
        i64::from(BAND_ROWS) * i64::from(self.side)
    }

    /// Per band of `BAND_ROWS` pixel rows, the triangles overlapping it, in mesh order.
    fn bins(&self) -> Vec<Vec<u32>> {
        let bands = self.height.div_ceil(BAND_ROWS) as usize;
        let mut bins = vec![Vec::new(); bands];
        let per_band = self.band_sample_rows();
        for (i, tri) in self.tris.iter().enumerate() {
            let first = (tri.rows.0 / per_band) as usize;
            let last = ((tri.rows.1 / per_band) as usize).min(bands - 1);
            for bin in &mut bins[first..=last] {
                bin.push(i as u32);
            }
        }
        bins
    }

    /// Rasterizes one band of pixel rows into `pixels` (its rows of the image).
    fn shade_band(&self, band: u32, bin: &[u32], pixels: &mut [Rgb]) {
        let side = i64::from(self.side);
        let cols = i64::from(self.width) * side;
        let row0 = i64::from(band) * self.band_sample_rows();
        let pixel_rows = pixels.len() as i64 / i64::from(self.width);
        let rows = (row0, row0 + pixel_rows * side - 1);
        let samples = (pixel_rows * side * cols) as usize;
        let mut depth = vec![0.0f64; samples];
        let mut colour = vec![Rgb::ZERO; samples];
        for &t in bin {
            let tri = &self.tris[t as usize];
            scan(tri, rows, cols, |row, col, e| {
                let e = [e[0] as f64, e[1] as f64, e[2] as f64];
                let q = e[0] * tri.inv_w[0] + e[1] * tri.inv_w[1] + e[2] * tri.inv_w[2];
                let area = e[0] + e[1] + e[2];
                let inv_w = q / area;
                let i = ((row - row0) * cols + col) as usize;
                if inv_w > depth[i] {
                    depth[i] = inv_w;
                    colour[i] =
                        (tri.l_over_w[0] * e[0] + tri.l_over_w[1] * e[1] + tri.l_over_w[2] * e[2])
                            / q;
                }
            });
        }
        // Box-filter the s × s samples of each pixel.
        let width = self.width as usize;
        let side = self.side as usize;
        let cols = cols as usize;
        let norm = 1.0 / (side * side) as f64;
        for (p, pixel) in pixels.iter_mut().enumerate() {
            let (x, y) = (p % width, p / width);
            let mut sum = Rgb::ZERO;
            for sy in 0..side {
                let start = (y * side + sy) * cols + x * side;
                sum += colour[start..start + side].iter().sum::<Rgb>();
            }
            *pixel = sum * norm;
        }
    }
}

/// Read-only inputs of triangle setup.
struct TriangleContext<'a> {
    lit: &'a LitMesh,
    proj: &'a Projection,
    clip: &'a [DVec3],
    planes: &'a [Plane; 5],
    /// Fixed-point units per pixel.
    unit: f64,
    /// Sample rows in the image.
    rows: i64,
}

impl TriangleContext<'_> {
    /// Culls, clips, projects and snaps triangle `t`, appending its pieces to `out`.
    fn prepare(
        &self,
        t: usize,
        poly: &mut Vec<ClipVertex>,
        scratch: &mut Vec<ClipVertex>,
        out: &mut Vec<RasterTri>,
    ) {
        let lit = self.lit;
        let idx = lit.triangles[t].map(|i| i as usize);
        if idx
            .iter()
            .any(|&i| i >= lit.positions.len() || i >= self.clip.len())
        {
            return;
        }
        // Which side faces the eye (in world space, before any clipping).
        let p = idx.map(|i| lit.positions[i].as_dvec3());
        let facing = (p[1] - p[0]).cross(p[2] - p[0]).dot(self.proj.eye() - p[0]);
        let (front, back) = (facing > 0.0, facing < 0.0);
        if !(front || back) {
            return; // edge-on or not finite
        }
        if back && lit.has_back_twin.get(t).copied().unwrap_or(false) {
            return;
        }
        poly.clear();
        poly.extend(idx.iter().map(|&i| ClipVertex {
            c: self.clip[i],
            l: if front {
                lit.radiosity.get(i).copied().unwrap_or(Rgb::ZERO) / std::f64::consts::PI
            } else {
                Rgb::ZERO
            },
        }));
        for plane in self.planes {
            if poly.iter().all(|v| plane.distance(v.c) >= 0.0) {
                continue;
            }
            clip_polygon(poly, scratch, plane);
            std::mem::swap(poly, scratch);
            if poly.len() < 3 {
                return;
            }
        }
        // Project and snap; fan-triangulate the clipped convex polygon.
        let snapped: Vec<([i64; 2], f64, Rgb)> = poly
            .iter()
            .map(|v| {
                let px = self.proj.clip_to_pixel(v.c) * self.unit;
                let inv_w = 1.0 / v.c.z;
                (
                    [px.x.round() as i64, px.y.round() as i64],
                    inv_w,
                    v.l * inv_w,
                )
            })
            .collect();
        for k in 1..snapped.len() - 1 {
            let mut tri = [snapped[0], snapped[k], snapped[k + 1]];
            let area = edge(tri[0].0, tri[1].0, tri[2].0);
            if area == 0 {
                continue;
            }
            if area < 0 {
                tri.swap(1, 2);
            }
            let v = tri.map(|v| v.0);
            let min_y = v.iter().map(|v| v[1]).min().unwrap_or(0);
            let max_y = v.iter().map(|v| v[1]).max().unwrap_or(0);
            let rows = (
                ceil_div(min_y - SAMPLE_STEP / 2, SAMPLE_STEP).max(0),
                floor_div(max_y - SAMPLE_STEP / 2, SAMPLE_STEP).min(self.rows - 1),
            );
            if rows.0 > rows.1 {
                continue;
            }
            out.push(RasterTri {
                v,
                inv_w: tri.map(|v| v.1),
                l_over_w: tri.map(|v| v.2),
                rows,
            });
        }
    }
}

/// One Sutherland–Hodgman pass: the part of polygon `input` inside `plane`, into `output`.
fn clip_polygon(input: &[ClipVertex], output: &mut Vec<ClipVertex>, plane: &Plane) {
    output.clear();
    for (i, &a) in input.iter().enumerate() {
        let b = input[(i + 1) % input.len()];
        let (da, db) = (plane.distance(a.c), plane.distance(b.c));
        if da >= 0.0 {
            output.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            // Interpolate from the inside end, so both triangles sharing this edge agree.
            let (inside, outside, di, dout) = if da >= 0.0 {
                (a, b, da, db)
            } else {
                (b, a, db, da)
            };
            let t = di / (di - dout);
            output.push(ClipVertex {
                c: inside.c + (outside.c - inside.c) * t,
                l: inside.l + (outside.l - inside.l) * t,
            });
        }
    }
}

/// The doubled signed area of (a, b, p): positive when p is on the inner side of a → b.
fn edge(a: [i64; 2], b: [i64; 2], p: [i64; 2]) -> i64 {
    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
}

/// Whether edge a → b is a top or left edge of a positively oriented triangle (y downward):
/// samples exactly on it belong to this triangle.
fn is_top_left(a: [i64; 2], b: [i64; 2]) -> bool {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    dy < 0 || (dy == 0 && dx > 0)
}

fn floor_div(a: i64, b: i64) -> i64 {
    a.div_euclid(b)
}

fn ceil_div(a: i64, b: i64) -> i64 {
    -(-a).div_euclid(b)
}

/// Calls `visit(row, col, e)` for every sample of rows `rows` (inclusive) and columns
/// `0..cols` covered by `tri`, in row-major order; `e` are its edge functions, e[i] opposite
/// vertex i, summing to the doubled area.
fn scan(tri: &RasterTri, rows: (i64, i64), cols: i64, mut visit: impl FnMut(i64, i64, [i64; 3])) {
    let v = tri.v;
    let row0 = tri.rows.0.max(rows.0);
    let row1 = tri.rows.1.min(rows.1);
    let min_x = v.iter().map(|v| v[0]).min().unwrap_or(0);
    let max_x = v.iter().map(|v| v[0]).max().unwrap_or(0);
    let col0 = ceil_div(min_x - SAMPLE_STEP / 2, SAMPLE_STEP).max(0);
    let col1 = floor_div(max_x - SAMPLE_STEP / 2, SAMPLE_STEP).min(cols - 1);
    if row0 > row1 || col0 > col1 {
        return;
    }
    // Edge i runs between the two vertices other than i.
    let edges = [(v[1], v[2]), (v[2], v[0]), (v[0], v[1])];
    let start = [
        col0 * SAMPLE_STEP + SAMPLE_STEP / 2,
        row0 * SAMPLE_STEP + SAMPLE_STEP / 2,
    ];
    let mut e_row = edges.map(|(a, b)| edge(a, b, start));
    let step_x = edges.map(|(a, b)| -(b[1] - a[1]) * SAMPLE_STEP);
    let step_y = edges.map(|(a, b)| (b[0] - a[0]) * SAMPLE_STEP);
    // A sample on a non-top-left edge (e = 0) is outside: test e + bias ≥ 0 with bias −1.
    let bias = edges.map(|(a, b)| if is_top_left(a, b) { 0 } else { -1 });
    for row in row0..=row1 {
        let mut e = e_row;
        for col in col0..=col1 {
            if e[0] + bias[0] >= 0 && e[1] + bias[1] >= 0 && e[2] + bias[2] >= 0 {
                visit(row, col, e);
            }
            for (e, step) in e.iter_mut().zip(step_x) {
                *e += step;
            }
        }
        for (e, step) in e_row.iter_mut().zip(step_y) {
            *e += step;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// How many triangles cover each sample (row-major over the sample grid), no depth test.
    fn coverage(lit: &LitMesh, camera: &Camera, settings: &RasterSettings) -> Vec<u32> {
        let setup = Setup::new(lit, camera, settings);
        let side = i64::from(setup.side);
        let (rows, cols) = (
            i64::from(setup.height) * side,
            i64::from(setup.width) * side,
        );
        let mut count = vec![0; (rows * cols) as usize];
        for tri in &setup.tris {
            scan(tri, (0, rows - 1), cols, |r, c, e| {
                assert!(e.iter().all(|&e| e >= 0), "covered sample outside: {e:?}");
                count[(r * cols + c) as usize] += 1;
            });
        }
        count
    }

    fn axis_camera() -> Camera {
        Camera {
            name: "axis".into(),
            eye: Vec3::ZERO,
            target: Vec3::NEG_Z,
            up: Vec3::Y,
            fov_y: 90.0,
        }
    }

    /// A grid mesh at z = −1 over vertex columns/rows at the given pixel coordinates of a
    /// 32×32 image (world x = px/16 − 1), quads split along alternating diagonals.
    fn grid(pixels: &[f32], jitter: f32) -> LitMesh {
        let n = pixels.len();
        let mut lit = LitMesh::default();
        for (j, &py) in pixels.iter().enumerate() {
            for (i, &px) in pixels.iter().enumerate() {
                let interior = (1..n - 1).contains(&i) && (1..n - 1).contains(&j);
                let wobble = if interior {
                    jitter * (((i * 7 + j * 13) % 5) as f32 - 2.0)
                } else {
                    0.0
                };
                lit.positions.push(Vec3::new(
                    (px + wobble) / 16.0 - 1.0,
                    1.0 - (py - wobble * 0.5) / 16.0,
                    -1.0,
                ));
                lit.radiosity.push(Rgb::ONE);
            }
        }
        let at = |i: usize, j: usize| (j * n + i) as u32;
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                // Image y grows downward, world y upward: (i, j+1) is below (i, j).
                let (a, b, c, d) = (at(i, j + 1), at(i + 1, j + 1), at(i + 1, j), at(i, j));
                let tris = if (i + j) % 2 == 0 {
                    [[a, b, c], [a, c, d]]
                } else {
                    [[a, b, d], [b, c, d]]
                };
                for t in tris {
                    lit.triangles.push(t);
                    lit.has_back_twin.push(false);
                    lit.triangle_patch.push(0);
                    lit.triangle_object.push(0);
                }
            }
        }
        lit
    }

    #[test]
    fn every_sample_is_covered_exactly_once() {
        // Vertex lines through sample centres (x.25, x.75 with 2×2 samples) put edges, and
        // vertices, exactly on samples; the outer lines lie outside the view.
        let on_samples = [-10.0, 5.25, 11.75, 16.0, 20.25, 26.75, 42.0];
        for (jitter, spp) in [(0.0, 4), (0.0, 1), (0.0, 9), (0.37, 4), (0.25, 16)] {
            let settings = RasterSettings {
                width: 32,
                height: 32,
                samples_per_pixel: spp,
            };
            let count = coverage(&grid(&on_samples, jitter), &axis_camera(), &settings);
            let bad: Vec<usize> = (0..count.len()).filter(|&i| count[i] != 1).collect();
            assert!(
                bad.is_empty(),
                "jitter {jitter}, spp {spp}: samples {bad:?}"
            );
        }
    }

    #[test]
    fn a_watched_render_reports_every_band_and_stops_when_told() {
        use crate::progress::{Progress, Silent};
        use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
        struct Count(AtomicU64, AtomicU64);
        impl Progress for Count {
            fn start(&self, stage: &str, work: Work) {
                let bands = ("render", Work::of(4, "bands"));
                assert_eq!((stage, work), bands, "32 rows in bands of 8");
            }
            fn advance(&self, n: u64) {
                self.0.fetch_add(n, Ordering::Relaxed);
            }
            fn tally(&self, count: u64, what: &'static str) {
                assert_eq!(what, "pixels");
                self.1.fetch_add(count, Ordering::Relaxed);
            }
            fn finish(&self) {}
        }
        let lit = grid(&[-10.0, 16.0, 42.0], 0.0);
        let settings = RasterSettings {
            width: 32,
            height: 32,
            samples_per_pixel: 4,
        };
        let count = Count(AtomicU64::new(0), AtomicU64::new(0));
        let watch = Watch {
            progress: &count,
            stop: None,
        };
        let watched = render_watched(&lit, &axis_camera(), &settings, &watch).expect("image");
        assert_eq!(count.0.load(Ordering::Relaxed), 4);
        assert_eq!(count.1.load(Ordering::Relaxed), 32 * 32);
        assert_eq!(watched, render(&lit, &axis_camera(), &settings));
        let stop = AtomicBool::new(true);
        let watch = Watch {
            progress: &Silent,
            stop: Some(&stop),
        };
        assert!(render_watched(&lit, &axis_camera(), &settings, &watch).is_none());
    }

    #[test]
    fn top_left_rule_is_antisymmetric() {
        let dirs = [
            [1, 0],
            [-1, 0],
            [0, 1],
            [0, -1],
            [3, 5],
            [-3, 5],
            [3, -5],
            [-3, -5],
        ];
        for d in dirs {
            let (o, b) = ([0, 0], d);
            assert_ne!(is_top_left(o, b), is_top_left(b, o), "{d:?}");
        }
    }

    #[test]
    fn grid_side_is_the_largest_fitting_square() {
        let side = |spp| {
            RasterSettings {
                samples_per_pixel: spp,
                ..RasterSettings::default()
            }
            .grid_side()
        };
        assert_eq!(
            [0, 1, 3, 4, 8, 9, 16, 63, 64, 1000].map(side),
            [1, 1, 1, 2, 2, 3, 4, 7, 8, 8]
        );
    }

    #[test]
    fn clipping_keeps_the_inside_and_agrees_on_shared_edges() {
        let v = |x: f64, y: f64, w: f64| ClipVertex {
            c: DVec3::new(x, y, w),
            l: Rgb::splat(w),
        };
        let near = Plane {
            k: DVec3::Z,
            offset: -1.0,
        };
        // A triangle with one vertex behind the plane becomes a quad; the new vertices lie
        // on the plane with their attribute interpolated linearly.
        let tri = [v(0.0, 0.0, -1.0), v(4.0, 0.0, 3.0), v(0.0, 4.0, 3.0)];
        let mut out = Vec::new();
        clip_polygon(&tri, &mut out, &near);
        assert_eq!(out.len(), 4);
        for p in &out {
            assert!(p.c.z >= 1.0 - 1e-12 && (p.l.x - p.c.z).abs() < 1e-12);
        }
        // The neighbour across edge (0 → 1), listed in the opposite direction, gets the
        // bit-identical cut vertex.
        let neighbour = [tri[1], tri[0], v(2.0, -4.0, 3.0)];
        let mut other = Vec::new();
        clip_polygon(&neighbour, &mut other, &near);
        let cut = |poly: &[ClipVertex]| {
            poly.iter()
                .map(|p| p.c)
                .find(|c| c.y == 0.0 && c.z == 1.0)
                .expect("cut on the shared edge")
        };
        assert_eq!(cut(&out), cut(&other));
    }
}
