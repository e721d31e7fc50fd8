//! The default strategy against the paper's algorithm (`Strategy::Paper`) on the
//! built-in example (the paper's L-block and box, its bounds), from one run: each
//! strategy's states, optimisation procedures (candidates handed to the optimiser: the
//! paper's count, 752 for its example), local optimisation runs, boxes of poses the
//! default's proofs examined (the paper's algorithm examines none) and wall time, and
//! the ratios default / paper.
//!
//! `cargo bench -p acsg --bench strategies`. The two runs alternate (paper, then
//! default); `ACSG_BENCH_ROUNDS=n` repeats the pair n times and reports the median times
//! (the counts do not change from run to run). Runs use every core, as `acsg demo` does.

use std::time::{Duration, Instant};

use acsg::graph::{Graph, Options, Strategy, generate};

/// What one strategy did: its graph (the counts do not change from run to run) and
/// the wall time of each run.
struct Measured {
    graph: Graph,
    times: Vec<Duration>,
}

impl Measured {
    /// Candidates handed to the optimiser, stage 1 and stage 2.
    fn procedures(&self) -> usize {
        self.graph.stats.stage1_searched + self.graph.stats.stage2_searched
    }

    /// Local optimisations run, stage 1 and stage 2.
    fn runs(&self) -> usize {
        self.graph.stats.stage1_optimisations + self.graph.stats.stage2_optimisations
    }

    fn median(&self) -> Duration {
        let mut times = self.times.clone();
        times.sort();
        times.get(times.len() / 2).copied().unwrap_or_default()
    }
}

fn main() {
    let rounds = std::env::var("ACSG_BENCH_ROUNDS")
        .ok()
        .and_then(|r| r.parse::<usize>().ok())
        .unwrap_or(1)
        .max(1);
    let (l_block, box_part) = acsg::examples::l_block_and_box();
    let bounds = acsg::examples::paper_bounds();
    let run = |strategy: Strategy, into: &mut Option<Measured>| {
        let options = Options {
            strategy,
            ..Options::default()
        };
        let started = Instant::now();
        let graph = generate(&l_block, &box_part, &bounds, &options);
        let took = started.elapsed();
        into.get_or_insert_with(|| Measured {
            graph,
            times: Vec::new(),
        })
        .times
        .push(took);
    };
    let (mut paper, mut full) = (None, None);
    for _ in 0..rounds {
        run(Strategy::Paper, &mut paper);
        run(Strategy::Full, &mut full);
    }
    let (Some(paper), Some(full)) = (paper, full) else {
        return;
    };
    println!(
        "built-in example (the paper's L-block and box; paper: 328 + 424 = 752 optimisation procedures, 126 states \
         with redundant descriptions), {rounds} round(s), all cores"
    );
    println!(
        "{:<9} {:>7} {:>9} {:>22} {:>12} {:>9} {:>10}",
        "strategy", "states", "complete", "procedures (1 + 2)", "local runs", "boxes", "wall s"
    );
    for (name, m) in [("paper", &paper), ("default", &full)] {
        let s = &m.graph.stats;
        println!(
            "{:<9} {:>7} {:>9} {:>22} {:>12} {:>9} {:>10.2}",
            name,
            s.states,
            if m.graph.is_complete() { "yes" } else { "no" },
            format!("{} ({} + {})", m.procedures(), s.stage1_searched, s.stage2_searched),
            m.runs(),
            s.boxes,
            m.median().as_secs_f64()
        );
    }
    let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { f64::NAN };
    println!(
        "default / paper: time {:.2}x, procedures {:.2}x, local runs {:.2}x, states {:.2}x",
        ratio(full.median().as_secs_f64(), paper.median().as_secs_f64()),
        ratio(full.procedures() as f64, paper.procedures() as f64),
        ratio(full.runs() as f64, paper.runs() as f64),
        ratio(full.graph.stats.states as f64, paper.graph.stats.states as f64)
    );
}
