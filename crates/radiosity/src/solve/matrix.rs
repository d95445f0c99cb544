//! The stored form-factor matrix of the gathering solvers: one row of F_{e→s} per element (the
//! receivers), one column per source, `f32`, row-major; and for each row the pieces of the
//! sources it opened in its near field ([`super::opened_sources`]), a few per row.
//!
//! Its size, elements × sources × 4 bytes, is checked against the limit *before* anything is
//! allocated, and the allocation itself is fallible, so a scene too large for memory is a
//! [`SolveError::MatrixTooLarge`], never an abort. Rows are filled in parallel in chunks; each
//! row depends on its element only, so the matrix is the same at any thread count.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use rayon::prelude::*;

use super::opened_sources::{self, Piece, Scratch};
use super::SolveError;
use crate::formfactor::{FormFactors, Geometry};
use crate::progress::{Progress, Work};

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
    /// The opened pieces of every row.
    near: Arc<Near>,
    /// Whether each chunk of rows is computed.
    done: Vec<bool>,
}

/// The opened pieces of every row, kept by chunks of [`CHUNK_ROWS`] rows as they were computed
/// (one array per chunk, no copy into one long array: at 60 000 elements with 4 400 sources
/// there are some 300 pieces per row, 0.2 GB).
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Near {
    chunks: Vec<NearChunk>,
}

/// The pieces of one chunk of rows: those of its row k are `pieces[start[k]..start[k + 1]]`.
#[derive(Clone, Debug, Default, PartialEq)]
struct NearChunk {
    start: Vec<u32>,
    pieces: Vec<Piece>,
}

impl NearChunk {
    /// Chunk `k` of a matrix of `rows` rows, without pieces.
    fn empty(rows: usize, k: usize) -> Self {
        Self {
            start: vec![0; CHUNK_ROWS.min(rows - k * CHUNK_ROWS) + 1],
            pieces: Vec::new(),
        }
    }

    /// From the pieces of each of its rows.
    fn from_rows(rows: impl IntoIterator<Item = Vec<Piece>>) -> Self {
        let mut chunk = Self {
            start: vec![0],
            pieces: Vec::new(),
        };
        for row in rows {
            chunk.pieces.extend(row);
            chunk.start.push(chunk.pieces.len() as u32);
        }
        chunk.pieces.shrink_to_fit();
        chunk
    }
}

impl Near {
    /// From each row's pieces, in row order.
    pub fn from_rows(rows: Vec<Vec<Piece>>) -> Self {
        let mut rows = rows.into_iter().peekable();
        let mut chunks = Vec::new();
        while rows.peek().is_some() {
            chunks.push(NearChunk::from_rows(rows.by_ref().take(CHUNK_ROWS)));
        }
        Self { chunks }
    }

    /// The pieces of row `e`.
    pub fn row(&self, e: usize) -> &[Piece] {
        let chunk = &self.chunks[e / CHUNK_ROWS];
        let k = e % CHUNK_ROWS;
        &chunk.pieces[chunk.start[k] as usize..chunk.start[k + 1] as usize]
    }

    /// The number of rows.
    fn rows(&self) -> usize {
        self.chunks.iter().map(|c| c.start.len() - 1).sum()
    }

    /// The number of pieces.
    fn len(&self) -> usize {
        self.chunks.iter().map(|c| c.pieces.len()).sum()
    }
}

