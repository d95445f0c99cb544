//! `radiosity info SCENE`: what a scene holds, without solving it.
//!
//! A photometric file (`.ies`, `.ldt`) is reported instead by [`crate::photometric`].
//!
//! Counts (objects, materials, polygons, patches — one per lit side — and the elements the
//! subdivision would make), the surface area, the emitted power Φ = Σ A·π·L_e per channel plus
//! the luminaires' flux (in W, the scene's length unit applied, and in lm: its luminance), the
//! bounding box, the cameras, and the warnings of loading.
//!
//! For every object whose polygons form a closed, oriented mesh (corners at equal positions
//! merged), the Euler–Poincaré counts V − E + F = 2 (S − H) and the genus H
//! ([`model::brep::closed_topology`]): a sphere has genus 0, a torus 1, a cube whose six faces
//! a ball has cut open 5.

use std::collections::HashMap;
use std::io::Write;

use anyhow::Result;
use radiosity::mesh::{Mesh, Subdivision};
use radiosity::photometry;
use radiosity::Scene;

use model::brep::{closed_topology, EulerCounts};
use model::PolyMesh;

use crate::args::InfoArgs;
use crate::photometric;

/// `radiosity info`.
pub fn run(args: &InfoArgs) -> Result<()> {
    let path = std::path::Path::new(&args.scene);
    if photometry::Format::from_path(path).is_some() {
        let file = photometry::read(path)?;
        write!(
            std::io::stdout().lock(),
            "{}",
            photometric::report(path, &file)
        )?;
        return Ok(());
    }
    let scene = Scene::resolve(&args.scene)?;
    let subdivision = match (args.elements, args.max_element_area) {
        (_, Some(a)) => Subdivision::MaxArea(a),
        (Some(n), None) => Subdivision::Elements(usize::try_from(n).unwrap_or(usize::MAX)),
        (None, None) => Subdivision::default(),
    };
    let mesh = Mesh::build(&scene, subdivision);
    let mut out = std::io::stdout().lock();
    write!(out, "{}", report(&scene, &mesh))?;
    Ok(())
}

/// The report, one fact per line.
fn report(scene: &Scene, mesh: &Mesh) -> String {
    let front = || mesh.patches.iter().filter(|p| !p.back);
    let area: f64 = front().map(|p| p.area).sum();
    let emitted = mesh.emitted_power();
    let corners = || scene.polygons.iter().flat_map(|p| &p.vertices);
    let (lo, hi) = corners().fold(
        (corners().next().copied(), corners().next().copied()),
        |(lo, hi), v| (lo.map(|l| l.min(*v)), hi.map(|h| h.max(*v))),
    );
    let emitters = scene.materials.iter().filter(|m| m.is_emitter()).count();
    let cameras: Vec<&str> = scene.cameras.iter().map(|c| c.name.as_str()).collect();
    let mut s = String::new();
    let mut line = |k: &str, v: String| s.push_str(&format!("{k:<14}{v}\n"));
    line("scene", scene.name.clone());
    line("objects", scene.objects.len().to_string());
    line(
        "materials",
        format!("{} ({emitters} emitting)", scene.materials.len()),
    );
    line("polygons", scene.polygons.len().to_string());
    line(
        "patches",
        format!(
            "{} ({} two-sided backs)",
            mesh.patches.len(),
            mesh.patches.len() - front().count()
        ),
    );
    line("elements", mesh.element_count().to_string());
    line("area", format!("{area:.6} units²"));
    let m2 = scene.units.metres().powi(2);
    line(
        "emitted",
        format!(
            "{:.6} {:.6} {:.6} W (per channel), {:.6} lm",
            emitted.x * m2,
            emitted.y * m2,
            emitted.z * m2,
            radiosity::color::luminance(emitted * m2)
        ),
    );
    if !scene.luminaires.is_empty() {
        line("luminaires", scene.luminaires.len().to_string());
    }
    if let (Some(lo), Some(hi)) = (lo, hi) {
        line(
            "bounds",
            format!(
                "[{:.4}, {:.4}, {:.4}] – [{:.4}, {:.4}, {:.4}]",
                lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
            ),
        );
    }
    for (name, c) in solids(scene) {
        let chi = c.vertices as i64 - c.edges as i64 + c.faces as i64;
        line(
            "solid",
            format!(
                "{name}: V − E + F = {} − {} + {} = {chi} = 2 (S − H), S = {}, genus H = {}",
                c.vertices, c.edges, c.faces, c.shells, c.holes
            ),
        );
    }
    line("cameras", cameras.join(", "));
    line("warnings", scene.warnings.len().to_string());
    for w in &scene.warnings {
        s.push_str(&format!("  warning: {w}\n"));
    }
    s
}

