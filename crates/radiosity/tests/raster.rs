//! The z-buffer rasterizer against closed forms and ray-plane intersections.

use std::f64::consts::PI;

use glam::Vec3;
use radiosity::mesh::LitMesh;
use radiosity::render::{render, Image, Projection, RasterSettings};
use radiosity::scene::Camera;
use radiosity::Rgb;

/// A camera at the origin looking down −z with a 90° vertical field of view.
fn axis_camera() -> Camera {
    Camera {
        name: "axis".into(),
        eye: Vec3::ZERO,
        target: Vec3::NEG_Z,
        up: Vec3::Y,
        fov_y: 90.0,
    }
}

fn settings(width: u32, height: u32, samples_per_pixel: u32) -> RasterSettings {
    RasterSettings {
        width,
        height,
        samples_per_pixel,
    }
}

/// Appends a quad (corners counter-clockwise seen from its front) with per-corner radiosity.
fn push_quad(mesh: &mut LitMesh, corners: [Vec3; 4], radiosity: [Rgb; 4], back_twin: bool) {
    let base = mesh.positions.len() as u32;
    mesh.positions.extend(corners);
    mesh.radiosity.extend(radiosity);
    for tri in [[0, 1, 2], [0, 2, 3]] {
        mesh.triangles.push(tri.map(|i| base + i));
        mesh.triangle_patch.push(0);
        mesh.has_back_twin.push(back_twin);
        mesh.triangle_object.push(0);
    }
}

/// A square facing +z at depth z, half-size h, uniform radiosity b.
fn facing_square(mesh: &mut LitMesh, z: f32, h: f32, b: Rgb) {
    let corners = [
        Vec3::new(-h, -h, z),
        Vec3::new(h, -h, z),
        Vec3::new(h, h, z),
        Vec3::new(-h, h, z),
    ];
    push_quad(mesh, corners, [b; 4], false);
}

fn assert_all(image: &Image, expected: Rgb, tolerance: f64) {
    for (i, p) in image.pixels.iter().enumerate() {
        assert!(
            (*p - expected).abs().max_element() <= tolerance,
            "pixel {i}: {p} != {expected}"
        );
    }
}

#[test]
fn uniform_quad_filling_the_view_is_radiance_b_over_pi() {
    let b = Rgb::new(1.0, 2.5, 30.0);
    let mut mesh = LitMesh::default();
    facing_square(&mut mesh, -1.0, 3.0, b);
    for spp in [1, 4, 9, 16] {
        let image = render(&mesh, &axis_camera(), &settings(33, 20, spp));
        assert_eq!((image.width, image.height), (33, 20));
        // Tolerance: the perspective division Σλ·B/w / Σλ/w rounds to ~1e-16 relative.
        assert_all(&image, b / PI, 1e-12);
    }
}

#[test]
fn nearer_surface_wins_in_either_draw_order() {
    let (near_b, far_b) = (Rgb::new(1.0, 0.0, 0.0), Rgb::new(0.0, 0.0, 2.0));
    for near_first in [false, true] {
        let mut mesh = LitMesh::default();
        if near_first {
            facing_square(&mut mesh, -1.0, 0.25, near_b);
            facing_square(&mut mesh, -3.0, 10.0, far_b);
        } else {
            facing_square(&mut mesh, -3.0, 10.0, far_b);
            facing_square(&mut mesh, -1.0, 0.25, near_b);
        }
        let image = render(&mesh, &axis_camera(), &settings(16, 16, 4));
        // The near square spans pixels [6, 10) in x and y (±0.25 at depth 1 over ±1 → 8 px).
        for y in 0..16 {
            for x in 0..16 {
                let inside = (6..10).contains(&x) && (6..10).contains(&y);
                let expected = if inside { near_b } else { far_b } / PI;
                let p = image.get(x, y);
                assert!((p - expected).abs().max_element() < 1e-12, "({x},{y}) {p}");
            }
        }
    }
}

