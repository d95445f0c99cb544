//! The length unit of a scene (`units = "mm"` at the top of a scene file).
//!
//! Geometry is solved in the scene's own units: radiosity is power per area and does not
//! depend on them, and the stats give areas in scene units². The unit matters where a file
//! leaves the program for tools that assume one: glTF lengths are metres (glTF 2.0
//! specification, §3.4 "Coordinate System and Units"), so a `.glb` export scales positions and
//! cameras by [`Units::metres`]. The built-in Cornell box is in millimetres, as published.

use std::fmt;
use std::str::FromStr;

/// A length unit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Units {
    /// Metres (the default).
    #[default]
    Metres,
    /// Kilometres.
    Kilometres,
    /// Centimetres.
    Centimetres,
    /// Millimetres.
    Millimetres,
    /// International inches (25.4 mm).
    Inches,
    /// International feet (0.3048 m).
    Feet,
}

impl Units {
    /// Every unit, with its short name and its length in metres.
    const ALL: [(Units, &'static str, f64); 6] = [
        (Units::Metres, "m", 1.0),
        (Units::Kilometres, "km", 1000.0),
        (Units::Centimetres, "cm", 0.01),
        (Units::Millimetres, "mm", 0.001),
        (Units::Inches, "in", 0.0254),
        (Units::Feet, "ft", 0.3048),
    ];

    /// Metres per unit.
    #[must_use]
    pub fn metres(self) -> f64 {
        Self::ALL
            .iter()
            .find(|(u, _, _)| *u == self)
            .map_or(1.0, |(_, _, m)| *m)
    }

    /// The short name (`m`, `km`, `cm`, `mm`, `in`, `ft`).
    #[must_use]
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(u, _, _)| *u == self)
            .map_or("m", |(_, n, _)| n)
    }
}

impl fmt::Display for Units {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A unit that is not one of [`Units`]; the message lists them.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown length unit \"{0}\" (one of m, km, cm, mm, in, ft)")]
pub struct UnknownUnit(pub String);

impl FromStr for Units {
    type Err = UnknownUnit;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .iter()
            .find(|(_, n, _)| *n == s)
            .map(|(u, _, _)| *u)
            .ok_or_else(|| UnknownUnit(s.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_lengths_are_the_international_ones() {
        for (u, name, metres) in Units::ALL {
            assert_eq!(name.parse::<Units>(), Ok(u));
            assert_eq!(u.metres(), metres);
            assert_eq!(u.to_string(), name);
        }
        assert!((Units::Feet.metres() / Units::Inches.metres() - 12.0).abs() < 1e-12);
        assert!("furlong".parse::<Units>().is_err());
        assert_eq!(Units::default(), Units::Metres);
    }
}
