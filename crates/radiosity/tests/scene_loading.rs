//! Scene loading end to end: the built-in scenes against their published geometry, OBJ/MTL
//! features, and every kind of bad input reported on one line with its line, column and key.

use std::path::{Path, PathBuf};

use glam::Vec3;
use model::polymesh::vector_area;
use radiosity::scene::{builtin, Scene, SceneError};
use radiosity::Rgb;

/// Area of the polygons of object `name`.
fn object_area(scene: &Scene, name: &str) -> f64 {
    let o = scene.objects.iter().position(|o| o.name == name).unwrap();
    scene
        .polygons
        .iter()
        .filter(|p| p.object == o)
        .map(|p| f64::from(vector_area(&p.vertices).length()))
        .sum()
}

fn centroid(vs: &[Vec3]) -> Vec3 {
    vs.iter().copied().sum::<Vec3>() / vs.len() as f32
}

#[test]
fn cornell_box_matches_the_published_geometry() {
    let scene = builtin::load("cornell").unwrap().unwrap();
    assert_eq!(scene.name, "cornell");
    // floor, light, 4 ceiling quads, back, right, left, 5 + 5 block faces.
    assert_eq!(scene.polygons.len(), 19);
    assert_eq!(scene.objects.len(), 8);
    // Closed forms from the published millimetre coordinates (trapezoids and rectangles).
    // Tolerance: f32 coordinates near 500 carry ~3e-5 relative error, areas twice that.
    let expected = [
        ("floor", 559.2 * (552.8 + 549.6) / 2.0),
        ("ceiling", 556.0 * 559.2 - 130.0 * 105.0),
        ("light", 130.0 * 105.0),
        ("back_wall", 548.8 * (549.6 + 556.0) / 2.0),
        ("right_wall", 548.8 * 559.2),
    ];
    for (name, area) in expected {
        let got = object_area(&scene, name);
        assert!((got - area).abs() / area < 1e-4, "{name}: {got} vs {area}");
    }
    // The left wall is slightly non-planar: its Newell area is within 0.5 % of 548.8 × 559.2.
    let left = object_area(&scene, "left_wall");
    assert!((left / (548.8 * 559.2) - 1.0).abs() < 5e-3, "{left}");
    // Every wall faces into the box; every block face faces out of its block.
    let box_centre = Vec3::new(278.0, 274.4, 279.6);
    let block_centre = |name: &str| {
        let o = scene.objects.iter().position(|o| o.name == name).unwrap();
        let vs: Vec<Vec3> = scene
            .polygons
            .iter()
            .filter(|p| p.object == o)
            .flat_map(|p| p.vertices.clone())
            .collect();
        (o, centroid(&vs))
    };
    let blocks = [block_centre("short_block"), block_centre("tall_block")];
    for p in &scene.polygons {
        let n = vector_area(&p.vertices);
        let c = centroid(&p.vertices);
        match blocks.iter().find(|(o, _)| *o == p.object) {
            Some((_, centre)) => assert!(n.dot(c - *centre) > 0.0, "block face {p:?}"),
            None => assert!(n.dot(box_centre - c) > 0.0, "wall {p:?}"),
        }
    }
    let light = &scene.materials[scene.polygons[1].material];
    assert_eq!(light.emission, Rgb::new(17.0, 12.0, 4.0));
    let cam = &scene.cameras[0];
    assert_eq!(cam.eye, Vec3::new(278.0, 273.0, -800.0));
    assert_eq!(cam.fov_y, 39.3077);
}

#[test]
fn furnace_cube_is_closed_and_faces_inward() {
    let scene = builtin::load("furnace").unwrap().unwrap();
    let total: Vec3 = scene
        .polygons
        .iter()
        .map(|p| vector_area(&p.vertices))
        .sum();
    // A closed surface has zero total vector area (exact here: unit coordinates).
    assert!(total.length() < 1e-6, "{total}");
    let centre = Vec3::splat(0.5);
    for p in &scene.polygons {
        let n = vector_area(&p.vertices);
        assert!((n.length() - 1.0).abs() < 1e-6);
        assert!(n.dot(centre - centroid(&p.vertices)) > 0.0, "{p:?}");
        assert_eq!(scene.materials[p.material].reflectance, Rgb::splat(0.5));
    }
    let emitters = scene
        .polygons
        .iter()
        .filter(|p| scene.materials[p.material].is_emitter())
        .count();
    assert_eq!(emitters, 1);
}

