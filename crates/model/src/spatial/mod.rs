//! Spatial data structures of the course's solid-modeling review, each with a `validate()`:
//!
//! * [`voxel::VoxelGrid`]: spatial enumeration, a solid as the set of occupied cells of a
//!   regular grid;
//! * [`orthtree::Quadtree`] and [`orthtree::Octree`]: recursive subdivision of a square or cube
//!   into 2ᵈ equal children where points crowd (Samet 1984), one generic implementation;
//! * [`bsp::BspTree`]: binary space partitioning by polygon planes (Fuchs, Kedem & Naylor
//!   1980), the engine of [`crate::csg`].
//!
//! Marching cubes walks an implicit octree of grid blocks
//! ([`crate::implicit::marching_cubes`]).

pub mod bsp;
pub mod orthtree;
pub mod voxel;
