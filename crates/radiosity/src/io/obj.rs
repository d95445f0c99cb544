//! OBJ (in progress).
