//! Handles: one end of a link, either a node of the element quadtrees or a cluster, in four
//! bytes so that a link stays 16 (the top bit tells which, the rest is the index).

/// The top bit of a handle's bits: set for a cluster.
const CLUSTER_BIT: u32 = 1 << 31;

/// A node of [`crate::mesh::Mesh::nodes`] or a cluster of [`super::cluster::Clusters`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Handle(u32);

/// What a [`Handle`] stands for, with its index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// A node of the element quadtrees: a root face, a split face or an element.
    Node(usize),
    /// A cluster.
    Cluster(usize),
}

impl Handle {
    /// The root cluster, which holds every face.
    pub const ROOT_CLUSTER: Self = Self(CLUSTER_BIT);

    /// The handle of node `n` (below 2³¹).
    #[must_use]
    pub fn node(n: u32) -> Self {
        debug_assert!(n & CLUSTER_BIT == 0, "node {n} beyond the handles' range");
        Self(n)
    }

    /// The handle of cluster `c` (below 2³¹).
    #[must_use]
    pub fn cluster(c: u32) -> Self {
        debug_assert!(
            c & CLUSTER_BIT == 0,
            "cluster {c} beyond the handles' range"
        );
        Self(c | CLUSTER_BIT)
    }

    /// What the handle stands for.
    #[must_use]
    pub fn end(self) -> End {
        if self.is_cluster() {
            End::Cluster((self.0 & !CLUSTER_BIT) as usize)
        } else {
            End::Node(self.0 as usize)
        }
    }

    /// Whether it is a cluster.
    #[must_use]
    pub fn is_cluster(self) -> bool {
        self.0 & CLUSTER_BIT != 0
    }

    /// The node index, for a handle that is a node.
    #[must_use]
    pub fn as_node(self) -> Option<usize> {
        match self.end() {
            End::Node(n) => Some(n),
            End::Cluster(_) => None,
        }
    }

    /// The bits, for checkpoints and for the hashes that seed a pair's rays.
    #[must_use]
    pub fn to_bits(self) -> u32 {
        self.0
    }

    /// The handle of [`Handle::to_bits`].
    #[must_use]
    pub fn from_bits(bits: u32) -> Self {
        Self(bits)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nodes_and_clusters_keep_their_index_and_kind() {
        for i in [0, 1, 7, (1 << 31) - 1] {
            assert_eq!(Handle::node(i).end(), End::Node(i as usize));
            assert_eq!(Handle::cluster(i).end(), End::Cluster(i as usize));
            assert_ne!(Handle::node(i), Handle::cluster(i));
            let h = Handle::cluster(i);
            assert_eq!(Handle::from_bits(h.to_bits()), h);
        }
        assert_eq!(Handle::ROOT_CLUSTER, Handle::cluster(0));
        // Every node sorts before every cluster (links are sorted by receiver).
        assert!(Handle::node((1 << 31) - 1) < Handle::cluster(0));
    }
}
