//! Sources opened near each receiver.
//!
//! Substructuring (Cohen, Greenberg, Immel & Brock 1986) lets a receiver e gather a coarse
//! source's area-weighted mean radiosity with one factor, F_es B̄_s. That is exact when the
//! kernel or the radiosity is uniform over the source, and far from the receiver the kernel
//! nearly is. Next to the receiver neither holds: a floor element in the corner behind the
//! Cornell box's tall block gathers most of its light from the two walls' sources beside it,
//! whose means include their lit upper parts, while the kernel weighs the dark lower parts
//! most. With 991 sources for 6 082 elements that corner came out +120 % and the floor +6 %.
//!
//! So each receiver opens the sources in its near field, the way hierarchical radiosity refines
//! a link by the distance between its ends (Hanrahan, Salzman & Aupperle 1991): a quadtree node
//! whose centroid lies within [`REACH`] of its diameter from the receiver's centroid, in front
//! of the node, is replaced by its four children, recursively. That gives each receiver its own
//! cut through the quadtrees: the shared sources far away, finer pieces nearby. The row is
//! computed over that cut by the form-factor method as it is (so every method opens alike), and
//! split into the dense row over the shared sources (zero where a source was opened) and the
//! opened pieces, each an element range with its factor: the receiver gathers Σ F_ep B̄_p over
//! them, with B̄_p the mean of the piece's elements over their open area
//! ([`super::System`]).
//!
//! Pieces depend on the receiver alone, so the matrix stays the same at any thread count.

use std::ops::Range;

use glam::DVec3;

use crate::formfactor::{FormFactors, Geometry};
use crate::mesh::Mesh;

/// A node is opened for a receiver whose centroid is closer to the node's centroid than this
/// many of the node's diameters. Measured on `benches/suite` with a quarter of the elements as
/// sources (`--sources`; `python3 benches/suite/compare.py`): at 2
/// diameters the closed-mesh scene's ceiling came out −0.93 % and the furnished room's walls
/// −1.2 to −1.4 % (every element a source: +0.18 %, +0.61 %); at 4 every scene is where it was
/// with every element a source, within 0.3 points (docs/decisions/near-sources.md).
pub const REACH: f64 = 4.0;

/// An opened piece of a source: its elements (a range of [`Mesh::elements`]) and the form
/// factor from the receiver to it.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// The piece's elements.
    pub elements: Range<u32>,
    /// F from the receiver to the piece.
    pub factor: f32,
}

impl Piece {
    /// Quadtree node `node` as a piece with the factor `factor`.
    fn of(mesh: &Mesh, node: u32, factor: f32) -> Self {
        Self {
            elements: mesh.nodes[node as usize].elements.clone(),
            factor,
        }
    }
}

/// Reusable buffers for [`row`] and [`opened`].
#[derive(Debug, Default)]
pub(super) struct Scratch {
    /// The receiver's cut.
    cut: Vec<u32>,
    /// For each node of the cut, the source it belongs to and whether it is an opened piece
    /// of it (or the source itself).
    origin: Vec<(u32, bool)>,
    /// The row over the receiver's cut.
    values: Vec<f32>,
}

impl Scratch {
    /// Fills the cut of receiver `at`: the pieces of the sources it opens, and, if
    /// `unopened`, the other sources as they are. Whether any source is opened.
    fn cut(&mut self, g: &Geometry, at: &Receiver, unopened: bool) -> bool {
        self.cut.clear();
        self.origin.clear();
        let mut opened = false;
        for (s, &node) in g.sources.iter().enumerate() {
            let s = s as u32;
            if at.opens(g.mesh, node) {
                opened = true;
                open(g.mesh, at, node, s, self);
            } else if unopened {
                self.cut.push(node);
                self.origin.push((s, false));
            }
        }
        opened
    }

    /// Each node of the cut with its source, whether it is an opened piece, and its factor
    /// from [`Scratch::row_over_cut`].
    fn entries(&self) -> impl Iterator<Item = (u32, u32, bool, f32)> + '_ {
        self.cut
            .iter()
            .zip(&self.origin)
            .zip(&self.values)
            .map(|((&node, &(source, piece)), &f)| (node, source, piece, f))
    }

    /// The form-factor method's row from `element` over the cut, into `values`.
    fn row_over_cut(&mut self, g: &Geometry, ff: &dyn FormFactors, element: usize) {
        self.values.clear();
        self.values.resize(self.cut.len(), 0.0);
        ff.row(
            &Geometry::new(g.mesh, g.bvh, &self.cut),
            element,
            &mut self.values,
        );
    }
}

/// Row `element` of the matrix: F to every shared source into `out` (zero for a source it
/// opens), and the opened pieces appended to `pieces`.
pub(super) fn row(
    g: &Geometry,
    ff: &dyn FormFactors,
    element: usize,
    out: &mut [f32],
    pieces: &mut Vec<Piece>,
    scratch: &mut Scratch,
) {
    let at = Receiver::of(g.mesh, element);
    if !scratch.cut(g, &at, true) {
        ff.row(g, element, out);
        return;
    }
    scratch.row_over_cut(g, ff, element);
    out.fill(0.0);
    for (node, s, piece, f) in scratch.entries() {
        if !piece {
            out[s as usize] = f;
        } else if f != 0.0 {
            pieces.push(Piece::of(g.mesh, node, f));
        }
    }
}

