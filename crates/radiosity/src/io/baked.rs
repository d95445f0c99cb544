//! A bake as binary glTF: the surfaces with their light in textures ([`crate::bake`]).
//!
//! One node and one mesh per scene object (named after it), one primitive of the object's
//! charted faces, every vertex with
//!
//! - `POSITION` in metres (glTF's unit) and `NORMAL` (the face's, flat);
//! - `TEXCOORD_0` and `TEXCOORD_1`, both the vertex's place in the light-map atlas (one
//!   accessor): the first for the baked base colour, the second where engines look for a
//!   light map (three.js's `lightMap` reads `uv1`, Bevy's `Lightmap` the second UV set).
//!
//! Two textures over that atlas, both sampled bilinearly without mipmaps (`minFilter`
//! `LINEAR`): a mip level averages each chart's edge with the empty atlas or the chart beside
//! it past the 2-texel gutter, which a viewer that builds mipmaps (three.js) shows as dark
//! lines along the chart seams of surfaces seen at a slant (`benches/bake/`):
//!
//! - the **fully baked** picture: the radiance L = B/π, exposed (automatically, as the picture
//!   is) and sRGB-encoded, the base colour of the one material, unlit
//!   (`KHR_materials_unlit`), so three.js, Blender, Babylon.js and `<model-viewer>` show it as
//!   it is;
//! - the **light map**: the irradiance H (module docs of [`crate::bake`]) in the RGBM encoding
//!   (value = rgb · a · range, bytes stored linear; range a power of 2 above the brightest
//!   texel), referenced from the material's `extras.lightmap` with its `texCoord` (1) and
//!   `range`, for engines that multiply it with their own albedo. The same irradiance in full
//!   floating point goes beside the file as OpenEXR (`<name>.lightmap.exr`, [`lightmap_path`],
//!   [`write_lightmap`]).
//!
//! The distant light's enclosure (the default sky, an environment's far cube) is not charted:
//! it comes as one more mesh, `distant light`, unlit, each polygon coloured by `COLOR_0` with
//! its emitted radiance exposed as the picture is, so a window shows the sky it shows in our
//! render.
//!
//! A two-sided polygon has a chart for each side; its two layers are the same triangles facing
//! opposite ways, each moved [`LAYER_GAP`] along its own normal so that a renderer that does not
//! cull back faces (Cycles) meets the layer that faces it first, and one that does (three.js,
//! the glTF default for a one-sided material) draws each from its own side.

use std::io;
use std::path::{Path, PathBuf};

use glam::{DVec2, Vec2, Vec3};
use serde_json::{json, Value};

use super::atomic::write_atomic;
use super::gltf::{
    cameras, glb, pad, vec3_bytes, Placement, ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER, FLOAT,
    UNSIGNED_INT,
};
use super::image_file::write_image;
use crate::bake::Baked;
use crate::mesh::triangulate::triangulate;
use crate::render::{tonemap, Image};
use crate::scene::enclosure::box_around;
use crate::{Rgb, Scene};

/// glTF's (OpenGL's) `LINEAR` texture filter: bilinear, no mipmaps.
const LINEAR: u32 = 9729;

/// How far each layer of a two-sided surface stands off its plane, metres.
pub const LAYER_GAP: f32 = 1e-4;

/// The OpenEXR light map written beside `path`: `<stem>.lightmap.exr`.
#[must_use]
pub fn lightmap_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!("{stem}.lightmap.exr"))
}

/// Writes `baked` (a bake of `scene`) as a `.glb` at `path` (atomically), naming `lightmap`
/// (the OpenEXR file's name, beside it) in its material.
///
/// # Errors
/// I/O errors, and `InvalidInput` when the file would exceed 4 GiB.
pub fn write_baked(
    path: &Path,
    scene: &Scene,
    baked: &Baked,
    placement: &Placement,
    lightmap: &str,
) -> io::Result<()> {
    let bytes = encode(scene, baked, placement, lightmap)?;
    write_atomic(path, |w| w.write_all(&bytes))
}

/// Writes the bake's irradiance as OpenEXR at `path` (atomically).
///
/// # Errors
/// I/O errors.
pub fn write_lightmap(path: &Path, baked: &Baked) -> io::Result<()> {
    write_image(path, &baked.irradiance, 0.0).map_err(io::Error::other)
}

