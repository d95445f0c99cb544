//! Mitsuba's XML, read into a tree of plugins with typed, located properties.
//!
//! A Mitsuba scene file (Mitsuba 3 "Scene XML file format"; Mitsuba 0.6 documentation §6) is a
//! tree of *objects* — `<shape>`, `<bsdf>`, `<emitter>`, `<sensor>`, `<texture>`, … each with a
//! plugin `type` and an optional `id` — whose leaves are *properties*: `<float>`, `<integer>`,
//! `<boolean>`, `<string>`, `<rgb>`, `<spectrum>`, `<point>`, `<vector>` and `<transform>`, each
//! with a `name`. `<ref id="…"/>` stands for an object declared elsewhere, `<default name
//! value/>` declares a parameter that `$name` in any attribute stands for, and `<include
//! filename/>` splices another file in.
//!
//! Both versions' spellings are accepted: Mitsuba 0.6's camelCase property names (`toWorld`,
//! `diffuseReflectance`) are read as Mitsuba 3's snake_case ones (`to_world`,
//! `diffuse_reflectance`), which is what Mitsuba 3's own upgrade of a 0.6 file does.
//!
//! Every object and property keeps its [`Loc`] (file, line, column), so that a later stage can
//! point at the exact element of a problem.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use crate::color::srgb_to_linear;
use crate::scene::{Loc, SceneError};
use crate::Rgb;

/// The kind of an object element (its tag).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Class {
    /// `<shape>`.
    Shape,
    /// `<bsdf>`.
    Bsdf,
    /// `<emitter>`.
    Emitter,
    /// `<sensor>`.
    Sensor,
    /// `<texture>`.
    Texture,
    /// `<film>`.
    Film,
    /// Read and ignored by a radiosity renderer: `<integrator>`, `<sampler>`, `<rfilter>`,
    /// `<medium>`, `<phase>`, `<volume>`, `<subsurface>`.
    Other,
}

impl Class {
    fn of_tag(tag: &str) -> Option<Self> {
        Some(match tag {
            "shape" => Self::Shape,
            "bsdf" => Self::Bsdf,
            "emitter" => Self::Emitter,
            "sensor" => Self::Sensor,
            "texture" => Self::Texture,
            "film" => Self::Film,
            "integrator" | "sampler" | "rfilter" | "medium" | "phase" | "volume" | "subsurface" => {
                Self::Other
            }
            _ => return None,
        })
    }
}

/// A property's value.
#[derive(Clone, Debug)]
pub enum Value {
    /// `<float>`.
    Float(f64),
    /// `<integer>`.
    Integer(i64),
    /// `<boolean>`.
    Boolean(bool),
    /// `<string>`.
    Str(String),
    /// `<rgb>`, `<srgb>` (decoded to linear), or a `<spectrum>` reduced to RGB.
    Rgb(Rgb),
    /// `<point>` or `<vector>`.
    Vector(Vec3),
    /// `<transform>`: the product of its operations.
    Transform(Mat4),
    /// A nested object, or a `<ref>` to one.
    Object(Arc<Object>),
}

/// One named property of an object.
#[derive(Clone, Debug)]
pub struct Property {
    /// The name, in Mitsuba 3's snake_case.
    pub name: String,
    /// The value.
    pub value: Value,
    /// Where it was written.
    pub loc: Loc,
}

/// An object element: a plugin instance with its properties and nested objects.
#[derive(Clone, Debug)]
pub struct Object {
    /// The tag.
    pub class: Class,
    /// The `type` attribute (the plugin name).
    pub kind: String,
    /// The `id` attribute.
    pub id: Option<String>,
    /// Named properties and nested objects, in file order (a nested object without a `name`
    /// gets an empty one).
    pub properties: Vec<Property>,
    /// Where the element starts.
    pub loc: Loc,
}

impl Object {
    /// The property called `name`.
    #[must_use]
    pub fn get(&self, name: &str) -> Option<&Property> {
        self.properties.iter().find(|p| p.name == name)
    }

    /// Nested objects (and references) of one class, in file order.
    pub fn children(&self, class: Class) -> impl Iterator<Item = &Arc<Object>> {
        self.properties.iter().filter_map(move |p| match &p.value {
            Value::Object(o) if o.class == class => Some(o),
            _ => None,
        })
    }

