//! Spatial enumeration: a solid as the occupied cells (voxels) of a regular grid. A cell is
//! occupied when its centre is inside the solid, so the occupied volume converges to the
//! solid's volume as the cells shrink (error of the order of area × cell size).

use glam::DVec3;

use crate::implicit::Sdf;

/// A regular grid of occupied / empty cubic cells.
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelGrid {
    min: DVec3,
    cell: f64,
    dims: [usize; 3],
    occupied: Vec<bool>,
}

impl VoxelGrid {
    /// The voxels of `sdf` over `min..max`, `resolution` cells along the longest side; `None`
    /// for an empty or non-finite box or a zero resolution.
    #[must_use]
    pub fn from_sdf(sdf: &Sdf, min: DVec3, max: DVec3, resolution: u32) -> Option<Self> {
        let extent = max - min;
        if !(extent.min_element() > 0.0 && extent.is_finite() && resolution > 0) {
            return None;
        }
        let cell = extent.max_element() / f64::from(resolution);
        let d = (extent / cell).ceil().as_uvec3().max(glam::UVec3::ONE);
        let dims = [d.x as usize, d.y as usize, d.z as usize];
        let mut occupied = Vec::with_capacity(dims.iter().product());
        for z in 0..dims[2] {
            for y in 0..dims[1] {
                for x in 0..dims[0] {
                    let c = min + (DVec3::new(x as f64, y as f64, z as f64) + 0.5) * cell;
                    occupied.push(sdf.eval(c) < 0.0);
                }
            }
        }
        Some(Self {
            min,
            cell,
            dims,
            occupied,
        })
    }

    /// Cells along x, y, z.
    #[must_use]
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// Whether cell (x, y, z) is occupied (`false` outside the grid).
    #[must_use]
    pub fn get(&self, x: usize, y: usize, z: usize) -> bool {
        x < self.dims[0]
            && y < self.dims[1]
            && z < self.dims[2]
            && self.occupied[x + self.dims[0] * (y + self.dims[1] * z)]
    }

    /// Number of occupied cells.
    #[must_use]
    pub fn count(&self) -> usize {
        self.occupied.iter().filter(|&&o| o).count()
    }

    /// Occupied volume.
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.count() as f64 * self.cell.powi(3)
    }

    /// Checks the invariants: a positive finite cell size, a finite origin, and one flag per
    /// cell.
    ///
    /// # Errors
    /// The violation, as a message.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.cell > 0.0 && self.cell.is_finite() && self.min.is_finite()) {
            return Err("bad cell size or origin".into());
        }
        if self.occupied.len() != self.dims.iter().product::<usize>() {
            return Err("cell count does not match the dimensions".into());
        }
        Ok(())
    }
}
