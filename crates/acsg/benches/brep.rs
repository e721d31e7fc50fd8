//! B-rep construction throughput on a finely triangulated part (target: 1 million
//! triangles a second on one core).

use acsg::examples::{refine_midpoints, triangle_soup};
use acsg::model::Part;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn brep_construction(c: &mut Criterion) {
    let (l_block, _) = acsg::examples::l_block_and_box();
    let mut soup = triangle_soup(&l_block);
    while soup.polygons.len() < 100_000 {
        soup = refine_midpoints(&soup);
    }
    let mut group = c.benchmark_group("brep");
    group.sample_size(10);
    group.throughput(Throughput::Elements(soup.polygons.len() as u64));
    group.bench_function(format!("l_block_{}_triangles", soup.polygons.len()), |b| {
        b.iter(|| Part::try_new(&soup, "fine l_block").expect("valid"));
    });
    group.finish();
}

criterion_group!(benches, brep_construction);
criterion_main!(benches);
