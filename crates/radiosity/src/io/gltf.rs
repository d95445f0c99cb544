//! Binary glTF 2.0 (`.glb`) export of the lit mesh (Khronos glTF 2.0 specification, §4.4
//! "GLB File Format Specification").
//!
//! A `.glb` is a 12-byte header (`glTF`, version 2, total length) and two chunks, each a length,
//! a type and a payload padded to 4 bytes: the JSON scene description (padded with spaces) and
//! the binary buffer (padded with zeros).
//!
//! The lit mesh becomes one node and one mesh per scene object (named after it, objects without
//! triangles left out), each with its own vertices (so its `POSITION` bounds are its own, which
//! viewers such as three.js use for culling and framing; vertices on the seam between two objects
//! are written once for each) in three vertex accessors:
//!
//! - `POSITION`: float VEC3, in metres (glTF's unit: scene coordinates times
//!   [`Placement::metres_per_unit`]), with its bounds as the specification requires;
//! - `COLOR_0`: float VEC3, the vertex radiance L = B/π, chosen by [`VertexColours`]: exposed
//!   (by a given exposure or the automatic one,
//!   [`auto_exposure`](crate::render::tonemap::auto_exposure), Reinhard et al. 2002) and
//!   clamped to [0, 1], or linear, scaled so that the brightest vertex is 1. glTF colours are
//!   linear; viewers apply the sRGB encoding themselves;
//! - `_RADIOSITY`: float VEC3, radiosity B in W·m⁻² (linear, unscaled) — an application-specific
//!   attribute (leading underscore), ignored by viewers, for tools that want the physics.
//!
//! The scene's cameras follow as perspective cameras on nodes of their own, the first the
//! default (a glTF camera looks down its local −z with +y up; [`camera_node`]), so Blender and
//! three.js open the file seen as the scene file sees it.
//!
//! The single material is unlit (`KHR_materials_unlit`), white and one-sided, so a viewer shows
//! `COLOR_0` as it is: the light is already in the colours. Two-sided surfaces carry reversed
//! twin triangles in the lit mesh, so their backs show too.

use std::f64::consts::PI;
use std::io;
use std::path::Path;

use glam::Vec3;
use serde_json::{json, Value};

use super::atomic::write_atomic;
use crate::mesh::LitMesh;
use crate::render::tonemap::{auto_exposure, exposure_scale};
use crate::render::Image;
use crate::scene::enclosure::box_around;
use crate::scene::Camera;

/// glTF `componentType` of `f32`.
pub(super) const FLOAT: u32 = 5126;
/// glTF `componentType` of `u32`.
pub(super) const UNSIGNED_INT: u32 = 5125;
/// glTF buffer-view target of vertex attributes.
pub(super) const ARRAY_BUFFER: u32 = 34962;
/// glTF buffer-view target of indices.
pub(super) const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// What `COLOR_0` holds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum VertexColours {
    /// Radiance exposed by the automatic exposure, clamped to [0, 1] (the default).
    #[default]
    AutoExposure,
    /// Radiance × 2^stops, clamped to [0, 1].
    Exposure(f32),
    /// Radiance L = B/π divided by the largest channel of any vertex, so the brightest is 1:
    /// linear, not tone-mapped, nothing clipped (glTF requires colours in [0, 1]). The
    /// absolute values are in `_RADIOSITY`.
    Linear,
}

/// The `COLOR_0` values of `lit`'s vertices under `mode`.
#[must_use]
pub fn vertex_colours(lit: &LitMesh, mode: VertexColours) -> Vec<Vec3> {
    let radiance = Image {
        width: lit.positions.len() as u32,
        height: 1,
        pixels: (0..lit.positions.len())
            .map(|i| lit.radiosity.get(i).copied().unwrap_or_default() / PI)
            .collect(),
    };
    let scale = match mode {
        VertexColours::AutoExposure => exposure_scale(auto_exposure(&radiance)),
        VertexColours::Exposure(stops) => exposure_scale(stops),
        VertexColours::Linear => {
            let max = radiance
                .pixels
                .iter()
                .map(|l| l.max_element())
                .filter(|m| m.is_finite())
                .fold(0.0, f64::max);
            if max > 0.0 {
                1.0 / max
            } else {
                1.0
            }
        }
    };
    radiance
        .pixels
        .iter()
        .map(|&l| {
            (l * scale)
                .clamp(glam::DVec3::ZERO, glam::DVec3::ONE)
                .as_vec3()
        })
        .collect()
}

