//! Task files: the two parts, the misalignment bounds and the options of one run, in
//! TOML.
//!
//! ```toml
//! fixed = "l_block.off"          # relative to the task file
//! moving = "box.off"
//! units = "mm"                   # optional: mm, cm, m or in (see acsg::units)
//! facet = 0.05                   # optional: read STEP cylinders, cones, circles as facets
//!
//! [bounds]                       # [min, max]; lengths in `units`, angles in degrees (±180)
//! x = [-5, 5]
//! y = [-5, 5]
//! z = [0, 240]
//! rx = [-18, 18]
//! ry = [-18, 18]
//! rz = [-18, 18]
//!
//! [options]                      # optional
//! degenerate = false             # keep states with a degenerate contact
//! threads = 0                    # 0: one per core
//! effort = 1                     # search and proof budget, a multiple of the default
//! strategy = "full"              # or "paper": the paper's algorithm, as a baseline
//! work_limit = 5000000           # stop searching after this much work (no limit if absent)
//! assembled = [0, 0, 0, 0, 0, 0] # G as x, y, z, rx, ry, rz (degrees)
//! ```

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::graph::{Options, Strategy};
use crate::pose::{Bounds, Pose, PoseError};
use crate::units::LengthUnit;

/// What can go wrong with a task file or a bounds specification.
#[derive(Debug, thiserror::Error)]
pub enum TaskError {
    /// The task file could not be read.
    #[error("{path}: cannot read the task file: {source} (check the path)")]
    Io {
        /// The task file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The TOML is malformed or has a wrong, missing or unknown key.
    #[error("{path}:{line}:{column}: {message} (see `acsg run --help` for the task file format)")]
    Syntax {
        /// The task file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// The bounds or the assembled pose are invalid.
    #[error("{place}: {source} (each bound is [min, max] with min <= max, finite numbers)")]
    Bounds {
        /// The task file and table, or the option that gave the bounds.
        place: String,
        /// The problems found.
        source: PoseError,
    },
    /// A `--bounds` specification is malformed.
    #[error(
        "--bounds: {0} (write e.g. x=-5:5,y=-5:5,z=0:240,rx=-18:18,ry=-18:18,rz=-18:18; angles in degrees, omitted components fixed at 0)"
    )]
    Spec(String),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TaskFile {
    fixed: String,
    moving: String,
    #[serde(default)]
    units: Option<LengthUnit>,
    #[serde(default)]
    facet: Option<toml::Spanned<f64>>,
    bounds: BoundsTable,
    #[serde(default)]
    options: OptionsTable,
}

/// A TOML array with where it was written (arrays are read whole and their length
/// checked, so that `[-1, 0, 1]` for a bound is refused rather than cut).
type Numbers = toml::Spanned<Vec<f64>>;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BoundsTable {
    x: Numbers,
    y: Numbers,
    z: Numbers,
    rx: Numbers,
    ry: Numbers,
    rz: Numbers,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct OptionsTable {
    #[serde(default)]
    degenerate: bool,
    #[serde(default)]
    threads: Option<toml::Spanned<usize>>,
    #[serde(default = "default_effort")]
    effort: u32,
    #[serde(default)]
    strategy: Strategy,
    #[serde(default)]
    work_limit: Option<toml::Spanned<u64>>,
    assembled: Option<Numbers>,
}

/// The most worker threads a run may ask for: four per core, at least 256. More only
/// slows the machine down (each thread holds a stack; the work does not grow).
#[must_use]
pub fn max_threads() -> usize {
    let cores = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
    (4 * cores).max(256)
}

/// Checks a thread count given by the user.
///
/// # Errors
/// A message naming the limit when `threads` exceeds [`max_threads`].
pub fn check_threads(threads: usize) -> Result<(), String> {
    let limit = max_threads();
    if threads > limit {
        let cores = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
        Err(format!(
            "{threads} threads is more than the limit of {limit} (this machine has {cores} cores; \
             give 0 for one thread per core)"
        ))
    } else {
        Ok(())
    }
}

fn default_effort() -> u32 {
    1
}

/// A run to do: what the task file says, with the part paths resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct Task {
    /// The fixed part's path as written in the task file.
    pub fixed_given: String,
    /// The moving part's path as written.
    pub moving_given: String,
    /// The fixed part's path, relative to the task file's folder.
    pub fixed: PathBuf,
    /// The moving part's path, resolved likewise.
    pub moving: PathBuf,
    /// The length unit of the run, if the task file gives one (`units = "mm"`).
    pub units: Option<LengthUnit>,
    /// The chord tolerance for reading STEP cylinders, cones and circles as facets
    /// (`facet = 0.05`, in `units`), if given.
    pub facet: Option<f64>,
    /// The bounds (radians inside).
    pub bounds: Bounds,
    /// The options.
    pub options: Options,
}

impl Task {
    /// Reads a task file.
    ///
    /// # Errors
    /// [`TaskError`] naming the file, line and column, and what to write instead.
    pub fn from_path(path: &Path) -> Result<Task, TaskError> {
        let io = |source| TaskError::Io {
            path: path.to_path_buf(),
            source,
        };
        let bytes = crate::io::read_capped(path, crate::io::max_input_bytes()).map_err(|e| match e {
            crate::io::CappedReadError::Io(source) => io(source),
            crate::io::CappedReadError::TooLarge(_) => io(std::io::Error::other(
                "it is larger than the input limit, and a task file is a few lines",
            )),
        })?;
        let text = String::from_utf8(bytes).map_err(|_| {
            io(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                "it is not UTF-8 text (save it as UTF-8)",
            ))
        })?;
        let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
        let folder = path.parent().unwrap_or(Path::new(""));
        Task::parse(text, path, folder)
    }

