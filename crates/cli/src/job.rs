//! `radiosity render` and `radiosity solve`: check the outputs, load, solve, render, write.
//!
//! Everything that can be checked before the (possibly long) solve is checked first: output
//! extensions, output directories, the mode, the camera name. A job's outputs are written to
//! temporary files first and renamed onto their targets together at the end
//! ([`radiosity::io::atomic::Batch`]), so a failure anywhere leaves none of them, and no
//! partial file.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use radiosity::io::atomic::{write_atomic, Batch};
use radiosity::io::image_file::write_image;
use radiosity::io::{self, export};
use radiosity::pipeline::{self, Solved};
use radiosity::plot::write_convergence_svg;
use radiosity::render::{mode, tonemap, ModeKind, RasterSettings};
use radiosity::scene::check::{camera_problem, CameraProblem};
use radiosity::scene::{sky, Camera};
use radiosity::solve::checkpoint::{Checkpoint, Checkpointing, Control};
use radiosity::stats::Timings;
use radiosity::Scene;
use radiosity::{grids, solve};

use crate::args::{CommonArgs, FrameArgs, RenderArgs, SolveArgs, ViewArgs};
use crate::false_colour;
use crate::interrupt::{stop_flag, Interrupted};
use crate::picture;
use crate::settings;
use crate::solver::Solver;

/// Image extensions `--output` accepts.
pub(crate) const IMAGE_EXTENSIONS: [&str; 4] = ["png", "exr", "hdr", "pfm"];
/// Bytes per pixel of a rendered radiance image (three f64).
const IMAGE_BYTES_PER_PIXEL: u64 = 24;

/// `radiosity render`.
pub fn render(args: &RenderArgs) -> Result<()> {
    if args.gather > 0 && args.mode != ModeKind::Raytrace {
        bail!("--gather applies to --mode raytrace only");
    }
    if args.no_shadows && args.mode != ModeKind::Local {
        bail!("--no-shadows applies to --mode local only");
    }
    false_colour::scale(args)?;
    if args.mode == ModeKind::Local {
        let common = &args.common;
        for (given, flag) in [
            (common.outputs.stats.is_some(), "--stats"),
            (common.outputs.plot.is_some(), "--plot"),
            (!common.outputs.export.is_empty(), "--export"),
            (common.run.checkpoint.is_some(), "--checkpoint"),
            (common.run.resume.is_some(), "--resume"),
        ] {
            if given {
                bail!("{flag}: --mode local does not solve the radiosity (leave out --mode local)");
            }
        }
    }
    for path in &args.outputs {
        check_output(path, "image", &IMAGE_EXTENSIONS)?;
    }
    check_common(&args.common)?;
    in_pool(args.common.run.threads, || render_job(args))
}

/// `radiosity solve`.
pub fn solve(args: &SolveArgs) -> Result<()> {
    check_common(&args.common)?;
    in_pool(args.common.run.threads, || {
        let start = Instant::now();
        let (scene, load) = load(&args.scene, &args.common)?;
        let solved = run_solve(scene, &args.common, !args.common.outputs.export.is_empty())?;
        let outputs = Outputs {
            batch: Batch::new(),
            start,
            load_seconds: load,
            render_seconds: 0.0,
        };
        finish(&solved, &args.common, None, outputs)
    })
}

/// Runs `job` in a rayon pool of `threads` workers, or in the global pool.
pub(crate) fn in_pool<T: Send>(
    threads: Option<u64>,
    job: impl FnOnce() -> Result<T> + Send,
) -> Result<T> {
    match threads {
        None => job(),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n as usize)
            .build()
            .with_context(|| format!("--threads {n}: cannot start the threads"))?
            .install(job),
    }
}

