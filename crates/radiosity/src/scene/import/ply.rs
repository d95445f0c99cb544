//! Stanford PLY meshes (Turk 1994), ASCII or binary, read into the same indexed form as an OBJ
//! file ([`ObjFile`]).
//!
//! A PLY file is a header — `ply`, `format ascii|binary_little_endian|binary_big_endian 1.0`,
//! then `element NAME COUNT` lines each followed by its `property TYPE NAME` or `property list
//! COUNT_TYPE ITEM_TYPE NAME` lines, then `end_header` — and the elements' records in header
//! order. Read: the `vertex` element's `x`, `y`, `z`, and the `face` element's `vertex_indices`
//! (or `vertex_index`) list; every other element and property is skipped (normals, texture
//! coordinates and colours play no part in a radiosity solve). Scalar types: `char`/`int8`,
//! `uchar`/`uint8`, `short`/`int16`, `ushort`/`uint16`, `int`/`int32`, `uint`/`uint32`,
//! `float`/`float32`, `double`/`float64`.

use std::path::Path;

use glam::Vec3;

use super::obj::{ObjFace, ObjFile};
use crate::scene::SceneError;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Ascii,
    Little,
    Big,
}

#[derive(Clone, Copy, Debug)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
}

#[derive(Clone, Debug)]
enum Property {
    Scalar(Scalar, String),
    List(Scalar, Scalar, String),
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// Reads a PLY file's positions and faces (one group named after the file's stem, no
/// materials).
///
/// # Errors
/// The file cannot be read, its header is malformed, or its data ends early or indexes a
/// vertex that does not exist; naming the file (and the header line for header problems).
pub fn read_ply(path: &Path) -> Result<ObjFile, SceneError> {
    let bytes =
        std::fs::read(path).map_err(|e| SceneError::in_file(path, format!("cannot read: {e}")))?;
    parse_ply(&bytes, path)
}

/// Parses PLY bytes; `file` names it in messages.
///
/// # Errors
/// As [`read_ply`].
pub fn parse_ply(bytes: &[u8], file: &Path) -> Result<ObjFile, SceneError> {
    let err = |m: String| SceneError::in_file(file, m);
    let (format, elements, body) = header(bytes).map_err(|(line, m)| {
        SceneError::at(
            crate::scene::Loc {
                file: file.to_path_buf(),
                line,
                col: 1,
            },
            m,
        )
    })?;
    let name = file
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("mesh")
        .to_string();
    let mut obj = ObjFile {
        groups: vec![name],
        ..ObjFile::default()
    };
    let mut data = Data {
        format,
        bytes: body,
        at: 0,
        ascii: None,
    };
    if format == Format::Ascii {
        let text = std::str::from_utf8(body).map_err(|_| err("ASCII data is not text".into()))?;
        data.ascii = Some(text.split_ascii_whitespace());
    }
    for element in &elements {
        for _ in 0..element.count {
            let mut position = [0.0f32; 3];
            let mut face: Option<Vec<u32>> = None;
            for p in &element.properties {
                match p {
                    Property::Scalar(t, n) => {
                        let v = data.scalar(*t).ok_or_else(|| err(early(&element.name)))?;
                        if element.name == "vertex" {
                            match n.as_str() {
                                "x" => position[0] = v as f32,
                                "y" => position[1] = v as f32,
                                "z" => position[2] = v as f32,
                                _ => {}
                            }
                        }
                    }
                    Property::List(ct, it, n) => {
                        let count = data.scalar(*ct).ok_or_else(|| err(early(&element.name)))?;
                        if !(0.0..=f64::from(u16::MAX)).contains(&count) {
                            return Err(err(format!(
                                "a list of {count} items in `{}`",
                                element.name
                            )));
                        }
                        let is_face = element.name == "face"
                            && (n == "vertex_indices" || n == "vertex_index");
                        let mut items = Vec::with_capacity(count as usize);
                        for _ in 0..count as usize {
                            let v = data.scalar(*it).ok_or_else(|| err(early(&element.name)))?;
                            items.push(v);
                        }
                        if is_face {
                            face = Some(
                                items
                                    .iter()
                                    .map(|&v| if v >= 0.0 { v as u32 } else { u32::MAX })
                                    .collect(),
                            );
                        }
                    }
                }
            }
            if element.name == "vertex" {
                obj.positions.push(Vec3::from_array(position));
            } else if let Some(indices) = face {
                obj.faces.push(ObjFace {
                    indices,
                    uv: None,
                    group: 0,
                    material: 0,
                    line: 0,
                });
            }
        }
    }
    let n = obj.positions.len();
    if let Some(bad) = obj
        .faces
        .iter()
        .flat_map(|f| f.indices.iter())
        .find(|&&i| i as usize >= n)
    {
        return Err(err(format!("a face refers to vertex {bad} of {n}")));
    }
    obj.materials.push(crate::scene::Material::default());
    Ok(obj)
}

fn early(element: &str) -> String {
    format!("the data ends inside element `{element}`")
}

type Header<'a> = (Format, Vec<Element>, &'a [u8]);

