//! Mitsuba BSDFs as the diffuse surfaces a radiosity solve sees.
//!
//! Radiosity assumes Lambertian reflection: every surface reflects a fraction ρ of the light it
//! receives, equally in all directions. A published scene's other BSDFs are mapped to that, by
//! the rule below; the scene's loading warnings name every BSDF type so mapped, in one line.
//! `benches/corpus/reference.py` writes the same mapping into a Mitsuba 3 scene, so that the
//! reference our pictures are checked against differs from ours in light transport only.
//!
//! | BSDF | ρ |
//! |---|---|
//! | `diffuse`, `roughdiffuse` | `reflectance` (default 0.5) |
//! | `twosided` | its nested BSDF's, reflecting from both sides |
//! | `plastic`, `roughplastic`, `pplastic` | `diffuse_reflectance` (default 0.5): the coating's specular lobe is dropped |
//! | `conductor`, `roughconductor` | `specular_reflectance` (default 1) × R₀ of `material` (table [`conductor_r0`]) |
//! | `dielectric`, `thindielectric`, `roughdielectric`, `null` | transparent: the shape is left out |
//! | `mask`, `bumpmap`, `normalmap`, `coating`, `roughcoating` | its nested BSDF's (a mask's opacity is ignored) |
//! | `blendbsdf` | (1 − w)·ρ₀ + w·ρ₁, w = `weight` |
//! | `principled`, `principledthin` | `base_color` (default 0.5) |
//! | any other Mitsuba BSDF | 0.5 |
//!
//! A colour may be a texture: a `bitmap` stands for its mean in linear RGB
//! ([`crate::scene::texture`]), a `checkerboard` for the mean of its two colours, a
//! Mitsuba 0.6 `scale` texture for its nested texture's mean times `scale`. Every ρ is clamped to
//! [0, [`MAX_REFLECTANCE`]]: ρ = 1 would make a closed scene's light grow without bound.

use std::collections::{BTreeMap, HashMap};
use std::path::PathBuf;
use std::sync::Arc;

use super::xml::{resolve, Class, Object, Property, Value};
use crate::scene::texture::Texture;
use crate::scene::{SceneError, MAX_REFLECTANCE};
use crate::Rgb;

/// What a radiosity solve sees of a BSDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    /// A Lambertian reflector.
    Diffuse {
        /// ρ per channel.
        reflectance: Rgb,
        /// Whether the back reflects too.
        two_sided: bool,
    },
    /// Light passes: the shape is left out of the scene.
    Transparent,
}

/// BSDF names of both Mitsuba versions that are mapped by the "any other" row.
const OTHER_BSDFS: &[&str] = &[
    "difftrans",
    "hair",
    "measured",
    "polarizer",
    "retarder",
    "circular",
    "phong",
    "ward",
    "irawan",
    "hk",
    "sssbrdf",
    "dipole",
];

/// Maps BSDFs, remembering the texture means it has computed and the types it approximated.
#[derive(Default)]
pub struct Mapper {
    textures: HashMap<(PathBuf, bool), Rgb>,
    /// Types other than `diffuse`/`twosided`, with how many BSDFs of each were mapped.
    pub approximated: BTreeMap<String, usize>,
}

