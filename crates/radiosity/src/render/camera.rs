//! The perspective projection of a [`Camera`] onto an image.
//!
//! A point p goes through three spaces:
//!
//! 1. **Camera space**: an orthonormal frame at the eye with `forward` f = (target − eye)/‖·‖,
//!    `right` r = f × up/‖·‖ and `up` u = r × f. Coordinates (x_c, y_c, z_c) = (r·d, u·d, f·d),
//!    d = p − eye; z_c is the depth along the view direction.
//! 2. **Clip space** (homogeneous): (x, y, w) = (x_c / (a·t), y_c / t, z_c) with
//!    t = tan(fov_y / 2) and a = width / height. The view frustum is |x| ≤ w, |y| ≤ w, w > 0;
//!    clipping against planes of this space keeps every attribute linear (it is a linear map of
//!    world space), which is what the rasterizer's near-plane clipping relies on.
//! 3. **Pixels**: (p_x, p_y) = ((x/w + 1)/2 · width, (1 − y/w)/2 · height): x to the right, y
//!    downward, pixel (i, j) covering [i, i+1) × [j, j+1). The image's top-left corner is
//!    (0, 0) and its centre is the camera's target direction.
//!
//! [`Projection::primary_ray`] inverts step 3 for ray tracers, so both renderers agree on which
//! direction every image point sees.

use glam::{DVec2, DVec3, Vec3};

use crate::scene::Camera;

/// Narrowest and widest vertical field of view accepted, in degrees; others are clamped.
const FOV_RANGE: (f64, f64) = (1e-3, 179.0);

/// A camera's perspective projection onto an image of a given size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    eye: DVec3,
    right: DVec3,
    up: DVec3,
    forward: DVec3,
    /// tan(fov_x / 2) = aspect · tan(fov_y / 2).
    tan_half_x: f64,
    /// tan(fov_y / 2).
    tan_half_y: f64,
    width: u32,
    height: u32,
}

impl Projection {
    /// The projection of `camera` onto a `width` × `height` image.
    ///
    /// Degenerate cameras do not panic: an eye on its target looks down −z, an `up` parallel to
    /// the view direction is replaced by some perpendicular, the field of view is clamped to
    /// [0.001°, 179°], and a zero size counts as 1 for the aspect ratio.
    #[must_use]
    pub fn new(camera: &Camera, width: u32, height: u32) -> Self {
        let eye = camera.eye.as_dvec3();
        let forward = (camera.target.as_dvec3() - eye)
            .try_normalize()
            .unwrap_or(DVec3::NEG_Z);
        let right = forward
            .cross(camera.up.as_dvec3())
            .try_normalize()
            .unwrap_or_else(|| forward.any_orthonormal_vector());
        let up = right.cross(forward);
        let fov = f64::from(camera.fov_y);
        let fov = if fov.is_nan() {
            45.0
        } else {
            fov.clamp(FOV_RANGE.0, FOV_RANGE.1)
        };
        let tan_half_y = (fov.to_radians() / 2.0).tan();
        let aspect = f64::from(width.max(1)) / f64::from(height.max(1));
        Self {
            eye,
            right,
            up,
            forward,
            tan_half_x: aspect * tan_half_y,
            tan_half_y,
            width,
            height,
        }
    }

    /// Image width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The eye position.
    #[must_use]
    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// Camera-space coordinates (right, up, depth along the view direction) of a world point.
    #[must_use]
    pub fn to_camera(&self, p: Vec3) -> DVec3 {
        let d = p.as_dvec3() - self.eye;
        DVec3::new(d.dot(self.right), d.dot(self.up), d.dot(self.forward))
    }

    /// Homogeneous clip coordinates (x, y, w) of a world point; w is its view depth.
    #[must_use]
    pub fn to_clip(&self, p: Vec3) -> DVec3 {
        let c = self.to_camera(p);
        DVec3::new(c.x / self.tan_half_x, c.y / self.tan_half_y, c.z)
    }

