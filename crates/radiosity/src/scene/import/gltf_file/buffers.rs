//! The bytes of a glTF file's buffers: the GLB binary chunk, `data:` URIs (base64) and files
//! (percent-encoded relative paths).

use std::path::Path;

use crate::scene::SceneError;

/// The bytes of every buffer, in order: the GLB binary chunk, a `data:` URI or a file.
pub(super) fn load_buffers(gltf: &gltf::Gltf, file: &Path) -> Result<Vec<Vec<u8>>, SceneError> {
    let mut out = Vec::new();
    for buffer in gltf.document.buffers() {
        let err = |m: String| SceneError::in_file(file, format!("buffer {}: {m}", buffer.index()));
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => gltf
                .blob
                .clone()
                .ok_or_else(|| err("the GLB binary chunk is missing".into()))?,
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                let payload = uri
                    .split_once(";base64,")
                    .map(|(_, p)| p)
                    .ok_or_else(|| err("only base64 data URIs are supported".into()))?;
                decode_base64(payload).ok_or_else(|| err("malformed base64 data".into()))?
            }
            gltf::buffer::Source::Uri(uri) => {
                let path = file
                    .parent()
                    .unwrap_or(Path::new(""))
                    .join(percent_decode(uri));
                std::fs::read(&path)
                    .map_err(|e| err(format!("cannot read `{}`: {e}", path.display())))?
            }
        };
        if data.len() < buffer.length() {
            return Err(err(format!(
                "holds {} bytes, fewer than its byteLength {}",
                data.len(),
                buffer.length()
            )));
        }
        out.push(data);
    }
    Ok(out)
}

/// Decodes standard base64 (RFC 4648 §4), padding optional; `None` on a bad character.
pub(super) fn decode_base64(text: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    let (mut acc, mut bits) = (0u32, 0u32);
    for c in text
        .bytes()
        .filter(|&c| c != b'=' && !c.is_ascii_whitespace())
    {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

/// Decodes `%XX` escapes of a relative URI (RFC 3986 §2.1); malformed escapes stay as written.
pub(super) fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(b)) => {
                out.push(b);
                i += 3;
            }
            (b, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}
