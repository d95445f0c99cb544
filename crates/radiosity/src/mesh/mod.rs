//! Meshing: patches, element quadtrees, and the display mesh.
//!
//! "Every surface in the scene is divided in patches … light intensity is constant along each
//! patch; chosen subdivision is therefore very important" (the lecture). Here a *patch* is one
//! side of an input polygon ([`Patch`]) and its *elements* are the leaves of a quadtree of
//! [`Face`]s below it: quads split into four quads, triangles into four triangles (Cohen,
//! Greenberg, Immel, Brock 1986 call these patches and elements). Uniform subdivision to a
//! target element area is done here; the hierarchical solver refines the same trees later.
//!
//! Nodes are stored in one arena ([`Mesh::nodes`]); a node's four children are consecutive, and
//! the leaves are numbered depth-first, so the elements below any node form a contiguous range.
//! That lets a coarse node act as a *source* whose radiosity is the area-weighted mean of its
//! leaves ([`Mesh::sources`]).

mod budget;
mod contact;
mod discontinuity;
pub mod display;
mod enclosure;
mod face;
mod imprint;
pub mod lit_mesh;
mod node;
mod patch;
mod receiver_grid;
mod root_faces;
mod shadow;
mod sources;
pub(crate) mod triangulate;

use std::ops::Range;

use glam::Vec3;

pub use contact::CONTACT_LEVELS;
pub use face::Face;
pub use lit_mesh::LitMesh;
pub use node::Node;
pub use patch::Patch;
pub use receiver_grid::NEAR_REFINEMENT;
pub use shadow::SHADOW_LEVELS;

use crate::accel::{Aabb, Bvh};
use crate::progress::{Progress, Silent, Work};
use crate::Scene;
pub use budget::DARK_EMITTER_COARSENING;

/// Elements per progress report in the meshing passes ([`Batched`](crate::progress::Batched)): a pass of 10⁵–10⁶
/// elements reports a few thousand times.
const ELEMENT_BATCH: u64 = 256;

/// How finely to subdivide patches into elements.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Subdivision {
    /// About this many elements in total (area-proportional).
    Elements(usize),
    /// Subdivide until no element is larger than this area (scene units²).
    MaxArea(f64),
}

impl Default for Subdivision {
    fn default() -> Self {
        Self::Elements(DEFAULT_ELEMENTS)
    }
}

/// Elements when the user asks for nothing else: enough for smooth Cornell-box shading.
pub const DEFAULT_ELEMENTS: usize = 4096;

/// The deepest quadtree level (4^12 ≈ 16.7 M leaves per root face).
pub const MAX_LEVEL: u8 = 12;

/// Patches and their element quadtrees, plus the triangles that the visibility structure needs.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Reflecting sides of the scene's polygons.
    pub patches: Vec<Patch>,
    /// All quadtree nodes; roots of patch `p` are `roots[p]`.
    pub nodes: Vec<Node>,
    /// Root node indices of each patch.
    pub roots: Vec<Range<u32>>,
    /// Leaf node indices in depth-first order: element `e` is `nodes[elements[e]]`.
    pub elements: Vec<u32>,
    /// The scene's polygons as triangles (each polygon once, whatever its sides): what rays hit.
    pub triangles: Vec<[Vec3; 3]>,
    /// Scene polygon of each triangle.
    pub triangle_polygon: Vec<u32>,
    /// The scene's point luminaires, whose light the elements take by their first shot
    /// ([`crate::solve::first_shot`]) and the pictures take exactly.
    pub luminaires: Vec<crate::scene::Luminaire>,
}

