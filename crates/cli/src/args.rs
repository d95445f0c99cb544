//! Command-line arguments (clap derive) and the parsers of their values.

use std::path::PathBuf;
use std::time::Duration;

use clap::{Args, Parser, Subcommand, ValueEnum};
use radiosity::color::scale::Spacing;
use radiosity::formfactor;
use radiosity::io::gltf::VertexColours;
use radiosity::pipeline::DisplayKind;
use radiosity::render::false_colour::Quantity as FalseColour;
use radiosity::render::ModeKind;

use crate::progress::Reporting;
use crate::solver::Solver;

/// Global illumination by radiosity: solve a scene once, then render it from any camera or
/// export the lit mesh.
#[derive(Debug, Parser)]
#[command(name = "radiosity", version, propagate_version = true)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Solve a scene and render it to images (default: the built-in Cornell box to cornell.png).
    Render(RenderArgs),
    /// Solve a scene without rendering an image (use --export and --stats).
    Solve(SolveArgs),
    /// Solve a scene and bake its light into light-map textures over its surfaces: a .glb that
    /// engines draw as it is (unlit, the light in its base colour) with the irradiance light
    /// map (RGBM in the file, OpenEXR beside it) on its second UV set.
    Bake(BakeArgs),
    /// Render local illumination, radiosity (and ray tracing when the scene has mirrors or
    /// glass) side by side in one labelled image.
    Compare(CompareArgs),
    /// List the built-in scenes.
    Scenes,
    /// Describe a scene without solving it: counts, area, emitted power, bounds, warnings; or a
    /// luminaire's photometric file (.ies, .ldt): flux, peak, beam and field angles, opening.
    Info(InfoArgs),
    /// Draw one element's hemicube, unfolded, coloured by the source each cell sees.
    Hemicube(HemicubeArgs),
    /// Draw a Bézier curve with its control polygon and de Casteljau construction (or a
    /// B-spline) as SVG.
    Curve(CurveArgs),
    /// Run the built-in validation suite (closed-form view factors, CIE 171:2006 integrating
    /// sphere and daylight through an opening, inverse-square law, energy conservation) and
    /// print the table.
    Validate(crate::validate::ValidateArgs),
}

/// `radiosity curve`.
#[derive(Debug, Args)]
pub struct CurveArgs {
    /// Control points as `x,y x,y …` (at least one).
    #[arg(long, value_name = "POINTS")]
    pub points: String,
    /// The parameter of the de Casteljau construction, in [0, 1].
    #[arg(long, default_value_t = 0.5)]
    pub t: f64,
    /// Draw the clamped uniform B-spline of this degree instead of the Bézier curve.
    #[arg(long, value_name = "DEGREE")]
    pub bspline: Option<u32>,
    /// The picture (.svg).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "PATH",
        default_value = "curve.svg"
    )]
    pub output: PathBuf,
}

/// `radiosity hemicube`.
#[derive(Debug, Args)]
pub struct HemicubeArgs {
    /// Scene file (.toml, .obj, .gltf, .glb) or built-in scene name (see `radiosity scenes`).
    pub scene: String,
    /// The element whose hemicube to draw (0 to elements − 1).
    #[arg(long, value_name = "ID")]
    pub element: u64,
    /// The picture (.png).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "PATH",
        default_value = "hemicube.png"
    )]
    pub output: PathBuf,
    /// Cells along a full edge of the hemicube.
    #[arg(long, value_name = "N", default_value_t = 32,
          value_parser = clap::value_parser!(u32).range(2..=4096))]
    pub resolution: u32,
    /// Colour the cells by their delta form factors instead of by what they see.
    #[arg(long)]
    pub heatmap: bool,
    /// Turn the hemicube about the normal by its random angle, as the solver does.
    #[arg(long)]
    pub rotate: bool,
    /// Seed of the rotation.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Subdivide into about N elements in total.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub elements: Option<u64>,
    /// Most light sources (quadtree nodes the hemicube sees).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub sources: Option<u64>,
}

