//! The built-in example's graph (the paper's L-block and box, its bounds): time per run
//! on one thread and on all cores, and the optimisation counts of one run (printed
//! once; the paper needed 752 optimisation procedures for its example).

use acsg::graph::{Options, generate};
use criterion::{Criterion, criterion_group, criterion_main};

fn built_in_example(c: &mut Criterion) {
    let (l_block, box_part) = acsg::examples::l_block_and_box();
    let bounds = acsg::examples::paper_bounds();
    let one_thread = Options {
        threads: 1,
        ..Options::default()
    };
    let s = generate(&l_block, &box_part, &bounds, &one_thread).stats;
    eprintln!(
        "built-in example: {} states, {} edges; optimisation procedures (candidates searched): {} + {} = {} \
         (paper: 328 + 424 = 752); local optimisation runs: {} + {} = {}",
        s.states,
        s.edges,
        s.stage1_searched,
        s.stage2_searched,
        s.stage1_searched + s.stage2_searched,
        s.stage1_optimisations,
        s.stage2_optimisations,
        s.stage1_optimisations + s.stage2_optimisations
    );
    let mut group = c.benchmark_group("generate");
    group.sample_size(10);
    group.bench_function("built_in_example_1_thread", |b| {
        b.iter(|| generate(&l_block, &box_part, &bounds, &one_thread).states.len())
    });
    group.bench_function("built_in_example_all_cores", |b| {
        b.iter(|| generate(&l_block, &box_part, &bounds, &Options::default()).states.len())
    });
    group.finish();
}

criterion_group!(benches, built_in_example);
criterion_main!(benches);
