//! A picture of a solved scene in one of the render modes, reporting its progress and
//! listening to the Ctrl-C flag: what `render` and `compare` both draw with.

use anyhow::Result;
use radiosity::mesh::{display, Mesh, Subdivision};
use radiosity::pipeline::Solved;
use radiosity::render::false_colour::{Measurement, Quantity};
use radiosity::render::local::{self, LocalSettings};
use radiosity::render::raytrace::{RaytraceSettings, Watch};
use radiosity::render::{self, Image, ModeKind, RasterSettings};
use radiosity::scene::Camera;
use radiosity::Rgb;
use radiosity::Scene;

use crate::interrupt::{stop_flag, Interrupted};
use crate::progress::Reporting;

/// The image of `solved` seen by `camera` in `mode`; `gather` is the final-gather ray count of
/// the ray tracer, `shadows` whether local illumination casts shadows. Every mode reports
/// progress as `reporting` asks and stops on Ctrl-C ([`Interrupted`], nothing written).
pub fn render_mode(
    solved: &Solved,
    camera: &Camera,
    mode: ModeKind,
    raster: &RasterSettings,
    gather: u32,
    shadows: bool,
    reporting: Reporting,
) -> Result<Image> {
    let settings = render::mode::Settings {
        local: LocalSettings {
            shadows,
            ..LocalSettings::default()
        },
        raytrace: RaytraceSettings {
            gather,
            ..RaytraceSettings::default()
        },
    };
    let mode = render::Mode::of(mode, &settings);
    watched(reporting, |watch| {
        solved.render(&mode, camera, raster, watch)
    })
}

/// The false-colour measurement of `quantity` in `solved` seen by `camera`
/// ([`Solved::measure`]), reporting progress and stopping on Ctrl-C as [`render_mode`] does.
pub fn measure(
    solved: &Solved,
    camera: &Camera,
    quantity: Quantity,
    raster: &RasterSettings,
    reporting: Reporting,
) -> Result<Measurement> {
    let progress = reporting.on_stderr();
    let stop = stop_flag();
    let watch = Watch {
        progress: &progress,
        stop: Some(&stop),
    };
    solved
        .measure(quantity, camera, raster, &watch)
        .ok_or_else(|| Interrupted("interrupted while rendering: wrote nothing".into()).into())
}

/// Local illumination of `scene` without a radiosity solve: its patches unsubdivided (the local
/// model reads only the geometry and the emitters).
pub fn render_local(
    scene: &Scene,
    camera: &Camera,
    raster: &RasterSettings,
    shadows: bool,
    reporting: Reporting,
) -> Result<Image> {
    let mesh = Mesh::build(scene, Subdivision::MaxArea(f64::INFINITY));
    let lit = display::lit_mesh(&mesh, &vec![Rgb::ZERO; mesh.element_count()]);
    let settings = LocalSettings {
        shadows,
        ..LocalSettings::default()
    };
    watched(reporting, |watch| {
        local::render(scene, &mesh, &lit, camera, raster, &settings, watch)
    })
}

/// Runs a render reporting to stderr as `reporting` asks, with the Ctrl-C flag; `None` from
/// it is an interruption.
fn watched(reporting: Reporting, render: impl FnOnce(&Watch) -> Option<Image>) -> Result<Image> {
    let progress = reporting.on_stderr();
    let stop = stop_flag();
    let watch = Watch {
        progress: &progress,
        stop: Some(&stop),
    };
    render(&watch)
        .ok_or_else(|| Interrupted("interrupted while rendering: wrote nothing".into()).into())
}
