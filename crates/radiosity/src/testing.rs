//! Test scenes (in progress).
