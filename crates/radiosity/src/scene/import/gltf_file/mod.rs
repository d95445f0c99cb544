//! glTF 2.0 import (`.gltf` with its buffers, or binary `.glb`), through the `gltf` crate.
//!
//! What is read (Khronos glTF 2.0 specification, §3.5 "Geometry", §3.9 "Materials"):
//!
//! - every node of the default scene (else the first, else every root node), with its world
//!   transform M = M_root · … · M_node (column-major 4×4); a mirroring transform (det M < 0)
//!   reverses the triangles so that fronts stay fronts;
//! - triangle primitives (`TRIANGLES`, `TRIANGLE_STRIP`, `TRIANGLE_FAN`), indexed or not; points
//!   and lines are skipped with a warning;
//! - materials: reflectance ρ = `baseColorFactor` (RGB; clamped to [`MAX_REFLECTANCE`] with a
//!   warning, since ρ ≥ 1 would create energy); emitted radiance
//!   L_e = `emissiveFactor` × `KHR_materials_emissive_strength`; `doubleSided` → two-sided.
//!   A `baseColorTexture` multiplies the factor, over `TEXCOORD_0` (`textures.rs`); emissive
//!   textures are ignored (with a warning);
//! - `COLOR_0` per vertex, kept for round trips (white where absent, as the specification says);
//! - perspective cameras: the eye at M·(0,0,0), looking down M's −z with M's +y up, `yfov` as the
//!   vertical field of view. Orthographic cameras are skipped with a warning;
//! - `KHR_lights_punctual` lights as luminaires ([`crate::scene::luminaire`]): a point or a
//!   spot shines `intensity` (cd) × `color` from M·(0,0,0), a spot along M's −z with its
//!   `innerConeAngle` and `outerConeAngle` and the extension's falloff, and `range` is left out
//!   (light falls as 1/r² to any distance); a directional light's rays travel along M's −z with
//!   the illuminance `intensity` (lx) × `color` on a plane facing them.
//!
//! An object is named after its node (else its mesh, else `node{i}`); nodes that share a name
//! are one object. Buffers are the GLB binary chunk, `data:` URIs (base64) or files relative to
//! the `.gltf` file.
//!
//! The result is a [`GltfFile`]: an indexed polygon mesh in the same form as an OBJ file
//! ([`ObjFile`]), so the scene builder treats both alike. [`crate::Scene::load`] takes `.gltf`
//! and `.glb` files as whole scenes, and a scene's `mesh` objects may name them.
//!
//! ```
//! use std::path::Path;
//! // A minimal glTF: one triangle, positions in a base64 data URI, no material.
//! let json = r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}],
//!   "nodes": [{"name": "tri", "mesh": 0}],
//!   "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
//!   "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
//!                  "min": [0, 0, 0], "max": [1, 1, 0]}],
//!   "bufferViews": [{"buffer": 0, "byteLength": 36}],
//!   "buffers": [{"byteLength": 36, "uri":
//!     "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]}"#;
//! let g = radiosity::scene::import::gltf_file::parse_gltf(json.as_bytes(), Path::new("tri.gltf"))?;
//! assert_eq!((g.mesh.faces.len(), g.mesh.groups[0].as_str()), (1, "tri"));
//! # Ok::<(), radiosity::scene::SceneError>(())
//! ```

use std::path::Path;

use glam::{Mat4, Vec2, Vec3};
use gltf::mesh::Mode;

use super::obj::{ObjFace, ObjFile};
use crate::scene::luminaire::{isotropic, spot, Falloff, Luminaire};
use crate::scene::{Camera, Material, SceneError};
use crate::Rgb;

mod buffers;
mod error;
mod textures;

use buffers::load_buffers;
use error::gltf_error;

use crate::scene::MAX_REFLECTANCE;

