//! Local illumination: the lecture's "OpenGL rendering", for comparison with radiosity.
//!
//! A local model lights every surface by the emitters alone and replaces all interreflected
//! light by one constant *ambient* irradiance A (as OpenGL's fixed pipeline did):
//!
//! L(x, ω) = L_e(x) + ρ/π · (E_direct(x) + A) + k_s (n+2)/(2π) ∫ cosⁿ α · L_e cos θ_x dω_y,
//!
//! - E_direct = ∫_A L_e cos θ_x cos θ_y V / r² dA_y over the emitters, estimated with
//!   stratified samples ([`crate::render::raytrace::world::World::direct`]); with
//!   [`LocalSettings::shadows`] off the visibility V is taken as 1, as in OpenGL.
//! - The last term is normalised Phong (Phong 1975; Lewis 1994) with k_s = the material's
//!   `specular`, α the angle between the light's mirror direction and the viewer; zero for
//!   purely diffuse materials.
//! - The default ambient is Cohen et al.'s (1988, progressive refinement) estimate of
//!   interreflected light in an enclosure: A = ρ̄/(1 − ρ̄) · Σ E_j A_j / Σ A_j, with ρ̄ the
//!   area-weighted mean reflectance — what the light would be if it were spread evenly.
//!
//! A point hidden from every emitter (the umbra of a shadow) therefore shows ρA/π exactly:
//! flat, where radiosity shows the light bounced from nearby walls.
//!
//! Light paths (Heckbert): L D E and L S E (highlights) only, plus the ambient guess.

use glam::Vec3;

use super::raytrace::optics::reflect;
use super::raytrace::world::World;
use super::raytrace::{render_primary, Watch};
use super::{Image, RasterSettings};
use crate::mesh::{LitMesh, Mesh};
use crate::scene::Camera;
use crate::{Rgb, Scene};

/// Options of the local illumination model (image size and samples are [`RasterSettings`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalSettings {
    /// Ambient irradiance A (W·m⁻² per channel); `None`: [`default_ambient`].
    pub ambient: Option<Rgb>,
    /// Whether emitters can be hidden (shadow rays); OpenGL has none.
    pub shadows: bool,
    /// Emitter samples per shading point.
    pub shadow_samples: u32,
    /// Phong exponent n of the highlights of specular materials.
    pub phong_exponent: f64,
    /// Jitter the samples inside their sub-squares.
    pub jitter: bool,
}

impl Default for LocalSettings {
    fn default() -> Self {
        Self {
            ambient: None,
            shadows: true,
            shadow_samples: 16,
            phong_exponent: 50.0,
            jitter: true,
        }
    }
}

/// The ambient irradiance of an enclosure (Cohen et al. 1988): ρ̄/(1 − ρ̄) · Σ E_j A_j / Σ A_j.
/// Zero for a mesh without area.
#[must_use]
pub fn default_ambient(mesh: &Mesh) -> Rgb {
    let (mut area, mut rho, mut power) = (0.0, Rgb::ZERO, Rgb::ZERO);
    for p in &mesh.patches {
        area += p.area;
        rho += p.reflectance * p.area;
        power += p.emission * p.area;
    }
    if area.is_nan() || area <= 0.0 {
        return Rgb::ZERO;
    }
    let rho = (rho / area).clamp(Rgb::ZERO, Rgb::splat(0.999));
    rho / (Rgb::ONE - rho) * power / area
}

/// Renders the local-illumination image of `scene` (its geometry taken from `lit`, the lit
/// mesh of `mesh`; the radiosity values are not used). `None` if `watch` stopped it.
#[must_use]
pub fn render(
    scene: &Scene,
    mesh: &Mesh,
    lit: &LitMesh,
    camera: &Camera,
    image: &RasterSettings,
    settings: &LocalSettings,
    watch: &Watch,
) -> Option<Image> {
    let world = World::new(scene, mesh, lit);
    let ambient = settings.ambient.unwrap_or_else(|| default_ambient(mesh));
    let n = settings.phong_exponent.max(0.0);
    render_primary(
        camera,
        image,
        settings.jitter,
        watch,
        |origin, dir, sampler| {
            let Some(hit) = world.intersect(origin, dir, f32::INFINITY) else {
                return Rgb::ZERO;
            };
            let m = world.material(hit.triangle);
            if hit.diffuse.is_none() && !(m.two_sided) {
                return Rgb::ZERO; // the back of a one-sided surface
            }
            let emitted = world.emitted(&hit);
            let diffuse = m.reflectance / std::f64::consts::PI;
            let specular = m.specular * ((n + 2.0) / std::f64::consts::TAU);
            let view = -dir;
            let shading = hit.shading;
            let brdf = |to_light: Vec3| {
                if specular.max_element() <= 0.0 {
                    return diffuse;
                }
                let mirror = reflect(-to_light, shading);
                let cos_alpha = f64::from(mirror.dot(view).max(0.0));
                diffuse + specular * cos_alpha.powf(n)
            };
            let direct = world.direct(
                hit.point,
                hit.shading,
                settings.shadow_samples,
                settings.shadows,
                sampler,
                brdf,
            );
            emitted + direct + diffuse * ambient
        },
    )
}
