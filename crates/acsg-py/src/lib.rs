//! `acsg._acsg`: the extension module under the Python package `acsg`
//! (`python/acsg/__init__.py`), a thin layer over the library's public API.
//!
//! Values cross the boundary as plain numbers, lists and JSON text (the graph's JSON
//! document, `schema/graph.schema.json`); the Python package turns them into objects
//! and numpy arrays. Errors become Python exceptions carrying the library's messages:
//! [`AcsgError`] for parts and graph files, `ValueError` for bad bounds, poses and
//! options. Nothing here panics on user data; a run interrupted by Ctrl-C unwinds out
//! of the generator (see [`Interrupted`]) and is caught before it reaches Python.

use std::panic::AssertUnwindSafe;
use std::path::PathBuf;
use std::sync::Mutex;

use acsg::contact::{ContactRecord, ContactScene};
use acsg::export::GraphFile;
use acsg::graph::{Document, Options, Progress, generate_with_progress};
use acsg::io::{Format, MeshSoup};
use acsg::model::{Part as LibPart, PartElements};
use acsg::pose::{Bounds, Pose};
use acsg::units::LengthUnit;
use glam::{DAffine3, DMat3, DVec3};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyKeyboardInterrupt, PyValueError};
use pyo3::prelude::*;

// Named `acsg.AcsgError` (where the package exports it), so that it pickles: Ray and
// multiprocessing carry it between processes.
create_exception!(
    acsg,
    AcsgError,
    PyException,
    "An input acsg cannot use: a part that cannot be read or is not a valid solid, a graph file that \
     cannot be read. The message names the file, the place and the fix."
);

/// A validated part: the exact boundary representation of one polyhedral solid.
#[pyclass(frozen, name = "Part", module = "acsg")]
struct Part {
    part: LibPart,
    /// The length unit given when it was read, if any.
    unit: Option<LengthUnit>,
    /// Whether it was read from a CAD file (STEP, IGES: millimetres unless told).
    cad: bool,
    /// The chord tolerance its curved STEP faces were faceted with, if any.
    facet: Option<f64>,
}

fn parse_unit(units: Option<&str>) -> PyResult<Option<LengthUnit>> {
    units
        .map(|u| {
            u.parse::<LengthUnit>()
                .map_err(|e| PyValueError::new_err(format!("invalid units: {e}")))
        })
        .transpose()
}

#[pymethods]
impl Part {
    /// Reads a part from a model file (OFF, OBJ, STL, PLY, or STEP/IGES with planar
    /// faces); `units` (mm, cm, m, in) as the CLI's `--units`, `facet` as `--facet`.
    #[staticmethod]
    #[pyo3(signature = (path, units=None, facet=None))]
    fn from_path(py: Python<'_>, path: PathBuf, units: Option<&str>, facet: Option<f64>) -> PyResult<Part> {
        let unit = parse_unit(units)?;
        if let Some(f) = facet.filter(|f| !(f.is_finite() && *f > 0.0)) {
            return Err(PyValueError::new_err(format!(
                "invalid facet: {f} (give the chord tolerance as a positive length, e.g. 0.05)"
            )));
        }
        let (part, format) = py
            .detach(|| LibPart::from_path_with(&path, unit, facet))
            .map_err(|e| AcsgError::new_err(e.to_string()))?;
        Ok(Part {
            part,
            unit,
            cad: format.is_cad(),
            facet,
        })
    }

    /// Builds a part from vertex coordinates and polygons (indices into `vertices`,
    /// counter-clockwise seen from outside); `name` labels it in messages and outputs.
    #[staticmethod]
    #[pyo3(signature = (vertices, faces, name="mesh".to_string(), units=None))]
    fn from_arrays(
        py: Python<'_>,
        vertices: Vec<[f64; 3]>,
        faces: Vec<Vec<u32>>,
        name: String,
        units: Option<&str>,
    ) -> PyResult<Part> {
        let unit = parse_unit(units)?;
        let soup = MeshSoup {
            positions: vertices.into_iter().map(DVec3::from_array).collect(),
            polygon_lines: vec![None; faces.len()],
            polygons: faces,
            polygon_noun: "face",
        };
        let part = py
            .detach(|| LibPart::try_new(&soup, &name))
            .map_err(|e| AcsgError::new_err(e.to_string()))?;
        Ok(Part {
            part,
            unit,
            cad: false,
            facet: None,
        })
    }