#[test]
fn resolve_finds_built_ins_and_reports_unknown_names() {
    assert_eq!(Scene::resolve("furnace").unwrap().polygons.len(), 6);
    let e = Scene::resolve("no_such_scene").unwrap_err().to_string();
    assert!(e.contains("cornell") && !e.contains('\n'), "{e}");
}

/// A fresh folder under the system temp dir.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("radiosity-scene-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const OBJ: &str = "# two groups\n\
mtllib lamp.mtl\n\
v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0 # a comment after values\nv 0 1 0\n\
g pentagon\nusemtl matte\nf 1/1/1 2/2/2 3/3/3 4/4/4 5/5/5\n\
o lamp\nv 0 0 1\nv 1 0 1\nv 1 1 1\nusemtl lamp\nf -3 -1 -2\n\
f 1 2 2\n";

const MTL: &str = "newmtl matte\nKd 0.25 0.5 0.75\nNs 10\nnewmtl lamp\nKd 0.1\nKe 2 2 2\n";

#[test]
fn bare_obj_scene_has_groups_two_sided_materials_and_a_framed_camera() {
    let dir = temp_dir("bare");
    std::fs::write(dir.join("m.obj"), OBJ).unwrap();
    std::fs::write(dir.join("lamp.mtl"), MTL).unwrap();
    let scene = Scene::load(&dir.join("m.obj")).unwrap();
    let names: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["pentagon", "lamp"]);
    // The degenerate `f 1 2 2` is skipped with a counted warning.
    assert_eq!(scene.polygons.len(), 2);
    assert!(scene
        .warnings
        .iter()
        .any(|w| w.contains("skipped 1 degenerate")));
    assert_eq!(scene.polygons[0].vertices.len(), 5);
    // `f -3 -1 -2` is (6, 8, 7) 1-based: reversed winding, facing -z.
    assert!(vector_area(&scene.polygons[1].vertices).z < 0.0);
    let matte = &scene.materials[scene.polygons[0].material];
    assert_eq!(matte.reflectance, Rgb::new(0.25, 0.5, 0.75));
    assert!(matte.two_sided);
    assert_eq!(
        scene.materials[scene.polygons[1].material].emission,
        Rgb::splat(2.0)
    );
    // Framed facing the two polygons (both in planes z = const), not edge-on from the side.
    let cam = &scene.cameras[0];
    let view = (cam.target - cam.eye).normalize();
    assert!(view.z.abs() > 0.99 && cam.fov_y == 40.0, "{cam:?}");
}

#[test]
fn coincident_duplicate_faces_are_dropped_with_one_warning_naming_the_line() {
    // A block side face repeated as its "bottom" (same corners, here also reversed: a bare OBJ
    // is two-sided, so orientation does not make it a different surface), then once more.
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
o side\nf 1 2 3 4\no bottom\nf 2 3 4 1\nf 4 3 2 1\no lamp\nv 0 0 1\nv 1 0 1\nv 1 1 1\nf 5 6 7\n";
    let dir = temp_dir("duplicates");
    std::fs::write(dir.join("d.obj"), obj).unwrap();
    let scene = Scene::load(&dir.join("d.obj")).unwrap();
    assert_eq!(scene.polygons.len(), 2, "{:?}", scene.polygons);
    let warning: Vec<&String> = scene
        .warnings
        .iter()
        .filter(|w| w.contains("coincident"))
        .collect();
    assert_eq!(warning.len(), 1, "{:?}", scene.warnings);
    assert!(
        warning[0].contains("d.obj")
            && warning[0].contains("dropped 2")
            && warning[0].contains("line 8"),
        "{}",
        warning[0]
    );
}