fn render_job(args: &RenderArgs) -> Result<()> {
    let start = Instant::now();
    let common = &args.common;
    let (scene, load) = load(&args.scene, common)?;
    let samples = args.samples.unwrap_or(args.mode.default_samples());
    let (camera, raster) = frame(&scene, &args.frame, samples)?;
    let pixels = u64::from(raster.width) * u64::from(raster.height);
    let budget = settings::memory_budget(common);
    if pixels * IMAGE_BYTES_PER_PIXEL > budget {
        bail!(
            "a {}×{} image needs {} MiB, more than the memory budget of {} MiB (--max-memory)",
            raster.width,
            raster.height,
            (pixels * IMAGE_BYTES_PER_PIXEL) >> 20,
            budget >> 20
        );
    }
    let outputs = if args.outputs.is_empty() {
        let name = PathBuf::from(format!("{}.png", scene.name));
        check_output(&name, "image", &IMAGE_EXTENSIONS)?;
        vec![name]
    } else {
        args.outputs.clone()
    };
    if args.mode == ModeKind::Local {
        let reporting = common.run.reporting();
        let image = picture::render_local(&scene, &camera, &raster, !args.no_shadows, reporting)?;
        let exposure = args
            .exposure
            .unwrap_or_else(|| tonemap::auto_exposure(&image));
        let mut batch = Batch::new();
        for path in &outputs {
            stage(&mut batch, path, |tmp| {
                Ok(write_image(tmp, &image, exposure)?)
            })?;
        }
        return commit(batch, common);
    }
    let shows_lit = args.mode != ModeKind::Final || !common.outputs.export.is_empty();
    let solved = run_solve(scene, common, shows_lit)?;

    let render_start = Instant::now();
    let mut batch = Batch::new();
    if let Some(quantity) = args.false_colour {
        // A false-colour picture has no quick form: after a Ctrl-C it is still measured, from
        // the solution so far.
        let pictures = false_colour::pictures(args, quantity, (&solved, &camera, &raster))?;
        say(common, &pictures.note);
        for path in &outputs {
            if may_write(path, &solved, common) {
                let image = pictures.for_path(path);
                stage(&mut batch, path, |tmp| Ok(write_image(tmp, image, 0.0)?))?;
            }
        }
        let render_seconds = render_start.elapsed().as_secs_f64();
        let aspect = raster.width as f32 / raster.height.max(1) as f32;
        return finish(
            &solved,
            common,
            Some((&camera, aspect)),
            Outputs {
                batch,
                start,
                load_seconds: load,
                render_seconds,
            },
        );
    }
    // After a Ctrl-C the run ends now: a ray-traced or evaluated picture takes seconds to
    // minutes, so an interrupted solve is pictured the quick way, by its interpolated lit mesh
    // at the default samples.
    let (mode, raster) = if solved.solution.interrupted && args.mode != ModeKind::Radiosity {
        say(
            common,
            "the solve was interrupted: the picture is the solution so far, interpolated \
             (--mode radiosity)",
        );
        let quick = RasterSettings {
            samples_per_pixel: raster.samples_per_pixel.min(mode::DEFAULT_SAMPLES),
            ..raster
        };
        (ModeKind::Radiosity, quick)
    } else {
        (args.mode, raster)
    };
    let image = picture::render_mode(
        &solved,
        &camera,
        mode,
        &raster,
        args.gather,
        !args.no_shadows,
        common.run.reporting(),
    )?;
    let exposure = args
        .exposure
        .unwrap_or_else(|| tonemap::auto_exposure(&image));
    for path in &outputs {
        if may_write(path, &solved, common) {
            stage(&mut batch, path, |tmp| {
                Ok(write_image(tmp, &image, exposure)?)
            })?;
        }
    }
    let render_seconds = render_start.elapsed().as_secs_f64();
    let aspect = raster.width as f32 / raster.height.max(1) as f32;
    finish(
        &solved,
        common,
        Some((&camera, aspect)),
        Outputs {
            batch,
            start,
            load_seconds: load,
            render_seconds,
        },
    )
}

