//! Pairwise distance queries between placed surface elements.
