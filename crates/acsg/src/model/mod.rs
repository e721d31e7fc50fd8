//! Part models: the validated boundary representation of one polyhedral solid.

mod elements;
mod ids;
mod part;
mod summary;
pub mod validation;

use std::path::Path;

pub use elements::PartElements;
pub use ids::{EdgeId, ElementId, FaceId, VertexId};
pub use part::{Aabb, Edge, Face, Loop, Part, Vertex};
pub use summary::{Inspection, PartSummary, PpcTotals};
pub use validation::{Defect, DefectKind, ValidationReport};

use crate::io::{Format, MeshSoup, ReadError};
use crate::units::LengthUnit;

/// Errors of loading a part.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The file could not be read or parsed.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The file was read, but does not describe a valid solid.
    #[error("{name}: not a valid solid:\n{report}")]
    Invalid {
        /// The part's name (its path).
        name: String,
        /// Everything wrong with it.
        report: ValidationReport,
    },
}

impl ModelError {
    /// The validation report, when the model was read but is invalid.
    #[must_use]
    pub fn report(&self) -> Option<&ValidationReport> {
        match self {
            ModelError::Invalid { report, .. } => Some(report),
            ModelError::Read(_) => None,
        }
    }
}

impl Part {
    /// Builds and validates a part from a soup; `name` labels it in messages.
    ///
    /// ```
    /// use acsg::io::MeshSoup;
    /// use acsg::model::Part;
    /// use glam::DVec3;
    ///
    /// // A unit tetrahedron, outward winding.
    /// let soup = MeshSoup {
    ///     positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z],
    ///     polygons: vec![vec![0, 2, 1], vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]],
    ///     ..Default::default()
    /// };
    /// let part = Part::try_new(&soup, "tetra").unwrap();
    /// assert_eq!((part.faces().len(), part.edges().len(), part.vertices().len()), (4, 6, 4));
    /// assert!((part.volume() - 1.0 / 6.0).abs() < 1e-12);
    /// ```
    ///
    /// # Errors
    /// [`ModelError::Invalid`] with a report of every defect found.
    pub fn try_new(soup: &MeshSoup, name: &str) -> Result<Part, ModelError> {
        let invalid = |report| ModelError::Invalid {
            name: name.to_string(),
            report,
        };
        let brep = crate::topology::build(soup).map_err(invalid)?;
        let mut part = Part {
            name: name.to_string(),
            vertices: brep.vertices,
            edges: brep.edges,
            faces: brep.faces,
            pieces: Vec::new(),
            bounds: brep.bounds,
            volume: brep.volume,
        };
        part.pieces = crate::convex::decompose(&part);
        Ok(part)
    }

    /// Reads, builds and validates a part from a model file.
    ///
    /// # Errors
    /// [`ModelError`] naming the file, the place and the fix.
    pub fn from_path(path: &Path) -> Result<Part, ModelError> {
        let soup: MeshSoup = crate::io::read_path(path)?;
        Part::try_new(&soup, &path.display().to_string())
    }

    /// Reads a part for a run in `unit` (see [`crate::units`]): a CAD file (STEP,
    /// IGES), which states its unit, is converted to `unit` (millimetres when `None`);
    /// a mesh's numbers are taken as they are, in `unit`. Also returns the format read.
    ///
    /// # Errors
    /// [`ModelError`] naming the file, the place and the fix.
    pub fn from_path_in(path: &Path, unit: Option<LengthUnit>) -> Result<(Part, Format), ModelError> {
        let (mut soup, format) = crate::io::read_path_as(path)?;
        if let Some(unit) = unit.filter(|u| format.is_cad() && *u != LengthUnit::Mm) {
            let scale = 1.0 / unit.millimetres();
            for p in &mut soup.positions {
                *p *= scale;
            }
        }
        Ok((Part::try_new(&soup, &path.display().to_string())?, format))
    }
}

/// card(PPC) of a fixed part A and a moving part B, split by type (DOMAIN.md section 8).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct PpcCount {
    /// |faces A| · |convex vertices B|.
    pub f_v: usize,
    /// |convex edges A| · |convex edges B|.
    pub e_e: usize,
    /// |convex vertices A| · |faces B|.
    pub v_f: usize,
}

impl PpcCount {
    /// The total.
    #[must_use]
    pub fn total(&self) -> usize {
        self.f_v + self.e_e + self.v_f
    }
}

/// Counts the primitive principal contacts between a fixed and a moving part.
#[must_use]
pub fn ppc_count(fixed: &Part, moving: &Part) -> PpcCount {
    PpcCount {
        f_v: fixed.faces().len() * moving.convex_vertices().count(),
        e_e: fixed.convex_edges().count() * moving.convex_edges().count(),
        v_f: fixed.convex_vertices().count() * moving.faces().len(),
    }
}