/// `--quality`: presets of the subdivision and of hierarchical radiosity's ε, measured on the
/// evaluated picture (`render`, 256², against Mitsuba 3's, 4 × 4-pixel blocks; measured
/// figures: docs/figures.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Quality {
    /// ε = 10⁻⁴ (hierarchical radiosity), or about 4 096 elements where a uniform mesh is asked
    /// for.
    Default,
    /// ε = 3·10⁻⁵, or about 16 000 elements: a smaller error, in more time.
    Final,
}

/// `radiosity info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Scene file (.toml, .obj, .gltf, .glb) or built-in scene name (see `radiosity scenes`),
    /// or a luminaire's photometric file (.ies IES LM-63, .ldt EULUMDAT).
    pub scene: String,
    /// Count the elements of a subdivision into about N elements.
    #[arg(long, value_name = "N", conflicts_with = "max_element_area",
          value_parser = clap::value_parser!(u64).range(1..))]
    pub elements: Option<u64>,
    /// Count the elements of a subdivision to at most A (scene units²) each.
    #[arg(long, value_name = "A", value_parser = positive_f64)]
    pub max_element_area: Option<f64>,
}

/// Parses `--samples`: a square from 1 to 64 (the s × s grid of a pixel's samples; a count
/// between squares would be rounded down without a word).
fn square_samples(text: &str) -> Result<u32, String> {
    let n: u32 = text
        .parse()
        .map_err(|_| format!("`{text}` is not a whole number"))?;
    let side = (1..=8).find(|s| s * s >= n).unwrap_or(9);
    if !(1..=64).contains(&n) || side * side != n {
        return Err(format!(
            "{n} is not a square from 1 to 64 (1, 4, 9, 16, 25, 36, 49, 64): the samples of a \
             pixel form an s × s grid"
        ));
    }
    Ok(n)
}

/// The picture's size and the camera it is taken from.
#[derive(Debug, Default, Args)]
pub struct FrameArgs {
    /// Image width in pixels (of each panel, for `compare`), at most 16384 as in the scene
    /// file (default: the scene's [render] width).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16_384))]
    pub width: Option<u32>,
    /// Image height in pixels (of each panel, for `compare`), at most 16384 as in the scene
    /// file (default: the scene's [render] height).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16_384))]
    pub height: Option<u32>,
    /// Camera to render from, by name (default: the scene's first camera).
    #[arg(long, value_name = "NAME")]
    pub camera: Option<String>,
    /// Changes to that camera from the command line.
    #[command(flatten)]
    pub view: ViewArgs,
}

/// The camera from the command line: each given value replaces the chosen camera's.
#[derive(Debug, Default, Args)]
pub struct ViewArgs {
    /// Eye position, X,Y,Z in scene units (replaces the camera's).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = point)]
    pub eye: Option<[f32; 3]>,
    /// The point looked at, X,Y,Z (replaces the camera's).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = point)]
    pub target: Option<[f32; 3]>,
    /// Up direction, X,Y,Z (replaces the camera's).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = point)]
    pub up: Option<[f32; 3]>,
    /// Vertical field of view in degrees, above 0 and below 180 (replaces the camera's).
    #[arg(long, value_name = "DEGREES", value_parser = field_of_view)]
    pub fov: Option<f32>,
}

/// Parses `X,Y,Z`: three finite numbers separated by commas.
fn point(text: &str) -> Result<[f32; 3], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let numbers: Vec<f32> = parts
        .iter()
        .filter_map(|p| p.parse::<f32>().ok().filter(|x| x.is_finite()))
        .collect();
    match numbers[..] {
        [x, y, z] if parts.len() == 3 => Ok([x, y, z]),
        _ => Err(format!("`{text}` is not three finite numbers X,Y,Z")),
    }
}

/// Parses a vertical field of view: degrees strictly between 0 and 180.
fn field_of_view(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(x) if x > 0.0 && x < 180.0 => Ok(x),
        _ => Err(format!(
            "`{text}` is not an angle between 0 and 180 degrees"
        )),
    }
}

