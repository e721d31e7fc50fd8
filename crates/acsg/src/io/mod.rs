//! Reading part models from files: one submodule per format.
//!
//! Every reader is generic over [`std::io::Read`] and produces a [`MeshSoup`]: points
//! and polygons exactly as the file states them. Turning a soup into a validated
//! boundary representation is the job of [`crate::model::Part::try_new`].

use std::fmt;
use std::io::Read;
use std::path::{Path, PathBuf};

use glam::DVec3;

pub mod iges;
pub mod obj;
pub mod off;
mod planar;
pub mod ply;
pub mod step;
pub mod stl;
mod text;

/// Inputs larger than this are refused before they are read (1 GiB holds a binary STL
/// of about 21 million triangles).
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

/// How to read a model.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReadOptions {
    /// Read STEP cylinders, cones and circles as planar facets within this chord
    /// tolerance (millimetres); see [`step::read_faceted`]. Meshes are already facets;
    /// IGES curved entities are refused either way.
    pub facet_mm: Option<f64>,
}

/// Points and polygons as a file states them, before any validation of the solid.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshSoup {
    /// Point coordinates.
    pub positions: Vec<DVec3>,
    /// Polygons as indices into `positions`, counter-clockwise seen from outside.
    pub polygons: Vec<Vec<u32>>,
    /// For text formats, the 1-based line each polygon was read from.
    pub polygon_lines: Vec<Option<usize>>,
    /// What the format calls one polygon ("face", "triangle"), for messages.
    pub polygon_noun: &'static str,
}

impl MeshSoup {
    /// Names polygon `index` for a message: `face 12 (line 40)` or `triangle 3`.
    #[must_use]
    pub fn describe_polygon(&self, index: usize) -> String {
        let noun = if self.polygon_noun.is_empty() {
            "polygon"
        } else {
            self.polygon_noun
        };
        match self.polygon_lines.get(index).copied().flatten() {
            Some(line) => format!("{noun} {index} (line {line})"),
            None => format!("{noun} {index}"),
        }
    }
}

/// Where in an input a problem is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Place {
    /// A 1-based line of a text file.
    Line(usize),
    /// A byte offset into a binary file.
    Byte(u64),
    /// The file as a whole.
    Whole,
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Place::Line(line) => write!(f, "line {line}"),
            Place::Byte(offset) => write!(f, "byte {offset}"),
            Place::Whole => write!(f, "whole file"),
        }
    }
}

/// A problem found while parsing one input, before the path is known.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{place}: {problem} ({fix})")]
pub struct ParseError {
    /// Where the problem is.
    pub place: Place,
    /// What is wrong.
    pub problem: String,
    /// What the user can do about it.
    pub fix: String,
}

impl ParseError {
    /// A new parse error.
    pub fn new(place: Place, problem: impl Into<String>, fix: impl Into<String>) -> Self {
        Self {
            place,
            problem: problem.into(),
            fix: fix.into(),
        }
    }
}

/// The model formats read by this crate: meshes (OFF, OBJ, STL, PLY) and CAD B-reps
/// (STEP, IGES; planar faces only, coordinates converted to millimetres).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Object File Format (polygon faces).
    Off,
    /// Wavefront OBJ.
    Obj,
    /// STL, ASCII or binary.
    Stl,
    /// Stanford PLY, ASCII or binary.
    Ply,
    /// STEP (ISO 10303-21) AP203/AP214 B-rep with planar faces.
    Step,
    /// IGES B-rep (186) or trimmed-surface (144) form with planar faces.
    Iges,
}

