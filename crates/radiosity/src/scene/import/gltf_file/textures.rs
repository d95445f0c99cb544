//! glTF base colour textures (§3.9.2, §5.22 images, §5.26 samplers) as reflectance.
//!
//! A material's `baseColorTexture` names a texture: an image and a sampler. The image is PNG or
//! JPEG, held in a buffer view (`.glb`), a `data:` URI (base64) or a file beside the `.gltf`;
//! it is sRGB-encoded, as the specification says of base colour. The sampler's `wrapS` and
//! `wrapT` (default `REPEAT`) say what lies outside [0, 1]; its filters are not needed for
//! means. Reflectance is `baseColorFactor` × the texture ([`crate::scene::texture`]), read
//! with `TEXCOORD_0`; a texture on another coordinate set counts with the image's mean.
//!
//! An image that cannot be found or decoded is a warning naming it, and the material keeps its
//! factor.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use gltf::texture::WrappingMode;

use super::buffers::{decode_base64, percent_decode};
use crate::scene::texture::{Texture, TextureMap, Wrap};
use crate::scene::Material;

/// Decoded images by glTF image index (`None`: could not be read), so that materials sharing
/// one image decode it once.
#[derive(Default)]
pub(super) struct Images {
    decoded: HashMap<usize, Option<Arc<Texture>>>,
}

impl Images {
    /// Lays `source`'s `baseColorTexture`, if it has one that can be read, over `material`,
    /// whose reflectance is the factor: the texture becomes its [`Material::texture`] and the
    /// image's mean its reflectance. Problems are pushed to `warnings`.
    pub(super) fn apply(
        &mut self,
        source: &gltf::Material,
        material: &mut Material,
        buffers: &[Vec<u8>],
        file: &Path,
        warnings: &mut Vec<String>,
    ) {
        let Some(info) = source.pbr_metallic_roughness().base_color_texture() else {
            return;
        };
        let texture = info.texture();
        let image = texture.source();
        let decoded = self.decoded.entry(image.index()).or_insert_with(|| {
            match read_image(&image, buffers, file) {
                Ok(t) => Some(Arc::new(t)),
                Err(e) => {
                    warnings.push(format!(
                        "{}: material `{}`: baseColorTexture: {e}; its factor is used",
                        file.display(),
                        material.name
                    ));
                    None
                }
            }
        });
        let Some(decoded) = decoded else {
            return;
        };
        let map = TextureMap {
            texture: Arc::clone(decoded),
            wrap: [texture.sampler().wrap_s(), texture.sampler().wrap_t()].map(wrap),
            factor: material.reflectance,
        };
        material.reflectance = map.mean();
        if info.tex_coord() == 0 {
            material.texture = Some(map);
        } else {
            warnings.push(format!(
                "{}: material `{}`: baseColorTexture uses TEXCOORD_{}, which is not read: \
                 the image's mean is used",
                file.display(),
                material.name,
                info.tex_coord()
            ));
        }
    }
}

/// The decoded image; the error names the image (its file, or its index when embedded).
fn read_image(image: &gltf::Image, buffers: &[Vec<u8>], file: &Path) -> Result<Texture, String> {
    let embedded = format!("image {}", image.index());
    match image.source() {
        gltf::image::Source::View { view, .. } => {
            let start = view.offset();
            let bytes = buffers
                .get(view.buffer().index())
                .and_then(|b| b.get(start..start + view.length()))
                .ok_or_else(|| format!("{embedded}: its buffer view is out of range"))?;
            Texture::decode(bytes, false).map_err(|e| format!("{embedded}: {e}"))
        }
        gltf::image::Source::Uri { uri, .. } if uri.starts_with("data:") => {
            let bytes = uri
                .split_once(";base64,")
                .and_then(|(_, payload)| decode_base64(payload))
                .ok_or_else(|| format!("{embedded}: malformed base64 data URI"))?;
            Texture::decode(&bytes, false).map_err(|e| format!("{embedded}: {e}"))
        }
        gltf::image::Source::Uri { uri, .. } => {
            let path = file
                .parent()
                .unwrap_or(Path::new(""))
                .join(percent_decode(uri));
            Texture::open(&path, false).map_err(|e| format!("`{}`: {e}", path.display()))
        }
    }
}

/// The texture's wrap mode of a glTF sampler's.
fn wrap(mode: WrappingMode) -> Wrap {
    match mode {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
    }
}
