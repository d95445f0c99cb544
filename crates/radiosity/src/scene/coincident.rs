//! Coincident faces: the same surface written twice.
//!
//! Downloaded OBJ files have them (the widespread Cornell-box OBJ repeats a side face of each
//! block as its "bottom"); two coincident surfaces would each hide the other's lifted ray ends
//! and shade as one z-fighting face. A face is a duplicate when it has exactly the corners of
//! one seen before, in the same cyclic order — or in either orientation when its material is
//! two-sided: two opposite one-sided faces are a legitimate two-sided sheet, as our own GLB
//! export writes them.

use std::collections::HashSet;

use glam::Vec3;

/// A position as the exact bit patterns of its coordinates (−0 taken as +0): equal keys are the
/// same point, as a file that shares a vertex between faces writes it.
#[must_use]
pub(crate) fn exact_bits(v: Vec3) -> [u32; 3] {
    v.to_array().map(|x| (x + 0.0).to_bits())
}

/// The faces seen so far, by their corners.
#[derive(Debug, Default)]
pub(crate) struct SeenFaces(HashSet<Vec<[u32; 3]>>);

impl SeenFaces {
    /// Records the face with corners `vs`; false when a face coincident with it was seen
    /// before (`unoriented`: either orientation counts).
    pub fn first_time(&mut self, vs: &[Vec3], unoriented: bool) -> bool {
        self.0.insert(corner_key(vs, unoriented))
    }
}

/// The duplicates dropped from one file: how many, and the line of the first.
#[derive(Debug, Default)]
pub(crate) struct Dropped {
    count: usize,
    first_line: Option<usize>,
}

impl Dropped {
    /// Counts one more dropped face, from `line` if known.
    pub fn add(&mut self, line: Option<usize>) {
        if self.count == 0 {
            self.first_line = line;
        }
        self.count += 1;
    }

    /// The one warning for the file `label`, if anything was dropped.
    pub fn warning(&self, label: &str) -> Option<String> {
        (self.count > 0).then(|| {
            let at = self
                .first_line
                .map_or(String::new(), |l| format!(" (first at line {l})"));
            format!(
                "{label}: dropped {} face(s) coincident with an earlier face{at}",
                self.count
            )
        })
    }
}

/// The corners as exact bit patterns in a canonical cyclic order (starting at the smallest),
/// and for `unoriented` faces the smaller of the two orientations: equal keys are coincident
/// faces.
fn corner_key(vs: &[Vec3], unoriented: bool) -> Vec<[u32; 3]> {
    let bits: Vec<[u32; 3]> = vs.iter().map(|&v| exact_bits(v)).collect();
    let canonical = |ring: Vec<[u32; 3]>| {
        let first = (0..ring.len()).min_by_key(|&i| ring[i]).unwrap_or(0);
        let mut out = ring;
        out.rotate_left(first);
        out
    };
    let forward = canonical(bits.clone());
    if !unoriented {
        return forward;
    }
    let mut reversed = bits;
    reversed.reverse();
    forward.min(canonical(reversed))
}
