//! `radiosity bake`: solve a scene and store its light in light-map textures over its surfaces
//! ([`radiosity::bake`]), written as a glTF a game or web engine draws as it is, with the
//! irradiance as OpenEXR beside it.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Result};
use radiosity::bake::{self, Settings, Size};
use radiosity::io::atomic::Batch;
use radiosity::io::baked::{lightmap_path, write_baked, write_lightmap};
use radiosity::io::gltf::Placement;
use radiosity::render::Watch;

use crate::args::BakeArgs;
use crate::interrupt::{stop_flag, Interrupted};
use crate::job::{self, check_output, in_pool, stage, Outputs};

/// Runs `radiosity bake`.
pub fn run(args: &BakeArgs) -> Result<()> {
    job::check_common(&args.common)?;
    let settings = settings(args)?;
    in_pool(args.common.run.threads, || {
        let start = Instant::now();
        let (scene, load) = job::load(&args.scene, &args.common)?;
        let output = args
            .output
            .clone()
            .unwrap_or_else(|| PathBuf::from(format!("{}.baked.glb", scene.name)));
        check_output(&output, "baked model", &["glb"])?;
        bake::layout(&scene, &settings)?;
        let solved = job::run_solve(scene, &args.common, false)?;
        if solved.solution.interrupted {
            return Err(Interrupted("interrupted while solving: wrote nothing".into()).into());
        }
        let bake_start = Instant::now();
        let progress = args.common.run.reporting().on_stderr();
        let stop = stop_flag();
        let watch = Watch {
            progress: &progress,
            stop: Some(&stop),
        };
        let baked = bake::bake(
            &solved.scene,
            &solved.mesh,
            &solved.solution,
            &settings,
            &watch,
        )?
        .ok_or_else(|| Interrupted("interrupted while baking: wrote nothing".into()))?;
        let scene = &solved.scene;
        let aspect = scene.render.width as f32 / scene.render.height.max(1) as f32;
        let placement = Placement {
            metres_per_unit: scene.units.metres(),
            cameras: &scene.cameras,
            aspect,
        };
        let exr = lightmap_path(&output);
        let exr_name = file_name(&exr);
        let mut batch = Batch::new();
        stage(&mut batch, &exr, |tmp| Ok(write_lightmap(tmp, &baked)?))?;
        stage(&mut batch, &output, |tmp| {
            Ok(write_baked(tmp, scene, &baked, &placement, &exr_name)?)
        })?;
        let (w, h) = baked.atlas.size;
        job::say(
            &args.common,
            &format!(
                "bake: {} charts in a {w} × {h} light map, {:.1} texels per unit; {:.2} s",
                baked.charts.len(),
                baked.atlas.density,
                bake_start.elapsed().as_secs_f64()
            ),
        );
        let outputs = Outputs {
            batch,
            start,
            load_seconds: load,
            render_seconds: 0.0,
        };
        job::finish(&solved, &args.common, None, outputs)
    })
}

/// The bake's settings from the flags.
fn settings(args: &BakeArgs) -> Result<Settings> {
    if args.padding < 2 {
        bail!("--padding {}: at least 2 texels", args.padding);
    }
    let size = match (args.lightmap_size, args.texels_per_unit) {
        (_, Some(d)) if !(d.is_finite() && d > 0.0) => {
            bail!("--texels-per-unit {d}: must be a positive number")
        }
        (_, Some(d)) => Size::Density(d),
        (Some(s), None) if !(16..=bake::MAX_SIDE).contains(&s) => {
            bail!("--lightmap-size {s}: from 16 to {}", bake::MAX_SIDE)
        }
        (Some(s), None) => Size::Side(s),
        (None, None) => Settings::default().size,
    };
    Ok(Settings {
        size,
        padding: args.padding,
        ..Settings::default()
    })
}

/// The last component of `path`, for naming a file beside another.
fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}
