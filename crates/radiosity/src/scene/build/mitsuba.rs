//! A Mitsuba scene file built into a [`Scene`]: every shape's polygons under its `to_world`,
//! with the material its BSDF and area emitter make (see [`crate::scene::import::mitsuba`]).
//!
//! Shapes take the name of their `id`, else of their mesh file's stem, else `{type}{n}`;
//! shapes that share a name are one object. Materials are shared by shapes with the same BSDF
//! and emission. A transparent BSDF (glass, `null`) leaves its shape out, but an emitting
//! shape stays, reflecting nothing. The first `perspective` sensor is the default camera and its
//! film's size the default image size; distant emitters enclose the scene
//! ([`Scene::add_environment`]).

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use glam::{Mat4, Vec3};
use model::Transform;

use super::{Builder, Material, Polygon, RenderDefaults, Scene, SceneError};
use crate::scene::import::mitsuba::bsdf::{self, Mapper, Surface};
use crate::scene::import::mitsuba::xml::{self, resolve, Class, Object};
use crate::scene::import::mitsuba::{self as mi, shapes};
use crate::scene::import::{obj, ply};
use crate::Rgb;

impl Scene {
    /// A Mitsuba 3 or 0.6 scene file (module docs).
    ///
    /// # Errors
    /// The file or a mesh or texture it names cannot be read, or an element is unknown or
    /// malformed; located to `file:line:col` and the element.
    pub fn from_mitsuba_file(path: &Path) -> Result<Self, SceneError> {
        let doc = xml::read(path)?;
        let version6 = doc.version.starts_with("0.");
        let mut b = Builder::new(path);
        let mut walk = Walk {
            mapper: Mapper::default(),
            materials: HashMap::new(),
            shapes: 0,
            left_out: 0,
        };
        let mut cameras = Vec::new();
        let mut render = RenderDefaults::default();
        let mut environments = Vec::new();
        let mut ignored_sensors = 0;
        for o in &doc.objects {
            match o.class {
                Class::Shape if o.kind == "shapegroup" => {}
                Class::Shape => walk.shape(&mut b, o, Mat4::IDENTITY)?,
                Class::Emitter => {
                    let name =
                        o.id.clone()
                            .unwrap_or_else(|| format!("{}{}", o.kind, b.scene.luminaires.len()));
                    match mi::luminaire(o, &name)? {
                        Some(l) => b.scene.luminaires.push(l),
                        None => environments.push(mi::environment(o, version6)?),
                    }
                }
                Class::Sensor => {
                    if cameras.is_empty() && matches!(o.kind.as_str(), "perspective" | "thinlens") {
                        let (camera, size) = mi::camera(o, "default")?;
                        cameras.push(camera);
                        render = size;
                    } else {
                        ignored_sensors += 1;
                    }
                }
                Class::Bsdf | Class::Texture | Class::Film | Class::Other => {}
            }
        }
        if ignored_sensors > 0 {
            b.scene.warnings.push(format!(
                "{}: {ignored_sensors} sensor(s) besides the first perspective one ignored",
                path.display()
            ));
        }
        b.scene
            .warnings
            .extend(bsdf::warning(&walk.mapper.approximated));
        if walk.left_out > 0 {
            b.scene.warnings.push(format!(
                "{}: {} transparent shape(s) (glass, null BSDF) left out: radiosity lets their light through",
                path.display(),
                walk.left_out
            ));
        }
        if !environments.is_empty() {
            b.scene.cameras.clone_from(&cameras);
            for env in &environments {
                b.scene.add_environment(env)?;
            }
        }
        b.finish(cameras, render)
    }
}

/// The state of one walk over the file's shapes.
struct Walk {
    mapper: Mapper,
    /// (BSDF identity, emission bits) → material index.
    materials: HashMap<(usize, [u64; 3]), usize>,
    /// Shapes seen, for `{type}{n}` names.
    shapes: usize,
    /// Transparent shapes left out.
    left_out: usize,
}

