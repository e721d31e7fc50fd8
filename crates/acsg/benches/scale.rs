//! How the generator's cost grows with the parts' size: an n-gon peg (circumradius 14)
//! over a block with a chamfered n-gon hole (circumradius 15), the `fixtures/scale/`
//! series that `scripts/make_fixtures.py` writes, bounds x, y ±2 mm, z 0–45 mm, every
//! angle ±2°. One run per n, printing card(PPC), the convex pieces of the block,
//! states, candidates decided, candidates searched by optimisation, local optimisation
//! runs, undecided candidates and wall seconds; then the growth exponent of the time
//! (and of the candidates) in n, fitted by least squares over log n.
//!
//! `cargo bench -p acsg --bench scale`; `ACSG_SCALE_SIDES=8,16` runs only those n (the
//! default is 8, 16, 32, 64, which takes long). `ACSG_SCALE_WORK_LIMIT=100000` gives
//! each run that work limit (`acsg generate --work-limit`): the runs end, their graphs
//! marked not complete, so that the figures show how far each n gets for the same work
//! (the growth exponent then says how the time per unit of work grows). Runs use every
//! core, as `acsg generate` does.

use std::path::Path;
use std::time::Instant;

use acsg::graph::{Options, generate};
use acsg::model::{Part, ppc_count};
use acsg::pose::Bounds;

/// The sides of the series, as the fixture script writes them.
const SIDES: [usize; 4] = [8, 16, 32, 64];

fn part(name: &str) -> Result<Part, String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/scale")
        .join(name);
    Part::from_path(&path).map_err(|e| format!("{}: {e} (run `python3 scripts/make_fixtures.py`)", path.display()))
}

/// The least-squares slope of `log y` over `log x`: the exponent `k` of `y ≈ c xᵏ`.
fn growth_exponent(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|&&(x, y)| x > 0.0 && y > 0.0)
        .map(|&(x, y)| (x.ln(), y.ln()))
        .collect();
    if logs.len() < 2 {
        return None;
    }
    let n = logs.len() as f64;
    let (mx, my) = (
        logs.iter().map(|p| p.0).sum::<f64>() / n,
        logs.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

fn main() -> Result<(), String> {
    let sides: Vec<usize> = match std::env::var("ACSG_SCALE_SIDES") {
        Ok(list) => list
            .split(',')
            .map(|s| {
                s.trim()
                    .parse::<usize>()
                    .ok()
                    .filter(|n| SIDES.contains(n))
                    .ok_or_else(|| format!("ACSG_SCALE_SIDES: `{s}` is not one of {SIDES:?}"))
            })
            .collect::<Result<_, _>>()?,
        Err(_) => SIDES.to_vec(),
    };
    let work_limit = match std::env::var("ACSG_SCALE_WORK_LIMIT") {
        Ok(limit) => Some(
            limit
                .trim()
                .parse::<u64>()
                .ok()
                .filter(|&l| l > 0)
                .ok_or_else(|| format!("ACSG_SCALE_WORK_LIMIT: `{limit}` is not a positive whole number"))?,
        ),
        Err(_) => None,
    };
    let options = Options {
        work_limit,
        ..Options::default()
    };
    let bounds = Bounds::from_degrees([-2.0, -2.0, 0.0, -2.0, -2.0, -2.0], [2.0, 2.0, 45.0, 2.0, 2.0, 2.0])
        .map_err(|e| e.to_string())?;
    println!("n-gon peg over a chamfered n-gon hole; x, y ±2 mm, z 0-45 mm, angles ±2°; one run each, all cores");
    if let Some(limit) = work_limit {
        println!("work limit {limit} per run: a run that reaches it is not complete");
    }
    println!(
        "{:>4} {:>8} {:>7} {:>7} {:>10} {:>9} {:>10} {:>10} {:>9} {:>9}",
        "n", "PPC", "pieces", "states", "candidates", "searched", "local runs", "undecided", "complete", "wall s"
    );
    let (mut times, mut candidates) = (Vec::new(), Vec::new());
    for n in sides {
        let block = part(&format!("block_with_round_hole_{n}.off"))?;
        let peg = part(&format!("round_peg_{n}.off"))?;
        let started = Instant::now();
        let graph = generate(&block, &peg, &bounds, &options);
        let seconds = started.elapsed().as_secs_f64();
        let s = &graph.stats;
        println!(
            "{:>4} {:>8} {:>7} {:>7} {:>10} {:>9} {:>10} {:>10} {:>9} {:>9.1}",
            n,
            ppc_count(&block, &peg).total(),
            block.convex_pieces().len(),
            s.states,
            s.candidates,
            s.stage1_searched + s.stage2_searched,
            s.stage1_optimisations + s.stage2_optimisations,
            s.undecided,
            if graph.is_complete() { "yes" } else { "no" },
            seconds
        );
        times.push((n as f64, seconds));
        candidates.push((n as f64, s.candidates as f64));
    }
    let show = |k: Option<f64>| k.map_or_else(|| "needs two n".to_string(), |k| format!("{k:.2}"));
    println!(
        "growth exponent in n (least squares over log n): time {}, candidates {}",
        show(growth_exponent(&times)),
        show(growth_exponent(&candidates))
    );
    Ok(())
}
