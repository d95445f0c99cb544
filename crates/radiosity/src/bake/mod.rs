//! Baking: the solution's light stored in textures over the surfaces, for engines that draw a
//! model with its light already in it (light maps).
//!
//! A solve leaves radiosity per element; a game or web engine wants it per texel of a texture
//! laid over the model. Baking takes four steps, each a module:
//!
//! 1. [`chart`]: the surfaces cut into charts that lie flat (planar charts, the first stage of
//!    the xatlas approach; Lévy et al. 2002 for chart growing);
//! 2. [`pack`]: the charts placed side by side in one atlas, a gutter of texels around each, at
//!    a texel density (`--texels-per-unit`) or the largest one a size allows
//!    (`--lightmap-size`);
//! 3. [`texels`]: the surface point each texel stands for, the gutter's texels at the nearest
//!    point of their chart's edge (so bilinear filtering shows no seam where charts meet);
//! 4. the light at each of those points, evaluated the noise-free way of the default picture
//!    ([`crate::render::surface_points`]): the exact direct light, the near field gathered at
//!    the point, the rest interpolated from the solution, so a texel shows what a camera ray
//!    hitting its point shows.
//!
//! Two maps come out of one bake, the two things engines take:
//!
//! ```text
//! L(x) = B(x) / π                      radiance: the model fully lit, drawn unlit as is
//! H(x) = (B(x) − E(x)) / ρ(x)          irradiance: the light map an engine multiplies by
//!                                      its own albedo (W·m⁻², or lx for photometric lights)
//! ```
//!
//! (H is 0 where a channel's ρ is 0: such a surface shows none of it.) A textured surface (a
//! glTF `baseColorTexture`, an MTL `map_Kd`) is solved with its texture's mean over each
//! polygon; its radiance texels show E + ρ(texel) H, the texture's own albedo averaged over the
//! texel's footprint in the model's texture coordinates, so a checker floor keeps its pattern
//! and still bleeds its mean colour. A texel whose point lies
//! inside another object (a floor under a box) reads the solution there, which is dark: its
//! shadow rays are blocked all round.

pub mod chart;
pub mod pack;
pub mod texels;

use glam::Vec3;

use crate::mesh::Mesh;
use crate::render::surface_points::{radiosity_at, SurfacePoint};
use crate::render::{Image, Watch};
use crate::solve::Solution;
use crate::{Rgb, Scene};

use self::chart::Chart;
use self::pack::Atlas;

/// How large the atlas is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Size {
    /// A square atlas of this side, texels, at the largest density that fits.
    Side(u32),
    /// This many texels per scene unit, the atlas as large as needed.
    Density(f64),
}

/// A bake's options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The atlas's size.
    pub size: Size,
    /// Texels of gutter around each chart (at least 2: bilinear filtering stays within a
    /// chart's own texels; the textures are written without mipmaps, `io::baked`).
    pub padding: u32,
    /// Shadow rays per luminaire at each texel's point.
    pub shadow_samples: u32,
}

impl Default for Settings {
    /// A 1024² atlas with a 2-texel gutter, the picture's shadow rays.
    fn default() -> Self {
        Self {
            size: Size::Side(1024),
            padding: 2,
            shadow_samples: crate::render::raytrace::RaytraceSettings::default().shadow_samples,
        }
    }
}

/// Why a bake cannot be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BakeError {
    /// The charts and their gutters do not fit the size asked for.
    #[error("{charts} charts and their gutters do not fit a {side}² light map: give a larger --lightmap-size")]
    TooSmall {
        /// Charts to place.
        charts: usize,
        /// The side asked for.
        side: u32,
    },
    /// The density asked for makes an atlas larger than a texture can be.
    #[error("{density} texels per unit makes a {width} × {height} light map (at most {MAX_SIDE}²): give a smaller --texels-per-unit")]
    TooLarge {
        /// The density asked for.
        density: f64,
        /// The atlas's width.
        width: u32,
        /// Its height.
        height: u32,
    },
    /// The scene has no polygon to bake.
    #[error("the scene has no surface to bake")]
    Empty,
}