/// Where an export sits in the world: the scene's length unit and its cameras.
#[derive(Clone, Copy, Debug)]
pub struct Placement<'a> {
    /// Metres per scene unit ([`crate::scene::units::Units::metres`]).
    pub metres_per_unit: f64,
    /// Cameras to carry, the first the default.
    pub cameras: &'a [Camera],
    /// Width over height of the image the cameras frame.
    pub aspect: f32,
}

impl Default for Placement<'_> {
    /// Metres, no cameras, square images.
    fn default() -> Self {
        Self {
            metres_per_unit: 1.0,
            cameras: &[],
            aspect: 1.0,
        }
    }
}

/// Writes `lit` as a binary glTF file at `path` (atomically). `object_names[i]` names the
/// triangles whose object index is `i`; triangles of unnamed objects are grouped as `object i`.
///
/// # Errors
/// I/O errors, and `InvalidInput` when a triangle refers to a missing vertex or the file would
/// exceed the 4 GiB that GLB lengths can describe.
pub fn write_glb(
    path: &Path,
    lit: &LitMesh,
    object_names: &[String],
    colours: VertexColours,
    placement: &Placement,
) -> io::Result<()> {
    let bytes = encode(lit, object_names, colours, placement)?;
    write_atomic(path, |w| w.write_all(&bytes))
}

/// The node of a perspective camera at `index` among the file's cameras, in metres: its
/// rotation turns glTF's camera frame (looking down −z, +y up) onto the camera's view.
pub(super) fn camera_node(camera: &Camera, index: usize, metres: f32) -> Value {
    let forward = (camera.target - camera.eye).normalize_or_zero();
    let right = forward.cross(camera.up).normalize_or_zero();
    let up = right.cross(forward);
    let rotation = if right == Vec3::ZERO || forward == Vec3::ZERO {
        glam::Quat::IDENTITY
    } else {
        glam::Quat::from_mat3(&glam::Mat3::from_cols(right, up, -forward)).normalize()
    };
    json!({
        "name": camera.name,
        "camera": index,
        "translation": (camera.eye * metres).to_array(),
        "rotation": rotation.to_array(),
    })
}

