//! acsg's penetration query against parry3d-f64's on the same convex pieces and poses.
//!
//! For each pair of parts, poses are drawn (deterministically) from the bounds the
//! generator searches; at each, acsg's `ContactScene::penetration_depth` gives the deepest
//! penetration over all pairs of convex pieces (or minus the smallest separation), and
//! parry's `contact` query (GJK/EPA), run on every pair of the same pieces whose
//! bounding boxes overlap (parry's own boxes), gives its deepest penetration. The
//! program prints, per pair of parts, both times, their ratio, and how often the two
//! disagree on whether the parts penetrate (beyond a tolerance of 1e-9 L) and by how
//! much their depths differ where both say they do. It also times acsg's yes-or-no
//! test (`ContactScene::penetrates_beyond` at the tolerance), which its search runs far
//! more often than the depth, and checks that it agrees with the depth.
//!
//! `cargo run --release` here (`benches/parry`, a workspace of its own so that parry
//! is never built by the main workspace's tests). `ACSG_PARRY_POSES=n` sets the poses
//! per pair (default 2000).

use std::path::Path;
use std::time::{Duration, Instant};

use acsg::contact::ContactScene;
use acsg::glam::{DAffine3, DVec3};
use acsg::model::{Part, length_scale};
use acsg::pose::{Bounds, Pose};
use parry3d_f64::bounding_volume::BoundingVolume;
use parry3d_f64::math::{Matrix, Pose as ParryPose, Rotation, Vector};
use parry3d_f64::query;
use parry3d_f64::shape::ConvexPolyhedron;

/// A small deterministic generator of numbers in [0, 1).
struct Numbers(u64);

impl Numbers {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn vector(p: DVec3) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

/// A part's convex pieces as parry's convex polyhedra (hulls of the pieces' vertices).
fn parry_pieces(part: &Part) -> Result<Vec<ConvexPolyhedron>, String> {
    part.convex_pieces()
        .iter()
        .enumerate()
        .map(|(k, piece)| {
            let points: Vec<Vector> = piece.vertices().iter().map(|&p| vector(p)).collect();
            ConvexPolyhedron::from_convex_hull(&points).ok_or_else(|| format!("piece {k}: parry has no hull"))
        })
        .collect()
}

fn parry_pose(a: &DAffine3) -> ParryPose {
    let m = a.matrix3;
    let rotation = Rotation::from_mat3(&Matrix::from_cols_array(&m.to_cols_array()));
    ParryPose::from_parts(vector(a.translation), rotation)
}

/// The deepest penetration of any pair of pieces by parry's contact query (`None` when
/// no pair's boxes overlap or none touches).
fn parry_depth(fixed: &[ConvexPolyhedron], moving: &[ConvexPolyhedron], at: &ParryPose) -> Option<f64> {
    let identity = ParryPose::IDENTITY;
    let boxes: Vec<_> = moving.iter().map(|m| m.aabb(at)).collect();
    let mut deepest: Option<f64> = None;
    for f in fixed {
        let fixed_box = f.aabb(&identity);
        for (m, moving_box) in moving.iter().zip(&boxes) {
            if !fixed_box.intersects(moving_box) {
                continue;
            }
            if let Ok(Some(contact)) = query::contact(&identity, f, at, m, 0.0) {
                let depth = -contact.dist;
                deepest = Some(deepest.map_or(depth, |d| d.max(depth)));
            }
        }
    }
    deepest
}

struct Case {
    name: &'static str,
    fixed: Part,
    moving: Part,
    bounds: Bounds,
}

fn fixture(name: &str) -> Result<Part, String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures").join(name);
    Part::from_path(&path).map_err(|e| format!("{}: {e}", path.display()))
}