/// The largest atlas side (the texture size most GPUs take).
pub const MAX_SIDE: u32 = 16_384;

/// A finished bake: the charts, where they are in the atlas, and the two maps (module docs).
#[derive(Clone, Debug)]
pub struct Baked {
    /// The charts.
    pub charts: Vec<Chart>,
    /// Their places.
    pub atlas: Atlas,
    /// L = B/π per texel, W·m⁻²·sr⁻¹ per channel; black where no chart is.
    pub radiance: Image,
    /// H per texel, W·m⁻² per channel.
    pub irradiance: Image,
    /// Whether each texel belongs to a chart (its face or its gutter).
    pub covered: Vec<bool>,
}

impl Baked {
    /// Where `point` (on `face`) lies in the atlas, in texture coordinates ([0, 1]², v down,
    /// as glTF's); `None` when the face was not charted (a degenerate polygon).
    #[must_use]
    pub fn uv(&self, face: chart::Face, point: glam::Vec3) -> Option<glam::DVec2> {
        let c = self.charts.iter().position(|c| c.faces.contains(&face))?;
        let (w, h) = self.atlas.size;
        let texel = self
            .atlas
            .texel(&self.charts, c, self.charts[c].flat(point));
        Some(texel / glam::DVec2::new(f64::from(w), f64::from(h)))
    }
}

/// The charts of `scene` and their places in the atlas `settings` ask for: what a bake will
/// fill, found before any solve (so a size too small is said at once).
///
/// # Errors
/// The charts do not fit the size asked for, the density asks for too large an atlas, or
/// there is nothing to bake.
pub fn layout(scene: &Scene, settings: &Settings) -> Result<(Vec<Chart>, Atlas), BakeError> {
    let charts = chart::charts(scene);
    if charts.is_empty() {
        return Err(BakeError::Empty);
    }
    let atlas = match settings.size {
        Size::Side(side) => {
            pack::into_size(&charts, side, settings.padding).ok_or(BakeError::TooSmall {
                charts: charts.len(),
                side,
            })?
        }
        Size::Density(density) => {
            let atlas = pack::at_density(&charts, density, settings.padding);
            if atlas.size.0 > MAX_SIDE || atlas.size.1 > MAX_SIDE {
                return Err(BakeError::TooLarge {
                    density,
                    width: atlas.size.0,
                    height: atlas.size.1,
                });
            }
            atlas
        }
    };
    Ok((charts, atlas))
}