impl Mesh {
    /// How many root faces and elements [`Mesh::build`] would make, without making them (to
    /// refuse absurd requests, or choose a solver, before allocating).
    #[must_use]
    pub fn plan(scene: &Scene, subdivision: Subdivision, discontinuity: bool) -> (usize, f64) {
        let patches = patch::patches(scene, discontinuity);
        let targets = budget::patch_targets(&patches, subdivision);
        let roots = patches.iter().map(|(_, roots)| roots.len()).sum();
        let elements = patches
            .iter()
            .zip(targets)
            .map(|((_, roots), target)| {
                let areas: Vec<f64> = roots.iter().map(Face::area).collect();
                budget::element_count(&areas, target)
            })
            .sum();
        (roots, elements)
    }

    /// The power the scene emits per channel, in scene units² × W·m⁻²: Σ A·E over the
    /// emitting patches plus the point luminaires' flux.
    #[must_use]
    pub fn emitted_power(&self) -> crate::Rgb {
        let patches: crate::Rgb = self.patches.iter().map(|p| p.area * p.emission).sum();
        patches
            + self
                .luminaires
                .iter()
                .map(crate::scene::Luminaire::scene_power)
                .sum::<crate::Rgb>()
    }

    /// Splits every polygon of `scene` into patches and subdivides them uniformly.
    #[must_use]
    pub fn build(scene: &Scene, subdivision: Subdivision) -> Self {
        Self::build_unless(scene, subdivision, false, &|| false, &Silent)
            .unwrap_or_else(|| unreachable!())
    }

    /// [`Mesh::build`], with the outlines of sharp shadows cut into the root faces when
    /// `discontinuity` is set (discontinuity meshing, [`discontinuity`]), abandoned (`None`)
    /// once `stop` returns true: the contact, shadow and near-field passes, which take
    /// seconds to minutes on large scenes, ask it before each element. Each pass is reported
    /// to `progress` as a [`Progress::phase`] of the current stage (`subdivision` in patches,
    /// then `contacts`, `shadows` and `near field` in elements tested).
    #[must_use]
    pub fn build_unless(
        scene: &Scene,
        subdivision: Subdivision,
        discontinuity: bool,
        stop: &(dyn Fn() -> bool + Sync),
        progress: &dyn Progress,
    ) -> Option<Self> {
        let patches = patch::patches(scene, discontinuity);
        let targets = budget::patch_targets(&patches, subdivision);
        let mut mesh = Mesh {
            luminaires: scene.luminaires.clone(),
            ..Mesh::default()
        };
        progress.phase("subdivision", Work::of(patches.len() as u64, "patches"));
        for (index, ((patch, roots), target)) in patches.into_iter().zip(targets).enumerate() {
            let first = mesh.nodes.len() as u32;
            mesh.nodes.extend(
                roots
                    .iter()
                    .map(|&face| Node::new(face, index as u32, 0, false)),
            );
            mesh.roots.push(first..mesh.nodes.len() as u32);
            for r in first..mesh.nodes.len() as u32 {
                let level = budget::level_for(mesh.nodes[r as usize].area(), target);
                mesh.grow(r, level);
            }
            mesh.patches.push(patch);
            progress.advance(1);
        }
        // What rays hit: the front patches' root faces, so each polygon once and exactly the
        // planar pieces the elements lie on.
        for (p, patch) in mesh.patches.iter().enumerate() {
            if patch.back {
                continue;
            }
            for r in mesh.roots[p].clone() {
                let c = mesh.nodes[r as usize].face.corners();
                mesh.triangles.push([c[0], c[1], c[2]]);
                mesh.triangle_polygon.push(patch.polygon);
                if let [a, _, c, d] = *c {
                    mesh.triangles.push([a, c, d]);
                    mesh.triangle_polygon.push(patch.polygon);
                }
            }
        }
        let bvh = Bvh::build(&mesh.triangles);
        progress.phase("contacts", Work::open_ended("elements"));
        mesh.refine_contacts(stop, progress);
        progress.phase("shadows", Work::open_ended("elements"));
        mesh.refine_shadows(&bvh, stop, progress);
        if stop() {
            return None;
        }
        let elements = Work::of(mesh.elements.len() as u64, "elements");
        progress.phase("near field", elements);
        mesh.mark_near_field(&bvh, stop, progress);
        if stop() {
            return None;
        }
        debug_assert_eq!(mesh.validate(), Ok(()));
        Some(mesh)
    }