impl Format {
    /// The format named by a path's extension, if any.
    #[must_use]
    pub fn from_extension(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "off" => Some(Format::Off),
            "obj" => Some(Format::Obj),
            "stl" => Some(Format::Stl),
            "ply" => Some(Format::Ply),
            "step" | "stp" | "p21" => Some(Format::Step),
            "igs" | "iges" => Some(Format::Iges),
            _ => None,
        }
    }

    /// The format a file's first bytes show, if they show one.
    #[must_use]
    pub fn sniff(head: &[u8]) -> Option<Format> {
        // Binary STL first: an 80-byte header, then a little-endian triangle count that
        // matches the length exactly (only trusted when the whole file is at hand). Its
        // header may start with "solid", and its bytes may look like OBJ lines.
        if head.len() >= 84 {
            let count = u64::from(u32::from_le_bytes([head[80], head[81], head[82], head[83]]));
            if 84 + 50 * count == head.len() as u64 {
                return Some(Format::Stl);
            }
        }
        let text = String::from_utf8_lossy(&head[..head.len().min(512)]);
        let first = text.trim_start_matches('\u{feff}').trim_start();
        if first.starts_with("ISO-10303-21") {
            return Some(Format::Step);
        }
        if iges::looks_like_iges(head) {
            return Some(Format::Iges);
        }
        let off_headers = ["OFF", "COFF", "NOFF", "CNOFF", "STOFF", "STCOFF"];
        if first.starts_with("ply") {
            Some(Format::Ply)
        } else if off_headers.iter().any(|h| first.starts_with(h)) {
            Some(Format::Off)
        } else if first.starts_with("solid") && text.contains("facet") {
            Some(Format::Stl)
        } else if text.lines().any(|l| {
            let l = l.trim_start();
            l.starts_with("v ") || l.starts_with("f ") || l.starts_with("o ") || l.starts_with("g ")
        }) {
            Some(Format::Obj)
        } else {
            None
        }
    }

    /// Parses a whole input of this format.
    ///
    /// # Errors
    /// A [`ParseError`] naming the place and the fix when the input is not valid.
    pub fn read(self, reader: impl Read) -> Result<MeshSoup, ParseError> {
        self.read_with(reader, &ReadOptions::default())
    }

    /// [`Format::read`] with options (faceting of STEP cylinders, cones and circles).
    ///
    /// # Errors
    /// A [`ParseError`] naming the place and the fix when the input is not valid.
    pub fn read_with(self, reader: impl Read, options: &ReadOptions) -> Result<MeshSoup, ParseError> {
        if let (Format::Step, Some(facet)) = (self, options.facet_mm) {
            return step::read_faceted(reader, Some(facet));
        }
        match self {
            Format::Off => off::read(reader),
            Format::Obj => obj::read(reader),
            Format::Stl => stl::read(reader),
            Format::Ply => ply::read(reader),
            Format::Step => step::read(reader),
            Format::Iges => iges::read(reader),
        }
    }
}

impl Format {
    /// `true` for the CAD formats (STEP, IGES), which state their length unit; their
    /// coordinates are read in millimetres.
    #[must_use]
    pub fn is_cad(self) -> bool {
        matches!(self, Format::Step | Format::Iges)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Off => "OFF",
            Format::Obj => "OBJ",
            Format::Stl => "STL",
            Format::Ply => "PLY",
            Format::Step => "STEP",
            Format::Iges => "IGES",
        })
    }
}

/// Errors of reading a model file.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file could not be opened or read.
    #[error("{path}: cannot read the file: {source} (check the path and its permissions)")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The file holds nothing.
    #[error("{path}: the file is empty (export the part again; a model needs at least 4 faces)")]
    Empty {
        /// The file.
        path: PathBuf,
    },
    /// The file is larger than [`MAX_INPUT_BYTES`] (or the limit set by
    /// `ACSG_MAX_INPUT_BYTES`, see [`max_input_bytes`]).
    #[error(
        "{path}: {}more than the {limit}-byte limit (simplify the mesh: coplanar triangles merge into one face anyway; a pipe or device must end within the limit)",
        .size.map(|s| format!("the file is {s} bytes, ")).unwrap_or_else(|| "the input is ".to_string())
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size, when the file system states it (not for pipes and devices).
        size: Option<u64>,
        /// The limit.
        limit: u64,
    },
    /// Neither the extension nor the content tells the format.
    #[error("{path}: unknown model format (use a .off, .obj, .stl, .ply, .step/.stp or .igs/.iges file)")]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The content is not valid for its format.
    #[error("{path}: {format} {detail}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// The format it was read as.
        format: Format,
        /// What is wrong, and where.
        detail: ParseError,
    },
}

/// Reads a model file, choosing the format by content, then by extension.
///
/// A file whose content clearly shows one format is read as that format even when its
/// extension names another, so a mislabelled file still reads.
///
/// # Errors
/// [`ReadError`] naming the file, the place and the fix.
pub fn read_path(path: &Path) -> Result<MeshSoup, ReadError> {
    read_path_as(path).map(|(soup, _)| soup)
}

