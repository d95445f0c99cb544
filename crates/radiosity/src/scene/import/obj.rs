//! Wavefront OBJ and MTL, read with line and column numbers for every error.
//!
//! OBJ statements read: `v x y z` (extra values such as `w` or vertex colours are ignored),
//! `vt u v` (texture coordinates; v is flipped to the image-down convention of
//! [`crate::scene::texture`]), `f` with three or more corners in any of the forms `v`, `v/vt`,
//! `v//vn`, `v/vt/vn`, where an index is 1-based or, when negative, relative to the end of the
//! vertices (or texture coordinates) read so far; `o`/`g` (the name of the object the following
//! faces belong to), `usemtl`, `mtllib`. A face has texture coordinates when every corner
//! names one that exists. `#` starts a comment anywhere on a line and a trailing `\` continues a line.
//! Everything else (`vn`, `s`, `l`, ...) is skipped.
//!
//! MTL statements read: `newmtl`, `Kd` → diffuse reflectance ρ, `Ke` → emitted radiance L_e,
//! `map_Kd` → a diffuse texture (PNG or JPEG, relative to the MTL file; `-clamp on` clamps
//! instead of repeating, other options are ignored with a warning). The texture **replaces**
//! `Kd`, as Blender's importer does and as exporters that write a default `Kd 0.8` beside a
//! texture expect: ρ is the texture's mean over each face ([`crate::scene::texture`]), and the
//! material's ρ where a face has no `vt` is the image's mean, both clamped to
//! [`crate::scene::MAX_REFLECTANCE`]. A texture that cannot be read leaves `Kd` in force, with a warning
//! naming the file. Other keys are ignored. A missing MTL file or an unknown `usemtl` name
//! falls back to a default material (ρ = 0.5) with a warning; faces before any `usemtl` use it
//! silently.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Vec2, Vec3};

use crate::scene::texture::{Texture, TextureMap, Wrap};
use crate::scene::{Loc, Material, SceneError};
use crate::Rgb;

/// An OBJ file: positions, faces grouped by object name, and the materials they use.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjFile {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Texture coordinates (image-down convention, [`crate::scene::texture`]).
    pub texcoords: Vec<Vec2>,
    /// Faces in file order.
    pub faces: Vec<ObjFace>,
    /// Object/group names; faces refer to them by index. Faces before any `o`/`g` belong to
    /// `default`.
    pub groups: Vec<String>,
    /// Materials; faces refer to them by index.
    pub materials: Vec<Material>,
    /// Problems repaired while reading, one line each.
    pub warnings: Vec<String>,
}

/// One `f` statement.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ObjFace {
    /// Zero-based indices into [`ObjFile::positions`].
    pub indices: Vec<u32>,
    /// Zero-based indices into [`ObjFile::texcoords`], one per corner, if the face has them.
    pub uv: Option<Vec<u32>>,
    /// Index into [`ObjFile::groups`].
    pub group: usize,
    /// Index into [`ObjFile::materials`].
    pub material: usize,
    /// 1-based line of the statement.
    pub line: usize,
}

impl ObjFace {
    /// The face's corners.
    #[must_use]
    pub fn positions(&self, obj: &ObjFile) -> Vec<Vec3> {
        self.indices
            .iter()
            .map(|&i| obj.positions[i as usize])
            .collect()
    }

    /// The face's texture coordinates, if it has them.
    #[must_use]
    pub fn texcoords(&self, obj: &ObjFile) -> Option<Vec<Vec2>> {
        let uv = self.uv.as_ref()?;
        Some(uv.iter().map(|&i| obj.texcoords[i as usize]).collect())
    }
}

/// Reads an OBJ file and the MTL files it names (relative to its folder).
///
/// # Errors
/// The file cannot be read, a number does not parse, or an index is out of range; with
/// `file:line:col`.
pub fn read_obj(path: &Path) -> Result<ObjFile, SceneError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| SceneError::in_file(path, format!("cannot read: {e}")))?;
    parse_obj(&text, path)
}