impl Mapper {
    /// The surface of `bsdf`.
    ///
    /// # Errors
    /// An unknown BSDF or texture plugin, a texture image that cannot be read, or a property of
    /// the wrong type; located at the element.
    pub fn surface(&mut self, bsdf: &Object) -> Result<Surface, SceneError> {
        let kind = bsdf.kind.as_str();
        if !matches!(kind, "diffuse" | "twosided") {
            *self.approximated.entry(kind.to_string()).or_default() += 1;
        }
        let diffuse = |reflectance: Rgb| Surface::Diffuse {
            reflectance: reflectance.clamp(Rgb::ZERO, Rgb::splat(MAX_REFLECTANCE)),
            two_sided: false,
        };
        Ok(match kind {
            "diffuse" | "roughdiffuse" => diffuse(self.colour(bsdf, "reflectance", 0.5)?),
            "plastic" | "roughplastic" | "pplastic" => {
                diffuse(self.colour(bsdf, "diffuse_reflectance", 0.5)?)
            }
            "principled" | "principledthin" => diffuse(self.colour(bsdf, "base_color", 0.5)?),
            "conductor" | "roughconductor" => {
                let material = bsdf.string("material")?.unwrap_or("none");
                let r0 = if bsdf.get("eta").is_some() || bsdf.get("k").is_some() {
                    Rgb::splat(0.9)
                } else {
                    conductor_r0(material)
                };
                diffuse(self.colour(bsdf, "specular_reflectance", 1.0)? * r0)
            }
            "dielectric" | "thindielectric" | "roughdielectric" | "null" => Surface::Transparent,
            "twosided" => match self.nested(bsdf, 0)? {
                Surface::Diffuse { reflectance, .. } => Surface::Diffuse {
                    reflectance,
                    two_sided: true,
                },
                Surface::Transparent => Surface::Transparent,
            },
            "mask" | "bumpmap" | "normalmap" | "coating" | "roughcoating" => {
                self.nested(bsdf, 0)?
            }
            "blendbsdf" => {
                let w = self.colour(bsdf, "weight", 0.5)?.x.clamp(0.0, 1.0);
                let rho = |s: Surface| match s {
                    Surface::Diffuse { reflectance, .. } => reflectance,
                    Surface::Transparent => Rgb::ZERO,
                };
                let (a, b) = (self.nested(bsdf, 0)?, self.nested(bsdf, 1)?);
                if a == Surface::Transparent && b == Surface::Transparent {
                    Surface::Transparent
                } else {
                    diffuse((1.0 - w) * rho(a) + w * rho(b))
                }
            }
            k if OTHER_BSDFS.contains(&k) => diffuse(Rgb::splat(0.5)),
            k => return Err(bsdf.error(format!("unknown BSDF plugin `{k}`"))),
        })
    }

    /// The `index`th nested BSDF's surface.
    fn nested(&mut self, bsdf: &Object, index: usize) -> Result<Surface, SceneError> {
        let inner: Vec<Arc<Object>> = bsdf.children(Class::Bsdf).cloned().collect();
        let inner = inner
            .get(index)
            .ok_or_else(|| bsdf.error(format!("needs a nested <bsdf> (found {})", inner.len())))?;
        self.surface(inner)
    }

    /// A colour property: an `rgb`/`spectrum`/number, or a texture's mean; `default` when
    /// absent.
    fn colour(&mut self, bsdf: &Object, name: &str, default: f64) -> Result<Rgb, SceneError> {
        match bsdf.get(name) {
            None => Ok(Rgb::splat(default)),
            Some(p) => self.value(p),
        }
    }

    fn value(&mut self, p: &Property) -> Result<Rgb, SceneError> {
        match &p.value {
            Value::Rgb(c) => Ok(*c),
            Value::Float(x) => Ok(Rgb::splat(*x)),
            Value::Object(t) if t.class == Class::Texture => self.texture_mean(t),
            _ => Err(p.error("expected a colour or a texture")),
        }
    }

    /// The mean of a texture over its domain.
    fn texture_mean(&mut self, t: &Object) -> Result<Rgb, SceneError> {
        match t.kind.as_str() {
            "bitmap" => {
                let name = t
                    .string("filename")?
                    .ok_or_else(|| t.error("a bitmap needs `filename`"))?;
                let path = resolve(&t.loc, name);
                let raw = t.boolean("raw", false)?;
                let key = (path.clone(), raw);
                if let Some(c) = self.textures.get(&key) {
                    return Ok(*c);
                }
                let mean = Texture::open(&path, raw)
                    .map_err(|e| t.error(format!("texture `{}`: {e}", path.display())))?
                    .mean();
                self.textures.insert(key, mean);
                Ok(mean)
            }
            "checkerboard" => {
                let a = self.colour(t, "color0", 0.4)?;
                let b = self.colour(t, "color1", 0.2)?;
                Ok(0.5 * (a + b))
            }
            "scale" => {
                let s = t.float("scale", 1.0)?;
                let inner = t
                    .children(Class::Texture)
                    .next()
                    .cloned()
                    .ok_or_else(|| t.error("a scale texture needs a nested <texture>"))?;
                Ok(s * self.texture_mean(&inner)?)
            }
            "gridtexture" => {
                let a = self.colour(t, "color0", 0.2)?;
                let b = self.colour(t, "color1", 0.4)?;
                Ok(0.5 * (a + b))
            }
            "vertexcolors" | "wireframe" | "curvature" | "volume" => Ok(Rgb::splat(0.5)),
            k => Err(t.error(format!("unknown texture plugin `{k}`"))),
        }
    }
}