#[test]
fn shared_edges_leave_no_cracks_in_a_fan() {
    // A fan of 7 triangles around an off-centre vertex with edges through sample centres
    // and pixel corners: with B = 1 every pixel must be exactly 1/π (a crack shows as less).
    let camera = axis_camera();
    let proj = Projection::new(&camera, 24, 24);
    let ring: Vec<Vec3> = (0..7)
        .map(|k| {
            let a = k as f32 / 7.0 * std::f32::consts::TAU + 0.3;
            Vec3::new(3.0 * a.cos(), 3.0 * a.sin(), -1.0)
        })
        .collect();
    // The centre on the sample at pixel (10, 13) sub-sample (0, 0) of a 2×2 grid.
    let (o, d) = proj.primary_ray(10.25, 13.25);
    let centre = o + d / -d.z;
    let mut mesh = LitMesh::default();
    mesh.positions.push(centre);
    mesh.positions.extend(&ring);
    mesh.radiosity = vec![Rgb::ONE; 8];
    for k in 0..7u32 {
        mesh.triangles.push([0, 1 + k, 1 + (k + 1) % 7]);
        mesh.triangle_patch.push(0);
        mesh.has_back_twin.push(false);
        mesh.triangle_object.push(0);
    }
    for spp in [1, 4, 16] {
        let image = render(&mesh, &camera, &settings(24, 24, spp));
        assert_all(&image, Rgb::ONE / PI, 1e-12);
    }
}

/// The radiosity of the test floor at depth z: linear in world space.
fn floor_b(z: f32) -> Rgb {
    let t = f64::from(1.0 + 0.1 * (10.0 - z));
    Rgb::new(t, 2.0 * t, 0.5 + t)
}

/// A floor at y = −1 spanning x ∈ [−10, 10], z ∈ [z_far, z_near].
fn floor(z_near: f32, z_far: f32) -> LitMesh {
    let corners = [
        Vec3::new(-10.0, -1.0, z_near),
        Vec3::new(10.0, -1.0, z_near),
        Vec3::new(10.0, -1.0, z_far),
        Vec3::new(-10.0, -1.0, z_far),
    ];
    let mut mesh = LitMesh::default();
    push_quad(&mut mesh, corners, corners.map(|c| floor_b(c.z)), false);
    mesh
}

/// Radiance the floor shows along the primary ray through image point (px, py), if it is hit
/// at least `margin` away from the floor's outline (where snapping may move the edge).
fn floor_by_ray(proj: &Projection, px: f32, py: f32, z_near: f32, z_far: f32) -> Option<Rgb> {
    let (o, d) = proj.primary_ray(px, py);
    if d.y >= 0.0 {
        return None;
    }
    let hit = o + d * ((-1.0 - o.y) / d.y);
    let margin = 0.05 * (hit - o).length();
    let inside = hit.x.abs() < 10.0 - margin && hit.z < z_near - margin && hit.z > z_far + margin;
    inside.then(|| floor_b(hit.z) / PI)
}

/// Checks every pixel of a 1-sample render against the ray-plane value at its centre.
fn check_floor(camera: &Camera, z_near: f32, z_far: f32) {
    let (w, h) = (48, 36);
    let image = render(&floor(z_near, z_far), camera, &settings(w, h, 1));
    let proj = Projection::new(camera, w, h);
    let mut checked = 0;
    for y in 0..h {
        for x in 0..w {
            let p = image.get(x, y);
            assert!(p.is_finite(), "({x},{y}) {p}");
            let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
            let Some(expected) = floor_by_ray(&proj, px, py, z_near, z_far) else {
                continue;
            };
            // Tolerance: vertices snap by ≤ 1/2048 pixel and the reference rays are f32; near
            // the horizon the value changes by up to ~20 % per pixel, so errors reach ~1e-4.
            // Screen-space (affine) interpolation is off by 8–15 % on these floors.
            let err = ((p - expected).abs() / expected).max_element();
            assert!(err < 5e-4, "({x},{y}) {p} vs {expected}");
            checked += 1;
        }
    }
    assert!(
        checked > (w * h / 4) as usize,
        "only {checked} pixels checked"
    );
}