/// Parses OBJ text; `file` names it in messages and locates its `mtllib` files.
///
/// # Errors
/// As [`read_obj`].
pub fn parse_obj(text: &str, file: &Path) -> Result<ObjFile, SceneError> {
    let mut obj = ObjFile {
        groups: vec!["default".into()],
        ..ObjFile::default()
    };
    // Material names as used, resolved against the MTL libraries at the end.
    let mut used: Vec<String> = Vec::new();
    let mut library: Vec<Material> = Vec::new();
    let mut group = 0;
    let mut material: Option<usize> = None;
    for line in Lines::new(text, file) {
        let mut tokens = line.tokens.iter();
        let Some(first) = tokens.next() else {
            continue;
        };
        let rest = &line.tokens[1..];
        match first.text {
            "v" => {
                if rest.len() < 3 {
                    return Err(line.error(first, "a vertex needs 3 coordinates"));
                }
                let mut p = [0.0f32; 3];
                for (c, t) in p.iter_mut().zip(rest) {
                    *c = line.number(t)? as f32;
                }
                obj.positions.push(Vec3::from_array(p));
            }
            "vt" => {
                let Some(u) = rest.first() else {
                    return Err(line.error(first, "a texture coordinate needs u"));
                };
                let v = rest.get(1).map_or(Ok(0.0), |t| line.number(t))?;
                obj.texcoords
                    .push(Vec2::new(line.number(u)? as f32, (1.0 - v) as f32));
            }
            "f" => {
                let mut indices = Vec::with_capacity(rest.len());
                let mut uv = Vec::with_capacity(rest.len());
                for t in rest {
                    let (v, vt) = line.corner(t, obj.positions.len(), obj.texcoords.len())?;
                    indices.push(v);
                    uv.extend(vt);
                }
                let material = *material.get_or_insert_with(|| intern(&mut used, ""));
                obj.faces.push(ObjFace {
                    uv: (uv.len() == indices.len()).then_some(uv),
                    indices,
                    group,
                    material,
                    line: line.number_1,
                });
            }
            "o" | "g" => {
                let name = line.rest_after().unwrap_or("default").to_string();
                group = match obj.groups.iter().position(|g| *g == name) {
                    Some(i) => i,
                    None => {
                        obj.groups.push(name);
                        obj.groups.len() - 1
                    }
                };
            }
            "usemtl" => {
                let name = line.rest_after().unwrap_or("");
                material = Some(intern(&mut used, name));
            }
            "mtllib" => {
                for t in rest {
                    let path = file.parent().unwrap_or(Path::new("")).join(t.text);
                    match std::fs::read_to_string(&path) {
                        Ok(mtl) => library.extend(parse_mtl(&mtl, &path, &mut obj.warnings)?),
                        Err(e) => obj.warnings.push(format!(
                            "{}: cannot read material library `{}`: {e}; default material used",
                            line.loc(t),
                            t.text
                        )),
                    }
                }
            }
            _ => {}
        }
    }
    // Resolve used names: "" is "no usemtl", unknown names get the default with a warning.
    for name in used {
        match library.iter().find(|m| m.name == name) {
            Some(m) => obj.materials.push(m.clone()),
            None => {
                if !name.is_empty() {
                    obj.warnings.push(format!(
                        "{}: unknown material `{name}`; default material (reflectance 0.5) used",
                        file.display()
                    ));
                }
                obj.materials.push(Material {
                    name: if name.is_empty() {
                        "default".into()
                    } else {
                        name
                    },
                    ..Material::default()
                });
            }
        }
    }
    // Drop groups no face uses (e.g. `default` when every face is in a named group).
    let mut remap = vec![usize::MAX; obj.groups.len()];
    let mut kept = Vec::new();
    for f in &mut obj.faces {
        if remap[f.group] == usize::MAX {
            remap[f.group] = kept.len();
            kept.push(obj.groups[f.group].clone());
        }
        f.group = remap[f.group];
    }
    obj.groups = kept;
    Ok(obj)
}

