//! Solve a scene once, then look at it in every format: a PNG from its camera, a glTF binary,
//! a PLY, a self-contained HTML viewer and a convergence plot.
//!
//! ```text
//! cargo run --release -p radiosity --example solve_and_export -- [SCENE] [OUT_DIR] [ELEMENTS]
//! ```
//!
//! SCENE is a file (.toml, .obj, .gltf, .glb) or a built-in name (default `cornell`); the files
//! go to OUT_DIR (default the current directory); ELEMENTS is the subdivision (default 2000).
//! Each output's size and writing time are printed.

use std::path::{Path, PathBuf};
use std::time::Instant;

use radiosity::io::export;
use radiosity::io::gltf::VertexColours;
use radiosity::io::image_file;
use radiosity::mesh::Subdivision;
use radiosity::pipeline::{self, Settings};
use radiosity::progress::Silent;
use radiosity::render::{self, tonemap, RasterSettings};
use radiosity::{plot, Scene};

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let scene = Scene::resolve(&args.next().unwrap_or_else(|| "cornell".into()))?;
    let out = PathBuf::from(args.next().unwrap_or_else(|| ".".into()));
    let name = scene.name.clone();
    let elements = args.next().map_or(Ok(2_000), |n| n.parse())?;

    // Solve: the result does not depend on any camera.
    let settings = Settings {
        subdivision: Subdivision::Elements(elements),
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
    let png = out.join(format!("{name}.png"));
    timed(&png, || {
        Ok(image_file::write_image(&png, &image, exposure)?)
    })?;

    // Export the lit mesh and the viewer (the same exposure as the picture), in every format.
    let options = export::Options {
        colours: VertexColours::Exposure(exposure),
        cameras: &solved.scene.cameras,
        aspect: 1.0,
    };
    for format in export::Format::ALL {
        let path = out.join(format!("{name}.{format}"));
        timed(&path, || Ok(format.write(&path, &solved, &options)?))?;
    }
    let glb = out.join(format!("{name}.glb"));
    let svg = out.join(format!("{name}-convergence.svg"));
    timed(&svg, || {
        let history = &solved.solution.history;
        Ok(plot::write_convergence_svg(&svg, &name, history)?)
    })?;

    // The glb reads back as a scene of its own.
    let again = Scene::load(&glb)?;
    println!(
        "wrote {name}.png/.glb/.ply/.html/-convergence.svg; the glb holds {} triangles in {} objects",
        again.polygons.len(),
        again.objects.len()
    );
    Ok(())
}

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

/// Runs `write`, then prints the file's size and the seconds it took.
fn timed(path: &Path, write: impl FnOnce() -> Result<()>) -> Result<()> {
    let start = Instant::now();
    write()?;
    let seconds = start.elapsed().as_secs_f64();
    let bytes = std::fs::metadata(path)?.len();
    println!("{}: {bytes} bytes in {seconds:.3} s", path.display());
    Ok(())
}
