//! Building: a checked [`SceneDesc`] (or an OBJ file) becomes the frozen [`Scene`].
//!
//! Every shape is turned into planar polygons here, one build function per [`ShapeDesc`]
//! variant: a polygon as written, a box by [`model::primitives::cuboid`], a sphere by
//! [`model::primitives::icosphere`], a mesh by [`crate::scene::import::obj`]. The object's transform
//! (scale → rotate x, y, z → translate, [`model::Transform::from_srt`]) is applied to the
//! corners, and faces are reversed when it mirrors so that fronts stay fronts.
//!
//! Objects that share a name are one object (the Cornell ceiling is four quads named
//! `ceiling`). Generated and imported faces are checked with
//! [`super::check::polygon_problem`]: degenerate ones are skipped and strongly non-planar
//! ones are split into a triangle fan, each with a counted warning, never an error.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Vec3;
use model::{PolyMesh, Transform};

use super::check::{fail, polygon_problem, PolygonProblem};
use super::coincident::{Dropped, SeenFaces};
use super::description::{Field, GridDesc, GridPlace, ObjectDesc, SceneDesc, ShapeDesc};
use super::environment::{CieSky, CieSkyKind, Environment};
use super::grid::{count_problem, Face, Grid, FACING_DEGREES, LIFT_METRES};
use super::{
    builtin, check, facing_emitters, frame, parse, Camera, Material, Object, Polygon, Scene,
};
use super::{RenderDefaults, SceneError};
use crate::scene::import::gltf_file;
use crate::scene::import::obj::{self, ObjFile};

mod luminaire;
mod mitsuba;
mod shapes;
use shapes::{modeled_mesh, solid_mesh};

impl Scene {
    /// Loads a scene file: `.toml` (the scene format), `.obj` (a bare mesh, see
    /// [`Scene::from_obj_file`]), `.gltf`/`.glb`, or `.xml` (a Mitsuba scene, see
    /// [`Scene::from_mitsuba_file`]).
    ///
    /// # Errors
    /// The file cannot be read, has another extension, or is not a valid scene; the error
    /// names the file, line, column and key where they apply.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        if path.is_dir() {
            return Err(SceneError::in_file(
                path,
                "is a directory, not a scene file (.toml, .obj, .gltf, .glb or .xml)",
            ));
        }
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("toml") => {
                let text = std::fs::read_to_string(path)
                    .map_err(|e| SceneError::in_file(path, format!("cannot read: {e}")))?;
                Self::from_toml_str(&text, path)
            }
            Some("obj") => Self::from_obj_file(path),
            Some("gltf" | "glb") => Self::from_gltf_file(path),
            Some("xml") => Self::from_mitsuba_file(path),
            _ => Err(SceneError::in_file(
                path,
                "unsupported scene file type (expected .toml, .obj, .gltf, .glb or .xml)",
            )),
        }
    }

    /// A scene from TOML text; `file` names it in messages and anchors relative mesh paths.
    ///
    /// # Errors
    /// As [`Scene::load`].
    pub fn from_toml_str(text: &str, file: &Path) -> Result<Self, SceneError> {
        let desc = parse::parse(text, file)?;
        check::check(&desc)?;
        build(&desc)
    }

    /// A bare OBJ file as a scene: one object per `o`/`g` name, materials from its MTL files
    /// made two-sided (emitters still emit from the front only), and a framed camera
    /// ([`frame::frame`]).
    ///
    /// # Errors
    /// The file cannot be read or is malformed (see [`crate::scene::import::obj`]), or has no usable face.
    pub fn from_obj_file(path: &Path) -> Result<Self, SceneError> {
        let obj = obj::read_obj(path)?;
        let mut b = Builder::new(path);
        b.scene.warnings = obj.warnings.clone();
        let base = b.scene.materials.len();
        b.scene
            .materials
            .extend(obj.materials.iter().map(|m| Material {
                two_sided: true,
                ..m.clone()
            }));
        let objects: Vec<usize> = obj.groups.iter().map(|g| b.object(g)).collect();
        b.add_obj(
            &obj,
            |f| (base + f.material, objects[f.group]),
            &Transform::IDENTITY,
            &path.display().to_string(),
        );
        b.finish(Vec::new(), RenderDefaults::default())
    }

    /// A glTF file (`.gltf` or `.glb`) as a scene: one object per node name, its materials
    /// as written (`doubleSided` kept), and its first perspective camera or a framed one
    /// (see [`crate::scene::import::gltf_file`]).
    ///
    /// # Errors
    /// The file cannot be read or is not valid glTF, or has no usable triangle.
    pub fn from_gltf_file(path: &Path) -> Result<Self, SceneError> {
        let gltf = gltf_file::read_gltf(path)?;
        let obj = gltf.mesh;
        let mut b = Builder::new(path);
        b.scene.warnings = obj.warnings.clone();
        let base = b.scene.materials.len();
        b.scene.materials.extend(obj.materials.iter().cloned());
        let objects: Vec<usize> = obj.groups.iter().map(|g| b.object(g)).collect();
        b.add_obj(
            &obj,
            |f| (base + f.material, objects[f.group]),
            &Transform::IDENTITY,
            &path.display().to_string(),
        );
        b.scene.luminaires = gltf.luminaires;
        b.finish(gltf.cameras, RenderDefaults::default())
    }

    /// A built-in scene by name (see [`builtin::names`]) or else a scene file path.
    ///
    /// # Errors
    /// As [`Scene::load`]; a path that does not exist also lists the built-in names.
    pub fn resolve(arg: &str) -> Result<Self, SceneError> {
        let path = Path::new(arg);
        if !path.exists() {
            if let Some(scene) = builtin::load(arg) {
                return scene;
            }
            let names: Vec<&str> = builtin::names().iter().map(|(n, _)| *n).collect();
            return Err(SceneError::in_file(
                path,
                format!(
                    "no such file, and not a built-in scene (built-ins: {})",
                    names.join(", ")
                ),
            ));
        }
        Self::load(path)
    }

    /// The camera named `name`.
    #[must_use]
    pub fn camera(&self, name: &str) -> Option<&Camera> {
        self.cameras.iter().find(|c| c.name == name)
    }
}

