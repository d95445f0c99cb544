//! The HTML viewer: self-contained (no URL to anything outside the file), and drawing the same
//! picture as the rasterizer, checked in headless Chromium when it is installed.

use std::path::{Path, PathBuf};
use std::process::Command;

use radiosity::io::html::{self, viewer_html, Viewer};
use radiosity::mesh::Subdivision;
use radiosity::pipeline::{self, Settings, Solved};
use radiosity::progress::Silent;
use radiosity::render::{self, tonemap, RasterSettings};
use radiosity::Scene;

/// The built-in Cornell box, coarsely solved (a few hundred elements keep the test quick).
fn cornell() -> Solved {
    let scene = Scene::resolve("cornell").expect("built-in Cornell box");
    let settings = Settings {
        subdivision: Subdivision::Elements(300),
        ..Settings::default()
    };
    pipeline::solve(scene, &settings, &Silent).expect("solve")
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("radiosity-viewer-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

#[test]
fn page_references_nothing_outside_itself() {
    let solved = cornell();
    let edges = html::element_edges(&solved.mesh);
    let page = viewer_html(&Viewer {
        title: &solved.scene.name,
        lit: &solved.lit,
        edges: &edges,
        cameras: &solved.scene.cameras,
        exposure: 0.0,
    });
    let lower = page.to_ascii_lowercase();
    // No scheme that fetches anything, no external script, style, image or font.
    for needle in [
        "http:",
        "https:",
        "ftp:",
        "ws:",
        "wss:",
        "//cdn",
        "src=",
        "href=",
        "@import",
        "url(",
        "fetch(",
        "xmlhttprequest",
        "import(",
    ] {
        assert!(!lower.contains(needle), "the page contains `{needle}`");
    }
    // Every quadtree element is outlined once: four edges per (quad) element on front sides.
    let front = (0..solved.mesh.element_count())
        .filter(|&e| !solved.mesh.element_patch(e).back)
        .map(|e| solved.mesh.element(e).face.corners().len())
        .sum::<usize>();
    assert_eq!(edges.len(), front);
}

/// The chromium binary, if any.
fn chromium() -> Option<PathBuf> {
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|name| {
            let out = Command::new("which").arg(name).output().ok()?;
            let path = String::from_utf8(out.stdout).ok()?.trim().to_string();
            (out.status.success() && !path.is_empty()).then(|| PathBuf::from(path))
        })
}

/// Decodes an 8-bit RGB or RGBA PNG into RGB bytes and its size.
fn read_png(path: &Path) -> (Vec<u8>, u32, u32) {
    let decoder = png::Decoder::new(std::fs::File::open(path).expect("screenshot"));
    let mut reader = decoder.read_info().expect("png header");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("png frame");
    let channels = match info.color_type {
        png::ColorType::Rgba => 4,
        png::ColorType::Rgb => 3,
        other => panic!("unexpected PNG colour type {other:?}"),
    };
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let rgb = buf[..info.buffer_size()]
        .chunks(channels)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    (rgb, info.width, info.height)
}

#[test]
fn browser_screenshot_matches_the_rasterizer() {
    let Some(chromium) = chromium() else {
        println!("SKIPPED: no chromium on PATH (Debian: apt-get install chromium)");
        return;
    };
    let (w, h) = (320u32, 320u32);
    let solved = cornell();
    let camera = &solved.scene.cameras[0];
    let raster = RasterSettings {
        width: w,
        height: h,
        samples_per_pixel: 4,
    };
    let image = render::render(&solved.lit, camera, &raster);
    let exposure = tonemap::auto_exposure(&image);
    let expected = tonemap::to_srgb8(&image, exposure);

    let dir = temp_dir("shot");
    let page = dir.join("cornell.html");
    html::write_solved(&page, &solved, Some(exposure)).expect("write viewer");
    let shot = dir.join("shot.png");
    let profile = dir.join("profile");
    let status = Command::new(&chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--virtual-time-budget=5000",
            "--disable-background-networking",
            "--no-first-run",
            "--hide-scrollbars",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--window-size={w},{h}"))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("file://{}#ui=0", page.display()))
        .output()
        .expect("run chromium");
    assert!(
        shot.exists(),
        "chromium wrote no screenshot: {}",
        String::from_utf8_lossy(&status.stderr)
    );
    let (got, gw, gh) = read_png(&shot);
    assert_eq!((gw, gh), (w, h));

    // Both draw the same triangles with the same projection, interpolation and tone curve;
    // they differ in antialiasing (4 stratified samples vs the GPU's multisampling), in
    // rasterization rules along edges and in 8-bit rounding. Tolerance: a mean difference of
    // 2 codes (of 255) and at most 2 % of pixels off by more than 24 codes, which only edge
    // pixels reach (measured with SwiftShader: 1.0 code and 1.0 %). An exposure off by a
    // third of a stop (×1.26) moves mid-grey sRGB codes by about 12, failing the mean.
    let diff: Vec<u32> = got
        .iter()
        .zip(&expected)
        .map(|(&a, &b)| u32::from(a.abs_diff(b)))
        .collect();
    let mean = diff.iter().sum::<u32>() as f64 / diff.len() as f64;
    let far = diff.chunks(3).filter(|p| p.iter().any(|&d| d > 24)).count() as f64 / (w * h) as f64;
    println!(
        "screenshot vs raster: mean |Δ| = {mean:.2} codes, {:.2} % pixels off by > 24",
        far * 100.0
    );
    assert!(mean < 2.0, "mean difference {mean:.2} codes");
    assert!(
        far < 0.03,
        "{:.2} % of pixels differ by more than 24 codes",
        far * 100.0
    );
    let _ = std::fs::remove_dir_all(&dir);
}