/// Parses MTL text into materials; `file` names it in messages and locates its textures.
/// Textures that cannot be read are reported in `warnings` (the material keeps its `Kd`).
///
/// # Errors
/// A number does not parse or is out of range (Kd outside [0, 1), Ke negative), with
/// `file:line:col`.
pub fn parse_mtl(
    text: &str,
    file: &Path,
    warnings: &mut Vec<String>,
) -> Result<Vec<Material>, SceneError> {
    let mut materials: Vec<Material> = Vec::new();
    // `map_Kd` per material (the last one wins), read once `Kd` can no longer change.
    let mut maps: Vec<(usize, MapKd)> = Vec::new();
    for line in Lines::new(text, file) {
        let Some(first) = line.tokens.first() else {
            continue;
        };
        let rest = &line.tokens[1..];
        match first.text {
            "newmtl" => materials.push(Material {
                name: line.rest_after().unwrap_or("").to_string(),
                ..Material::default()
            }),
            "Kd" | "Ke" => {
                let Some(m) = materials.last_mut() else {
                    return Err(line.error(first, "material value before any `newmtl`"));
                };
                let c = line.colour(first, rest)?;
                if first.text == "Kd" {
                    if !c.cmpge(Rgb::ZERO).all() || !c.cmplt(Rgb::ONE).all() {
                        return Err(
                            line.error(&rest[0], &format!("reflectance {c} is outside [0, 1)"))
                        );
                    }
                    m.reflectance = c;
                } else {
                    if !c.cmpge(Rgb::ZERO).all() {
                        return Err(line.error(&rest[0], &format!("emission {c} is negative")));
                    }
                    m.emission = c;
                }
            }
            "map_Kd" => {
                if materials.is_empty() {
                    return Err(line.error(first, "material value before any `newmtl`"));
                }
                let map = MapKd::parse(&line, rest, file, warnings)?;
                maps.retain(|(m, _)| *m != materials.len() - 1);
                maps.push((materials.len() - 1, map));
            }
            _ => {}
        }
    }
    let mut images: HashMap<PathBuf, Option<Arc<Texture>>> = HashMap::new();
    for (m, map) in maps {
        let image = images.entry(map.path.clone()).or_insert_with(|| {
            match Texture::open(&map.path, false) {
                Ok(t) => Some(Arc::new(t)),
                Err(e) => {
                    warnings.push(format!(
                        "{}: map_Kd `{}`: {e}; Kd used",
                        map.loc,
                        map.path.display()
                    ));
                    None
                }
            }
        });
        if let Some(texture) = image {
            let texture = TextureMap {
                texture: Arc::clone(texture),
                wrap: [map.wrap; 2],
                factor: Rgb::ONE,
            };
            materials[m].reflectance = texture.mean();
            materials[m].texture = Some(texture);
        }
    }
    Ok(materials)
}

/// A `map_Kd` statement: `map_Kd [-option value…] file`.
struct MapKd {
    /// The image, relative to the MTL file's folder.
    path: PathBuf,
    wrap: Wrap,
    /// Where the statement is, for messages.
    loc: Loc,
}

impl MapKd {
    /// Reads the options and the file name; options other than `-clamp` are reported in
    /// `warnings`.
    fn parse(
        line: &Line<'_>,
        rest: &[Token<'_>],
        file: &Path,
        warnings: &mut Vec<String>,
    ) -> Result<Self, SceneError> {
        let mut wrap = Wrap::Repeat;
        let mut k = 0;
        while let Some(option) = rest.get(k).filter(|t| t.text.starts_with('-')) {
            // Each option's values: one word, two numbers (`-mm`), or one to three (`-o`, `-s`, `-t`).
            let values = match option.text {
                "-mm" => 2,
                "-o" | "-s" | "-t" => {
                    let numbers = rest[k + 1..]
                        .iter()
                        .take(3)
                        .take_while(|t| t.text.parse::<f64>().is_ok())
                        .count();
                    numbers.max(1)
                }
                _ => 1,
            };
            if option.text == "-clamp" {
                if rest.get(k + 1).is_some_and(|t| t.text == "on") {
                    wrap = Wrap::ClampToEdge;
                }
            } else {
                warnings.push(format!(
                    "{}: map_Kd option `{}` is ignored",
                    line.loc(option),
                    option.text
                ));
            }
            k += 1 + values;
        }
        let name: Vec<&str> = rest.iter().skip(k).map(|t| t.text).collect();
        if name.is_empty() {
            return Err(line.error(&line.tokens[0], "expected a file name"));
        }
        // Files written on Windows separate folders with `\`.
        let name = name.join(" ").replace('\\', "/");
        Ok(Self {
            path: file.parent().unwrap_or(Path::new("")).join(name),
            wrap,
            loc: line.loc(&line.tokens[0]),
        })
    }
}

/// Index of `name` in `names`, added if new.
fn intern(names: &mut Vec<String>, name: &str) -> usize {
    names.iter().position(|n| n == name).unwrap_or_else(|| {
        names.push(name.to_string());
        names.len() - 1
    })
}

/// A word of a line and its 1-based column.
struct Token<'a> {
    text: &'a str,
    col: usize,
}