    /// The part's name (its path as given, or the name given to `from_arrays`).
    #[getter]
    fn name(&self) -> &str {
        self.part.name()
    }

    /// The number of vertices, edges and faces of the B-rep.
    #[getter]
    fn counts(&self) -> (usize, usize, usize) {
        (
            self.part.vertices().len(),
            self.part.edges().len(),
            self.part.faces().len(),
        )
    }

    /// The part's volume.
    #[getter]
    fn volume(&self) -> f64 {
        self.part.volume()
    }

    /// The elements with geometry, as the graph's JSON writes them (JSON text).
    fn elements_json(&self) -> String {
        serde_json::to_string(&PartElements::of(&self.part)).unwrap_or_default()
    }

    fn __repr__(&self) -> String {
        let (v, e, f) = self.counts();
        format!("<acsg.Part {:?}: {f} faces, {e} edges, {v} vertices>", self.part.name())
    }
}

/// The label of a run's lengths, as the CLI gives it: the unit given, else `mm` when
/// both parts are CAD files, else "model units".
fn length_label(fixed: &Part, moving: &Part) -> String {
    match fixed.unit.or(moving.unit) {
        Some(unit) => unit.symbol().to_string(),
        None if fixed.cad && moving.cad => LengthUnit::Mm.symbol().to_string(),
        None => acsg::units::UNSPECIFIED.to_string(),
    }
}

/// A placement from 6 values (x, y, z, rx, ry, rz; angles in degrees when `degrees`)
/// or 16 (a row-major 4x4 rigid transform), checked as the CLI checks `--pose`.
fn placement(values: &[f64], degrees: bool, what: &str) -> PyResult<DAffine3> {
    let bad = |e: &dyn std::fmt::Display| PyValueError::new_err(format!("invalid {what}: {e}"));
    match values.len() {
        6 => {
            let text: Vec<String> = values.iter().map(f64::to_string).collect();
            let pose = Pose::parse_checked(&text.join(","), degrees).map_err(|e| bad(&e))?;
            Ok(pose.to_affine(&DAffine3::IDENTITY))
        }
        16 => {
            let m = |r: usize, c: usize| values[4 * r + c];
            let last = [m(3, 0), m(3, 1), m(3, 2), m(3, 3)];
            if last != [0.0, 0.0, 0.0, 1.0] {
                return Err(bad(&format!(
                    "the last row of a 4x4 transform must be 0 0 0 1, not {last:?}"
                )));
            }
            let transform = DAffine3::from_mat3_translation(
                DMat3::from_cols_array(&[
                    m(0, 0),
                    m(1, 0),
                    m(2, 0),
                    m(0, 1),
                    m(1, 1),
                    m(2, 1),
                    m(0, 2),
                    m(1, 2),
                    m(2, 2),
                ]),
                DVec3::new(m(0, 3), m(1, 3), m(2, 3)),
            );
            // Checks that it is rigid (finite, orthonormal, no reflection).
            Pose::from_affine(&transform, &DAffine3::IDENTITY).map_err(|e| bad(&e))?;
            Ok(transform)
        }
        n => Err(bad(&format!(
            "expected 6 values (x, y, z, rx, ry, rz) or a 4x4 matrix, got {n} values"
        ))),
    }
}

/// The payload of the unwind that stops a run when Python has a signal pending
/// (Ctrl-C): raised with `resume_unwind` (no panic message) from the progress
/// callback, which the generator calls from the calling thread between batches, and
/// caught by [`generate`] before it returns to Python.
struct Interrupted;

/// Generates the contact state graph; returns the graph's JSON document.
///
/// `bounds_min`, `bounds_max`: x, y, z, rx, ry, rz (angles in degrees when `degrees`);
/// `assembled`: 6 values in the same units, or a 4x4 matrix as 16 values; `progress`:
/// called as `progress(stage, done, total, states)` between batches of searches;
/// `strategy`: "full" (the default) or "paper" (the paper's algorithm, a baseline);
/// `work_limit`: stop searching and proving after this much work (boxes of poses, a local
/// optimisation counting as 50), leaving the candidates met after it undecided.
#[pyfunction]
#[pyo3(signature = (fixed, moving, bounds_min, bounds_max, degrees=true, degenerate=false, assembled=None,
                    threads=None, effort=None, progress=None, names=None, strategy=None, work_limit=None))]
