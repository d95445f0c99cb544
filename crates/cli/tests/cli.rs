//! End-to-end tests of the `radiosity` binary: its public contract (command line, exit codes, outputs, stats JSON).

use std::collections::BTreeSet;
use std::fs;
use std::path::Path;
use std::process::Output;

mod common;

use common::{radiosity, scratch};

/// Runs the binary with `args` in `dir`.
fn run(dir: &Path, args: &[&str]) -> Output {
    radiosity()
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

/// File names in `dir`, sorted.
fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .expect("read dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The JSON document in file `path`.
fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&fs::read(path).expect("stats")).expect("json")
}

/// The keys of a JSON object, sorted.
fn keys(v: &serde_json::Value) -> BTreeSet<String> {
    v.as_object()
        .unwrap_or_else(|| panic!("not an object: {v}"))
        .keys()
        .cloned()
        .collect()
}

fn set(names: &[&str]) -> BTreeSet<String> {
    names.iter().map(|s| s.to_string()).collect()
}

/// A small valid scene: a glowing grey box on a floor, one camera named `front`. `extra` is
/// inserted as a line of the box object.
fn scene_text(extra: &str) -> String {
    format!(
        r#"[[cameras]]
name = "front"
eye = [0.0, 0.5, 3.0]
target = [0.0, 0.5, 0.0]

[render]
width = 32
height = 32

[materials.grey]
reflectance = [0.5, 0.5, 0.5]
emission = [1.0, 1.0, 1.0]

[materials.white]
reflectance = [0.8, 0.8, 0.8]

[[objects]]
name = "room"
material = "grey"
{extra}
shape = "box"
min = [-0.5, 0.0, -0.5]
max = [0.5, 1.0, 0.5]

[[objects]]
name = "floor"
material = "white"
shape = "polygon"
vertices = [[-2, 0, 2], [2, 0, 2], [2, 0, -2], [-2, 0, -2]]
"#
    )
}

/// The 1-based line of the first line of `scene_text("colour = ...")` holding `colour`.
fn colour_line() -> usize {
    1 + scene_text("colour = [1, 0, 0]")
        .lines()
        .position(|l| l.starts_with("colour"))
        .expect("the line is there")
}

