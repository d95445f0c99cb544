//! `radiosity compare`: the lecture's comparison — local illumination ("OpenGL"), radiosity,
//! and (when the scene has mirrors or glass) the two-pass ray tracer — side by side in one
//! labelled image, all from one solve and one exposure.

use std::time::Instant;

use anyhow::Result;
use radiosity::io::atomic::Batch;
use radiosity::io::image_file::write_image;
use radiosity::render::raytrace;
use radiosity::render::{compare, tonemap, Image, ModeKind};
use radiosity::Rgb;

use crate::args::CompareArgs;
use crate::job;
use crate::picture;

/// `radiosity compare`.
pub fn run(args: &CompareArgs) -> Result<()> {
    job::check_output(&args.output, "image", &job::IMAGE_EXTENSIONS)?;
    job::check_common(&args.common)?;
    job::in_pool(args.common.run.threads, || {
        let start = Instant::now();
        let common = &args.common;
        let (scene, load) = job::load(&args.scene, common)?;
        let (camera, raster) = job::frame(&scene, &args.frame, args.samples)?;
        let solved = job::run_solve(scene, common, true)?;
        if solved.solution.interrupted {
            // Three renders, one of them possibly ray-traced: after a Ctrl-C the run ends now.
            let outputs = job::Outputs {
                batch: Batch::new(),
                start,
                load_seconds: load,
                render_seconds: 0.0,
            };
            job::say(common, "not rendered: the solve was interrupted");
            return job::finish(&solved, common, None, outputs);
        }
        let render_start = Instant::now();
        let mut modes = vec![
            ("local", ModeKind::Local),
            ("radiosity", ModeKind::Radiosity),
        ];
        if raytrace::has_specular(&solved.scene) {
            modes.push(("ray tracing", ModeKind::Raytrace));
        }
        let mut panels = Vec::with_capacity(modes.len());
        for (label, mode) in modes {
            let t = Instant::now();
            let image = picture::render_mode(
                &solved,
                &camera,
                mode,
                &raster,
                args.gather,
                true,
                common.run.reporting(),
            )?;
            panels.push((label, image));
            job::say(
                common,
                &format!("{label}: rendered in {:.2} s", t.elapsed().as_secs_f64()),
            );
        }
        let radiosity = &panels[1].1;
        let exposure = args
            .exposure
            .unwrap_or_else(|| tonemap::auto_exposure(radiosity));
        let white = Rgb::splat(1.0 / tonemap::exposure_scale(exposure));
        let refs: Vec<(&str, &Image)> = panels.iter().map(|(l, i)| (*l, i)).collect();
        let image = compare::compose(&refs, white);
        let mut batch = Batch::new();
        if job::may_write(&args.output, &solved, common) {
            job::stage(&mut batch, &args.output, |tmp| {
                Ok(write_image(tmp, &image, exposure)?)
            })?;
        }
        let outputs = job::Outputs {
            batch,
            start,
            load_seconds: load,
            render_seconds: render_start.elapsed().as_secs_f64(),
        };
        job::finish(&solved, common, None, outputs)
    })
}