/// Builds a checked description into a scene.
///
/// # Errors
/// A mesh file cannot be read or is malformed, or the scene ends up with no polygon.
pub fn build(desc: &SceneDesc) -> Result<Scene, SceneError> {
    let mut b = Builder::new(&desc.file);
    b.scene.materials = desc
        .materials
        .iter()
        .map(|m| Material {
            name: m.name.value.clone(),
            reflectance: m.reflectance.value,
            texture: None,
            emission: m.emission.value,
            two_sided: m.two_sided,
            specular: m.specular.value,
            transmission: m.transmission.value,
            ior: m.ior.value,
        })
        .collect();
    for o in &desc.objects {
        build_object(&mut b, desc, o)?;
    }
    let cameras = desc
        .cameras
        .iter()
        .map(|c| Camera {
            name: c.name.value.clone(),
            eye: c.eye.value,
            target: c.target.value,
            up: c.up.value,
            fov_y: c.fov_y.value,
        })
        .collect();
    let defaults = RenderDefaults::default();
    let render = RenderDefaults {
        width: desc
            .render
            .width
            .as_ref()
            .map_or(defaults.width, |w| w.value),
        height: desc
            .render
            .height
            .as_ref()
            .map_or(defaults.height, |h| h.value),
    };
    b.scene.units = desc
        .units
        .as_ref()
        .map_or_else(Default::default, |u| u.value);
    let mut grids = Vec::with_capacity(desc.grids.len());
    for g in &desc.grids {
        grids.push(match &g.place {
            GridPlace::Corners(c) => {
                let c = &c.value;
                Grid::new(
                    &g.name.value,
                    [c[0], c[1], c[2]],
                    g.spacing.value,
                    g.normal.as_ref().map(|n| n.value),
                )
            }
            GridPlace::On(on) => grid_on(&b, desc, g, on)?,
        });
    }
    b.scene.grids = grids;
    if let Some(sky_desc) = &desc.sky {
        let sky = CieSky {
            kind: CieSkyKind::named(&sky_desc.kind.value).expect("checked"),
            zenith_luminance: sky_desc.zenith_luminance.value,
            sun_direction: super::check::sun_direction(desc, sky_desc)?.unwrap_or(Vec3::Y),
            up: Vec3::Y,
        };
        b.scene.sky_illuminance = Some(sky.horizontal_illuminance());
        if let Some(e) = &sky_desc.sun_illuminance {
            let metres = b.scene.units.metres();
            let aim = -sky.sun_direction;
            let beam =
                super::Luminaire::directional("sun", aim, crate::Rgb::splat(e.value), metres);
            b.scene.luminaires.push(beam);
        }
        b.scene.cameras.clone_from(&cameras);
        b.scene.add_environment(&Environment::Cie(sky))?;
    }
    b.finish(cameras, render)
}

