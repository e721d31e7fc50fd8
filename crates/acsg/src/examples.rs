//! Built-in example parts, so that the tool runs with no files to find.
//!
//! The models are the repository's fixtures (`fixtures/`, made by
//! `scripts/make_fixtures.py`), compiled into the library.

use std::path::Path;

use crate::model::Part;

/// The paper's example (its Fig. 4, as modelled in `fixtures/`): an L-shaped block
/// (fixed, 200 × 100 × 150 mm) and a box (moving, 100 × 80 × 100 mm) that sits in the
/// L's inside corner at the assembled pose.
pub const L_BLOCK_OFF: &str = include_str!("../../../fixtures/l_block.off");
/// The box of [`L_BLOCK_OFF`]'s example.
pub const BOX_OFF: &str = include_str!("../../../fixtures/box.off");

/// Builds a part from an embedded OFF text.
///
/// # Panics
/// Only if the embedded model is broken, which the test suite rules out.
#[must_use]
pub fn builtin(name: &str, off: &str) -> Part {
    let soup = crate::io::read_bytes(off.as_bytes(), Path::new(name)).expect("embedded model reads");
    Part::try_new(&soup, name).expect("embedded model is a valid solid")
}

/// The L-block (fixed) and the box (moving) of the paper's example.
#[must_use]
pub fn l_block_and_box() -> (Part, Part) {
    (
        builtin("builtin:l_block.off", L_BLOCK_OFF),
        builtin("builtin:box.off", BOX_OFF),
    )
}