/// `radiosity render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file (.toml, .obj, .gltf, .glb) or built-in scene name (see `radiosity scenes`).
    #[arg(default_value = "cornell")]
    pub scene: String,
    /// Image to write (repeatable): .png is tone-mapped sRGB; .exr, .hdr, .pfm hold linear
    /// radiance. Default: <scene name>.png in the current directory.
    #[arg(short = 'o', long = "output", value_name = "PATH")]
    pub outputs: Vec<PathBuf>,
    /// Image size and camera.
    #[command(flatten)]
    pub frame: FrameArgs,
    /// Antialiasing samples per pixel, taken as an s×s grid: a square, 1, 4, 9, ... 64
    /// (others are refused). With `--mode final` (default 16) they are the first pass that
    /// finds the edges: it evaluates the light once per pixel and surface, and a pixel whose
    /// samples, or its neighbours' next to it, see more than one surface is sampled again for
    /// its coverage (16×16, refined to 64×64 where the surface changes). Default 64 with
    /// `--mode radiosity` (rasterized); 4 with `raytrace` and `local`.
    #[arg(long, value_parser = square_samples)]
    pub samples: Option<u32>,
    /// Exposure of .png outputs in stops (radiance × 2^STOPS); default: automatic (the
    /// log-average luminance maps to middle grey).
    #[arg(long, value_name = "STOPS", allow_negative_numbers = true, value_parser = finite_f32)]
    pub exposure: Option<f32>,
    /// Rendering mode. `final` by default: against a path tracer, its block error is a
    /// fraction of `radiosity`'s (measured figures: docs/figures.md).
    #[arg(long, value_enum, default_value_t = ModeKind::Final)]
    pub mode: ModeKind,
    /// With --mode raytrace: final-gather N rays per pixel at the first diffuse hit, plus
    /// sampled direct light (removes the meshing artefacts; 0 reads the lit mesh).
    #[arg(long, value_name = "N", default_value_t = 0,
          value_parser = clap::value_parser!(u32).range(0..=4096))]
    pub gather: u32,
    /// With --mode local: no shadow rays (the lecture's plain "OpenGL rendering").
    #[arg(long)]
    pub no_shadows: bool,
    /// Instead of the picture, each pixel shows in false colour a quantity of the surface seen
    /// through it: `lux`, the illuminance on it, or `luminance`, the luminance it sends to the
    /// eye (cd/m²); both read in these units when the emitters' radiance is given in cd/m².
    /// Computed as the picture (--mode final) computes its light. A .png gets the colours and
    /// a legend strip at the right (the colour bar with its levels and the unit); .exr, .hdr
    /// and .pfm hold the values themselves on all three channels (0 where no surface is seen).
    #[arg(long, value_enum, value_name = "QUANTITY")]
    pub false_colour: Option<FalseColour>,
    /// With --false-colour: the colour scale, `log` (equal ratios as equal steps, as lighting
    /// standards space their levels) or `linear` [default: log]
    #[arg(long, value_enum, value_name = "SCALE")]
    pub false_colour_scale: Option<Spacing>,
    /// With --false-colour: the values at the two ends of the colour scale, MIN:MAX (values
    /// beyond take the end colours). Default: fitted to the picture, from the nice number
    /// 1, 2 or 5 × 10^k at or below its smallest value (at most three decades below the top;
    /// 0 on a linear scale) to the one at or above its largest.
    #[arg(long, value_name = "MIN:MAX", allow_hyphen_values = true, value_parser = range)]
    pub false_colour_range: Option<(f64, f64)>,
    /// Options shared with `solve`.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Parses `MIN:MAX`: two finite numbers, the first below the second.
fn range(text: &str) -> Result<(f64, f64), String> {
    let bad = || format!("`{text}` is not MIN:MAX, two finite numbers with MIN below MAX");
    let (lo, hi) = text.split_once(':').ok_or_else(bad)?;
    let number = |t: &str| t.trim().parse::<f64>().ok().filter(|x| x.is_finite());
    match (number(lo), number(hi)) {
        (Some(lo), Some(hi)) if lo < hi => Ok((lo, hi)),
        _ => Err(bad()),
    }
}