/// A grid `on` an object ([`Grid::on`]): on the faces of the object whose front faces the
/// grid's `normal` (default up) within [`FACING_DEGREES`], its points [`LIFT_METRES`] above
/// them. Errors, at `on`: the object has no such face; at `spacing`: too many points.
fn grid_on(
    b: &Builder,
    desc: &SceneDesc,
    g: &GridDesc,
    on: &Field<String>,
) -> Result<Grid, SceneError> {
    let normal = g.normal.as_ref().map_or(Vec3::Y, |n| n.value.normalize());
    let object = b.objects.get(&on.value).copied();
    let cos = FACING_DEGREES.to_radians().cos();
    let faces: Vec<Face> = b
        .scene
        .polygons
        .iter()
        .filter(|p| Some(p.object) == object)
        .filter_map(|p| Face::of(&p.vertices))
        .map(|(face, _)| face)
        .filter(|face| face.normal.dot(normal) >= cos)
        .collect();
    let lift = (LIFT_METRES / b.scene.units.metres()) as f32;
    let Some(grid) = Grid::on(&g.name.value, faces, g.spacing.value, normal, lift) else {
        let [x, y, z] = normal.to_array();
        return Err(check::fail(
            desc,
            on,
            format!(
                "no face of `{}` faces the grid's normal [{x}, {y}, {z}] (within \
                 {FACING_DEGREES}°): give the `normal` of the faces to measure on",
                on.value
            ),
        ));
    };
    if let Some(message) = count_problem(grid.first, grid.second, g.spacing.value) {
        return Err(check::fail(desc, &g.spacing, message));
    }
    if grid.layout().is_empty() {
        let message = format!(
            "no cell centre at spacing {} falls on the faces of `{}`: narrow it",
            g.spacing.value, on.value
        );
        return Err(check::fail(desc, &g.spacing, message));
    }
    Ok(grid)
}

