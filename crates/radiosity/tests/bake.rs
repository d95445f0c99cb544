//! Bakes: each texel holds the light of its own surface point (the inverse-square law read
//! back through the atlas), nothing leaks under a box standing on the floor, two charts that
//! meet along an edge agree there, and charts never share texels.

use glam::{DVec2, Vec3};
use radiosity::bake::chart::Face;
use radiosity::bake::texels;
use radiosity::bake::{self, Baked, Settings, Size};
use radiosity::pipeline::{self, Solved};
use radiosity::progress::Silent;
use radiosity::render::{Image, Watch};
use radiosity::{Rgb, Scene};

fn solve(toml: &str) -> Solved {
    let scene = Scene::from_toml_str(toml, std::path::Path::new("bake.toml")).expect("scene");
    pipeline::solve(scene, &pipeline::Settings::default(), &Silent).expect("solve")
}

fn bake_at(solved: &Solved, density: f64) -> Baked {
    let settings = Settings {
        size: Size::Density(density),
        ..Settings::default()
    };
    let watch = Watch {
        progress: &Silent,
        stop: None,
    };
    bake::bake(
        &solved.scene,
        &solved.mesh,
        &solved.solution,
        &settings,
        &watch,
    )
    .expect("bakes")
    .expect("not stopped")
}