/// Loads the scene and prints its warnings; returns it with the seconds it took.
pub(crate) fn load(arg: &str, common: &CommonArgs) -> Result<(Scene, f64)> {
    let start = Instant::now();
    let mut scene = Scene::resolve(arg)?;
    if !common.run.no_default_light && scene.add_default_sky() {
        let note = format!(
            "no material emits light: the scene is lit by the default sky, a uniform enclosure of \
             radiance {} W·m⁻²·sr⁻¹ (object `{}`; --no-default-light turns it off)",
            sky::RADIANCE,
            sky::NAME
        );
        match scene
            .warnings
            .iter_mut()
            .find(|w| w.ends_with(sky::NO_LIGHT))
        {
            Some(w) => {
                w.truncate(w.len() - sky::NO_LIGHT.len());
                w.push_str(&note);
            }
            None => scene.warnings.push(note),
        }
    }
    if common.outputs.grids.is_some() && scene.grids.is_empty() {
        bail!("--grids: {arg} has no calculation grids ([[grids]] in a scene file)");
    }
    for warning in crate::warnings::summarise(&scene.warnings) {
        say(common, &format!("warning: {warning}"));
    }
    Ok((scene, start.elapsed().as_secs_f64()))
}

/// The camera and the raster of `frame` on `scene`, with `samples` per pixel: the size given,
/// or the scene's.
pub(crate) fn frame(
    scene: &Scene,
    frame: &FrameArgs,
    samples: u32,
) -> Result<(Camera, RasterSettings)> {
    let camera = pick_camera(scene, frame.camera.as_deref(), &frame.view)?;
    let raster = RasterSettings {
        width: frame.width.unwrap_or(scene.render.width),
        height: frame.height.unwrap_or(scene.render.height),
        samples_per_pixel: samples,
    };
    Ok((camera, raster))
}

/// The camera named `name`, or the scene's first, with the changes of `view` (`--eye`,
/// `--target`, `--up`, `--fov`), refused if they leave no direction to look in.
fn pick_camera(scene: &Scene, name: Option<&str>, view: &ViewArgs) -> Result<Camera> {
    let mut camera = match name {
        None => scene
            .cameras
            .first()
            .with_context(|| format!("scene `{}` has no camera", scene.name))?,
        Some(name) => scene.camera(name).with_context(|| {
            let known: Vec<&str> = scene.cameras.iter().map(|c| c.name.as_str()).collect();
            format!(
                "--camera: unknown camera `{name}` in scene `{}` (defined: {})",
                scene.name,
                known.join(", ")
            )
        })?,
    }
    .clone();
    if let Some(eye) = view.eye {
        camera.eye = eye.into();
    }
    if let Some(target) = view.target {
        camera.target = target.into();
    }
    if let Some(up) = view.up {
        camera.up = up.into();
    }
    if let Some(fov) = view.fov {
        camera.fov_y = fov;
    }
    match camera_problem(camera.eye, camera.target, camera.up, camera.fov_y) {
        Some(CameraProblem::TargetIsEye) => {
            bail!("--eye, --target: the eye and the target are the same point")
        }
        Some(CameraProblem::UpAlongView) => {
            bail!("--up: the up direction is parallel to the view direction (or zero)")
        }
        Some(CameraProblem::FieldOfView(fov)) => {
            bail!("--fov: {fov} is outside (0, 180) degrees")
        }
        None => Ok(camera),
    }
}