/// A vertex of the baked mesh.
struct Vertex {
    position: Vec3,
    normal: Vec3,
    uv: Vec2,
}

/// The whole `.glb` in memory; `exr` is the light map's file name, named in the material.
fn encode(scene: &Scene, baked: &Baked, placement: &Placement, exr: &str) -> io::Result<Vec<u8>> {
    let metres = placement.metres_per_unit as f32;
    let (width, height) = baked.atlas.size;
    let size = DVec2::new(f64::from(width), f64::from(height));
    // Per object: its vertices and triangles.
    let mut objects: Vec<(Vec<Vertex>, Vec<[u32; 3]>)> = (0..scene.objects.len())
        .map(|_| (Vec::new(), Vec::new()))
        .collect();
    for (c, chart) in baked.charts.iter().enumerate() {
        for (face, corners) in chart.faces.iter().zip(&chart.corners) {
            let polygon = &scene.polygons[face.polygon as usize];
            let two_sided = scene.materials[polygon.material].two_sided;
            let vertices = face.vertices(scene);
            let normal = face.normal(scene).as_vec3();
            let gap = if two_sided { LAYER_GAP / metres } else { 0.0 };
            let (list, triangles) = &mut objects[polygon.object];
            let first = list.len() as u32;
            for (v, &q) in vertices.iter().zip(corners) {
                let uv = baked.atlas.texel(&baked.charts, c, q) / size;
                list.push(Vertex {
                    position: (*v + normal * gap) * metres,
                    normal,
                    uv: uv.as_vec2(),
                });
            }
            triangles.extend(
                triangulate(&vertices, normal)
                    .iter()
                    .map(|t| t.map(|i| first + i)),
            );
        }
    }

    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut view = |bin: &mut Vec<u8>, data: &[u8], target: Option<u32>| -> usize {
        let mut v = json!({ "buffer": 0, "byteOffset": bin.len(), "byteLength": data.len() });
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        bin.extend_from_slice(data);
        pad(bin, 0);
        views.push(v);
        views.len() - 1
    };
    let mut meshes = Vec::new();
    let mut nodes = Vec::new();
    for (o, (vertices, triangles)) in objects.iter().enumerate() {
        if triangles.is_empty() {
            continue;
        }
        let positions: Vec<Vec3> = vertices.iter().map(|v| v.position).collect();
        let (lo, hi) = box_around(positions.iter().copied()).unwrap_or_default();
        let normals: Vec<Vec3> = vertices.iter().map(|v| v.normal).collect();
        let uvs: Vec<u8> = vertices
            .iter()
            .flat_map(|v| v.uv.to_array())
            .flat_map(f32::to_le_bytes)
            .collect();
        let count = vertices.len();
        let p = view(&mut bin, &vec3_bytes(&positions), Some(ARRAY_BUFFER));
        accessors.push(
            json!({ "bufferView": p, "componentType": FLOAT, "count": count,
            "type": "VEC3", "min": lo.to_array(), "max": hi.to_array() }),
        );
        let n = view(&mut bin, &vec3_bytes(&normals), Some(ARRAY_BUFFER));
        accessors.push(
            json!({ "bufferView": n, "componentType": FLOAT, "count": count,
            "type": "VEC3" }),
        );
        let t = view(&mut bin, &uvs, Some(ARRAY_BUFFER));
        accessors.push(
            json!({ "bufferView": t, "componentType": FLOAT, "count": count,
            "type": "VEC2" }),
        );
        let indices: Vec<u8> = triangles
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let i = view(&mut bin, &indices, Some(ELEMENT_ARRAY_BUFFER));
        accessors.push(json!({ "bufferView": i, "componentType": UNSIGNED_INT,
            "count": triangles.len() * 3, "type": "SCALAR" }));
        let a = accessors.len();
        let name = &scene.objects[o].name;
        meshes.push(json!({
            "name": name,
            "primitives": [{
                "attributes": {
                    "POSITION": a - 4, "NORMAL": a - 3, "TEXCOORD_0": a - 2, "TEXCOORD_1": a - 2
                },
                "indices": a - 1,
                "material": 0,
                "mode": 4
            }]
        }));
        nodes.push(json!({ "name": name, "mesh": meshes.len() - 1 }));
    }
    let exposure = exposure(baked);
    let mut materials = vec![json!({
        "name": "baked",
        "pbrMetallicRoughness": {
            "baseColorTexture": { "index": 0, "texCoord": 0 },
            "metallicFactor": 0.0,
            "roughnessFactor": 1.0
        },
        "extensions": { "KHR_materials_unlit": {} },
        "extras": { "lightmap": {
            "texture": 1, "texCoord": 1, "encoding": "RGBM",
            "quantity": "irradiance, W/m² (lx for photometric lights)",
            "exr": exr,
            "exposure": exposure
        } }
    })];
    // The distant light's enclosure: its own mesh, each polygon its exposed radiance.
    let sky = distant(scene, exposure, metres);
    if !sky.0.is_empty() {
        let count = sky.0.len();
        let (lo, hi) = box_around(sky.0.iter().copied()).unwrap_or_default();
        let p = view(&mut bin, &vec3_bytes(&sky.0), Some(ARRAY_BUFFER));
        accessors.push(
            json!({ "bufferView": p, "componentType": FLOAT, "count": count,
            "type": "VEC3", "min": lo.to_array(), "max": hi.to_array() }),
        );
        let c = view(&mut bin, &vec3_bytes(&sky.1), Some(ARRAY_BUFFER));
        accessors.push(
            json!({ "bufferView": c, "componentType": FLOAT, "count": count,
            "type": "VEC3" }),
        );
        let a = accessors.len();
        materials.push(json!({
            "name": "distant light",
            "pbrMetallicRoughness": { "metallicFactor": 0.0, "roughnessFactor": 1.0 },
            "extensions": { "KHR_materials_unlit": {} }
        }));
        meshes.push(json!({
            "name": "distant light",
            "primitives": [{
                "attributes": { "POSITION": a - 2, "COLOR_0": a - 1 },
                "material": 1,
                "mode": 4
            }]
        }));
        nodes.push(json!({ "name": "distant light", "mesh": meshes.len() - 1 }));
    }
    let cameras = cameras(placement, &mut nodes);

    let scale = tonemap::exposure_scale(exposure);
    let picture = png(
        &baked.radiance,
        |l| {
            let [r, g, b] = tonemap::tonemap_pixel(l, scale);
            [r, g, b, 255]
        },
        true,
    )?;
    let range = range(&baked.irradiance);
    let lightmap = png(&baked.irradiance, |h| rgbm(h, range), false)?;
    let picture_view = view(&mut bin, &picture, None);
    let lightmap_view = view(&mut bin, &lightmap, None);
    let mut doc = json!({
        "asset": { "version": "2.0", "generator": "radiosity bake" },
        "scene": 0,
        "scenes": [{ "nodes": (0..nodes.len()).collect::<Vec<_>>() }],
        "nodes": nodes,
        "extensionsUsed": ["KHR_materials_unlit"],
        "samplers": [{ "magFilter": LINEAR, "minFilter": LINEAR, "wrapS": 33071, "wrapT": 33071 }],
        "images": [
            { "name": "baked", "bufferView": picture_view, "mimeType": "image/png" },
            { "name": "lightmap", "bufferView": lightmap_view, "mimeType": "image/png" }
        ],
        "textures": [{ "sampler": 0, "source": 0 }, { "sampler": 0, "source": 1 }],
    });
    doc["materials"] = Value::Array(materials);
    doc["materials"][0]["extras"]["lightmap"]["range"] = json!(range);
    if !cameras.is_empty() {
        doc["cameras"] = Value::Array(cameras);
    }
    if !meshes.is_empty() {
        doc["meshes"] = Value::Array(meshes);
        doc["accessors"] = Value::Array(accessors);
    }
    doc["bufferViews"] = Value::Array(views);
    doc["buffers"] = json!([{ "byteLength": bin.len() }]);
    glb(&doc, bin)
}