impl Walk {
    /// One shape (or an instance of a group) under the parent transform `parent`.
    fn shape(&mut self, b: &mut Builder, o: &Object, parent: Mat4) -> Result<(), SceneError> {
        self.shapes += 1;
        let to_world = parent * o.transform("to_world")?;
        if o.kind == "instance" {
            let group = o
                .children(Class::Shape)
                .next()
                .cloned()
                .ok_or_else(|| o.error("an instance needs a <ref> to a shapegroup"))?;
            if group.kind != "shapegroup" {
                return Err(o.error("an instance refers to a shapegroup"));
            }
            for member in group.children(Class::Shape) {
                self.shape(b, member, to_world)?;
            }
            return Ok(());
        }
        let emission = match o.children(Class::Emitter).next() {
            Some(e) => mi::area_radiance(e)?,
            None => Rgb::ZERO,
        };
        let bsdf = o.children(Class::Bsdf).next();
        let surface = match bsdf {
            Some(bsdf) => self.mapper.surface(bsdf)?,
            None => Surface::Diffuse {
                reflectance: Rgb::splat(0.5),
                two_sided: false,
            },
        };
        let (reflectance, two_sided) = match surface {
            Surface::Diffuse {
                reflectance,
                two_sided,
            } => (reflectance, two_sided),
            Surface::Transparent if emission.max_element() > 0.0 => (Rgb::ZERO, false),
            Surface::Transparent => {
                self.left_out += 1;
                return Ok(());
            }
        };
        let faces = self.faces(o)?;
        let name = o.id.clone().unwrap_or_else(|| {
            o.string("filename")
                .ok()
                .flatten()
                .and_then(|f| Path::new(f).file_stem().and_then(|s| s.to_str()))
                .map_or_else(|| format!("{}{}", o.kind, self.shapes), str::to_string)
        });
        let object = b.object(&name);
        let key = (
            bsdf.map_or(0, |a| Arc::as_ptr(a) as usize),
            emission.to_array().map(f64::to_bits),
        );
        let material = *self.materials.entry(key).or_insert_with(|| {
            let label = bsdf
                .and_then(|a| a.id.clone())
                .unwrap_or_else(|| bsdf.map_or("default".into(), |a| a.kind.clone()));
            b.scene.materials.push(Material {
                name: if emission.max_element() > 0.0 {
                    format!("{label} (emitting)")
                } else {
                    label
                },
                reflectance,
                emission,
                two_sided,
                ..Material::default()
            });
            b.scene.materials.len() - 1
        });
        let t = Transform::from_mat4(to_world);
        let flip = o.boolean("flip_normals", false)? != t.mirrors();
        let label = format!("{}:{}: {}", o.loc.file.display(), o.loc.line, o.key());
        let placed = faces.into_iter().map(|f| {
            let mut vs: Vec<Vec3> = f.into_iter().map(|p| t.point(p)).collect();
            if flip {
                vs.reverse();
            }
            let face = Polygon {
                vertices: vs,
                material,
                object,
                uv: None,
            };
            (face, None)
        });
        b.add_faces(placed, &label);
        Ok(())
    }

