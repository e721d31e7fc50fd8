//! How the candidate states are searched: a strategy proposes candidates, decides each
//! with the feasibility module's primitives, and records the outcomes in the store
//! (`graph::store::Store`); the store keeps the graph, the canonical index and the
//! completeness record, whatever the strategy. Two strategies exist:
//! - [`Strategy::Full`] (the default, module `full`): every single contact, growth by
//!   every single-contact state under every outcome of the mapping rules, each candidate
//!   decided (witnessed, proved infeasible, or undecided) with warm starts, sound
//!   exclusions and sliding, then descents;
//! - [`Strategy::Paper`] (module `paper`): the paper's algorithm step by step, as a
//!   baseline to measure against on the same input.

mod full;
mod paper;

use serde::{Deserialize, Serialize};

use super::Progress;
use super::store::Store;
use crate::feasibility::Problem;

/// Which search builds the graph. Every strategy reports only states whose witnesses
/// the contact module verified; they differ in which candidates they meet and how hard
/// they search each.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Strategy {
    /// The project's search: every single contact that can hold alone (not only the
    /// PPCs), growth by every single-contact state found under every outcome of the
    /// mapping rules, and descents one contact below each state; each candidate is
    /// decided by local searches from warm and constructive starts, sliding, and a
    /// branch and prune of sound exclusion tests, so that it ends witnessed, proved
    /// infeasible or undecided. The graph is complete when nothing is undecided.
    #[default]
    Full,
    /// The paper's algorithm (Pan and Schimmels, section III), as a baseline: stage 1
    /// optimises every PPC, stage 2 grows each state by every feasible PPC it does not
    /// imply, drops combinations that fail topological existence, maps the rest to
    /// their description (TopUniqDesc) and optimises each new one. Each optimisation
    /// (GeoFeas) is a local search from a fixed set of spread starts, stopped at the
    /// first whose pose verifies as the candidate (with the same witness check as
    /// [`Strategy::Full`]); no exclusion tests, warm starts, sliding or descents, and
    /// no budget to raise ([`super::Options::effort`] does not apply).
    ///
    /// It cannot prove a candidate infeasible: every candidate it fails to witness is
    /// recorded undecided, with the whole bounds left open, and its graph is never
    /// reported complete (it also never meets the single contacts that are not PPCs,
    /// such as a face flat on a face).
    Paper,
}

impl Strategy {
    /// Every strategy, the default first.
    pub const ALL: [Strategy; 2] = [Strategy::Full, Strategy::Paper];

    /// Its name on the command line, in task files and in the JSON.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Strategy::Full => "full",
            Strategy::Paper => "paper",
        }
    }

    /// Whether the strategy can prove candidates infeasible, so that a graph it builds
    /// with nothing undecided misses no state.
    #[must_use]
    pub fn proves(self) -> bool {
        match self {
            Strategy::Full => true,
            Strategy::Paper => false,
        }
    }

    /// Whether this is the default strategy (left out of the JSON).
    #[must_use]
    pub fn is_default(&self) -> bool {
        *self == Strategy::default()
    }
}

impl std::fmt::Display for Strategy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A strategy name that is none of [`Strategy::ALL`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown strategy '{0}' (give full, the default, or paper, the paper's algorithm as a baseline)")]
pub struct UnknownStrategy(pub String);

impl std::str::FromStr for Strategy {
    type Err = UnknownStrategy;

    fn from_str(text: &str) -> Result<Strategy, UnknownStrategy> {
        Strategy::ALL
            .into_iter()
            .find(|s| s.name() == text.trim())
            .ok_or_else(|| UnknownStrategy(text.to_string()))
    }
}

/// Runs a strategy's stages on a store holding free space alone.
pub(crate) fn run(
    strategy: Strategy,
    store: &mut Store<'_>,
    problem: &Problem<'_>,
    progress: &(dyn Fn(Progress) + Sync),
) {
    match strategy {
        Strategy::Full => full::run(store, problem, progress),
        Strategy::Paper => paper::run(store, problem, progress),
    }
}

/// Searches run in parallel per batch of this many, merged in order, with progress
/// reported between batches (the full strategy checks its work limit there, and
/// without one takes batches four times as large).
const BATCH: usize = 64;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_read_back_and_unknown_names_are_refused_listing_the_choices() {
        for strategy in Strategy::ALL {
            assert_eq!(strategy.name().parse::<Strategy>(), Ok(strategy));
            assert_eq!(strategy.to_string(), strategy.name());
        }
        assert_eq!(" paper ".parse::<Strategy>(), Ok(Strategy::Paper));
        let err = "Paper2".parse::<Strategy>().unwrap_err().to_string();
        assert!(
            err.contains("'Paper2'") && err.contains("full") && err.contains("paper"),
            "{err}"
        );
        assert_eq!(Strategy::default(), Strategy::Full);
        assert!(Strategy::Full.proves() && !Strategy::Paper.proves());
    }

    #[test]
    fn the_json_and_task_files_use_the_same_names() {
        for strategy in Strategy::ALL {
            assert_eq!(
                serde_json::to_string(&strategy).unwrap(),
                format!("\"{}\"", strategy.name())
            );
        }
        assert_eq!(serde_json::from_str::<Strategy>("\"paper\"").unwrap(), Strategy::Paper);
        assert!(serde_json::from_str::<Strategy>("\"Paper\"").is_err());
    }
}