/// The whole `.glb` file in memory.
fn encode(
    lit: &LitMesh,
    object_names: &[String],
    mode: VertexColours,
    placement: &Placement,
) -> io::Result<Vec<u8>> {
    let metres = placement.metres_per_unit as f32;
    let invalid = |m: &str| io::Error::new(io::ErrorKind::InvalidInput, m.to_string());
    let n = lit.positions.len();
    if lit.triangles.iter().flatten().any(|&v| v as usize >= n) {
        return Err(invalid("triangle refers to a missing vertex"));
    }

    // Triangles grouped by object, in object order, keeping mesh order within each.
    let groups = group_by_object(lit);

    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut push_view = |bin: &mut Vec<u8>, data: &[u8], target: u32| -> usize {
        views.push(json!({
            "buffer": 0, "byteOffset": bin.len(), "byteLength": data.len(), "target": target
        }));
        bin.extend_from_slice(data);
        views.len() - 1
    };

    let mut meshes = Vec::new();
    let mut nodes = Vec::new();
    if n > 0 && !lit.triangles.is_empty() {
        let radiosity = |i: usize| lit.radiosity.get(i).copied().unwrap_or_default();
        let colours = vertex_colours(lit, mode);
        let b: Vec<Vec3> = (0..n).map(|i| radiosity(i).as_vec3()).collect();
        // Each object's own vertices (its local index of every lit-mesh vertex it uses).
        let mut local = vec![u32::MAX; n];
        for (object, triangles) in &groups {
            let mut used: Vec<usize> = Vec::new();
            let indices: Vec<u8> = triangles
                .iter()
                .flat_map(|&t| lit.triangles[t])
                .map(|v| {
                    let v = v as usize;
                    if local[v] == u32::MAX {
                        local[v] = used.len() as u32;
                        used.push(v);
                    }
                    local[v]
                })
                .flat_map(u32::to_le_bytes)
                .collect();
            let pick = |data: &[Vec3]| -> Vec<Vec3> { used.iter().map(|&v| data[v]).collect() };
            let positions: Vec<Vec3> = pick(&lit.positions)
                .into_iter()
                .map(|p| p * metres)
                .collect();
            let (lo, hi) = box_around(positions.iter().copied()).unwrap_or_default();
            let mut attributes = serde_json::Map::new();
            for (name, data, bounds) in [
                ("POSITION", positions, Some((lo, hi))),
                ("COLOR_0", pick(&colours), None),
                ("_RADIOSITY", pick(&b), None),
            ] {
                let view = push_view(&mut bin, &vec3_bytes(&data), ARRAY_BUFFER);
                let mut accessor = json!({
                    "bufferView": view, "componentType": FLOAT, "count": used.len(),
                    "type": "VEC3", "name": name
                });
                if let Some((lo, hi)) = bounds {
                    accessor["min"] = json!(lo.to_array());
                    accessor["max"] = json!(hi.to_array());
                }
                accessors.push(accessor);
                attributes.insert(name.into(), json!(accessors.len() - 1));
            }
            for &v in &used {
                local[v] = u32::MAX;
            }
            let view = push_view(&mut bin, &indices, ELEMENT_ARRAY_BUFFER);
            accessors.push(json!({
                "bufferView": view, "componentType": UNSIGNED_INT,
                "count": triangles.len() * 3, "type": "SCALAR"
            }));
            let name = object_names
                .get(*object as usize)
                .cloned()
                .unwrap_or_else(|| format!("object {object}"));
            meshes.push(json!({
                "name": name,
                "primitives": [{
                    "attributes": attributes,
                    "indices": accessors.len() - 1,
                    "material": 0,
                    "mode": 4
                }]
            }));
            nodes.push(json!({ "name": name, "mesh": meshes.len() - 1 }));
        }
    }

    let cameras = cameras(placement, &mut nodes);
    let mut doc = json!({
        "asset": { "version": "2.0", "generator": "radiosity" },
        "scene": 0,
        "scenes": [{ "nodes": (0..nodes.len()).collect::<Vec<_>>() }],
        "nodes": nodes,
        "extensionsUsed": ["KHR_materials_unlit"],
        "materials": [{
            "name": "radiosity",
            "pbrMetallicRoughness": {
                "baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 1.0
            },
            "extensions": { "KHR_materials_unlit": {} }
        }],
    });
    if !cameras.is_empty() {
        doc["cameras"] = Value::Array(cameras);
    }
    if !meshes.is_empty() {
        doc["meshes"] = Value::Array(meshes);
        doc["accessors"] = Value::Array(accessors);
        doc["bufferViews"] = Value::Array(views);
        doc["buffers"] = json!([{ "byteLength": bin.len() }]);
    }

    glb(&doc, bin)
}

/// The placement's cameras as glTF perspective cameras, their nodes pushed onto `nodes`.
pub(super) fn cameras(placement: &Placement, nodes: &mut Vec<Value>) -> Vec<Value> {
    let metres = placement.metres_per_unit as f32;
    let mut cameras = Vec::new();
    for (i, camera) in placement.cameras.iter().enumerate() {
        cameras.push(json!({
            "name": camera.name,
            "type": "perspective",
            "perspective": {
                "yfov": camera.fov_y.to_radians(),
                "aspectRatio": placement.aspect,
                "znear": 0.01,
            }
        }));
        nodes.push(camera_node(camera, i, metres));
    }
    cameras
}

