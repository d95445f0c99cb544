//! The false-colour scale of lighting plots and pictures — one colour map for the grids' plans
//! ([`crate::plot::iso_lux`]) and the false-colour renders ([`crate::render::false_colour`]),
//! kept with the colours, below both.
//!
//! A value v between the ends lo < hi of a scale is placed at
//!
//! ```text
//! t = (v − lo) / (hi − lo)                       (linear),
//! t = (log v − log lo) / (log hi − log lo)       (logarithmic, lo > 0),
//! ```
//!
//! clamped to [0, 1], and t is coloured by piecewise-linear interpolation between five stops,
//! blue, cyan, green, yellow and red, in the display's (sRGB-encoded) values. A logarithmic
//! scale shows equal *ratios* as equal steps, as the eye sees brightness and as lighting
//! standards space their illuminance levels (EN 12464-1 §4.3: 20, 30, 50, 75, 100, 150, 200,
//! 300, 500, 750, 1000, … lx, a factor of about 1.5 between steps); a linear one shows the
//! differences within a narrow range, as on a work plane.
//!
//! Levels labelled on a legend are *nice* numbers: on a linear scale, multiples of a step of
//! 1, 2 or 5 × 10^k that cut the range into five to ten steps ([`levels`]); on a logarithmic
//! one, the numbers 1, 2 and 5 × 10^k within the range, or only 1 × 10^k over more than four
//! decades, or the finer 1, 1.5, 2, 3, 5 and 7.5 × 10^k within one decade ([`log_levels`]).

use crate::registry::registry;

/// The colour map's stops, from t = 0 to t = 1, in sRGB-encoded display values.
const STOPS: [[f64; 3]; 5] = [
    [0.19, 0.27, 0.85],
    [0.10, 0.75, 0.85],
    [0.30, 0.80, 0.25],
    [0.98, 0.85, 0.15],
    [0.85, 0.15, 0.10],
];

registry! {
    /// How values are spaced along a colour scale.
    pub enum Spacing {
        /// Equal ratios as equal steps (the ends and the levels 1, 2, 5 × 10^k).
        Log = "log",
        /// Equal differences as equal steps, from 0 unless a range is given.
        Linear = "linear",
    }
    /// An unknown scale name.
    pub struct UnknownSpacing = "unknown scale";
}

/// A colour scale: its ends and its spacing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scale {
    /// The value coloured at t = 0 (values below take its colour).
    pub lo: f64,
    /// The value coloured at t = 1 (values above take its colour).
    pub hi: f64,
    /// Linear or logarithmic.
    pub spacing: Spacing,
}

/// Why two ends make no scale.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum ScaleError {
    /// An end is not a finite number, or the ends are not in increasing order.
    #[error("the range {lo}:{hi} is not two finite numbers, the first below the second")]
    Order {
        /// The lower end.
        lo: f64,
        /// The upper end.
        hi: f64,
    },
    /// A logarithmic scale's lower end is not above zero.
    #[error("a logarithmic scale needs a lower end above 0, not {lo}")]
    LogOfZero {
        /// The lower end.
        lo: f64,
    },
}

impl Scale {
    /// The scale from `lo` to `hi`.
    ///
    /// # Errors
    /// When the ends are not finite and increasing, or a logarithmic scale starts at or
    /// below zero.
    pub fn new(lo: f64, hi: f64, spacing: Spacing) -> Result<Self, ScaleError> {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(ScaleError::Order { lo, hi });
        }
        if spacing == Spacing::Log && lo <= 0.0 {
            return Err(ScaleError::LogOfZero { lo });
        }
        Ok(Self { lo, hi, spacing })
    }

    /// The scale a picture's `values` call for when no range is given: on a linear scale from
    /// 0 to the nice level at or above the largest value; on a logarithmic one from the nice
    /// number 1, 2 or 5 × 10^k at or below the smallest value above zero to the one at or
    /// above the largest, at most [`LOG_DECADES`] decades (values further down take the
    /// bottom colour). Without any value above zero, 0 to 1 (linear) or 0.1 to 1 (log).
    #[must_use]
    pub fn fitted(values: impl IntoIterator<Item = f64>, spacing: Spacing) -> Self {
        let (mut least, mut most) = (f64::INFINITY, 0.0f64);
        for v in values.into_iter().filter(|v| v.is_finite() && *v > 0.0) {
            least = least.min(v);
            most = most.max(v);
        }
        if most <= 0.0 {
            let lo = match spacing {
                Spacing::Linear => 0.0,
                Spacing::Log => 0.1,
            };
            return Self {
                lo,
                hi: 1.0,
                spacing,
            };
        }
        match spacing {
            Spacing::Linear => {
                let (m, e) = step(most).unwrap_or((1, 0));
                let steps = (most / power(m as f64, e) * (1.0 - 1e-12)).ceil().max(1.0);
                Self {
                    lo: 0.0,
                    hi: power(steps * m as f64, e),
                    spacing,
                }
            }
            Spacing::Log => {
                let hi = nice(most, true);
                let mut lo = nice(least, false).max(hi / 10f64.powi(LOG_DECADES));
                if lo >= hi {
                    lo = nice(hi * 0.99, false);
                }
                Self { lo, hi, spacing }
            }
        }
    }

    /// Where `value` lies on the scale, t ∈ [0, 1] (NaN: 0).
    #[must_use]
    pub fn position(&self, value: f64) -> f64 {
        let t = match self.spacing {
            Spacing::Linear => (value - self.lo) / (self.hi - self.lo),
            Spacing::Log => {
                if value <= 0.0 {
                    0.0
                } else {
                    (value / self.lo).ln() / (self.hi / self.lo).ln()
                }
            }
        };
        if t.is_nan() {
            0.0
        } else {
            t.clamp(0.0, 1.0)
        }
    }

    /// The value at position `t` ∈ [0, 1]: the inverse of [`Scale::position`] inside the
    /// range.
    #[must_use]
    pub fn value_at(&self, t: f64) -> f64 {
        match self.spacing {
            Spacing::Linear => self.lo + t * (self.hi - self.lo),
            Spacing::Log => self.lo * (self.hi / self.lo).powf(t),
        }
    }

    /// The colour of `value`, 8-bit sRGB.
    #[must_use]
    pub fn colour(&self, value: f64) -> [u8; 3] {
        colour(self.position(value))
    }

    /// The levels a legend labels: both ends and the nice levels between them (module docs).
    #[must_use]
    pub fn levels(&self) -> Vec<f64> {
        let inner = match self.spacing {
            Spacing::Linear => levels(self.lo, self.hi),
            Spacing::Log => log_levels(self.lo, self.hi),
        };
        let mut all = vec![self.lo];
        all.extend(inner);
        all.push(self.hi);
        all
    }
}

