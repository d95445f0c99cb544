//! Visibility acceleration (in progress).