    /// Pixel coordinates of a clip-space point with w > 0 (x right, y down, in pixels).
    #[must_use]
    pub fn clip_to_pixel(&self, c: DVec3) -> DVec2 {
        DVec2::new(
            (c.x / c.z + 1.0) * 0.5 * f64::from(self.width),
            (1.0 - c.y / c.z) * 0.5 * f64::from(self.height),
        )
    }

    /// The primary ray through image point (`px`, `py`) in pixels (pixel (i, j) spans
    /// [i, i+1) × [j, j+1)): origin at the eye, unit direction.
    #[must_use]
    pub fn primary_ray(&self, px: f32, py: f32) -> (Vec3, Vec3) {
        let ndc_x = 2.0 * f64::from(px) / f64::from(self.width.max(1)) - 1.0;
        let ndc_y = 1.0 - 2.0 * f64::from(py) / f64::from(self.height.max(1));
        let dir = self.forward
            + self.right * (ndc_x * self.tan_half_x)
            + self.up * (ndc_y * self.tan_half_y);
        (self.eye.as_vec3(), dir.normalize().as_vec3())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            name: "test".into(),
            eye: Vec3::new(1.0, 2.0, 3.0),
            target: Vec3::new(0.5, 1.0, -2.0),
            up: Vec3::Y,
            fov_y: 50.0,
        }
    }

    #[test]
    fn target_projects_to_the_image_centre_and_up_is_up() {
        let cam = camera();
        let proj = Projection::new(&cam, 640, 480);
        let centre = proj.clip_to_pixel(proj.to_clip(cam.target));
        assert!((centre - DVec2::new(320.0, 240.0)).length() < 1e-9);
        // A point above the target appears higher in the image (smaller y).
        let above = proj.clip_to_pixel(proj.to_clip(cam.target + Vec3::Y * 0.1));
        assert!(above.y < 240.0);
    }

    #[test]
    fn fov_spans_the_image_height() {
        // The top edge of the image is fov_y/2 above the view axis.
        let cam = Camera {
            name: "axis".into(),
            eye: Vec3::ZERO,
            target: Vec3::NEG_Z,
            up: Vec3::Y,
            fov_y: 90.0,
        };
        let proj = Projection::new(&cam, 200, 100);
        let top = proj.clip_to_pixel(proj.to_clip(Vec3::new(0.0, 1.0, -1.0)));
        assert!((top - DVec2::new(100.0, 0.0)).length() < 1e-6, "{top}");
        // The right edge is at tan(fov_x/2) = aspect · tan(fov_y/2) = 2.
        let right = proj.clip_to_pixel(proj.to_clip(Vec3::new(2.0, 0.0, -1.0)));
        assert!((right - DVec2::new(200.0, 50.0)).length() < 1e-6, "{right}");
    }

    #[test]
    fn primary_ray_inverts_the_projection() {
        let cam = camera();
        let proj = Projection::new(&cam, 300, 200);
        for &(px, py) in &[
            (0.0f32, 0.0f32),
            (150.0, 100.0),
            (299.5, 13.25),
            (7.0, 199.0),
        ] {
            let (o, d) = proj.primary_ray(px, py);
            let p = proj.clip_to_pixel(proj.to_clip(o + d * 3.7));
            // Tolerance: f32 direction and point, a few ulps of ~300 pixels.
            assert!(
                (p - DVec2::new(f64::from(px), f64::from(py))).length() < 1e-3,
                "{p}"
            );
            assert!((d.length() - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn degenerate_cameras_do_not_panic() {
        let mut cam = camera();
        cam.up = cam.target - cam.eye;
        cam.fov_y = f32::NAN;
        let proj = Projection::new(&cam, 0, 0);
        let (_, d) = proj.primary_ray(0.5, 0.5);
        assert!(d.is_finite());
        cam.target = cam.eye;
        let c = Projection::new(&cam, 10, 10).to_clip(Vec3::new(1.0, 2.0, 2.0));
        assert!((c.z - 1.0).abs() < 1e-12, "eye on target looks down -z");
    }
}
