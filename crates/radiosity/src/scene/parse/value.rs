//! The reader's tree: TOML values and keys with their byte spans.
//!
//! The `toml` crate hands spans over through serde_spanned's protocol (see the comment on
//! `SPANNED`); the visitors here read that protocol into [`Value`] and [`Key`], so that every
//! message can name the line and column of what it is about.

use std::fmt;
use std::ops::Range;

use serde::de::{self, Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};

/// The byte span and kind of a TOML value (the reader's tree).
pub(super) struct Value {
    pub(super) span: Range<usize>,
    pub(super) kind: Kind,
}

/// A TOML key with its byte span.
pub(super) struct Key {
    pub(super) span: Range<usize>,
    pub(super) name: String,
}

/// What a TOML value is.
pub(super) enum Kind {
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
    Datetime,
    Array(Vec<Value>),
    Table(Vec<(Key, Value)>),
}

impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Bool(_) => "a boolean",
            Self::Int(_) => "an integer",
            Self::Float(_) => "a float",
            Self::Str(_) => "a string",
            Self::Datetime => "a date-time",
            Self::Array(_) => "an array",
            Self::Table(_) => "a table",
        })
    }
}

// The `toml` crate reports spans through serde_spanned's protocol: a value asked for as a struct
// of this name and these fields is handed over as a map {start, end, value}. `toml::Spanned`
// cannot be used directly because implicit tables (`materials` in `[materials.white]`) have no
// span and make it fail; here a value without a span is read as is and takes its key's span.
const SPANNED: &str = "$__serde_spanned_private_Spanned";
const SPANNED_START: &str = "$__serde_spanned_private_start";
const SPANNED_FIELDS: &[&str] = &[
    SPANNED_START,
    "$__serde_spanned_private_end",
    "$__serde_spanned_private_value",
];
const DATETIME_FIELD: &str = "$__toml_private_datetime";

impl<'de> Deserialize<'de> for Value {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_struct(SPANNED, SPANNED_FIELDS, ValueVisitor)
    }
}

/// The value inside a spanned map, read without asking for a span again.
struct Unspanned(Value);

impl<'de> Deserialize<'de> for Unspanned {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ValueVisitor).map(Unspanned)
    }
}

impl<'de> Deserialize<'de> for Key {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_struct(SPANNED, SPANNED_FIELDS, KeyVisitor)
    }
}

struct KeyVisitor;

impl<'de> Visitor<'de> for KeyVisitor {
    type Value = Key;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a key")
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Key, E> {
        Ok(Key {
            span: 0..0,
            name: v.to_string(),
        })
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Key, A::Error> {
        let (Some(_), start) = (map.next_key::<String>()?, map.next_value::<usize>()?) else {
            return Err(de::Error::custom("malformed key span"));
        };
        let (Some(_), end) = (map.next_key::<String>()?, map.next_value::<usize>()?) else {
            return Err(de::Error::custom("malformed key span"));
        };
        let (Some(_), name) = (map.next_key::<String>()?, map.next_value::<String>()?) else {
            return Err(de::Error::custom("malformed key span"));
        };
        Ok(Key {
            span: start..end,
            name,
        })
    }
}

struct ValueVisitor;

impl ValueVisitor {
    fn value(kind: Kind) -> Value {
        Value { span: 0..0, kind }
    }
}

impl<'de> Visitor<'de> for ValueVisitor {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a TOML value")
    }

    fn visit_bool<E: de::Error>(self, v: bool) -> Result<Value, E> {
        Ok(Self::value(Kind::Bool(v)))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Value, E> {
        Ok(Self::value(Kind::Int(v)))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Value, E> {
        Ok(Self::value(match i64::try_from(v) {
            Ok(i) => Kind::Int(i),
            Err(_) => Kind::Float(v as f64),
        }))
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Value, E> {
        Ok(Self::value(Kind::Float(v)))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Value, E> {
        Ok(Self::value(Kind::Str(v.to_string())))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut items = Vec::new();
        while let Some(item) = seq.next_element()? {
            items.push(item);
        }
        Ok(Self::value(Kind::Array(items)))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut entries = Vec::new();
        while let Some(key) = map.next_key::<Key>()? {
            if key.span.is_empty() && key.name == SPANNED_START {
                // The spanned protocol: start, end, then the value itself.
                let start: usize = map.next_value()?;
                let _ = map.next_key::<Key>()?;
                let end: usize = map.next_value()?;
                let _ = map.next_key::<Key>()?;
                let Unspanned(mut value) = map.next_value()?;
                value.span = start..end;
                return Ok(value);
            }
            if key.name == DATETIME_FIELD {
                map.next_value::<de::IgnoredAny>()?;
                return Ok(Self::value(Kind::Datetime));
            }
            let mut value: Value = map.next_value()?;
            if value.span.is_empty() {
                value.span = key.span.clone();
            }
            entries.push((key, value));
        }
        Ok(Self::value(Kind::Table(entries)))
    }
}
