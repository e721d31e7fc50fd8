//! Evaluates P(X) many times on the built-in pair (for profilers).
fn main() {
    let (l_block, box_part) = acsg::examples::l_block_and_box();
    let scene = acsg::contact::ContactScene::new(&l_block, &box_part);
    let poses: Vec<glam::DAffine3> = [[0.0, 0.0, 0.0, 0.0, 0.0, 0.0], [-2.0, 1.0, 3.0, 0.05, -0.03, 0.1]]
        .iter()
        .map(|&x| acsg::pose::Pose::from_array(x).to_affine(&glam::DAffine3::IDENTITY))
        .collect();
    let mut total = 0;
    for _ in 0..20_000 {
        for p in &poses {
            total += scene.evaluate(p, acsg::tolerance::CONTACT_REL).contacts.len();
        }
    }
    println!("{total}");
}