/// One `[[objects]]` entry into polygons.
fn build_object(b: &mut Builder, desc: &SceneDesc, o: &ObjectDesc) -> Result<(), SceneError> {
    let object = b.object(&o.name());
    let material = o
        .material
        .as_ref()
        .and_then(|m| b.scene.materials.iter().position(|d| d.name == m.value));
    let transform = o.transform.as_ref().map_or(Transform::IDENTITY, |t| {
        Transform::from_srt(t.scale.value, t.rotate.value, t.translate.value)
    });
    let label = format!("objects[{}] (`{}`)", o.index, o.name());
    // Validation guarantees the material exists for every shape but `mesh`.
    let m = material.unwrap_or(0);
    match &o.shape {
        ShapeDesc::Polygon { vertices } => {
            build_polygon(b, &vertices.value, &transform, m, object, &label);
        }
        ShapeDesc::Box { min, max } => {
            let mesh = model::primitives::cuboid(min.value, max.value);
            b.add_mesh(mesh, &transform, m, object, &label);
        }
        ShapeDesc::Sphere {
            center,
            radius,
            subdivisions,
        } => {
            let mesh = model::primitives::icosphere(center.value, radius.value, subdivisions.value);
            b.add_mesh(mesh, &transform, m, object, &label);
        }
        ShapeDesc::Mesh { path } => {
            build_mesh(b, desc, path, &transform, material, object, &label)?
        }
        ShapeDesc::Implicit { .. } | ShapeDesc::Csg { .. } => {
            let mesh = solid_mesh(desc, o, &o.shape)?;
            if let Err(e) = model::brep::closed_topology(&mesh) {
                b.scene
                    .warnings
                    .push(format!("{label}: the solid is not closed ({e})"));
            }
            b.add_mesh(mesh, &transform, m, object, &label);
        }
        ShapeDesc::Luminaire(l) => {
            let metres = desc.units.as_ref().map_or(1.0, |u| u.value.metres());
            let lum = luminaire::build(desc, &o.name(), l, &transform, metres)?;
            b.scene.luminaires.push(lum);
        }
        ShapeDesc::Instance { of } => {
            let mesh = b.prototype(desc, &of.value)?;
            b.add_mesh(PolyMesh::clone(&mesh), &transform, m, object, &label);
        }
        shape @ (ShapeDesc::BezierPatch { .. }
        | ShapeDesc::NurbsSurface { .. }
        | ShapeDesc::Revolve { .. }
        | ShapeDesc::Subdivision { .. }
        | ShapeDesc::Teapot { .. }) => {
            let mesh = modeled_mesh(desc, o, shape)?;
            b.add_mesh(mesh, &transform, m, object, &label);
        }
    }
    Ok(())
}

/// A polygon as written (already checked), transformed.
fn build_polygon(
    b: &mut Builder,
    vertices: &[Vec3],
    t: &Transform,
    material: usize,
    object: usize,
    label: &str,
) {
    let mut vs: Vec<Vec3> = vertices.iter().map(|&v| t.point(v)).collect();
    if t.mirrors() {
        vs.reverse();
    }
    // Repeated corners are dropped and a strongly non-planar polygon is fanned, with a warning.
    let face = Polygon {
        vertices: vs,
        material,
        object,
        uv: None,
    };
    b.add_faces(std::iter::once((face, None)), label);
}

/// Drops corners that repeat the one before (and a last corner repeating the first), with
/// their texture coordinates.
fn drop_repeated_corners(face: &mut Polygon) {
    let vs = &face.vertices;
    let mut keep: Vec<usize> = Vec::with_capacity(vs.len());
    for k in 0..vs.len() {
        if !keep.last().is_some_and(|&last| vs[last] == vs[k]) {
            keep.push(k);
        }
    }
    if keep.len() > 1 && vs[keep[0]] == vs[keep[keep.len() - 1]] {
        keep.pop();
    }
    if keep.len() < vs.len() {
        face.vertices = keep.iter().map(|&k| vs[k]).collect();
        if let Some(uv) = &mut face.uv {
            *uv = keep.iter().filter_map(|&k| uv.get(k).copied()).collect();
        }
    }
}

/// A file a scene names (`path`, relative to the scene file's folder).
fn beside(desc: &SceneDesc, path: &Path) -> PathBuf {
    desc.file.parent().unwrap_or(Path::new("")).join(path)
}