/// [`read_path`], also telling the format the file was read as.
///
/// # Errors
/// [`ReadError`] naming the file, the place and the fix.
pub fn read_path_as(path: &Path) -> Result<(MeshSoup, Format), ReadError> {
    read_path_with(path, &ReadOptions::default())
}

/// [`read_path_as`] with options.
///
/// # Errors
/// [`ReadError`] naming the file, the place and the fix.
pub fn read_path_with(path: &Path, options: &ReadOptions) -> Result<(MeshSoup, Format), ReadError> {
    let io_err = |source| ReadError::Io {
        path: path.to_path_buf(),
        source,
    };
    let limit = max_input_bytes();
    let too_large = |size: Option<u64>| ReadError::TooLarge {
        path: path.to_path_buf(),
        size,
        limit,
    };
    let bytes = read_capped(path, limit).map_err(|e| match e {
        CappedReadError::Io(source) => io_err(source),
        CappedReadError::TooLarge(size) => too_large(size),
    })?;
    read_bytes_with(&bytes, path, options)
}

/// The input size limit: [`MAX_INPUT_BYTES`], or less when the environment variable
/// `ACSG_MAX_INPUT_BYTES` gives a smaller number of bytes (for small machines, and
/// for tests).
#[must_use]
pub fn max_input_bytes() -> u64 {
    std::env::var("ACSG_MAX_INPUT_BYTES")
        .ok()
        .and_then(|v| v.trim().parse::<u64>().ok())
        .map_or(MAX_INPUT_BYTES, |v| v.min(MAX_INPUT_BYTES))
}

/// Why [`read_capped`] failed.
#[derive(Debug)]
pub(crate) enum CappedReadError {
    /// The operating system's error.
    Io(std::io::Error),
    /// More than the limit; the size when the file system states it.
    TooLarge(Option<u64>),
}

/// Reads a whole file, refusing it as soon as more than `limit` bytes have been read:
/// the cap holds for pipes and devices (`/dev/zero`), whose reported size is 0.
///
/// # Errors
/// [`CappedReadError`].
pub(crate) fn read_capped(path: &Path, limit: u64) -> Result<Vec<u8>, CappedReadError> {
    let file = std::fs::File::open(path).map_err(CappedReadError::Io)?;
    let reported = file.metadata().ok().filter(std::fs::Metadata::is_file).map(|m| m.len());
    if let Some(size) = reported.filter(|&s| s > limit) {
        return Err(CappedReadError::TooLarge(Some(size)));
    }
    let mut bytes = Vec::with_capacity(reported.map_or(0, |s| usize::try_from(s).unwrap_or(0)));
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(CappedReadError::Io)?;
    if bytes.len() as u64 > limit {
        return Err(CappedReadError::TooLarge(None));
    }
    Ok(bytes)
}

/// Reads a model held in memory; `path` names it in messages and gives the extension.
///
/// # Errors
/// [`ReadError`] naming the file, the place and the fix.
pub fn read_bytes(bytes: &[u8], path: &Path) -> Result<MeshSoup, ReadError> {
    read_bytes_as(bytes, path).map(|(soup, _)| soup)
}

/// [`read_bytes`], also telling the format the bytes were read as.
///
/// # Errors
/// [`ReadError`] naming the file, the place and the fix.
pub fn read_bytes_as(bytes: &[u8], path: &Path) -> Result<(MeshSoup, Format), ReadError> {
    read_bytes_with(bytes, path, &ReadOptions::default())
}

/// [`read_bytes_as`] with options.
///
/// # Errors
/// [`ReadError`] naming the file, the place and the fix.
pub fn read_bytes_with(bytes: &[u8], path: &Path, options: &ReadOptions) -> Result<(MeshSoup, Format), ReadError> {
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(ReadError::Empty {
            path: path.to_path_buf(),
        });
    }
    let format = Format::sniff(bytes)
        .or_else(|| Format::from_extension(path))
        .ok_or_else(|| ReadError::UnknownFormat {
            path: path.to_path_buf(),
        })?;
    let soup = format.read_with(bytes, options).map_err(|detail| ReadError::Parse {
        path: path.to_path_buf(),
        format,
        detail,
    })?;
    Ok((soup, format))
}