#[allow(clippy::too_many_arguments)]
fn generate(
    py: Python<'_>,
    fixed: &Part,
    moving: &Part,
    bounds_min: [f64; 6],
    bounds_max: [f64; 6],
    degrees: bool,
    degenerate: bool,
    assembled: Option<Vec<f64>>,
    threads: Option<usize>,
    effort: Option<u32>,
    progress: Option<Py<PyAny>>,
    names: Option<(String, String)>,
    strategy: Option<String>,
    work_limit: Option<u64>,
) -> PyResult<String> {
    let bounds = if degrees {
        Bounds::from_degrees(bounds_min, bounds_max)
    } else {
        Bounds::try_new(bounds_min, bounds_max)
    }
    .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let mut options = Options {
        degenerate,
        ..Options::default()
    };
    if let Some(values) = assembled {
        options.assembled = placement(&values, degrees, "assembled pose")?;
    }
    if let Some(threads) = threads {
        acsg::task::check_threads(threads).map_err(|m| PyValueError::new_err(format!("invalid threads: {m}")))?;
        options.threads = threads;
    }
    if let Some(effort) = effort {
        if !(1..=1000).contains(&effort) {
            return Err(PyValueError::new_err(format!(
                "invalid effort: {effort} (give a multiple of the default budget from 1 to 1000)"
            )));
        }
        options.effort = effort;
    }
    if work_limit == Some(0) {
        return Err(PyValueError::new_err(
            "invalid work_limit: 0 (give the most work the run may do, in boxes of poses, at least 1; or None for no limit)",
        ));
    }
    options.work_limit = work_limit;
    if let Some(name) = strategy {
        options.strategy = name.parse().map_err(|e: acsg::graph::strategy::UnknownStrategy| {
            PyValueError::new_err(format!("invalid strategy: {e}"))
        })?;
    }
    // The first error the callback raised (or the pending signal's), raised at the end.
    let failure: Mutex<Option<PyErr>> = Mutex::new(None);
    let report = |p: Progress| {
        let stop = Python::attach(|py| {
            let outcome = py.check_signals().and_then(|()| match &progress {
                Some(callback) => callback.call1(py, (p.stage, p.done, p.total, p.states)).map(drop),
                None => Ok(()),
            });
            match outcome {
                Ok(()) => false,
                Err(err) => {
                    if let Ok(mut slot) = failure.lock() {
                        slot.get_or_insert(err);
                    }
                    true
                }
            }
        });
        if stop {
            std::panic::resume_unwind(Box::new(Interrupted));
        }
    };
    let run = py.detach(|| {
        std::panic::catch_unwind(AssertUnwindSafe(|| {
            generate_with_progress(&fixed.part, &moving.part, &bounds, &options, &report)
        }))
    });
    let graph = match run {
        Ok(graph) => graph,
        Err(payload) if payload.is::<Interrupted>() => {
            let err = failure.lock().ok().and_then(|mut slot| slot.take());
            return Err(err.unwrap_or_else(|| PyKeyboardInterrupt::new_err("generation interrupted")));
        }
        Err(payload) => {
            let message = payload
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| payload.downcast_ref::<&str>().copied())
                .unwrap_or("unknown panic");
            return Err(PyException::new_err(format!(
                "internal error in acsg (please report it): {message}"
            )));
        }
    };
    let names = names.unwrap_or_else(|| (fixed.part.name().to_string(), moving.part.name().to_string()));
    let mut document = Document::new(
        &graph,
        &fixed.part,
        &moving.part,
        &bounds,
        &options,
        [&names.0, &names.1],
    );
    document.units.length = length_label(fixed, moving);
    document.facet = fixed.facet.or(moving.facet);
    Ok(document.to_json())
}

/// The JSON of [`contacts`].
#[derive(serde::Serialize)]
struct ContactsDocument {
    matrix: [[f64; 4]; 4],
    tolerance: f64,
    contacts: Vec<ContactRecord>,
    penetration: f64,
    min_gap: Option<f64>,
}

