//! File formats end to end: OBJ → solve → glTF binary → re-import keeps triangles, names and
//! colours; a glTF file is a scene and a `mesh` object; the Khronos validator accepts the
//! export (when node and the npm package `gltf-validator` can be had).

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::Vec3;
use radiosity::bake;
use radiosity::io::baked::write_baked;
use radiosity::io::gltf::{vertex_colours, write_glb, Placement, VertexColours};
use radiosity::mesh::Subdivision;
use radiosity::pipeline::{self, Settings, Solved};
use radiosity::progress::Silent;
use radiosity::render::Watch;
use radiosity::scene::import::gltf_file::read_gltf;
use radiosity::Scene;

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("radiosity-formats-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// A lamp over a floor in front of a wall, as OBJ + MTL in `dir`; returns the OBJ path.
fn write_obj_scene(dir: &Path) -> PathBuf {
    std::fs::write(
        dir.join("room.mtl"),
        "newmtl grey\nKd 0.6 0.6 0.6\nnewmtl red\nKd 0.7 0.1 0.1\n\
         newmtl lamp\nKd 0.5 0.5 0.5\nKe 10 9 8\n",
    )
    .expect("mtl");
    let obj = "mtllib room.mtl\n\
        v -1 0 1\nv 1 0 1\nv 1 0 -1\nv -1 0 -1\n\
        v -1 2 -1\nv 1 2 -1\n\
        v -0.25 1.5 -0.25\nv 0.25 1.5 -0.25\nv 0.25 1.5 0.25\nv -0.25 1.5 0.25\n\
        o floor\nusemtl grey\nf 1 2 3 4\n\
        o back wall\nusemtl red\nf 4 3 6 5\n\
        o lamp\nusemtl lamp\nf 7 8 9 10\n";
    let path = dir.join("room.obj");
    std::fs::write(&path, obj).expect("obj");
    path
}

fn solve(scene: Scene) -> Solved {
    let settings = Settings {
        subdivision: Subdivision::Elements(120),
        ..Settings::default()
    };
    pipeline::solve(scene, &settings, &Silent).expect("solve")
}

fn names(solved: &Solved) -> Vec<String> {
    solved
        .scene
        .objects
        .iter()
        .map(|o| o.name.clone())
        .collect()
}

/// (object name, corners, corner colours) per triangle, sorted, for order-free comparison.
type Corner = ([u32; 3], [u32; 3]);
fn key(name: &str, corners: [Vec3; 3], colours: [Vec3; 3]) -> (String, Vec<Corner>) {
    let mut c: Vec<Corner> = corners
        .iter()
        .zip(&colours)
        .map(|(p, c)| {
            (
                p.to_array().map(f32::to_bits),
                c.to_array().map(f32::to_bits),
            )
        })
        .collect();
    // Keep the winding: rotate so the smallest corner is first, without reordering.
    let first = (0..3).min_by_key(|&i| c[i]).unwrap_or(0);
    c.rotate_left(first);
    (name.to_string(), c)
}

#[test]
fn obj_to_glb_round_trip_keeps_triangles_names_and_colours() {
    let dir = temp_dir("roundtrip");
    let solved = solve(Scene::load(&write_obj_scene(&dir)).expect("obj scene"));
    let glb = dir.join("room.glb");
    let mode = VertexColours::AutoExposure;
    write_glb(
        &glb,
        &solved.lit,
        &names(&solved),
        mode,
        &Placement::default(),
    )
    .expect("write glb");

    let colours = vertex_colours(&solved.lit, mode);
    let lit = &solved.lit;
    let mut expected: Vec<_> = (0..lit.triangles.len())
        .map(|t| {
            let v = lit.triangles[t];
            let name = &solved.scene.objects[lit.triangle_object[t] as usize].name;
            key(
                name,
                v.map(|i| lit.positions[i as usize]),
                v.map(|i| colours[i as usize]),
            )
        })
        .collect();
    let back = read_gltf(&glb).expect("re-import");
    let mut got: Vec<_> = back
        .mesh
        .faces
        .iter()
        .map(|f| {
            let v: [u32; 3] = f.indices.clone().try_into().expect("triangle");
            key(
                &back.mesh.groups[f.group],
                v.map(|i| back.mesh.positions[i as usize]),
                v.map(|i| back.colours[i as usize].as_vec3()),
            )
        })
        .collect();
    expected.sort();
    got.sort();
    // Positions and colours are f32 written and read back bit for bit, so equality is exact.
    assert_eq!(got.len(), expected.len());
    assert!(got == expected, "triangles, names or colours differ");
    let mut groups = back.mesh.groups.clone();
    groups.sort();
    assert_eq!(groups, ["back wall", "floor", "lamp"]);
    // The lamp's front saturates (its back, made two-sided by the OBJ reader, does not emit).
    assert!(got
        .iter()
        .filter(|(n, _)| n == "lamp")
        .flat_map(|(_, corners)| corners)
        .any(|(_, c)| f32::from_bits(c[0]) == 1.0));

    // The glb is a scene too: the same objects, one polygon per triangle.
    let scene = Scene::load(&glb).expect("glb scene");
    assert_eq!(scene.polygons.len(), lit.triangles.len());
    let mut objects: Vec<_> = scene.objects.iter().map(|o| o.name.clone()).collect();
    objects.sort();
    assert_eq!(objects, ["back wall", "floor", "lamp"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn linear_colours_are_the_radiance() {
    let dir = temp_dir("linear");
    let solved = solve(Scene::load(&write_obj_scene(&dir)).expect("obj scene"));
    let linear = vertex_colours(&solved.lit, VertexColours::Linear);
    let doubled = vertex_colours(&solved.lit, VertexColours::Exposure(1.0));
    // Linear: L / max L, so the lamp's brightest channel is exactly 1.
    let max = solved
        .lit
        .radiosity
        .iter()
        .map(|b| b.max_element() / std::f64::consts::PI)
        .fold(0.0, f64::max);
    assert_eq!(
        linear.iter().map(|c| c.max_element()).fold(0.0, f32::max),
        1.0
    );
    for (i, b) in solved.lit.radiosity.iter().enumerate() {
        let l = (*b / std::f64::consts::PI).as_vec3();
        assert!((linear[i] - l / max as f32).abs().max_element() < 1e-6);
        // One stop doubles, then clamps to 1.
        let want = (l * 2.0).min(Vec3::ONE);
        assert!((doubled[i] - want).abs().max_element() < 1e-5, "{i}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_glb_is_usable_as_a_mesh_object() {
    let dir = temp_dir("meshobject");
    let solved = solve(Scene::load(&write_obj_scene(&dir)).expect("obj scene"));
    write_glb(
        &dir.join("room.glb"),
        &solved.lit,
        &names(&solved),
        VertexColours::AutoExposure,
        &Placement::default(),
    )
    .expect("glb");
    let toml = r#"
[materials.white]
reflectance = [0.5, 0.5, 0.5]
emission = [1.0, 1.0, 1.0]

[[objects]]
name = "imported"
shape = "mesh"
path = "room.glb"
material = "white"
transform = { translate = [10, 0, 0] }
"#;
    let scene = Scene::from_toml_str(toml, &dir.join("scene.toml")).expect("scene");
    assert_eq!(scene.objects.len(), 1);
    assert_eq!(scene.objects[0].name, "imported");
    assert_eq!(scene.polygons.len(), solved.lit.triangles.len());
    // Translated by +10 in x: every corner lies in x ∈ [9, 11].
    assert!(scene
        .polygons
        .iter()
        .flat_map(|p| &p.vertices)
        .all(|v| (9.0..=11.0).contains(&v.x)));
    let missing = toml.replace("room.glb", "nope.glb");
    let e = Scene::from_toml_str(&missing, &dir.join("scene.toml")).expect_err("missing mesh");
    assert!(e.to_string().contains("nope.glb"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A folder holding `node_modules/gltf-validator`: `$GLTF_VALIDATOR_DIR`, else a fresh
/// `npm install` into a temporary folder. `Err` says why there is none.
fn validator_dir() -> Result<PathBuf, String> {
    if let Ok(dir) = std::env::var("GLTF_VALIDATOR_DIR") {
        return Ok(PathBuf::from(dir));
    }
    let node = Command::new("node").arg("--version").output();
    if !node.is_ok_and(|o| o.status.success()) {
        return Err("node is not installed".into());
    }
    let dir = temp_dir("validator");
    let out = Command::new("npm")
        .args([
            "install",
            "--no-audit",
            "--no-fund",
            "--silent",
            "gltf-validator",
        ])
        .current_dir(&dir)
        .output()
        .map_err(|e| format!("npm cannot run: {e}"))?;
    if !out.status.success() || !dir.join("node_modules/gltf-validator").is_dir() {
        return Err(format!(
            "`npm install gltf-validator` failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    Ok(dir)
}

#[test]
fn khronos_validator_reports_no_errors() {
    let modules = match validator_dir() {
        Ok(dir) => dir,
        Err(why) => {
            println!("SKIPPED: {why}");
            return;
        }
    };
    let dir = temp_dir("validate");
    let solved = solve(Scene::load(&write_obj_scene(&dir)).expect("obj scene"));
    for (file, mode) in [
        ("auto.glb", VertexColours::AutoExposure),
        ("linear.glb", VertexColours::Linear),
    ] {
        let glb = dir.join(file);
        let placement = Placement {
            metres_per_unit: solved.scene.units.metres(),
            cameras: &solved.scene.cameras,
            aspect: 1.0,
        };
        write_glb(&glb, &solved.lit, &names(&solved), mode, &placement).expect("glb");
        let issues = validate(&modules, &glb);
        let first = issues["messages"].get(0).cloned().unwrap_or_default();
        assert_eq!(issues["numErrors"], 0, "first message: {first}");
        assert_eq!(issues["numWarnings"], 0, "first message: {first}");
    }
    // A bake: no errors and no warnings either (its infos name the light map's texture and
    // UV set, which only the material's extras use).
    let baked = bake::bake(
        &solved.scene,
        &solved.mesh,
        &solved.solution,
        &bake::Settings {
            size: bake::Size::Side(128),
            ..bake::Settings::default()
        },
        &Watch {
            progress: &Silent,
            stop: None,
        },
    )
    .expect("bakes")
    .expect("not stopped");
    let glb = dir.join("baked.glb");
    let placement = Placement {
        metres_per_unit: solved.scene.units.metres(),
        cameras: &solved.scene.cameras,
        aspect: 1.5,
    };
    write_baked(
        &glb,
        &solved.scene,
        &baked,
        &placement,
        "baked.lightmap.exr",
    )
    .expect("glb");
    let issues = validate(&modules, &glb);
    let first = issues["messages"].get(0).cloned().unwrap_or_default();
    assert_eq!(issues["numErrors"], 0, "first message: {first}");
    assert_eq!(issues["numWarnings"], 0, "first message: {first}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Khronos validator's report on the file at `glb` (`issues`: counts and messages).
fn validate(modules: &Path, glb: &Path) -> serde_json::Value {
    let script = "const v = require('gltf-validator'); const fs = require('fs');\
        v.validateBytes(new Uint8Array(fs.readFileSync(process.argv[1])))\
         .then(r => console.log(JSON.stringify(r.issues)))\
         .catch(e => { console.error(e); process.exit(1); });";
    let out = Command::new("node")
        .args(["-e", script, &glb.display().to_string()])
        .env("NODE_PATH", modules.join("node_modules"))
        .output()
        .expect("node");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let issues: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json report");
    let summary: Vec<String> = ["numErrors", "numWarnings", "numInfos", "numHints"]
        .iter()
        .map(|k| format!("{k} {}", issues[k]))
        .collect();
    println!("{}: gltf-validator: {}", glb.display(), summary.join(", "));
    issues
}

#[test]
fn a_malformed_gltf_is_reported_at_its_line_and_column() {
    let dir = temp_dir("malformed");
    // The comma after the `scenes` line is missing: `serde_json` stops at line 4, column 3.
    let text = "{\n  \"asset\": {\"version\": \"2.0\"},\n  \"scenes\": [{\"nodes\": [0]}]\n  \"nodes\": [{\"mesh\": 0}]\n}\n";
    let path = dir.join("broken.gltf");
    std::fs::write(&path, text).expect("write");
    let e = read_gltf(&path).expect_err("syntax error");
    assert_eq!(e.line_col, Some((4, 3)), "{e}");
    assert_eq!(e.file.as_deref(), Some(path.as_path()));
    // As a whole scene, and as a scene's mesh object (the inner location is in the message).
    let e = Scene::load(&path).expect_err("scene");
    assert_eq!(e.line_col, Some((4, 3)), "{e}");
    let toml = "[materials.white]\nreflectance = [0.5, 0.5, 0.5]\nemission = [1.0, 1.0, 1.0]\n\n\
                [[objects]]\nname = \"m\"\nshape = \"mesh\"\npath = \"broken.gltf\"\n\
                material = \"white\"\n";
    let e = Scene::from_toml_str(toml, &dir.join("scene.toml")).expect_err("mesh object");
    assert!(
        e.to_string()
            .contains("broken.gltf:4:3: invalid glTF: expected `,` or `}`"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// glTF lengths are metres: the built-in Cornell box (`units = "mm"`) arrives 0.56 m wide, not
/// 560 m, and its camera comes with it (at the eye, looking at the target, the same field of
/// view), read back by our own importer as Blender and three.js read it.
#[test]
fn glb_is_in_metres_and_carries_the_cameras() {
    let dir = temp_dir("units");
    let scene = radiosity::scene::builtin::load("cornell")
        .expect("built in")
        .expect("loads");
    assert_eq!(scene.units, radiosity::scene::units::Units::Millimetres);
    let solved = solve(scene);
    let glb = dir.join("cornell.glb");
    let placement = Placement {
        metres_per_unit: solved.scene.units.metres(),
        cameras: &solved.scene.cameras,
        aspect: 1.0,
    };
    write_glb(
        &glb,
        &solved.lit,
        &names(&solved),
        VertexColours::AutoExposure,
        &placement,
    )
    .expect("glb");
    let back = read_gltf(&glb).expect("re-import");
    let (lo, hi) = back.mesh.positions.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    // The published box spans 0..556 mm in x and 0..548.8 mm in y (the light's ceiling).
    assert!(
        (hi.y - 0.5488).abs() < 1e-4 && lo.y.abs() < 1e-4,
        "{lo} {hi}"
    );
    assert!((0.55..0.56).contains(&hi.x), "{hi}");
    let original = &solved.scene.cameras[0];
    let camera = &back.cameras[0];
    assert!(
        (camera.eye - original.eye * 0.001).length() < 1e-5,
        "{camera:?}"
    );
    let view = (camera.target - camera.eye).normalize();
    let expected = (original.target - original.eye).normalize();
    assert!(view.dot(expected) > 0.99999, "{view} vs {expected}");
    assert!(camera.up.dot(Vec3::Y) > 0.99999, "{:?}", camera.up);
    assert!((camera.fov_y - original.fov_y).abs() < 1e-3, "{camera:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