/// Checks that a coordinate triple read from `place` is finite.
///
/// # Errors
/// A [`ParseError`] for NaN or infinite coordinates.
pub(crate) fn finite_point(p: [f64; 3], place: Place) -> Result<DVec3, ParseError> {
    if p.iter().all(|c| c.is_finite()) {
        Ok(DVec3::from_array(p))
    } else {
        Err(ParseError::new(
            place,
            format!("the point ({}, {}, {}) is not finite", p[0], p[1], p[2]),
            "every coordinate must be a finite number; re-export the model",
        ))
    }
}

/// The marker in the names of [`write_atomic`]'s temporary files:
/// `.NAME.acsg-partial.PID.tmp` beside `NAME`.
pub const PARTIAL_MARKER: &str = "acsg-partial";

/// Writes a file atomically: the bytes go to a temporary file in the same folder, which
/// then replaces `path` in one rename, so a reader never sees a half-written file and an
/// existing file survives a failed write.
///
/// - A symbolic link is followed: its target is replaced, the link stays.
/// - A special file (`/dev/null`, a named pipe, a terminal) is written directly: it
///   cannot be replaced, and a rename would turn it into a regular file.
/// - A replaced file keeps its permissions.
/// - The temporary file is named `.NAME.acsg-partial.PID.tmp`; one left by a run that
///   was killed between write and rename (its process is gone) is removed by the next
///   write of `NAME`.
///
/// # Errors
/// The operating system's error, with the path in the message.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let with_path = |e: std::io::Error| std::io::Error::new(e.kind(), format!("{}: {e}", path.display()));
    let target = follow_links(path).map_err(with_path)?;
    let existing = std::fs::metadata(&target).ok();
    if existing.as_ref().is_some_and(|m| !m.is_file() && !m.is_dir()) {
        use std::io::Write;
        let mut file = std::fs::OpenOptions::new()
            .write(true)
            .truncate(true)
            .open(&target)
            .map_err(with_path)?;
        return file.write_all(bytes).and_then(|()| file.flush()).map_err(with_path);
    }
    replace_file(&target, bytes, existing.map(|m| m.permissions())).map_err(with_path)
}

/// The file a path names after following symbolic links (at most 40, as the kernel
/// does); a dangling link gives the path it points to, which is then created.
fn follow_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut current = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&current) {
            Ok(m) if m.file_type().is_symlink() => {
                let link = std::fs::read_link(&current)?;
                current = match current.parent() {
                    Some(parent) if link.is_relative() => parent.join(link),
                    _ => link,
                };
            }
            _ => return Ok(current),
        }
    }
    Err(std::io::Error::other("too many levels of symbolic links"))
}

/// Writes `bytes` to a temporary file beside `path` and renames it over `path`.
fn replace_file(path: &Path, bytes: &[u8], permissions: Option<std::fs::Permissions>) -> std::io::Result<()> {
    use std::io::Write;
    let file_name = path
        .file_name()
        .ok_or_else(|| std::io::Error::other("not a file name"))?
        .to_string_lossy()
        .into_owned();
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    remove_stale_partials(&folder, &file_name);
    let pid = std::process::id();
    let mut temporary = folder.join(format!(".{file_name}.{PARTIAL_MARKER}.{pid}.tmp"));
    let mut attempt = 0;
    while temporary.exists() {
        attempt += 1;
        temporary = folder.join(format!(".{file_name}.{PARTIAL_MARKER}.{pid}.{attempt}.tmp"));
    }
    let result = (|| {
        let mut file = std::fs::File::create(&temporary)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        if let Some(permissions) = permissions {
            std::fs::set_permissions(&temporary, permissions)?;
        }
        std::fs::rename(&temporary, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

/// Removes the temporary files of earlier writes of `file_name` in `folder` whose
/// process no longer runs (killed between write and rename). Only where processes can
/// be seen (`/proc`); elsewhere the files stay, named so that a user knows them.
fn remove_stale_partials(folder: &Path, file_name: &str) {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return;
    }
    let prefix = format!(".{file_name}.{PARTIAL_MARKER}.");
    let Ok(entries) = std::fs::read_dir(folder) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(rest) = name.to_str().and_then(|n| n.strip_prefix(&prefix)) else {
            continue;
        };
        let Some(pid) = rest.strip_suffix(".tmp").and_then(|r| r.split('.').next()) else {
            continue;
        };
        let alive = pid.parse::<u32>().is_ok_and(|pid| proc.join(pid.to_string()).exists());
        let is_file = entry.file_type().is_ok_and(|t| t.is_file());
        if !alive && is_file {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}