/// The triangles of the distant light's enclosure (the default sky, an environment's far
/// cube), in metres, and the colour of each corner: the polygon's emitted radiance exposed by
/// `exposure` stops, clamped to [0, 1] (linear, as glTF colours are).
fn distant(scene: &Scene, exposure: f32, metres: f32) -> (Vec<Vec3>, Vec<Vec3>) {
    let scale = tonemap::exposure_scale(exposure);
    let (mut positions, mut colours) = (Vec::new(), Vec::new());
    for p in &scene.polygons {
        let name = &scene.objects[p.object].name;
        if name != crate::scene::sky::NAME && name != crate::scene::environment::NAME {
            continue;
        }
        let material = &scene.materials[p.material];
        let colour = (material.emission * scale)
            .clamp(Rgb::ZERO, Rgb::ONE)
            .as_vec3();
        let n = crate::bake::chart::newell(&p.vertices).as_vec3();
        for t in triangulate(&p.vertices, n) {
            for i in t {
                positions.push(p.vertices[i as usize] * metres);
                colours.push(colour);
            }
        }
    }
    (positions, colours)
}

/// The exposure (stops) of the fully baked picture: the automatic one of the covered texels.
fn exposure(baked: &Baked) -> f32 {
    let pixels: Vec<Rgb> = baked
        .radiance
        .pixels
        .iter()
        .zip(&baked.covered)
        .filter(|(_, &c)| c)
        .map(|(&l, _)| l)
        .collect();
    let width = pixels.len() as u32;
    tonemap::auto_exposure(&Image {
        width,
        height: 1,
        pixels,
    })
}