/// `radiosity compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Scene file (.toml, .obj, .gltf, .glb) or built-in scene name (see `radiosity scenes`).
    #[arg(default_value = "cornell-spheres")]
    pub scene: String,
    /// The side-by-side image to write (.png, .exr, .hdr, .pfm).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "PATH",
        default_value = "compare.png"
    )]
    pub output: PathBuf,
    /// Size of each panel and camera.
    #[command(flatten)]
    pub frame: FrameArgs,
    /// Antialiasing samples per pixel, taken as an s×s grid: a square, 1, 4, 9, ... 64
    /// (others are refused).
    #[arg(long, default_value_t = 4, value_parser = square_samples)]
    pub samples: u32,
    /// Exposure in stops (default: automatic, from the radiosity panel; all panels share it).
    #[arg(long, value_name = "STOPS", allow_negative_numbers = true, value_parser = finite_f32)]
    pub exposure: Option<f32>,
    /// Final-gather rays of the ray-traced panel (see `render --gather`).
    #[arg(long, value_name = "N", default_value_t = 0,
          value_parser = clap::value_parser!(u32).range(0..=4096))]
    pub gather: u32,
    /// Options shared with `solve`.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// `radiosity solve`.
#[derive(Debug, Args)]
pub struct SolveArgs {
    /// Scene file (.toml, .obj, .gltf, .glb) or built-in scene name (see `radiosity scenes`).
    pub scene: String,
    /// Options shared with `render`.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// `radiosity bake`.
#[derive(Debug, Args)]
pub struct BakeArgs {
    /// Scene file (.toml, .obj, .gltf, .glb, .xml) or built-in scene name.
    pub scene: String,
    /// The baked model (.glb); the light map's OpenEXR goes beside it as
    /// `<name>.lightmap.exr`. Default: `<scene>.baked.glb`.
    #[arg(short = 'o', long = "output", value_name = "PATH")]
    pub output: Option<PathBuf>,
    /// The light map's side, texels (a square atlas, filled at the largest texel density that
    /// fits).
    #[arg(long, value_name = "TEXELS", conflicts_with = "texels_per_unit")]
    pub lightmap_size: Option<u32>,
    /// Texels per scene unit instead of a size: the atlas as large as that needs.
    #[arg(long, value_name = "TEXELS")]
    pub texels_per_unit: Option<f64>,
    /// Texels of gutter around each chart (at least 2).
    #[arg(long, default_value_t = 2)]
    pub padding: u32,
    /// Options shared with `solve` and `render`.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Options of every job that solves a scene, in groups (each its own help heading).
#[derive(Debug, Args)]
pub struct CommonArgs {
    /// What a solve writes besides images.
    #[command(flatten)]
    pub outputs: OutputArgs,
    /// How finely the scene is cut into elements and sources.
    #[command(flatten)]
    pub mesh: MeshArgs,
    /// How form factors are computed (each option belongs to one or more methods).
    #[command(flatten)]
    pub form_factors: FormFactorArgs,
    /// Which solver, and when it stops.
    #[command(flatten)]
    pub solver: SolverArgs,
    /// The scene's default light, checkpoints, threads and messages.
    #[command(flatten)]
    pub run: RunArgs,
}

/// What a solve writes besides images.
#[derive(Debug, Args)]
#[command(next_help_heading = "Outputs")]
pub struct OutputArgs {
    /// Write statistics (counts, timings, energy, per-object radiosity) as JSON.
    #[arg(long, value_name = "PATH")]
    pub stats: Option<PathBuf>,
    /// Plot the residual against iteration and time (.svg).
    #[arg(long, value_name = "PATH")]
    pub plot: Option<PathBuf>,
    /// Export the lit mesh (repeatable, one solve for all): .ply (float radiosity and 8-bit
    /// colours per vertex, metres), .glb (glTF with COLOR_0, metres) or .html (a
    /// self-contained WebGL2 viewer).
    #[arg(long, value_name = "PATH")]
    pub export: Vec<PathBuf>,
    /// Write the illuminance on the scene's calculation grids (`[[grids]]`) into DIR (created
    /// if missing): `<name>.csv` per grid (columns x,y,z,lux) and `grids.json` (E_avg, E_min,
    /// E_max, U₀ = E_min/E_avg, E_min/E_max per grid); direct light exact at each point,
    /// the rest gathered from the solution.
    #[arg(long, value_name = "DIR")]
    pub grids: Option<PathBuf>,
    /// Colours of the export: `auto` (radiance exposed automatically, clamped to [0, 1]),
    /// STOPS (radiance × 2^STOPS, clamped), or `linear` (.glb: radiance B/π scaled so that
    /// the brightest vertex is 1, nothing clipped; the absolute radiosity is in the
    /// `_RADIOSITY` attribute).
    #[arg(long, value_name = "auto|linear|STOPS", default_value = "auto",
          allow_negative_numbers = true, value_parser = parse_export_colours)]
    pub export_exposure: VertexColours,
    /// The lit mesh's vertex radiosity (exports, `--mode radiosity` and `raytrace`):
    /// `evaluated` at each vertex as the final picture is (exact direct light, near field) and
    /// its triangles split where interpolation misses by more than --display-tolerance, or
    /// `averaged` from the elements around each vertex (docs/raytracing.md).
    #[arg(long, value_enum, default_value_t = DisplayKind::Evaluated)]
    pub display: DisplayKind,
    /// With --display evaluated: the largest error, in per cent of the luminance, that
    /// interpolating along an edge may make at its midpoint before the edge is split.
    #[arg(long, value_name = "PERCENT", default_value_t = 1.0, value_parser = positive_f64)]
    pub display_tolerance: f64,
    /// When a solve is interrupted, replace existing outputs with the partial results too (by
    /// default an interrupted run writes only outputs that do not exist yet).
    #[arg(long)]
    pub write_partial: bool,
}

