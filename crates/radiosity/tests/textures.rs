//! Textures as reflectance, from file to solve: a glTF `baseColorTexture` (× factor) and an
//! MTL `map_Kd` give each patch the mean of its texture over the patch's footprint, in linear
//! light; a texture that cannot be read is a warning and the material keeps its factor.

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Vec2, Vec3};
use radiosity::mesh::{Mesh, Subdivision};
use radiosity::progress::Silent;
use radiosity::scene::texture::{Texture, TextureMap, Wrap};
use radiosity::solve::{self, Method, Settings};
use radiosity::testing::{self, Prepared};
use radiosity::{formfactor, Rgb, Scene};

/// A fresh folder for one test's files.
fn folder(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("radiosity-textures-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A PNG of `w` × `h` 8-bit grey codes given per texel.
fn png(w: u32, h: u32, code: impl Fn(u32, u32) -> u8) -> Vec<u8> {
    let img = image::RgbImage::from_fn(w, h, |x, y| image::Rgb([code(x, y); 3]));
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .unwrap();
    bytes
}

/// The 2 × 2 black-and-white checker.
fn checker() -> Vec<u8> {
    png(2, 2, |x, y| if (x + y) % 2 == 0 { 255 } else { 0 })
}

fn base64(bytes: &[u8]) -> String {
    const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            s.push(if k <= chunk.len() {
                A[(n >> (18 - 6 * k) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    s
}

/// The floor quad's buffer: positions of the unit square at y = 0 facing up, UVs over the
/// whole texture, and two triangles (92 bytes).
fn floor_buffer() -> Vec<u8> {
    let positions = [
        0.0f32, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0,
    ];
    let uv = [0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0];
    let indices = [0u16, 1, 2, 0, 2, 3];
    let mut b: Vec<u8> = positions.iter().flat_map(|f| f.to_le_bytes()).collect();
    b.extend(uv.iter().flat_map(|f| f.to_le_bytes()));
    b.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    b
}

/// A glTF of the floor quad whose material has base colour factor (0.8, 0.6, 0.4) and the
/// texture `image` (a glTF image object); the buffer is `buffer` (a buffer object).
fn floor_gltf(image: &str, buffer: &str, extra_views: &str) -> String {
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"name": "floor", "mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1}},
    "indices": 2, "material": 0}}]}}],
  "materials": [{{"name": "tiles", "pbrMetallicRoughness": {{
    "baseColorFactor": [0.8, 0.6, 0.4, 1], "baseColorTexture": {{"index": 0}}}}}}],
  "textures": [{{"source": 0}}],
  "images": [{image}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
      "min": [0, 0, 0], "max": [1, 0, 1]}},
    {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}},
    {{"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 48}},
    {{"buffer": 0, "byteOffset": 48, "byteLength": 32}},
    {{"buffer": 0, "byteOffset": 80, "byteLength": 12}}{extra_views}],
  "buffers": [{buffer}]}}"#
    )
}

/// A binary glTF of `json` and the binary chunk `bin`.
fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    json.resize(json.len().next_multiple_of(4), b' ');
    let mut bin = bin.to_vec();
    bin.resize(bin.len().next_multiple_of(4), 0);
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

/// The floor's base colour factor, as the file stores it (f32).
fn factor() -> Rgb {
    Vec3::new(0.8, 0.6, 0.4).as_dvec3()
}

/// The reflectance of every patch of the scene.
fn patch_reflectances(scene: &Scene) -> Vec<Rgb> {
    let mesh = Mesh::build(scene, Subdivision::Elements(8));
    mesh.patches.iter().map(|p| p.reflectance).collect()
}

fn close(a: Rgb, b: Rgb) -> bool {
    (a - b).abs().max_element() < 1e-12
}