/// An imported glTF file.
#[derive(Clone, Debug, Default)]
pub struct GltfFile {
    /// World-space positions, faces (triangles), object names (`groups`), materials and
    /// warnings.
    pub mesh: ObjFile,
    /// `COLOR_0` per vertex of [`GltfFile::mesh`] (linear RGB; white where absent).
    pub colours: Vec<Rgb>,
    /// Perspective cameras, in node order.
    pub cameras: Vec<Camera>,
    /// `KHR_lights_punctual` point and spot lights, in node order.
    pub luminaires: Vec<Luminaire>,
}

/// Reads a `.gltf` or `.glb` file.
///
/// # Errors
/// The file or one of its buffers cannot be read, or it is not valid glTF 2.0. The error names
/// the file, and where the problem is: `file:LINE:COL` for a JSON syntax or type error in a
/// `.gltf` (columns count characters), `JSON chunk line L col C` in the message for one in a
/// `.glb`, and the JSON path as the key (`accessors[0].bufferView`) for a validation error.
pub fn read_gltf(path: &Path) -> Result<GltfFile, SceneError> {
    let bytes =
        std::fs::read(path).map_err(|e| SceneError::in_file(path, format!("cannot read: {e}")))?;
    parse_gltf(&bytes, path)
}

/// Parses glTF from memory; `file` names it in messages and locates external buffers.
///
/// # Errors
/// As [`read_gltf`].
pub fn parse_gltf(bytes: &[u8], file: &Path) -> Result<GltfFile, SceneError> {
    let err = |m: String| SceneError::in_file(file, m);
    // The `gltf` crate subtracts the 12-byte header from the GLB's declared length unchecked
    // (an overflow panic in debug builds), so a shorter declared length is refused first.
    if let Some(length) = bytes
        .strip_prefix(b"glTF")
        .and_then(|rest| rest.get(4..8))
        .map(|l| u32::from_le_bytes([l[0], l[1], l[2], l[3]]))
        .filter(|&l| l < 12)
    {
        return Err(err(format!(
            "invalid glTF: the GLB header declares {length} bytes, fewer than the header's 12"
        )));
    }
    let invalid = |e: gltf::Error| gltf_error(e, bytes, file);
    let gltf = gltf::Gltf::from_slice_without_validation(bytes).map_err(invalid)?;
    // Validation in `gltf-json` 1.4 indexes the accessors with a primitive's POSITION index
    // unchecked (a panic), so that index is checked before the document is validated.
    let json = gltf.document.as_json();
    let positions = gltf::json::validation::Checked::Valid(gltf::json::mesh::Semantic::Positions);
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(a) = primitive
                .attributes
                .get(&positions)
                .filter(|a| a.value() >= json.accessors.len())
            {
                return Err(err(format!(
                    "invalid glTF: POSITION accessor {} does not exist",
                    a.value()
                ))
                .with_key(format!("meshes[{m}].primitives[{p}].attributes.POSITION")));
            }
        }
    }
    let gltf = gltf::Gltf {
        document: gltf::Document::from_json(gltf.document.into_json()).map_err(invalid)?,
        blob: gltf.blob,
    };
    let buffers = load_buffers(&gltf, file)?;
    let doc = &gltf.document;
    let mut out = GltfFile::default();

    // Materials: the glTF ones in order, then the default material (for primitives without one).
    let mut clamped = Vec::new();
    let mut images = textures::Images::default();
    for m in doc.materials() {
        let name = m.name().map_or_else(
            || format!("material{}", out.mesh.materials.len()),
            str::to_string,
        );
        if m.emissive_texture().is_some() {
            out.mesh.warnings.push(format!(
                "{}: material `{name}`: the emissive texture is ignored; its factor is used",
                file.display()
            ));
        }
        let mut material = material(&m, &name, &mut clamped);
        images.apply(&m, &mut material, &buffers, file, &mut out.mesh.warnings);
        out.mesh.materials.push(material);
    }
    let default_material = out.mesh.materials.len();
    out.mesh.materials.push(Material {
        name: "default".into(),
        reflectance: Rgb::splat(MAX_REFLECTANCE),
        ..Material::default()
    });
    if !clamped.is_empty() {
        out.mesh.warnings.push(format!(
            "{}: base colour ≥ {MAX_REFLECTANCE} clamped to {MAX_REFLECTANCE} (a reflectance must stay below 1) in material(s): {}",
            file.display(),
            clamped.join(", ")
        ));
    }
    out.mesh.groups.clear();

    // Nodes from the roots down, with their world transforms.
    let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    is_child[c.index()] = true;
                }
            }
            doc.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    let mut stack: Vec<(gltf::Node, Mat4)> =
        roots.into_iter().map(|n| (n, Mat4::IDENTITY)).collect();
    stack.reverse();
    let mut skipped_modes = 0usize;
    let mut depth_guard = 0usize;
    let mut used_default = false;
    while let Some((node, parent)) = stack.pop() {
        // Validation rejects cycles; the guard keeps a bad file from looping anyway.
        depth_guard += 1;
        if depth_guard > 16 * doc.nodes().len() + 16 {
            return Err(err("the node hierarchy is not a tree".into()));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(camera) = node.camera() {
            match camera.projection() {
                gltf::camera::Projection::Perspective(p) => {
                    let name = camera
                        .name()
                        .or(node.name())
                        .map_or_else(|| format!("camera{}", out.cameras.len()), str::to_string);
                    out.cameras.push(Camera {
                        name,
                        eye: world.transform_point3(Vec3::ZERO),
                        target: world.transform_point3(Vec3::ZERO)
                            + world.transform_vector3(-Vec3::Z),
                        up: world.transform_vector3(Vec3::Y),
                        fov_y: p.yfov().to_degrees(),
                    });
                }
                gltf::camera::Projection::Orthographic(_) => out.mesh.warnings.push(format!(
                    "{}: node {}: orthographic camera skipped",
                    file.display(),
                    node.index()
                )),
            }
        }
        if let Some(light) = node.light() {
            out.luminaires.extend(luminaire(&light, &node, world));
        }
        if let Some(mesh) = node.mesh() {
            let name = node
                .name()
                .or(mesh.name())
                .map_or_else(|| format!("node{}", node.index()), str::to_string);
            let group = match out.mesh.groups.iter().position(|g| *g == name) {
                Some(i) => i,
                None => {
                    out.mesh.groups.push(name);
                    out.mesh.groups.len() - 1
                }
            };
            let mirrors = world.determinant() < 0.0;
            for primitive in mesh.primitives() {
                let key = |what: &str| {
                    let what = if what == "indices" {
                        what.to_string()
                    } else {
                        format!("attributes.{what}")
                    };
                    format!(
                        "meshes[{}].primitives[{}].{what}",
                        mesh.index(),
                        primitive.index()
                    )
                };
                // The `gltf` reader panics (`unreachable!`) on accessor types that the glTF
                // specification forbids for these attributes and that its validation lets by.
                if let Some(what) = bad_accessor_type(&primitive) {
                    return Err(err(format!(
                        "invalid glTF: the {what} accessor has a type glTF does not allow"
                    ))
                    .with_key(key(what)));
                }
                let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
                let Some(positions) = reader.read_positions() else {
                    continue;
                };
                let base = out.mesh.positions.len() as u32;
                out.mesh
                    .positions
                    .extend(positions.map(|p| world.transform_point3(Vec3::from_array(p))));
                let count = out.mesh.positions.len() - base as usize;
                let uv_base = out.mesh.texcoords.len() as u32;
                let has_uv = match reader.read_tex_coords(0) {
                    Some(uv) => {
                        let uv = uv.into_f32().map(Vec2::from_array);
                        out.mesh
                            .texcoords
                            .extend(uv.chain(std::iter::repeat(Vec2::ZERO)).take(count));
                        true
                    }
                    None => false,
                };
                match reader.read_colors(0) {
                    Some(c) => out.colours.extend(
                        c.into_rgb_f32()
                            .map(|c| Vec3::from_array(c).as_dvec3())
                            .chain(std::iter::repeat(Rgb::ONE))
                            .take(count),
                    ),
                    None => out.colours.extend(std::iter::repeat_n(Rgb::ONE, count)),
                }
                let indices: Vec<u32> = match reader.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..count as u32).collect(),
                };
                if let Some(i) = indices.iter().find(|&&i| i as usize >= count) {
                    return Err(err(format!(
                        "index {i} is out of range: the primitive has {count} vertices"
                    ))
                    .with_key(key("indices")));
                }
                let material = primitive.material().index().unwrap_or_else(|| {
                    used_default = true;
                    default_material
                });
                let Some(triangles) = triangles(primitive.mode(), &indices) else {
                    skipped_modes += 1;
                    continue;
                };
                for mut t in triangles {
                    if mirrors {
                        t.swap(1, 2);
                    }
                    if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                        continue;
                    }
                    out.mesh.faces.push(ObjFace {
                        indices: t.map(|i| base + i).to_vec(),
                        uv: has_uv.then(|| t.map(|i| uv_base + i).to_vec()),
                        group,
                        material,
                        line: 0,
                    });
                }
            }
        }
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child, world));
        }
    }
    if used_default {
        out.mesh.warnings.push(format!(
            "{}: primitives without a material use a grey default (ρ = {MAX_REFLECTANCE})",
            file.display()
        ));
    }
    if skipped_modes > 0 {
        out.mesh.warnings.push(format!(
            "{}: skipped {skipped_modes} point or line primitive(s)",
            file.display()
        ));
    }
    Ok(out)
}