    /// Subdivides node `n` uniformly down to `levels` more levels, numbering leaves depth-first.
    fn grow(&mut self, n: u32, levels: u8) {
        let start = self.elements.len() as u32;
        if levels == 0 {
            self.elements.push(n);
        } else {
            let node = &self.nodes[n as usize];
            let (patch, level, near) = (node.patch, node.level + 1, node.near);
            let first = self.nodes.len() as u32;
            for face in node.face.split() {
                self.nodes.push(Node::new(face, patch, level, near));
            }
            self.nodes[n as usize].children = Some(first);
            for c in first..first + 4 {
                self.grow(c, levels - 1);
            }
        }
        self.nodes[n as usize].elements = start..self.elements.len() as u32;
    }

    /// Splits each of the given leaf nodes into four children and renumbers the elements
    /// depth-first (adaptive subdivision; O(nodes) per call, so refine in batches).
    ///
    /// # Panics
    /// If a node is not a leaf or its level is already [`MAX_LEVEL`].
    pub fn refine(&mut self, leaves: &[u32]) {
        for &n in leaves {
            let node = &self.nodes[n as usize];
            assert!(node.children.is_none() && node.level < MAX_LEVEL);
            let (patch, level, faces) = (node.patch, node.level + 1, node.face.split());
            let near = node.near;
            let first = self.nodes.len() as u32;
            self.nodes.extend(
                faces
                    .into_iter()
                    .map(|face| Node::new(face, patch, level, near)),
            );
            self.nodes[n as usize].children = Some(first);
        }
        self.elements.clear();
        for r in self.roots.clone().into_iter().flatten() {
            self.number(r);
        }
        debug_assert_eq!(self.validate(), Ok(()));
    }

    /// Calls `visit` with every triangle (an index into [`Mesh::triangles`]) of another polygon
    /// than node `n`'s whose bounds come within `reach` of the node's bounds: the candidates of
    /// the near-field test.
    fn other_triangles_near(&self, bvh: &Bvh, n: u32, reach: f32, mut visit: impl FnMut(usize)) {
        let node = &self.nodes[n as usize];
        let own = self.patches[node.patch as usize].polygon;
        let mut query = Aabb::from_points(node.face.corners());
        query.min -= Vec3::splat(reach);
        query.max += Vec3::splat(reach);
        bvh.overlapping(&query, |t| {
            if self.triangle_polygon[t] != own {
                visit(t);
            }
        });
    }

    /// Numbers the leaves below `n` depth-first, appending them to `elements`.
    fn number(&mut self, n: u32) {
        let start = self.elements.len() as u32;
        match self.nodes[n as usize].children {
            None => self.elements.push(n),
            Some(c) => (c..c + 4).for_each(|k| self.number(k)),
        }
        self.nodes[n as usize].elements = start..self.elements.len() as u32;
    }

    /// Number of elements (quadtree leaves).
    #[must_use]
    pub fn element_count(&self) -> usize {
        self.elements.len()
    }

    /// The node of element `e`.
    #[must_use]
    pub fn element(&self, e: usize) -> &Node {
        &self.nodes[self.elements[e] as usize]
    }

    /// The patch of element `e`.
    #[must_use]
    pub fn element_patch(&self, e: usize) -> &Patch {
        &self.patches[self.element(e).patch as usize]
    }

    /// The shallowest leaf level of each patch: the level its uniform subdivision reached
    /// (contact and shadow refinement only go deeper).
    #[must_use]
    pub fn uniform_levels(&self) -> Vec<u8> {
        let mut levels = vec![MAX_LEVEL; self.patches.len()];
        for &n in &self.elements {
            let node = &self.nodes[n as usize];
            let level = &mut levels[node.patch as usize];
            *level = (*level).min(node.level);
        }
        levels
    }

