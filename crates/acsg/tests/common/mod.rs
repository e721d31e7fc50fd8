//! Helpers shared by the integration tests (declared with `mod common;` in each).
// Each test crate compiles its own copy and uses only part of it.
#![allow(dead_code)]

pub mod hull;
pub mod principal;
pub mod slices;
