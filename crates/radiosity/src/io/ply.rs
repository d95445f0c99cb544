//! PLY export of the lit mesh (Turk 1994, "The PLY polygon file format").
//!
//! The file is `binary_little_endian 1.0` with two elements:
//!
//! ```text
//! element vertex N
//! property float x                 position, metres
//! property float y
//! property float z
//! property float radiosity_red     radiosity B, W·m⁻², linear (radiance is B/π)
//! property float radiosity_green
//! property float radiosity_blue
//! property uchar red               the same colour tone-mapped to 8-bit sRGB, for viewers
//! property uchar green
//! property uchar blue
//! element face M
//! property list uchar int vertex_indices   counter-clockwise seen from the lit front
//! property int object                      index into the `comment object` lines
//! ```
//!
//! Positions are in metres, as in the `.glb` export: scene units times the scene's `units`
//! (a millimetre model arrives at its real size), named by the header line `comment units
//! metres`, in the scene's own axes (the built-in scenes are right-handed and y-up).
//!
//! Object names survive as header lines `comment object <index> <name>` (control characters in a
//! name become spaces, so the header stays one line per comment).
//!
//! The 8-bit colours use the same exposure rule as the images
//! ([`auto_exposure`](crate::render::tonemap::auto_exposure), Reinhard et al. 2002), applied to
//! the vertex radiances L = B/π: their log-average luminance maps to middle grey, then the sRGB
//! transfer function encodes them. Viewers show these; the float properties keep the physics.

use std::f64::consts::PI;
use std::io::{self, Write};
use std::path::Path;

use super::atomic::write_atomic;
use crate::mesh::LitMesh;
use crate::render::tonemap::{auto_exposure, exposure_scale, tonemap_pixel};
use crate::render::Image;

/// Writes `lit` as a binary little-endian PLY file at `path` (atomically: the file appears
/// complete or not at all), its positions scaled by `metres_per_unit` into metres.
/// `object_names[i]` names the faces whose object index is `i`.
///
/// # Errors
/// I/O errors, and `InvalidInput` when the mesh has more vertices than an `int` index holds or
/// a triangle refers to a missing vertex.
pub fn write_ply(
    path: &Path,
    lit: &LitMesh,
    object_names: &[String],
    metres_per_unit: f64,
) -> io::Result<()> {
    check(lit)?;
    write_atomic(path, |out| {
        encode(out, lit, object_names, metres_per_unit as f32)
    })
}

/// Rejects meshes that the PLY `int` indices cannot describe.
fn check(lit: &LitMesh) -> io::Result<()> {
    let invalid = |m: &str| Err(io::Error::new(io::ErrorKind::InvalidInput, m.to_string()));
    if i32::try_from(lit.positions.len()).is_err() || i32::try_from(lit.triangles.len()).is_err() {
        return invalid("mesh too large for PLY int indices");
    }
    let n = lit.positions.len() as u32;
    if lit.triangles.iter().flatten().any(|&v| v >= n) {
        return invalid("triangle refers to a missing vertex");
    }
    Ok(())
}