    /// A number property (`float` or `integer`), or `default` when absent.
    ///
    /// # Errors
    /// The property has another type.
    pub fn float(&self, name: &str, default: f64) -> Result<f64, SceneError> {
        match self.get(name) {
            None => Ok(default),
            Some(Property {
                value: Value::Float(x),
                ..
            }) => Ok(*x),
            #[allow(clippy::cast_precision_loss)]
            Some(Property {
                value: Value::Integer(i),
                ..
            }) => Ok(*i as f64),
            Some(p) => Err(p.expected("a number")),
        }
    }

    /// A boolean property, or `default`.
    ///
    /// # Errors
    /// The property has another type.
    pub fn boolean(&self, name: &str, default: bool) -> Result<bool, SceneError> {
        match self.get(name) {
            None => Ok(default),
            Some(Property {
                value: Value::Boolean(b),
                ..
            }) => Ok(*b),
            Some(p) => Err(p.expected("a boolean")),
        }
    }

    /// A string property, or `None`.
    ///
    /// # Errors
    /// The property has another type.
    pub fn string(&self, name: &str) -> Result<Option<&str>, SceneError> {
        match self.get(name) {
            None => Ok(None),
            Some(Property {
                value: Value::Str(s),
                ..
            }) => Ok(Some(s)),
            Some(p) => Err(p.expected("a string")),
        }
    }

    /// A point or vector property, or `default`.
    ///
    /// # Errors
    /// The property has another type.
    pub fn vector(&self, name: &str, default: Vec3) -> Result<Vec3, SceneError> {
        match self.get(name) {
            None => Ok(default),
            Some(Property {
                value: Value::Vector(v),
                ..
            }) => Ok(*v),
            Some(p) => Err(p.expected("a point or vector")),
        }
    }

    /// A transform property, or the identity.
    ///
    /// # Errors
    /// The property has another type.
    pub fn transform(&self, name: &str) -> Result<Mat4, SceneError> {
        match self.get(name) {
            None => Ok(Mat4::IDENTITY),
            Some(Property {
                value: Value::Transform(m),
                ..
            }) => Ok(*m),
            Some(p) => Err(p.expected("a transform")),
        }
    }

    /// A located error about this object.
    #[must_use]
    pub fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError::at(self.loc.clone(), message).with_key(self.key())
    }

    /// `shape type="obj" id="floor"` as a key for messages.
    #[must_use]
    pub fn key(&self) -> String {
        let tag = match self.class {
            Class::Shape => "shape",
            Class::Bsdf => "bsdf",
            Class::Emitter => "emitter",
            Class::Sensor => "sensor",
            Class::Texture => "texture",
            Class::Film => "film",
            Class::Other => "object",
        };
        match &self.id {
            Some(id) => format!("{tag} type=\"{}\" id=\"{id}\"", self.kind),
            None => format!("{tag} type=\"{}\"", self.kind),
        }
    }
}

impl Property {
    /// A located error about this property.
    #[must_use]
    pub fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError::at(self.loc.clone(), message).with_key(self.name.clone())
    }

    fn expected(&self, what: &str) -> SceneError {
        self.error(format!("expected {what}"))
    }
}

/// A whole file: its top-level objects in order.
#[derive(Clone, Debug, Default)]
pub struct Document {
    /// Top-level objects (with `<include>`d files' objects in place).
    pub objects: Vec<Arc<Object>>,
    /// The `version` attribute of `<scene>` (`0.6.0`, `3.0.0`, …).
    pub version: String,
}

/// Reads a Mitsuba XML file and the files it includes.
///
/// # Errors
/// A file cannot be read, is not well-formed XML, or has an element, attribute or value that
/// Mitsuba would not accept; located to `file:line:col`.
pub fn read(path: &Path) -> Result<Document, SceneError> {
    let mut reader = Reader::default();
    let version = reader.file(path, 0)?;
    Ok(Document {
        objects: reader.top,
        version,
    })
}

/// Parses XML text; `file` names it in messages and anchors `<include>` paths.
///
/// # Errors
/// As [`read`].
pub fn parse(text: &str, file: &Path) -> Result<Document, SceneError> {
    let mut reader = Reader::default();
    let version = reader.text(text, file, 0)?;
    Ok(Document {
        objects: reader.top,
        version,
    })
}

