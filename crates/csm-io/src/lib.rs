//! I/O layer of csm (work in progress).