#[test]
fn missing_mtl_and_unknown_material_fall_back_with_warnings() {
    let dir = temp_dir("nomtl");
    std::fs::write(dir.join("m.obj"), OBJ).unwrap();
    let scene = Scene::load(&dir.join("m.obj")).unwrap();
    assert!(scene.warnings.iter().any(|w| w.contains("lamp.mtl")));
    assert!(scene
        .warnings
        .iter()
        .any(|w| w.contains("unknown material `matte`")));
    for p in &scene.polygons {
        assert_eq!(scene.materials[p.material].reflectance, Rgb::splat(0.5));
    }
    // No emitter: a warning, not an error.
    assert!(scene
        .warnings
        .iter()
        .any(|w| w.contains("no material emits")));
}

#[test]
fn mesh_object_is_one_object_with_optional_material_override() {
    let dir = temp_dir("mesh");
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::write(dir.join("meshes/m.obj"), OBJ).unwrap();
    std::fs::write(dir.join("meshes/lamp.mtl"), MTL).unwrap();
    let scene_text = "[materials.white]\nreflectance = 0.7\n\
        [[objects]]\nname = \"thing\"\nshape = \"mesh\"\npath = \"meshes/m.obj\"\n\
        transform = { scale = 2, translate = [0, 0, 5] }\n\
        [[objects]]\nname = \"grey_thing\"\nshape = \"mesh\"\npath = \"meshes/m.obj\"\nmaterial = \"white\"\n";
    let file = dir.join("s.toml");
    std::fs::write(&file, scene_text).unwrap();
    let scene = Scene::load(&file).unwrap();
    assert_eq!(scene.objects.len(), 2);
    assert_eq!(scene.polygons.len(), 4);
    let thing: Vec<_> = scene.polygons.iter().filter(|p| p.object == 0).collect();
    assert_eq!(thing.len(), 2);
    // Transformed: scale 2 then translate z by 5.
    assert_eq!(thing[0].vertices[2], Vec3::new(2.0, 2.0, 5.0));
    assert!(scene.materials[thing[1].material].is_emitter());
    for p in scene.polygons.iter().filter(|p| p.object == 1) {
        assert_eq!(scene.materials[p.material].name, "white");
    }
    // An unnamed object gets a generated name.
    let unnamed = "[materials.w]\nreflectance = 0.5\nemission = 1\n[[objects]]\nname = \"a\"\nmaterial = \"w\"\n\
        shape = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n\
        [[objects]]\nmaterial = \"w\"\nshape = \"sphere\"\ncenter = [3, 0, 0]\nradius = 1\nsubdivisions = 1\n";
    let scene = Scene::from_toml_str(unnamed, Path::new("u.toml")).unwrap();
    assert_eq!(scene.objects[1].name, "object1");
    assert_eq!(scene.polygons.len(), 6 + 80);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

const MATERIALS: &str = "[materials.white]\nreflectance = 0.5\n";
const TRIANGLE: &str = "[[objects]]\nname = \"t\"\nmaterial = \"white\"\nshape = \"polygon\"\n";

/// `line:col` of the first occurrence of `needle` in `text`.
fn line_col(text: &str, needle: &str) -> String {
    let at = text
        .find(needle)
        .unwrap_or_else(|| panic!("no `{needle}` in test text"));
    let line = text[..at].matches('\n').count() + 1;
    let col = at - text[..at].rfind('\n').map_or(0, |i| i + 1) + 1;
    format!("{line}:{col}")
}

fn load_err(text: &str) -> SceneError {
    match Scene::from_toml_str(text, Path::new("bad.toml")) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

/// The error of `text` is one line at `needle`'s position, names `key`, and mentions `what`.
fn assert_error(text: &str, needle: &str, key: &str, what: &str) {
    let e = load_err(text).to_string();
    let head = format!("bad.toml:{}: `{key}`: ", line_col(text, needle));
    assert!(e.starts_with(&head), "expected `{head}...`, got `{e}`");
    assert!(e.contains(what), "`{e}` lacks `{what}`");
    assert!(!e.contains('\n'), "{e}");
}

#[test]
fn every_bad_input_is_reported_with_line_column_and_key() {
    let ok_vertices = "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n";
    let tri = |extra: &str| format!("{MATERIALS}{TRIANGLE}{ok_vertices}{extra}");
    assert_error(
        &tri("colour = 3\n"),
        "colour",
        "objects[0].colour",
        "unknown key",
    );
    assert_error(
        &format!("{MATERIALS}[[objects]]\nname = \"s\"\nmaterial = \"white\"\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = \"big\"\n"),
        "\"big\"",
        "objects[0].radius",
        "expected a number, found a string",
    );
    assert_error(
        &format!("{MATERIALS}[[objects]]\nname = \"t\"\nmaterial = \"whit\"\nshape = \"polygon\"\n{ok_vertices}"),
        "\"whit\"",
        "objects[0].material",
        "unknown material `whit`",
    );
    let material = |line: &str| format!("[materials.white]\n{line}\n{TRIANGLE}{ok_vertices}");
    let t = material("reflectance = [0.5, 1.0, 0.5]");
    assert_error(
        &t,
        "[0.5",
        "materials.white.reflectance",
        "1 (green) is outside [0, 1)",
    );
    let t = material("reflectance = -0.1");
    assert_error(&t, "-0.1", "materials.white.reflectance", "outside [0, 1)");
    let t = material("reflectance = 0.5\nemission = [1, -2, 0]");
    assert_error(&t, "[1, -2", "materials.white.emission", "outside [0, ∞)");
    let t = material("reflectance = [0.5, nan, 0.5]");
    assert_error(
        &t,
        "nan",
        "materials.white.reflectance[1]",
        "must be finite",
    );
    let t = tri("").replace("[1, 0, 0]", "[inf, 0, 0]");
    assert_error(&t, "inf", "objects[0].vertices[1][0]", "must be finite");
    let poly = |vs: &str| format!("{MATERIALS}{TRIANGLE}vertices = {vs}\n");
    let vs = "[[0, 0, 0], [1, 0, 0], [1, 0, 0]]";
    let t = poly(vs);
    assert_error(&t, vs, "objects[0].vertices", "2 distinct vertices");
    let vs = "[[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]]";
    let t = poly(vs);
    assert_error(&t, vs, "objects[0].vertices", "collinear");
    // Strongly non-planar: not an error, split into triangles with a warning.
    let t = poly("[[0, 0, 0], [1, 0, 0], [1, 1, 0.5], [0, 1, 0]]");
    let scene = Scene::from_toml_str(&t, Path::new("bad.toml")).expect("non-planar is repaired");
    assert_eq!(scene.polygons.len(), 2, "fanned into two triangles");
    assert!(
        scene.warnings.iter().any(|w| w.contains("non-planar")),
        "{:?}",
        scene.warnings
    );
    let t = format!(
        "{MATERIALS}[[objects]]\nname = \"m\"\nshape = \"mesh\"\npath = \"nowhere/x.obj\"\n"
    );
    assert_error(&t, "\"nowhere", "objects[0].path", "cannot read mesh");
    let t = format!("{MATERIALS}{TRIANGLE}");
    assert_error(
        &t,
        "[[objects]]",
        "objects[0].vertices",
        "missing required key",
    );
    let t =
        format!("{MATERIALS}[[objects]]\nname = \"c\"\nmaterial = \"white\"\nshape = \"cone\"\n");
    assert_error(&t, "\"cone\"", "objects[0].shape", "unknown shape `cone`");
    let t = format!(
        "[camera]\neye = [0, 0, 0]\ntarget = [0, 0, 1]\nfov = 40\n{}",
        tri("")
    );
    assert_error(&t, "fov =", "camera.fov", "unknown key");
    let t = format!("[render]\nwidth = 1.5\n{}", tri(""));
    assert_error(
        &t,
        "1.5",
        "render.width",
        "expected a whole number, found a float",
    );
    let t = format!(
        "[camera]\neye = [0, 0, 0]\ntarget = [0, 0, 0.0]\n{}",
        tri("")
    );
    assert_error(&t, "[0, 0, 0.0]", "camera.target", "target equals eye");
    let t = tri("").replace("shape", "transform = { scale = [1, 0, 1] }\nshape");
    assert_error(
        &t,
        "[1, 0, 1]",
        "objects[0].transform.scale",
        "must not be zero",
    );
    // Names of CSG operations, subdivision schemes and base meshes are read at parse time, at
    // any depth.
    let solid = |shape: &str| format!("{}[[objects]]\nmaterial = \"white\"\n{shape}", tri(""));
    let ball = "{ shape = \"sphere\", center = [0, 0, 0], radius = 1 }";
    let t = solid(&format!(
        "shape = \"csg\"\nop = \"union\"\noperands = [{ball}, {{ shape = \"csg\", op = \"xor\", \
         operands = [{ball}, {ball}] }}]\n"
    ));
    assert_error(
        &t,
        "\"xor\"",
        "objects[1].operands[1].op",
        "expected `union`, `intersection` or `difference`",
    );
    let t = solid("shape = \"subdivision\"\nbase = \"cube\"\nscheme = \"sqrt3\"\n");
    assert_error(
        &t,
        "\"sqrt3\"",
        "objects[1].scheme",
        "unknown scheme `sqrt3` (expected catmull_clark or loop)",
    );
    let t = solid("shape = \"subdivision\"\nbase = \"cone\"\n");
    assert_error(
        &t,
        "\"cone\"",
        "objects[1].base",
        "unknown base `cone` (expected cube or tetrahedron)",
    );
}

#[test]
fn malformed_toml_empty_scene_and_bad_obj_are_one_line_errors() {
    let text = "[materials.white]\nreflectance = [0.5, 0.5\n";
    let e = load_err(text).to_string();
    assert!(e.starts_with("bad.toml:3:1: "), "{e}");
    assert!(!e.contains('\n'), "{e}");
    let e = load_err(MATERIALS).to_string();
    assert_eq!(e, "bad.toml: the scene has no polygons");
    let dir = temp_dir("badobj");
    std::fs::write(dir.join("b.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n").unwrap();
    let scene =
        format!("{MATERIALS}[[objects]]\nname = \"b\"\nshape = \"mesh\"\npath = \"b.obj\"\n");
    std::fs::write(dir.join("s.toml"), scene).unwrap();
    let e = Scene::load(&dir.join("s.toml")).unwrap_err();
    let obj = dir.join("b.obj");
    assert_eq!(
        e.to_string(),
        format!(
            "{}:4:7: `f`: vertex index -4 is out of range (3 vertices so far)",
            obj.display()
        )
    );
    let e = Scene::load(Path::new("/nonexistent/x.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("/nonexistent/x.toml: cannot read: "), "{e}");
}

#[test]
fn non_finite_and_huge_inputs_never_panic() {
    let cases = [
        "objects = 3",
        "[[objects]]\nshape = 4",
        "[materials]\nwhite = 1",
        "[[cameras]]\neye = [0,0,0]\ntarget = [0,0,1]",
        "[camera]\neye = [0,0,0]\ntarget = [0,0,1]\n[[cameras]]\nname = \"x\"",
        "[[objects]]\nname = \"x\"\nmaterial = \"m\"\nshape = \"sphere\"\ncenter = [0,0,0]\nradius = 1e39",
        "[[objects]]\nshape = \"polygon\"\nvertices = [[1e30, 0, 0], [-1e30, 1e30, 0], [0, -1e30, 1e30]]",
        "when = 1979-05-27",
        "[materials.m]\nreflectance = [0.5, 0.5]",
        "[render]\nwidth = -3",
        "",
    ];
    for text in cases {
        let e = load_err(text).to_string();
        assert!(
            !e.contains('\n') && e.starts_with("bad.toml"),
            "{text:?}: {e}"
        );
    }
}

/// The modeling shapes report their errors at the offending key like every other shape.
#[test]
fn modeling_shapes_report_errors_at_their_keys() {
    let object = |shape: &str, keys: &str| {
        format!("{MATERIALS}[[objects]]\nname = \"m\"\nmaterial = \"white\"\nshape = \"{shape}\"\n{keys}")
    };
    // Rows of unequal length in a Bézier control net.
    let t = object(
        "bezier_patch",
        "points = [[[0, 0, 0], [1, 0, 0]], [[0, 1, 0]]]\n",
    );
    let e = load_err(&t).to_string();
    assert!(
        e.starts_with(&format!("bad.toml:{}", line_col(&t, "[[[0"))),
        "{e}"
    );
    assert!(e.contains("objects[0].points") && !e.contains('\n'), "{e}");
    // An unknown subdivision scheme.
    let t = object("subdivision", "base = \"cube\"\nscheme = \"doo_sabin\"\n");
    let e = load_err(&t).to_string();
    assert!(
        e.contains("objects[0].scheme") && e.contains(&line_col(&t, "\"doo_sabin\"")),
        "{e}"
    );
    // A knot vector that does not fit the degree and point count.
    let t = object(
        "nurbs_surface",
        "points = [[[0, 0, 0], [1, 0, 0]], [[0, 1, 0], [1, 1, 0]]]\nknots_u = [0, 1]\n",
    );
    let e = load_err(&t).to_string();
    assert!(
        e.contains("objects[0].knots_u") && e.contains(&line_col(&t, "[0, 1]")),
        "{e}"
    );
}

#[test]
fn units_are_read_and_an_unknown_one_is_named_with_its_line() {
    use radiosity::scene::units::Units;
    let body = "[materials.w]\nreflectance = [0.5, 0.5, 0.5]\nemission = [1.0, 1.0, 1.0]\n\n\
                [[objects]]\nmaterial = \"w\"\nshape = \"polygon\"\n\
                vertices = [[0, 0, 0], [1, 0, 0], [1, 1, 0]]\n";
    let file = Path::new("units.toml");
    let scene = Scene::from_toml_str(body, file).expect("no units: metres");
    assert_eq!(scene.units, Units::Metres);
    let scene = Scene::from_toml_str(&format!("units = \"cm\"\n{body}"), file).expect("cm");
    assert_eq!(scene.units, Units::Centimetres);
    assert_eq!(scene.units.metres(), 0.01);
    let e = Scene::from_toml_str(&format!("\n\nunits = \"furlong\"\n{body}"), file)
        .expect_err("unknown unit");
    assert_eq!(e.line_col.map(|(line, _)| line), Some(3), "{e}");
    let text = e.to_string();
    assert!(text.contains("units") && text.contains("furlong"), "{text}");
}

/// `on = "desk"`: the grid covers the top of a desk box turned by 30° about y, its first axis
/// along the desk's long side, every point 1 mm above the top (in the scene's units: here
/// millimetres), facing up; the sides and the bottom carry none.
#[test]
fn a_grid_on_a_turned_desk_covers_its_top() {
    let text = r#"
units = "mm"
[materials.wood]
reflectance = 0.4
[materials.lamp]
emission = 10.0
[[objects]]
name = "desk"
material = "wood"
shape = "box"
min = [-800, 0, -400]
max = [800, 750, 400]
transform = { rotate = [0, 30, 0], translate = [100, 0, 200] }
[[objects]]
name = "lamp"
material = "lamp"
shape = "polygon"
vertices = [[-500, 2500, -500], [500, 2500, -500], [500, 2500, 500], [-500, 2500, 500]]
[[grids]]
name = "top"
on = "desk"
spacing = 200
"#;
    let scene = Scene::from_toml_str(text, Path::new("desk.toml")).expect("loads");
    let grid = &scene.grids[0];
    assert_eq!(grid.cells(), (8, 4));
    assert!(
        (grid.first.length() - 1600.0).abs() < 0.01,
        "{}",
        grid.first
    );
    let points = grid.layout();
    assert_eq!(points.len(), 32);
    // The desk's own frame: turned back by 30° about y around its translation.
    let (s, c) = 30f32.to_radians().sin_cos();
    for p in &points {
        assert!((p.position.y - 751.0).abs() < 1e-3, "{p:?}");
        assert!((p.normal - Vec3::Y).length() < 1e-5);
        let d = p.position - Vec3::new(100.0, 0.0, 200.0);
        let (x, z) = (c * d.x - s * d.z, s * d.x + c * d.z);
        // Cell centres: 100 mm in from the edges at most, inside the 1600 × 800 top.
        assert!(
            x.abs() < 800.0 - 99.9 && z.abs() < 400.0 - 99.9,
            "({x}, {z})"
        );
    }
}
