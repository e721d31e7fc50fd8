//! Property tests of the pose convention (docs/concepts.md#poses-and-bounds):
//! `p_A = G (R p_B + t)`, `R = Rz(rz) Ry(ry) Rx(rx)`, checked against quaternions applied
//! one after the other, plus the round trips affine <-> pose and text <-> pose, and the
//! clamping of bounds.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use acsg::pose::{Bounds, Pose};
use glam::{DAffine3, DMat3, DQuat, DVec3};
use proptest::prelude::*;

fn angle() -> impl Strategy<Value = f64> {
    -PI..PI
}

/// Poses away from gimbal lock: |ry| < π/2 - 1e-3.
fn pose() -> impl Strategy<Value = Pose> {
    (
        -1e3..1e3f64,
        -1e3..1e3f64,
        -1e3..1e3f64,
        angle(),
        -(FRAC_PI_2 - 1e-3)..(FRAC_PI_2 - 1e-3),
        angle(),
    )
        .prop_map(|(x, y, z, rx, ry, rz)| Pose::from_array([x, y, z, rx, ry, rz]))
}

fn vec3(r: f64) -> impl Strategy<Value = DVec3> {
    (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// A random rigid transform, built from an axis-angle rotation (independent of `Pose`).
fn rigid() -> impl Strategy<Value = DAffine3> {
    (vec3(1.0), 0.0..TAU, vec3(100.0)).prop_map(|(axis, angle, t)| {
        let axis = axis.try_normalize().unwrap_or(DVec3::Z);
        DAffine3::from_rotation_translation(DQuat::from_axis_angle(axis, angle), t)
    })
}

/// Difference of two angles, modulo 2π, in [-π, π].
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    if d > PI { d - TAU } else { d }
}

fn max_abs(m: DMat3) -> f64 {
    m.to_cols_array().iter().fold(0.0, |acc, v| acc.max(v.abs()))
}

proptest! {
    #[test]
    fn rotation_is_orthonormal_with_det_one(rx in -10.0..10.0f64, ry in -10.0..10.0f64, rz in -10.0..10.0f64) {
        let r = Pose::from_array([0.0, 0.0, 0.0, rx, ry, rz]).rotation();
        prop_assert!(max_abs(r.transpose() * r - DMat3::IDENTITY) < 1e-12);
        prop_assert!((r.determinant() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn mapping_is_g_after_r_then_t(p in pose(), g in rigid(), point in vec3(10.0)) {
        // Rx first, then Ry, then Rz, each about A's fixed axes; then t; then G.
        let rotated = DQuat::from_rotation_z(p.rz)
            * (DQuat::from_rotation_y(p.ry) * (DQuat::from_rotation_x(p.rx) * point));
        let expected = g.transform_point3(rotated + DVec3::new(p.x, p.y, p.z));
        let got = p.to_affine(&g).transform_point3(point);
        prop_assert!(got.abs_diff_eq(expected, 1e-9), "{got} vs {expected}");

        // The 4x4 matrix says the same, row-major.
        let m = p.matrix(&g);
        let h = [point.x, point.y, point.z, 1.0];
        for (i, row) in m.iter().enumerate() {
            let v: f64 = row.iter().zip(h).map(|(a, b)| a * b).sum();
            let want = if i < 3 { expected[i] } else { 1.0 };
            prop_assert!((v - want).abs() < 1e-9, "row {i}: {v} vs {want}");
        }
    }

    #[test]
    fn affine_round_trip(p in pose(), g in rigid()) {
        let back = Pose::from_affine(&p.to_affine(&g), &g).unwrap();
        for (a, b) in [(p.x, back.x), (p.y, back.y), (p.z, back.z)] {
            prop_assert!((a - b).abs() < 1e-9, "{p:?} -> {back:?}");
        }
        for (a, b) in [(p.rx, back.rx), (p.ry, back.ry), (p.rz, back.rz)] {
            prop_assert!(angle_diff(a, b).abs() < 1e-9, "{p:?} -> {back:?}");
        }
        prop_assert!((-FRAC_PI_2..=FRAC_PI_2).contains(&back.ry));
    }

    #[test]
    fn affine_round_trip_of_any_rotation_reproduces_the_matrix(
        rx in -10.0..10.0f64, ry in -10.0..10.0f64, rz in -10.0..10.0f64, g in rigid()
    ) {
        // Any angles (gimbal lock included): the pose found may differ, the transform may not.
        let m = Pose::from_array([1.0, 2.0, 3.0, rx, ry, rz]).to_affine(&g);
        let back = Pose::from_affine(&m, &g).unwrap();
        prop_assert!(back.to_affine(&g).abs_diff_eq(m, 1e-9));
        prop_assert!((-FRAC_PI_2..=FRAC_PI_2).contains(&back.ry));
        prop_assert!((-PI..=PI).contains(&back.rx) && (-PI..=PI).contains(&back.rz));
    }

    #[test]
    fn affine_round_trip_near_gimbal_lock(
        sign in prop_oneof![Just(1.0), Just(-1.0)],
        offset in prop_oneof![Just(0.0), 0.0..1e-12f64, 1e-12..1e-6f64],
        rx in angle(), rz in angle(), g in rigid(),
    ) {
        let ry = sign * (FRAC_PI_2 - offset);
        let m = Pose::from_array([1.0, 2.0, 3.0, rx, ry, rz]).to_affine(&g);
        let back = Pose::from_affine(&m, &g).unwrap();
        prop_assert!(back.to_affine(&g).abs_diff_eq(m, 1e-9), "{back:?}");
        prop_assert!((back.ry - ry).abs() < 1e-7);
    }

    #[test]
    fn parse_round_trips_display(a in proptest::array::uniform6(proptest::num::f64::NORMAL | proptest::num::f64::ZERO)) {
        let p = Pose::from_array(a);
        prop_assert_eq!(Pose::parse(&p.to_string(), false).unwrap(), p);
        let spaced = format!(" {} , {},{} ,{},  {},{} ", a[0], a[1], a[2], a[3], a[4], a[5]);
        prop_assert_eq!(Pose::parse(&spaced, false).unwrap(), p);
    }

    #[test]
    fn parse_degrees_converts_only_angles(p in pose()) {
        let text = format!(
            "{},{},{},{},{},{}",
            p.x, p.y, p.z, p.rx.to_degrees(), p.ry.to_degrees(), p.rz.to_degrees()
        );
        let q = Pose::parse(&text, true).unwrap();
        prop_assert_eq!((q.x, q.y, q.z), (p.x, p.y, p.z));
        for (a, b) in [(p.rx, q.rx), (p.ry, q.ry), (p.rz, q.rz)] {
            prop_assert!((a - b).abs() <= 1e-15 * (1.0 + a.abs()));
        }
    }

    #[test]
    fn clamp_lands_inside_and_keeps_inside_poses(
        lo in proptest::array::uniform6(-100.0..100.0f64),
        width in proptest::array::uniform6(prop_oneof![Just(0.0), 0.0..50.0f64]),
        frac in proptest::array::uniform6(0.0..=1.0f64),
        any_pose in proptest::array::uniform6(-1e3..1e3f64),
    ) {
        let hi: [f64; 6] = std::array::from_fn(|i| lo[i] + width[i]);
        let b = Bounds::try_new(lo, hi).unwrap();

        let clamped = b.clamp(&Pose::from_array(any_pose));
        prop_assert!(b.contains(&clamped, 0.0, 0.0), "{clamped:?} outside {b:?}");
        prop_assert_eq!(b.clamp(&clamped), clamped);

        let inside = Pose::from_array(std::array::from_fn(|i| (lo[i] + frac[i] * width[i]).clamp(lo[i], hi[i])));
        prop_assert!(b.contains(&inside, 0.0, 0.0));
        prop_assert_eq!(b.clamp(&inside), inside);
        prop_assert!(b.contains(&b.center(), 0.0, 0.0));
    }
}
