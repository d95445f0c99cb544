//! The state of a hierarchical solve between two passes, for checkpoints.
//!
//! A pass refines the links and the quadtrees, then solves; at its end everything the next
//! pass reads is here: the leaves split so far, in order (replayed on the unrefined mesh, they
//! give the refined quadtrees with the same node numbers, since [`crate::mesh::Mesh::refine`]
//! appends children in the order of the splits), the links, and the push-pull state of every
//! node and cluster. The node areas are left out: they follow from the replayed mesh.

use super::link::Link;
use super::push_pull::{Directional, State};
use crate::solve::checkpoint::file::{allocate, Decoder, Encoder};
use crate::solve::Sample;
use crate::Rgb;

/// See the module documentation.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// Passes done.
    pub(super) passes: u32,
    /// The leaves split so far, in order.
    pub(super) splits: Vec<u32>,
    /// The links after the last refinement, sorted by (receiver, source).
    pub(super) links: Vec<Link>,
    /// B, irradiance and the clusters' directional sums (node areas empty).
    pub(super) state: State,
    /// The convergence history so far.
    pub(super) history: Vec<Sample>,
    /// Seconds spent refining and iterating so far.
    pub(super) seconds: (f64, f64),
    /// Peak bytes of the hierarchy so far.
    pub(super) peak: u64,
}

impl Snapshot {
    /// Writes the snapshot in the checkpoint encoding.
    pub(crate) fn encode(&self, e: &mut Encoder) -> std::io::Result<()> {
        e.u32(self.passes)?;
        e.usize(self.splits.len())?;
        self.splits.iter().try_for_each(|&n| e.u32(n))?;
        e.usize(self.links.len())?;
        for link in &self.links {
            link.to_bits().into_iter().try_for_each(|x| e.u32(x))?;
        }
        let s = &self.state;
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

    /// Reads what [`Snapshot::encode`] wrote.
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
            links.push(Link::from_bits([d.u32()?, d.u32()?, d.u32()?, d.u32()?]));
        }
        let state = State {
            node_b: d.rgbs()?,
            node_h: d.rgbs()?,
            node_area: Vec::new(),
            node_probed: Vec::new(),
            node_open: Vec::new(),
            node_shine: Vec::new(),
            node_gain: Vec::new(),
            cluster_b: d.rgbs()?,
            cluster_n: read_directional(d)?,
            cluster_h: d.rgbs()?,
            cluster_q: read_directional(d)?,
        };
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
            state,
            history,
            seconds: (d.f64()?, d.f64()?),
            peak: d.u64()?,
        })
    }
}

fn directional(e: &mut Encoder, v: &[Directional]) -> std::io::Result<()> {
    e.usize(v.len())?;
    v.iter().flatten().try_for_each(|&c| e.rgb(c))
}

fn read_directional(d: &mut Decoder) -> Result<Vec<Directional>, String> {
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
