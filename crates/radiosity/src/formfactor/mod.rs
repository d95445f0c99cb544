//! Form factors (in progress).
