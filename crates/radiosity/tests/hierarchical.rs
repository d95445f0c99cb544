//! The hierarchical solver against closed forms, against the full-matrix solver, and for the
//! invariants of its hierarchies.

use radiosity::accel::{Bvh, Ray};
use radiosity::mesh::{Mesh, Subdivision};
use radiosity::pipeline::{self, Settings, Solved};
use radiosity::progress::Silent;
use radiosity::scene::builtin;
use radiosity::solve::hierarchical::cluster::Clusters;
use radiosity::solve::hierarchical::link::{Estimate, Handle, Sight, View};
use radiosity::solve::{self, Method};
use radiosity::testing;
use radiosity::{Rgb, Scene};

fn cornell() -> Scene {
    builtin::load("cornell").unwrap().unwrap()
}

fn hierarchical(epsilon: f64, tolerance: f64) -> Settings {
    Settings {
        method: Some(Method::Hierarchical),
        solve: solve::Settings {
            epsilon,
            tolerance,
            max_iterations: 10_000,
            ..solve::Settings::default()
        },
        ..Settings::default()
    }
}

fn run(scene: Scene, settings: &Settings) -> Solved {
    pipeline::solve(scene, settings, &Silent).unwrap()
}

/// Σ A B over all elements.
fn power(s: &Solved) -> Rgb {
    (0..s.mesh.element_count())
        .map(|e| s.mesh.element(e).area() * s.solution.radiosity[e])
        .sum()
}

#[test]
fn cube_power_is_emitted_over_one_minus_rho() {
    // One emitting face of radiance 1 (E = π, area 1): Σ A B = π/(1 − ρ) when every receiver's
    // links cover the cube once. The elements gather with their own factors (leaf rows) and
    // every source shines what its pieces shine toward each receiver (source pieces), so rows
    // and columns both sum to one: measured 0.008 % (ρ 0.3) and 0.041 % (ρ 0.7); asserted
    // within the 0.1 % that the reference suite asks of every closed scene.
    for rho in [0.3, 0.7] {
        let s = run(
            testing::closed_cube(rho, [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]),
            &hierarchical(1e-4, 1e-8),
        );
        let expected = std::f64::consts::PI / (1.0 - rho);
        let p = power(&s).x;
        assert!(
            (p - expected).abs() < 1e-3 * expected,
            "ρ {rho}: {p} vs {expected}"
        );
        assert!(s.solution.hierarchy.unwrap().links > 0);
        // The history is (iteration, seconds, residual), as the plot reads it: seconds never
        // fall, and the last residual is the solution's.
        let history = &s.solution.history;
        let rising = history.windows(2).all(|w| w[1].seconds >= w[0].seconds);
        assert!(rising, "{history:?}");
        assert_eq!(
            history.last().map(|h| h.residual),
            Some(s.solution.residual)
        );
    }
}

#[test]
fn furnace_objects_agree_with_gauss_seidel() {
    // The built-in furnace (closed unit cube, ρ = 0.5, ceiling emitting) against Gauss-Seidel
    // with every element a source: measured 0.51 % worst (floor) at ε = 1e-4 and 4 000
    // elements; asserted within 1 % per object.
    let furnace = || builtin::load("furnace").unwrap().unwrap();
    let h = run(furnace(), &hierarchical(1e-4, 1e-8));
    let reference = run(
        furnace(),
        &Settings {
            subdivision: Subdivision::Elements(1500),
            method: Some(Method::GaussSeidel),
            solve: solve::Settings {
                tolerance: 1e-8,
                max_sources: usize::MAX,
                ..solve::Settings::default()
            },
            ..Settings::default()
        },
    );
    let (a, b) = (
        h.stats(&h.timings).objects,
        reference.stats(&reference.timings).objects,
    );
    assert_eq!(a.len(), 6);
    for (x, y) in a.iter().zip(&b) {
        let error = (x.radiosity[0] - y.radiosity[0]).abs() / y.radiosity[0];
        assert!(
            error < 0.01,
            "{}: {} vs {}",
            x.name,
            x.radiosity[0],
            y.radiosity[0]
        );
    }
}

