//! File input and output (in progress).
pub mod obj;