/// One logical line: its words (comments removed, continuations joined).
struct Line<'a> {
    file: &'a Path,
    number_1: usize,
    text: String,
    tokens: Vec<Token<'a>>,
}

impl Line<'_> {
    fn loc(&self, t: &Token<'_>) -> Loc {
        Loc {
            file: self.file.to_path_buf(),
            line: self.number_1,
            col: t.col,
        }
    }

    fn error(&self, t: &Token<'_>, message: &str) -> SceneError {
        SceneError::at(self.loc(t), message).with_key(self.tokens[0].text)
    }

    /// Everything after the statement word, trimmed (names may contain spaces).
    fn rest_after(&self) -> Option<&str> {
        let rest = self.text.trim_start();
        let rest = rest.split_once(char::is_whitespace)?.1.trim();
        (!rest.is_empty()).then_some(rest)
    }

    fn number(&self, t: &Token<'_>) -> Result<f64, SceneError> {
        match t.text.parse::<f64>() {
            Ok(x) if x.is_finite() && (x as f32).is_finite() => Ok(x),
            _ => Err(self.error(t, &format!("`{}` is not a finite number", t.text))),
        }
    }

    /// One to three numbers (one means grey); `Kd spectral ...` and the like are refused.
    fn colour(&self, first: &Token<'_>, rest: &[Token<'_>]) -> Result<Rgb, SceneError> {
        let values = rest
            .iter()
            .take(3)
            .map(|t| self.number(t))
            .collect::<Result<Vec<_>, _>>()?;
        match values[..] {
            [g] => Ok(Rgb::splat(g)),
            [r, g, b] => Ok(Rgb::new(r, g, b)),
            _ => Err(self.error(first, "expected 1 or 3 numbers")),
        }
    }

    /// A face corner `v[/vt][/vn]` as a zero-based vertex index and, when `vt` names one of
    /// the `texcoords` read so far, a zero-based texture coordinate index.
    fn corner(
        &self,
        t: &Token<'_>,
        positions: usize,
        texcoords: usize,
    ) -> Result<(u32, Option<u32>), SceneError> {
        let mut parts = t.text.split('/');
        let first = parts.next().unwrap_or("");
        let Ok(i) = first.parse::<i64>() else {
            return Err(self.error(t, &format!("`{}` is not a vertex index", t.text)));
        };
        let Some(v) = resolve(i, positions) else {
            return Err(self.error(
                t,
                &format!("vertex index {i} is out of range ({positions} vertices so far)"),
            ));
        };
        let vt = parts
            .next()
            .and_then(|p| p.parse::<i64>().ok())
            .and_then(|i| resolve(i, texcoords));
        Ok((v, vt))
    }
}

/// A 1-based (or negative, relative) OBJ index into `count` items, zero-based.
fn resolve(i: i64, count: usize) -> Option<u32> {
    let resolved = if i > 0 { i - 1 } else { count as i64 + i };
    if i == 0 || resolved < 0 || resolved >= count as i64 {
        return None;
    }
    u32::try_from(resolved).ok()
}