/// Meshes, computes form factors and solves, reporting the stages on stderr
/// ([`crate::progress::Reporting::on_stderr`]: bars on a terminal, lines otherwise).
/// Ctrl-C stops the solve (see [`Interrupted`]); `--checkpoint` and `--resume` apply. The lit
/// mesh is refined for display (`--display`) only if `shows_lit`: something will show it.
pub(crate) fn run_solve(scene: Scene, common: &CommonArgs, shows_lit: bool) -> Result<Solved> {
    let mut settings = settings::pipeline_settings(common)?;
    if !shows_lit {
        settings.display = pipeline::Display::Averaged;
    }
    let control = control(common)?;
    let progress = common.run.reporting().on_stderr();
    let solved = pipeline::solve_controlled(scene, &settings, &control, &progress);
    if let Ok(solved) = &solved {
        let subdivision = common.mesh.elements.is_some() || common.mesh.max_element_area.is_some();
        if subdivision
            && common.solver.solver == Solver::Auto
            && solved.solution.hierarchy.is_some()
        {
            say(
                common,
                "note: the subdivision asked for needs a form-factor matrix beyond --max-memory; \
                 the automatic choice took the hierarchical solver, which refines by --epsilon \
                 instead (--solver progressive keeps the subdivision)",
            );
        }
    }
    if solved.as_ref().is_ok_and(|s| s.solution.interrupted) {
        // The Ctrl-C ended the solve; the solution so far is still rendered and written, and
        // only a further Ctrl-C stops that.
        stop_flag().store(false, Ordering::SeqCst);
    }
    match (solved, &common.run.resume) {
        (Err(pipeline::PipelineError::Interrupted), _) => {
            Err(Interrupted("interrupted while meshing: wrote nothing".into()).into())
        }
        (Err(e), Some(path)) => {
            Err(e).with_context(|| format!("{}: cannot resume", path.display()))
        }
        (Err(e), None) => Err(with_flags(e)),
        (Ok(solved), _) => Ok(solved),
    }
}

/// The engine's error with the flags that get around it (the engine names its settings; the
/// command line knows its flags).
fn with_flags(e: pipeline::PipelineError) -> anyhow::Error {
    use radiosity::solve::SolveError;
    let advice = match &e {
        pipeline::PipelineError::Solve(SolveError::MatrixTooLarge { .. }) => {
            "use `--solver hierarchical` (scales to millions of elements), `--solver progressive` (no stored matrix) or raise `--max-memory`"
        }
        pipeline::PipelineError::TooManyElements { .. } => {
            "use `--solver hierarchical` (it refines on demand), lower `--elements` or raise `--max-element-area`, or raise `--max-memory`"
        }
        _ => return e.into(),
    };
    anyhow::anyhow!("{e}: {advice}")
}

/// The solve's control: the Ctrl-C flag, `--checkpoint` and `--resume`.
fn control(common: &CommonArgs) -> Result<Control> {
    let resume = match &common.run.resume {
        Some(path) => {
            let file = std::fs::File::open(path)
                .with_context(|| format!("{}: cannot resume", path.display()))?;
            let cp = Checkpoint::read(&mut std::io::BufReader::new(file))
                .map_err(|e| anyhow::anyhow!("{}: cannot resume: {e}", path.display()))?;
            Some(cp)
        }
        None => None,
    };
    let checkpoint = common.run.checkpoint.clone().map(|path| {
        let quiet = common.run.quiet;
        Checkpointing {
            every: Duration::from_secs_f64(common.run.checkpoint_every),
            save: Arc::new(move |cp: &Checkpoint| {
                let written = write_atomic(&path, |w| cp.write(w));
                if let Err(e) = written {
                    if !quiet {
                        let _ = writeln!(
                            std::io::stderr(),
                            "warning: {}: cannot write the checkpoint: {e}",
                            path.display()
                        );
                    }
                }
            }),
        }
    });
    Ok(Control {
        stop: Some(stop_flag()),
        checkpoint,
        resume,
        ..Control::default()
    })
}

/// The camera a render looked through and its image's width over height: the first camera of
/// its `.glb` exports.
pub(crate) type View<'a> = (&'a Camera, f32);

/// The outputs of a job so far (its images, staged) and the times its statistics report.
pub(crate) struct Outputs {
    /// Files written so far, renamed onto their targets together by [`finish`].
    pub batch: Batch,
    /// When the job began.
    pub start: Instant,
    /// Seconds spent loading the scene.
    pub load_seconds: f64,
    /// Seconds spent rendering (zero without a render).
    pub render_seconds: f64,
}

