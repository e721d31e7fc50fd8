//! Small text and input helpers shared by the readers.

use std::borrow::Cow;
use std::io::Read;

use super::{MAX_INPUT_BYTES, ParseError, Place, finite_point};

/// Reads a whole input into memory, refusing more than [`MAX_INPUT_BYTES`].
///
/// # Errors
/// A [`ParseError`] for an I/O failure or an oversized input.
pub(crate) fn read_limited(reader: impl Read) -> Result<Vec<u8>, ParseError> {
    let mut bytes = Vec::new();
    reader
        .take(MAX_INPUT_BYTES.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| {
            ParseError::new(
                Place::Whole,
                format!("cannot read the input: {e}"),
                "check that the file is readable and not being written to",
            )
        })?;
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return Err(ParseError::new(
            Place::Whole,
            format!("the input is larger than the {MAX_INPUT_BYTES}-byte limit"),
            "simplify the mesh: coplanar triangles merge into one face anyway",
        ));
    }
    Ok(bytes)
}

/// The lines of a text input, numbered from 1, without their line ending (`\n` or
/// `\r\n`); bytes that are not UTF-8 are replaced, a leading byte-order mark is dropped.
pub(crate) struct TextLines<'a> {
    rest: &'a [u8],
    line: usize,
}

impl<'a> TextLines<'a> {
    /// The lines of `bytes`; `first_line` is the number of the first one.
    pub(crate) fn new(bytes: &'a [u8], first_line: usize) -> Self {
        let rest = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        Self {
            rest,
            line: first_line.saturating_sub(1),
        }
    }

    /// The number of the last line returned (0 before the first).
    pub(crate) fn last_line(&self) -> usize {
        self.line
    }
}

impl<'a> Iterator for TextLines<'a> {
    type Item = (usize, Cow<'a, str>);

    fn next(&mut self) -> Option<Self::Item> {
        if self.rest.is_empty() {
            return None;
        }
        let (raw, rest) = match self.rest.iter().position(|&b| b == b'\n') {
            Some(end) => {
                let (raw, rest) = self.rest.split_at(end);
                (raw, rest.get(1..).unwrap_or_default())
            }
            None => (self.rest, &[][..]),
        };
        self.rest = rest;
        self.line += 1;
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        Some((self.line, String::from_utf8_lossy(raw)))
    }
}

/// Drops a `#` comment from a line.
pub(crate) fn strip_comment(line: &str) -> &str {
    line.split_once('#').map_or(line, |(body, _)| body)
}

/// Parses one number; `what` names the value for the message ("the y coordinate of
/// vertex 4").
///
/// # Errors
/// A [`ParseError`] at `place` quoting the token.
pub(crate) fn parse_f64(token: &str, what: &str, place: Place) -> Result<f64, ParseError> {
    token.parse::<f64>().map_err(|_| {
        ParseError::new(
            place,
            format!("`{token}` is not a number (expected {what})"),
            "write each value as a decimal number such as 1.5 or -2e-3",
        )
    })
}

/// Checks that a point is finite, naming the vertex in the message.
///
/// # Errors
/// The [`finite_point`] error, its problem prefixed with `vertex` ("vertex 4").
pub(crate) fn finite_vertex(p: [f64; 3], vertex: &str, place: Place) -> Result<glam::DVec3, ParseError> {
    finite_point(p, place).map_err(|mut e| {
        e.problem = format!("{vertex}: {}", e.problem);
        e
    })
}

/// A vertex index as the soup stores it.
///
/// # Errors
/// A [`ParseError`] when the index does not fit in 32 bits (it cannot, for inputs
/// within [`MAX_INPUT_BYTES`]).
pub(crate) fn to_u32(index: usize, place: Place) -> Result<u32, ParseError> {
    u32::try_from(index).map_err(|_| {
        ParseError::new(
            place,
            format!("vertex index {index} is beyond 2^32"),
            "split the model into smaller parts",
        )
    })
}

/// Helpers shared by the readers' tests.
#[cfg(test)]
pub(crate) mod testing {
    use super::super::{MeshSoup, ParseError};

    /// The error a reader must give; panics with the soup if it reads fine.
    pub(crate) fn expect_err(result: Result<MeshSoup, ParseError>) -> ParseError {
        match result {
            Ok(soup) => panic!("expected an error, got {soup:?}"),
            Err(e) => e,
        }
    }

    /// One step of a xorshift generator: deterministic garbage without a dependency.
    pub(crate) fn xorshift(state: &mut u64) -> u64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        *state
    }

    /// Feeds every prefix of a valid input to a reader, which must return (Ok or Err)
    /// without panicking.
    pub(crate) fn read_every_prefix(read: impl Fn(&[u8]) -> Result<MeshSoup, ParseError>, bytes: &[u8]) {
        for end in 0..=bytes.len() {
            let _ = read(&bytes[..end]);
        }
    }
}