/// P(X): the principal contacts at one placement of the moving part, with the
/// penetration depth and the smallest gap (JSON text).
///
/// `pose`: 6 values (angles in degrees when `degrees`) applied after `assembled`, or a
/// 4x4 matrix (16 values, row-major) placing the moving part in the fixed part's frame
/// (then `assembled` is not used); `tol`: the contact tolerance relative to L.
#[pyfunction]
#[pyo3(signature = (fixed, moving, pose, degrees=true, assembled=None, tol=acsg::tolerance::CONTACT_REL))]
fn contacts(
    py: Python<'_>,
    fixed: &Part,
    moving: &Part,
    pose: Vec<f64>,
    degrees: bool,
    assembled: Option<Vec<f64>>,
    tol: f64,
) -> PyResult<String> {
    if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
        return Err(PyValueError::new_err(format!(
            "invalid tol: {tol} (give a relative tolerance between 0 and 1, e.g. 1e-9)"
        )));
    }
    let g = match assembled {
        Some(values) => placement(&values, degrees, "assembled pose")?,
        None => DAffine3::IDENTITY,
    };
    let local = placement(&pose, degrees, "pose")?;
    let transform = if pose.len() == 16 { local } else { g * local };
    let report = py.detach(|| ContactScene::new(&fixed.part, &moving.part).evaluate(&transform, tol));
    let mut matrix = [[0.0; 4]; 4];
    let cols = transform.to_cols_array_2d();
    for (c, col) in cols.iter().enumerate() {
        for (r, value) in col.iter().enumerate() {
            matrix[r][c] = *value;
        }
    }
    matrix[3] = [0.0, 0.0, 0.0, 1.0];
    let document = ContactsDocument {
        matrix,
        tolerance: report.tolerance,
        contacts: report
            .contacts
            .iter()
            .map(|c| ContactRecord::of(c, &fixed.part, &moving.part))
            .collect(),
        penetration: report.penetration,
        min_gap: report.min_gap,
    };
    serde_json::to_string(&document).map_err(|e| PyException::new_err(format!("internal error: {e}")))
}

/// Reads and checks a graph's JSON file (the Python side keeps the text as read:
/// parsing and writing again could change the last digit of a number).
#[pyfunction]
fn check_graph_file(py: Python<'_>, path: PathBuf) -> PyResult<()> {
    py.detach(|| GraphFile::from_path(&path).map(drop))
        .map_err(|e| AcsgError::new_err(e.to_string()))
}

/// Checks a graph's JSON text (`name` labels it in messages).
#[pyfunction]
#[pyo3(signature = (text, name="<string>"))]
fn check_graph(text: &str, name: &str) -> PyResult<()> {
    GraphFile::from_json(text, name)
        .map(drop)
        .map_err(|e| AcsgError::new_err(e.to_string()))
}

/// Writes text to a file atomically (a temporary file renamed over it).
#[pyfunction]
fn write_atomic(path: PathBuf, text: &str) -> PyResult<()> {
    acsg::io::write_atomic(&path, text.as_bytes())
        .map_err(|e| AcsgError::new_err(format!("{}: cannot write: {e}", path.display())))
}

/// The formats a part can be read from, by extension.
#[pyfunction]
fn formats() -> Vec<String> {
    ["off", "obj", "stl", "ply", "step", "stp", "igs", "iges"]
        .iter()
        .filter(|ext| Format::from_extension(std::path::Path::new(&format!("x.{ext}"))).is_some())
        .map(|ext| (*ext).to_string())
        .collect()
}

/// The extension module of the `acsg` Python package.
#[pymodule]
fn _acsg(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("AcsgError", m.py().get_type::<AcsgError>())?;
    m.add("CONTACT_REL", acsg::tolerance::CONTACT_REL)?;
    m.add_class::<Part>()?;
    m.add_function(wrap_pyfunction!(generate, m)?)?;
    m.add_function(wrap_pyfunction!(contacts, m)?)?;
    m.add_function(wrap_pyfunction!(check_graph_file, m)?)?;
    m.add_function(wrap_pyfunction!(check_graph, m)?)?;
    m.add_function(wrap_pyfunction!(write_atomic, m)?)?;
    m.add_function(wrap_pyfunction!(formats, m)?)?;
    Ok(())
}
