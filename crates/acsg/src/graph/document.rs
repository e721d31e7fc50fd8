//! The graph as written to JSON (documented by `schema/graph.schema.json`).

use serde::{Deserialize, Serialize};

use super::{Graph, Options, Stats, Strategy};
use crate::contact::ContactRecord;
use crate::model::{Part, PartElements};
use crate::pose::{Bounds, CONVENTION, Pose};

/// The identifier of the output format, bumped when a key changes meaning.
pub const FORMAT: &str = "acsg-graph/1";

/// The whole output of a run; also what [`crate::export`] reads back.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Document {
    /// [`FORMAT`].
    pub format: String,
    /// The pose convention ([`CONVENTION`]).
    pub convention: String,
    /// Units of lengths and angles in this file.
    #[serde(default)]
    pub units: Units,
    /// The chord tolerance (in `units.length`) with which STEP cylinders, cones and
    /// circles were read as planar facets (`--facet`): the graph is then that of the
    /// faceted parts. Absent when nothing was faceted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub facet: Option<f64>,
    /// The fixed part A: path as given and elements with geometry.
    pub fixed: PartElements,
    /// The moving part B.
    pub moving: PartElements,
    /// G, row-major 4x4.
    pub assembled: [[f64; 4]; 4],
    /// The misalignment bounds, radians for angles.
    pub bounds: BoundsRecord,
    /// The options of the run.
    pub options: OptionsRecord,
    /// The states; `states[0]` is free space.
    pub states: Vec<StateRecord>,
    /// Neighbour pairs of state ids.
    pub edges: Vec<[usize; 2]>,
    /// Whether every candidate the search met was witnessed or proved infeasible
    /// (docs/concepts.md#the-graph): then no state within the bounds is missing. Always
    /// false with the paper's strategy, which proves nothing infeasible.
    #[serde(default)]
    pub complete: bool,
    /// The candidates left undecided: states the graph may lack.
    #[serde(default)]
    pub undecided: Vec<UndecidedRecord>,
    /// Counts and times.
    pub stats: Stats,
}

/// A candidate left undecided, as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UndecidedRecord {
    /// Its principal contacts.
    pub contacts: Vec<ContactRecord>,
    /// A box of poses the proofs left open, where the candidate may still hold: the
    /// one the last proof stopped at (the smallest the decision left open when no
    /// last proof ran).
    pub open: BoundsRecord,
}

/// Units used in the file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Units {
    /// The unit of lengths: `mm`, `cm`, `m`, `in` (see [`crate::units`]), or "model
    /// units" when none was given.
    pub length: String,
    /// Always "radians" in files (degrees are for the command line and the report).
    pub angle: String,
}

impl Default for Units {
    fn default() -> Units {
        Units {
            length: "model units".into(),
            angle: "radians".into(),
        }
    }
}

/// Bounds as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoundsRecord {
    /// Lower ends, in the order x, y, z, rx, ry, rz.
    pub min: [f64; 6],
    /// Upper ends.
    pub max: [f64; 6],
}

/// Options as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OptionsRecord {
    /// Whether degenerate states were kept.
    pub degenerate: bool,
    /// The strategy that built the graph; written only when it is not the default
    /// (`full`), so that the default's files are as before.
    #[serde(default, skip_serializing_if = "Strategy::is_default")]
    pub strategy: Strategy,
    /// The work limit of the run ([`Options::work_limit`]), written only when one was
    /// given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub work_limit: Option<u64>,
}

/// One state as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StateRecord {
    /// Index in `states`.
    pub id: usize,
    /// The principal contacts.
    pub contacts: Vec<ContactRecord>,
    /// Degrees of freedom left.
    pub dof: u8,
    /// Whether a contact is degenerate.
    pub degenerate: bool,
    /// The witness pose, or null for free space when no free pose was probed.
    pub witness: Option<WitnessRecord>,
}

/// A witness pose as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WitnessRecord {
    /// x, y, z, rx, ry, rz (radians).
    pub pose: [f64; 6],
    /// The placement of B in A's frame, row-major 4x4 (G·[R|t]).
    pub matrix: [[f64; 4]; 4],
}

impl Document {
    /// The document of a graph; `paths` are the parts' paths as the user gave them.
    #[must_use]
    pub fn new(
        graph: &Graph,
        fixed: &Part,
        moving: &Part,
        bounds: &Bounds,
        options: &Options,
        paths: [&str; 2],
    ) -> Document {
        let mut fixed_elements = PartElements::of(fixed);
        fixed_elements.path = paths[0].to_string();
        let mut moving_elements = PartElements::of(moving);
        moving_elements.path = paths[1].to_string();
        let g = options.assembled;
        Document {
            format: FORMAT.into(),
            convention: CONVENTION.into(),
            units: Units::default(),
            facet: None,
            fixed: fixed_elements,
            moving: moving_elements,
            assembled: Pose::default().matrix(&g),
            bounds: BoundsRecord {
                min: bounds.min.to_array(),
                max: bounds.max.to_array(),
            },
            options: OptionsRecord {
                degenerate: options.degenerate,
                strategy: graph.strategy,
                work_limit: options.work_limit,
            },
            states: graph
                .states
                .iter()
                .map(|s| StateRecord {
                    id: s.id,
                    contacts: s.contacts.iter().map(|c| ContactRecord::of(c, fixed, moving)).collect(),
                    dof: s.dof,
                    degenerate: s.degenerate,
                    witness: s.witness.map(|p| WitnessRecord {
                        pose: p.to_array(),
                        matrix: p.matrix(&g),
                    }),
                })
                .collect(),
            edges: graph.edges.clone(),
            complete: graph.is_complete(),
            undecided: graph
                .undecided
                .iter()
                .map(|u| UndecidedRecord {
                    contacts: u.contacts.iter().map(|c| ContactRecord::of(c, fixed, moving)).collect(),
                    open: BoundsRecord {
                        min: u.open.min.to_array(),
                        max: u.open.max.to_array(),
                    },
                })
                .collect(),
            stats: graph.stats.clone(),
        }
    }

    /// Pretty JSON text, ending with a newline.
    #[must_use]
    pub fn to_json(&self) -> String {
        // Plain structs of numbers, strings and arrays: serialising cannot fail.
        let mut text = serde_json::to_string_pretty(self).expect("a document serialises");
        text.push('\n');
        text
    }
}