/// Writes the exports, the plot and the stats of a finished job beside the images already in
/// `outputs`, then lets them all appear together; `view` is the render's camera, if any (the
/// exports then carry it first, before the scene's own).
pub(crate) fn finish(
    solved: &Solved,
    common: &CommonArgs,
    view: Option<View>,
    outputs: Outputs,
) -> Result<()> {
    let Outputs {
        mut batch,
        start,
        load_seconds,
        render_seconds,
    } = outputs;
    let scene_cameras = &solved.scene.cameras;
    let first = view.map(|(camera, _)| {
        let mut camera = camera.clone();
        if !scene_cameras.contains(&camera) {
            // Moved by --eye/--target/--up/--fov: not the scene's camera of that name.
            camera.name = format!("{} (command line)", camera.name);
        }
        camera
    });
    let cameras: Vec<Camera> = first
        .iter()
        .cloned()
        .chain(
            scene_cameras
                .iter()
                .filter(|c| Some(*c) != first.as_ref())
                .cloned(),
        )
        .collect();
    let aspect = view.map_or_else(
        || solved.scene.render.width as f32 / solved.scene.render.height.max(1) as f32,
        |(_, aspect)| aspect,
    );
    let options = export::Options {
        colours: common.outputs.export_exposure,
        cameras: &cameras,
        aspect,
    };
    for path in common
        .outputs
        .export
        .iter()
        .filter(|p| may_write(p, solved, common))
    {
        let format = export::Format::of(path).context("checked by check_common")?;
        stage(&mut batch, path, |tmp| {
            Ok(format.write(tmp, solved, &options)?)
        })?;
    }
    let stats = solved.stats(&Timings {
        load: load_seconds,
        render: render_seconds,
        total: start.elapsed().as_secs_f64(),
        ..Timings::default()
    });
    if let Some(path) = common
        .outputs
        .plot
        .as_ref()
        .filter(|p| may_write(p, solved, common))
    {
        let history = &solved.solution.history;
        stage(&mut batch, path, |tmp| {
            Ok(write_convergence_svg(tmp, &solved.scene.name, history)?)
        })?;
    }
    if let Some(dir) = common
        .outputs
        .grids
        .as_ref()
        .filter(|p| may_write(p, solved, common))
    {
        let seed = common.form_factors.seed.unwrap_or(0);
        let readings = grids::measure(&solved.scene, &solved.mesh, &solved.solution, seed);
        for r in &readings {
            let s = r.statistics;
            say(
                common,
                &format!(
                    "grid {}: {} points, E_avg {} lx, E_min {} lx, E_max {} lx, U0 {:.2}",
                    r.name,
                    s.points,
                    grids::rounded(s.average),
                    grids::rounded(s.minimum),
                    grids::rounded(s.maximum),
                    s.uniformity
                ),
            );
            if let Some(df) = r.daylight_factor {
                say(
                    common,
                    &format!(
                        "grid {}: daylight factor {:.2} % on average, {:.2} % at least",
                        r.name, df.average, df.minimum
                    ),
                );
            }
        }
        let unit = solved.scene.units.name();
        io::grids::stage(&mut batch, dir, &readings, unit)
            .with_context(|| format!("{}: cannot write the grids", dir.display()))?;
    }
    if let Some(path) = common
        .outputs
        .stats
        .as_ref()
        .filter(|p| may_write(p, solved, common))
    {
        let mut json = serde_json::to_vec_pretty(&stats)?;
        json.push(b'\n');
        stage(&mut batch, path, |tmp| {
            Ok(write_atomic(tmp, |w| w.write_all(&json))?)
        })?;
    }
    commit(batch, common)?;
    say(
        common,
        &format!(
            "{}: {} patches, {} elements, {} links; {} {} iterations, residual {:.2e}; {:.2} s",
            solved.scene.name,
            stats.patches,
            stats.elements,
            stats.links,
            stats.solver.method,
            stats.solver.iterations,
            stats.solver.residual,
            stats.timings.total
        ),
    );
    if solved.solution.interrupted {
        return Err(Interrupted(format!(
            "interrupted after {} iterations: wrote the solution so far (to new files only, \
             unless --write-partial)",
            solved.solution.iterations
        ))
        .into());
    }
    Ok(())
}