/// Included files nest at most this deep (a file including itself is an error, not a hang).
const MAX_INCLUDE_DEPTH: usize = 16;

#[derive(Default)]
struct Reader {
    top: Vec<Arc<Object>>,
    ids: HashMap<String, Arc<Object>>,
    params: HashMap<String, String>,
}

/// One file being read: its text (for positions) and name.
struct Source<'a> {
    doc: &'a roxmltree::Document<'a>,
    file: &'a Path,
}

impl Source<'_> {
    fn loc(&self, at: usize) -> Loc {
        let p = self.doc.text_pos_at(at);
        Loc {
            file: self.file.to_path_buf(),
            line: p.row as usize,
            col: p.col as usize,
        }
    }

    fn node_loc(&self, node: roxmltree::Node) -> Loc {
        self.loc(node.range().start)
    }

    fn error(&self, node: roxmltree::Node, message: impl Into<String>) -> SceneError {
        SceneError::at(self.node_loc(node), message)
            .with_key(format!("<{}>", node.tag_name().name()))
    }
}

impl Reader {
    fn file(&mut self, path: &Path, depth: usize) -> Result<String, SceneError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| SceneError::in_file(path, format!("cannot read: {e}")))?;
        self.text(&text, path, depth)
    }

    fn text(&mut self, text: &str, file: &Path, depth: usize) -> Result<String, SceneError> {
        let doc = roxmltree::Document::parse(text).map_err(|e| {
            let p = e.pos();
            SceneError::at(
                Loc {
                    file: file.to_path_buf(),
                    line: p.row as usize,
                    col: p.col as usize,
                },
                format!("not well-formed XML: {e}"),
            )
        })?;
        let src = Source { doc: &doc, file };
        let root = doc.root_element();
        if root.tag_name().name() != "scene" {
            return Err(src.error(root, "the root element must be <scene>"));
        }
        let version = root.attribute("version").unwrap_or("").to_string();
        for child in root.children().filter(roxmltree::Node::is_element) {
            match child.tag_name().name() {
                "default" => {
                    let name = self.attr(&src, child, "name")?;
                    let value = self.attr(&src, child, "value")?;
                    self.params.entry(name).or_insert(value);
                }
                "include" => {
                    if depth >= MAX_INCLUDE_DEPTH {
                        return Err(src.error(child, "includes nest too deep (a cycle?)"));
                    }
                    let name = self.attr(&src, child, "filename")?;
                    let path = file.parent().unwrap_or(Path::new("")).join(name);
                    if !path.is_file() {
                        return Err(src.error(
                            child,
                            format!("cannot read included file `{}`", path.display()),
                        ));
                    }
                    self.file(&path, depth + 1)?;
                }
                "alias" => {
                    let id = self.attr(&src, child, "id")?;
                    let alias = self.attr(&src, child, "as")?;
                    let object = self.ids.get(&id).cloned().ok_or_else(|| {
                        src.error(child, format!("no object with id `{id}` declared before"))
                    })?;
                    self.ids.insert(alias, object);
                }
                tag => {
                    if Class::of_tag(tag).is_some() {
                        let object = self.object(&src, child)?;
                        self.top.push(object);
                    } else if is_property_tag(tag) {
                        return Err(src.error(
                            child,
                            "a property outside any object (it belongs inside a <shape>, <bsdf>, …)",
                        ));
                    } else {
                        return Err(src.error(child, format!("unknown element <{tag}>")));
                    }
                }
            }
        }
        Ok(version)
    }

    /// An attribute, `$param`s replaced.
    fn attr(&self, src: &Source, node: roxmltree::Node, name: &str) -> Result<String, SceneError> {
        let raw = node
            .attribute(name)
            .ok_or_else(|| src.error(node, format!("missing attribute `{name}`")))?;
        self.substitute(src, node, raw)
    }

    fn opt_attr(
        &self,
        src: &Source,
        node: roxmltree::Node,
        name: &str,
    ) -> Result<Option<String>, SceneError> {
        node.attribute(name)
            .map(|raw| self.substitute(src, node, raw))
            .transpose()
    }

    /// `$name` → the `<default>` value of `name`.
    fn substitute(
        &self,
        src: &Source,
        node: roxmltree::Node,
        raw: &str,
    ) -> Result<String, SceneError> {
        if !raw.contains('$') {
            return Ok(raw.to_string());
        }
        let mut out = String::new();
        let mut rest = raw;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let tail = &rest[i + 1..];
            let end = tail
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(tail.len());
            let name = &tail[..end];
            let value = self.params.get(name).ok_or_else(|| {
                src.error(node, format!("`${name}` has no <default name=\"{name}\">"))
            })?;
            out.push_str(value);
            rest = &tail[end..];
        }
        out.push_str(rest);
        Ok(out)
    }

    /// An object element and everything inside it.
    fn object(&mut self, src: &Source, node: roxmltree::Node) -> Result<Arc<Object>, SceneError> {
        let tag = node.tag_name().name();
        let class = Class::of_tag(tag).ok_or_else(|| src.error(node, "not an object"))?;
        let kind = self.attr(src, node, "type")?;
        let id = self.opt_attr(src, node, "id")?;
        let mut properties = Vec::new();
        for child in node.children().filter(roxmltree::Node::is_element) {
            properties.push(self.property(src, child)?);
        }
        let object = Arc::new(Object {
            class,
            kind,
            id: id.clone(),
            properties,
            loc: src.node_loc(node),
        });
        if let Some(id) = id {
            self.ids.insert(id, Arc::clone(&object));
        }
        Ok(object)
    }

    /// A property, a nested object or a reference.
    fn property(&mut self, src: &Source, node: roxmltree::Node) -> Result<Property, SceneError> {
        let tag = node.tag_name().name();
        let loc = src.node_loc(node);
        let name = self
            .opt_attr(src, node, "name")?
            .map(|n| snake_case(&n))
            .unwrap_or_default();
        let value = match tag {
            "ref" => {
                let id = self.attr(src, node, "id")?;
                let object = self.ids.get(&id).cloned().ok_or_else(|| {
                    src.error(node, format!("no object with id `{id}` declared before"))
                })?;
                Value::Object(object)
            }
            "float" => Value::Float(self.number(src, node, "value")?),
            "integer" => {
                let v = self.attr(src, node, "value")?;
                Value::Integer(
                    v.trim()
                        .parse()
                        .map_err(|_| src.error(node, format!("`{v}` is not an integer")))?,
                )
            }
            "boolean" => {
                let v = self.attr(src, node, "value")?;
                Value::Boolean(match v.trim() {
                    "true" => true,
                    "false" => false,
                    _ => return Err(src.error(node, format!("`{v}` is not true or false"))),
                })
            }
            "string" => Value::Str(self.attr(src, node, "value")?),
            "rgb" => Value::Rgb(self.rgb(src, node)?),
            "srgb" => Value::Rgb(self.srgb(src, node)?),
            "spectrum" if node.attribute("type").is_none() => Value::Rgb(self.spectrum(src, node)?),
            "blackbody" => {
                return Err(src.error(
                    node,
                    "blackbody spectra are not read; give the colour as <rgb>",
                ))
            }
            "point" | "vector" => Value::Vector(self.triple(src, node, 0.0)?),
            "transform" => Value::Transform(self.transform(src, node)?),
            _ if Class::of_tag(tag).is_some() => Value::Object(self.object(src, node)?),
            _ => return Err(src.error(node, format!("unknown element <{tag}>"))),
        };
        if name.is_empty() && !matches!(value, Value::Object(_)) {
            return Err(src.error(node, "missing attribute `name`"));
        }
        Ok(Property { name, value, loc })
    }

    fn number(&self, src: &Source, node: roxmltree::Node, attr: &str) -> Result<f64, SceneError> {
        let v = self.attr(src, node, attr)?;
        parse_number(&v).ok_or_else(|| src.error(node, format!("`{attr}`: `{v}` is not a number")))
    }

    /// Numbers separated by commas and/or spaces.
    fn numbers(
        &self,
        src: &Source,
        node: roxmltree::Node,
        attr: &str,
    ) -> Result<Vec<f64>, SceneError> {
        let v = self.attr(src, node, attr)?;
        v.split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .map(|s| {
                parse_number(s)
                    .ok_or_else(|| src.error(node, format!("`{attr}`: `{s}` is not a number")))
            })
            .collect()
    }

    fn rgb(&self, src: &Source, node: roxmltree::Node) -> Result<Rgb, SceneError> {
        let v = self.numbers(src, node, "value")?;
        match v[..] {
            [x] => Ok(Rgb::splat(x)),
            [r, g, b] => Ok(Rgb::new(r, g, b)),
            _ => Err(src.error(
                node,
                format!("`value`: expected 1 or 3 numbers, found {}", v.len()),
            )),
        }
    }

    /// `<srgb value="#rrggbb"/>` or three numbers in [0, 1], decoded from sRGB to linear.
    fn srgb(&self, src: &Source, node: roxmltree::Node) -> Result<Rgb, SceneError> {
        let v = self.attr(src, node, "value")?;
        let encoded = if let Some(hex) = v.trim().strip_prefix('#') {
            let channel = |i: usize| {
                hex.get(i..i + 2)
                    .and_then(|h| u8::from_str_radix(h, 16).ok())
                    .map(|c| f64::from(c) / 255.0)
            };
            match (hex.len(), channel(0), channel(2), channel(4)) {
                (6, Some(r), Some(g), Some(b)) => Rgb::new(r, g, b),
                _ => return Err(src.error(node, format!("`value`: `{v}` is not #rrggbb"))),
            }
        } else {
            self.rgb(src, node)?
        };
        Ok(Rgb::new(
            srgb_to_linear(encoded.x),
            srgb_to_linear(encoded.y),
            srgb_to_linear(encoded.z),
        ))
    }

    /// A spectrum: one value (grey), or `wavelength:value` pairs, reduced to the grey of their
    /// mean over the visible range (a documented approximation: no colour is recovered).
    fn spectrum(&self, src: &Source, node: roxmltree::Node) -> Result<Rgb, SceneError> {
        let v = self.attr(src, node, "value")?;
        if !v.contains(':') {
            return self.rgb(src, node);
        }
        let mut values = Vec::new();
        for pair in v
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
        {
            let value = pair
                .split_once(':')
                .and_then(|(_, x)| parse_number(x))
                .ok_or_else(|| {
                    src.error(node, format!("`value`: `{pair}` is not wavelength:value"))
                })?;
            values.push(value);
        }
        #[allow(clippy::cast_precision_loss)]
        let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
        Ok(Rgb::splat(mean))
    }

    /// `x`, `y`, `z` attributes (missing ones `default`), or `value="x y z"`.
    fn triple(
        &self,
        src: &Source,
        node: roxmltree::Node,
        default: f64,
    ) -> Result<Vec3, SceneError> {
        if node.attribute("value").is_some() {
            let v = self.numbers(src, node, "value")?;
            return match v[..] {
                [x] => Ok(Vec3::splat(x as f32)),
                [x, y, z] => Ok(Vec3::new(x as f32, y as f32, z as f32)),
                _ => Err(src.error(
                    node,
                    format!("`value`: expected 3 numbers, found {}", v.len()),
                )),
            };
        }
        let mut out = [default as f32; 3];
        for (o, a) in out.iter_mut().zip(["x", "y", "z"]) {
            if node.attribute(a).is_some() {
                *o = self.number(src, node, a)? as f32;
            }
        }
        Ok(Vec3::from_array(out))
    }

    /// A point given as `origin="x, y, z"`.
    fn point_attr(
        &self,
        src: &Source,
        node: roxmltree::Node,
        attr: &str,
    ) -> Result<Vec3, SceneError> {
        let v = self.numbers(src, node, attr)?;
        match v[..] {
            [x, y, z] => Ok(Vec3::new(x as f32, y as f32, z as f32)),
            _ => Err(src.error(
                node,
                format!("`{attr}`: expected 3 numbers, found {}", v.len()),
            )),
        }
    }

    /// The product of a `<transform>`'s operations, each applied after the ones before it.
    fn transform(&self, src: &Source, node: roxmltree::Node) -> Result<Mat4, SceneError> {
        let mut m = Mat4::IDENTITY;
        for op in node.children().filter(roxmltree::Node::is_element) {
            let step = match op.tag_name().name() {
                "translate" => Mat4::from_translation(self.triple(src, op, 0.0)?),
                "scale" => Mat4::from_scale(self.triple(src, op, 1.0)?),
                "rotate" => {
                    let axis = self.triple(src, op, 0.0)?;
                    let angle = self.number(src, op, "angle")?;
                    let axis = axis.try_normalize().ok_or_else(|| {
                        src.error(op, "the rotation axis (x, y, z or value) is zero")
                    })?;
                    Mat4::from_axis_angle(axis, (angle as f32).to_radians())
                }
                "matrix" => {
                    let v = self.numbers(src, op, "value")?;
                    let f = |i: usize| v[i] as f32;
                    match v.len() {
                        // Row-major in the file; glam's constructors take columns.
                        16 => Mat4::from_cols(
                            Vec4::new(f(0), f(4), f(8), f(12)),
                            Vec4::new(f(1), f(5), f(9), f(13)),
                            Vec4::new(f(2), f(6), f(10), f(14)),
                            Vec4::new(f(3), f(7), f(11), f(15)),
                        ),
                        9 => Mat4::from_cols(
                            Vec4::new(f(0), f(3), f(6), 0.0),
                            Vec4::new(f(1), f(4), f(7), 0.0),
                            Vec4::new(f(2), f(5), f(8), 0.0),
                            Vec4::W,
                        ),
                        n => {
                            return Err(src.error(
                                op,
                                format!("`value`: a matrix has 16 (or 9) numbers, found {n}"),
                            ))
                        }
                    }
                }
                "lookat" | "lookAt" => {
                    let origin = self.point_attr(src, op, "origin")?;
                    let target = self.point_attr(src, op, "target")?;
                    let up = if op.attribute("up").is_some() {
                        self.point_attr(src, op, "up")?
                    } else {
                        Vec3::Y
                    };
                    look_at(origin, target, up).ok_or_else(|| {
                        src.error(op, "origin, target and up do not define a frame")
                    })?
                }
                tag => return Err(src.error(op, format!("unknown transform operation <{tag}>"))),
            };
            m = step * m;
        }
        if !m.is_finite() {
            return Err(src.error(node, "the transform is not finite"));
        }
        Ok(m)
    }
}