/// The checker's linear mean is ½ (black 0, white 1), so each of the floor's two triangles
/// (each covers half of every texel its diagonal crosses, and one whole texel of each colour
/// between) reflects ½ × factor: the same whether the image is embedded in the `.glb`, a data
/// URI or a file beside the `.gltf`. Before textures were read the factor alone was used.
#[test]
fn a_gltf_checker_floor_reflects_its_mean_times_the_factor() {
    let dir = folder("gltf");
    let expected = 0.5 * factor();
    let buffer = floor_buffer();
    let data_uri = |mime: &str, b: &[u8]| format!("data:{mime};base64,{}", base64(b));

    let embedded = floor_gltf(
        &format!(r#"{{"uri": "{}"}}"#, data_uri("image/png", &checker())),
        &format!(
            r#"{{"byteLength": 92, "uri": "{}"}}"#,
            data_uri("application/octet-stream", &buffer)
        ),
        "",
    );
    std::fs::write(dir.join("data.gltf"), &embedded).unwrap();

    std::fs::write(dir.join("checker.png"), checker()).unwrap();
    let beside = floor_gltf(
        r#"{"uri": "checker.png"}"#,
        &format!(
            r#"{{"byteLength": 92, "uri": "{}"}}"#,
            data_uri("application/octet-stream", &buffer)
        ),
        "",
    );
    std::fs::write(dir.join("beside.gltf"), &beside).unwrap();

    let mut bin = buffer.clone();
    let image = checker();
    bin.extend(&image);
    let binary = floor_gltf(
        r#"{"bufferView": 3, "mimeType": "image/png"}"#,
        &format!(r#"{{"byteLength": {}}}"#, bin.len()),
        &format!(
            r#", {{"buffer": 0, "byteOffset": 92, "byteLength": {}}}"#,
            image.len()
        ),
    );
    std::fs::write(dir.join("floor.glb"), glb(&binary, &bin)).unwrap();

    for name in ["data.gltf", "beside.gltf", "floor.glb"] {
        let scene = Scene::load(&dir.join(name)).unwrap();
        assert!(
            !scene
                .warnings
                .iter()
                .any(|w| w.contains("baseColorTexture")),
            "{name}: {:?}",
            scene.warnings
        );
        let rho = patch_reflectances(&scene);
        assert_eq!(rho.len(), 2, "{name}");
        for r in rho {
            assert!(close(r, expected), "{name}: {r} vs {expected}");
        }
        // Without UVs a polygon takes the image's mean: the same here.
        assert!(close(scene.materials[0].reflectance, expected), "{name}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// An OBJ quad with `vt` and an MTL `map_Kd`: the texture replaces `Kd`. Over the whole
/// checker ρ = ½; with UVs over the left (white) half of a white|black image, white (clamped
/// below 1); `-clamp on` with UVs beyond the right edge, black.
#[test]
fn an_obj_map_kd_gives_the_mean_over_each_face() {
    let dir = folder("obj");
    std::fs::write(dir.join("checker.png"), checker()).unwrap();
    std::fs::write(
        dir.join("halves.png"),
        png(2, 1, |x, _| if x == 0 { 255 } else { 0 }),
    )
    .unwrap();
    std::fs::write(
        dir.join("floor.mtl"),
        "newmtl tiles\nmap_Kd checker.png\nKd 0.3 0.3 0.3\n\
         newmtl white\nKd 0.3\nmap_Kd halves.png\n\
         newmtl edge\nmap_Kd -clamp on halves.png\n",
    )
    .unwrap();
    let quad = |y: f32, u0: f32, u1: f32| {
        format!(
            "v 0 {y} 0\nv 0 {y} 1\nv 1 {y} 1\nv 1 {y} 0\n\
             vt {u0} 1\nvt {u0} 0\nvt {u1} 0\nvt {u1} 1\nf -4/-4 -3/-3 -2/-2 -1/-1\n"
        )
    };
    let obj = format!(
        "mtllib floor.mtl\ng tiles\nusemtl tiles\n{}g white\nusemtl white\n{}g edge\nusemtl edge\n{}",
        quad(0.0, 0.0, 1.0),
        quad(1.0, 0.0, 0.5),
        quad(2.0, 1.5, 3.0)
    );
    std::fs::write(dir.join("floor.obj"), obj).unwrap();
    let scene = Scene::load(&dir.join("floor.obj")).unwrap();
    assert!(
        scene.warnings.iter().all(|w| !w.contains("map_Kd")),
        "{:?}",
        scene.warnings
    );
    let rho: Vec<f64> = scene
        .polygons
        .iter()
        .map(|p| scene.materials[p.material].reflectance_of(p).x)
        .collect();
    assert_eq!(rho.len(), 3);
    assert!((rho[0] - 0.5).abs() < 1e-12, "{rho:?}");
    assert_eq!(rho[1], radiosity::scene::MAX_REFLECTANCE, "{rho:?}");
    assert_eq!(rho[2], 0.0, "{rho:?}");
    // The patches carry the same values (front and back: the OBJ scene is two-sided).
    let patches = patch_reflectances(&scene);
    assert_eq!(patches.len(), 6);
    assert!((patches[0].x - 0.5).abs() < 1e-12 && (patches[1].x - 0.5).abs() < 1e-12);
    std::fs::remove_dir_all(&dir).ok();
}

/// A texture that is missing or not an image is a warning naming the file, and the material
/// keeps its factor (glTF) or `Kd` (MTL).
#[test]
fn an_unreadable_texture_is_a_warning_and_the_factor_stays() {
    let dir = folder("missing");
    let buffer = floor_buffer();
    std::fs::write(dir.join("broken.png"), b"not a png").unwrap();
    for image in ["missing.png", "broken.png"] {
        let json = floor_gltf(
            &format!(r#"{{"uri": "{image}"}}"#),
            &format!(
                r#"{{"byteLength": 92, "uri": "data:application/octet-stream;base64,{}"}}"#,
                base64(&buffer)
            ),
            "",
        );
        let path = dir.join("floor.gltf");
        std::fs::write(&path, json).unwrap();
        let scene = Scene::load(&path).unwrap();
        let warning = scene
            .warnings
            .iter()
            .find(|w| w.contains(image))
            .unwrap_or_else(|| panic!("{image}: {:?}", scene.warnings));
        assert!(warning.contains("its factor is used"), "{warning}");
        for r in patch_reflectances(&scene) {
            assert!(close(r, factor()), "{r}");
        }
    }
    std::fs::write(
        dir.join("q.mtl"),
        "newmtl m\nKd 0.25\nmap_Kd textures\\gone.png\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("q.obj"),
        "mtllib q.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    let scene = Scene::load(&dir.join("q.obj")).unwrap();
    let warning = scene
        .warnings
        .iter()
        .find(|w| w.contains("gone.png"))
        .unwrap();
    assert!(
        warning.starts_with(&format!("{}:3:1: map_Kd", dir.join("q.mtl").display())),
        "{warning}"
    );
    assert!(
        warning.contains("textures/gone.png") && warning.ends_with("Kd used"),
        "{warning}"
    );
    assert_eq!(scene.materials[0].reflectance, Rgb::splat(0.25));
    std::fs::remove_dir_all(&dir).ok();
}

/// The closed cube of uniform ρ, one wall textured with a uniformly grey image whose linear
/// value is ρ: the energy identity Σ A B = Σ A E/(1 − ρ) still holds, and the solution is the
/// untextured one (the wall's patch mean equals ρ to rounding).
#[test]
fn a_closed_room_with_a_uniformly_textured_wall_keeps_its_energy() {
    let grey = Texture::decode(&png(4, 4, |_, _| 188), false).unwrap();
    let rho = grey.mean().x;
    assert!((rho - 0.5029).abs() < 1e-4, "sRGB 188 is linear {rho}");
    let plain = testing::closed_cube(rho, [0.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let mut textured = plain.clone();
    textured.materials[0].texture = Some(TextureMap {
        texture: Arc::new(grey),
        wrap: [Wrap::Repeat; 2],
        factor: Rgb::ONE,
    });
    textured.polygons[0].uv = Some(vec![
        Vec2::new(0.1, 0.2),
        Vec2::new(3.7, 0.0),
        Vec2::new(3.9, 2.5),
        Vec2::new(-0.4, 2.2),
    ]);
    let solve = |scene: &Scene| {
        let p = Prepared::new(scene, Subdivision::Elements(96), 10_000);
        let g = p.geometry();
        let ff = formfactor::build(&formfactor::Settings::of(formfactor::Method::Analytic));
        let settings = Settings {
            tolerance: 1e-10,
            max_iterations: 1_000_000,
            ..Settings::default()
        };
        let s = solve::solve(&g, ff.as_ref(), Method::GaussSeidel, &settings, &Silent).unwrap();
        let power: Rgb = (0..g.mesh.element_count())
            .map(|e| s.radiosity[e] * g.mesh.element(e).area())
            .sum();
        (s.radiosity, power)
    };
    let (b_plain, _) = solve(&plain);
    let (b_textured, power) = solve(&textured);
    // As in tests/energy.rs: f32 form factors, residual 1e-10.
    let expected = std::f64::consts::PI / (1.0 - rho);
    assert!(
        (power.x - expected).abs() < 1e-6 * expected,
        "{power} vs {expected}"
    );
    for (a, b) in b_plain.iter().zip(&b_textured) {
        assert!(
            (*a - *b).abs().max_element() < 1e-9 * a.max_element(),
            "{a} vs {b}"
        );
    }
}
