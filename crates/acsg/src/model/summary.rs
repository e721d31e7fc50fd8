//! A serializable summary of parts, as `acsg inspect` prints it.

use serde::Serialize;

use super::{Part, PpcCount, ppc_count};

/// Counts and measures of one part.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PartSummary {
    /// The part's name (its path, as given).
    pub path: String,
    /// Number of faces.
    pub faces: usize,
    /// Faces with at least one hole.
    pub faces_with_holes: usize,
    /// Faces whose outer outline has a reflex corner.
    pub nonconvex_faces: usize,
    /// Number of vertices.
    pub vertices: usize,
    /// Convex vertices.
    pub convex_vertices: usize,
    /// Number of edges.
    pub edges: usize,
    /// Convex edges.
    pub convex_edges: usize,
    /// Concave edges.
    pub concave_edges: usize,
    /// Pieces of the exact convex decomposition.
    pub convex_pieces: usize,
    /// Enclosed volume.
    pub volume: f64,
    /// Bounding box, `[min, max]`.
    pub bounds: [[f64; 3]; 2],
}

impl PartSummary {
    /// Summarises a part.
    #[must_use]
    pub fn of(part: &Part) -> PartSummary {
        let convex_edges = part.convex_edges().count();
        PartSummary {
            path: part.name().to_string(),
            faces: part.faces().len(),
            faces_with_holes: part.faces().iter().filter(|f| f.loops.len() > 1).count(),
            nonconvex_faces: (0..part.faces().len() as u32)
                .filter(|&f| part.face_outline_is_nonconvex(super::FaceId(f)))
                .count(),
            vertices: part.vertices().len(),
            convex_vertices: part.convex_vertices().count(),
            edges: part.edges().len(),
            convex_edges,
            concave_edges: part.edges().len() - convex_edges,
            convex_pieces: part.convex_pieces().len(),
            volume: part.volume(),
            bounds: [part.bounds().min.to_array(), part.bounds().max.to_array()],
        }
    }
}

/// What `acsg inspect` reports: each part, and for a fixed and a moving part their
/// card(PPC).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Inspection {
    /// The unit of every length here (`mm`, `cm`, `m`, `in`, or `model units` when
    /// none was given; see [`crate::units`]).
    pub units: String,
    /// The chord tolerance curved STEP faces were faceted with (`--facet`), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub facet: Option<f64>,
    /// One summary per part, fixed first.
    pub parts: Vec<PartSummary>,
    /// card(PPC) when two parts were given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ppc: Option<PpcTotals>,
}

/// card(PPC) by type, with the total.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct PpcTotals {
    /// Faces of A against convex vertices of B.
    pub f_v: usize,
    /// Convex edges of A against convex edges of B.
    pub e_e: usize,
    /// Convex vertices of A against faces of B.
    pub v_f: usize,
    /// The sum.
    pub total: usize,
}

impl From<PpcCount> for PpcTotals {
    fn from(c: PpcCount) -> Self {
        PpcTotals {
            f_v: c.f_v,
            e_e: c.e_e,
            v_f: c.v_f,
            total: c.total(),
        }
    }
}

impl Inspection {
    /// Inspects one part, or a fixed and a moving part.
    ///
    /// ```
    /// let (fixed, moving) = acsg::examples::l_block_and_box();
    /// let report = acsg::model::Inspection::of(&fixed, Some(&moving));
    /// assert_eq!(report.ppc.unwrap().total, 328);
    /// assert_eq!(report.parts[0].concave_edges, 1);
    /// ```
    #[must_use]
    pub fn of(fixed: &Part, moving: Option<&Part>) -> Inspection {
        let mut parts = vec![PartSummary::of(fixed)];
        parts.extend(moving.map(PartSummary::of));
        Inspection {
            units: crate::units::UNSPECIFIED.to_string(),
            facet: None,
            parts,
            ppc: moving.map(|m| ppc_count(fixed, m).into()),
        }
    }
}
