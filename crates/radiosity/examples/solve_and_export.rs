//! Solve a scene once, then look at it in every format: a PNG from its camera, a glTF binary,
//! a PLY, a self-contained HTML viewer and a convergence plot.
//!
//! ```text
//! cargo run --release -p radiosity --example solve_and_export -- [SCENE] [OUT_DIR]
//! ```
//!
//! SCENE is a file (.toml, .obj, .gltf, .glb) or a built-in name (default `cornell`); the files
//! go to OUT_DIR (default the current directory).

use std::path::PathBuf;

use radiosity::io::gltf::{write_glb, VertexColours};
use radiosity::io::{html, image_file, ply};
use radiosity::mesh::Subdivision;
use radiosity::pipeline::{self, Settings};
use radiosity::progress::Silent;
use radiosity::render::{self, tonemap, RasterSettings};
use radiosity::{plot, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let scene = Scene::resolve(&args.next().unwrap_or_else(|| "cornell".into()))?;
    let out = PathBuf::from(args.next().unwrap_or_else(|| ".".into()));
    let name = scene.name.clone();

    // Solve: the result does not depend on any camera.
    let settings = Settings {
        subdivision: Subdivision::Elements(2_000),
        ..Settings::default()
    };
    let solved = pipeline::solve(scene, &settings, &Silent)?;
    println!(
        "{name}: {} elements, {} iterations, residual {:.1e}",
        solved.mesh.element_count(),
        solved.solution.iterations,
        solved.solution.residual
    );

    // Render from the scene's first camera, with the automatic exposure.
    let camera = &solved.scene.cameras[0];
    let image = render::render(&solved.lit, camera, &RasterSettings::default());
    let exposure = tonemap::auto_exposure(&image);
    image_file::write_image(&out.join(format!("{name}.png")), &image, exposure)?;

    // Export the lit mesh and the viewer, named after the scene's objects.
    let names: Vec<String> = solved
        .scene
        .objects
        .iter()
        .map(|o| o.name.clone())
        .collect();
    let glb = out.join(format!("{name}.glb"));
    write_glb(&glb, &solved.lit, &names, VertexColours::Exposure(exposure))?;
    ply::write_ply(&out.join(format!("{name}.ply")), &solved.lit, &names)?;
    html::write_solved(&out.join(format!("{name}.html")), &solved, Some(exposure))?;
    plot::write_convergence_svg(
        &out.join(format!("{name}-convergence.svg")),
        &name,
        &solved.solution.history,
    )?;

    // The glb reads back as a scene of its own.
    let again = Scene::load(&glb)?;
    println!(
        "wrote {name}.png/.glb/.ply/.html/-convergence.svg; the glb holds {} triangles in {} objects",
        again.polygons.len(),
        again.objects.len()
    );
    Ok(())
}
