//! A self-contained web viewer of the lit mesh: one HTML file, WebGL2, no network.
//!
//! "Solve once, look from anywhere": the viewer-independent solution is embedded in the page
//! (base64 little-endian arrays inside a JSON `<script>` block), and the page draws it from any
//! camera with the same physics as [`crate::render::raster`]: per-vertex radiance L = B/π
//! interpolated across each triangle (Gouraud 1971) or its three corners' mean (flat), then
//! exposed by 2^stops, clamped and sRGB-encoded per pixel, as [`crate::render::tonemap`] does.
//! A triangle seen from behind is dropped when a reversed twin carries its back, else drawn
//! black. The element edges (the quadtree subdivision the solver used) can be drawn on top.
//!
//! Controls: an exposure slider, the scene's cameras, orbit (drag, wheel, shift-drag) or walk
//! (W A S D Q E, drag to look), flat or Gouraud shading, element edges. The URL fragment sets
//! the initial state for scripted screenshots: `#exposure=STOPS&shading=flat&edges=1&ui=0`.
//!
//! Everything from the scene that reaches the page (its name, object and camera names) goes
//! through JSON with `<`, `>` and `&` escaped as `\u003c`, `\u003e`, `\u0026`, and into the
//! title HTML-escaped, so a name cannot close the script block or inject markup; the page
//! shows names with `textContent` only.
//!
//! The whole library path, from a scene to its viewer:
//!
//! ```
//! use radiosity::io::{gltf, html};
//! use radiosity::mesh::Subdivision;
//! use radiosity::pipeline::{self, Settings};
//! use radiosity::progress::Silent;
//! use radiosity::render::{self, tonemap, RasterSettings};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let scene = radiosity::Scene::resolve("cornell")?; // or Scene::load(Path::new("x.glb"))
//! let settings = Settings { subdivision: Subdivision::Elements(64), ..Settings::default() };
//! let solved = pipeline::solve(scene, &settings, &Silent)?;
//! let small = RasterSettings { width: 32, height: 32, samples_per_pixel: 1 };
//! let image = render::render(&solved.lit, &solved.scene.cameras[0], &small);
//! let stops = tonemap::auto_exposure(&image);
//!
//! let dir = std::env::temp_dir();
//! html::write_solved(&dir.join("doc-cornell.html"), &solved, Some(stops))?;
//! let names: Vec<String> = solved.scene.objects.iter().map(|o| o.name.clone()).collect();
//! let glb = dir.join("doc-cornell.glb");
//! let placement = gltf::Placement { cameras: &solved.scene.cameras, ..Default::default() };
//! gltf::write_glb(&glb, &solved.lit, &names, gltf::VertexColours::Exposure(stops), &placement)?;
//! assert_eq!(radiosity::Scene::load(&glb)?.polygons.len(), solved.lit.triangles.len());
//! # Ok(())
//! # }
//! ```

use std::f64::consts::PI;
use std::io;
use std::path::Path;

use glam::Vec3;
use serde_json::json;

use super::atomic::write_atomic;
use crate::mesh::{LitMesh, Mesh};
use crate::pipeline::Solved;
use crate::render::tonemap::auto_exposure;
use crate::render::{render, RasterSettings};
use crate::scene::Camera;

/// The page template; `__TITLE__` and `__DATA__` are replaced.
const TEMPLATE: &str = include_str!("viewer/viewer.html");

/// What the viewer shows.
#[derive(Clone, Copy, Debug)]
pub struct Viewer<'a> {
    /// The page title (the scene's name).
    pub title: &'a str,
    /// The lit mesh.
    pub lit: &'a LitMesh,
    /// Element edges as segments (see [`element_edges`]); may be empty.
    pub edges: &'a [[Vec3; 2]],
    /// Cameras; the first is the initial view. Must not be empty.
    pub cameras: &'a [Camera],
    /// Initial exposure in stops.
    pub exposure: f32,
}

/// The outline of every element (front patches only, so a two-sided surface is outlined once).
#[must_use]
pub fn element_edges(mesh: &Mesh) -> Vec<[Vec3; 2]> {
    let mut out = Vec::new();
    for e in 0..mesh.element_count() {
        if mesh.element_patch(e).back {
            continue;
        }
        let corners = mesh.element(e).face.corners();
        for (i, &a) in corners.iter().enumerate() {
            out.push([a, corners[(i + 1) % corners.len()]]);
        }
    }
    out
}