/// How finely the scene is cut into elements and sources.
#[derive(Debug, Args)]
#[command(next_help_heading = "Mesh")]
pub struct MeshArgs {
    /// Subdivide into about N elements in total (gathering and progressive solvers; contact
    /// lines add some) [default: 4096]
    #[arg(long, value_name = "N", conflicts_with = "max_element_area",
          value_parser = clap::value_parser!(u64).range(1..))]
    pub elements: Option<u64>,
    /// Subdivide until no element is larger than A (scene units²; gathering and progressive
    /// solvers).
    #[arg(long, value_name = "A", value_parser = positive_f64)]
    pub max_element_area: Option<f64>,
    /// Most light sources: quadtree nodes that shoot the mean radiosity of their elements
    /// (substructuring); with fewer sources than elements, each element opens those in its
    /// near field. Sources are the elements themselves when there are fewer elements; a
    /// gathering solver takes more where contact lines need them, within --max-memory
    /// [default: 8192]
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub sources: Option<u64>,
    /// Cut the outlines of sharp shadows (umbra and penumbra of each emitter through each
    /// convex occluder) into the mesh as element edges: discontinuity meshing (Heckbert 1992).
    /// Off by default: measured against the quadtree's shadow refinement alone it changes the
    /// Cornell box little and costs the furnished room twice the time (docs/decisions/discontinuity-meshing.md)
    #[arg(long)]
    pub discontinuity_meshing: bool,
    /// How fine a mesh to solve on when --elements and --max-element-area are not given (and
    /// hierarchical radiosity's ε when --epsilon is not).
    #[arg(long, value_enum, default_value_t = Quality::Default)]
    pub quality: Quality,
}

/// How form factors are computed (each option belongs to one or more methods).
#[derive(Debug, Args)]
#[command(next_help_heading = "Form factors")]
pub struct FormFactorArgs {
    /// Form-factor method [default: raycast]
    #[arg(long, value_enum, value_name = "METHOD")]
    pub form_factors: Option<formfactor::Method>,
    /// Quadrature points per receiver element, as an N × N grid (ray-cast and analytic form
    /// factors: Lambert's formula at each point; hemicube: one hemicube at each point); twice
    /// as many per side on elements that another surface touches [default: 2]
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=16))]
    pub quadrature: Option<u32>,
    /// Shadow rays per element–source pair, stratified (ray-cast form factors) [default: 4]
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub rays: Option<u32>,
    /// Seed of the ray-cast form factors' jitter, of the hemicubes' rotations and of the rays
    /// of the calculation grids' meter (`--grids`) [default: 0]
    #[arg(long)]
    pub seed: Option<u64>,
    /// Cells along a full edge of a hemicube (hemicube form factors) [default: 128]
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(2..=4096))]
    pub hemicube_resolution: Option<u32>,
}