/// The objects whose polygons make a closed, oriented mesh, with its Euler–Poincaré counts.
fn solids(scene: &Scene) -> Vec<(&str, EulerCounts)> {
    let mut meshes: Vec<(PolyMesh, HashMap<[u32; 3], u32>)> =
        vec![(PolyMesh::default(), HashMap::new()); scene.objects.len()];
    for p in &scene.polygons {
        let Some((mesh, index)) = meshes.get_mut(p.object) else {
            continue;
        };
        let mut face: Vec<u32> = p
            .vertices
            .iter()
            .map(|v| {
                *index
                    .entry(v.to_array().map(f32::to_bits))
                    .or_insert_with(|| {
                        mesh.positions.push(*v);
                        mesh.positions.len() as u32 - 1
                    })
            })
            .collect();
        face.dedup();
        while face.len() > 1 && face.first() == face.last() {
            face.pop();
        }
        mesh.faces.push(face);
    }
    scene
        .objects
        .iter()
        .zip(&meshes)
        .filter(|(_, (mesh, _))| mesh.faces.len() >= 4)
        .filter_map(|(o, (mesh, _))| Some((o.name.as_str(), closed_topology(mesh).ok()?)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cornell_report_has_its_facts() {
        let scene = Scene::resolve("cornell").expect("built-in");
        let mesh = Mesh::build(&scene, Subdivision::Elements(100));
        let r = report(&scene, &mesh);
        // The emitted power is Σ A·π·L_e over the light's front patches.
        let light: f64 = scene
            .polygons
            .iter()
            .filter(|p| scene.materials[p.material].is_emitter())
            .map(|p| {
                let v = &p.vertices;
                let a = (1..v.len() - 1)
                    .map(|i| (v[i] - v[0]).cross(v[i + 1] - v[0]))
                    .fold(v[0] * 0.0, |a, b| a + b);
                f64::from(a.length()) / 2.0 * scene.materials[p.material].emission.x
            })
            .sum::<f64>()
            * std::f64::consts::PI
            * scene.units.metres().powi(2);
        let emitted: f64 = r
            .lines()
            .find(|l| l.starts_with("emitted"))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse().ok())
            .expect("emitted line");
        assert!(
            (emitted - light).abs() <= 1e-4 * light,
            "{emitted} vs {light}"
        );
        assert!(r.contains(&format!("elements      {}", mesh.element_count())));
        assert!(r.contains("bounds"));
    }

    #[test]
    fn solids_report_gives_each_closed_object_its_genus() {
        let scene = Scene::resolve("solids").expect("built-in");
        let mesh = Mesh::build(&scene, Subdivision::Elements(100));
        let r = report(&scene, &mesh);
        let genus = |name: &str| -> Option<usize> {
            r.lines()
                .find(|l| l.starts_with("solid") && l.contains(&format!(" {name}: ")))
                .and_then(|l| l.rsplit(' ').next())
                .and_then(|g| g.parse().ok())
        };
        // A torus and its instances have one hole; the metaball blob none; the cube whose six
        // faces the sphere cuts open, drilled through two corners, is the cube's frame
        // (genus 5) with a tunnel through each of the two corners (genus 7).
        for (name, g) in [
            ("torus", 1),
            ("ring_left", 1),
            ("ring_right", 1),
            ("blob", 0),
            ("part", 7),
        ] {
            assert_eq!(genus(name), Some(g), "{name}\n{r}");
        }
        // Open objects (the walls) get no line.
        assert_eq!(genus("floor"), None);
        for l in r.lines().filter(|l| l.starts_with("solid")) {
            let n: Vec<i64> = l
                .split(|c: char| !c.is_ascii_digit() && c != '-')
                .filter_map(|t| t.parse().ok())
                .collect();
            // V, E, F, χ, 2, S, H: the formula holds on the printed counts.
            assert_eq!(n[0] - n[1] + n[2], n[3], "{l}");
            assert_eq!(n[3], 2 * (n[5] - n[6]), "{l}");
        }
    }
}