#[test]
fn cube_emitting_everywhere_is_uniform_on_average() {
    // Every face emits E = π: B = E/(1 − ρ) on every element. With the push alone, links
    // gathered by a parent gave its children the parent's mean factor, and a corner element
    // was 17.5 % off (its row summed to 1.44); each element gathering with its own factors
    // (`leaf_rows`) measured 0.016 % worst and the mean within 0.008 %.
    let rho = 0.5;
    let s = run(
        testing::closed_cube(rho, [1.0; 6]),
        &hierarchical(1e-3, 1e-8),
    );
    let expected = std::f64::consts::PI / (1.0 - rho);
    let area: f64 = (0..s.mesh.element_count())
        .map(|e| s.mesh.element(e).area())
        .sum();
    let mean = power(&s).x / area;
    let worst = s
        .solution
        .radiosity
        .iter()
        .map(|b| (b.x - expected).abs() / expected)
        .fold(0.0, f64::max);
    eprintln!("uniform cube: mean {mean}, worst element {worst}");
    assert!(
        (mean - expected).abs() < 1e-3 * expected,
        "{mean} vs {expected}"
    );
    assert!(worst < 5e-3, "{worst}");
}

#[test]
fn clusters_validate_and_links_join_facing_distinct_faces() {
    let scene = cornell();
    let mesh = Mesh::build(&scene, Subdivision::Elements(200));
    let bvh = Bvh::build(&mesh.triangles);
    let clusters = Clusters::build(&mesh);
    clusters.validate(&mesh).unwrap();
    assert!(clusters.nodes.len() > 1);
    let view = View::new(&mesh, &clusters, &bvh);
    let mut links = 0;
    for &r in mesh.elements.iter().step_by(7) {
        for &s in mesh.elements.iter().step_by(5) {
            let (a, b) = (&mesh.nodes[r as usize], &mesh.nodes[s as usize]);
            match view.estimate(Handle::node(r), Handle::node(s), Sight::Unknown) {
                Estimate::Link(l) => {
                    links += 1;
                    assert!(r != s && a.patch != b.patch);
                    let (na, nb) = (
                        mesh.patches[a.patch as usize].normal,
                        mesh.patches[b.patch as usize].normal,
                    );
                    // Each face has some point in front of the other.
                    assert!(b
                        .face
                        .corners()
                        .iter()
                        .any(|&p| na.dot(p - a.face.corners()[0]) > 0.0));
                    assert!(a
                        .face
                        .corners()
                        .iter()
                        .any(|&p| nb.dot(p - b.face.corners()[0]) > 0.0));
                    assert!(l.factor >= 0.0 && l.factor <= 1.0 && l.spread() >= 0.0);
                }
                Estimate::Open => panic!("faces never need opening"),
                Estimate::Nothing => {}
            }
        }
        let r = Handle::node(r);
        assert!(matches!(
            view.estimate(r, r, Sight::Unknown),
            Estimate::Nothing
        ));
    }
    assert!(links > 100);
    // The root cluster with itself always needs opening.
    assert!(matches!(
        view.estimate(Handle::ROOT_CLUSTER, Handle::ROOT_CLUSTER, Sight::Unknown),
        Estimate::Open
    ));
}

#[test]
fn one_and_two_threads_give_identical_solutions() {
    let pools = [1, 2].map(|n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    });
    let [a, b] = [&pools[0], &pools[1]]
        .map(|pool| pool.install(|| run(cornell(), &hierarchical(1e-3, 1e-4))));
    assert_eq!(a.solution.radiosity, b.solution.radiosity);
    assert_eq!(a.solution.hierarchy, b.solution.hierarchy);
    a.mesh.validate().unwrap();
}

#[test]
fn dark_and_empty_scenes_give_zero_without_links() {
    for scene in [testing::closed_cube(0.5, [0.0; 6]), Scene::default()] {
        let s = run(scene, &hierarchical(1e-3, 1e-6));
        assert!(s.solution.radiosity.iter().all(|b| *b == Rgb::ZERO));
        assert_eq!((s.solution.iterations, s.solution.links), (0, 0));
    }
}

