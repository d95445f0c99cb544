//! Scene descriptions: what a scene file says, before it is checked or built.
//!
//! Plain structs, one per table of the format (docs/scene-format.md), in which every value keeps where
//! it was written ([`Field`]: its 1-based line and column and its dotted key path), so that
//! [`super::check`] and [`super::build`] can point at the exact spot of a problem, as
//! pbrt-v4's scene entities keep their `FileLoc`.
//!
//! Shapes are a closed enum, [`ShapeDesc`]: a new kind of object (a Bézier patch, a CSG tree)
//! is one more variant, one entry in the parser's shape table (its keys), and one build
//! function that turns it into polygons.

use std::path::PathBuf;

use glam::Vec3;

use crate::Rgb;

/// A 1-based line and column in the scene file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Pos {
    /// 1-based line.
    pub line: usize,
    /// 1-based column (in characters).
    pub col: usize,
}

/// A value with the place it was written and its key path (`objects[2].material`).
#[derive(Clone, Debug, PartialEq)]
pub struct Field<T> {
    /// The value.
    pub value: T,
    /// Where the value (or, for a default, its table) was written.
    pub pos: Pos,
    /// Dotted key path.
    pub key: String,
}

impl<T> Field<T> {
    /// The same place and key with the value mapped.
    #[must_use]
    pub fn map<U>(self, f: impl FnOnce(T) -> U) -> Field<U> {
        Field {
            value: f(self.value),
            pos: self.pos,
            key: self.key,
        }
    }
}

/// A whole scene file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneDesc {
    /// The file, for messages and for resolving relative mesh paths.
    pub file: PathBuf,
    /// `[camera]` or `[[cameras]]`, in order (the first is the default); may be empty.
    pub cameras: Vec<CameraDesc>,
    /// `[render]`.
    pub render: RenderDesc,
    /// `units`, the length unit (metres when absent).
    pub units: Option<Field<crate::scene::units::Units>>,
    /// `[materials.NAME]`, in file order.
    pub materials: Vec<MaterialDesc>,
    /// `[[objects]]`, in file order.
    pub objects: Vec<ObjectDesc>,
    /// `[[grids]]`, in file order.
    pub grids: Vec<GridDesc>,
    /// `[sky]`, a CIE standard sky around the scene.
    pub sky: Option<SkyDesc>,
}

/// A CIE standard sky ([`crate::scene::environment::cie_sky`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SkyDesc {
    /// `type`: `cie-overcast`, `cie-1` or `cie-12`.
    pub kind: Field<String>,
    /// `zenith_luminance`, cd·m⁻².
    pub zenith_luminance: Field<f64>,
    /// `sun`: the direction towards the sun (needed by `cie-12`, unless the place and time
    /// below are given).
    pub sun: Option<Field<Vec3>>,
    /// `latitude`, degrees north: with `longitude`, `date` and `time`, where the sun is
    /// ([`crate::scene::environment::solar`]).
    pub latitude: Option<Field<f64>>,
    /// `longitude`, degrees east.
    pub longitude: Option<Field<f64>>,
    /// `date`, `YYYY-MM-DD`.
    pub date: Option<Field<String>>,
    /// `time`, the local clock time `HH:MM`.
    pub time: Option<Field<String>>,
    /// `utc_offset`, hours (default 0).
    pub utc_offset: Option<Field<f64>>,
    /// `north`, the scene's north (default −z).
    pub north: Option<Field<Vec3>>,
    /// `sun_illuminance`, lx: the sun's beam as a directional light of this illuminance on a
    /// plane facing the sun (none by default: the sky alone).
    pub sun_illuminance: Option<Field<f64>>,
}

/// A calculation grid ([`crate::scene::grid`]).
#[derive(Clone, Debug, PartialEq)]
pub struct GridDesc {
    /// `name`.
    pub name: Field<String>,
    /// `corners` or `on`: where the grid lies.
    pub place: GridPlace,
    /// `spacing`: the widest cell side, scene units.
    pub spacing: Field<f32>,
    /// `normal` of the measuring surface (default: up for a horizontal grid, else the
    /// right-hand normal).
    pub normal: Option<Field<Vec3>>,
}

/// Where a calculation grid lies: one of its two keys.
#[derive(Clone, Debug, PartialEq)]
pub enum GridPlace {
    /// `corners`: the origin, the end of the first axis, the end of the second.
    Corners(Field<Vec<Vec3>>),
    /// `on`: the name of the object whose faces facing the grid's normal it covers.
    On(Field<String>),
}

/// A perspective camera.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraDesc {
    /// `name` (`default` for a lone `[camera]`).
    pub name: Field<String>,
    /// `eye`.
    pub eye: Field<Vec3>,
    /// `target`.
    pub target: Field<Vec3>,
    /// `up` (default +y).
    pub up: Field<Vec3>,
    /// `fov_y` in degrees (default 40).
    pub fov_y: Field<f32>,
}