/// Mitsuba's `lookat`: the frame whose +z looks from `origin` at `target`, +y towards `up`, and
/// +x = up × direction (to the left in the image).
fn look_at(origin: Vec3, target: Vec3, up: Vec3) -> Option<Mat4> {
    let dir = (target - origin).try_normalize()?;
    let left = up.cross(dir).try_normalize()?;
    let new_up = dir.cross(left);
    Some(Mat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        origin.extend(1.0),
    ))
}

fn is_property_tag(tag: &str) -> bool {
    matches!(
        tag,
        "float"
            | "integer"
            | "boolean"
            | "string"
            | "rgb"
            | "srgb"
            | "spectrum"
            | "point"
            | "vector"
            | "transform"
            | "ref"
    )
}

fn parse_number(s: &str) -> Option<f64> {
    s.trim().parse::<f64>().ok().filter(|x| x.is_finite())
}

/// `toWorld` → `to_world`, `intIOR` → `int_ior`; snake_case names are kept.
#[must_use]
pub fn snake_case(name: &str) -> String {
    let mut out = String::with_capacity(name.len() + 4);
    let mut prev_lower = false;
    for c in name.chars() {
        if c.is_ascii_uppercase() {
            if prev_lower {
                out.push('_');
            }
            out.push(c.to_ascii_lowercase());
            prev_lower = false;
        } else {
            out.push(c);
            prev_lower = c.is_ascii_lowercase() || c.is_ascii_digit();
        }
    }
    out
}

