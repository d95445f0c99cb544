//! Column balance: every source hands out, through the stored matrix, the power that its own
//! rows say it sends, and every row keeps its sum.
//!
//! A gathering solver's matrix is computed row by row, at the receivers: F_is is what element
//! i sees of source s, and the row sum Σ_s F_is what the element sees of the scene. What a
//! source gives away is its column, with its opened pieces ([`super::opened_sources`]),
//!
//! ```text
//! C_s = Σ_i A_i F_is ,
//! ```
//!
//! and reciprocity (A_i F_is = A_s F_si) says what it should be: the light its own elements
//! send to the scene, T_s = Σ_{j ∈ s} A_j Σ_k F_jk. In a closed scene
//!
//! ```text
//! absorbed − emitted = Σ_s B̄_s (C_s − T_s)     (B uniform over each source),
//! ```
//!
//! A hemicube's rows tile its hemisphere, so they sum to what the element sees exactly, but the
//! errors of its cells — a source seen at a grazing angle from many receivers covers a few
//! cells too many or too few ([`crate::formfactor::hemicube`]; Baum, Rushmeier & Winget 1989)
//! — do not cancel in a column: the furnished room's window column was 1.0011 T and the room
//! absorbed 1.0014 times its lamps' power, the partitioned room 1.0010 times. So, for the
//! form-factor methods whose rows tile the hemisphere
//! ([`crate::formfactor::FormFactors::rows_tile_the_hemisphere`]), each column is scaled to
//! its target, w_s = T_s / C_s, and then each row back to its own sum, x_i = Σ_s F_is /
//! Σ_s F_is w_s: one step of the iterative proportional fitting of Sinkhorn (1964). It is not
//! iterated to the end: where a hemicube does not see a small source at all (its aliasing:
//! 182 of the furnished room's 7 000 sources are seen by no cell, some see nothing themselves)
//! the fitting has no solution and, iterated, its weights ran off to 10¹⁶⁰ on the furnished
//! room. For the same reason a column more than [`TRUSTED`] times off its target is left as it
//! is: such a column is the aliasing, not a bias, and scaling it would pour the source's light
//! onto the few receivers whose cells caught it.
//!
//! Measured (`radiosity solve scenes/suite/… --solver gauss-seidel --form-factors hemicube
//! --stats`, worst channel): absorbed / emitted 1.0014 → 0.9998 (furnished room), 1.0010 →
//! 1.0001 (partitions). Ray casting's rows are estimates like its columns (and capped near
//! contact lines): balancing its columns to them took the furnished room from 1.0004 to
//! 0.9989, so it is not balanced.
//!
//! The weights depend on the matrix alone and every sum is taken in a fixed order, so they are
//! the same at any thread count.

use rayon::prelude::*;

use super::matrix::{Matrix, CHUNK_ROWS};

/// A column is scaled only when its target is within this factor of it.
pub const TRUSTED: f64 = 2.0;

/// Rows per block of the column sums, each block summed alone and the blocks in order.
const BLOCK_ROWS: usize = CHUNK_ROWS * 64;

/// The weights of the rows (per element: what it gathers) and of the columns (per source: what
/// it shines).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Weights {
    /// x_i.
    pub row: Vec<f64>,
    /// w_s.
    pub column: Vec<f64>,
}

impl Weights {
    /// Every weight 1: the matrix as it is.
    pub fn none(elements: usize, sources: usize) -> Self {
        Self {
            row: vec![1.0; elements],
            column: vec![1.0; sources],
        }
    }
}

/// The balance of `matrix`, with `area` the area of each element and `source_of` its source.
pub(super) fn weights(matrix: &Matrix, area: &[f64], source_of: &[u32]) -> Weights {
    let (rows, sources) = matrix.shape();
    let row_sum: Vec<f64> = (0..rows)
        .into_par_iter()
        .map(|i| matrix.row_sum(i))
        .collect();
    let given = columns(matrix, area, source_of);
    let mut sent = vec![0.0f64; sources];
    for (j, &s) in source_of.iter().enumerate() {
        sent[s as usize] += area[j] * row_sum[j];
    }
    let column: Vec<f64> = sent
        .iter()
        .zip(&given)
        .map(|(&t, &c)| {
            let trusted = c > 0.0 && t > 0.0 && t < TRUSTED * c && c < TRUSTED * t;
            if trusted {
                t / c
            } else {
                1.0
            }
        })
        .collect();
    let row = (0..rows)
        .into_par_iter()
        .map(|i| {
            let weighed: f64 = matrix
                .row(i)
                .iter()
                .zip(&column)
                .map(|(&f, w)| f64::from(f) * w)
                .sum::<f64>()
                + matrix
                    .pieces(i)
                    .iter()
                    .map(|p| {
                        f64::from(p.factor) * column[source_of[p.elements.start as usize] as usize]
                    })
                    .sum::<f64>();
            if weighed > 0.0 {
                row_sum[i] / weighed
            } else {
                1.0
            }
        })
        .collect();
    Weights { row, column }
}