/// The whole page.
#[must_use]
pub fn viewer_html(v: &Viewer) -> String {
    let n = v.lit.positions.len();
    // Triangles that refer to a missing vertex are left out rather than trusted by the page.
    let keep: Vec<usize> = (0..v.lit.triangles.len())
        .filter(|&t| v.lit.triangles[t].iter().all(|&i| (i as usize) < n))
        .collect();
    let positions: Vec<u8> = v
        .lit
        .positions
        .iter()
        .flat_map(|p| p.to_array())
        .flat_map(f32::to_le_bytes)
        .collect();
    let radiance: Vec<u8> = (0..n)
        .flat_map(|i| {
            let l = v.lit.radiosity.get(i).copied().unwrap_or_default() / PI;
            l.as_vec3().to_array()
        })
        .flat_map(f32::to_le_bytes)
        .collect();
    let triangles: Vec<u8> = keep
        .iter()
        .flat_map(|&t| v.lit.triangles[t])
        .flat_map(u32::to_le_bytes)
        .collect();
    let twin: Vec<u8> = keep
        .iter()
        .map(|&t| u8::from(v.lit.has_back_twin.get(t).copied().unwrap_or(false)))
        .collect();
    let edges: Vec<u8> = v
        .edges
        .iter()
        .flat_map(|e| [e[0].to_array(), e[1].to_array()])
        .flatten()
        .flat_map(f32::to_le_bytes)
        .collect();
    let cameras: Vec<_> = v
        .cameras
        .iter()
        .map(|c| {
            json!({
                "name": c.name, "eye": c.eye.to_array(), "target": c.target.to_array(),
                "up": c.up.to_array(), "fov_y": c.fov_y
            })
        })
        .collect();
    let data = json!({
        "title": v.title,
        "exposure": if v.exposure.is_finite() { v.exposure } else { 0.0 },
        "cameras": cameras,
        "positions": encode_base64(&positions),
        "radiance": encode_base64(&radiance),
        "triangles": encode_base64(&triangles),
        "twin": encode_base64(&twin),
        "edges": encode_base64(&edges),
    });
    let data = script_safe(&data.to_string());
    TEMPLATE
        .replacen("__TITLE__", &escape_html(v.title), 1)
        .replacen("__DATA__", &data, 1)
}

/// Writes the page at `path` (atomically).
///
/// # Errors
/// I/O errors, and `InvalidInput` when there is no camera.
pub fn write_html(path: &Path, viewer: &Viewer) -> io::Result<()> {
    if viewer.cameras.is_empty() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "the viewer needs a camera",
        ));
    }
    let page = viewer_html(viewer);
    write_atomic(path, |w| w.write_all(page.as_bytes()))
}

/// Writes the viewer of a solved scene at `path`: its cameras, element edges, and `exposure` in
/// stops, or else the automatic exposure of a small raster image from the first camera (the
/// exposure `radiosity render` picks for that view).
///
/// # Errors
/// As [`write_html`].
pub fn write_solved(path: &Path, solved: &Solved, exposure: Option<f32>) -> io::Result<()> {
    let edges = element_edges(&solved.mesh);
    let exposure = exposure.unwrap_or_else(|| {
        solved.scene.cameras.first().map_or(0.0, |camera| {
            let preview = RasterSettings {
                width: PREVIEW_SIZE,
                height: PREVIEW_SIZE,
                samples_per_pixel: 1,
            };
            auto_exposure(&render(&solved.lit, camera, &preview))
        })
    });
    write_html(
        path,
        &Viewer {
            title: &solved.scene.name,
            lit: &solved.lit,
            edges: &edges,
            cameras: &solved.scene.cameras,
            exposure,
        },
    )
}

/// Side of the preview image whose automatic exposure [`write_solved`] uses.
const PREVIEW_SIZE: u32 = 128;

/// JSON text made safe inside a `<script>` element: `<`, `>` and `&` only occur inside JSON
/// strings, where their `\u` escapes mean the same.
fn script_safe(json: &str) -> String {
    json.replace('<', "\\u003c")
        .replace('>', "\\u003e")
        .replace('&', "\\u0026")
}

/// Text made safe as HTML element content and attribute values.
fn escape_html(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '&' => out.push_str("&amp;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

/// Standard base64 with padding (RFC 4648 §4), what the page's `atob` reads.
fn encode_base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(char::from(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Rgb;

    fn camera(name: &str) -> Camera {
        Camera {
            name: name.into(),
            eye: Vec3::new(0.0, 0.0, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y: 40.0,
        }
    }

    #[test]
    fn base64_matches_rfc4648_vectors() {
        // RFC 4648 §10 test vectors.
        for (plain, coded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(encode_base64(plain.as_bytes()), coded);
        }
    }

    #[test]
    fn hostile_names_cannot_break_out_of_the_page() {
        let evil = "</script><img src=x onerror=alert(1)>&";
        let lit = LitMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            radiosity: vec![Rgb::ONE; 3],
            triangles: vec![[0, 1, 2], [0, 1, 9]],
            triangle_patch: vec![0, 0],
            has_back_twin: vec![false, false],
            triangle_object: vec![0, 0],
        };
        let cams = [camera(evil)];
        let page = viewer_html(&Viewer {
            title: evil,
            lit: &lit,
            edges: &[],
            cameras: &cams,
            exposure: 0.0,
        });
        assert!(!page.contains(evil));
        assert!(!page.contains("<img"));
        // Exactly the template's own script elements close.
        assert_eq!(
            page.matches("</script>").count(),
            TEMPLATE.matches("</script>").count()
        );
        // The data block is valid JSON that decodes to the original name; the dangling
        // triangle is dropped (12 bytes → 16 base64 characters for one triangle).
        let start = page.find("type=\"application/json\">").expect("data") + 24;
        let end = start + page[start..].find("</script>").expect("end");
        let data: serde_json::Value = serde_json::from_str(&page[start..end]).expect("json");
        assert_eq!(data["title"], evil);
        assert_eq!(data["cameras"][0]["name"], evil);
        assert_eq!(data["triangles"].as_str().map(str::len), Some(16));
        assert!(page.contains("<title>&lt;/script&gt;&lt;img"));
    }

    #[test]
    fn a_camera_is_required() {
        let e = write_html(
            Path::new("/nonexistent/x.html"),
            &Viewer {
                title: "t",
                lit: &LitMesh::default(),
                edges: &[],
                cameras: &[],
                exposure: 0.0,
            },
        )
        .expect_err("no camera");
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
    }
}