/// Image size defaults.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderDesc {
    /// `width` in pixels.
    pub width: Option<Field<u32>>,
    /// `height` in pixels.
    pub height: Option<Field<u32>>,
}

/// A material.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialDesc {
    /// The table name (`[materials.NAME]`).
    pub name: Field<String>,
    /// `reflectance` ρ (default 0).
    pub reflectance: Field<Rgb>,
    /// `emission`: emitted radiance (default 0).
    pub emission: Field<Rgb>,
    /// `two_sided` (default false).
    pub two_sided: bool,
    /// `specular` (default 0).
    pub specular: Field<Rgb>,
    /// `transmission` (default 0).
    pub transmission: Field<Rgb>,
    /// `ior` (default 1.5).
    pub ior: Field<f64>,
}

/// One `[[objects]]` entry.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectDesc {
    /// Position in the `objects` array (names unnamed objects: `object3`).
    pub index: usize,
    /// Where the entry starts.
    pub pos: Pos,
    /// `name`.
    pub name: Option<Field<String>>,
    /// `material` (required except for meshes, where it overrides the file's materials).
    pub material: Option<Field<String>>,
    /// `transform`.
    pub transform: Option<TransformDesc>,
    /// `shape` and the shape's own keys.
    pub shape: ShapeDesc,
}

impl ObjectDesc {
    /// The object's name, or the generated `object{index}`.
    #[must_use]
    pub fn name(&self) -> String {
        self.name
            .as_ref()
            .map_or_else(|| format!("object{}", self.index), |n| n.value.clone())
    }
}

/// `transform = { scale, rotate, translate }`: scale, then rotate about x, y, z (degrees), then
/// translate.
#[derive(Clone, Debug, PartialEq)]
pub struct TransformDesc {
    /// `scale` (a number or a 3-vector; default 1).
    pub scale: Field<Vec3>,
    /// `rotate` in degrees (default 0).
    pub rotate: Field<Vec3>,
    /// `translate` (default 0).
    pub translate: Field<Vec3>,
}

/// The shape of an object and its own keys.
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeDesc {
    /// `shape = "polygon"`: one planar polygon.
    Polygon {
        /// `vertices`, counter-clockwise seen from the front.
        vertices: Field<Vec<Vec3>>,
    },
    /// `shape = "box"`: an axis-aligned box, faces outward.
    Box {
        /// `min` corner.
        min: Field<Vec3>,
        /// `max` corner.
        max: Field<Vec3>,
    },
    /// `shape = "sphere"`: a subdivided icosahedron.
    Sphere {
        /// `center`.
        center: Field<Vec3>,
        /// `radius`.
        radius: Field<f32>,
        /// `subdivisions` (default 3: 1280 triangles).
        subdivisions: Field<u32>,
    },
    /// `shape = "mesh"`: an OBJ file.
    Mesh {
        /// `path`, as written (relative to the scene file).
        path: Field<PathBuf>,
    },
    /// `shape = "bezier_patch"`: tensor-product Bézier patches, from `points` or a file.
    BezierPatch {
        /// `points`: one patch's control net, a list of rows (along u) of points (along v).
        points: Option<Field<Vec<Vec<Vec3>>>>,
        /// `path`: bicubic patches in Newell's text format, relative to the scene file.
        path: Option<Field<PathBuf>>,
        /// `tolerance`: chordal tolerance in scene units.
        tolerance: Option<Field<f64>>,
    },
    /// `shape = "nurbs_surface"`: one tensor-product NURBS patch.
    NurbsSurface {
        /// `points`: the control net, rows along u.
        points: Field<Vec<Vec<Vec3>>>,
        /// `weights`, the same shape as `points` (default all 1).
        weights: Option<Field<Vec<Vec<f64>>>>,
        /// `degree = [p, q]` (default 3, at most the net size − 1).
        degree: Option<Field<Vec<u32>>>,
        /// `knots_u` (default clamped uniform).
        knots_u: Option<Field<Vec<f64>>>,
        /// `knots_v` (default clamped uniform).
        knots_v: Option<Field<Vec<f64>>>,
        /// `tolerance`: chordal tolerance in scene units.
        tolerance: Option<Field<f64>>,
    },
    /// `shape = "revolve"`: a NURBS profile curve turned about an axis.
    Revolve {
        /// `profile` control points.
        profile: Field<Vec<Vec3>>,
        /// `weights` of the profile (default all 1).
        weights: Option<Field<Vec<f64>>>,
        /// `degree` of the profile (default 3, at most the point count − 1).
        degree: Option<Field<u32>>,
        /// `knots` of the profile (default clamped uniform).
        knots: Option<Field<Vec<f64>>>,
        /// `origin`: a point on the axis (default 0).
        origin: Field<Vec3>,
        /// `axis` direction (default +y).
        axis: Field<Vec3>,
        /// `angle` in degrees (default 360).
        angle: Field<f64>,
        /// `tolerance`: chordal tolerance in scene units.
        tolerance: Option<Field<f64>>,
    },
    /// `shape = "subdivision"`: a subdivision surface.
    Subdivision {
        /// `base`: a built-in base mesh (`cube`, `tetrahedron`), or else `vertices` + `faces`.
        base: Option<Field<BaseMesh>>,
        /// `vertices` of the base mesh.
        vertices: Option<Field<Vec<Vec3>>>,
        /// `faces` of the base mesh: 0-based vertex indices, counter-clockwise.
        faces: Option<Field<Vec<Vec<u32>>>>,
        /// `scheme`: `catmull_clark` (default) or `loop`.
        scheme: Field<model::surface::subdivision::Scheme>,
        /// `levels` of refinement (default 3).
        levels: Field<u32>,
    },
    /// `shape = "teapot"`: the Utah teapot's 32 Bézier patches (y-up, on y = 0, 3.15 tall).
    Teapot {
        /// `tolerance`: chordal tolerance in scene units.
        tolerance: Option<Field<f64>>,
    },
    /// `shape = "implicit"`: the zero set of a signed distance expression, by marching cubes.
    Implicit {
        /// `sdf`: the expression (see docs/scene-format.md), already checked.
        sdf: Field<model::implicit::Sdf>,
        /// `resolution`: marching-cubes cells along the longest side of the solid's bounds.
        resolution: Field<u32>,
    },
    /// `shape = "csg"`: a Boolean tree of closed operands.
    Csg {
        /// `op`: `union`, `intersection` or `difference` (the first minus all others).
        op: Field<model::csg::CsgOp>,
        /// `operands`, each a shape table with an optional `transform`.
        operands: Field<Vec<OperandDesc>>,
    },
    /// `shape = "instance"`: another object's shape again, with this object's transform.
    Instance {
        /// `of`: the name of the object whose shape is reused.
        of: Field<String>,
    },
    /// `shape = "luminaire"`, `"point"`, `"spot"` or `"directional"`: a luminaire
    /// ([`crate::scene::luminaire`]), no polygon.
    Luminaire(LuminaireDesc),
}