/// Scales a row (its shared sources and its opened pieces) whose sum exceeds 1 down to 1: an
/// element cannot see more than its hemisphere.
/// The quadrature of each factor is accurate to ~10⁻³, but next to contact lines, where a
/// receiver's few points see a touching surface's steep kernel, rows came to sum a little above
/// one and a closed furnished room absorbed 1.004 times the power it emits. Only the rows of
/// elements in another surface's near field ([`crate::mesh::Node::near`]) are capped: elsewhere
/// a row errs only by its shadow rays' noise, both ways, and cutting its high draws alone is a
/// bias (with four rays per pair the furnished room absorbed 0.13 % less than it emits when
/// every row was capped, 0.04 % more with near rows only; docs/decisions/row-capping.md).
fn cap_at_hemisphere(row: &mut [f32], pieces: &mut [Piece]) {
    let sum: f64 = row.iter().map(|&f| f64::from(f)).sum::<f64>()
        + pieces.iter().map(|p| f64::from(p.factor)).sum::<f64>();
    if sum > 1.0 {
        let scale = (1.0 / sum) as f32;
        row.iter_mut().for_each(|f| *f *= scale);
        pieces.iter_mut().for_each(|p| p.factor *= scale);
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
        progress.start("form factors", Work::of(rows as u64, "rows"));
        let chunks: Vec<Option<NearChunk>> = if sources > 0 {
            data.par_chunks_mut(CHUNK_ROWS * sources)
                .enumerate()
                .map(|(chunk, block)| {
                    let first = chunk * CHUNK_ROWS;
                    let rows = block.len() / sources;
                    let near = if let Some(prior) = prior.filter(|p| p.done[chunk]) {
                        block.copy_from_slice(&prior.data[first * sources..][..block.len()]);
                        NearChunk::from_rows(
                            (first..first + rows).map(|e| prior.near.row(e).to_vec()),
                        )
                    } else {
                        if stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
                            return None;
                        }
                        let mut scratch = Scratch::default();
                        NearChunk::from_rows(block.chunks_mut(sources).enumerate().map(
                            |(k, row)| {
                                let mut pieces = Vec::new();
                                opened_sources::row(
                                    g,
                                    ff,
                                    first + k,
                                    row,
                                    &mut pieces,
                                    &mut scratch,
                                );
                                if g.mesh.element(first + k).near {
                                    cap_at_hemisphere(row, &mut pieces);
                                }
                                pieces
                            },
                        ))
                    };
                    progress.advance(rows as u64);
                    Some(near)
                })
                .collect()
        } else {
            (0..rows.div_ceil(CHUNK_ROWS))
                .map(|k| Some(NearChunk::empty(rows, k)))
                .collect()
        };
        // A chunk is missing only when the stop flag skipped it.
        progress.end(chunks.iter().any(Option::is_none));
        let done = chunks.iter().map(Option::is_some).collect();
        let near = Near {
            chunks: chunks
                .into_iter()
                .enumerate()
                .map(|(k, chunk)| chunk.unwrap_or_else(|| NearChunk::empty(rows, k)))
                .collect(),
        };
        Ok(Self {
            sources,
            data: Arc::new(data),
            near: Arc::new(near),
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

    /// The opened pieces of every row (none in chunks not done).
    pub(super) fn near(&self) -> &Near {
        &self.near
    }

    /// A matrix read back from a checkpoint: `data` holds every row, zero where `done` is
    /// false, and `near` the pieces of every row. `None` when the lengths disagree.
    pub(super) fn from_parts(
        sources: usize,
        data: Vec<f32>,
        near: Near,
        done: Vec<bool>,
    ) -> Option<Self> {
        let rows = data.len().checked_div(sources).unwrap_or(0);
        let consistent = data.len().is_multiple_of(sources.max(1))
            && done.len() == rows.div_ceil(CHUNK_ROWS)
            && near.rows() == rows
            && near
                .chunks
                .iter()
                .all(|c| c.pieces.iter().all(|p| p.elements.end as usize <= rows));
        consistent.then(|| Self {
            sources,
            data: Arc::new(data),
            near: Arc::new(near),
            done,
        })
    }

    /// Row `element`: F from that element to every source (zero for the sources it opened).
    #[must_use]
    pub fn row(&self, element: usize) -> &[f32] {
        &self.data[element * self.sources..(element + 1) * self.sources]
    }

    /// The pieces of the sources that row `element` opened, with their factors.
    #[must_use]
    pub fn pieces(&self, element: usize) -> &[Piece] {
        self.near.row(element)
    }

    /// Σ F of row `element`, shared sources and opened pieces.
    #[must_use]
    pub fn row_sum(&self, element: usize) -> f64 {
        self.row(element).iter().map(|&f| f64::from(f)).sum::<f64>()
            + self
                .pieces(element)
                .iter()
                .map(|p| f64::from(p.factor))
                .sum::<f64>()
    }

    /// Number of non-zero form factors (opened pieces included).
    #[must_use]
    pub fn links(&self) -> u64 {
        (self.data.iter().filter(|&&f| f != 0.0).count() + self.near.len()) as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_above_one_are_scaled_to_one_others_kept() {
        let mut over = [0.5f32, 0.4, 0.2];
        let mut pieces = [Piece {
            elements: 0..2,
            factor: 0.1,
        }];
        cap_at_hemisphere(&mut over, &mut pieces);
        let sum: f32 = over.iter().sum::<f32>() + pieces[0].factor;
        assert!((sum - 1.0).abs() < 1e-6, "{over:?}");
        assert!(
            (over[0] / pieces[0].factor - 0.5 / 0.1).abs() < 1e-4,
            "proportions kept"
        );
        let mut under = [0.5f32, 0.2, 0.1];
        cap_at_hemisphere(&mut under, &mut []);
        assert_eq!(under, [0.5, 0.2, 0.1]);
    }
}