/// Which solver, and when it stops.
#[derive(Debug, Args)]
#[command(next_help_heading = "Solver")]
pub struct SolverArgs {
    /// Solver of the radiosity equation.
    #[arg(long, value_enum, default_value_t = Solver::Auto)]
    pub solver: Solver,
    /// Stop iterating when the residual falls below this (relative) [default: 1e-4]
    #[arg(long, value_parser = positive_f64)]
    pub tolerance: Option<f64>,
    /// Stop after this many iterations [default: 100000]
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_iterations: Option<u64>,
    /// Memory budget of the form-factor matrix and of the image, in bytes (suffixes K, M, G, T:
    /// powers of 1024; e.g. 512M, 2G). Default: 1 GiB for the matrix, 8 GiB for the image.
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
    /// Hierarchical solver: refine a link while it moves more than this fraction of the emitted
    /// power (default 1e-4; smaller is finer and slower).
    #[arg(long, value_parser = positive_f64)]
    pub epsilon: Option<f64>,
    /// Hierarchical solver: smallest element area refinement may create (scene units²;
    /// default a millionth of the total area).
    #[arg(long, value_name = "A", value_parser = positive_f64)]
    pub min_element_area: Option<f64>,
}

/// The scene's default light, checkpoints, threads and messages.
#[derive(Debug, Args)]
#[command(next_help_heading = "Run")]
pub struct RunArgs {
    /// Leave a scene without emitters unlit (black) instead of lighting it by the default sky:
    /// a uniform white enclosure of radiance 1 W·m⁻²·sr⁻¹ around its bounds
    #[arg(long)]
    pub no_default_light: bool,
    /// Save the solver state to this file periodically and when interrupted, also during the
    /// form factors (every solver; the gathering solvers' checkpoint holds the form-factor rows
    /// computed so far, so a resumed run computes only the missing ones; binary).
    #[arg(long, value_name = "PATH")]
    pub checkpoint: Option<PathBuf>,
    /// Seconds between two checkpoints.
    #[arg(long, value_name = "SECONDS", default_value_t = 60.0, value_parser = positive_f64)]
    pub checkpoint_every: f64,
    /// Continue the solve from a checkpoint of the same scene and settings.
    #[arg(long, value_name = "PATH")]
    pub resume: Option<PathBuf>,
    /// Worker threads (default: one per core). Results do not depend on it.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=4096))]
    pub threads: Option<u64>,
    /// No progress bars, progress lines, warnings or messages on stderr (errors are still
    /// printed).
    #[arg(short, long)]
    pub quiet: bool,
    /// When stderr is not a terminal (a log file, CI), progress comes as lines instead of
    /// bars: `STAGE done: COUNT WHAT, ... in S s` as each stage (meshing, form factors, solve,
    /// hierarchical, display, render) ends (`STAGE stopped: ...` after a Ctrl-C), and `STAGE
    /// (PHASE): DONE/TOTAL UNIT after S s` every this many seconds within it (0: at its start,
    /// at each phase and at every step).
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0, value_parser = interval)]
    pub progress_every: f64,
}

impl RunArgs {
    /// The reporting its flags ask for: `--quiet` and `--progress-every`.
    pub fn reporting(&self) -> Reporting {
        Reporting {
            quiet: self.quiet,
            every: Duration::from_secs_f64(self.progress_every),
        }
    }
}

/// `--export-exposure`: `auto`, `linear` or a finite number of stops.
fn parse_export_colours(s: &str) -> Result<VertexColours, String> {
    match s.trim().to_ascii_lowercase().as_str() {
        "auto" => Ok(VertexColours::AutoExposure),
        "linear" => Ok(VertexColours::Linear),
        _ => finite_f32(s)
            .map(VertexColours::Exposure)
            .map_err(|_| format!("`{s}` is not `auto`, `linear` or a number of stops")),
    }
}

/// A finite floating-point number.
fn finite_f32(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("`{s}` is not a finite number")),
    }
}

/// A finite number greater than zero.
fn positive_f64(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err(format!("`{s}` is not a positive number")),
    }
}