/// A `KHR_lights_punctual` light at the node whose world transform is `world`, as a luminaire
/// (module docs); `None` when the transform leaves it no direction.
fn luminaire(
    light: &gltf::khr_lights_punctual::Light,
    node: &gltf::Node,
    world: Mat4,
) -> Option<Luminaire> {
    use gltf::khr_lights_punctual::Kind;
    let name = light
        .name()
        .or(node.name())
        .map_or_else(|| format!("light{}", light.index()), str::to_string);
    let colour = Vec3::from_array(light.color()).as_dvec3().max(Rgb::ZERO);
    let strength = colour * f64::from(light.intensity().max(0.0));
    let forward = world.transform_vector3(-Vec3::Z).try_normalize();
    let (distribution, aim) = match light.kind() {
        Kind::Point => (isotropic(1.0), Vec3::NEG_Y),
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            let cone = f64::from(outer_cone_angle).to_degrees().clamp(1e-3, 90.0);
            let beam = f64::from(inner_cone_angle)
                .to_degrees()
                .clamp(0.0, cone * (1.0 - 1e-6));
            (spot(1.0, beam, cone, Falloff::SquaredCosineRamp), forward?)
        }
        Kind::Directional => {
            return Some(Luminaire::directional(&name, forward?, strength, 1.0));
        }
    };
    Some(Luminaire::new(
        &name,
        world.transform_point3(Vec3::ZERO),
        aim,
        0.0,
        std::sync::Arc::new(distribution),
        strength,
        1.0,
    ))
}