    /// The shape's polygons in its object space.
    fn faces(&self, o: &Object) -> Result<Vec<Vec<Vec3>>, SceneError> {
        let kind = o.kind.as_str();
        Ok(match kind {
            "obj" | "ply" => {
                let name = o
                    .string("filename")?
                    .ok_or_else(|| o.error("needs `filename`"))?;
                let path = resolve(&o.loc, name);
                if !path.is_file() {
                    return Err(o.error(format!("cannot read mesh `{}`", path.display())));
                }
                let mesh = if kind == "obj" {
                    let text = std::fs::read_to_string(&path).map_err(|e| {
                        o.error(format!("cannot read mesh `{}`: {e}", path.display()))
                    })?;
                    obj::parse_obj(&text, &path)?
                } else {
                    ply::read_ply(&path)?
                };
                mesh.faces.iter().map(|f| f.positions(&mesh)).collect()
            }
            "rectangle" => shapes::rectangle(),
            "cube" => shapes::cube(),
            "disk" => shapes::disk(),
            "sphere" => {
                let radius = o.float("radius", 1.0)? as f32;
                shapes::sphere(o.vector("center", Vec3::ZERO)?, radius)
            }
            "cylinder" => {
                let p0 = o.vector("p0", Vec3::ZERO)?;
                let p1 = o.vector("p1", Vec3::Z)?;
                let radius = o.float("radius", 1.0)? as f32;
                shapes::cylinder(p0, p1, radius)
                    .ok_or_else(|| o.error("a cylinder needs p0 ≠ p1 and a positive radius"))?
            }
            "serialized" => {
                return Err(o.error(
                    "Mitsuba's serialized meshes are not read: export the mesh as PLY or OBJ",
                ))
            }
            "hair" | "heightfield" | "bsplinecurve" | "linearcurve" | "sdfgrid" | "ellipsoids"
            | "ellipsoidsmesh" | "merge" => {
                return Err(o.error(format!(
                    "`{kind}` shapes are not read: they have no polygons for radiosity"
                )))
            }
            _ => return Err(o.error(format!("unknown shape plugin `{kind}`"))),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(xml: &str) -> Result<Scene, SceneError> {
        let dir = std::env::temp_dir().join(format!(
            "radiosity-mitsuba-{}-{}",
            std::process::id(),
            xml.len()
        ));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("scene.xml");
        std::fs::write(&path, xml).unwrap();
        std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        let scene = Scene::load(&path);
        std::fs::remove_dir_all(&dir).ok();
        scene
    }

    #[test]
    fn a_lit_box_of_rectangles_with_a_camera() {
        let s = load(
            r#"<scene version="3.0.0">
              <bsdf type="twosided" id="white"><bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></bsdf>
              <sensor type="perspective"><float name="fov" value="40"/><string name="fov_axis" value="y"/>
                <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
                <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="32"/></film></sensor>
              <shape type="cube" id="room"><ref id="white"/><boolean name="flip_normals" value="true"/>
                <transform name="to_world"><scale value="2"/></transform></shape>
              <shape type="rectangle" id="lamp"><transform name="to_world"><rotate x="1" angle="90"/><translate y="1.9"/></transform>
                <emitter type="area"><rgb name="radiance" value="10"/></emitter></shape>
              <shape type="obj"><string name="filename" value="tri.obj"/><bsdf type="dielectric"/></shape>
            </scene>"#,
        )
        .unwrap();
        assert!(!s.name.is_empty());
        assert_eq!(s.polygons.len(), 6 + 1);
        assert_eq!((s.render.width, s.render.height), (64, 32));
        assert!((s.cameras[0].fov_y - 40.0).abs() < 1e-4);
        // The flipped cube faces inward: every face's normal points at the centre.
        let room = s.objects.iter().position(|o| o.name == "room").unwrap();
        for p in s.polygons.iter().filter(|p| p.object == room) {
            let n = model::polymesh::vector_area(&p.vertices);
            assert!(n.dot(-p.vertices[0]) > 0.0);
            assert!(
                (n.length() - 16.0).abs() < 1e-4,
                "2 × 2 scaled faces: area 16"
            );
        }
        // The lamp, rotated +90° about x, faces down (its +z goes to −y).
        let lamp = s
            .polygons
            .iter()
            .find(|p| s.materials[p.material].is_emitter())
            .unwrap();
        assert!(model::polymesh::vector_area(&lamp.vertices).y < 0.0);
        assert!(
            s.warnings
                .iter()
                .any(|w| w.contains("transparent shape(s)")),
            "{:?}",
            s.warnings
        );
    }

    #[test]
    fn unknown_shapes_are_located_errors() {
        let e = load("<scene version=\"3.0.0\">\n<shape type=\"torus\"/></scene>").unwrap_err();
        assert_eq!(e.line_col, Some((2, 1)));
        assert!(
            e.to_string().contains("unknown shape plugin `torus`"),
            "{e}"
        );
        let e = load("<scene version=\"3.0.0\"><shape type=\"obj\"><string name=\"filename\" value=\"none.obj\"/></shape></scene>")
            .unwrap_err();
        assert!(e.message.contains("none.obj"), "{e}");
    }

    #[test]
    fn an_instance_places_its_group_again() {
        let s = load(
            r#"<scene version="3.0.0">
              <shape type="shapegroup" id="g"><shape type="rectangle" id="tile">
                <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape></shape>
              <shape type="instance"><ref id="g"/><transform name="to_world"><translate x="5"/></transform></shape>
              <shape type="instance"><ref id="g"/><transform name="to_world"><translate x="-5"/></transform></shape>
            </scene>"#,
        )
        .unwrap();
        let xs: Vec<f32> = s.polygons.iter().map(|p| p.vertices[0].x).collect();
        assert_eq!(xs, vec![4.0, -6.0]);
    }
}
