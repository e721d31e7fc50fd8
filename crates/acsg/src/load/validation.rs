//! What can be wrong with an input solid, collected into one report.

use std::fmt;

/// The classes of defect a model can have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DefectKind {
    /// No points or no polygons.
    Empty,
    /// A coordinate is NaN or infinite.
    NonFinite,
    /// A polygon has (nearly) zero area.
    ZeroArea,
    /// A polygon's corners do not lie in one plane.
    NotPlanar,
    /// An edge is used by only one polygon: the surface has a gap.
    NotClosed,
    /// An edge is used by more than two polygons, or a vertex joins two separate fans.
    NotManifold,
    /// Two neighbouring polygons disagree on orientation.
    InconsistentOrientation,
    /// The surface is consistently oriented, but its normals point inwards.
    InwardOrientation,
    /// The file holds more than one connected shell.
    SeveralShells,
    /// Anything else that makes the B-rep ill-defined (faces meeting at 0 or 360
    /// degrees, a face that cannot be triangulated).
    Degenerate,
}

impl DefectKind {
    /// A short name for the class.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            DefectKind::Empty => "empty model",
            DefectKind::NonFinite => "non-finite coordinate",
            DefectKind::ZeroArea => "zero-area face",
            DefectKind::NotPlanar => "face not planar",
            DefectKind::NotClosed => "not closed",
            DefectKind::NotManifold => "not manifold",
            DefectKind::InconsistentOrientation => "inconsistent orientation",
            DefectKind::InwardOrientation => "inward orientation",
            DefectKind::SeveralShells => "several shells",
            DefectKind::Degenerate => "degenerate geometry",
        }
    }
}

/// One defect: its class, where it is, and what to do.
#[derive(Clone, Debug, PartialEq)]
pub struct Defect {
    /// The class.
    pub kind: DefectKind,
    /// Where: a polygon, an edge between two points, a vertex.
    pub place: String,
    /// What the user can do about it.
    pub fix: String,
}

/// Everything wrong with one model (in the spirit of truck's `ShellCondition` and geo's
/// `Validation`): construction collects all defects rather than stopping at the first.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ValidationReport {
    defects: Vec<Defect>,
    omitted: usize,
}

/// Listing more defects than this helps nobody; the rest are counted.
const MAX_LISTED: usize = 20;

impl ValidationReport {
    /// Records a defect.
    pub fn push(&mut self, kind: DefectKind, place: impl Into<String>, fix: impl Into<String>) {
        if self.defects.len() < MAX_LISTED {
            self.defects.push(Defect {
                kind,
                place: place.into(),
                fix: fix.into(),
            });
        } else {
            self.omitted += 1;
        }
    }
    /// Whether nothing is wrong.
    #[must_use]
    pub fn is_ok(&self) -> bool {
        self.defects.is_empty()
    }
    /// The defects recorded (at most 20; see [`ValidationReport::omitted`]).
    #[must_use]
    pub fn defects(&self) -> &[Defect] {
        &self.defects
    }
    /// How many defects were found beyond those listed.
    #[must_use]
    pub fn omitted(&self) -> usize {
        self.omitted
    }
    /// Whether a defect of this class was recorded.
    #[must_use]
    pub fn has(&self, kind: DefectKind) -> bool {
        self.defects.iter().any(|d| d.kind == kind)
    }
}

impl fmt::Display for ValidationReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, d) in self.defects.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "  - {}: {} (fix: {})", d.kind.name(), d.place, d.fix)?;
        }
        if self.omitted > 0 {
            write!(f, "\n  ... and {} more", self.omitted)?;
        }
        Ok(())
    }
}