/// An OBJ file as the faces of one object, with its own materials unless `material` is given.
fn build_mesh(
    b: &mut Builder,
    desc: &SceneDesc,
    path: &Field<PathBuf>,
    transform: &Transform,
    material: Option<usize>,
    object: usize,
    label: &str,
) -> Result<(), SceneError> {
    let full = beside(desc, &path.value);
    let is_gltf = full
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"));
    let obj = if is_gltf {
        if !full.is_file() {
            return Err(fail(
                desc,
                path,
                format!("cannot read mesh `{}`", full.display()),
            ));
        }
        let gltf = gltf_file::read_gltf(&full)?;
        if !gltf.luminaires.is_empty() {
            b.scene.warnings.push(format!(
                "{label}: {} KHR_lights_punctual light(s) of `{}` left out: a mesh object brings \
                 its surfaces only (load the file as the scene to keep them)",
                gltf.luminaires.len(),
                full.display()
            ));
        }
        gltf.mesh
    } else {
        let text = std::fs::read_to_string(&full).map_err(|e| {
            fail(
                desc,
                path,
                format!("cannot read mesh `{}`: {e}", full.display()),
            )
        })?;
        obj::parse_obj(&text, &full)?
    };
    if obj.faces.is_empty() {
        let message = format!("mesh `{}` has no faces: is it a mesh?", full.display());
        return Err(fail(desc, path, message));
    }
    b.scene.warnings.extend(obj.warnings.iter().cloned());
    let base = b.scene.materials.len();
    if material.is_none() {
        b.scene.materials.extend(obj.materials.iter().cloned());
    }
    b.add_obj(
        &obj,
        |f| (material.unwrap_or(base + f.material), object),
        transform,
        label,
    );
    Ok(())
}

/// A scene under construction.
struct Builder {
    file: PathBuf,
    scene: Scene,
    objects: HashMap<String, usize>,
    /// Meshes of objects reused by `instance` shapes, built once and shared.
    prototypes: HashMap<String, Arc<PolyMesh>>,
    /// The faces added so far, to drop coincident duplicates.
    seen: SeenFaces,
}

impl Builder {
    fn new(file: &Path) -> Self {
        let stem = file.file_stem().and_then(|s| s.to_str()).unwrap_or("scene");
        // `scenes/cornell/scene.toml` is called `cornell`, and so is `cornell/scene_mi3.xml`.
        let name = match file
            .parent()
            .and_then(|p| p.file_name())
            .and_then(|p| p.to_str())
        {
            Some(dir) if stem == "scene" || stem.starts_with("scene_") => dir,
            _ => stem,
        };
        Self {
            file: file.to_path_buf(),
            scene: Scene {
                name: name.to_string(),
                ..Scene::default()
            },
            objects: HashMap::new(),
            prototypes: HashMap::new(),
            seen: SeenFaces::default(),
        }
    }

    /// The shape (before its transform) of the object named `name`, built on first use and
    /// shared by every instance of it.
    fn prototype(&mut self, desc: &SceneDesc, name: &str) -> Result<Arc<PolyMesh>, SceneError> {
        if let Some(m) = self.prototypes.get(name) {
            return Ok(Arc::clone(m));
        }
        let o = desc
            .objects
            .iter()
            .find(|o| o.name.as_ref().is_some_and(|n| n.value == name))
            .ok_or_else(|| SceneError::in_file(&self.file, format!("no object named `{name}`")))?;
        let mesh = Arc::new(solid_mesh(desc, o, &o.shape)?);
        self.prototypes.insert(name.to_string(), Arc::clone(&mesh));
        Ok(mesh)
    }

    /// The index of the object called `name`, created on first use.
    fn object(&mut self, name: &str) -> usize {
        if let Some(&i) = self.objects.get(name) {
            return i;
        }
        self.scene.objects.push(Object { name: name.into() });
        let i = self.scene.objects.len() - 1;
        self.objects.insert(name.into(), i);
        i
    }

    /// Faces of a generated mesh, transformed and checked.
    fn add_mesh(
        &mut self,
        mut mesh: PolyMesh,
        t: &Transform,
        material: usize,
        object: usize,
        label: &str,
    ) {
        mesh.transform(t);
        let faces = (0..mesh.faces.len()).map(|f| Polygon {
            vertices: mesh.face_positions(f),
            material,
            object,
            uv: None,
        });
        self.add_faces(faces.map(|f| (f, None)), label);
    }