/// The `.glb` container of the JSON document `doc` and the binary buffer `bin` (§4.4).
///
/// # Errors
/// `InvalidInput` when the file would exceed the 4 GiB that GLB lengths can describe.
pub(super) fn glb(doc: &Value, mut bin: Vec<u8>) -> io::Result<Vec<u8>> {
    let invalid = |m: &str| io::Error::new(io::ErrorKind::InvalidInput, m.to_string());
    let mut json_chunk = serde_json::to_vec(doc).map_err(io::Error::other)?;
    pad(&mut json_chunk, b' ');
    pad(&mut bin, 0);
    let mut total = 12 + 8 + json_chunk.len();
    if !bin.is_empty() {
        total += 8 + bin.len();
    }
    let total = u32::try_from(total).map_err(|_| invalid("mesh too large for a .glb file"))?;
    let mut out = Vec::with_capacity(total as usize);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total.to_le_bytes());
    for (kind, data) in [(b"JSON", &json_chunk), (b"BIN\0", &bin)] {
        if data.is_empty() {
            continue;
        }
        out.extend_from_slice(&(data.len() as u32).to_le_bytes());
        out.extend_from_slice(kind);
        out.extend_from_slice(data);
    }
    Ok(out)
}

/// Triangle indices per object index, objects in increasing order.
fn group_by_object(lit: &LitMesh) -> Vec<(u32, Vec<usize>)> {
    let mut groups: std::collections::BTreeMap<u32, Vec<usize>> = Default::default();
    for t in 0..lit.triangles.len() {
        let object = lit.triangle_object.get(t).copied().unwrap_or(u32::MAX);
        groups.entry(object).or_default().push(t);
    }
    groups.into_iter().collect()
}

/// Little-endian bytes of a list of vectors.
pub(super) fn vec3_bytes(data: &[Vec3]) -> Vec<u8> {
    data.iter()
        .flat_map(|v| v.to_array())
        .flat_map(f32::to_le_bytes)
        .collect()
}

