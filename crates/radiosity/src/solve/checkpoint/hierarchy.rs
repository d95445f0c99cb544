//! The state of a hierarchical solve between two passes, for checkpoints.
//!
//! A pass refines the links and the quadtrees, then solves; at its end everything the next
//! pass reads is here: the leaves split so far, in order (replayed on the unrefined mesh, they
//! give the refined quadtrees with the same node numbers, since [`crate::mesh::Mesh::refine`]
//! appends children in the order of the splits), the links, and the radiosity and irradiance
//! of every node and cluster. What follows from the replayed mesh (areas, openness, gains) is
//! left out. The record is plain data — links as their bits, the push-pull state as its
//! vectors — so that the checkpoint knows nothing of the solver that fills it.

use super::file::{allocate, Decoder, Encoder};
use crate::solve::Sample;
use crate::Rgb;

/// See the module documentation.
#[derive(Clone, Debug, PartialEq)]
pub(in crate::solve) struct Hierarchy {
    /// Passes done.
    pub passes: u32,
    /// The leaves split so far, in order.
    pub splits: Vec<u32>,
    /// The links after the last refinement, sorted by (receiver, source), as their bits.
    pub links: Vec<[u32; 4]>,
    /// B of every mesh node.
    pub node_b: Vec<Rgb>,
    /// Irradiance gathered by every mesh node.
    pub node_h: Vec<Rgb>,
    /// B of every cluster.
    pub cluster_b: Vec<Rgb>,
    /// Every cluster's directional sums of its members' normals.
    pub cluster_n: Vec<[Rgb; 6]>,
    /// Irradiance gathered by every cluster.
    pub cluster_h: Vec<Rgb>,
    /// Every cluster's directional sums of power.
    pub cluster_q: Vec<[Rgb; 6]>,
    /// The convergence history so far.
    pub history: Vec<Sample>,
    /// Seconds spent refining and iterating so far.
    pub seconds: (f64, f64),
    /// Peak bytes of the hierarchy so far.
    pub peak: u64,
}

impl Hierarchy {
    /// Writes the snapshot in the checkpoint encoding.
    pub(crate) fn encode(&self, e: &mut Encoder) -> std::io::Result<()> {
        e.u32(self.passes)?;
        e.usize(self.splits.len())?;
        self.splits.iter().try_for_each(|&n| e.u32(n))?;
        e.usize(self.links.len())?;
        for link in &self.links {
            link.iter().try_for_each(|&x| e.u32(x))?;
        }
        let s = self;
        e.rgbs(&s.node_b)?;
        e.rgbs(&s.node_h)?;
        e.rgbs(&s.cluster_b)?;
        directional(e, &s.cluster_n)?;
        e.rgbs(&s.cluster_h)?;
        directional(e, &s.cluster_q)?;
        e.usize(self.history.len())?;
        for s in &self.history {
            e.usize(s.iteration)?;
            e.f64(s.seconds)?;
            e.f64(s.residual)?;
        }
        e.f64(self.seconds.0)?;
        e.f64(self.seconds.1)?;
        e.u64(self.peak)
    }

    /// Reads what [`Hierarchy::encode`] wrote.
    pub(crate) fn decode(d: &mut Decoder) -> Result<Self, String> {
        let passes = d.u32()?;
        let n = d.usize()?;
        let mut splits = allocate(n)?;
        for _ in 0..n {
            splits.push(d.u32()?);
        }
        let n = d.usize()?;
        let mut links = allocate(n)?;
        for _ in 0..n {
            links.push([d.u32()?, d.u32()?, d.u32()?, d.u32()?]);
        }
        let node_b = d.rgbs()?;
        let node_h = d.rgbs()?;
        let cluster_b = d.rgbs()?;
        let cluster_n = read_directional(d)?;
        let cluster_h = d.rgbs()?;
        let cluster_q = read_directional(d)?;
        let n = d.usize()?;
        let mut history = allocate(n)?;
        for _ in 0..n {
            history.push(Sample {
                iteration: d.usize()?,
                seconds: d.f64()?,
                residual: d.f64()?,
            });
        }
        Ok(Self {
            passes,
            splits,
            links,
            node_b,
            node_h,
            cluster_b,
            cluster_n,
            cluster_h,
            cluster_q,
            history,
            seconds: (d.f64()?, d.f64()?),
            peak: d.u64()?,
        })
    }
}

fn directional(e: &mut Encoder, v: &[[Rgb; 6]]) -> std::io::Result<()> {
    e.usize(v.len())?;
    v.iter().flatten().try_for_each(|&c| e.rgb(c))
}

fn read_directional(d: &mut Decoder) -> Result<Vec<[Rgb; 6]>, String> {
    let n = d.usize()?;
    let mut v = allocate(n)?;
    for _ in 0..n {
        let mut x = [Rgb::ZERO; 6];
        for c in &mut x {
            *c = d.rgb()?;
        }
        v.push(x);
    }
    Ok(v)
}