/// Writes the header and the binary body.
fn encode(
    out: &mut dyn Write,
    lit: &LitMesh,
    object_names: &[String],
    metres: f32,
) -> io::Result<()> {
    let mut header = String::from("ply\nformat binary_little_endian 1.0\n");
    header.push_str("comment units metres\n");
    header
        .push_str("comment radiosity lit mesh: radiosity_* = B in W/m^2 (linear, radiance B/pi)\n");
    header.push_str("comment red green blue = B/pi auto-exposed, sRGB 8-bit\n");
    for (i, name) in object_names.iter().enumerate() {
        let clean: String = name
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect();
        header.push_str(&format!("comment object {i} {clean}\n"));
    }
    header.push_str(&format!("element vertex {}\n", lit.positions.len()));
    for p in [
        "x",
        "y",
        "z",
        "radiosity_red",
        "radiosity_green",
        "radiosity_blue",
    ] {
        header.push_str(&format!("property float {p}\n"));
    }
    for p in ["red", "green", "blue"] {
        header.push_str(&format!("property uchar {p}\n"));
    }
    header.push_str(&format!("element face {}\n", lit.triangles.len()));
    header.push_str("property list uchar int vertex_indices\nproperty int object\nend_header\n");
    out.write_all(header.as_bytes())?;

    let radiance = Image {
        width: lit.positions.len() as u32,
        height: 1,
        pixels: lit.radiosity.iter().map(|&b| b / PI).collect(),
    };
    let scale = exposure_scale(auto_exposure(&radiance));
    let mut buf = Vec::with_capacity(lit.positions.len() * 27 + lit.triangles.len() * 17);
    for (i, p) in lit.positions.iter().enumerate() {
        let b = lit.radiosity.get(i).copied().unwrap_or_default();
        for x in (*p * metres).to_array() {
            buf.extend_from_slice(&x.to_le_bytes());
        }
        for c in b.to_array() {
            buf.extend_from_slice(&(c as f32).to_le_bytes());
        }
        buf.extend_from_slice(&tonemap_pixel(b / PI, scale));
    }
    for (t, tri) in lit.triangles.iter().enumerate() {
        buf.push(3);
        for &v in tri {
            buf.extend_from_slice(&(v as i32).to_le_bytes());
        }
        let object = lit.triangle_object.get(t).map_or(-1, |&o| o as i32);
        buf.extend_from_slice(&object.to_le_bytes());
    }
    out.write_all(&buf)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::Rgb;

    /// Two triangles of a unit square, objects 0 and 1, radiosity π, 2π, 0 ... per vertex.
    fn square() -> LitMesh {
        LitMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Y, Vec3::Y],
            radiosity: vec![
                Rgb::splat(PI),
                Rgb::new(2.0 * PI, 0.0, 0.0),
                Rgb::ZERO,
                Rgb::splat(0.5),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            triangle_patch: vec![0, 0],
            has_back_twin: vec![false, false],
            triangle_object: vec![0, 1],
        }
    }

    /// Where the binary body starts: just past `end_header\n`.
    fn body_start(bytes: &[u8]) -> usize {
        let end = b"end_header\n";
        bytes
            .windows(end.len())
            .position(|w| w == end)
            .expect("header end")
            + end.len()
    }

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("radiosity-ply-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create scratch dir");
        dir
    }

    #[test]
    fn header_counts_and_body_layout_round_trip() {
        let dir = scratch("round-trip");
        let path = dir.join("lit.ply");
        let names = vec!["floor".to_string(), "back\nwall".to_string()];
        write_ply(&path, &square(), &names, 1.0).expect("write");
        let bytes = std::fs::read(&path).expect("read");
        let split = body_start(&bytes);
        let header = std::str::from_utf8(&bytes[..split]).expect("ascii header");
        assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"));
        assert!(header.contains("comment units metres\n"));
        assert!(header.contains("element vertex 4\n"));
        assert!(header.contains("element face 2\n"));
        assert!(header.contains("comment object 0 floor\n"));
        assert!(header.contains("comment object 1 back wall\n"));
        // Vertex: 6 floats + 3 bytes = 27 bytes; face: 1 + 3·4 + 4 = 17 bytes.
        let body = &bytes[split..];
        assert_eq!(body.len(), 4 * 27 + 2 * 17);
        let f32_at = |o: usize| f32::from_le_bytes(body[o..o + 4].try_into().expect("4 bytes"));
        // Vertex 1: position (1, 0, 0), radiosity (2π, 0, 0).
        assert_eq!([f32_at(27), f32_at(31), f32_at(35)], [1.0, 0.0, 0.0]);
        assert_eq!(f32_at(39), (2.0 * PI) as f32);
        // Radiance 2 in red only is brighter than radiance 1 in every channel of vertex 0.
        assert!(body[27 + 24] > body[24]);
        assert_eq!(
            &body[2 * 27 + 24..2 * 27 + 27],
            &[0, 0, 0],
            "black stays black"
        );
        // Second face: count 3, indices 0 2 3, object 1.
        let face = &body[4 * 27 + 17..];
        assert_eq!(face[0], 3);
        let i32_at = |o: usize| i32::from_le_bytes(face[o..o + 4].try_into().expect("4 bytes"));
        assert_eq!([i32_at(1), i32_at(5), i32_at(9), i32_at(13)], [0, 2, 3, 1]);
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }

    #[test]
    fn dangling_index_is_an_error_and_writes_nothing() {
        let dir = scratch("dangling");
        let path = dir.join("bad.ply");
        let mut lit = square();
        lit.triangles[1][2] = 9;
        let err = write_ply(&path, &lit, &[], 1.0).expect_err("must fail");
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
        assert!(!path.exists());
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }

    /// A millimetre model arrives at its real size, as in the `.glb`: positions times the
    /// metres per scene unit, radiosity untouched.
    #[test]
    fn positions_are_written_in_metres() {
        let dir = scratch("metres");
        let path = dir.join("mm.ply");
        write_ply(&path, &square(), &[], 0.001).expect("write");
        let bytes = std::fs::read(&path).expect("read");
        let split = body_start(&bytes);
        let body = &bytes[split..];
        let f32_at = |o: usize| f32::from_le_bytes(body[o..o + 4].try_into().expect("4 bytes"));
        // Vertex 2: (1, 1, 0) millimetres, radiosity (0, 0, 0).
        assert_eq!([f32_at(54), f32_at(58), f32_at(62)], [0.001, 0.001, 0.0]);
        assert_eq!(f32_at(27 + 12), (2.0 * PI) as f32);
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }
}