    /// Total area of all patches (both sides of two-sided polygons count).
    #[must_use]
    pub fn total_area(&self) -> f64 {
        self.patches.iter().map(|p| p.area).sum()
    }

    /// Checks the quadtree invariants: children partition their parent's area and element range,
    /// levels increase by one, leaves are numbered depth-first, every patch's roots cover its
    /// area, and every node's cached measures are its face's ([`Node::consistent`]). Areas are
    /// taken from the faces themselves.
    ///
    /// # Errors
    /// A description of the first broken invariant.
    pub fn validate(&self) -> Result<(), String> {
        if self.roots.len() != self.patches.len() {
            return Err("one root range per patch".into());
        }
        for (e, &n) in self.elements.iter().enumerate() {
            let node = self.nodes.get(n as usize).ok_or("element out of range")?;
            if node.children.is_some() || node.elements != (e as u32..e as u32 + 1) {
                return Err(format!("element {e} is not a leaf numbered {e}"));
            }
        }
        if let Some(i) = self.nodes.iter().position(|n| !n.consistent()) {
            return Err(format!("node {i}'s measures are not its face's"));
        }
        for (i, node) in self.nodes.iter().enumerate() {
            let Some(c) = node.children else { continue };
            let children = &self.nodes[c as usize..c as usize + 4];
            let area: f64 = children.iter().map(|k| k.face.area()).sum();
            let (parent, tolerance) = (node.face.area(), split_area_tolerance(&node.face));
            if (area - parent).abs() > tolerance {
                return Err(format!(
                    "children of node {i} do not cover it (areas {area:e} vs {parent:e})"
                ));
            }
            if children
                .iter()
                .any(|k| k.level != node.level + 1 || k.patch != node.patch)
            {
                return Err(format!("children of node {i} have wrong level or patch"));
            }
            if children[0].elements.start != node.elements.start
                || children[3].elements.end != node.elements.end
                || children
                    .windows(2)
                    .any(|w| w[0].elements.end != w[1].elements.start)
            {
                return Err(format!("element ranges of node {i} are not contiguous"));
            }
        }
        for (p, roots) in self.roots.iter().enumerate() {
            let area: f64 = roots
                .clone()
                .map(|r| self.nodes[r as usize].face.area())
                .sum();
            if (area - self.patches[p].area).abs() > 1e-4 * self.patches[p].area {
                return Err(format!("roots of patch {p} do not cover it"));
            }
        }
        Ok(())
    }
}

