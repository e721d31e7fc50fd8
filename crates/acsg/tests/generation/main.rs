//! The generator's end-to-end tests, in one binary so that the built-in example's
//! graph (the longest run they share) is generated once:
//!
//! - `generator`: hand-derived state sets, witnesses re-verified, neighbours, the same
//!   bytes for any thread count, the same states whatever the file;
//! - `recall`: recall against the independent rotation-slice oracle;
//! - `strategies`: the paper's algorithm as a baseline against the default search.

#[path = "../common/mod.rs"]
mod common;
mod generator;
mod recall;
mod strategies;

use std::sync::OnceLock;

use acsg::graph::{Graph, Options, generate};

/// The built-in example's graph with the default options, generated once for every
/// test that reads it (its stage times zeroed).
fn built_in_example() -> &'static Graph {
    static RUN: OnceLock<Graph> = OnceLock::new();
    RUN.get_or_init(|| {
        let (l_block, box_part) = acsg::examples::l_block_and_box();
        let mut graph = generate(
            &l_block,
            &box_part,
            &acsg::examples::paper_bounds(),
            &Options::default(),
        );
        graph.stats.stage1_seconds = 0.0;
        graph.stats.stage2_seconds = 0.0;
        graph
    })
}
