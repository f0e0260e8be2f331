//! Stage 2: the normal check on solid elements (Kratos `NormalCheckProcess`, reference §14).
//! Not implemented yet.