/// Logical lines of an OBJ/MTL text.
struct Lines<'a> {
    file: &'a Path,
    raw: std::iter::Enumerate<std::str::Lines<'a>>,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str, file: &'a Path) -> Self {
        Self {
            file,
            raw: text.lines().enumerate(),
        }
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = Line<'a>;

    fn next(&mut self) -> Option<Line<'a>> {
        let (i, first) = self.raw.next()?;
        let mut tokens = Vec::new();
        let mut text = String::new();
        let mut part = first;
        loop {
            let code = part.split('#').next().unwrap_or("");
            let continued = code.trim_end().strip_suffix('\\');
            let code = continued.unwrap_or(code);
            // Columns of continuation lines count from the start of the statement's line.
            let offset = text.chars().count();
            tokens.extend(words(code, offset));
            text.push_str(code);
            text.push(' ');
            match continued.and_then(|_| self.raw.next()) {
                Some((_, next)) => part = next,
                None => break,
            }
        }
        Some(Line {
            file: self.file,
            number_1: i + 1,
            text,
            tokens,
        })
    }
}

/// Whitespace-separated words with 1-based character columns (plus `offset`).
fn words(code: &str, offset: usize) -> impl Iterator<Item = Token<'_>> {
    let mut col = offset;
    let mut start: Option<(usize, usize)> = None;
    let mut out = Vec::new();
    for (byte, ch) in code.char_indices() {
        col += 1;
        match (ch.is_whitespace(), start) {
            (false, None) => start = Some((byte, col)),
            (true, Some((b, c))) => {
                out.push(Token {
                    text: &code[b..byte],
                    col: c,
                });
                start = None;
            }
            _ => {}
        }
    }
    if let Some((b, c)) = start {
        out.push(Token {
            text: &code[b..],
            col: c,
        });
    }
    out.into_iter()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_groups_negative_indices_and_comments() {
        let text = "# a quad and a triangle\n\
                    v 0 0 0\nv 1 0 0 # trailing comment\nv 1 1 0\nv 0 1 0\n\
                    o quad\nf 1/1/1 2//2 3/3 4\n\
                    g tri\nv 2 0 0\nf -1 -4 \\\n -3\n";
        let obj = parse_obj(text, Path::new("t.obj")).unwrap();
        assert_eq!(obj.positions.len(), 5);
        assert_eq!(obj.groups, ["quad", "tri"]);
        assert_eq!(obj.faces[0].indices, [0, 1, 2, 3]);
        assert_eq!(obj.faces[1].indices, [4, 1, 2]);
        assert_eq!(obj.faces[1].group, 1);
        assert_eq!(obj.faces[1].line, 10);
        assert_eq!(obj.materials.len(), 1);
        assert_eq!(obj.materials[0].reflectance, Rgb::splat(0.5));
        assert!(obj.warnings.is_empty());
    }

    #[test]
    fn errors_have_line_and_column() {
        let e = parse_obj("v 0 0 0\nf 1 2 3\n", Path::new("t.obj")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.obj:2:5: `f`: vertex index 2 is out of range (1 vertices so far)"
        );
        let e = parse_obj("v 0 x 0\n", Path::new("t.obj")).unwrap_err();
        assert_eq!(e.to_string(), "t.obj:1:5: `v`: `x` is not a finite number");
        let e = parse_mtl(
            "newmtl a\n  Kd 0.5 1.0 0.5\n",
            Path::new("t.mtl"),
            &mut Vec::new(),
        )
        .unwrap_err();
        assert!(
            e.to_string().starts_with("t.mtl:2:6: `Kd`: reflectance"),
            "{e}"
        );
    }

    #[test]
    fn mtl_reads_kd_and_ke() {
        let m = parse_mtl(
            "newmtl light\nKd 0.78 0.78 0.78\nKe 17 12 4\nNs 10\nnewmtl grey\nKd 0.2\n",
            Path::new("t.mtl"),
            &mut Vec::new(),
        )
        .unwrap();
        assert_eq!(m.len(), 2);
        assert_eq!(m[0].emission, Rgb::new(17.0, 12.0, 4.0));
        assert_eq!(m[1].reflectance, Rgb::splat(0.2));
    }
}