/// Most decades a fitted logarithmic scale spans.
pub const LOG_DECADES: i32 = 3;

/// The nice number 1, 2 or 5 × 10^k nearest `value` (> 0) from above (`up`) or from below.
fn nice(value: f64, up: bool) -> f64 {
    let e = value.log10().floor() as i32;
    let candidates = (e - 1..=e + 1).flat_map(|k| [1.0, 2.0, 5.0].map(|m| power(m, k)));
    if up {
        candidates
            .filter(|&c| c >= value * (1.0 - 1e-12))
            .fold(f64::INFINITY, f64::min)
    } else {
        candidates
            .filter(|&c| c <= value * (1.0 + 1e-12))
            .fold(0.0, f64::max)
    }
}

/// m × 10^k, computed so that 0.2 is the double nearest 0.2 (an exact power of ten divides).
fn power(m: f64, k: i32) -> f64 {
    if k < 0 {
        m / 10f64.powi(-k)
    } else {
        m * 10f64.powi(k)
    }
}

/// The colour map at `t` ∈ [0, 1], 8-bit sRGB.
#[must_use]
pub fn colour(t: f64) -> [u8; 3] {
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let k = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - k as f64;
    [0, 1, 2].map(|i| ((STOPS[k][i] * (1.0 - f) + STOPS[k + 1][i] * f) * 255.0).round() as u8)
}

/// The colour map at `t` as `#rrggbb`.
#[must_use]
pub fn hex(t: f64) -> String {
    let [r, g, b] = colour(t);
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// The step m · 10^e (m = 1, 2, 5 or 10) that cuts `range` into five to ten steps, as (m, e);
/// `None` for a range that is not finite and positive.
fn step(range: f64) -> Option<(i64, i32)> {
    if !(range > 0.0 && range.is_finite()) {
        return None;
    }
    let e = (range / 10.0).log10().floor() as i32;
    let base = 10f64.powi(e);
    let m = [1i64, 2, 5, 10]
        .into_iter()
        .find(|&m| range / (m as f64 * base) <= 10.0)
        .unwrap_or(10);
    Some((m, e))
}

/// The levels strictly inside (lo, hi) of a linear scale: multiples of a step of 1, 2 or
/// 5 × 10^k that makes five to ten steps of the range.
#[must_use]
pub fn levels(lo: f64, hi: f64) -> Vec<f64> {
    let Some((m, e)) = step(hi - lo) else {
        return Vec::new();
    };
    // A level k · step is computed as the integer k·m scaled by an exact power of ten, so
    // that 0.35 comes out as the double nearest 0.35, not 7 × 0.05.
    let value = |k: i64| power((k * m) as f64, e);
    let first = (lo / (m as f64 * 10f64.powi(e))).floor() as i64 + 1;
    (first..)
        .map(value)
        .take_while(|&v| v < hi)
        .filter(|&v| v > lo)
        .collect()
}

/// The levels strictly inside (lo, hi) of a logarithmic scale (0 < lo < hi): the mantissas
/// 1, 2, 5 × 10^k; over more than four decades 1 × 10^k alone; where that leaves fewer than
/// two, 1, 1.5, 2, 3, 5, 7.5 × 10^k.
#[must_use]
pub fn log_levels(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Vec::new();
    }
    let within = |mantissas: &[f64]| -> Vec<f64> {
        let (first, last) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
        (first..=last)
            .flat_map(|k| mantissas.iter().map(move |&m| power(m, k)))
            .filter(|&v| v > lo * (1.0 + 1e-9) && v < hi * (1.0 - 1e-9))
            .collect()
    };
    if (hi / lo).log10() > 4.0 {
        return within(&[1.0]);
    }
    let levels = within(&[1.0, 2.0, 5.0]);
    if levels.len() >= 2 {
        levels
    } else {
        within(&[1.0, 1.5, 2.0, 3.0, 5.0, 7.5])
    }
}