/// The RGBM range: the least power of 2 at or above the brightest channel of any texel (1 for
/// a black map).
fn range(irradiance: &Image) -> f64 {
    let max = irradiance
        .pixels
        .iter()
        .map(|h| h.max_element())
        .filter(|m| m.is_finite())
        .fold(0.0, f64::max);
    if max > 0.0 {
        2f64.powi(max.log2().ceil() as i32)
    } else {
        1.0
    }
}

/// RGBM bytes of `h` over `range`: a = the largest channel over the range, rounded up to a
/// 255th (at least 1/255), and rgb = h / (a · range).
fn rgbm(h: Rgb, range: f64) -> [u8; 4] {
    let h = h.max(Rgb::ZERO);
    let a = (h.max_element() / range).clamp(1.0 / 255.0, 1.0);
    let a = (a * 255.0).ceil() / 255.0;
    let c = (h / (a * range)).clamp(Rgb::ZERO, Rgb::ONE);
    let byte = |x: f64| (x * 255.0).round() as u8;
    [byte(c.x), byte(c.y), byte(c.z), byte(a)]
}

/// An RGBA PNG of `image`, each pixel's bytes by `bytes` (with an sRGB chunk when `srgb`).
fn png(image: &Image, bytes: impl Fn(Rgb) -> [u8; 4], srgb: bool) -> io::Result<Vec<u8>> {
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, image.width, image.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        if srgb {
            encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        }
        let data: Vec<u8> = image.pixels.iter().flat_map(|&p| bytes(p)).collect();
        let mut writer = encoder.write_header().map_err(io::Error::other)?;
        writer.write_image_data(&data).map_err(io::Error::other)?;
        writer.finish().map_err(io::Error::other)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgbm_round_trips_within_its_steps() {
        let range = 8.0;
        for h in [
            Rgb::new(0.3, 2.0, 7.9),
            Rgb::new(0.01, 0.02, 0.0),
            Rgb::splat(8.0),
        ] {
            let [r, g, b, a] = rgbm(h, range);
            let back = Rgb::new(f64::from(r), f64::from(g), f64::from(b))
                * (f64::from(a) / 255.0 * range / 255.0);
            // A step of the colour bytes at the texel's own multiplier.
            let step = f64::from(a) / 255.0 * range / 255.0;
            assert!((back - h).abs().max_element() <= step, "{h} → {back}");
        }
        assert_eq!(range_of(&[Rgb::new(0.2, 5.0, 1.0)]), 8.0);
        assert_eq!(range_of(&[Rgb::ZERO]), 1.0);
    }

    fn range_of(pixels: &[Rgb]) -> f64 {
        range(&Image {
            width: pixels.len() as u32,
            height: 1,
            pixels: pixels.to_vec(),
        })
    }
}