/// The bilinear filter of `image` at texture coordinates `uv` (texel centres at (i + ½)/w).
fn bilinear(image: &Image, uv: DVec2) -> Rgb {
    let (w, h) = (f64::from(image.width), f64::from(image.height));
    let (x, y) = (uv.x * w - 0.5, uv.y * h - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: f64, j: f64| {
        let i = i.clamp(0.0, w - 1.0) as usize;
        let j = j.clamp(0.0, h - 1.0) as usize;
        image.pixels[j * image.width as usize + i]
    };
    at(x0, y0) * ((1.0 - fx) * (1.0 - fy))
        + at(x0 + 1.0, y0) * (fx * (1.0 - fy))
        + at(x0, y0 + 1.0) * ((1.0 - fx) * fy)
        + at(x0 + 1.0, y0 + 1.0) * (fx * fy)
}

/// A 2 × 2 m floor of ρ 0.5 under a 100 cd point light 1 m over its centre, and `extra`.
fn lamp_over_floor(extra: &str) -> String {
    format!(
        r#"
[materials.floor]
reflectance = 0.5
[[objects]]
name = "floor"
material = "floor"
shape = "polygon"
vertices = [[-1.0, 0.0, -1.0], [-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0]]
[[objects]]
name = "lamp"
shape = "point"
position = [0.0, 1.0, 0.0]
intensity = 100.0
{extra}"#
    )
}

#[test]
fn each_texel_holds_the_light_of_its_own_point() {
    // Alone under the lamp, the floor's irradiance is I cos θ / r² = 100 / (1 + d²)^{3/2}:
    // 100 lx under the lamp, 19 lx at the corners. Each texel of the floor's chart, read
    // back through its texture coordinates, holds that law at its own point: measured to
    // 4e-16 (the direct light is exact and nothing else reflects); asserted within 1e-9.
    let solved = solve(&lamp_over_floor(""));
    let baked = bake_at(&solved, 32.0);
    let texels = texels::texels(&solved.scene, &baked.charts, &baked.atlas);
    let (w, h) = baked.atlas.size;
    let size = DVec2::new(f64::from(w), f64::from(h));
    let mut worst = 0.0_f64;
    for t in texels.iter().filter(|t| t.inside) {
        let d2 = f64::from(t.point.x * t.point.x + t.point.z * t.point.z);
        let law = 100.0 / (1.0 + d2).powf(1.5);
        let texel = baked.irradiance.pixels[t.index as usize].x;
        worst = worst.max((texel / law - 1.0).abs());
        // And back: the texel's point lies in the texel its coordinates name.
        let at = baked.uv(t.face, t.point).unwrap() * size;
        assert_eq!(at.y as u32 * w + at.x as u32, t.index);
    }
    assert!(texels.iter().filter(|t| t.inside).count() == 64 * 64);
    assert!(worst < 1e-9, "worst texel {worst}");
}

#[test]
fn no_light_leaks_under_a_box_on_the_floor() {
    // A closed 0.6 m box standing on the floor right under the lamp: the floor's texels under
    // it are dark (every shadow ray and every near-field path is blocked), those around it lit:
    // measured at most 0.02 % of the open floor's light, asserted within 0.1 %.
    let solved = solve(&lamp_over_floor(
        r#"
[materials.box]
reflectance = 0.5
[[objects]]
name = "box"
material = "box"
shape = "box"
min = [-0.3, 0.0, -0.3]
max = [0.3, 0.6, 0.3]
"#,
    ));
    let baked = bake_at(&solved, 40.0);
    let face = Face {
        polygon: 0,
        back: false,
    };
    let read = |x: f32, z: f32| {
        let uv = baked.uv(face, Vec3::new(x, 0.0, z)).unwrap();
        bilinear(&baked.irradiance, uv).x
    };
    // 0.9 m aside the lamp sees past the box's edge.
    let outside = read(0.9, 0.0);
    assert!(outside > 20.0, "{outside}");
    for (x, z) in [(0.0, 0.0), (0.2, 0.1), (-0.25, -0.25), (0.25, -0.1)] {
        let under = read(x, z);
        assert!(
            under < 1e-3 * outside,
            "under the box at ({x}, {z}): {under} vs {outside}"
        );
    }
}

#[test]
fn two_charts_agree_along_the_edge_they_share() {
    // The floor as two objects side by side, so two charts meet along x = 0: filtered at
    // points of that edge, each chart gives the light of the edge (its gutter holds the light
    // extrapolated past it). Measured within 2e-6 at 24 texels per unit (copying the edge's
    // light into the gutter instead left a 2.5 % step); asserted within 1e-3.
    let toml = r#"
[materials.floor]
reflectance = 0.5
[[objects]]
name = "west"
material = "floor"
shape = "polygon"
vertices = [[-1.0, 0.0, -1.0], [-1.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]
[[objects]]
name = "east"
material = "floor"
shape = "polygon"
vertices = [[0.0, 0.0, -1.0], [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0]]
[[objects]]
name = "lamp"
shape = "point"
position = [0.3, 0.8, 0.2]
intensity = 100.0
"#;
    let solved = solve(toml);
    let baked = bake_at(&solved, 24.0);
    assert_eq!(baked.charts.len(), 2);
    let (west, east) = (
        Face {
            polygon: 0,
            back: false,
        },
        Face {
            polygon: 1,
            back: false,
        },
    );
    let mut worst = 0.0_f64;
    for k in 0..=40 {
        let p = Vec3::new(0.0, 0.0, -0.95 + 0.0475 * k as f32);
        let a = bilinear(&baked.irradiance, baked.uv(west, p).unwrap()).x;
        let b = bilinear(&baked.irradiance, baked.uv(east, p).unwrap()).x;
        worst = worst.max((a / b - 1.0).abs());
    }
    assert!(worst < 1e-3, "worst step across the seam {worst}");
}

#[test]
fn charts_keep_to_their_own_texels() {
    // The built-in Cornell box (in millimetres) at 0.3 texels per unit: every covered texel belongs to one
    // chart's box, and no two charts' boxes overlap (the packer's promise), so no texel holds
    // two surfaces' light.
    let scene = Scene::resolve("cornell").expect("built in");
    let solved = pipeline::solve(scene, &pipeline::Settings::default(), &Silent).expect("solve");
    let baked = bake_at(&solved, 0.3);
    let (w, _) = baked.atlas.size;
    let covered = baked.covered.iter().filter(|&&c| c).count();
    assert!(covered > 0);
    let mut owner = vec![usize::MAX; baked.covered.len()];
    for (c, chart) in baked.charts.iter().enumerate() {
        // The chart's box: its extent in texels rounded up, one more, and the gutter twice.
        let (x0, y0) = baked.atlas.corners[c];
        let e = (chart.max - chart.min) * baked.atlas.density;
        let side = |x: f64| x.ceil() as u32 + 1 + 2 * baked.atlas.padding;
        for y in y0..(y0 + side(e.y)).min(baked.atlas.size.1) {
            for x in x0..(x0 + side(e.x)).min(w) {
                let i = (y * w + x) as usize;
                assert!(
                    owner[i] == usize::MAX,
                    "texel {i}: charts {} and {c}",
                    owner[i]
                );
                owner[i] = c;
            }
        }
    }
    for (i, &c) in baked.covered.iter().enumerate() {
        assert!(
            !c || owner[i] != usize::MAX,
            "covered texel {i} in no chart's box"
        );
    }
}

#[test]
fn a_textured_floor_keeps_its_pattern_in_the_baked_picture() {
    // A 2 × 2 m floor under the default sky, textured by a 2 × 2 black-and-white checker
    // (`map_Kd`, one square per metre): the solve reflects the texture's mean, 0.495, while
    // the baked picture shows each texel's own albedo: 0.99 · H / π on the white squares, 0 on
    // the black ones, the mean between.
    let dir = std::env::temp_dir().join(format!("radiosity-bake-texture-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let img = image::RgbImage::from_fn(2, 2, |x, y| {
        image::Rgb([if (x + y) % 2 == 0 { 255 } else { 0 }; 3])
    });
    img.save(dir.join("checker.png")).unwrap();
    std::fs::write(
        dir.join("floor.mtl"),
        "newmtl checker\nKd 0.8 0.8 0.8\nmap_Kd checker.png\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("floor.obj"),
        "mtllib floor.mtl\no floor\nv -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\n\
         vt 0 0\nvt 0 1\nvt 1 1\nvt 1 0\nusemtl checker\nf 1/1 2/2 3/3 4/4\n",
    )
    .unwrap();
    let mut scene = Scene::load(&dir.join("floor.obj")).expect("obj");
    assert!(scene.add_default_sky());
    let solved = pipeline::solve(scene, &pipeline::Settings::default(), &Silent).expect("solve");
    let baked = bake_at(&solved, 16.0);
    let texels = texels::texels(&solved.scene, &baked.charts, &baked.atlas);
    let (mut white, mut black, mut all) = (Vec::new(), Vec::new(), Vec::new());
    for t in texels.iter().filter(|t| t.inside) {
        let i = t.index as usize;
        let ratio =
            baked.radiance.pixels[i].x / (baked.irradiance.pixels[i].x / std::f64::consts::PI);
        all.push(ratio);
        // Well inside a square (a texel away from the checker's lines at x, z = 0).
        if t.point.x.abs() > 0.1 && t.point.z.abs() > 0.1 {
            if (t.point.x > 0.0) == (t.point.z > 0.0) {
                black.push(ratio);
            } else {
                white.push(ratio);
            }
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    assert!(
        white.iter().all(|r| (r - 0.99).abs() < 1e-6),
        "white {}",
        mean(&white)
    );
    assert!(
        black.iter().all(|r| r.abs() < 1e-6),
        "black {}",
        mean(&black)
    );
    assert!((mean(&all) - 0.495).abs() < 0.01, "mean {}", mean(&all));
    let _ = std::fs::remove_dir_all(&dir);
}
