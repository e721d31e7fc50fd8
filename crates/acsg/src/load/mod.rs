//! Loading a part: a file read into a polygon soup ([`crate::io`]), the soup checked
//! and built into a boundary representation (`topology`), the solid decomposed into
//! exact convex pieces (`convex`), and the [`Part`] assembled from both. Everything
//! wrong with a model is reported at once, with its place and fix
//! ([`ValidationReport`]).

mod convex;
mod topology;
mod validation;

use std::path::Path;

pub use validation::{Defect, DefectKind, ValidationReport};

use crate::io::{Format, MeshSoup, ReadError, ReadOptions, read_path, read_path_with};
use crate::model::Part;
use crate::units::LengthUnit;

/// Errors of loading a part.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The file could not be read or parsed.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The part lies so far from the origin, for its size, that its coordinates keep
    /// too few digits for the contact tolerance ([`crate::tolerance::OFFSET_REL`]).
    #[error(
        "{name}: the part lies {offset:e} from the origin, {ratio:.1e} times its size ({diagonal:e}); at that distance \
         coordinates keep too few digits for the contact tolerance (1e-9 of the size), and contacts would appear or \
         vanish by rounding (move the part near the origin in your CAD program or mesh tool, at most {limit:e} times \
         its size away; place the parts relative to each other with the assembled pose, --assembled)"
    )]
    FarFromOrigin {
        /// The part's name (its path).
        name: String,
        /// The largest distance of a point from the origin.
        offset: f64,
        /// The part's bounding-box diagonal.
        diagonal: f64,
        /// `offset / diagonal`.
        ratio: f64,
        /// [`crate::tolerance::OFFSET_REL`].
        limit: f64,
    },
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
            ModelError::Read(_) | ModelError::FarFromOrigin { .. } => None,
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
        check_offset(soup, name)?;
        let brep = topology::build(soup).map_err(invalid)?;
        let pieces = convex::decompose(&brep);
        Ok(Part {
            name: name.to_string(),
            vertices: brep.vertices,
            edges: brep.edges,
            faces: brep.faces,
            pieces,
            bounds: brep.bounds,
            volume: brep.volume,
        })
    }

    /// Reads, builds and validates a part from a model file.
    ///
    /// # Errors
    /// [`ModelError`] naming the file, the place and the fix.
    pub fn from_path(path: &Path) -> Result<Part, ModelError> {
        let soup: MeshSoup = read_path(path)?;
        Part::try_new(&soup, &path.display().to_string())
    }

    /// Reads a part for a run in `unit` (see [`crate::units`]): a CAD file (STEP,
    /// IGES), which states its unit, is converted to `unit` (millimetres when `None`);
    /// a mesh's numbers are taken as they are, in `unit`. Also returns the format read.
    ///
    /// # Errors
    /// [`ModelError`] naming the file, the place and the fix.
    pub fn from_path_in(path: &Path, unit: Option<LengthUnit>) -> Result<(Part, Format), ModelError> {
        Part::from_path_with(path, unit, None)
    }

    /// [`Part::from_path_in`], with STEP cylinders, cones and circles read as planar
    /// facets within the chord tolerance `facet` (in `unit`, millimetres when `None`;
    /// see [`crate::io::step::read_faceted`]).
    ///
    /// # Errors
    /// [`ModelError`] naming the file, the place and the fix.
    pub fn from_path_with(
        path: &Path,
        unit: Option<LengthUnit>,
        facet: Option<f64>,
    ) -> Result<(Part, Format), ModelError> {
        let options = ReadOptions {
            facet_mm: facet.map(|f| f * unit.map_or(1.0, LengthUnit::millimetres)),
        };
        let (mut soup, format) = read_path_with(path, &options)?;
        if let Some(unit) = unit.filter(|u| format.is_cad() && *u != LengthUnit::Mm) {
            let scale = 1.0 / unit.millimetres();
            for p in &mut soup.positions {
                *p *= scale;
            }
        }
        Ok((Part::try_new(&soup, &path.display().to_string())?, format))
    }
}

/// Refuses a soup whose points lie farther from the origin than
/// [`crate::tolerance::OFFSET_REL`] times its diagonal. Soups without a finite, non-zero
/// diagonal are left to the validation, which names their defects.
fn check_offset(soup: &MeshSoup, name: &str) -> Result<(), ModelError> {
    let Some(&first) = soup.positions.first() else {
        return Ok(());
    };
    let (mut lo, mut hi, mut offset) = (first, first, 0.0_f64);
    for &p in &soup.positions {
        lo = lo.min(p);
        hi = hi.max(p);
        offset = offset.max(p.length());
    }
    let diagonal = (hi - lo).length();
    let limit = crate::tolerance::OFFSET_REL;
    if diagonal.is_finite() && diagonal > 0.0 && offset.is_finite() && offset > limit * diagonal {
        return Err(ModelError::FarFromOrigin {
            name: name.to_string(),
            offset,
            diagonal,
            ratio: offset / diagonal,
            limit,
        });
    }
    Ok(())
}
