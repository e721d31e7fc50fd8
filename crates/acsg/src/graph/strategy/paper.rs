//! The paper's algorithm step by step ([`super::Strategy::Paper`]), as the baseline the
//! default strategy is measured against (Pan and Schimmels, section III):
//!
//! ```text
//! for every PPC:  if GeoFeas(PPC) then FPPC <- FPPC + PPC
//! ACSG <- FPPC
//! for every CS of ACSG, in order (the list grows while it is walked):
//!     for every PPC of FPPC not in KLC(CS):
//!         HLCS <- CS + PPC
//!         if TopExist(HLCS):
//!             HLCS <- TopUniqDesc(HLCS)
//!             if HLCS not in ACSG and GeoFeas(HLCS) then ACSG <- ACSG + HLCS
//! ```
//!
//! TopExist and TopUniqDesc are the derived mapping rules ([`rules::grow`]: a
//! combination that cannot exist maps to nothing; one the rules leave ambiguous maps to
//! each of its descriptions, each a candidate). GeoFeas is local optimisation:
//! [`Problem::solve_from`] from [`SPREAD_STARTS`] fixed starts spread over the bounds
//! ([`Problem::spread_starts`]), stopped at the first whose pose verifies as the
//! candidate. The paper calls a zero objective feasible; the witness check here is
//! stricter (exactly this state, robustly, DOMAIN.md section 7), so a pose where the
//! candidate holds with other pairs touching gets the one clearing optimisation that
//! [`Problem::settle`] adds. States met on the way are not kept: GeoFeas answers for its
//! candidate only.
//!
//! Two departures, both in the baseline's favour: a candidate is optimised once even when
//! several states generate it (the pseudo-code would optimise a failed one again), and
//! the candidates of one round are optimised in parallel (the set found is the same as
//! walking the list in order, since a candidate's outcome does not depend on when it is
//! met).

use rayon::prelude::*;

use super::BATCH;
use crate::contact::PrincipalContact;
use crate::feasibility::{Decided, Decision, PRIMITIVE_STARTS, Problem, SearchStats, primitive_contacts};
use crate::graph::Progress;
use crate::graph::rules;
use crate::graph::store::Store;
use crate::pose::Pose;

/// The starts of every GeoFeas: the centre of the bounds' rotations, the centres of
/// their eight octants and their eight corners (as the default strategy's single
/// contacts get), each with the candidate's contacts placed together in turn.
const SPREAD_STARTS: usize = PRIMITIVE_STARTS;

/// Stage 1, then stage 2 round by round until no new state appears.
pub(super) fn run(store: &mut Store<'_>, problem: &Problem<'_>, progress: &(dyn Fn(Progress) + Sync)) {
    let feasible = stage1(store, problem, progress);
    store.end_stage1();
    // Each round grows the states the previous round found (stage 1's first).
    let mut first = 1;
    loop {
        let last = store.states().len();
        let candidates = combinations(store, &feasible, first..last);
        first = last;
        if candidates.is_empty() {
            return;
        }
        let found = geo_feas_all(problem, &candidates, 2, store.states().len(), progress);
        for (target, (witness, stats)) in candidates.into_iter().zip(found) {
            store.stats.stage2_searched += 1;
            store.stats.stage2_optimisations += stats.optimisations;
            store.record(target, decided(witness, problem), problem);
        }
    }
}

/// Stage 1: GeoFeas of every PPC; the feasible ones (FPPC), in the order of the PPCs.
fn stage1(store: &mut Store<'_>, problem: &Problem<'_>, progress: &(dyn Fn(Progress) + Sync)) -> Vec<PrincipalContact> {
    let ppcs = primitive_contacts(store.fixed(), store.moving());
    store.stats.ppc = ppcs.len();
    store.stats.singles = ppcs.len();
    let targets: Vec<Vec<PrincipalContact>> = ppcs.iter().map(|pc| vec![*pc]).collect();
    let found = geo_feas_all(problem, &targets, 1, store.states().len(), progress);
    let mut feasible = Vec::new();
    for (target, (witness, stats)) in targets.into_iter().zip(found) {
        store.stats.stage1_searched += 1;
        store.stats.stage1_optimisations += stats.optimisations;
        if witness.is_some() {
            store.stats.feasible_ppc += 1;
            feasible.extend(target.first().copied());
        }
        store.record(target, decided(witness, problem), problem);
    }
    feasible
}

/// The topologically unique combinations of the states `parents` with the feasible
/// PPCs they do not imply, not known and not decided yet, in a fixed order; counted as
/// the default strategy counts its pairs.
fn combinations(
    store: &mut Store<'_>,
    feasible: &[PrincipalContact],
    parents: std::ops::Range<usize>,
) -> Vec<Vec<PrincipalContact>> {
    let (fixed, moving) = (store.fixed(), store.moving());
    let mut out: Vec<Vec<PrincipalContact>> = Vec::new();
    let mut proposed = std::collections::BTreeSet::new();
    for parent in parents {
        let state = store.states()[parent].contacts.clone();
        // KLC(CS): the PPCs the state implies, its own among them.
        let implied = rules::state_primitives(fixed, moving, &state);
        for &ppc in feasible {
            store.stats.stage2_pairs += 1;
            if state.contains(&ppc) || implied.contains(&ppc) {
                store.stats.pruned_implied += 1;
                continue;
            }
            // TopExist and TopUniqDesc.
            let targets = rules::grow(fixed, moving, &state, ppc);
            if targets.is_empty() {
                store.stats.pruned_topology += 1;
            }
            for target in targets {
                if store.admit(&target, &state, &mut proposed) {
                    out.push(target);
                }
            }
        }
    }
    out
}

/// GeoFeas of each target, in parallel batches, with progress after each batch.
fn geo_feas_all(
    problem: &Problem<'_>,
    targets: &[Vec<PrincipalContact>],
    stage: u8,
    states: usize,
    progress: &(dyn Fn(Progress) + Sync),
) -> Vec<(Option<Pose>, SearchStats)> {
    let mut found = Vec::with_capacity(targets.len());
    for chunk in targets.chunks(BATCH) {
        found.par_extend(chunk.par_iter().map(|target| {
            let mut stats = SearchStats::default();
            (geo_feas(problem, target, &mut stats), stats)
        }));
        progress(Progress {
            stage,
            done: found.len(),
            total: targets.len(),
            states,
        });
    }
    found
}

/// The paper's GeoFeas: local optimisations from the spread starts, in order, until one
/// reaches a pose that verifies as the target.
fn geo_feas(problem: &Problem<'_>, target: &[PrincipalContact], stats: &mut SearchStats) -> Option<Pose> {
    let bounds = *problem.bounds();
    // Other states met on the way: GeoFeas does not report them.
    let mut met = Vec::new();
    problem
        .spread_starts(target, SPREAD_STARTS)
        .into_iter()
        .find_map(|start| {
            let pose = problem.solve_from(target, start, &bounds, stats);
            problem.settle(target, pose, &bounds, &mut met, stats)
        })
}

/// A GeoFeas outcome as a decision: witnessed, or undecided over the whole bounds (a
/// local search that fails proves nothing).
fn decided(witness: Option<Pose>, problem: &Problem<'_>) -> Decided {
    Decided {
        decision: match witness {
            Some(pose) => Decision::Witnessed(pose),
            None => Decision::Undecided(*problem.bounds()),
        },
        others: Vec::new(),
        rest: Vec::new(),
    }
}