/// The header's format and elements, and the bytes after `end_header`; errors carry their
/// 1-based header line.
fn header(bytes: &[u8]) -> Result<Header<'_>, (usize, String)> {
    let mut at = 0;
    let mut lines = 0;
    let mut next_line = || -> Option<&str> {
        let rest = &bytes[at..];
        let end = rest.iter().position(|&b| b == b'\n')?;
        at += end + 1;
        lines += 1;
        std::str::from_utf8(&rest[..end])
            .ok()
            .map(|s| s.trim_end_matches('\r'))
    };
    if next_line() != Some("ply") {
        return Err((1, "not a PLY file (it must start with `ply`)".into()));
    }
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut line_no = 1;
    loop {
        let line =
            next_line().ok_or((line_no + 1, "the header has no `end_header`".to_string()))?;
        line_no += 1;
        let words: Vec<&str> = line.split_ascii_whitespace().collect();
        match words.as_slice() {
            ["end_header"] => break,
            ["comment", ..] | ["obj_info", ..] | [] => {}
            ["format", f, _] => {
                format = Some(match *f {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::Little,
                    "binary_big_endian" => Format::Big,
                    _ => return Err((line_no, format!("unknown format `{f}`"))),
                });
            }
            ["element", name, count] => elements.push(Element {
                name: (*name).to_string(),
                count: count
                    .parse()
                    .map_err(|_| (line_no, format!("`{count}` is not a count")))?,
                properties: Vec::new(),
            }),
            ["property", "list", ct, it, name] => {
                let (Some(ct), Some(it)) = (Scalar::parse(ct), Scalar::parse(it)) else {
                    return Err((line_no, format!("unknown type in `{line}`")));
                };
                elements
                    .last_mut()
                    .ok_or((line_no, "a property before any element".to_string()))?
                    .properties
                    .push(Property::List(ct, it, (*name).to_string()));
            }
            ["property", t, name] => {
                let t = Scalar::parse(t).ok_or((line_no, format!("unknown type `{t}`")))?;
                elements
                    .last_mut()
                    .ok_or((line_no, "a property before any element".to_string()))?
                    .properties
                    .push(Property::Scalar(t, (*name).to_string()));
            }
            _ => return Err((line_no, format!("unexpected header line `{line}`"))),
        }
    }
    let format = format.ok_or((1, "the header has no `format` line".to_string()))?;
    Ok((format, elements, &bytes[at..]))
}

/// The data section, read one scalar at a time.
struct Data<'a> {
    format: Format,
    bytes: &'a [u8],
    at: usize,
    ascii: Option<std::str::SplitAsciiWhitespace<'a>>,
}

impl Data<'_> {
    fn scalar(&mut self, t: Scalar) -> Option<f64> {
        if let Some(words) = &mut self.ascii {
            return words.next()?.parse().ok();
        }
        let b = self.bytes.get(self.at..self.at + t.size())?;
        self.at += t.size();
        let little = self.format == Format::Little;
        macro_rules! read {
            ($ty:ty) => {{
                let a = b.try_into().ok()?;
                f64::from(if little {
                    <$ty>::from_le_bytes(a)
                } else {
                    <$ty>::from_be_bytes(a)
                })
            }};
        }
        Some(match t {
            Scalar::I8 => read!(i8),
            Scalar::U8 => read!(u8),
            Scalar::I16 => read!(i16),
            Scalar::U16 => read!(u16),
            Scalar::I32 => read!(i32),
            Scalar::U32 => read!(u32),
            Scalar::F32 => read!(f32),
            Scalar::F64 => read!(f64),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII: &str = "ply\nformat ascii 1.0\ncomment a unit square\nelement vertex 4\n\
        property float x\nproperty float y\nproperty float z\nproperty float nx\n\
        element face 1\nproperty list uchar int vertex_indices\nend_header\n\
        0 0 0 9\n1 0 0 9\n1 1 0 9\n0 1 0 9\n4 0 1 2 3\n";

    #[test]
    fn ascii_and_binary_read_the_same_square() {
        let a = parse_ply(ASCII.as_bytes(), Path::new("sq.ply")).unwrap();
        assert_eq!(a.positions[2], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(a.faces[0].indices, vec![0, 1, 2, 3]);
        assert_eq!(a.groups, vec!["sq".to_string()]);
        // The same square, binary little-endian, with a uv pair skipped and an extra element.
        let mut bin = b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n\
            property float y\nproperty float z\nproperty float u\nelement face 1\n\
            property list uchar uint vertex_indices\nelement edge 1\nproperty int a\nend_header\n"
            .to_vec();
        for p in [
            [0.0f32, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ] {
            for c in p.iter().chain(&[5.0]) {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        bin.push(4);
        for i in 0u32..4 {
            bin.extend_from_slice(&i.to_le_bytes());
        }
        bin.extend_from_slice(&7i32.to_le_bytes());
        let b = parse_ply(&bin, Path::new("sq.ply")).unwrap();
        assert_eq!((b.positions, b.faces), (a.positions, a.faces));
    }

    #[test]
    fn problems_name_the_file_and_header_line() {
        let e = parse_ply(
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n",
            Path::new("m.ply"),
        )
        .unwrap_err();
        assert_eq!(e.line_col, Some((4, 1)));
        let short = ASCII.replace("4 0 1 2 3\n", "4 0 1\n");
        let e = parse_ply(short.as_bytes(), Path::new("m.ply")).unwrap_err();
        assert!(e.message.contains("ends inside element `face`"), "{e}");
        let bad = ASCII.replace("4 0 1 2 3", "4 0 1 2 9");
        let e = parse_ply(bad.as_bytes(), Path::new("m.ply")).unwrap_err();
        assert!(e.message.contains("vertex 9"), "{e}");
        assert!(parse_ply(b"solid x\n", Path::new("m.ply")).is_err());
    }
}