fn main() -> Result<(), String> {
    let poses: usize = match std::env::var("ACSG_PARRY_POSES") {
        Ok(n) => n
            .trim()
            .parse()
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| format!("ACSG_PARRY_POSES: `{n}` is not a positive whole number of poses"))?,
        Err(_) => 2000,
    };
    let peg_bounds = Bounds::from_degrees([-2.0, -2.0, 0.0, -2.0, -2.0, -2.0], [2.0, 2.0, 45.0, 2.0, 2.0, 2.0])
        .map_err(|e| e.to_string())?;
    let (l_block, box_part) = acsg::examples::l_block_and_box();
    let cases = [
        Case {
            name: "L-block and box",
            fixed: l_block,
            moving: box_part,
            bounds: acsg::examples::paper_bounds(),
        },
        Case {
            name: "square peg, chamfered hole",
            fixed: fixture("block_with_chamfered_hole.off")?,
            moving: fixture("peg.off")?,
            bounds: peg_bounds,
        },
        Case {
            name: "32-gon peg, chamfered hole",
            fixed: fixture("scale/block_with_round_hole_32.off")?,
            moving: fixture("scale/round_peg_32.off")?,
            bounds: peg_bounds,
        },
        Case {
            name: "64-gon peg, chamfered hole",
            fixed: fixture("scale/block_with_round_hole_64.off")?,
            moving: fixture("scale/round_peg_64.off")?,
            bounds: peg_bounds,
        },
    ];
    println!("penetration of the parts at {poses} poses per pair drawn from the generator's bounds (one thread)");
    println!(
        "{:<28} {:>13} {:>10} {:>10} {:>8} {:>12} {:>14} {:>10} {:>10}",
        "parts", "piece pairs", "acsg ms", "parry ms", "ratio", "disagree", "max |Δdepth|", "excess ms", "yes/no ms"
    );
    for case in &cases {
        let length = length_scale(&case.fixed, &case.moving);
        let tolerance = 1e-9 * length;
        let scene = ContactScene::new(&case.fixed, &case.moving);
        let (fixed_parry, moving_parry) = (parry_pieces(&case.fixed)?, parry_pieces(&case.moving)?);
        let mut numbers = Numbers(0x9E37_79B9_7F4A_7C15);
        let (lo, hi) = (case.bounds.min.to_array(), case.bounds.max.to_array());
        let placements: Vec<DAffine3> = (0..poses)
            .map(|_| {
                let x: [f64; 6] = std::array::from_fn(|k| lo[k] + numbers.next() * (hi[k] - lo[k]));
                Pose::from_array(x).to_affine(&DAffine3::IDENTITY)
            })
            .collect();
        let started = Instant::now();
        let ours: Vec<f64> = placements.iter().map(|p| scene.penetration_depth(p)).collect();
        let acsg_time = started.elapsed();
        // The yes-or-no question the search asks most: do they penetrate beyond the
        // tolerance? (Pairs are dropped at their first axis that says no.)
        let started = Instant::now();
        let beyond: Vec<bool> = placements
            .iter()
            .map(|p| scene.penetrates_beyond(p, tolerance))
            .collect();
        let beyond_time = started.elapsed();
        // The optimiser's residual: the depth when positive (pairs dropped early too).
        let started = Instant::now();
        let excess: Vec<f64> = placements.iter().map(|p| scene.penetration_excess(p)).collect();
        let excess_time = started.elapsed();
        if excess.iter().zip(&ours).any(|(&e, &d)| e != d.max(0.0)) {
            return Err(format!(
                "{}: penetration_excess is not the positive part of the depth",
                case.name
            ));
        }
        let beyond_wrong = beyond
            .iter()
            .zip(&ours)
            .filter(|&(&b, &d)| b != (d > tolerance))
            .count();
        if beyond_wrong > 0 {
            return Err(format!(
                "{}: penetrates_beyond disagrees with the depth at {beyond_wrong} poses",
                case.name
            ));
        }
        let parry_poses: Vec<ParryPose> = placements.iter().map(parry_pose).collect();
        let started = Instant::now();
        let theirs: Vec<Option<f64>> = parry_poses
            .iter()
            .map(|p| parry_depth(&fixed_parry, &moving_parry, p))
            .collect();
        let parry_time = started.elapsed();
        let (mut disagree, mut worst) = (0usize, 0.0f64);
        for (&a, &b) in ours.iter().zip(&theirs) {
            let b = b.unwrap_or(f64::NEG_INFINITY);
            let (ours_in, theirs_in) = (a > tolerance, b > tolerance);
            if ours_in != theirs_in && (a - b).abs() > tolerance {
                disagree += 1;
            } else if ours_in && theirs_in {
                worst = worst.max((a - b).abs());
            }
        }
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        println!(
            "{:<28} {:>13} {:>10.1} {:>10.1} {:>7.2}x {:>12} {:>14.3e} {:>10.1} {:>10.1}",
            case.name,
            format!("{} x {}", fixed_parry.len(), moving_parry.len()),
            ms(acsg_time),
            ms(parry_time),
            ms(parry_time) / ms(acsg_time).max(1e-9),
            format!("{disagree} of {poses}"),
            worst,
            ms(excess_time),
            ms(beyond_time)
        );
    }
    println!(
        "ratio: parry's time over acsg's depth (above 1: acsg is faster); excess: acsg's optimiser residual (the \
         depth when positive); yes/no: acsg's `penetrates_beyond` at the tolerance"
    );
    Ok(())
}