/// The sources that receiver `element` opens, for shooting: every opened piece of each, with
/// its factor, appended to `out` as (source, piece) in source order. Progressive refinement
/// shoots a source's pieces with their own unshot radiosity to the receivers that open it
/// ([`super::progressive`]); the shared sources' factors are its column's. For a method that
/// sees nothing but what it is given, the sources not opened go into the cut too, as
/// occluders ([`FormFactors::occluded_only_by_sources`]): with the opened pieces alone, a
/// hemicube saw the light unoccluded from every floor element of the bare OBJ room, the torus
/// and the block included, and its floor came out 39 % too bright after one shot.
pub(super) fn opened(
    g: &Geometry,
    ff: &dyn FormFactors,
    element: usize,
    out: &mut Vec<(u32, Piece)>,
    scratch: &mut Scratch,
) {
    let at = Receiver::of(g.mesh, element);
    if !scratch.cut(g, &at, ff.occluded_only_by_sources()) {
        return;
    }
    scratch.row_over_cut(g, ff, element);
    for (node, s, piece, f) in scratch.entries() {
        if piece && f != 0.0 {
            out.push((s, Piece::of(g.mesh, node, f)));
        }
    }
}

/// The receiving element, as far as opening goes.
struct Receiver {
    centroid: DVec3,
    patch: u32,
}

impl Receiver {
    /// Element `element` as a receiver.
    fn of(mesh: &Mesh, element: usize) -> Self {
        let receiver = mesh.element(element);
        Self {
            centroid: receiver.centroid().as_dvec3(),
            patch: receiver.patch,
        }
    }

    /// Whether `node` is opened for this receiver: it has children, lies on another patch,
    /// faces the receiver, and is within [`REACH`] of its diameter.
    fn opens(&self, mesh: &Mesh, node: u32) -> bool {
        let n = &mesh.nodes[node as usize];
        if n.children.is_none() || n.patch == self.patch {
            return false;
        }
        let centroid = n.centroid().as_dvec3();
        let normal = mesh.patches[n.patch as usize].normal.as_dvec3();
        let offset = self.centroid - centroid;
        normal.dot(offset) > 0.0 && offset.length() < REACH * f64::from(n.diameter())
    }
}

/// Pushes the receiver's cut below the opened `node` of source `source`: each child, or its
/// own cut if opened.
fn open(mesh: &Mesh, at: &Receiver, node: u32, source: u32, scratch: &mut Scratch) {
    let first = mesh.nodes[node as usize]
        .children
        .expect("opened nodes have children");
    for child in first..first + 4 {
        if at.opens(mesh, child) {
            open(mesh, at, child, source, scratch);
        } else {
            scratch.cut.push(child);
            scratch.origin.push((source, true));
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::accel::Bvh;
    use crate::formfactor::hemicube::Hemicube;
    use crate::mesh::Subdivision;
    use crate::Scene;

    /// A light over a floor and a small plate just under the light: the floor elements open
    /// the light (large and near) but not the plate (small for its distance), which shades
    /// them.
    const SHADOW: &str = r#"
[materials.grey]
reflectance = 0.5
[materials.light]
reflectance = 0.0
emission = 10.0
[[objects]]
name = "floor"
material = "grey"
shape = "polygon"
vertices = [[-1, 0, 1], [1, 0, 1], [1, 0, -1], [-1, 0, -1]]
[[objects]]
name = "plate"
material = "grey"
shape = "polygon"
vertices = [[-0.1, 0.8, 0.1], [0.1, 0.8, 0.1], [0.1, 0.8, -0.1], [-0.1, 0.8, -0.1]]
[[objects]]
name = "light"
material = "light"
shape = "polygon"
vertices = [[-0.5, 1, -0.5], [0.5, 1, -0.5], [0.5, 1, 0.5], [-0.5, 1, 0.5]]
"#;

    #[test]
    fn a_hemicube_opens_the_same_pieces_with_the_same_factors_for_shooting_as_for_gathering() {
        // Progressive refinement's pieces (`opened`) are the gathering row's (`row`) to the
        // bit: a hemicube sees only what it draws, so the sources that are not opened are
        // drawn too, or the plate would not shade the floor. (Ray casting traces the whole
        // scene either way; its jitter follows the index of the source in the cut, so its
        // pieces agree only to its noise.)
        let scene = Scene::from_toml_str(SHADOW, Path::new("shadow.toml")).unwrap();
        let mesh = Mesh::build(&scene, Subdivision::Elements(300));
        let bvh = Bvh::build(&mesh.triangles);
        let sources = mesh.sources(24, 24);
        let g = Geometry::new(&mesh, &bvh, &sources);
        let ff = Hemicube::new(64, 2, 0);
        let (mut compared, mut scratch) = (0, Scratch::default());
        for e in 0..mesh.element_count() {
            let (mut gathered, mut shot) = (Vec::new(), Vec::new());
            let mut out = vec![0.0; sources.len()];
            row(&g, &ff, e, &mut out, &mut gathered, &mut scratch);
            opened(&g, &ff, e, &mut shot, &mut scratch);
            let shot: Vec<Piece> = shot.into_iter().map(|(_, p)| p).collect();
            assert_eq!(shot, gathered, "element {e}");
            compared += shot.len();
        }
        assert!(compared > 100, "only {compared} pieces opened");
    }
}