    /// Parses a task from its text; `path` names it in messages, part paths are taken
    /// relative to `folder`.
    ///
    /// ```
    /// use std::path::Path;
    /// let text = "fixed = \"a.off\"\nmoving = \"b.off\"\n[bounds]\nx = [-1, 1]\ny = [-1, 1]\n\
    ///             z = [0, 5]\nrx = [-10, 10]\nry = [-10, 10]\nrz = [0, 0]\n";
    /// let task = acsg::task::Task::parse(text, Path::new("t.toml"), Path::new("parts")).unwrap();
    /// assert_eq!(task.fixed, Path::new("parts/a.off"));
    /// assert!((task.bounds.max.rx - 10f64.to_radians()).abs() < 1e-15);
    /// ```
    ///
    /// # Errors
    /// [`TaskError::Syntax`] for malformed TOML or wrong keys, [`TaskError::Bounds`] for
    /// inverted or non-finite bounds.
    pub fn parse(text: &str, path: &Path, folder: &Path) -> Result<Task, TaskError> {
        let file: TaskFile = toml::from_str(text).map_err(|e| {
            let (line, column) = e.span().map_or((1, 1), |s| line_column(text, s.start));
            TaskError::Syntax {
                path: path.to_path_buf(),
                line,
                column,
                message: e.message().trim().to_string(),
            }
        })?;
        let at = |span: std::ops::Range<usize>, message: String| {
            let (line, column) = line_column(text, span.start);
            TaskError::Syntax {
                path: path.to_path_buf(),
                line,
                column,
                message,
            }
        };
        let b = &file.bounds;
        let mut pairs = [[0.0; 2]; 6];
        for ((pair, value), name) in pairs
            .iter_mut()
            .zip([&b.x, &b.y, &b.z, &b.rx, &b.ry, &b.rz])
            .zip(["x", "y", "z", "rx", "ry", "rz"])
        {
            match value.get_ref().as_slice() {
                &[lo, hi] => *pair = [lo, hi],
                other => {
                    return Err(at(
                        value.span(),
                        format!(
                            "[bounds] {name} has {} values; give two, [min, max] (a fixed component is [v, v])",
                            other.len()
                        ),
                    ));
                }
            }
        }
        let bounds =
            Bounds::from_degrees(pairs.map(|p| p[0]), pairs.map(|p| p[1])).map_err(|source| TaskError::Bounds {
                place: format!("{}: [bounds]", path.display()),
                source,
            })?;
        let facet = match &file.facet {
            Some(f) if !(f.get_ref().is_finite() && *f.get_ref() > 0.0) => {
                return Err(at(
                    f.span(),
                    format!(
                        "facet = {} (give the chord tolerance as a positive length)",
                        f.get_ref()
                    ),
                ));
            }
            Some(f) => Some(*f.get_ref()),
            None => None,
        };
        let threads = match &file.options.threads {
            Some(t) => {
                check_threads(*t.get_ref()).map_err(|m| at(t.span(), format!("[options] threads: {m}")))?;
                *t.get_ref()
            }
            None => 0,
        };
        let mut options = Options {
            degenerate: file.options.degenerate,
            threads,
            effort: file.options.effort.max(1),
            strategy: file.options.strategy,
            work_limit: file.options.work_limit.as_ref().map(|w| *w.get_ref()),
            ..Options::default()
        };
        if let Some(w) = file.options.work_limit.as_ref().filter(|w| *w.get_ref() == 0) {
            return Err(at(
                w.span(),
                "[options] work_limit = 0; give the most work the run may do, at least 1 (boxes of poses), or leave \
                 the key out for no limit"
                    .to_string(),
            ));
        }
        if let Some(g) = &file.options.assembled {
            if g.get_ref().len() != 6 {
                return Err(at(
                    g.span(),
                    format!(
                        "[options] assembled has {} values; give six, [x, y, z, rx, ry, rz] (angles in degrees)",
                        g.get_ref().len()
                    ),
                ));
            }
            let place = format!("{}: [options] assembled", path.display());
            let text = g.get_ref().iter().map(|v| v.to_string()).collect::<Vec<_>>().join(",");
            let pose = Pose::parse_checked(&text, true).map_err(|source| TaskError::Bounds {
                place: place.clone(),
                source,
            })?;
            options.assembled = pose.to_affine(&glam::DAffine3::IDENTITY);
        }
        Ok(Task {
            fixed: folder.join(&file.fixed),
            moving: folder.join(&file.moving),
            fixed_given: file.fixed,
            moving_given: file.moving,
            units: file.units,
            facet,
            bounds,
            options,
        })
    }
}