/// A path in the file, resolved against the folder of the file it was written in.
#[must_use]
pub fn resolve(loc: &Loc, path: &str) -> PathBuf {
    loc.file.parent().unwrap_or(Path::new("")).join(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc(text: &str) -> Result<Document, SceneError> {
        parse(text, Path::new("t.xml"))
    }

    #[test]
    fn camel_case_names_read_as_snake_case() {
        assert_eq!(snake_case("toWorld"), "to_world");
        assert_eq!(snake_case("intIOR"), "int_ior");
        assert_eq!(snake_case("diffuseReflectance"), "diffuse_reflectance");
        assert_eq!(snake_case("sunRadiusScale"), "sun_radius_scale");
        assert_eq!(snake_case("to_world"), "to_world");
    }

    #[test]
    fn defaults_refs_and_typed_properties() {
        let d = doc(r#"<scene version="3.0.0">
            <default name="r" value="0.25"/>
            <bsdf type="diffuse" id="grey"><rgb name="reflectance" value="$r, $r, 0.5"/></bsdf>
            <shape type="sphere"><float name="radius" value="2"/><ref id="grey"/>
              <point name="center" x="1" z="3"/></shape>
        </scene>"#)
        .unwrap();
        assert_eq!(d.version, "3.0.0");
        let shape = &d.objects[1];
        assert_eq!(shape.float("radius", 1.0).unwrap(), 2.0);
        assert_eq!(
            shape.vector("center", Vec3::ZERO).unwrap(),
            Vec3::new(1.0, 0.0, 3.0)
        );
        let bsdf = shape.children(Class::Bsdf).next().unwrap();
        match &bsdf.get("reflectance").unwrap().value {
            Value::Rgb(c) => assert_eq!(*c, Rgb::new(0.25, 0.25, 0.5)),
            v => panic!("{v:?}"),
        }
    }

    #[test]
    fn transform_operations_apply_in_order() {
        let d = doc(
            r#"<scene version="3.0.0"><shape type="cube"><transform name="toWorld">
            <scale value="2"/><rotate y="1" angle="90"/><translate x="1" y="2" z="3"/>
            </transform></shape></scene>"#,
        )
        .unwrap();
        let m = d.objects[0].transform("to_world").unwrap();
        // (1, 0, 0) → scaled (2, 0, 0) → rotated about +y by 90° (0, 0, −2) → (1, 2, 1).
        let p = m.transform_point3(Vec3::X);
        assert!((p - Vec3::new(1.0, 2.0, 1.0)).length() < 1e-5, "{p}");
    }

    #[test]
    fn a_matrix_is_row_major_and_lookat_looks_along_z() {
        let d = doc(r#"<scene version="3.0.0"><sensor type="perspective">
            <transform name="to_world"><matrix value="1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1"/></transform>
            </sensor><sensor type="perspective"><transform name="to_world">
            <lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor></scene>"#)
        .unwrap();
        let m = d.objects[0].transform("to_world").unwrap();
        assert_eq!(m.transform_point3(Vec3::ZERO), Vec3::new(5.0, 6.0, 7.0));
        let l = d.objects[1].transform("to_world").unwrap();
        assert!((l.transform_vector3(Vec3::Z) + Vec3::Z).length() < 1e-6);
        assert!((l.transform_vector3(Vec3::Y) - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn problems_are_located() {
        let e = doc("<scene version=\"3.0.0\">\n  <shape type=\"cube\">\n    <flaot name=\"x\" value=\"1\"/>\n  </shape>\n</scene>").unwrap_err();
        assert_eq!(
            (e.line_col, e.message.as_str()),
            (Some((3, 5)), "unknown element <flaot>")
        );
        let e = doc(
            "<scene version=\"3.0.0\"><bsdf type=\"diffuse\"><ref id=\"nope\"/></bsdf></scene>",
        )
        .unwrap_err();
        assert!(e.to_string().starts_with("t.xml:1:"), "{e}");
        assert!(e.message.contains("nope"), "{e}");
        let e = doc("<scene><float name=\"x\" value=\"one\"/></scene>").unwrap_err();
        assert!(e.message.contains("outside any object"), "{e}");
        let e = doc("<scene version=\"3\"><shape type=\"cube\"><float name=\"x\" value=\"$y\"/></shape></scene>")
            .unwrap_err();
        assert!(e.message.contains("$y"), "{e}");
        let e = doc("<scene><shape type=\"cube\">").unwrap_err();
        assert!(e.message.starts_with("not well-formed XML"), "{e}");
    }

    #[test]
    fn srgb_hex_decodes_to_linear() {
        let d = doc(r##"<scene version="3.0.0"><bsdf type="diffuse"><srgb name="reflectance" value="#ffffff"/></bsdf></scene>"##)
            .unwrap();
        match &d.objects[0].get("reflectance").unwrap().value {
            Value::Rgb(c) => assert!((*c - Rgb::ONE).length() < 1e-12),
            v => panic!("{v:?}"),
        }
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-6);
    }
}