#[test]
fn gouraud_interpolation_is_perspective_correct() {
    // Looking down the floor: depth varies strongly across the image, so screen-space
    // (affine) interpolation would be off by several percent.
    let camera = Camera {
        name: "floor".into(),
        eye: Vec3::new(0.0, 0.5, 0.0),
        target: Vec3::new(0.3, -1.0, -4.0),
        up: Vec3::Y,
        fov_y: 60.0,
    };
    check_floor(&camera, -0.5, -20.0);
}

#[test]
fn floor_passing_under_the_camera_is_clipped_not_dropped() {
    // The floor extends 10 units behind the eye, so both triangles cross the camera plane.
    let camera = Camera {
        name: "under".into(),
        eye: Vec3::new(0.0, 0.0, 0.0),
        target: Vec3::new(0.0, -0.8, -1.0),
        up: Vec3::Y,
        fov_y: 100.0,
    };
    check_floor(&camera, 10.0, -20.0);
}

#[test]
fn one_sided_back_face_is_a_black_occluder_and_twinned_back_is_culled() {
    for back_twin in [false, true] {
        let mut mesh = LitMesh::default();
        facing_square(&mut mesh, -3.0, 10.0, Rgb::ONE);
        // A square facing away from the camera (−z), covering the view.
        let h = 5.0;
        let corners = [
            Vec3::new(-h, -h, -1.0),
            Vec3::new(-h, h, -1.0),
            Vec3::new(h, h, -1.0),
            Vec3::new(h, -h, -1.0),
        ];
        push_quad(&mut mesh, corners, [Rgb::splat(7.0); 4], back_twin);
        let image = render(&mesh, &axis_camera(), &settings(8, 8, 4));
        let expected = if back_twin { Rgb::ONE / PI } else { Rgb::ZERO };
        assert_all(&image, expected, 1e-12);
    }
}

/// A deterministic soup of overlapping triangles, some crossing the camera plane.
fn soup(n: usize) -> LitMesh {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut mesh = LitMesh::default();
    for t in 0..n {
        let c = Vec3::new(next() * 4.0 - 2.0, next() * 4.0 - 2.0, -next() * 6.0 + 0.5);
        for _ in 0..3 {
            mesh.positions
                .push(c + Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5));
            mesh.radiosity
                .push(Rgb::new(f64::from(next()), f64::from(next()), 1.0));
        }
        let i = 3 * t as u32;
        mesh.triangles.push([i, i + 1, i + 2]);
        mesh.triangle_patch.push(0);
        mesh.has_back_twin.push(t % 3 == 0);
        mesh.triangle_object.push(0);
    }
    mesh
}

#[test]
fn identical_images_with_one_and_two_threads() {
    let mesh = soup(3000);
    let camera = axis_camera();
    let s = settings(97, 61, 4);
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool")
            .install(|| render(&mesh, &camera, &s))
    };
    let one = run(1);
    let two = run(2);
    assert!(one.mean().max_element() > 0.0, "the soup is visible");
    assert_eq!(one, two);
}

#[test]
fn bad_input_does_not_panic() {
    let mut mesh = soup(10);
    mesh.triangles.push([0, 1, 9999]);
    mesh.positions[3] = Vec3::NAN;
    mesh.radiosity.truncate(5);
    mesh.has_back_twin.clear();
    let image = render(&mesh, &axis_camera(), &settings(16, 16, 0));
    assert!(image.pixels.iter().all(|p| p.is_finite()));
    assert!(render(&mesh, &axis_camera(), &settings(0, 7, 4))
        .pixels
        .is_empty());
}