/// How far the summed areas of `face`'s four children may stray from its own area.
///
/// Exactly, the children partition the face. In f32 each midpoint `(a + b)·0.5` is off by at
/// most ε/2·M per coordinate (ε = `f32::EPSILON`, M the largest corner coordinate), a quad's
/// centre by at most 9/8·ε·M, and moving a corner by δ changes a child's area by at most
/// δ·D/2 (D the face's diameter). Over the 9 moved corners of a triangle's children, or the 8
/// midpoints and 4 centres of a quad's, that is below 8·ε·M·D; twice that is allowed, plus
/// 1e-4 relative for quads that are planar only to the scene's tolerance. For a sliver far from
/// the origin the rounding term may exceed the area itself: its children are then as good as
/// f32 can place them, and this check cannot tell them from a wrong split.
fn split_area_tolerance(face: &Face) -> f64 {
    let magnitude = face
        .corners()
        .iter()
        .map(|c| c.abs().max_element())
        .fold(0.0f32, f32::max);
    let rounding =
        16.0 * f64::from(f32::EPSILON) * f64::from(magnitude) * f64::from(face.diameter());
    1e-4 * face.area() + rounding
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Material, Object, Polygon};
    use crate::Rgb;

    fn square_scene(two_sided: bool) -> Scene {
        Scene {
            materials: vec![Material {
                two_sided,
                ..Material::default()
            }],
            objects: vec![Object { name: "sq".into() }],
            polygons: vec![Polygon {
                vertices: vec![Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Y, Vec3::Y],
                material: 0,
                object: 0,
                uv: None,
            }],
            ..Scene::default()
        }
    }

    #[test]
    fn element_count_and_max_area_are_honoured() {
        let mesh = Mesh::build(&square_scene(false), Subdivision::Elements(256));
        assert_eq!(mesh.element_count(), 256);
        mesh.validate().unwrap();
        let mesh = Mesh::build(&square_scene(false), Subdivision::MaxArea(0.01));
        assert_eq!(mesh.element_count(), 256, "1/4^4 = 0.0039 ≤ 0.01 < 1/4^3");
        assert_eq!(mesh.triangles.len(), 2);
    }

    #[test]
    fn many_small_roots_do_not_starve_a_large_face() {
        // One unit square and 2 000 tiny triangles far away: asking for 1 024 elements must
        // still cut the square to elements of at most four fair shares of the area.
        let mut scene = square_scene(false);
        for k in 0..2000 {
            let x = 10.0 + k as f32 * 0.01;
            scene.polygons.push(Polygon {
                vertices: vec![
                    Vec3::new(x, 0.0, 0.0),
                    Vec3::new(x + 0.001, 0.0, 0.0),
                    Vec3::new(x, 0.001, 0.0),
                ],
                material: 0,
                object: 0,
                uv: None,
            });
        }
        let mesh = Mesh::build(&scene, Subdivision::Elements(1024));
        let square = mesh.roots[0].clone();
        let elements: u32 = square
            .map(|r| mesh.nodes[r as usize].elements.len() as u32)
            .sum();
        assert_eq!(elements, 256, "area 1 in elements of at most 4/1024");
        assert_eq!(mesh.element_count(), 256 + 2000);
    }

    #[test]
    fn two_sided_polygons_give_two_patches_one_hit_surface() {
        let mesh = Mesh::build(&square_scene(true), Subdivision::Elements(8));
        assert_eq!(mesh.patches.len(), 2);
        assert_eq!(mesh.patches[0].normal, -mesh.patches[1].normal);
        assert_eq!(mesh.triangles.len(), 2);
        mesh.validate().unwrap();
    }

    /// A two-sided unit cube (faces outward), optionally without its top, standing on a
    /// two-sided floor of 4 × 4.
    fn cube_on_floor(closed: bool) -> Scene {
        cube_on_floor_without(if closed { None } else { Some(1) })
    }

    /// The same, without its face `skip` (0 the bottom, 1 the top).
    fn cube_on_floor_without(skip: Option<usize>) -> Scene {
        let mut scene = square_scene(true);
        scene.polygons[0].vertices = vec![
            Vec3::new(-2.0, 0.0, 2.0),
            Vec3::new(2.0, 0.0, 2.0),
            Vec3::new(2.0, 0.0, -2.0),
            Vec3::new(-2.0, 0.0, -2.0),
        ];
        scene.objects.push(Object {
            name: "cube".into(),
        });
        // Off the floor's dyadic grid, so its footprint crosses elements at every level.
        let c = |x: f32, y: f32, z: f32| Vec3::new(x - 0.4321, y, z - 0.3456);
        let faces = [
            [c(0., 0., 0.), c(1., 0., 0.), c(1., 0., 1.), c(0., 0., 1.)], // bottom, facing −y
            [c(0., 1., 0.), c(0., 1., 1.), c(1., 1., 1.), c(1., 1., 0.)], // top
            [c(0., 0., 0.), c(0., 1., 0.), c(1., 1., 0.), c(1., 0., 0.)], // z = 0, facing −z
            [c(0., 0., 1.), c(1., 0., 1.), c(1., 1., 1.), c(0., 1., 1.)],
            [c(0., 0., 0.), c(0., 0., 1.), c(0., 1., 1.), c(0., 1., 0.)], // x = 0, facing −x
            [c(1., 0., 0.), c(1., 1., 0.), c(1., 1., 1.), c(1., 0., 1.)],
        ];
        for (k, f) in faces.iter().enumerate() {
            if skip != Some(k) {
                scene.polygons.push(Polygon {
                    vertices: f.to_vec(),
                    material: 0,
                    object: 1,
                    uv: None,
                });
            }
        }
        scene
    }

    #[test]
    fn closed_two_sided_objects_lose_their_inner_sides_open_ones_keep_them() {
        let closed = Mesh::build(&cube_on_floor(true), Subdivision::Elements(64));
        assert_eq!(
            closed.patches.len(),
            2 + 6,
            "floor twins and the cube's outsides"
        );
        assert!(closed.patches[2..].iter().all(|p| !p.back && !p.two_sided));
        // Each outside faces away from the cube's centre.
        let centre = Vec3::new(0.0679, 0.5, 0.1544);
        for p in 2..closed.patches.len() {
            let face = &closed.nodes[closed.roots[p].start as usize].face;
            assert!(closed.patches[p].normal.dot(face.centroid() - centre) > 0.0);
        }
        let open = Mesh::build(&cube_on_floor(false), Subdivision::Elements(64));
        assert_eq!(open.patches.len(), 2 + 2 * 5);
        closed.validate().unwrap();
        open.validate().unwrap();
    }

    #[test]
    fn a_two_sided_box_standing_on_a_floor_without_its_bottom_is_closed_by_the_floor() {
        let outsides = |scene: &Scene| {
            let mesh = Mesh::build(scene, Subdivision::Elements(64));
            mesh.validate().unwrap();
            mesh.patches.iter().filter(|p| p.object == 1).count()
        };
        let standing = cube_on_floor_without(Some(0));
        assert_eq!(outsides(&standing), 5, "the floor caps it: outsides only");
        // Lifted by 1 mm: light reaches its inside through the gap.
        let mut lifted = standing.clone();
        for p in &mut lifted.polygons[1..] {
            p.vertices.iter_mut().for_each(|v| v.y += 1e-3);
        }
        assert_eq!(outsides(&lifted), 10);
        // Half off a floor of 1 × 4 along x: open where it overhangs.
        let mut overhanging = standing.clone();
        for v in &mut overhanging.polygons[0].vertices {
            v.x = v.x.signum() * 0.5;
        }
        assert_eq!(outsides(&overhanging), 10);
        // A floor facing down, one-sided: nothing reflects on the inside, still open.
        let mut facing_down = standing.clone();
        facing_down.polygons[0].vertices.reverse();
        facing_down.materials.push(Material::default());
        facing_down.polygons[0].material = 1;
        assert_eq!(outsides(&facing_down), 10);
        // Open at the top: no floor there.
        assert_eq!(outsides(&cube_on_floor(false)), 10);
    }

    #[test]
    fn a_bottom_lying_on_the_floor_is_cut_into_it_exactly() {
        let mesh = Mesh::build(&cube_on_floor(true), Subdivision::Elements(64));
        mesh.validate().unwrap();
        assert_eq!(mesh.patches[0].imprinted, vec![1], "the cube's bottom");
        // The footprint x ∈ [−0.4321, 0.5679], z ∈ [−0.3456, 0.6544]: every floor element lies
        // wholly inside or wholly outside it, and those inside make up its area.
        let (x0, z0) = (-0.4321f32, -0.3456f32);
        let (mut under, t) = (0.0, 1e-5);
        for e in mesh.roots[0]
            .clone()
            .flat_map(|r| mesh.nodes[r as usize].elements.clone())
        {
            let c = mesh.element(e as usize).face.corners();
            let inside = c.iter().all(|p| {
                (x0 - t..=x0 + 1.0 + t).contains(&p.x) && (z0 - t..=z0 + 1.0 + t).contains(&p.z)
            });
            let outside = c.iter().all(|p| p.x <= x0 + t)
                || c.iter().all(|p| p.x >= x0 + 1.0 - t)
                || c.iter().all(|p| p.z <= z0 + t)
                || c.iter().all(|p| p.z >= z0 + 1.0 - t);
            assert!(
                inside || outside,
                "element {e} straddles the footprint: {c:?}"
            );
            if inside {
                under += mesh.element(e as usize).area();
            }
        }
        assert!((under - 1.0).abs() < 1e-5, "{under}");
    }

    #[test]
    fn contact_lines_are_refined_and_sources_do_not_straddle_them() {
        // Without its bottom the cube's footprint is only where its walls cross the floor.
        let mut scene = cube_on_floor(true);
        scene.polygons.remove(1);
        let mesh = Mesh::build(&scene, Subdivision::Elements(64));
        // The floor's elements under the cube's footprint edges go CONTACT_LEVELS deeper.
        let floor: Vec<u8> = mesh.nodes[mesh.roots[0].start as usize]
            .elements
            .clone()
            .map(|e| mesh.element(e as usize).level)
            .collect();
        let (lo, hi) = (floor.iter().min().unwrap(), floor.iter().max().unwrap());
        assert_eq!(hi - lo, CONTACT_LEVELS, "{lo} {hi}");
        // The walls of the cube meet the floor along its footprint, not its own edges: the
        // cube's faces themselves are not crossed by anything.
        for p in 2..mesh.patches.len() {
            let levels: Vec<u8> = mesh.roots[p]
                .clone()
                .flat_map(|r| mesh.nodes[r as usize].elements.clone())
                .map(|e| mesh.element(e as usize).level)
                .collect();
            assert!(levels.windows(2).all(|w| w[0] == w[1]));
        }
        // Sources: a coarse cut, but every node with leaves at several levels is opened, as long
        // as the contact lines' leaves fit the budget; when they do not, the budget wins.
        let all = mesh.element_count();
        let sources = mesh.sources(all - 1, all - 1);
        assert!(sources.len() < all);
        let tight = mesh.sources(8, 8);
        assert!(tight.len() <= 8.max(mesh.roots.iter().map(|r| r.len()).sum()));
        // Given room to grow, a small budget grows until no source straddles.
        let grown = mesh.sources(8, all);
        assert!(grown.len() > 8 && grown.len() < all);
        for sources in [&sources, &grown] {
            for &s in sources {
                let node = &mesh.nodes[s as usize];
                let mut levels = node
                    .elements
                    .clone()
                    .map(|e| mesh.element(e as usize).level);
                let first = levels.next();
                assert!(levels.all(|l| Some(l) == first), "source {s} straddles");
            }
        }
        mesh.validate().unwrap();
    }

    #[test]
    fn an_emitter_hovering_face_down_is_outlined_deeper_than_other_covers() {
        // The unit square (facing +z) with a panel 1 mm above it, off the square's dyadic grid:
        // facing the square and emitting, or emitting away from it.
        let levels = |facing: bool| {
            let mut scene = square_scene(false);
            scene.materials.push(Material {
                emission: Rgb::ONE,
                ..Material::default()
            });
            // L-shaped, so not cut into the square's root faces as a convex outline would be.
            let (a, m, b, h) = (0.2345, 0.5123, 0.7321, 0.001);
            let mut vertices = vec![
                Vec3::new(a, a, h),
                Vec3::new(b, a, h),
                Vec3::new(b, m, h),
                Vec3::new(m, m, h),
                Vec3::new(m, b, h),
                Vec3::new(a, b, h),
            ];
            if facing {
                vertices.reverse();
            }
            scene.polygons.push(Polygon {
                vertices,
                material: 1,
                object: 0,
                uv: None,
            });
            let mesh = Mesh::build(&scene, Subdivision::Elements(256));
            mesh.validate().unwrap();
            let square: Vec<u8> = mesh.nodes[mesh.roots[0].start as usize]
                .elements
                .clone()
                .map(|e| mesh.element(e as usize).level)
                .collect();
            square.iter().max().unwrap() - square.iter().min().unwrap()
        };
        assert_eq!(levels(true), contact::COVER_LEVELS);
        assert_eq!(levels(false), CONTACT_LEVELS);
    }

    #[test]
    fn sources_cut_covers_every_element_once() {
        let mesh = Mesh::build(&square_scene(false), Subdivision::Elements(1024));
        let sources = mesh.sources(64, 64);
        assert_eq!(sources.len(), 64);
        assert_eq!(
            mesh.sources(100, 100).len(),
            64,
            "the next cut has 256 nodes"
        );
        let mut covered = 0;
        for &s in &sources {
            let r = &mesh.nodes[s as usize].elements;
            assert_eq!(r.start, covered);
            covered = r.end;
        }
        assert_eq!(covered as usize, mesh.element_count());
        assert_eq!(mesh.sources(5000, 5000), mesh.elements);
    }

    #[test]
    fn over_budget_sources_still_open_the_coarse_mixed_nodes() {
        // A cube standing on a floor: the floor's quadtree is refined along the contact line.
        // With a limit below what opening every mixed node needs, the sources still open the
        // shallow ones (whose means mix the most across the line) and stay within the limit.
        let mesh = Mesh::build(&cube_on_floor(true), Subdivision::Elements(256));
        let mixed = |n: u32| {
            let node = &mesh.nodes[n as usize];
            let levels: Vec<u8> = mesh.elements
                [node.elements.start as usize..node.elements.end as usize]
                .iter()
                .map(|&e| mesh.nodes[e as usize].level)
                .collect();
            levels.iter().any(|&l| l != levels[0])
        };
        let all = mesh.sources(8, 100_000);
        assert!(
            all.iter().all(|&n| !mixed(n)),
            "everything opened when it fits"
        );
        let limit = all.len() / 2;
        let some = mesh.sources(8, limit);
        assert!(some.len() <= limit.max(mesh.roots.iter().map(|r| r.len()).sum()));
        let shallowest = some
            .iter()
            .filter(|&&n| mixed(n))
            .map(|&n| mesh.nodes[n as usize].level)
            .min();
        // Whatever still straddles a contact line is deeper than the roots.
        assert!(shallowest.is_none_or(|l| l > 0), "{shallowest:?}");
    }

    /// Ctrl-C must not wait for the contact and shadow refinements (seconds on large scenes):
    /// they ask their stop question for every element they test, and a meshing told to stop
    /// gives up. Counting the questions states this without a clock.
    #[test]
    fn meshing_asks_whether_to_stop_for_every_element_and_gives_up_when_told() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        // Boxes standing on a floor under a light: both refinements have work.
        let scene = crate::scene::builtin::load("cornell")
            .expect("built in")
            .expect("loads");
        let subdivision = Subdivision::Elements(300);
        let asked = AtomicUsize::new(0);
        let counting = || {
            asked.fetch_add(1, Ordering::SeqCst);
            false
        };
        let mesh =
            Mesh::build_unless(&scene, subdivision, false, &counting, &Silent).expect("not told");
        assert_eq!(
            mesh.element_count(),
            Mesh::build(&scene, subdivision).element_count()
        );
        // Contact refinement asks for each uniform element, shadow refinement for each element
        // contact refinement left (at least as many).
        let (_, uniform) = Mesh::plan(&scene, subdivision, false);
        let asked = asked.load(Ordering::SeqCst);
        assert!(
            asked as f64 >= 2.0 * uniform,
            "{asked} questions, {uniform} elements"
        );
        assert!(Mesh::build_unless(&scene, subdivision, false, &|| true, &Silent).is_none());
    }
}