/// Normal-incidence reflectance R₀ of a conductor named in Mitsuba's `material` list, in linear
/// RGB; `none` is Mitsuba 3's default, a perfect mirror. Metals not listed take 0.9.
#[must_use]
pub fn conductor_r0(material: &str) -> Rgb {
    match material {
        "none" => Rgb::ONE,
        "Ag" => Rgb::new(0.95, 0.93, 0.88),
        "Al" => Rgb::new(0.91, 0.92, 0.92),
        "Au" => Rgb::new(1.00, 0.71, 0.29),
        "Cu" => Rgb::new(0.95, 0.64, 0.54),
        "Cr" => Rgb::new(0.55, 0.56, 0.55),
        "Fe" => Rgb::new(0.56, 0.57, 0.58),
        _ => Rgb::splat(0.9),
    }
}

/// The one loading warning that names every approximated BSDF type, if any.
#[must_use]
pub fn warning(approximated: &BTreeMap<String, usize>) -> Option<String> {
    if approximated.is_empty() {
        return None;
    }
    let list: Vec<String> = approximated
        .iter()
        .map(|(k, n)| format!("{k} ({n})"))
        .collect();
    Some(format!(
        "BSDFs approximated as diffuse for radiosity (docs/mitsuba.md): {}",
        list.join(", ")
    ))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::super::xml::parse;
    use super::*;

    fn surfaces(xml: &str) -> Result<(Vec<Surface>, Mapper), SceneError> {
        let doc = parse(
            &format!("<scene version=\"3.0.0\">{xml}</scene>"),
            Path::new("b.xml"),
        )?;
        let mut m = Mapper::default();
        let s = doc
            .objects
            .iter()
            .map(|o| m.surface(o))
            .collect::<Result<_, _>>()?;
        Ok((s, m))
    }

    #[test]
    fn every_row_of_the_table() {
        let (s, m) = surfaces(
            r#"<bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.4, 0.6"/></bsdf></bsdf>
               <bsdf type="roughplastic"><rgb name="diffuseReflectance" value="0.3"/></bsdf>
               <bsdf type="conductor"><string name="material" value="Au"/></bsdf>
               <bsdf type="conductor"/>
               <bsdf type="dielectric"/>
               <bsdf type="blendbsdf"><float name="weight" value="0.25"/>
                 <bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf>
                 <bsdf type="diffuse"><rgb name="reflectance" value="0.4"/></bsdf></bsdf>
               <bsdf type="mask"><bsdf type="plastic"/></bsdf>
               <bsdf type="diffuse"><texture type="checkerboard" name="reflectance"/></bsdf>"#,
        )
        .unwrap();
        let d = |r: Rgb, two_sided| Surface::Diffuse {
            reflectance: r,
            two_sided,
        };
        assert_eq!(s[0], d(Rgb::new(0.2, 0.4, 0.6), true));
        assert_eq!(s[1], d(Rgb::splat(0.3), false));
        assert_eq!(s[2], d(Rgb::new(0.99, 0.71, 0.29), false));
        assert_eq!(s[3], d(Rgb::splat(MAX_REFLECTANCE), false));
        assert_eq!(s[4], Surface::Transparent);
        let Surface::Diffuse { reflectance, .. } = s[5] else {
            panic!()
        };
        assert!((reflectance - Rgb::splat(0.7)).length() < 1e-12);
        assert_eq!(s[6], d(Rgb::splat(0.5), false));
        let Surface::Diffuse { reflectance, .. } = s[7] else {
            panic!()
        };
        assert!(
            (reflectance - Rgb::splat(0.3)).length() < 1e-12,
            "checkerboard mean"
        );
        assert_eq!(
            warning(&m.approximated).unwrap(),
            "BSDFs approximated as diffuse for radiosity (docs/mitsuba.md): blendbsdf (1), \
             conductor (2), dielectric (1), mask (1), plastic (1), roughplastic (1)"
        );
    }

    #[test]
    fn unknown_plugins_are_located_errors() {
        let e = surfaces("\n<bsdf type=\"velvet\"/>").err().unwrap();
        assert_eq!(e.line_col, Some((2, 1)));
        assert!(e.message.contains("unknown BSDF plugin `velvet`"), "{e}");
        let e = surfaces(
            "<bsdf type=\"diffuse\"><texture type=\"noise\" name=\"reflectance\"/></bsdf>",
        )
        .err()
        .unwrap();
        assert!(e.message.contains("unknown texture plugin `noise`"), "{e}");
        let e = surfaces("<bsdf type=\"diffuse\"><texture type=\"bitmap\" name=\"reflectance\"><string name=\"filename\" value=\"gone.png\"/></texture></bsdf>")
            .err()
            .unwrap();
        assert!(e.message.contains("gone.png"), "{e}");
    }
}