/// A glTF material as a radiosity material; its name is pushed to `clamped` when its base
/// colour had to be brought below 1.
fn material(m: &gltf::Material, name: &str, clamped: &mut Vec<String>) -> Material {
    let base = m.pbr_metallic_roughness().base_color_factor();
    let base = Rgb::new(f64::from(base[0]), f64::from(base[1]), f64::from(base[2]));
    if base.max_element() > MAX_REFLECTANCE {
        clamped.push(format!("`{name}`"));
    }
    let strength = f64::from(m.emissive_strength().unwrap_or(1.0));
    let emission = Vec3::from_array(m.emissive_factor()).as_dvec3() * strength;
    Material {
        name: name.to_string(),
        reflectance: base.clamp(Rgb::ZERO, Rgb::splat(MAX_REFLECTANCE)),
        emission: emission.max(Rgb::ZERO),
        two_sided: m.double_sided(),
        ..Material::default()
    }
}

/// The triangles of a primitive's index list, or `None` for points and lines.
fn triangles(mode: Mode, indices: &[u32]) -> Option<Vec<[u32; 3]>> {
    let n = indices.len();
    Some(match mode {
        Mode::Triangles => indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect(),
        // Every other strip triangle is flipped back to the strip's winding (§3.7.2.1).
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .map(|i| {
                let (a, b, c) = (indices[i], indices[i + 1], indices[i + 2]);
                if i % 2 == 0 {
                    [a, b, c]
                } else {
                    [b, a, c]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..n.saturating_sub(1))
            .map(|i| [indices[0], indices[i], indices[i + 1]])
            .collect(),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => return None,
    })
}

/// The attribute of `primitive` whose accessor has a type that glTF 2.0 (§3.7.2.1) forbids for
/// it, if any: POSITION must be float VEC3, indices unsigned-integer SCALAR, COLOR_0 VEC3 or
/// VEC4 and TEXCOORD_0 VEC2 of float or normalised unsigned bytes or shorts.
fn bad_accessor_type(primitive: &gltf::Primitive) -> Option<&'static str> {
    use gltf::accessor::{DataType as D, Dimensions as T};
    let bad = |a: Option<gltf::Accessor>, ok: &dyn Fn(D, T) -> bool| {
        a.is_some_and(|a| !ok(a.data_type(), a.dimensions()))
    };
    if bad(primitive.get(&gltf::Semantic::Positions), &|d, t| {
        matches!((d, t), (D::F32, T::Vec3))
    }) {
        Some("POSITION")
    } else if bad(primitive.indices(), &|d, t| {
        matches!((d, t), (D::U8 | D::U16 | D::U32, T::Scalar))
    }) {
        Some("indices")
    } else if bad(primitive.get(&gltf::Semantic::Colors(0)), &|d, t| {
        matches!((d, t), (D::U8 | D::U16 | D::F32, T::Vec3 | T::Vec4))
    }) {
        Some("COLOR_0")
    } else if bad(primitive.get(&gltf::Semantic::TexCoords(0)), &|d, t| {
        matches!((d, t), (D::U8 | D::U16 | D::F32, T::Vec2))
    }) {
        Some("TEXCOORD_0")
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::buffers::{decode_base64, percent_decode};
    use super::error::char_column;
    use super::*;

    /// A `.gltf` with one triangle in a data URI, under a node that translates by (0, 0, −2)
    /// and mirrors x, a red half-reflective two-sided emitter of strength 5, and a camera.
    fn sample() -> String {
        // Positions (0,0,0), (1,0,0), (0,1,0) as little-endian f32.
        let floats = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let bytes: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
        let b64 = encode_base64(&bytes);
        format!(
            r#"{{
  "asset": {{"version": "2.0"}},
  "extensionsUsed": ["KHR_materials_emissive_strength"],
  "scene": 0,
  "scenes": [{{"nodes": [0, 2]}}],
  "nodes": [
    {{"name": "parent", "translation": [0, 0, -2], "children": [1]}},
    {{"name": "tri", "mesh": 0, "scale": [-1, 1, 1]}},
    {{"name": "cam", "camera": 0, "translation": [0, 1, 5]}}
  ],
  "cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.5, "znear": 0.1}}}}],
  "meshes": [{{"name": "m", "primitives": [{{"attributes": {{"POSITION": 0}}, "material": 0}}]}}],
  "materials": [{{"name": "lamp", "doubleSided": true,
    "pbrMetallicRoughness": {{"baseColorFactor": [0.5, 1.0, 0.25, 1.0]}},
    "emissiveFactor": [1.0, 0.5, 0.0],
    "extensions": {{"KHR_materials_emissive_strength": {{"emissiveStrength": 5.0}}}}}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
    "min": [0, 0, 0], "max": [1, 1, 0]}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
  "buffers": [{{"byteLength": 36, "uri": "data:application/octet-stream;base64,{b64}"}}]
}}"#
        )
    }

    fn encode_base64(bytes: &[u8]) -> String {
        const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut s = String::new();
        for chunk in bytes.chunks(3) {
            let b = [
                chunk[0],
                *chunk.get(1).unwrap_or(&0),
                *chunk.get(2).unwrap_or(&0),
            ];
            let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
            for k in 0..4 {
                if k <= chunk.len() {
                    s.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
                } else {
                    s.push('=');
                }
            }
        }
        s
    }

    /// A file that requires `KHR_lights_punctual` (Blender's exporter with its lamps) loads;
    /// its point, spot and directional lights at nodes become luminaires.
    #[test]
    fn punctual_lights_become_luminaires() {
        let with_lights = sample()
            .replacen(
                r#""extensionsUsed": ["KHR_materials_emissive_strength"],"#,
                r#""extensionsUsed": ["KHR_materials_emissive_strength", "KHR_lights_punctual"],
  "extensionsRequired": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"type": "point", "intensity": 100},
    {"type": "spot", "intensity": 50, "spot": {"outerConeAngle": 0.5}},
    {"type": "point", "color": [1, 0.5, 0.5]},
    {"type": "directional", "intensity": 1000}]}},"#,
                1,
            )
            .replacen(r#""nodes": [0, 2]"#, r#""nodes": [0, 2, 3, 4, 5]"#, 1)
            .replacen(
                r#"{"name": "cam", "camera": 0, "translation": [0, 1, 5]}"#,
                r#"{"name": "cam", "camera": 0, "translation": [0, 1, 5]},
    {"name": "bulb", "translation": [0, 3, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"name": "down", "translation": [1, 3, 0], "rotation": [-0.70710678, 0, 0, 0.70710678],
     "extensions": {"KHR_lights_punctual": {"light": 1}}},
    {"name": "sun", "extensions": {"KHR_lights_punctual": {"light": 3}}}"#,
                1,
            );
        let g = parse_gltf(with_lights.as_bytes(), Path::new("t.gltf")).expect("loads");
        assert_eq!(g.mesh.faces.len(), 1);
        assert_eq!(g.luminaires.len(), 3);
        // 100 cd 3 m over the origin: 100 / 9 lx.
        let bulb = &g.luminaires[0];
        assert_eq!(bulb.name, "bulb");
        let e = bulb.irradiance(Vec3::ZERO, Vec3::Y).x;
        assert!((e - 100.0 / 9.0).abs() < 1e-5, "{e}");
        // The spot, turned to look down −y: 50 cd on its axis, dark beyond 0.5 rad.
        let spot = &g.luminaires[1];
        assert!((spot.intensity(Vec3::NEG_Y).x - 50.0).abs() < 1e-3);
        assert_eq!(spot.intensity(Vec3::new(0.7, -1.0, 0.0)).x, 0.0);
        // The sun, unturned, sends 1000 lx down its node's −z: full on a face turned to +z,
        // cos 60° of it on one turned 60° away, nothing behind.
        let sun = &g.luminaires[2];
        assert_eq!((sun.name.as_str(), sun.position()), ("sun", None));
        assert!((sun.irradiance(Vec3::ZERO, Vec3::Z).x - 1000.0).abs() < 1e-6);
        let tilted = Vec3::new(0.0, 0.75f32.sqrt(), 0.5);
        assert!((sun.irradiance(Vec3::ONE, tilted).x - 500.0).abs() < 1e-3);
        assert_eq!(sun.irradiance(Vec3::ZERO, Vec3::NEG_Z), Rgb::ZERO);
        assert!(
            !g.mesh.warnings.iter().any(|w| w.contains("KHR_lights")),
            "{:?}",
            g.mesh.warnings
        );
        let g = parse_gltf(sample().as_bytes(), Path::new("t.gltf")).expect("valid");
        assert!(g.luminaires.is_empty());
    }

    #[test]
    fn transforms_materials_and_cameras_are_read() {
        let g = parse_gltf(sample().as_bytes(), Path::new("t.gltf")).expect("valid");
        // Mirrored by scale −1 in x, then moved to z = −2: (0,0,−2), (−1,0,−2), (0,1,−2),
        // with the winding reversed so the face still points the way it did (+z).
        assert_eq!(g.mesh.faces.len(), 1);
        let corners = g.mesh.faces[0].positions(&g.mesh);
        assert_eq!(
            corners,
            [
                Vec3::new(0.0, 0.0, -2.0),
                Vec3::new(0.0, 1.0, -2.0),
                Vec3::new(-1.0, 0.0, -2.0)
            ]
        );
        let n = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        assert!(n.z > 0.0, "front must stay +z: {n}");
        assert_eq!(g.mesh.groups, ["tri"]);
        let m = &g.mesh.materials[g.mesh.faces[0].material];
        assert_eq!(m.name, "lamp");
        assert_eq!(m.reflectance, Rgb::new(0.5, MAX_REFLECTANCE, 0.25));
        assert_eq!(m.emission, Rgb::new(5.0, 2.5, 0.0));
        assert!(m.two_sided);
        assert!(
            g.mesh.warnings.iter().any(|w| w.contains("clamped")),
            "{:?}",
            g.mesh.warnings
        );
        assert_eq!(g.colours, vec![Rgb::ONE; 3]);
        let c = &g.cameras[0];
        assert_eq!(c.name, "cam");
        assert_eq!(c.eye, Vec3::new(0.0, 1.0, 5.0));
        assert_eq!(c.target, Vec3::new(0.0, 1.0, 4.0));
        assert!((c.fov_y - 0.5f32.to_degrees()).abs() < 1e-4);
    }

    #[test]
    fn strips_and_fans_keep_their_winding() {
        // Strip 0 1 2 3: triangles (0 1 2) and (2 1 3); fan 0 1 2 3: (0 1 2) and (0 2 3).
        assert_eq!(
            triangles(Mode::TriangleStrip, &[0, 1, 2, 3]),
            Some(vec![[0, 1, 2], [2, 1, 3]])
        );
        assert_eq!(
            triangles(Mode::TriangleFan, &[0, 1, 2, 3]),
            Some(vec![[0, 1, 2], [0, 2, 3]])
        );
        assert_eq!(triangles(Mode::Lines, &[0, 1]), None);
    }

    #[test]
    fn base64_and_percent_decoding() {
        for s in ["", "a", "ab", "abc", "abcd", "hello world!"] {
            assert_eq!(
                decode_base64(&encode_base64(s.as_bytes())).as_deref(),
                Some(s.as_bytes())
            );
        }
        assert_eq!(decode_base64("a*b"), None);
        assert_eq!(percent_decode("my%20mesh.bin"), "my mesh.bin");
        assert_eq!(percent_decode("100%"), "100%");
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        // The last: a GLB header declaring a total length of 0 (found by the `gltf` fuzz target).
        let glb_length_zero = "glTF\u{2}\0\0\0\0\0\0\0\u{7f}\0\0\0JSON{\"asset\":";
        for bad in [
            "",
            "{",
            "{\"asset\":{}}",
            "glTF\u{2}\0\0\0",
            glb_length_zero,
        ] {
            assert!(
                parse_gltf(bad.as_bytes(), Path::new("x.glb")).is_err(),
                "{bad:?}"
            );
        }
        // A POSITION accessor index past the accessors (found by the `gltf` fuzz target).
        let missing = sample().replace("\"POSITION\": 0", "\"POSITION\": 7");
        let e = parse_gltf(missing.as_bytes(), Path::new("x.gltf")).expect_err("bad accessor");
        assert!(e.to_string().contains("POSITION accessor 7"), "{e}");
        assert_eq!(
            e.key.as_deref(),
            Some("meshes[0].primitives[0].attributes.POSITION")
        );
        // Float indices (found by the `gltf` fuzz target: `unreachable!` in the reader).
        let float_indices = sample().replace(
            "\"attributes\": {\"POSITION\": 0}",
            "\"attributes\": {\"POSITION\": 0}, \"indices\": 0",
        );
        let e = parse_gltf(float_indices.as_bytes(), Path::new("x.gltf")).expect_err("indices");
        assert!(e.to_string().contains("indices accessor"), "{e}");
        assert_eq!(e.key.as_deref(), Some("meshes[0].primitives[0].indices"));
        let short = sample().replace("\"byteLength\": 36, \"uri\"", "\"byteLength\": 48, \"uri\"");
        let e = parse_gltf(short.as_bytes(), Path::new("x.gltf")).expect_err("short buffer");
        assert!(e.to_string().contains("x.gltf"), "{e}");
    }

    #[test]
    fn json_errors_name_the_line_and_column_in_characters() {
        // The comma after `"2.0"` is missing: `serde_json` stops at the `"` of `"scene"`,
        // line 3, character 3.
        let text = "{\n  \"asset\": {\"version\": \"2.0\"}\n  \"scene\": 0\n}";
        let e = parse_gltf(text.as_bytes(), Path::new("s.gltf")).expect_err("syntax");
        assert_eq!(
            e.to_string(),
            "s.gltf:3:3: invalid glTF: expected `,` or `}`"
        );
        // Columns count characters: `é` is two bytes but one column, so the `5` where a key
        // should be is character 22 of line 1 (byte 23).
        let text = "{\"asset\": {\"x\": \"é\", 5}}";
        let e = parse_gltf(text.as_bytes(), Path::new("u.gltf")).expect_err("key");
        assert_eq!(e.loc().map(|l| (l.line, l.col)), Some((1, 22)), "{e}");
        assert!(e.message.contains("key must be a string"), "{e}");
        // A type error inside a valid JSON text is located too.
        let text = sample().replace("\"count\": 3", "\"count\": \"three\"");
        let line = 1 + text[..text.find("\"three\"").unwrap()]
            .matches('\n')
            .count();
        let e = parse_gltf(text.as_bytes(), Path::new("t.gltf")).expect_err("type");
        assert_eq!(e.line_col.map(|(l, _)| l), Some(line), "{e}");
        assert!(
            e.message.starts_with("invalid glTF: invalid type: string"),
            "{e}"
        );
        // Empty input: the end of line 1.
        let e = parse_gltf(b"", Path::new("e.gltf")).expect_err("empty");
        assert_eq!(e.line_col, Some((1, 1)), "{e}");
    }

    #[test]
    fn glb_json_errors_are_located_in_the_json_chunk() {
        let json = b"{\"asset\": {\"version\": \"2.0\"},\n \"nodes\": [}";
        let mut glb = b"glTF".to_vec();
        glb.extend_from_slice(&2u32.to_le_bytes());
        glb.extend_from_slice(&(20 + json.len() as u32).to_le_bytes());
        glb.extend_from_slice(&(json.len() as u32).to_le_bytes());
        glb.extend_from_slice(b"JSON");
        glb.extend_from_slice(json);
        let e = parse_gltf(&glb, Path::new("b.glb")).expect_err("syntax");
        assert_eq!(
            e.to_string(),
            "b.glb: invalid glTF: JSON chunk line 2 col 12: expected value"
        );
    }

    #[test]
    fn validation_errors_name_the_json_path() {
        let bad_view = sample().replace("\"bufferView\": 0", "\"bufferView\": 3");
        let e = parse_gltf(bad_view.as_bytes(), Path::new("v.gltf")).expect_err("index");
        assert_eq!(
            e.to_string(),
            "v.gltf: `accessors[0].bufferView`: invalid glTF: index out of bounds"
        );
        // Attribute keys are written as fields, as in the scene files' key paths.
        let bad_colour = sample().replace(
            "\"attributes\": {\"POSITION\": 0}",
            "\"attributes\": {\"POSITION\": 0, \"COLOR_0\": 9}",
        );
        let e = parse_gltf(bad_colour.as_bytes(), Path::new("c.gltf")).expect_err("colour");
        assert_eq!(
            e.key.as_deref(),
            Some("meshes[0].primitives[0].attributes.COLOR_0"),
            "{e}"
        );
    }

    #[test]
    fn char_columns_count_characters_not_bytes() {
        let text = "ab\nxé€z".as_bytes();
        // Bytes of line 2: x(1) é(2,3) €(4,5,6) z(7).
        assert_eq!(
            [1, 3, 6, 7, 99].map(|b| char_column(text, 2, b)),
            [1, 2, 3, 4, 4]
        );
        assert_eq!((char_column(text, 1, 0), char_column(text, 5, 3)), (1, 1));
    }
}
