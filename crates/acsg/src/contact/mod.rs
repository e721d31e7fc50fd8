//! Contact geometry at a pose: which elements touch, and whether the parts penetrate.

pub mod penetration;
pub mod queries;