/// Pads `data` with `byte` to a multiple of 4 bytes.
pub(super) fn pad(data: &mut Vec<u8>, byte: u8) {
    while !data.len().is_multiple_of(4) {
        data.push(byte);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Rgb;

    /// A unit square in two triangles of objects 1 and 0; radiosity π at vertex 0 only.
    fn square() -> LitMesh {
        LitMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 2.0, 0.0), Vec3::Y],
            radiosity: vec![Rgb::splat(PI), Rgb::ZERO, Rgb::ZERO, Rgb::new(0.0, PI, 0.0)],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            triangle_patch: vec![0, 0],
            has_back_twin: vec![false, false],
            triangle_object: vec![1, 0],
        }
    }

    fn u32_at(b: &[u8], o: usize) -> u32 {
        u32::from_le_bytes(b[o..o + 4].try_into().expect("4 bytes"))
    }

    /// Splits a GLB into its JSON document and binary chunk, checking the framing.
    fn parse(glb: &[u8]) -> (Value, Vec<u8>) {
        assert_eq!(&glb[..4], b"glTF");
        assert_eq!(u32_at(glb, 4), 2);
        assert_eq!(u32_at(glb, 8) as usize, glb.len());
        let json_len = u32_at(glb, 12) as usize;
        assert_eq!(&glb[16..20], b"JSON");
        assert_eq!(json_len % 4, 0);
        let doc: Value = serde_json::from_slice(&glb[20..20 + json_len]).expect("json");
        let rest = &glb[20 + json_len..];
        if rest.is_empty() {
            return (doc, Vec::new());
        }
        let bin_len = u32_at(rest, 0) as usize;
        assert_eq!(&rest[4..8], b"BIN\0");
        assert_eq!(bin_len % 4, 0);
        assert_eq!(rest.len(), 8 + bin_len);
        (doc, rest[8..].to_vec())
    }

    #[test]
    fn framing_accessors_and_object_meshes_are_consistent() {
        let names = vec!["floor".to_string(), "wall".to_string()];
        let (doc, bin) = parse(
            &encode(
                &square(),
                &names,
                VertexColours::AutoExposure,
                &Placement::default(),
            )
            .expect("encode"),
        );
        assert_eq!(
            doc["buffers"][0]["byteLength"].as_u64(),
            Some(bin.len() as u64)
        );
        // One mesh per object, in object order: floor holds triangle 1, wall triangle 0.
        assert_eq!(doc["meshes"][0]["name"], "floor");
        assert_eq!(doc["meshes"][1]["name"], "wall");
        assert_eq!(doc["nodes"].as_array().map(Vec::len), Some(2));
        let accessor = |i: u64| &doc["accessors"][i as usize];
        let view_bytes = |a: &Value| -> Vec<u8> {
            let v = &doc["bufferViews"][a["bufferView"].as_u64().expect("view") as usize];
            let o = v["byteOffset"].as_u64().expect("offset") as usize;
            let l = v["byteLength"].as_u64().expect("length") as usize;
            bin[o..o + l].to_vec()
        };
        let floor = &doc["meshes"][0]["primitives"][0];
        let indices = accessor(floor["indices"].as_u64().expect("indices"));
        let idx: Vec<u32> = view_bytes(indices)
            .chunks(4)
            .map(|c| u32_at(c, 0))
            .collect();
        // The floor's own vertices: lit-mesh vertices 0, 2, 3 in order of first use.
        assert_eq!(idx, [0, 1, 2]);
        // POSITION bounds are required, exact, and the object's own: the floor's triangle
        // (0,0)-(1,2)-(0,1), not the whole mesh's (which reaches x = 1 at y = 0 too).
        let attribute = |name: &str| accessor(floor["attributes"][name].as_u64().expect(name));
        let pos = attribute("POSITION");
        assert_eq!(pos["min"], json!([0.0, 0.0, 0.0]));
        assert_eq!(pos["max"], json!([1.0, 2.0, 0.0]));
        assert_eq!(view_bytes(pos).len(), 3 * 12);
        let wall = &doc["meshes"][1]["primitives"][0];
        let wall_pos = accessor(wall["attributes"]["POSITION"].as_u64().expect("position"));
        assert_eq!(wall_pos["min"], json!([0.0, 0.0, 0.0]));
        assert_eq!(wall_pos["max"], json!([1.0, 2.0, 0.0]));
        assert_ne!(wall_pos["bufferView"], pos["bufferView"]);
        // COLOR_0 within [0, 1]; _RADIOSITY keeps B: π at vertex 0 (the floor's first).
        let colour = view_bytes(attribute("COLOR_0"));
        let floats: Vec<f32> = colour
            .chunks(4)
            .map(|c| f32::from_le_bytes(c.try_into().expect("4")))
            .collect();
        assert!(floats.iter().all(|c| (0.0..=1.0).contains(c)), "{floats:?}");
        assert!(floats[0] > 0.0 && floats[3] == 0.0);
        let b = view_bytes(attribute("_RADIOSITY"));
        assert_eq!(f32::from_le_bytes(b[..4].try_into().expect("4")), PI as f32);
    }

    #[test]
    fn empty_mesh_is_a_valid_empty_scene() {
        let (doc, bin) = parse(
            &encode(
                &LitMesh::default(),
                &[],
                VertexColours::AutoExposure,
                &Placement::default(),
            )
            .expect("encode"),
        );
        assert!(bin.is_empty());
        assert_eq!(doc["nodes"], json!([]));
        assert!(doc.get("accessors").is_none());
    }

    #[test]
    fn dangling_index_is_an_error() {
        let mut lit = square();
        lit.triangles[0][1] = 7;
        assert_eq!(
            encode(&lit, &[], VertexColours::Linear, &Placement::default())
                .map_err(|e| e.kind())
                .err(),
            Some(io::ErrorKind::InvalidInput)
        );
    }
}