/// 1-based line and column of a byte offset.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// Bounds from a command-line specification such as
/// `x=-5:5,y=-5:5,z=0:240,rx=-18:18,ry=-18:18,rz=-18:18` (angles in degrees); omitted
/// components are fixed at 0.
///
/// ```
/// let b = acsg::task::bounds_from_spec("x=-1:1,z=0:5,rz=-90:90").unwrap();
/// assert_eq!((b.min.y, b.max.y), (0.0, 0.0));
/// assert!((b.max.rz - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// assert!(acsg::task::bounds_from_spec("x=1:-1").is_err());
/// ```
///
/// # Errors
/// [`TaskError::Spec`] for malformed text, [`TaskError::Bounds`] for inverted or
/// non-finite values.
pub fn bounds_from_spec(spec: &str) -> Result<Bounds, TaskError> {
    const NAMES: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];
    let (mut min, mut max) = ([0.0; 6], [0.0; 6]);
    let mut given = [false; 6];
    for item in spec.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (name, range) = item
            .split_once('=')
            .ok_or_else(|| TaskError::Spec(format!("'{item}' has no '='")))?;
        let k = NAMES
            .iter()
            .position(|n| *n == name.trim())
            .ok_or_else(|| TaskError::Spec(format!("unknown component '{}'", name.trim())))?;
        if given[k] {
            return Err(TaskError::Spec(format!("{} is given twice", NAMES[k])));
        }
        given[k] = true;
        let (lo, hi) = range
            .split_once(':')
            .ok_or_else(|| TaskError::Spec(format!("'{item}': write the range as min:max")))?;
        let number = |t: &str| {
            t.trim()
                .parse::<f64>()
                .map_err(|_| TaskError::Spec(format!("'{}' in '{item}' is not a number", t.trim())))
        };
        (min[k], max[k]) = (number(lo)?, number(hi)?);
    }
    if !given.iter().any(|g| *g) {
        return Err(TaskError::Spec("no component given".into()));
    }
    Bounds::from_degrees(min, max).map_err(|source| TaskError::Bounds {
        place: "--bounds".into(),
        source,
    })
}
