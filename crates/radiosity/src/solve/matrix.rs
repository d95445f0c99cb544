//! The stored form-factor matrix of the gathering solvers: one row of F_{e→s} per element (the
//! receivers), one column per source, `f32`, row-major.
//!
//! Its size, elements × sources × 4 bytes, is checked against the limit *before* anything is
//! allocated, and the allocation itself is fallible, so a scene too large for memory is a
//! [`SolveError::MatrixTooLarge`], never an abort. Rows are filled in parallel in chunks; each
//! row depends on its element only, so the matrix is the same at any thread count.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use rayon::prelude::*;

use super::SolveError;
use crate::formfactor::{FormFactors, Geometry};
use crate::progress::Progress;

/// Rows per parallel task (and per progress report, and per unit of a partial matrix).
pub(super) const CHUNK_ROWS: usize = 16;

/// Form factors from every element (row) to every source (column), possibly partial: a stop
/// leaves whole chunks of [`CHUNK_ROWS`] rows done and the others zero, and a checkpoint keeps
/// the done ones (see [`super::checkpoint`]). The data is shared, so a checkpoint holds the
/// matrix without copying it.
#[derive(Clone, Debug, PartialEq)]
pub struct Matrix {
    sources: usize,
    data: Arc<Vec<f32>>,
    /// Whether each chunk of rows is computed.
    done: Vec<bool>,
}

/// Scales a row whose sum exceeds 1 down to 1: an element cannot see more than its hemisphere.
/// The quadrature of each factor is accurate to ~10⁻³, but next to contact lines, where a
/// receiver's few points see a touching surface's steep kernel, rows came to sum a little above
/// one and a closed furnished room absorbed 1.004 times the power it emits.
fn cap_at_hemisphere(row: &mut [f32]) {
    let sum: f64 = row.iter().map(|&f| f64::from(f)).sum();
    if sum > 1.0 {
        let scale = (1.0 / sum) as f32;
        row.iter_mut().for_each(|f| *f *= scale);
    }
}

impl Matrix {
    /// Bytes that a matrix of `elements × sources` takes (saturating).
    #[must_use]
    pub fn bytes(elements: usize, sources: usize) -> u64 {
        (elements as u64)
            .saturating_mul(sources as u64)
            .saturating_mul(std::mem::size_of::<f32>() as u64)
    }

    /// Computes every row of `g` with `ff`, reporting rows done to `progress` under the stage
    /// "form factors".
    ///
    /// # Errors
    /// [`SolveError::MatrixTooLarge`] when the matrix would take more than `limit` bytes or
    /// cannot be allocated.
    pub fn compute(
        g: &Geometry,
        ff: &dyn FormFactors,
        limit: u64,
        progress: &dyn Progress,
    ) -> Result<Self, SolveError> {
        Self::resume(g, ff, limit, None, None, progress)
    }

    /// [`Matrix::compute`], taking the chunks already done in `prior` (a matrix of the same
    /// shape from a checkpoint) and skipping the chunks not yet begun once `stop` is set: the
    /// result is then partial ([`Matrix::complete`] is false). Every row depends on its element
    /// only, so the rows taken from `prior` are those this run would compute.
    pub(super) fn resume(
        g: &Geometry,
        ff: &dyn FormFactors,
        limit: u64,
        stop: Option<&AtomicBool>,
        prior: Option<&Matrix>,
        progress: &dyn Progress,
    ) -> Result<Self, SolveError> {
        let (rows, sources) = (g.mesh.element_count(), g.sources.len());
        let mut data = Self::zeros(rows, sources, limit)?;
        let prior = prior.filter(|p| p.shape() == (rows, sources));
        progress.start("form factors", rows as u64);
        let done = if sources > 0 {
            data.par_chunks_mut(CHUNK_ROWS * sources)
                .enumerate()
                .map(|(chunk, block)| {
                    let first = chunk * CHUNK_ROWS;
                    if let Some(prior) = prior.filter(|p| p.done[chunk]) {
                        block.copy_from_slice(&prior.data[first * sources..][..block.len()]);
                    } else {
                        if stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
                            return false;
                        }
                        for (k, row) in block.chunks_mut(sources).enumerate() {
                            ff.row(g, first + k, row);
                            cap_at_hemisphere(row);
                        }
                    }
                    progress.advance((block.len() / sources) as u64);
                    true
                })
                .collect()
        } else {
            vec![true; rows.div_ceil(CHUNK_ROWS)]
        };
        progress.finish();
        Ok(Self {
            sources,
            data: Arc::new(data),
            done,
        })
    }

    /// A zero `rows × sources` array, if it fits within `limit` bytes and in memory.
    fn zeros(rows: usize, sources: usize, limit: u64) -> Result<Vec<f32>, SolveError> {
        let bytes = Self::bytes(rows, sources);
        let too_large = SolveError::MatrixTooLarge { bytes, limit };
        if bytes > limit || usize::try_from(bytes).is_err() {
            return Err(too_large);
        }
        let mut data = Vec::new();
        data.try_reserve_exact(rows * sources)
            .map_err(|_| too_large)?;
        data.resize(rows * sources, 0.0);
        Ok(data)
    }

    /// (rows, sources).
    #[must_use]
    pub fn shape(&self) -> (usize, usize) {
        (
            self.data.len().checked_div(self.sources).unwrap_or(0),
            self.sources,
        )
    }

    /// Whether every row is computed.
    #[must_use]
    pub fn complete(&self) -> bool {
        self.done.iter().all(|&d| d)
    }

    /// Whether each chunk of [`CHUNK_ROWS`] rows is computed.
    pub(super) fn chunks_done(&self) -> &[bool] {
        &self.done
    }

    /// The rows, row-major (zero in chunks not done).
    pub(super) fn data(&self) -> &[f32] {
        &self.data
    }

    /// A matrix read back from a checkpoint: `data` holds every row, zero where `done` is
    /// false. `None` when the lengths disagree.
    pub(super) fn from_parts(sources: usize, data: Vec<f32>, done: Vec<bool>) -> Option<Self> {
        let rows = data.len().checked_div(sources).unwrap_or(0);
        let consistent =
            data.len().is_multiple_of(sources.max(1)) && done.len() == rows.div_ceil(CHUNK_ROWS);
        consistent.then(|| Self {
            sources,
            data: Arc::new(data),
            done,
        })
    }

    /// Row `element`: F from that element to every source.
    #[must_use]
    pub fn row(&self, element: usize) -> &[f32] {
        &self.data[element * self.sources..(element + 1) * self.sources]
    }

    /// Number of non-zero form factors.
    #[must_use]
    pub fn links(&self) -> u64 {
        self.data.iter().filter(|&&f| f != 0.0).count() as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_above_one_are_scaled_to_one_others_kept() {
        let mut over = [0.5f32, 0.4, 0.3];
        cap_at_hemisphere(&mut over);
        let sum: f32 = over.iter().sum();
        assert!((sum - 1.0).abs() < 1e-6, "{over:?}");
        assert!(
            (over[0] / over[2] - 0.5 / 0.3).abs() < 1e-5,
            "proportions kept"
        );
        let mut under = [0.5f32, 0.2, 0.1];
        cap_at_hemisphere(&mut under);
        assert_eq!(under, [0.5, 0.2, 0.1]);
    }
}
