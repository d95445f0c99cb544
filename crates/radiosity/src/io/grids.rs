//! Grid readings as files: per grid `DIR/<name>.csv` (columns `x,y,z,lux`, one point per row,
//! coordinates in the scene's units) and `DIR/<name>.svg` (its plan in false colour with
//! iso-lux lines, [`crate::plot::iso_lux`]), and `DIR/grids.json` with every grid's
//! statistics.
//! They are staged in a [`Batch`], to appear with the run's other outputs or not at all.

use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::Path;

use serde::Serialize;

use super::atomic::Batch;
use crate::grids::{Reading, Statistics};
use crate::plot::iso_lux::{plan_svg, Plan};

/// One grid in `grids.json`.
#[derive(Serialize)]
struct Entry<'a> {
    name: &'a str,
    /// The file of its points, relative to the JSON file.
    file: String,
    normal: [f32; 3],
    /// E_avg, E_min, E_max (lx), U₀, U_d and the point count.
    #[serde(flatten)]
    statistics: Statistics,
    /// The daylight factor's statistics (per cent), under a CIE sky.
    #[serde(skip_serializing_if = "Option::is_none")]
    daylight_factor: Option<Statistics>,
}

/// `grids.json`.
#[derive(Serialize)]
struct Summary<'a> {
    /// The unit of the illuminance values.
    unit: &'static str,
    /// The unit of the coordinates in the CSV files.
    length_unit: &'a str,
    grids: Vec<Entry<'a>>,
}

/// Stages `readings` into `batch` as files of `dir` (created if missing), to appear when it
/// commits; `length_unit` names the scene's unit of length.
///
/// # Errors
/// The directory cannot be created or a file written (the batch, dropped, then leaves none).
pub fn stage(
    batch: &mut Batch,
    dir: &Path,
    readings: &[Reading],
    length_unit: &str,
) -> io::Result<()> {
    std::fs::create_dir_all(dir)
        .map_err(|e| io::Error::new(e.kind(), format!("{}: {e}", dir.display())))?;
    let mut entries = Vec::with_capacity(readings.len());
    for r in readings {
        let file = format!("{}.csv", r.name);
        let tmp = batch.stage(&dir.join(&file))?;
        std::fs::write(&tmp, csv(r))?;
        // The plan's cells row by row; those without a point (beside an `on` grid's faces)
        // are holes.
        let (na, nb) = (r.cells.0 as usize, r.cells.1 as usize);
        let mut cells = vec![f64::NAN; na * nb];
        for (&(i, j), &lux) in r.cell.iter().zip(&r.lux) {
            cells[j as usize * na + i as usize] = lux;
        }
        let plan = Plan {
            name: &r.name,
            lux: &cells,
            cells: r.cells,
            size: r.size,
            unit: length_unit,
        };
        let tmp = batch.stage(&dir.join(format!("{}.svg", r.name)))?;
        std::fs::write(&tmp, plan_svg(&plan))?;
        entries.push(Entry {
            name: &r.name,
            file,
            normal: r.normal.to_array(),
            statistics: r.statistics,
            daylight_factor: r.daylight_factor,
        });
    }
    let summary = Summary {
        unit: "lx",
        length_unit,
        grids: entries,
    };
    let tmp = batch.stage(&dir.join("grids.json"))?;
    let mut out = std::fs::File::create(&tmp)?;
    serde_json::to_writer_pretty(&mut out, &summary).map_err(io::Error::other)?;
    writeln!(out)?;
    Ok(())
}

/// The CSV text of one grid.
fn csv(r: &Reading) -> String {
    let mut s = String::from("x,y,z,lux\n");
    for (p, lux) in r.points.iter().zip(&r.lux) {
        let _ = writeln!(s, "{},{},{},{lux:.6}", p.x, p.y, p.z);
    }
    s
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::Rgb;

    #[test]
    fn a_grid_is_written_as_csv_and_summarised_in_json() {
        let dir = std::env::temp_dir().join(format!("grids-io-{}", std::process::id()));
        let lux = vec![100.0, 300.0];
        let reading = Reading {
            name: "desk".into(),
            normal: Vec3::Y,
            points: vec![Vec3::new(0.25, 0.8, 0.5), Vec3::new(0.75, 0.8, 0.5)],
            cell: vec![(0, 0), (1, 0)],
            irradiance: vec![Rgb::splat(100.0), Rgb::splat(300.0)],
            statistics: Statistics::of(&lux),
            lux,
            cells: (2, 1),
            size: (1.0, 0.5),
            daylight_factor: None,
        };
        let mut batch = Batch::new();
        stage(&mut batch, &dir, &[reading], "metres").unwrap();
        assert!(
            !dir.join("desk.csv").exists(),
            "nothing appears before the commit"
        );
        assert_eq!(batch.commit().unwrap().len(), 3);
        assert!(std::fs::read_to_string(dir.join("desk.svg"))
            .unwrap()
            .starts_with("<svg"));
        let csv = std::fs::read_to_string(dir.join("desk.csv")).unwrap();
        assert_eq!(
            csv,
            "x,y,z,lux\n0.25,0.8,0.5,100.000000\n0.75,0.8,0.5,300.000000\n"
        );
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("grids.json")).unwrap())
                .unwrap();
        let g = &json["grids"][0];
        assert_eq!(g["name"], "desk");
        assert_eq!(g["file"], "desk.csv");
        assert_eq!(g["average"], 200.0);
        assert_eq!(g["uniformity"], 0.5);
        assert_eq!(json["unit"], "lx");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
