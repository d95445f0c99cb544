//! Quadtrees and octrees of points: a cell splits into 2ᵈ equal children (quadrants, octants)
//! when it holds more than `capacity` points, down to `max_depth` (Finkel & Bentley 1974;
//! Samet 1984). One implementation generic over the dimension d.

/// A 2ᵈ-tree of points in d dimensions (see the module doc).
#[derive(Clone, Debug)]
pub struct Orthtree<const D: usize> {
    nodes: Vec<Cell<D>>,
    points: Vec<[f64; D]>,
    capacity: usize,
    max_depth: u32,
}

/// A quadtree of 2-D points.
pub type Quadtree = Orthtree<2>;
/// An octree of 3-D points.
pub type Octree = Orthtree<3>;

#[derive(Clone, Debug)]
struct Cell<const D: usize> {
    min: [f64; D],
    max: [f64; D],
    depth: u32,
    /// Index of the first of 2ᵈ consecutive children, for an inner cell.
    children: Option<usize>,
    /// Points of a leaf.
    items: Vec<usize>,
}

impl<const D: usize> Cell<D> {
    fn contains(&self, p: &[f64; D]) -> bool {
        (0..D).all(|a| p[a] >= self.min[a] && p[a] <= self.max[a])
    }
}

impl<const D: usize> Orthtree<D> {
    /// An empty tree over the box `min..max`; leaves split above `capacity` points (at least
    /// 1) until `max_depth`.
    #[must_use]
    pub fn new(min: [f64; D], max: [f64; D], capacity: usize, max_depth: u32) -> Self {
        Self {
            nodes: vec![Cell {
                min,
                max,
                depth: 0,
                children: None,
                items: Vec::new(),
            }],
            points: Vec::new(),
            capacity: capacity.max(1),
            max_depth,
        }
    }

    /// Inserts `p`; returns its index, or `None` (and stores nothing) if `p` is outside the
    /// root box or not finite.
    pub fn insert(&mut self, p: [f64; D]) -> Option<usize> {
        if !(p.iter().all(|x| x.is_finite()) && self.nodes[0].contains(&p)) {
            return None;
        }
        let id = self.points.len();
        self.points.push(p);
        let mut n = 0;
        while let Some(first) = self.nodes[n].children {
            n = first + self.child_of(n, &p);
        }
        self.nodes[n].items.push(id);
        if self.nodes[n].items.len() > self.capacity && self.nodes[n].depth < self.max_depth {
            self.split(n);
        }
        Some(id)
    }

    /// Which child of cell `n` holds `p` (bit a set: upper half along axis a).
    fn child_of(&self, n: usize, p: &[f64; D]) -> usize {
        let c = &self.nodes[n];
        (0..D)
            .filter(|&a| p[a] > 0.5 * (c.min[a] + c.max[a]))
            .map(|a| 1 << a)
            .sum()
    }

    /// Splits leaf `n`, pushing its points down (repeatedly while a child stays crowded).
    fn split(&mut self, n: usize) {
        let mut work = vec![n];
        while let Some(n) = work.pop() {
            let (min, max, depth) = (self.nodes[n].min, self.nodes[n].max, self.nodes[n].depth);
            let first = self.nodes.len();
            for k in 0..1usize << D {
                let mut lo = min;
                let mut hi = max;
                for a in 0..D {
                    let mid = 0.5 * (min[a] + max[a]);
                    if k >> a & 1 == 1 {
                        lo[a] = mid;
                    } else {
                        hi[a] = mid;
                    }
                }
                self.nodes.push(Cell {
                    min: lo,
                    max: hi,
                    depth: depth + 1,
                    children: None,
                    items: Vec::new(),
                });
            }
            self.nodes[n].children = Some(first);
            for id in std::mem::take(&mut self.nodes[n].items) {
                let c = first + self.child_of(n, &self.points[id]);
                self.nodes[c].items.push(id);
            }
            for c in first..first + (1 << D) {
                if self.nodes[c].items.len() > self.capacity && depth + 1 < self.max_depth {
                    work.push(c);
                }
            }
        }
    }

    /// Indices of the points inside the box `min..max` (inclusive).
    #[must_use]
    pub fn query_box(&self, min: [f64; D], max: [f64; D]) -> Vec<usize> {
        let mut out = Vec::new();
        let mut work = vec![0];
        while let Some(n) = work.pop() {
            let c = &self.nodes[n];
            if (0..D).any(|a| c.max[a] < min[a] || c.min[a] > max[a]) {
                continue;
            }
            match c.children {
                Some(first) => work.extend(first..first + (1 << D)),
                None => out.extend(c.items.iter().copied().filter(|&id| {
                    let p = &self.points[id];
                    (0..D).all(|a| p[a] >= min[a] && p[a] <= max[a])
                })),
            }
        }
        out.sort_unstable();
        out
    }

    /// Number of points stored.
    #[must_use]
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether no point is stored.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Number of cells (inner and leaves).
    #[must_use]
    pub fn cell_count(&self) -> usize {
        self.nodes.len()
    }

    /// Checks the invariants: children tile their parent exactly (halves along every axis) one
    /// level deeper; inner cells hold no points; every point is in exactly one leaf, which
    /// contains it; leaves above capacity only at the maximum depth.
    ///
    /// # Errors
    /// The first violation, as a message.
    pub fn validate(&self) -> Result<(), String> {
        let mut seen = vec![0u32; self.points.len()];
        for (n, c) in self.nodes.iter().enumerate() {
            match c.children {
                Some(first) => {
                    if !c.items.is_empty() {
                        return Err(format!("inner cell {n} holds points"));
                    }
                    for k in 0..1usize << D {
                        let Some(ch) = self.nodes.get(first + k) else {
                            return Err(format!("cell {n}: child out of range"));
                        };
                        for a in 0..D {
                            let mid = 0.5 * (c.min[a] + c.max[a]);
                            let (lo, hi) = if k >> a & 1 == 1 {
                                (mid, c.max[a])
                            } else {
                                (c.min[a], mid)
                            };
                            if ch.min[a] != lo || ch.max[a] != hi || ch.depth != c.depth + 1 {
                                return Err(format!("cell {n}: child {k} does not tile it"));
                            }
                        }
                    }
                }
                None => {
                    if c.items.len() > self.capacity && c.depth < self.max_depth {
                        return Err(format!("leaf {n} is over capacity"));
                    }
                    for &id in &c.items {
                        if !c.contains(&self.points[id]) {
                            return Err(format!("leaf {n} does not contain point {id}"));
                        }
                        seen[id] += 1;
                    }
                }
            }
        }
        match seen.iter().position(|&s| s != 1) {
            Some(id) => Err(format!("point {id} is in {} leaves", seen[id])),
            None => Ok(()),
        }
    }
}
