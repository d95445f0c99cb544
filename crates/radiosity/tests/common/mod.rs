//! Helpers shared by the form-factor test binaries.

use radiosity::formfactor::{FormFactors, Geometry};

/// F from patch `from` (all its elements, area-weighted) to patch `to` (all its sources),
/// through columns: F_{from→to} = Σ_e A_e Σ_s F_{e→s} / A_from (for hemicubes, the cubes at
/// the sources and reciprocity).
pub fn patch_to_patch(g: &Geometry, ff: &dyn FormFactors, from: u32, to: u32) -> f64 {
    let mut column = vec![0.0; g.mesh.element_count()];
    let mut sum = 0.0;
    for s in (0..g.sources.len()).filter(|&s| g.source_patch(s) == to) {
        ff.column(g, s, &mut column);
        for (e, &f) in column.iter().enumerate() {
            if g.mesh.element(e).patch == from {
                sum += g.mesh.element(e).area() * f64::from(f);
            }
        }
    }
    sum / g.mesh.patches[from as usize].area
}
