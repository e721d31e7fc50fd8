//! The Assembly Contact State Graph: every contact state that some pose within the
//! bounds shows (docs/concepts.md#the-graph), each with a verified witness, and the neighbour
//! relation between them.
//!
//! The graph being built (module `store`: states, canonical index, completeness
//! record, counts) is kept apart from how it is searched ([`strategy`]): the default strategy
//! decides every candidate it meets (witnessed, proved infeasible, or recorded as
//! undecided); the paper's algorithm is a second strategy, a baseline on the same input
//! ([`Options::strategy`]). Whatever the strategy, a state's identity is P(X) at its
//! witness, every witness is verified by the contact module before the state is kept,
//! and neighbour edges (module `neighbours`) join states one contact apart and states whose
//! touching regions meet (found by small probes from each witness). Candidates are
//! decided in parallel and merged in a fixed order, so the output does not depend on
//! the number of threads.

pub mod document;
mod dof;
mod neighbours;
pub(crate) mod rules;
mod store;
pub mod strategy;

use glam::DAffine3;
use serde::{Deserialize, Serialize};

use crate::contact::PrincipalContact;
use crate::feasibility::Problem;
use crate::model::Part;
use crate::pose::{Bounds, Pose};

pub use document::Document;
pub(crate) use dof::state_dof;
pub use strategy::Strategy;

/// How to generate a graph.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Keep states with a degenerate contact (v-v, e-v, v-e, e-e-t between convex
    /// elements), which hold only on a set any small motion leaves.
    pub degenerate: bool,
    /// G: the assembled pose of the moving part in the fixed part's frame.
    pub assembled: DAffine3,
    /// Worker threads; 0 uses rayon's default (one per core).
    pub threads: usize,
    /// How hard each candidate is searched and proved before it is left undecided: a
    /// multiple of the default budget of boxes and local searches (1).
    pub effort: u32,
    /// How the candidates are searched: the default, or the paper's algorithm as a
    /// baseline.
    pub strategy: Strategy,
    /// The most work the default strategy may do, in boxes of poses examined, each
    /// local optimisation counted as [`SEARCH_WORK`] boxes; `None` (the default): no
    /// limit. Once reached (checked between batches of candidates, so the output still
    /// does not depend on the thread count), no candidate is searched or proved any
    /// more: each one met after that is recorded undecided, the sweeps and the last
    /// proofs are skipped, and the graph is not complete
    /// ([`Stats::work_limit_reached`]). For parts so large that a complete run would
    /// take longer than a user can wait.
    pub work_limit: Option<u64>,
}

/// Boxes of poses a local optimisation counts for against [`Options::work_limit`]: on the
/// fixture pairs one costs about as much time as 20 to 60 boxes.
pub const SEARCH_WORK: u64 = 50;

impl Default for Options {
    fn default() -> Options {
        Options {
            degenerate: false,
            assembled: DAffine3::IDENTITY,
            threads: 0,
            effort: 1,
            strategy: Strategy::Full,
            work_limit: None,
        }
    }
}

/// One contact state of the graph.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Its index in [`Graph::states`]; 0 is free space.
    pub id: usize,
    /// P(X) at the witness: its principal contacts, sorted.
    pub contacts: Vec<PrincipalContact>,
    /// Degrees of freedom left at the witness (6 in free space).
    pub dof: u8,
    /// Whether one of its contacts is degenerate.
    pub degenerate: bool,
    /// A pose within the bounds showing exactly this state, verified. Free space has
    /// one when some probed pose in the bounds touches nothing.
    pub witness: Option<Pose>,
}