/// A luminaire's keys.
#[derive(Clone, Debug, PartialEq)]
pub struct LuminaireDesc {
    /// What gives its distribution of intensity.
    pub light: LightDesc,
    /// `position` (none for a directional light: the origin, unused).
    pub position: Field<Vec3>,
    /// `aim`: the direction of the photometric nadir, or the direction a directional light's
    /// rays travel (default −y).
    pub aim: Field<Vec3>,
    /// `rotation`: degrees about the aim (default 0).
    pub rotation: Field<f64>,
    /// `multiplier`: the light-loss factor (default 1).
    pub multiplier: Field<f64>,
    /// `colour`: a tint, scaled to luminance 1 (default white).
    pub colour: Option<Field<Rgb>>,
}

/// Where a luminaire's distribution of intensity comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum LightDesc {
    /// `shape = "luminaire"`: `file`, an IES LM-63 or EULUMDAT file relative to the scene, and
    /// `opening`: whether the light leaves from the luminous opening the file declares
    /// (default false: from the position alone).
    File(Field<PathBuf>, Field<bool>),
    /// `shape = "point"`: the same intensity every way.
    Point(Strength),
    /// `shape = "spot"`: a cone.
    Spot {
        /// Its intensity on the axis, or its flux.
        strength: Strength,
        /// `cone`: the half-angle of the edge, degrees (default 30).
        cone: Field<f64>,
        /// `beam`: the half-angle of the full intensity, degrees (default ¾ of the cone).
        beam: Option<Field<f64>>,
    },
    /// `shape = "directional"`: parallel light of `illuminance` (lx) on a plane facing it.
    Directional(Field<f64>),
}

/// How strong a shorthand light is: exactly one of `intensity` (cd) and `flux` (lm).
#[derive(Clone, Debug, PartialEq)]
pub enum Strength {
    /// `intensity`, cd (W/sr per channel).
    Intensity(Field<f64>),
    /// `flux`, lm (W per channel).
    Flux(Field<f64>),
}

/// A built-in base mesh of a subdivision surface (`base = "…"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BaseMesh {
    /// `cube`: the unit cube centred at the origin.
    Cube,
    /// `tetrahedron`: the regular tetrahedron on four corners of that cube.
    Tetrahedron,
}

/// One operand of a `csg` shape.
#[derive(Clone, Debug, PartialEq)]
pub struct OperandDesc {
    /// Where the operand's table starts.
    pub pos: Pos,
    /// Its key path (`objects[2].operands[1]`).
    pub key: String,
    /// Its `transform`.
    pub transform: Option<TransformDesc>,
    /// Its shape.
    pub shape: ShapeDesc,
}