#[test]
fn settings_that_are_not_positive_are_refused_by_name() {
    // Neither setting has a zero that means "default": ε's default is a number, the minimum
    // area's is `None` (a millionth of the total area).
    let cube = || testing::closed_cube(0.5, [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
    let mut settings = hierarchical(0.0, 1e-6);
    let err = pipeline::solve(cube(), &settings, &Silent).unwrap_err();
    assert!(
        err.to_string()
            .contains("epsilon must be positive and finite, not 0"),
        "{err}"
    );
    settings.solve.epsilon = solve::DEFAULT_EPSILON;
    for area in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        settings.solve.min_element_area = Some(area);
        let err = pipeline::solve(cube(), &settings, &Silent).unwrap_err();
        assert!(
            err.to_string().contains(&format!(
                "min_element_area must be positive and finite, not {area}"
            )),
            "{err}"
        );
    }
}

#[test]
fn shadow_boundaries_get_denser_elements_than_open_floor() {
    // Floor elements whose centre sees the light partly (penumbra) against those that see it
    // wholly: refinement must put more elements per unit area into the penumbra.
    let s = run(cornell(), &hierarchical(1e-3, 1e-4));
    let bvh = Bvh::build(&s.mesh.triangles);
    let light = s
        .scene
        .objects
        .iter()
        .position(|o| o.name == "light")
        .unwrap();
    let light_face = s
        .mesh
        .patches
        .iter()
        .position(|p| p.object as usize == light)
        .unwrap();
    let light_face = s.mesh.nodes[s.mesh.roots[light_face].start as usize].face;
    let floor = s
        .scene
        .objects
        .iter()
        .position(|o| o.name == "floor")
        .unwrap();
    let (mut open, mut penumbra) = ((0usize, 0.0), (0usize, 0.0));
    for e in 0..s.mesh.element_count() {
        if s.mesh.element_patch(e).object as usize != floor {
            continue;
        }
        let face = s.mesh.element(e).face;
        let c = face.centroid() + glam::Vec3::Y * 0.1;
        let seen = (0..16)
            .filter(|k| {
                let t = light_face
                    .point((k % 4) as f32 / 4.0 + 0.125, (k / 4) as f32 / 4.0 + 0.125)
                    - glam::Vec3::Y * 0.1;
                !bvh.occluded(&Ray::new(c, t - c), 1.0)
            })
            .count();
        let bucket = match seen {
            16 => &mut open,
            1..=15 => &mut penumbra,
            _ => continue,
        };
        bucket.0 += 1;
        bucket.1 += face.area();
    }
    let density = |b: (usize, f64)| b.0 as f64 / b.1;
    eprintln!("penumbra {penumbra:?} open {open:?}");
    assert!(penumbra.0 > 20, "{penumbra:?}");
    // Measured at ε = 1e-3: 2.15e-3 elements per unit² in the penumbra, 1.46e-3 in the open,
    // 1.47× (1.2× while the display criterion's scale included the light's own emission,
    // which hid every shadow boundary). Asserted: at least 1.3×.
    assert!(
        density(penumbra) > 1.3 * density(open),
        "{penumbra:?} {open:?}"
    );
}

/// Per-object mean radiosity: the largest relative difference over objects and channels.
fn object_difference(a: &Solved, b: &Solved) -> f64 {
    let t = Default::default();
    let (sa, sb) = (a.stats(&t), b.stats(&t));
    sa.objects
        .iter()
        .zip(&sb.objects)
        .flat_map(|(x, y)| {
            (0..3).map(move |c| {
                (x.radiosity[c] - y.radiosity[c]).abs() / y.radiosity[c].abs().max(1e-9)
            })
        })
        .fold(0.0, f64::max)
}

#[test]
fn cornell_agrees_with_gauss_seidel_and_converges_with_epsilon() {
    let reference = run(
        cornell(),
        &Settings {
            subdivision: Subdivision::Elements(1500),
            method: Some(Method::GaussSeidel),
            solve: solve::Settings {
                tolerance: 1e-7,
                max_sources: 100_000,
                ..solve::Settings::default()
            },
            ..Settings::default()
        },
    );
    // Measured: 0.8 % at the default ε = 1e-4, 2.x % at 1e-3 (both solvers share the form
    // factor estimators; the Gauss-Seidel reference itself is ~0.2 % from converged).
    let coarse = object_difference(&run(cornell(), &hierarchical(1e-3, 1e-7)), &reference);
    let fine = object_difference(
        &run(cornell(), &hierarchical(solve::DEFAULT_EPSILON, 1e-7)),
        &reference,
    );
    eprintln!("object difference: ε 1e-3 {coarse}, ε 1e-4 {fine}");
    assert!(fine < 0.02, "{fine}");
    assert!(fine < coarse, "{fine} vs {coarse}");
}

/// A closed room of two-sided walls with a box inside it, under a sky: no light can reach the
/// inside, whose radiosity is 0, while the outside reads ρ times the irradiance of the sky.
/// The sky is a far cube of tiles emitting some 3 000 times what the room receives. With the
/// refinement threshold and the residual taken against that emitted power, the box inside
/// came out as bright as the outside walls (1.57, through a link from the room's cluster of
/// lit outer and dark inner sides, which shines its mean) and the inner walls at 1.3 % of the
/// outside; against the power delivered to what reflects ([`solve::hierarchical::delivered`])
/// both are below 10⁻⁴ of it.
#[test]
fn a_closed_room_under_a_sky_stays_dark_inside() {
    use radiosity::scene::environment::{Environment, SunSky};
    let quad = |name: &str, v: [[f32; 3]; 4]| {
        format!(
            "[[objects]]\nname = \"{name}\"\nmaterial = \"paint\"\nshape = \"polygon\"\n\
             vertices = {v:?}\n"
        )
    };
    // The room [0, 6] × [0, 3] × [0, 4], every wall counter-clockwise seen from inside; the
    // box [2.5, 3.5] × [0.5, 1.5] × [1.5, 2.5] floating in it, its faces seen from outside.
    let (x, y, z) = (6.0, 3.0, 4.0);
    let mut text =
        String::from("[materials.paint]\nreflectance = [0.5, 0.5, 0.5]\ntwo_sided = true\n");
    for (name, v) in [
        (
            "floor",
            [[0.0, 0.0, 0.0], [0.0, 0.0, z], [x, 0.0, z], [x, 0.0, 0.0]],
        ),
        (
            "ceiling",
            [[0.0, y, 0.0], [x, y, 0.0], [x, y, z], [0.0, y, z]],
        ),
        (
            "west",
            [[0.0, 0.0, 0.0], [0.0, y, 0.0], [0.0, y, z], [0.0, 0.0, z]],
        ),
        ("east", [[x, 0.0, 0.0], [x, 0.0, z], [x, y, z], [x, y, 0.0]]),
        (
            "north",
            [[0.0, 0.0, 0.0], [x, 0.0, 0.0], [x, y, 0.0], [0.0, y, 0.0]],
        ),
        (
            "south",
            [[0.0, 0.0, z], [0.0, y, z], [x, y, z], [x, 0.0, z]],
        ),
    ] {
        text += &quad(name, v);
    }
    let (lo, hi) = ([2.5, 0.5, 1.5], [3.5, 1.5, 2.5]);
    for (k, v) in [
        [
            [lo[0], lo[1], lo[2]],
            [hi[0], lo[1], lo[2]],
            [hi[0], lo[1], hi[2]],
            [lo[0], lo[1], hi[2]],
        ],
        [
            [lo[0], hi[1], lo[2]],
            [lo[0], hi[1], hi[2]],
            [hi[0], hi[1], hi[2]],
            [hi[0], hi[1], lo[2]],
        ],
        [
            [lo[0], lo[1], lo[2]],
            [lo[0], lo[1], hi[2]],
            [lo[0], hi[1], hi[2]],
            [lo[0], hi[1], lo[2]],
        ],
        [
            [hi[0], lo[1], lo[2]],
            [hi[0], hi[1], lo[2]],
            [hi[0], hi[1], hi[2]],
            [hi[0], lo[1], hi[2]],
        ],
        [
            [lo[0], lo[1], lo[2]],
            [lo[0], hi[1], lo[2]],
            [hi[0], hi[1], lo[2]],
            [hi[0], lo[1], lo[2]],
        ],
        [
            [lo[0], lo[1], hi[2]],
            [hi[0], lo[1], hi[2]],
            [hi[0], hi[1], hi[2]],
            [lo[0], hi[1], hi[2]],
        ],
    ]
    .into_iter()
    .enumerate()
    {
        text += &quad(&format!("box{k}"), v);
    }
    let mut scene = Scene::from_toml_str(&text, std::path::Path::new("room.toml")).unwrap();
    scene
        .add_environment(&Environment::SunSky(SunSky {
            sun_direction: glam::Vec3::new(0.3, 0.8, 0.5).normalize(),
            up: glam::Vec3::Y,
            turbidity: 3.0,
            albedo: 0.0,
            sky_scale: 1.0,
            sun_scale: 0.0,
            sun_radius_deg: 0.0,
            sky: true,
        }))
        .unwrap();
    let solved = run(scene, &hierarchical(1e-4, 1e-6));
    let names: Vec<String> = solved
        .scene
        .objects
        .iter()
        .map(|o| o.name.clone())
        .collect();
    // Area-weighted mean radiosity (largest channel) of the elements `pick` selects.
    let mean = |pick: &dyn Fn(&str, bool) -> bool| {
        let (mut power, mut area) = (0.0, 0.0);
        for e in 0..solved.mesh.element_count() {
            let patch = solved.mesh.element_patch(e);
            if pick(&names[patch.object as usize], patch.back) {
                let a = solved.mesh.element(e).area();
                power += a * solved.solution.radiosity[e].max_element();
                area += a;
            }
        }
        power / area
    };
    let wall = |n: &str| !n.starts_with("box") && n != "environment";
    let outside = mean(&|n, back| wall(n) && back);
    let inside = mean(&|n, back| wall(n) && !back);
    let boxed = mean(&|n, _| n.starts_with("box"));
    assert!(outside > 0.1, "the outside is lit: {outside}");
    assert!(
        inside < 1e-4 * outside,
        "inner walls {inside}, outside {outside}"
    );
    assert!(
        boxed < 1e-4 * outside,
        "the box inside {boxed}, outside {outside}"
    );
}