/// A level's label: the fewest decimals (at most six) that write it exactly to 10⁻⁹ of its
/// value — `250`, `0.35`, `0.002`.
#[must_use]
pub fn label(level: f64) -> String {
    (0..=6)
        .map(|d| format!("{level:.d$}"))
        .find(|text| {
            text.parse::<f64>()
                .is_ok_and(|v| (v - level).abs() <= 1e-9 * level.abs().max(1e-300))
        })
        .unwrap_or_else(|| format!("{level:.6}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_levels_are_nice_steps_inside_the_range() {
        assert_eq!(
            levels(0.0, 100.0),
            vec![10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0]
        );
        assert_eq!(
            levels(212.0, 488.0),
            vec![250.0, 300.0, 350.0, 400.0, 450.0]
        );
        assert_eq!(
            levels(0.31, 0.74),
            vec![0.35, 0.4, 0.45, 0.5, 0.55, 0.6, 0.65, 0.7]
        );
        assert!(levels(5.0, 5.0).is_empty());
        assert!(levels(f64::NAN, 1.0).is_empty());
    }

    #[test]
    fn log_levels_are_one_two_five_per_decade() {
        assert_eq!(
            log_levels(10.0, 1000.0),
            vec![20.0, 50.0, 100.0, 200.0, 500.0]
        );
        assert_eq!(log_levels(0.01, 1000.0), vec![0.1, 1.0, 10.0, 100.0]);
        assert_eq!(log_levels(100.0, 300.0), vec![150.0, 200.0]);
        assert!(log_levels(0.0, 1.0).is_empty());
    }

    #[test]
    fn positions_invert_and_clamp() {
        let log = Scale::new(10.0, 1000.0, Spacing::Log).unwrap();
        assert!((log.position(100.0) - 0.5).abs() < 1e-12);
        assert_eq!(log.position(1.0), 0.0);
        assert_eq!(log.position(0.0), 0.0);
        assert_eq!(log.position(1e6), 1.0);
        let linear = Scale::new(0.0, 500.0, Spacing::Linear).unwrap();
        assert!((linear.position(125.0) - 0.25).abs() < 1e-12);
        for scale in [log, linear] {
            for t in [0.0, 0.13, 0.5, 0.99, 1.0] {
                let back = scale.position(scale.value_at(t));
                assert!((back - t).abs() < 1e-12, "{scale:?} {t}");
            }
        }
        assert_eq!(linear.levels().first(), Some(&0.0));
        assert_eq!(linear.levels().last(), Some(&500.0));
    }

    #[test]
    fn bad_ends_are_refused() {
        assert!(Scale::new(5.0, 5.0, Spacing::Linear).is_err());
        assert!(Scale::new(1.0, f64::INFINITY, Spacing::Linear).is_err());
        assert_eq!(
            Scale::new(0.0, 5.0, Spacing::Log),
            Err(ScaleError::LogOfZero { lo: 0.0 })
        );
        assert!(Scale::new(-1.0, 5.0, Spacing::Linear).is_ok());
    }

    /// A fitted scale starts and ends on nice numbers that hold the values; a logarithmic one
    /// spans at most three decades.
    #[test]
    fn fitted_scales_hold_the_values_between_nice_ends() {
        let values = [0.0, 37.0, 212.0, 734.0];
        let linear = Scale::fitted(values, Spacing::Linear);
        assert_eq!((linear.lo, linear.hi), (0.0, 800.0));
        let log = Scale::fitted(values, Spacing::Log);
        assert_eq!((log.lo, log.hi), (20.0, 1000.0));
        let wide = Scale::fitted([1e-4, 3000.0], Spacing::Log);
        assert_eq!((wide.lo, wide.hi), (5.0, 5000.0));
        let one = Scale::fitted([200.0], Spacing::Log);
        assert!(one.lo < 200.0 && one.hi >= 200.0, "{one:?}");
        let dark = Scale::fitted([0.0], Spacing::Log);
        assert!(dark.lo > 0.0 && dark.hi > dark.lo);
    }

    #[test]
    fn the_colour_map_runs_from_blue_to_red() {
        assert_eq!(hex(0.0), "#3045d9");
        assert_eq!(colour(1.0), [217, 38, 26]);
        assert_eq!(colour(-3.0), colour(0.0));
        assert_eq!(label(250.0), "250");
        assert_eq!(label(0.35), "0.35");
        assert_eq!(label(0.002), "0.002");
        assert_eq!(label(1.5), "1.5");
    }
}
