//! Affine transforms in the order the scene format states: scale, then rotate about x, y, z (in
//! that order, degrees), then translate — the course's "composition of transformations".

use glam::{Affine3A, EulerRot, Quat, Vec3};

/// An affine map of points, built from scale → rotate(x, y, z) → translate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    affine: Affine3A,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    /// The identity.
    pub const IDENTITY: Self = Self {
        affine: Affine3A::IDENTITY,
    };

    /// Scale by `scale`, rotate by `rotate_deg` about x then y then z (fixed axes), translate.
    #[must_use]
    pub fn from_srt(scale: Vec3, rotate_deg: Vec3, translate: Vec3) -> Self {
        let r = rotate_deg * (std::f32::consts::PI / 180.0);
        // Extrinsic x, then y, then z: q = Rz · Ry · Rx.
        let rotation = Quat::from_euler(EulerRot::ZYX, r.z, r.y, r.x);
        Self {
            affine: Affine3A::from_scale_rotation_translation(scale, rotation, translate),
        }
    }

    /// The affine part of a 4×4 matrix (its last row is taken as 0 0 0 1), as scene files
    /// such as Mitsuba's write `to_world`.
    #[must_use]
    pub fn from_mat4(m: glam::Mat4) -> Self {
        Self {
            affine: Affine3A::from_mat4(m),
        }
    }

    /// `self` applied after `inner`.
    #[must_use]
    pub fn then(self, outer: Self) -> Self {
        Self {
            affine: outer.affine * self.affine,
        }
    }

    /// Maps a point.
    #[must_use]
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.affine.transform_point3(p)
    }

    /// Maps a direction (the linear part alone, no translation).
    #[must_use]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.affine.transform_vector3(v)
    }

    /// Whether the map reverses orientation (negative determinant), so faces must be reversed to
    /// keep their fronts.
    #[must_use]
    pub fn mirrors(&self) -> bool {
        self.affine.matrix3.determinant() < 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_is_scale_rotate_translate() {
        let t = Transform::from_srt(
            Vec3::splat(2.0),
            Vec3::new(0.0, 90.0, 0.0),
            Vec3::new(10.0, 0.0, 0.0),
        );
        // (1,0,0) → scale (2,0,0) → rotate 90° about y gives (0,0,-2) → translate (10,0,-2).
        let p = t.point(Vec3::X);
        assert!((p - Vec3::new(10.0, 0.0, -2.0)).length() < 1e-5, "{p}");
    }

    #[test]
    fn rotation_about_x_then_y() {
        let t = Transform::from_srt(Vec3::ONE, Vec3::new(90.0, 90.0, 0.0), Vec3::ZERO);
        // y → (rot x 90) z → (rot y 90) x.
        let p = t.point(Vec3::Y);
        assert!((p - Vec3::X).length() < 1e-5, "{p}");
    }

    #[test]
    fn negative_scale_mirrors() {
        assert!(Transform::from_srt(Vec3::new(-1.0, 1.0, 1.0), Vec3::ZERO, Vec3::ZERO).mirrors());
        assert!(!Transform::IDENTITY.mirrors());
    }
}