/// Bakes the light of `solution` (of `mesh`, built from `scene`) into an atlas (module docs).
/// `Ok(None)` if `watch` stopped it.
///
/// # Errors
/// The charts do not fit the size asked for, the density asks for too large an atlas, or
/// there is nothing to bake.
pub fn bake(
    scene: &Scene,
    mesh: &Mesh,
    solution: &Solution,
    settings: &Settings,
    watch: &Watch,
) -> Result<Option<Baked>, BakeError> {
    let (charts, atlas) = layout(scene, settings)?;
    let texels = texels::texels(scene, &charts, &atlas);
    let warps: Vec<f32> = scene.polygons.iter().map(|p| warp(&p.vertices)).collect();
    let sample = |(point, normal, face): (Vec3, Vec3, chart::Face)| SurfacePoint {
        point,
        normal,
        polygon: face.polygon,
        warp: warps[face.polygon as usize],
    };
    // Each texel's point, then the mirror points of the gutter's texels.
    let points: Vec<SurfacePoint> = texels
        .iter()
        .map(|t| sample((t.point, t.normal, t.face)))
        .chain(texels.iter().filter_map(|t| t.mirror.map(sample)))
        .collect();
    let Some(values) = radiosity_at(
        scene,
        mesh,
        solution,
        &points,
        settings.shadow_samples,
        watch,
    ) else {
        return Ok(None);
    };
    let (width, height) = atlas.size;
    let blank = || Image {
        width,
        height,
        pixels: vec![Rgb::ZERO; (width * height) as usize],
    };
    let (mut radiance, mut irradiance) = (blank(), blank());
    let mut covered = vec![false; (width * height) as usize];
    let mut missing = Vec::new();
    let (own, mut mirrors) = values.split_at(texels.len());
    for (t, &b) in texels.iter().zip(own) {
        let inner = if t.mirror.is_some() {
            let (first, rest) = mirrors.split_first().expect("one value per mirror");
            mirrors = rest;
            *first
        } else {
            None
        };
        let Some(b) = b else {
            missing.push(t.index);
            continue;
        };
        // A gutter texel: the light extrapolated past the edge (texels module docs), kept
        // within half and twice the edge's own.
        let b = inner.map_or(b, |inner| (b * 2.0 - inner).clamp(b * 0.5, b * 2.0));
        let polygon = &scene.polygons[t.face.polygon as usize];
        let material = &scene.materials[polygon.material];
        let emitted = if t.face.back {
            Rgb::ZERO
        } else {
            material.emission * std::f64::consts::PI
        };
        let rho = material.reflectance_of(polygon);
        let mut h = Rgb::ZERO;
        for c in 0..3 {
            if rho[c] > 0.0 {
                h[c] = ((b[c] - emitted[c]) / rho[c]).max(0.0);
            }
        }
        // A textured surface shows its texture's own albedo over the texel, not the
        // polygon's mean the solve used.
        let shown = match (&material.texture, t.footprint) {
            (Some(map), Some(uv)) => {
                let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
                    .map(|(x, y)| Vec3::new(x, y, 0.0));
                emitted + map.mean_over(&square, &uv) * h
            }
            _ => b,
        };
        let i = t.index as usize;
        radiance.pixels[i] = shown / std::f64::consts::PI;
        irradiance.pixels[i] = h;
        covered[i] = true;
    }
    fill(
        &mut [&mut radiance, &mut irradiance],
        &mut covered,
        &missing,
    );
    Ok(Some(Baked {
        charts,
        atlas,
        radiance,
        irradiance,
        covered,
    }))
}

/// How far a polygon strays from the plane of its Newell normal through its first corner.
fn warp(vertices: &[glam::Vec3]) -> f32 {
    let n = chart::newell(vertices).as_vec3();
    vertices
        .iter()
        .map(|&v| (v - vertices[0]).dot(n).abs())
        .fold(0.0, f32::max)
}

/// Fills the `missing` texels (whose points no probe found: a point exactly on an edge the
/// probe slipped past) with the mean of their covered neighbours, in rounds until none is
/// left or a round fills nothing.
fn fill(maps: &mut [&mut Image], covered: &mut [bool], missing: &[u32]) {
    let width = maps[0].width as i64;
    let height = maps[0].height as i64;
    let mut left: Vec<u32> = missing.to_vec();
    while !left.is_empty() {
        let mut filled = Vec::new();
        let mut still = Vec::new();
        for &i in &left {
            let (x, y) = (i64::from(i) % width, i64::from(i) / width);
            let mut n = 0.0;
            let mut sums = vec![Rgb::ZERO; maps.len()];
            for (dx, dy) in [
                (-1, 0),
                (1, 0),
                (0, -1),
                (0, 1),
                (-1, -1),
                (1, 1),
                (-1, 1),
                (1, -1),
            ] {
                let (a, b) = (x + dx, y + dy);
                if a < 0 || b < 0 || a >= width || b >= height {
                    continue;
                }
                let j = (b * width + a) as usize;
                if covered[j] {
                    n += 1.0;
                    for (s, m) in sums.iter_mut().zip(maps.iter()) {
                        *s += m.pixels[j];
                    }
                }
            }
            if n > 0.0 {
                filled.push((
                    i as usize,
                    sums.into_iter().map(|s| s / n).collect::<Vec<_>>(),
                ));
            } else {
                still.push(i);
            }
        }
        if filled.is_empty() {
            break;
        }
        for (i, values) in filled {
            covered[i] = true;
            for (m, v) in maps.iter_mut().zip(values) {
                m.pixels[i] = v;
            }
        }
        left = still;
    }
}