/// Writes `path`'s content with `write` to a file staged in `batch`; an error names `path`.
pub(crate) fn stage(
    batch: &mut Batch,
    path: &Path,
    write: impl FnOnce(&Path) -> Result<()>,
) -> Result<()> {
    let tmp = batch.stage(path)?;
    write(&tmp).with_context(|| format!("{}: cannot write", path.display()))
}

/// Lets the staged outputs appear and says so.
fn commit(batch: Batch, common: &CommonArgs) -> Result<()> {
    for path in batch.commit()? {
        say(common, &format!("wrote {}", path.display()));
    }
    Ok(())
}

/// Checks the flags that contradict each other (a form-factor option the method has no use
/// for among them) and the `--stats`, `--plot`, `--export` and `--checkpoint` paths, before
/// any work.
pub(crate) fn check_common(common: &CommonArgs) -> Result<()> {
    if common.solver.solver == Solver::Method(solve::Method::Hierarchical) {
        if common.mesh.elements.is_some() {
            bail!("--elements does not apply to --solver hierarchical, which refines by --epsilon");
        }
        if common.mesh.max_element_area.is_some() {
            bail!(
                "--max-element-area does not apply to --solver hierarchical (its smallest \
                 element is --min-element-area)"
            );
        }
    }
    settings::pipeline_settings(common)?;
    if let Some(path) = &common.outputs.stats {
        check_directory(path)?;
    }
    if let Some(path) = &common.outputs.plot {
        check_output(path, "plot", &["svg"])?;
    }
    let formats = export::Format::ALL.map(export::Format::name);
    for path in &common.outputs.export {
        check_output(path, "export", &formats)?;
    }
    if let Some(path) = &common.run.checkpoint {
        check_directory(path)?;
    }
    Ok(())
}

/// Checks that `path` has one of the `allowed` extensions and that its directory exists.
pub(crate) fn check_output(path: &Path, what: &str, allowed: &[&str]) -> Result<()> {
    let extension = extension(path);
    if !allowed.contains(&extension.as_str()) {
        let list: Vec<String> = allowed.iter().map(|e| format!(".{e}")).collect();
        bail!(
            "{}: unsupported {what} extension {:?} (expected {})",
            path.display(),
            extension,
            list.join(", ")
        );
    }
    check_directory(path)
}

/// Checks that the directory `path` would be written in exists, before any work is done.
fn check_directory(path: &Path) -> Result<()> {
    if path.file_name().is_none() || path.is_dir() {
        bail!("{}: not a file path", path.display());
    }
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if dir.is_file() {
        bail!(
            "{}: cannot write: {} is a file, not a directory",
            path.display(),
            dir.display()
        );
    }
    if !dir.is_dir() {
        bail!(
            "{}: cannot write: directory {} does not exist",
            path.display(),
            dir.display()
        );
    }
    // Writable: create (and remove) a probe file beside it, as the atomic write will.
    let probe = dir.join(format!(".radiosity-probe-{}", std::process::id()));
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => bail!(
            "{}: cannot write in directory {}: {e}",
            path.display(),
            dir.display()
        ),
    }
}

/// The lower-case extension of `path` (empty if none).
fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default()
}

/// Whether to write `path`: always after a complete solve; after an interrupted one only if it
/// does not exist yet or `--write-partial` asks (partial results never silently replace a
/// finished run's files), saying so when it is kept.
pub(crate) fn may_write(path: &Path, solved: &Solved, common: &CommonArgs) -> bool {
    if !solved.solution.interrupted || common.outputs.write_partial || !path.exists() {
        return true;
    }
    say(
        common,
        &format!(
            "kept {}: the run was interrupted (--write-partial replaces it)",
            path.display()
        ),
    );
    false
}

/// A message on stderr unless `--quiet`.
pub(crate) fn say(common: &CommonArgs, message: &str) {
    if !common.run.quiet {
        let _ = writeln!(std::io::stderr(), "{message}");
    }
}
