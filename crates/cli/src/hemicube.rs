//! `radiosity hemicube`: the teaching picture of one element's hemicube.
//!
//! The hemicube is unfolded into a cross: the top face in the middle, the four half side faces
//! folded out around it with their horizon on the outside. Each cell is coloured by the source
//! it sees (a colour from a hash of the source's index, black where it sees nothing), or with
//! `--heatmap` by its delta form factor (black → red → yellow → white, relative to the largest).

use anyhow::{bail, Context, Result};
use radiosity::accel::Bvh;
use radiosity::formfactor::hemicube::raster::{Layout, NOTHING};
use radiosity::formfactor::hemicube::Hemicube;
use radiosity::formfactor::Geometry;
use radiosity::io::image_file::write_image;
use radiosity::mesh::{Mesh, Subdivision};
use radiosity::render::Image;
use radiosity::{solve, Rgb, Scene};

use crate::args::HemicubeArgs;

/// Side of the picture the cells are scaled up to, in pixels (about).
const PICTURE: u32 = 768;

/// `radiosity hemicube`.
pub fn run(args: &HemicubeArgs) -> Result<()> {
    let is_png = args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !is_png {
        bail!("{}: the hemicube picture is a .png", args.output.display());
    }
    let scene = Scene::resolve(&args.scene)?;
    let subdivision = match args.elements {
        Some(n) => Subdivision::Elements(usize::try_from(n).unwrap_or(usize::MAX)),
        None => Subdivision::default(),
    };
    let mesh = Mesh::build(&scene, subdivision);
    let element = usize::try_from(args.element).unwrap_or(usize::MAX);
    if element >= mesh.element_count() {
        bail!(
            "--element {}: scene `{}` has {} elements (0 to {})",
            args.element,
            scene.name,
            mesh.element_count(),
            mesh.element_count().saturating_sub(1)
        );
    }
    let bvh = Bvh::build(&mesh.triangles);
    let max_sources = args
        .sources
        .map_or(solve::Settings::default().max_sources, |n| {
            usize::try_from(n).unwrap_or(usize::MAX)
        });
    let sources = mesh.sources(max_sources, max_sources);
    let g = Geometry::new(&mesh, &bvh, &sources);
    let hemicube = Hemicube::new(args.resolution, 1, args.seed).with_rotation(args.rotate);
    let view = hemicube.view(&g, element);

    let image = if args.heatmap {
        let max = view.deltas.iter().copied().fold(0.0, f64::max);
        unfold(view.layout, |cell| heat(view.deltas[cell] / max))
    } else {
        unfold(view.layout, |cell| item_colour(view.items[cell]))
    };
    write_image(&args.output, &image, 0.0)
        .with_context(|| format!("writing {}", args.output.display()))?;

    let seen = view.items.iter().filter(|&&i| i != NOTHING).count();
    let covered: f64 = view
        .items
        .iter()
        .zip(&view.deltas)
        .filter(|(&i, _)| i != NOTHING)
        .map(|(_, d)| d)
        .sum();
    let patch = &mesh.patches[mesh.element(element).patch as usize];
    println!(
        "element {element} of object `{}`: {} × {} hemicube, {seen} of {} cells see a source, Σ ΔF over them = {covered:.6}",
        scene.objects[patch.object as usize].name,
        view.layout.resolution,
        view.layout.resolution,
        view.layout.cells(),
    );
    Ok(())
}

/// The cross layout: an image of 2·res × 2·res cells, the top face in the middle square, the
/// side faces as the four arms, each cell `scale` pixels wide.
fn unfold(layout: Layout, colour: impl Fn(usize) -> Rgb) -> Image {
    let res = layout.resolution;
    let half = res / 2;
    let scale = (PICTURE / (2 * res)).max(1);
    let side = 2 * res * scale;
    let mut image = Image::new(side, side);
    image.pixels.fill(Rgb::splat(0.02));
    // Face and cell of each unfolded position (x right, y down, in cells).
    let place = |face: usize, i: u32, j: u32| -> (u32, u32) {
        let flip = res - 1 - i;
        // Side rows count from the horizon, which lies on the outside of the cross.
        let outer = || half - 1 - j;
        match face {
            // Top: x along a, b upward.
            0 => (half + i, half + (res - 1 - j)),
            // +a: right arm, its x (= b) upward.
            1 => (half + res + outer(), half + flip),
            // +b: upper arm, its x (= −a) leftward.
            2 => (half + flip, j),
            // −a: left arm, its x (= −b) downward.
            3 => (j, half + i),
            // −b: lower arm, its x (= a) rightward.
            _ => (half + i, half + res + outer()),
        }
    };
    for face in 0..5 {
        for j in 0..layout.rows(face) {
            for i in 0..res {
                let c = colour(layout.index(face, i, j));
                let (x, y) = place(face, i, j);
                for dy in 0..scale {
                    let row = ((y * scale + dy) * side) as usize;
                    for dx in 0..scale {
                        image.pixels[row + (x * scale + dx) as usize] = c;
                    }
                }
            }
        }
    }
    image
}

/// A distinct, fairly bright colour per item (linear RGB), black for nothing.
fn item_colour(item: u32) -> Rgb {
    if item == NOTHING {
        return Rgb::ZERO;
    }
    let z = radiosity::hash::mix(u64::from(item));
    let channel = |k: u32| 0.15 + 0.85 * ((z >> (16 * k)) & 0xFFFF) as f64 / 65535.0;
    let srgb = Rgb::new(channel(0), channel(1), channel(2));
    // The PNG encoder applies the sRGB curve: undo it so the hashed colours come out as drawn.
    srgb * srgb
}

/// Black → red → yellow → white for t in [0, 1] (linear RGB).
fn heat(t: f64) -> Rgb {
    let t = t.clamp(0.0, 1.0) * 3.0;
    let srgb = Rgb::new(
        t.min(1.0),
        (t - 1.0).clamp(0.0, 1.0),
        (t - 2.0).clamp(0.0, 1.0),
    );
    srgb * srgb
}
