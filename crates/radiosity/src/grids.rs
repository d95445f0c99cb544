//! Illuminance on the scene's calculation grids, and the statistics a lighting standard asks
//! of each (EN 12464-1 §4.3–4.4, CIE 171:2006):
//!
//! ```text
//! E_avg = (1/n) Σ E_k,   U₀ = E_min / E_avg,   U_d = E_min / E_max.
//! ```
//!
//! E_k is read at each grid point by [`meter::Meter::irradiance`] (direct light exactly, the rest
//! gathered from the solution). *Lux* is its luminance-weighted channel (Rec. 709 weights,
//! [`crate::color::luminance`]): a white emitter's radiance given in cd·m⁻² on all three
//! channels makes the irradiance's channels read in lx, so the scene's numbers are
//! photometric ones when its emitters are specified that way. Lengths do not enter: a form
//! factor has no unit, so the illuminance of an area source is the same whatever `units`
//! says.
//!
//! Under a CIE sky (`[sky]`, [`crate::scene::environment::cie_sky`]) each reading also gives
//! the *daylight factor* DF = 100 · E / E_h, E_h the illuminance the same sky gives a horizontal
//! plane open to all of it: the measure of daylighting codes, independent of the sky's
//! brightness. It counts every light of the scene in E, so it means what it says in a scene lit
//! by the sky alone.

use glam::Vec3;
use serde::Serialize;

use crate::color::luminance;
use crate::mesh::Mesh;
use crate::render::evaluated::meter;
use crate::scene::grid::Grid;
use crate::solve::Solution;
use crate::{Rgb, Scene};

/// The readings on one grid.
#[derive(Clone, Debug)]
pub struct Reading {
    /// The grid's name.
    pub name: String,
    /// The unit normal the points measure on.
    pub normal: Vec3,
    /// The points (scene coordinates), row by row along the grid's first axis.
    pub points: Vec<Vec3>,
    /// The cell of each point (i along the first axis, j along the second): every cell of a
    /// grid of `corners`, those on the faces of an `on` grid.
    pub cell: Vec<(u32, u32)>,
    /// Cells along the first and the second axis.
    pub cells: (u32, u32),
    /// The lengths of the two axes (scene units).
    pub size: (f64, f64),
    /// The irradiance at each point, per channel (W·m⁻², or lx for photometric emitters).
    pub irradiance: Vec<Rgb>,
    /// The illuminance at each point (the luminance-weighted channel).
    pub lux: Vec<f64>,
    /// Its statistics.
    pub statistics: Statistics,
    /// The statistics of the daylight factor, per cent (100 · E / E_h, E_h the unobstructed
    /// horizontal illuminance of the scene's CIE sky), when the scene has one.
    pub daylight_factor: Option<Statistics>,
}

/// The statistics of a grid's illuminance.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Statistics {
    /// Points.
    pub points: usize,
    /// E_avg, the mean.
    pub average: f64,
    /// E_min.
    pub minimum: f64,
    /// E_max.
    pub maximum: f64,
    /// U₀ = E_min / E_avg (0 when E_avg is 0).
    pub uniformity: f64,
    /// U_d = E_min / E_max (0 when E_max is 0).
    pub diversity: f64,
}

impl Statistics {
    /// The statistics of `values` (none: all zero).
    #[must_use]
    pub fn of(values: &[f64]) -> Self {
        if values.is_empty() {
            return Self {
                points: 0,
                average: 0.0,
                minimum: 0.0,
                maximum: 0.0,
                uniformity: 0.0,
                diversity: 0.0,
            };
        }
        let average = values.iter().sum::<f64>() / values.len() as f64;
        let minimum = values.iter().copied().fold(f64::INFINITY, f64::min);
        let maximum = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.0 };
        Self {
            points: values.len(),
            average,
            minimum,
            maximum,
            uniformity: ratio(minimum, average),
            diversity: ratio(minimum, maximum),
        }
    }
}

/// An illuminance with three significant digits (at least the units): `512`, `48.3`, `0.366`.
#[must_use]
pub fn rounded(lux: f64) -> String {
    let digits = if lux.abs() >= 100.0 || lux == 0.0 {
        0
    } else {
        (2 - lux.abs().log10().floor() as i32).clamp(0, 9) as usize
    };
    format!("{lux:.digits$}")
}

/// Reads every grid of `scene` from its solution, the meter's rays drawn from `seed`: the
/// same seed gives the same bits, another one other rays (readings that differ by the meter's
/// noise). Daylight factors only where the sky is the scene's only light.
#[must_use]
pub fn measure(scene: &Scene, mesh: &Mesh, solution: &Solution, seed: u64) -> Vec<Reading> {
    let sky = scene.sky_illuminance.filter(|_| daylight_only(scene));
    meter::with_meter(scene, mesh, solution, |meter| {
        scene
            .grids
            .iter()
            .enumerate()
            .map(|(k, grid)| {
                // The grid's index in the low half, the run's seed in the high half: the grids
                // of one run never share rays.
                let stream = seed.rotate_left(32) ^ k as u64;
                read(meter, grid, stream, sky)
            })
            .collect()
    })
}

/// Whether the scene's only light is its distant environment: no luminaire, and every
/// emitting polygon one of the environment's tiles.
fn daylight_only(scene: &Scene) -> bool {
    scene.luminaires.is_empty()
        && scene.polygons.iter().all(|p| {
            !scene.materials[p.material].is_emitter()
                || scene.objects[p.object].name == crate::scene::environment::NAME
        })
}

/// The reading of one grid; `seed` keeps its rays apart from the other grids'. `sky` is the
/// unobstructed horizontal illuminance of the scene's CIE sky, if it has one.
fn read(meter: &meter::Meter<'_>, grid: &Grid, seed: u64, sky: Option<f64>) -> Reading {
    let layout = grid.layout();
    let facing: Vec<(Vec3, Vec3)> = layout.iter().map(|p| (p.position, p.normal)).collect();
    let irradiance = meter.irradiance_facing(&facing, seed);
    let points = layout.iter().map(|p| p.position).collect();
    let cell = layout.iter().map(|p| p.cell).collect();
    let lux: Vec<f64> = irradiance.iter().map(|&e| luminance(e)).collect();
    let daylight_factor = sky.filter(|&e| e > 0.0).map(|sky| {
        let df: Vec<f64> = lux.iter().map(|&e| 100.0 * e / sky).collect();
        Statistics::of(&df)
    });
    Reading {
        daylight_factor,
        name: grid.name.clone(),
        normal: grid.normal,
        statistics: Statistics::of(&lux),
        points,
        cell,
        cells: grid.cells(),
        size: (
            f64::from(grid.first.length()),
            f64::from(grid.second.length()),
        ),
        irradiance,
        lux,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics_follow_their_definitions() {
        let s = Statistics::of(&[100.0, 200.0, 300.0, 400.0]);
        assert_eq!(s.points, 4);
        assert_eq!((s.average, s.minimum, s.maximum), (250.0, 100.0, 400.0));
        assert_eq!((s.uniformity, s.diversity), (0.4, 0.25));
        let dark = Statistics::of(&[0.0, 0.0]);
        assert_eq!((dark.uniformity, dark.diversity), (0.0, 0.0));
        assert_eq!(Statistics::of(&[]).points, 0);
    }

    #[test]
    fn illuminances_print_with_three_significant_digits() {
        let printed: Vec<String> = [512.4, 48.31, 0.36617, 0.0, 1.0].map(rounded).into();
        assert_eq!(printed, ["512", "48.3", "0.366", "0", "1.00"]);
    }
}