#[test]
fn scenes_lists_the_builtins() {
    let dir = scratch("scenes");
    let out = run(&dir, &["scenes"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    let names: Vec<&str> = text
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    assert!(names.contains(&"cornell"), "{text}");
    assert!(names.contains(&"furnace"), "{text}");
    assert!(
        text.lines().all(|l| l.split_whitespace().count() >= 2),
        "descriptions: {text}"
    );
    fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn discontinuity_meshing_cuts_the_shadows_and_keeps_the_answer() {
    let dir = scratch("discontinuity");
    let solve = |extra: &[&str], stats: &str| {
        let mut args = vec!["solve", "cornell", "--elements", "400", "--stats", stats];
        args.extend_from_slice(extra);
        let out = run(&dir, &args);
        assert!(out.status.success(), "{}", stderr(&out));
        read_json(&dir.join(stats))
    };
    let plain = solve(&[], "plain.json");
    let cut = solve(&["--discontinuity-meshing"], "cut.json");
    assert_eq!(plain["patches"], cut["patches"]);
    assert_ne!(
        plain["elements"], cut["elements"],
        "the blocks' shadows cut the floor"
    );
    // The same scene, differently meshed: every object's radiosity within 3 %.
    let objects = |s: &serde_json::Value| s["objects"].as_array().expect("objects").clone();
    for (a, b) in objects(&plain).iter().zip(objects(&cut)) {
        assert_eq!(a["name"], b["name"]);
        for k in 0..3 {
            let (x, y) = (
                a["radiosity"][k].as_f64().expect("number"),
                b["radiosity"][k].as_f64().expect("number"),
            );
            assert!(
                (x - y).abs() <= 0.03 * x.max(1e-3),
                "{}: {x} against {y}",
                a["name"]
            );
        }
    }
}

/// The vertex count in the header of PLY file `path`.
fn ply_vertices(path: &Path) -> usize {
    let bytes = fs::read(path).expect("ply");
    let header = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]).into_owned();
    header
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .expect("vertex count")
        .trim()
        .parse()
        .expect("a number")
}

#[test]
fn exports_are_refined_for_display_unless_averaged() {
    let dir = scratch("display");
    let solve = |extra: &[&str], name: &str| {
        let (ply, stats) = (format!("{name}.ply"), format!("{name}.json"));
        let mut args = vec!["solve", "cornell", "--elements", "300", "--export", &ply];
        args.extend_from_slice(&["--stats", &stats]);
        args.extend_from_slice(extra);
        let out = run(&dir, &args);
        assert!(out.status.success(), "{}", stderr(&out));
        (ply_vertices(&dir.join(&ply)), read_json(&dir.join(&stats)))
    };
    let (averaged, plain) = solve(&["--display", "averaged"], "averaged");
    let (refined, stats) = solve(&[], "refined");
    let (coarse, _) = solve(&["--display-tolerance", "20"], "coarse");
    assert!(plain["timings"].get("display").is_none());
    assert!(stats["timings"]["display"].as_f64().expect("seconds") > 0.0);
    // Corners, shadow edges and the light's footprint need vertices the elements do not
    // have; a looser tolerance needs fewer.
    assert!(refined > 2 * averaged, "{averaged} → {refined}");
    assert!(
        averaged < coarse && coarse < refined,
        "{averaged}, {coarse}, {refined}"
    );
    // Only the lit mesh changes: the per-object answer is the solve's.
    assert_eq!(plain["objects"], stats["objects"]);
}

#[test]
fn render_writes_png_and_stats_with_the_contract_keys() {
    let dir = scratch("render");
    let args = [
        "render",
        "furnace",
        "--width",
        "64",
        "--height",
        "64",
        "--elements",
        "200",
        "-o",
        "f.png",
        "--stats",
        "s.json",
        "--quiet",
    ];
    let out = run(&dir, &args);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(out.stderr.is_empty(), "--quiet: {}", stderr(&out));
    assert_eq!(files(&dir), ["f.png", "s.json"]);

    let png = fs::read(dir.join("f.png")).expect("png");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    // IHDR: width and height, big-endian, at bytes 16..24.
    assert_eq!(&png[16..24], &[0, 0, 0, 64, 0, 0, 0, 64]);

    let stats = read_json(&dir.join("s.json"));
    let top = [
        "patches",
        "elements",
        "links",
        "solver",
        "timings",
        "energy",
        "objects",
        "materials",
    ];
    assert_eq!(keys(&stats), set(&top));
    assert_eq!(
        keys(&stats["solver"]),
        set(&["method", "iterations", "residual"])
    );
    // The default render (`--mode final`, no export) does not show the lit mesh, so it is not
    // refined for display and `timings.display` is left out.
    let timings = ["load", "mesh", "form_factors", "solve", "render", "total"];
    assert_eq!(keys(&stats["timings"]), set(&timings));
    assert_eq!(
        keys(&stats["energy"]),
        set(&[
            "emitted",
            "absorbed",
            "emitted_w",
            "absorbed_w",
            "emitted_lm",
            "absorbed_lm",
        ])
    );
    for list in ["objects", "materials"] {
        let items = stats[list].as_array().expect("list");
        assert!(!items.is_empty(), "{list} is empty");
        for item in items {
            assert_eq!(keys(item), set(&["name", "area", "radiosity"]));
            assert_eq!(item["radiosity"].as_array().map(Vec::len), Some(3));
        }
    }
    let elements = stats["elements"].as_u64().expect("elements");
    // The subdivision is uniform per patch: within a factor of 4 of the request.
    assert!((50..=800).contains(&elements), "elements {elements}");
    let total = stats["timings"]["total"].as_f64().expect("total");
    let parts: f64 = ["load", "mesh", "form_factors", "solve", "render"]
        .iter()
        .map(|k| stats["timings"][k].as_f64().expect("timing"))
        .sum();
    assert!(
        total >= parts * 0.999,
        "total {total} < sum of stages {parts}"
    );
    fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn solve_exports_ply_with_object_names() {
    let dir = scratch("solve");
    fs::write(dir.join("room.toml"), scene_text("")).expect("write scene");
    let solve = |export: &[&str]| {
        let head = ["solve", "room.toml", "--elements", "96", "--export"];
        run(&dir, &[&head[..], export].concat())
    };
    let out = solve(&["lit.ply", "--stats", "s.json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(files(&dir), ["lit.ply", "room.toml", "s.json"]);
    let ply = fs::read(dir.join("lit.ply")).expect("ply");
    let text = String::from_utf8_lossy(&ply);
    let header = &text[..text.find("end_header\n").expect("header end")];
    assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"));
    assert!(header.contains("comment object 0 room\n"), "{header}");
    assert!(header.contains("comment object 1 floor\n"), "{header}");
    let count = |element: &str| -> usize {
        header
            .lines()
            .find_map(|l| l.strip_prefix(&format!("element {element} ")))
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no {element} count in {header}"))
    };
    let (vertices, faces) = (count("vertex"), count("face"));
    assert!(faces >= 96, "{faces} faces for ≥ 96 elements");
    // Vertex: 6 floats + 3 bytes; face: count byte, 3 ints, object int.
    let body = ply.len() - header.len() - "end_header\n".len();
    assert_eq!(body, vertices * 27 + faces * 17);

    // The same mesh as binary glTF (header magic, version 2, and the total length) and as the
    // HTML viewer, both from one solve: --export repeats.
    let out = solve(&["lit.glb", "--export", "lit.html"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let html = fs::read_to_string(dir.join("lit.html")).expect("html");
    assert!(html.starts_with("<!DOCTYPE html>"), "{}", &html[..40]);
    let glb = fs::read(dir.join("lit.glb")).expect("glb");
    assert_eq!(&glb[..8], b"glTF\x02\0\0\0");
    assert_eq!(
        u32::from_le_bytes([glb[8], glb[9], glb[10], glb[11]]) as usize,
        glb.len()
    );
    fs::remove_dir_all(&dir).expect("cleanup");
}

/// Whether `line` reports a stage (`STAGE done: ... in S s`, `STAGE: ... after S s`): a run
/// whose stderr is no terminal says so of the stages it finished before a failure.
fn stage_line(line: &str) -> bool {
    line.ends_with(" s") && (line.contains(" done: ") || line.contains(" after "))
}

/// Checks a failure: status 2, exactly one stderr line `error: ...` containing every one of
/// `mentions` (besides the lines of the stages run before it), and no file in `dir` other
/// than the scenes.
fn assert_fails(name: &str, args: &[&str], mentions: &[&str]) {
    let dir = scratch(name);
    fs::write(dir.join("room.toml"), scene_text("")).expect("write scene");
    fs::write(dir.join("bad.toml"), scene_text("colour = [1, 0, 0]")).expect("write scene");
    let out = run(&dir, args);
    let err: String = stderr(&out)
        .lines()
        .filter(|l| !stage_line(l))
        .map(|l| format!("{l}\n"))
        .collect();
    assert_eq!(out.status.code(), Some(2), "{name}: {err}");
    assert_eq!(err.lines().count(), 1, "{name}: one line expected: {err}");
    assert!(err.starts_with("error: "), "{name}: {err}");
    for m in mentions {
        assert!(err.contains(m), "{name}: {err:?} does not mention {m:?}");
    }
    assert!(
        out.stdout.is_empty(),
        "{name}: stdout {:?}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert_eq!(
        files(&dir),
        ["bad.toml", "room.toml"],
        "{name}: output left behind"
    );
    fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn bad_inputs_exit_2_with_one_line_and_no_output() {
    let small = [
        "--elements",
        "24",
        "--width",
        "8",
        "--height",
        "8",
        "--stats",
        "s.json",
    ];
    let with = |head: &[&'static str]| -> Vec<&'static str> {
        head.iter().copied().chain(small.iter().copied()).collect()
    };
    assert_fails(
        "missing-file",
        &with(&["render", "nope.toml", "-o", "x.png"]),
        &["nope.toml"],
    );
    let at = format!("bad.toml:{}", colour_line());
    assert_fails(
        "unknown-key",
        &with(&["render", "bad.toml", "-o", "x.png"]),
        &[at.as_str(), "colour"],
    );
    // An output in a directory that cannot be written: refused before any work, so the good
    // output beside it is not written either, and the cause said once.
    assert_fails(
        "unwritable-output",
        &with(&[
            "render",
            "room.toml",
            "-o",
            "good.png",
            "-o",
            "/sys/bad.png",
        ]),
        &["/sys/bad.png", "cannot write in directory /sys"],
    );
    // Flags that did not do what they said are refused with the reason.
    assert_fails(
        "samples-not-square",
        &with(&["render", "room.toml", "-o", "x.png", "--samples", "3"]),
        &["--samples", "not a square"],
    );
    assert_fails(
        "no-shadows-without-local",
        &with(&["render", "room.toml", "-o", "x.png", "--no-shadows"]),
        &["--no-shadows", "--mode local"],
    );
    assert_fails(
        "width-beyond-the-scene-limit",
        &with(&["render", "room.toml", "-o", "x.png", "--width", "65536"]),
        &["--width", "16384"],
    );
    assert_fails(
        "elements-under-hierarchical",
        &with(&[
            "render",
            "room.toml",
            "-o",
            "x.png",
            "--solver",
            "hierarchical",
        ]),
        &["--elements", "--solver hierarchical", "--epsilon"],
    );
    // A form-factor option the method has no use for.
    assert_fails(
        "rays-with-hemicubes",
        &with(&[
            "render",
            "room.toml",
            "-o",
            "x.png",
            "--form-factors",
            "hemicube",
            "--rays",
            "4",
        ]),
        &["--rays", "--form-factors hemicube"],
    );
    assert_fails(
        "resolution-with-ray-casting",
        &with(&[
            "render",
            "room.toml",
            "-o",
            "x.png",
            "--hemicube-resolution",
            "64",
        ]),
        &["--hemicube-resolution", "--form-factors raycast"],
    );
    assert_fails(
        "seed-with-analytic",
        &with(&[
            "render",
            "room.toml",
            "-o",
            "x.png",
            "--form-factors",
            "analytic",
            "--seed",
            "3",
        ]),
        &["--seed", "--form-factors analytic"],
    );
    assert_fails(
        "eye-not-a-point",
        &with(&["render", "room.toml", "-o", "x.png", "--eye", "1,2"]),
        &["--eye", "X,Y,Z"],
    );
    assert_fails(
        "up-along-the-view",
        &with(&[
            "render",
            "room.toml",
            "-o",
            "x.png",
            "--eye",
            "0,5,0",
            "--target",
            "0,0,0",
        ]),
        &["--up", "parallel"],
    );
    assert_fails(
        "directory-as-scene",
        &with(&["render", ".", "-o", "x.png"]),
        &["is a directory"],
    );
    assert_fails(
        "file-as-directory",
        &with(&["render", "room.toml", "-o", "room.toml/x.png"]),
        &["room.toml is a file, not a directory"],
    );
    assert_fails(
        "bad-width",
        &with(&["render", "room.toml", "-o", "x.png", "--width", "wide"]),
        &["--width", "wide"],
    );
    assert_fails(
        "bad-memory",
        &with(&["render", "room.toml", "--max-memory", "lots"]),
        &["--max-memory", "lots"],
    );
    assert_fails(
        "bad-solver",
        &with(&["render", "room.toml", "--solver", "magic"]),
        &["--solver", "magic"],
    );
    assert_fails(
        "unknown-camera",
        &with(&["render", "room.toml", "-o", "x.png", "--camera", "side"]),
        &["side", "front"],
    );
    assert_fails(
        "unwritable-dir",
        &with(&["render", "room.toml", "-o", "no/such/dir/x.png"]),
        &["no/such/dir"],
    );
    assert_fails(
        "unwritable-stats",
        &[
            "solve",
            "room.toml",
            "--elements",
            "24",
            "--stats",
            "gone/s.json",
        ],
        &["gone/s.json"],
    );
    assert_fails(
        "output-extension",
        &with(&["render", "room.toml", "-o", "x.bmp"]),
        &["x.bmp", "bmp"],
    );
    assert_fails(
        "export-extension",
        &with(&["render", "room.toml", "-o", "x.png", "--export", "lit.stl"]),
        &["lit.stl"],
    );
    assert_fails(
        "stats-under-local",
        &with(&["render", "room.toml", "--mode", "local", "--plot", "p.svg"]),
        &["--", "--mode local does not solve"],
    );
    assert_fails(
        "gather-without-raytrace",
        &with(&["render", "room.toml", "--mode", "local", "--gather", "4"]),
        &["--gather applies to --mode raytrace only"],
    );
    assert_fails("no-scene", &["solve"], &["SCENE"]);
    assert_fails(
        "absurd-elements",
        &["render", "room.toml", "--max-element-area", "1e-12"],
        &["--elements", "--max-memory"],
    );
    assert_fails(
        "matrix-too-large",
        &[
            "render",
            "room.toml",
            "--elements",
            "400",
            "--solver",
            "jacobi",
            "--max-memory",
            "150K",
            "--width",
            "8",
            "--height",
            "8",
        ],
        &["--solver progressive", "--max-memory"],
    );
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let dir = scratch("threads");
    let mut objects = Vec::new();
    let mut images = Vec::new();
    for threads in ["1", "2"] {
        let (pfm, json) = (format!("t{threads}.pfm"), format!("t{threads}.json"));
        let out = run(
            &dir,
            &[
                "render",
                "cornell",
                "--width",
                "48",
                "--height",
                "40",
                "--elements",
                "300",
                "--threads",
                threads,
                "-o",
                &pfm,
                "--stats",
                &json,
                "--quiet",
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        let stats = read_json(&dir.join(&json));
        objects.push(serde_json::to_string(&stats["objects"]).expect("serialize"));
        images.push(fs::read(dir.join(&pfm)).expect("pfm"));
    }
    assert_eq!(
        objects[0], objects[1],
        "stats objects differ between 1 and 2 threads"
    );
    assert!(images[0].starts_with(b"PF\n48 40\n"), "a 48×40 colour PFM");
    assert!(
        images[0] == images[1],
        "PFM bytes differ between 1 and 2 threads"
    );
    fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn curve_draws_the_de_casteljau_construction_as_svg() {
    let dir = scratch("curve");
    let out = run(
        &dir,
        &[
            "curve",
            "--points",
            "0,0 1,2 3,2 4,0",
            "--t",
            "0.25",
            "-o",
            "c.svg",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let svg = fs::read_to_string(dir.join("c.svg")).expect("svg written");
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    // The control polygon, and one construction polygon per level below it (3 for a cubic).
    assert!(svg.matches("<polyline").count() >= 4, "{svg}");
    let bad = run(&dir, &["curve", "--points", "0,0 1,x", "-o", "d.svg"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(!dir.join("d.svg").exists());
    fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn the_camera_can_be_set_from_the_command_line() {
    // The same solve seen from the scene's camera and from one set by --eye/--target/--fov:
    // different pictures; a negative coordinate parses.
    let dir = scratch("camera");
    fs::write(dir.join("room.toml"), scene_text("")).expect("write scene");
    let render = |extra: &[&str], out: &str| {
        let head = [
            "render",
            "room.toml",
            "--elements",
            "24",
            "--width",
            "16",
            "--height",
        ];
        let o = run(&dir, &[&head[..], &["16", "-o", out], extra].concat());
        assert!(o.status.success(), "{}", stderr(&o));
        fs::read(dir.join(out)).expect("image")
    };
    let scene_camera = render(&[], "a.png");
    let moved = render(
        &["--eye", "-0.5,0.8,-2", "--target", "0,0.2,0", "--fov", "70"],
        "b.png",
    );
    assert_ne!(scene_camera, moved);
    fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn local_mode_renders_without_a_radiosity_solve() {
    // Local illumination reads only the geometry and the emitters: no solve runs (its summary
    // line names the solver and its iterations), and the picture differs from radiosity's.
    let dir = scratch("local");
    fs::write(dir.join("room.toml"), scene_text("")).expect("write scene");
    let head = ["render", "room.toml", "--width", "16", "--height", "16"];
    let local = run(
        &dir,
        &[&head[..], &["--mode", "local", "-o", "l.png"]].concat(),
    );
    assert!(local.status.success(), "{}", stderr(&local));
    let said = String::from_utf8_lossy(&local.stdout).to_string() + &stderr(&local);
    assert!(!said.contains("iterations"), "{said}");
    let solved = run(&dir, &[&head[..], &["-o", "r.png"]].concat());
    assert!(solved.status.success(), "{}", stderr(&solved));
    let said = String::from_utf8_lossy(&solved.stdout).to_string() + &stderr(&solved);
    assert!(said.contains("iterations"), "{said}");
    assert_ne!(
        fs::read(dir.join("l.png")).expect("local image"),
        fs::read(dir.join("r.png")).expect("radiosity image")
    );
    fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn a_scene_without_light_is_lit_by_the_default_sky() {
    // A bare OBJ without `Ke`: a floor under a seat. Lit by the default sky (radiance 1), a
    // surface that sees only the sky has B = ρπ exactly: the floor's back (default ρ = 0.5)
    // faces nothing but the sky below it. --no-default-light leaves it black.
    let dir = scratch("sky");
    let obj = "o seat\nv -0.5 0.5 -0.5\nv 0.5 0.5 -0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n\
               f 1 4 3 2\no floor\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nf 5 8 7 6\n";
    fs::write(dir.join("model.obj"), obj).expect("write model");
    let solve = |extra: &[&str]| {
        let args = [&["solve", "model.obj", "--elements", "300"][..], extra].concat();
        let out = run(&dir, &args);
        assert!(out.status.success(), "{}", stderr(&out));
        out
    };
    let out = solve(&["--stats", "sky.json"]);
    let said = stderr(&out) + &String::from_utf8_lossy(&out.stdout);
    assert_eq!(said.matches("default sky").count(), 1, "{said}");
    assert!(!said.contains("will be black"), "{said}");
    let stats = read_json(&dir.join("sky.json"));
    let object = |name: &str| {
        stats["objects"]
            .as_array()
            .expect("objects")
            .iter()
            .find(|o| o["name"] == name)
            .cloned()
    };
    let back = object("floor").expect("floor")["back"][1]
        .as_f64()
        .expect("back radiosity");
    let expected = 0.5 * std::f64::consts::PI;
    assert!(
        (back - expected).abs() < 0.005 * expected,
        "{back} vs {expected}"
    );
    assert!(object("default_sky").is_some());
    let out = solve(&["--stats", "dark.json", "--no-default-light"]);
    assert!(stderr(&out).contains("will be black"), "{}", stderr(&out));
    let dark = read_json(&dir.join("dark.json"));
    let names: Vec<&str> = dark["objects"]
        .as_array()
        .expect("objects")
        .iter()
        .map(|o| o["name"].as_str().expect("name"))
        .collect();
    assert_eq!(names, ["seat", "floor"]);
    fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn a_render_exports_its_own_camera_first() {
    // The camera the picture was taken with (moved by --eye) leads the .glb's cameras, with
    // the picture's aspect ratio; the scene's own camera follows.
    let dir = scratch("glb-camera");
    fs::write(dir.join("room.toml"), scene_text("")).expect("write scene");
    let out = run(
        &dir,
        &[
            "render",
            "room.toml",
            "--elements",
            "24",
            "--width",
            "32",
            "--height",
            "16",
            "--eye",
            "0.25,0.5,-2",
            "-o",
            "a.png",
            "--export",
            "a.glb",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let glb = fs::read(dir.join("a.glb")).expect("glb");
    let length = u32::from_le_bytes(glb[12..16].try_into().expect("4 bytes")) as usize;
    let json: serde_json::Value = serde_json::from_slice(&glb[20..20 + length]).expect("json");
    let cameras = json["cameras"].as_array().expect("cameras");
    assert_eq!(cameras.len(), 2, "{json}");
    assert_eq!(cameras[0]["perspective"]["aspectRatio"], 2.0);
    let node = json["nodes"]
        .as_array()
        .expect("nodes")
        .iter()
        .find(|n| n["camera"] == 0)
        .expect("a node of camera 0");
    let t: Vec<f64> = node["translation"]
        .as_array()
        .expect("translation")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect();
    assert!((t[0] - 0.25).abs() < 1e-6 && (t[1] - 0.5).abs() < 1e-6 && (t[2] + 2.0).abs() < 1e-6);
    assert!(cameras[0]["name"]
        .as_str()
        .expect("name")
        .ends_with("(command line)"));
    fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn a_failing_output_leaves_none_of_the_outputs() {
    // The export's directory vanishes after the run has checked its outputs: the image,
    // written before the export, and the stats must not appear either, and no temporary file
    // may stay behind. The run checks its outputs before it reads the scene, and the scene
    // comes through a named pipe: once the run has opened the pipe (the test's opening of it
    // for writing returns), the check is behind it; the directory is then removed and the
    // scene written. No clock decides the order.
    let dir = scratch("all-or-nothing");
    fs::create_dir_all(dir.join("sub")).expect("mkdir");
    fs::write(dir.join("out.png"), b"earlier").expect("seed");
    let pipe = dir.join("scene.toml");
    let made = std::process::Command::new("mkfifo")
        .arg(&pipe)
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    let mut child = radiosity()
        .args([
            "render",
            "scene.toml",
            "--elements",
            "200",
            "-o",
            "out.png",
            "--export",
            "sub/lit.glb",
            "--stats",
            "stats.json",
        ])
        .current_dir(&dir)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("spawns");
    // Opening a pipe for writing waits for its reader: on a thread, while this one watches
    // for a run that ends without reading the scene (a failure, not a hang).
    let (opened, open) = std::sync::mpsc::channel();
    let writer = pipe.clone();
    std::thread::spawn(move || {
        let _ = opened.send(fs::OpenOptions::new().write(true).open(writer));
    });
    let mut scene = loop {
        match open.recv_timeout(std::time::Duration::from_millis(100)) {
            Ok(file) => break file.expect("opens the pipe"),
            Err(_) => {
                if child.try_wait().expect("polls").is_some() {
                    let out = child.wait_with_output().expect("waits");
                    panic!("the run ended without reading its scene: {}", stderr(&out));
                }
            }
        }
    };
    fs::remove_dir(dir.join("sub")).expect("rmdir");
    std::io::Write::write_all(&mut scene, scene_text("").as_bytes()).expect("write scene");
    drop(scene);
    let out = child.wait_with_output().expect("waits");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    let error: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(error.len(), 1, "{stderr}");
    assert!(error[0].contains("sub/lit.glb: cannot write"), "{stderr}");
    let mut left: Vec<String> = fs::read_dir(&dir)
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["out.png", "scene.toml"], "{stderr}");
    assert_eq!(fs::read(dir.join("out.png")).expect("read"), b"earlier");
    fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn help_states_every_default() {
    // Every option that has a default says it, in clap's "[default: …]" or in its own words
    // ("default: …", "default …"); options without one (paths, flags, views) are listed.
    let without_default = [
        "--output",
        "--camera",
        "--eye",
        "--target",
        "--up",
        "--fov",
        "--stats",
        "--plot",
        "--export",
        "--grids",
        "--false-colour",
        "--max-element-area",
        "--checkpoint",
        "--resume",
        "--threads",
        "--quiet",
        "--write-partial",
        "--no-shadows",
        "--no-default-light",
        "--help",
        "--version",
    ];
    let out = run(Path::new("."), &["render", "--help"]);
    let help = String::from_utf8_lossy(&out.stdout);
    // Each option's block runs from its line to the next option's.
    let mut blocks: Vec<(String, String)> = Vec::new();
    for line in help.lines() {
        let t = line.trim_start();
        if t.starts_with('-') && line.starts_with("  ") && !line.starts_with("          ") {
            let name = t
                .split([' ', ','])
                .find(|w| w.starts_with("--"))
                .unwrap_or("")
                .to_owned();
            blocks.push((name, String::new()));
        } else if let Some((_, text)) = blocks.last_mut() {
            text.push_str(line);
            text.push('\n');
        }
    }
    assert!(blocks.len() > 30, "{help}");
    for (name, text) in &blocks {
        if without_default.contains(&name.as_str()) {
            continue;
        }
        let states = text.to_lowercase().contains("default");
        assert!(states, "{name} does not state its default:\n{text}");
    }
}
