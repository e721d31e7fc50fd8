//! Evaluates P(X) on two 5000-face convex parts (for profilers).
use acsg::convex::ConvexPolytope;
use acsg::io::MeshSoup;
use acsg::model::Part;
use glam::{DAffine3, DQuat, DVec3};

fn faceted_sphere(faces: usize, radius: f64) -> Part {
    let mut polytope = ConvexPolytope::cuboid(DVec3::splat(-2.0 * radius), DVec3::splat(2.0 * radius));
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    for i in 0..faces {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / faces as f64;
        let r = (1.0 - z * z).sqrt();
        let normal = DVec3::new(r * (golden * i as f64).cos(), r * (golden * i as f64).sin(), z);
        polytope = polytope.clip(normal, radius, 1e-9 * radius).expect("kept");
    }
    let mut soup = MeshSoup {
        polygon_noun: "face",
        ..MeshSoup::default()
    };
    for face in polytope.faces() {
        let start = soup.positions.len() as u32;
        soup.positions.extend(&face.points);
        soup.polygons.push((start..start + face.points.len() as u32).collect());
    }
    Part::try_new(&soup, "faceted sphere").expect("valid")
}

fn main() {
    let t = std::time::Instant::now();
    let (a, b) = (faceted_sphere(5000, 50.0), faceted_sphere(5000, 30.0));
    eprintln!("setup {:?}", t.elapsed());
    split_timing(&a, &b);
    let scene = acsg::contact::ContactScene::new(&a, &b);
    let towards = DVec3::new(0.3, -0.4, 0.866).normalize();
    let t = std::time::Instant::now();
    for d in [79.5, 80.0, 80.5, 82.0].iter().cycle().take(400) {
        let pose = DAffine3::from_rotation_translation(DQuat::from_rotation_z(0.3), towards * *d);
        std::hint::black_box(scene.state(&pose, acsg::tolerance::CONTACT_REL));
    }
    eprintln!("400 evaluations {:?}", t.elapsed());
}

#[allow(dead_code)]
fn split_timing(a: &Part, b: &Part) {
    use acsg::contact::penetration::{PreparedPieces, penetration_prepared};
    let (pa, pb) = (PreparedPieces::new(a), PreparedPieces::new(b));
    let towards = DVec3::new(0.3, -0.4, 0.866).normalize();
    let t = std::time::Instant::now();
    for d in [79.5, 80.0, 80.5, 82.0].iter().cycle().take(400) {
        let pose = DAffine3::from_rotation_translation(DQuat::from_rotation_z(0.3), towards * *d);
        std::hint::black_box(penetration_prepared(&pa, &pb, &pose, 200.0));
    }
    eprintln!("400 penetrations {:?}", t.elapsed());
}