/// Counts and times of a run.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    /// card(PPC): every primitive principal contact.
    pub ppc: usize,
    /// Single contacts decided in stage 1: the PPCs and every other contact that can
    /// hold alone (face on face, edge in face, contacts with concave elements).
    pub singles: usize,
    /// PPCs ruled out by the reach test without optimising.
    pub ppc_unreachable: usize,
    /// Feasible PPCs.
    pub feasible_ppc: usize,
    /// PPCs handed to the optimiser in stage 1 (the paper's count of optimisation
    /// procedures; each may run several local optimisations).
    pub stage1_searched: usize,
    /// Local optimisations run in stage 1.
    pub stage1_optimisations: usize,
    /// Stage-2 pairs (state, feasible PPC) considered.
    pub stage2_pairs: usize,
    /// Pairs where the state already implies the PPC.
    pub pruned_implied: usize,
    /// Pairs ruled out by topological existence.
    pub pruned_topology: usize,
    /// Candidate states left out because they hold a degenerate contact.
    pub pruned_degenerate: usize,
    /// Candidate states already known or already searched.
    pub pruned_duplicate: usize,
    /// Candidates ruled out by the reach test.
    pub pruned_unreachable: usize,
    /// Candidates searched by optimisation.
    pub stage2_candidates: usize,
    /// Candidates handed to the optimiser in stage 2, descents included (the paper's
    /// count of optimisation procedures).
    pub stage2_searched: usize,
    /// Local optimisations run in stage 2.
    pub stage2_optimisations: usize,
    /// States found while searching for another.
    pub found_on_the_way: usize,
    /// Stage-2 searches for a state one contact below a known one, started from its
    /// witness (after the breadth-first growth settles), retries of candidates left
    /// undecided included.
    pub descents: usize,
    /// States found by those searches.
    pub found_by_descent: usize,
    /// Rotations at which the states were read off the Minkowski differences of the
    /// convex pieces (the slice sweep, when the searches settle).
    pub slices: usize,
    /// Translations whose state the sweep read.
    pub slice_samples: usize,
    /// States the sweep found that no search had.
    pub found_by_slices: usize,
    /// Candidates met in all (stage 1's PPCs, stage 2's combinations, descents): each
    /// ends witnessed, proved infeasible or undecided.
    pub candidates: usize,
    /// Candidates with a verified witness (the state asked for).
    pub witnessed: usize,
    /// Candidates proved infeasible: no pose in the bounds shows them.
    pub infeasible: usize,
    /// Candidates neither witnessed nor proved infeasible: the graph may lack them.
    pub undecided: usize,
    /// Candidates still undecided once the searches and sweeps were done that the last,
    /// strongest proofs proved infeasible (counted in `infeasible` too).
    pub proved_last: usize,
    /// Boxes of poses examined by the branch and prune of the decisions.
    pub boxes: usize,
    /// States, free space included.
    pub states: usize,
    /// Neighbour edges.
    pub edges: usize,
    /// Seconds in stage 1.
    pub stage1_seconds: f64,
    /// Seconds in stage 2 (with the neighbour edges).
    pub stage2_seconds: f64,
    /// Whether the run reached its work limit ([`Options::work_limit`]): the candidates
    /// met after that were left undecided without a search, the sweeps and the last
    /// proofs skipped, so the graph is not complete. Written only when true.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub work_limit_reached: bool,
}

/// A candidate state that was neither witnessed nor proved infeasible.
#[derive(Clone, Debug, PartialEq)]
pub struct Undecided {
    /// Its principal contacts, sorted.
    pub contacts: Vec<PrincipalContact>,
    /// A box of poses the proofs left open, where the candidate may still hold: the one
    /// the last proof stopped at, else the smallest its decision left open (the whole
    /// bounds when the strategy tries no proof, as the paper's does not).
    pub open: Bounds,
}

/// The generated graph.
#[derive(Clone, Debug, PartialEq)]
pub struct Graph {
    /// The states; `states[0]` is free space.
    pub states: Vec<State>,
    /// Neighbour pairs of state ids, each `[smaller, larger]`, sorted.
    pub edges: Vec<[usize; 2]>,
    /// Counts and times.
    pub stats: Stats,
    /// The candidates left undecided, in the order met: empty when the graph is
    /// complete.
    pub undecided: Vec<Undecided>,
    /// The strategy that built it.
    pub strategy: Strategy,
}

impl Graph {
    /// Whether no state within the bounds is missing: every candidate the search met
    /// was witnessed or proved infeasible, by a strategy that proves
    /// ([`Strategy::proves`]; the paper's cannot), before any work limit was reached.
    #[must_use]
    pub fn is_complete(&self) -> bool {
        self.undecided.is_empty() && self.strategy.proves() && !self.stats.work_limit_reached
    }
}

/// Progress of a run, for progress bars.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// 1 or 2.
    pub stage: u8,
    /// Searches done in this stage (or this stage-2 level).
    pub done: usize,
    /// Searches planned.
    pub total: usize,
    /// States so far.
    pub states: usize,
}

/// Generates the contact state graph of a fixed and a moving part within bounds.
///
/// ```
/// use acsg::graph::{Options, generate};
/// use acsg::pose::Bounds;
///
/// let (slab, cube) = acsg::examples::cube_and_slab();
/// // The cube over the slab's top face, free to tilt by 10 degrees, to yaw and to drop.
/// let bounds = Bounds::from_degrees(
///     [-1.0, -1.0, 0.0, -10.0, -10.0, -180.0],
///     [1.0, 1.0, 3.0, 10.0, 10.0, 180.0],
/// )
/// .unwrap();
/// let graph = generate(&slab, &cube, &bounds, &Options::default());
/// // Free space, 4 corners, 4 edges and the bottom face on the slab.
/// assert_eq!(graph.states.len(), 1 + 9);
/// ```
#[must_use]
pub fn generate(fixed: &Part, moving: &Part, bounds: &Bounds, options: &Options) -> Graph {
    generate_with_progress(fixed, moving, bounds, options, &|_| {})
}

/// [`generate`], calling `progress` from the calling thread as searches finish.
#[must_use]
pub fn generate_with_progress(
    fixed: &Part,
    moving: &Part,
    bounds: &Bounds,
    options: &Options,
    progress: &(dyn Fn(Progress) + Sync),
) -> Graph {
    let run = || {
        let mut problem = Problem::new(fixed, moving, *bounds, options.assembled);
        problem.set_effort(options.effort);
        let mut store = store::Store::new(fixed, moving, options, &problem);
        strategy::run(options.strategy, &mut store, &problem, progress);
        store.finish(&problem)
    };
    match options.threads {
        0 => run(),
        n => match rayon::ThreadPoolBuilder::new().num_threads(n).build() {
            Ok(pool) => pool.install(run),
            Err(_) => run(),
        },
    }
}
