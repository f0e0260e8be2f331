//! Stage 1: interface conditions generated from element faces when a contact part has only
//! nodes (Kratos `InterfacePreprocessCondition`, reference §13). Not implemented yet.