/// An interval in seconds: a number from 0 to 10⁹ (about 32 years).
fn interval(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if (0.0..=1e9).contains(&x) => Ok(x),
        _ => Err(format!("`{s}` is not a number of seconds from 0 to 1e9")),
    }
}

/// A byte count: a number with an optional suffix K, M, G or T (powers of 1024, optionally
/// followed by `B` or `iB`, any case), e.g. `2G`, `512M`, `1.5GiB`, `1000000`.
pub fn parse_bytes(s: &str) -> Result<u64, String> {
    let bad = || format!("`{s}` is not a byte count (e.g. 512M, 2G)");
    let t = s.trim().to_ascii_uppercase();
    let t = t
        .strip_suffix("IB")
        .or_else(|| t.strip_suffix('B'))
        .unwrap_or(&t);
    let (number, shift) = match t.chars().last() {
        Some('K') => (&t[..t.len() - 1], 10),
        Some('M') => (&t[..t.len() - 1], 20),
        Some('G') => (&t[..t.len() - 1], 30),
        Some('T') => (&t[..t.len() - 1], 40),
        _ => (t, 0),
    };
    let value: f64 = number.trim().parse().map_err(|_| bad())?;
    let bytes = value * (1u64 << shift) as f64;
    if !(bytes.is_finite() && bytes >= 1.0 && bytes < u64::MAX as f64) {
        return Err(bad());
    }
    Ok(bytes.round() as u64)
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    use super::*;

    #[test]
    fn help_states_the_engines_defaults() {
        let mut cli = Cli::command();
        let solve = cli.find_subcommand_mut("solve").expect("solve");
        let help = solve.render_long_help().to_string();
        let ff = radiosity::formfactor::Settings::default();
        let radiosity::formfactor::Settings::RayCast(rays) = ff else {
            panic!("the default form factors are ray-cast: {ff:?}");
        };
        let solver = radiosity::solve::Settings::default();
        for (flag, default) in [
            ("--elements", radiosity::mesh::DEFAULT_ELEMENTS.to_string()),
            ("--form-factors", ff.method().name().to_string()),
            ("--sources", solver.max_sources.to_string()),
            ("--quadrature", rays.quadrature.to_string()),
            ("--rays", rays.rays.to_string()),
            ("--tolerance", format!("{:e}", solver.tolerance)),
            ("--max-iterations", solver.max_iterations.to_string()),
        ] {
            let at = help.find(&format!("{flag} ")).expect(flag);
            let next = help[at + 2..]
                .find("\n      --")
                .map_or(help.len(), |k| at + 2 + k);
            let text = help[at..next].replace('\n', " ");
            assert!(text.contains(&format!("[default: {default}]")), "{text}");
        }
    }

    #[test]
    fn byte_counts_with_binary_suffixes() {
        assert_eq!(parse_bytes("2G"), Ok(2 << 30));
        assert_eq!(parse_bytes("512M"), Ok(512 << 20));
        assert_eq!(parse_bytes("512mb"), Ok(512 << 20));
        assert_eq!(parse_bytes("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_bytes("4k"), Ok(4096));
        assert_eq!(parse_bytes("1000000"), Ok(1_000_000));
        for bad in ["", "G", "-1G", "0", "1X", "nanG", "1e30T"] {
            assert!(parse_bytes(bad).is_err(), "{bad:?} accepted");
        }
    }

    #[test]
    fn ranges_are_two_increasing_numbers() {
        assert_eq!(range("50:2000"), Ok((50.0, 2000.0)));
        assert_eq!(range("-1:0.5"), Ok((-1.0, 0.5)));
        for bad in ["", "100", "5:5", "9:1", "a:b", "1:inf", "1:2:3"] {
            assert!(range(bad).is_err(), "{bad:?} accepted");
        }
    }

    #[test]
    fn numbers_must_be_finite_and_positive() {
        assert_eq!(positive_f64("0.25"), Ok(0.25));
        assert!(positive_f64("0").is_err());
        assert!(positive_f64("inf").is_err());
        assert_eq!(finite_f32("-2"), Ok(-2.0));
        assert!(finite_f32("NaN").is_err());
    }

    #[test]
    fn clap_definition_is_consistent() {
        Cli::command().debug_assert();
    }
}
