//! P(X) evaluations per second (target: 100,000 a second on the L-block and box).

use acsg::contact::ContactScene;
use acsg::pose::Pose;
use acsg::tolerance::CONTACT_REL;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{DAffine3, DQuat, DVec3};

fn small_pair(c: &mut Criterion) {
    let (l_block, box_part) = acsg::examples::l_block_and_box();
    let scene = ContactScene::new(&l_block, &box_part);
    // Poses of the kind a generator visits: flush, touching, near, clear.
    let poses: Vec<DAffine3> = [
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [-2.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [-2.0, 1.0, 3.0, 0.05, -0.03, 0.1],
        [0.0, 0.0, 120.0, 0.2, 0.1, -0.2],
    ]
    .iter()
    .map(|&x| Pose::from_array(x).to_affine(&DAffine3::IDENTITY))
    .collect();
    let mut group = c.benchmark_group("contacts");
    group.throughput(Throughput::Elements(poses.len() as u64));
    group.bench_function("l_block_box_state", |b| {
        b.iter(|| {
            poses
                .iter()
                .map(|p| scene.state(p, CONTACT_REL).contacts.len())
                .sum::<usize>()
        })
    });
    group.bench_function("l_block_box_with_min_gap", |b| {
        b.iter(|| {
            poses
                .iter()
                .map(|p| scene.evaluate(p, CONTACT_REL).contacts.len())
                .sum::<usize>()
        })
    });
    group.finish();
}

fn large_pair(c: &mut Criterion) {
    let (a, b) = (
        acsg::examples::faceted_sphere(5000, 50.0),
        acsg::examples::faceted_sphere(5000, 30.0),
    );
    let scene = ContactScene::new(&a, &b);
    let towards = DVec3::new(0.3, -0.4, 0.866).normalize();
    let poses: Vec<DAffine3> = [79.5, 80.0, 80.5, 82.0]
        .iter()
        .map(|&d| DAffine3::from_rotation_translation(DQuat::from_rotation_z(0.3), towards * d))
        .collect();
    let mut group = c.benchmark_group("contacts");
    group.sample_size(10);
    group.throughput(Throughput::Elements(poses.len() as u64));
    let name = format!("faceted_spheres_{}_{}_faces_state", a.faces().len(), b.faces().len());
    group.bench_function(name, |bench| {
        bench.iter(|| {
            poses
                .iter()
                .map(|p| scene.state(p, CONTACT_REL).contacts.len())
                .sum::<usize>()
        })
    });
    group.finish();
}

criterion_group!(benches, small_pair, large_pair);
criterion_main!(benches);