/// C_s = Σ_i A_i F_is of every source, its opened pieces included.
fn columns(matrix: &Matrix, area: &[f64], source_of: &[u32]) -> Vec<f64> {
    let (rows, sources) = matrix.shape();
    let blocks: Vec<Vec<f64>> = (0..rows.div_ceil(BLOCK_ROWS))
        .into_par_iter()
        .map(|b| {
            let mut column = vec![0.0f64; sources];
            let first = b * BLOCK_ROWS;
            for (i, &a) in area
                .iter()
                .enumerate()
                .take(rows)
                .skip(first)
                .take(BLOCK_ROWS)
            {
                for (c, &f) in column.iter_mut().zip(matrix.row(i)) {
                    *c += a * f64::from(f);
                }
                for p in matrix.pieces(i) {
                    column[source_of[p.elements.start as usize] as usize] +=
                        a * f64::from(p.factor);
                }
            }
            column
        })
        .collect();
    let mut sum = vec![0.0f64; sources];
    for block in blocks {
        sum.iter_mut().zip(block).for_each(|(s, b)| *s += b);
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::super::matrix::Near;
    use super::super::opened_sources::Piece;
    use super::*;

    /// Four elements in three sources (elements 0–1, 2, 3); element 3 opens source 0 into its
    /// two elements.
    fn matrix(to_source_1: f32) -> Matrix {
        let f = to_source_1;
        let data = vec![
            0.0, f, 0.4, //
            0.0, f, 0.3, //
            0.5, 0.0, 0.45, //
            0.0, 0.3, 0.0,
        ];
        let piece = |e: u32, factor: f32| Piece {
            elements: e..e + 1,
            factor,
        };
        let near = Near::from_rows(vec![
            vec![],
            vec![],
            vec![],
            vec![piece(0, 0.2), piece(1, 0.25)],
        ]);
        Matrix::from_parts(3, data, near, vec![true]).unwrap()
    }

    const AREA: [f64; 4] = [0.5, 0.5, 1.0, 1.0];
    const SOURCE_OF: [u32; 4] = [0, 0, 1, 2];

    #[test]
    fn columns_give_what_their_sources_send_and_rows_keep_their_sums() {
        let m = matrix(0.5);
        let w = weights(&m, &AREA, &SOURCE_OF);
        let row_sum: Vec<f64> = (0..4).map(|i| m.row_sum(i)).collect();
        // Each source's column, its opened pieces included, times its weight, is its elements'
        // area-weighted row sums.
        let given = columns(&m, &AREA, &SOURCE_OF);
        let mut sent = [0.0; 3];
        for j in 0..4 {
            sent[SOURCE_OF[j] as usize] += AREA[j] * row_sum[j];
        }
        assert!((given[0] - (0.5 + 0.45)).abs() < 1e-6, "{given:?}");
        for s in 0..3 {
            assert!((given[s] * w.column[s] - sent[s]).abs() < 1e-12, "{s}");
            assert!(
                (w.column[s] - 1.0).abs() > 0.05,
                "the example moves every column"
            );
        }
        // Each row, weighed, sums to what it summed.
        for (i, &sum) in row_sum.iter().enumerate() {
            let weighed: f64 = m
                .row(i)
                .iter()
                .zip(&w.column)
                .map(|(&f, c)| f64::from(f) * c)
                .sum::<f64>()
                + m.pieces(i)
                    .iter()
                    .map(|p| f64::from(p.factor) * w.column[0])
                    .sum::<f64>();
            assert!((w.row[i] * weighed - sum).abs() < 1e-12, "{i}");
        }
    }

    #[test]
    fn a_column_far_off_its_target_is_left_alone() {
        // Source 1 barely seen (0.001 from two receivers) while its element sees 0.95: aliasing,
        // not a bias.
        let w = weights(&matrix(0.001), &AREA, &SOURCE_OF);
        assert_eq!(w.column[1], 1.0);
        assert!((w.column[2] - 0.75 / 0.8).abs() < 1e-6, "{:?}", w.column);
    }
}
