//! ply reader (to be written).

use super::{MeshSoup, ParseError};

/// Reads a ply model.
///
/// # Errors
/// A [`ParseError`] naming the place and the fix.
pub fn read(_reader: impl std::io::Read) -> Result<MeshSoup, ParseError> {
    todo!()
}