    /// Faces of an OBJ file, transformed and checked; `assign` gives each face its material
    /// and object.
    fn add_obj(
        &mut self,
        obj: &ObjFile,
        assign: impl Fn(&obj::ObjFace) -> (usize, usize),
        t: &Transform,
        label: &str,
    ) {
        let faces = obj.faces.iter().map(|f| {
            let (material, object) = assign(f);
            let mut face = Polygon {
                vertices: f.positions(obj).into_iter().map(|p| t.point(p)).collect(),
                material,
                object,
                uv: f.texcoords(obj),
            };
            if t.mirrors() {
                face.vertices.reverse();
                if let Some(uv) = &mut face.uv {
                    uv.reverse();
                }
            }
            (face, Some(f.line))
        });
        self.add_faces(faces, label);
    }

    /// Adds faces (with the file line they come from, if any), skipping degenerate ones,
    /// fanning strongly non-planar ones and dropping coincident duplicates (see
    /// [`super::coincident`]), with a warning for each kind. Texture coordinates follow their
    /// corners.
    fn add_faces(&mut self, faces: impl Iterator<Item = (Polygon, Option<usize>)>, label: &str) {
        let (mut skipped, mut split) = (0usize, 0usize);
        let mut dropped = Dropped::default();
        for (mut face, line) in faces {
            drop_repeated_corners(&mut face);
            let vs = &face.vertices;
            let two_sided = self.scene.materials[face.material].two_sided;
            if vs.len() >= 3 && !self.seen.first_time(vs, two_sided) {
                dropped.add(line);
                continue;
            }
            match polygon_problem(vs) {
                None => self.scene.polygons.push(face),
                Some(PolygonProblem::NonPlanar(_)) => {
                    split += 1;
                    let corners = |i: usize, j: usize| Polygon {
                        vertices: vec![vs[0], vs[i], vs[j]],
                        uv: face.uv.as_ref().map(|uv| vec![uv[0], uv[i], uv[j]]),
                        material: face.material,
                        object: face.object,
                    };
                    let fan: Vec<Polygon> = (1..vs.len() - 1)
                        .map(|i| corners(i, i + 1))
                        .filter(|tri| polygon_problem(&tri.vertices).is_none())
                        .collect();
                    self.scene.polygons.extend(fan);
                }
                Some(_) => skipped += 1,
            }
        }
        if skipped > 0 {
            self.scene
                .warnings
                .push(format!("{label}: skipped {skipped} degenerate face(s)"));
        }
        if split > 0 {
            self.scene.warnings.push(format!(
                "{label}: split {split} non-planar face(s) into triangles"
            ));
        }
        self.scene.warnings.extend(dropped.warning(label));
    }

    /// Fits the directional lights to the bounds of the scene's polygons, a far environment's
    /// left out ([`super::Luminaire::within`]): their shadow rays cross the scene and end short of it.
    fn fit_directional_lights(&mut self) {
        let far = self
            .scene
            .objects
            .iter()
            .position(|o| o.name == super::environment::NAME);
        let bounds = super::enclosure::box_around(
            self.scene
                .polygons
                .iter()
                .filter(|p| Some(p.object) != far)
                .flat_map(|p| p.vertices.iter().copied()),
        );
        if let Some((lo, hi)) = bounds {
            for l in &mut self.scene.luminaires {
                l.within(lo, hi);
            }
        }
    }

    /// The finished scene: at least one polygon, and a camera (framed if none was given).
    fn finish(mut self, cameras: Vec<Camera>, render: RenderDefaults) -> Result<Scene, SceneError> {
        if self.scene.polygons.is_empty() {
            return Err(SceneError::in_file(&self.file, "the scene has no polygons"));
        }
        self.fit_directional_lights();
        if !self.scene.has_emitter() {
            self.scene
                .warnings
                .push(format!("{}: {}", self.file.display(), super::sky::NO_LIGHT));
        }
        let near = facing_emitters::warnings(&self.scene, &self.file.display().to_string());
        self.scene.warnings.extend(near);
        self.scene.cameras = if cameras.is_empty() {
            vec![frame::frame(&self.scene.polygons, &self.scene.materials)]
        } else {
            cameras
        };
        self.scene.render = render;
        Ok(self.scene)
    }
}
