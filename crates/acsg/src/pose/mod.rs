//! Poses of the moving part and bounds on them (docs/concepts.md#poses-and-bounds).
//!
//! A pose is `X = (x, y, z, rx, ry, rz)`, angles in radians. A point `p` of the moving
//! part B maps into the frame of the fixed part A as
//!
//! ```text
//! p_A = G (R p_B + t),   R = Rz(rz) · Ry(ry) · Rx(rx),   t = (x, y, z)
//! ```
//!
//! where `G` is the assembled pose of B in A's frame (a rigid transform; the identity
//! when both models share their frame at assembly). [`CONVENTION`] states this in one
//! line for output files. Bounds are the box `X_min <= X <= X_max` (Eq. 24), compared
//! componentwise on the raw numbers (angles are not wrapped modulo 2π).

use std::fmt;

use glam::{DAffine3, DMat3, DVec3};
use serde::{Deserialize, Serialize};

use crate::tolerance;

/// One-line statement of the pose convention, for output files and reports.
pub const CONVENTION: &str = "p_A = G (R p_B + t), R = Rz(rz)*Ry(ry)*Rx(rx), t = (x, y, z), angles in radians; \
                              4x4 matrices are row-major G*[R|t] with last row 0 0 0 1";

/// Largest deviation `max |RᵀR − I|` accepted for the 3x3 part of a rigid transform.
const RIGID_TOL: f64 = tolerance::RIGID_REL;

/// Below this value of `cos(ry)` the Euler extraction treats `ry` as exactly ±π/2
/// (gimbal lock) and sets `rx = 0`. This is a numerical guard at the level of
/// floating-point rounding, not a geometric tolerance: either branch reproduces the
/// rotation matrix to rounding accuracy.
const GIMBAL_EPS: f64 = 16.0 * f64::EPSILON;

/// One of the six pose components.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Component {
    /// Translation along x.
    X,
    /// Translation along y.
    Y,
    /// Translation along z.
    Z,
    /// Rotation about x (radians).
    Rx,
    /// Rotation about y (radians).
    Ry,
    /// Rotation about z (radians).
    Rz,
}

impl Component {
    /// All six components in the order of `X = (x, y, z, rx, ry, rz)`.
    pub const ALL: [Component; 6] = [
        Component::X,
        Component::Y,
        Component::Z,
        Component::Rx,
        Component::Ry,
        Component::Rz,
    ];

    /// Index of the component in `X = (x, y, z, rx, ry, rz)` (0-based).
    #[must_use]
    pub fn index(self) -> usize {
        self as usize
    }

    /// Name of the component: `"x"`, `"y"`, `"z"`, `"rx"`, `"ry"` or `"rz"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        ["x", "y", "z", "rx", "ry", "rz"][self.index()]
    }

    /// `true` for the three rotation components.
    #[must_use]
    pub fn is_angle(self) -> bool {
        self.index() >= 3
    }
}

impl fmt::Display for Component {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Everything that can go wrong when reading or building poses and bounds.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PoseError {
    /// The pose text does not have exactly six comma-separated values.
    #[error("expected 6 comma-separated values x,y,z,rx,ry,rz, got {got}")]
    WrongCount {
        /// Number of values found.
        got: usize,
    },
    /// One of the six values is empty (e.g. `"1,,3,0,0,0"`).
    #[error("value {position} ({component}) is empty, expected a number")]
    EmptyValue {
        /// 1-based position of the value in the text.
        position: usize,
        /// The component at that position.
        component: Component,
    },
    /// One of the six values is not a number.
    #[error("value {position} ({component}) is '{token}', not a number")]
    NotANumber {
        /// 1-based position of the value in the text.
        position: usize,
        /// The component at that position.
        component: Component,
        /// The offending text, trimmed.
        token: String,
    },
    /// One of the six values is NaN or infinite.
    #[error("value {position} ({component}) is {value}; every value must be finite")]
    NonFinite {
        /// 1-based position of the value in the text.
        position: usize,
        /// The component at that position.
        component: Component,
        /// The non-finite value read.
        value: f64,
    },
    /// A transform that should be rigid (rotation + translation) is not.
    #[error("{what} is not a rigid transform: {reason}")]
    NotRigid {
        /// Which transform (`"transform"` or `"assembled pose G"`).
        what: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// An angle outside ±180° (±π): angles are not wrapped, so such a value is almost
    /// always a slip (radians read as degrees, or the reverse).
    #[error("{}", angle_out_of_range_message(*.position, *.component, *.value, *.degrees))]
    AngleOutOfRange {
        /// 1-based position of the value in the text.
        position: usize,
        /// The component at that position.
        component: Component,
        /// The value as given.
        value: f64,
        /// Whether the value was given in degrees (else radians).
        degrees: bool,
    },
    /// Bounds with one or more problems; every problem found is listed.
    #[error("invalid bounds: {}", .problems.join("; "))]
    InvalidBounds {
        /// One message per problem, naming the component.
        problems: Vec<String>,
    },
}

/// The largest angle accepted from a user, in degrees: every angle given (bounds,
/// poses, the assembled pose) must lie in `[-180°, 180°]`.
pub const MAX_ANGLE_DEGREES: f64 = 180.0;

/// `true` when `value` (degrees, or radians when `degrees` is false) lies within ±180°.
#[must_use]
pub fn angle_in_range(value: f64, degrees: bool) -> bool {
    if degrees {
        value.abs() <= MAX_ANGLE_DEGREES
    } else {
        value.abs() <= std::f64::consts::PI + tolerance::RADIAN_SLACK
    }
}

/// The same turn as `degrees`, written within ±180°.
fn wrapped_degrees(degrees: f64) -> f64 {
    let w = (degrees + 180.0).rem_euclid(360.0) - 180.0;
    // Round the suggestion to what a user would type.
    (w * 1e6).round() / 1e6
}

fn angle_out_of_range_message(position: usize, component: Component, value: f64, degrees: bool) -> String {
    if degrees {
        format!(
            "value {position} ({component}) is {value}°, outside ±180° (angles are degrees and are not wrapped; \
             the same turn is {}°)",
            wrapped_degrees(value)
        )
    } else {
        format!(
            "value {position} ({component}) is {value} rad ({}°), outside ±π (these angles are radians; \
             give degrees without --radians, or the same turn as {} rad)",
            (value.to_degrees() * 1e4).round() / 1e4,
            (wrapped_degrees(value.to_degrees()).to_radians() * 1e9).round() / 1e9
        )
    }
}

/// A pose `X = (x, y, z, rx, ry, rz)` of the moving part B (angles in radians).
///
/// See the [module documentation](self) for the convention.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Translation along x.
    pub x: f64,
    /// Translation along y.
    pub y: f64,
    /// Translation along z.
    pub z: f64,
    /// Rotation about x, radians (applied first).
    pub rx: f64,
    /// Rotation about y, radians (applied second).
    pub ry: f64,
    /// Rotation about z, radians (applied last).
    pub rz: f64,
}

impl Default for Pose {
    fn default() -> Self {
        Pose::IDENTITY
    }
}

impl fmt::Display for Pose {
    /// Writes `x,y,z,rx,ry,rz` (radians), the format [`Pose::parse`] reads back exactly.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{},{},{},{},{},{}",
            self.x, self.y, self.z, self.rx, self.ry, self.rz
        )
    }
}

impl Pose {
    /// The zero pose: no translation, no rotation.
    pub const IDENTITY: Pose = Pose {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        rx: 0.0,
        ry: 0.0,
        rz: 0.0,
    };

    /// Builds a pose from `[x, y, z, rx, ry, rz]` (angles in radians).
    #[must_use]
    pub fn from_array(a: [f64; 6]) -> Pose {
        Pose {
            x: a[0],
            y: a[1],
            z: a[2],
            rx: a[3],
            ry: a[4],
            rz: a[5],
        }
    }

    /// Returns `[x, y, z, rx, ry, rz]` (angles in radians).
    #[must_use]
    pub fn to_array(&self) -> [f64; 6] {
        [self.x, self.y, self.z, self.rx, self.ry, self.rz]
    }

    /// The value of one component.
    #[must_use]
    pub fn get(&self, component: Component) -> f64 {
        self.to_array()[component.index()]
    }

    /// The rotation `R = Rz(rz) · Ry(ry) · Rx(rx)`.
    #[must_use]
    pub fn rotation(&self) -> DMat3 {
        DMat3::from_rotation_z(self.rz) * DMat3::from_rotation_y(self.ry) * DMat3::from_rotation_x(self.rx)
    }

    /// The translation `t = (x, y, z)`.
    #[must_use]
    pub fn translation(&self) -> DVec3 {
        DVec3::new(self.x, self.y, self.z)
    }

    /// The transform taking points of B into A's frame: `G · [R | t]`, i.e.
    /// `p_A = G (R p_B + t)`.
    ///
    /// ```
    /// use acsg::pose::Pose;
    /// use glam::{DAffine3, DVec3};
    ///
    /// // rz = 90°: B's x-axis lies along A's y-axis.
    /// let pose = Pose::parse("0,0,0,0,0,90", true).unwrap();
    /// let m = pose.to_affine(&DAffine3::IDENTITY);
    /// assert!(m.transform_vector3(DVec3::X).abs_diff_eq(DVec3::Y, 1e-12));
    ///
    /// // The rotation acts first, then the translation, then the assembled pose G.
    /// let pose = Pose::parse("1,0,0,0,0,90", true).unwrap();
    /// let g = DAffine3::from_translation(DVec3::new(0.0, 0.0, 5.0));
    /// let p = pose.to_affine(&g).transform_point3(DVec3::X);
    /// assert!(p.abs_diff_eq(DVec3::new(1.0, 1.0, 5.0), 1e-12));
    /// ```
    #[must_use]
    pub fn to_affine(&self, assembled: &DAffine3) -> DAffine3 {
        *assembled * DAffine3::from_mat3_translation(self.rotation(), self.translation())
    }

    /// The transform of [`Pose::to_affine`] as a row-major 4x4 matrix
    /// (`m[row][col]`, translation in the last column, last row `0 0 0 1`).
    #[must_use]
    pub fn matrix(&self, assembled: &DAffine3) -> [[f64; 4]; 4] {
        let a = self.to_affine(assembled);
        let mut m = [[0.0; 4]; 4];
        for (i, row) in m.iter_mut().take(3).enumerate() {
            for (j, cell) in row.iter_mut().take(3).enumerate() {
                *cell = a.matrix3.col(j)[i];
            }
            row[3] = a.translation[i];
        }
        m[3][3] = 1.0;
        m
    }

    /// Reads a pose from `"x,y,z,rx,ry,rz"`: exactly six comma-separated finite numbers,
    /// spaces around them allowed. Angles are radians, or degrees when `degrees` is
    /// `true` (only the three angles are converted).
    ///
    /// ```
    /// use acsg::pose::Pose;
    ///
    /// let p = Pose::parse("1, 2, 3, 0, 0, 90", true).unwrap();
    /// assert_eq!((p.x, p.y, p.z), (1.0, 2.0, 3.0));
    /// assert!((p.rz - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    ///
    /// let err = Pose::parse("1,2,3,abc,0,0", false).unwrap_err();
    /// assert_eq!(err.to_string(), "value 4 (rx) is 'abc', not a number");
    /// let err = Pose::parse("1,2,3,0,0", false).unwrap_err();
    /// assert_eq!(err.to_string(), "expected 6 comma-separated values x,y,z,rx,ry,rz, got 5");
    /// ```
    pub fn parse(text: &str, degrees: bool) -> Result<Pose, PoseError> {
        let tokens: Vec<&str> = if text.trim().is_empty() {
            Vec::new()
        } else {
            text.split(',').map(str::trim).collect()
        };
        if tokens.len() != 6 {
            return Err(PoseError::WrongCount { got: tokens.len() });
        }
        let mut values = [0.0; 6];
        for ((slot, token), component) in values.iter_mut().zip(&tokens).zip(Component::ALL) {
            let position = component.index() + 1;
            if token.is_empty() {
                return Err(PoseError::EmptyValue { position, component });
            }
            let value: f64 = token.parse().map_err(|_| PoseError::NotANumber {
                position,
                component,
                token: (*token).to_string(),
            })?;
            if !value.is_finite() {
                return Err(PoseError::NonFinite {
                    position,
                    component,
                    value,
                });
            }
            *slot = if degrees && component.is_angle() {
                value.to_radians()
            } else {
                value
            };
        }
        Ok(Pose::from_array(values))
    }

    /// [`Pose::parse`], then refuses angles outside ±180° (±π in radians) with
    /// [`PoseError::AngleOutOfRange`]: what every pose typed by a user goes through.
    ///
    /// ```
    /// use acsg::pose::Pose;
    ///
    /// assert!(Pose::parse_checked("0,0,0,0,0,180", true).is_ok());
    /// let err = Pose::parse_checked("0,0,0,0,0,200", true).unwrap_err();
    /// assert!(err.to_string().contains("outside ±180°"), "{err}");
    /// assert!(err.to_string().contains("-160°"), "{err}");
    /// assert!(Pose::parse_checked("0,0,0,0,0,18", false).is_err()); // 18 rad
    /// ```
    ///
    /// # Errors
    /// Those of [`Pose::parse`], and [`PoseError::AngleOutOfRange`].
    pub fn parse_checked(text: &str, degrees: bool) -> Result<Pose, PoseError> {
        let pose = Pose::parse(text, degrees)?;
        // Check the numbers as typed: a value in degrees converts to radians exactly
        // enough that 180 stays within range, but the message should quote the input.
        let tokens: Vec<&str> = text.split(',').map(str::trim).collect();
        for component in [Component::Rx, Component::Ry, Component::Rz] {
            let i = component.index();
            let value = tokens
                .get(i)
                .and_then(|t| t.parse::<f64>().ok())
                .unwrap_or(pose.get(component));
            if !angle_in_range(value, degrees) {
                return Err(PoseError::AngleOutOfRange {
                    position: i + 1,
                    component,
                    value,
                    degrees,
                });
            }
        }
        Ok(pose)
    }

    /// Inverse of [`Pose::to_affine`]: the pose `X` with `G · [R | t] = transform`.
    ///
    /// The angles are extracted for `R = Rz(rz) · Ry(ry) · Rx(rx)` with
    /// `ry` in `[-π/2, π/2]` and `rx`, `rz` in `[-π, π]`. At gimbal lock
    /// (`ry = ±π/2`, where only `rz ∓ rx` is determined) the choice is `rx = 0`.
    /// Away from gimbal lock the angles are unique up to these ranges.
    ///
    /// Errors with [`PoseError::NotRigid`] when `assembled` or `transform` has a
    /// non-finite entry, a 3x3 part that is not orthonormal (within
    /// [`tolerance::RIGID_REL`]) or a reflection.
    pub fn from_affine(transform: &DAffine3, assembled: &DAffine3) -> Result<Pose, PoseError> {
        check_rigid(assembled, "assembled pose G")?;
        check_rigid(transform, "transform")?;
        let local = assembled.inverse() * *transform;
        check_rigid(&local, "transform relative to G")?;
        let (rx, ry, rz) = euler_zyx(&local.matrix3);
        let t = local.translation;
        Ok(Pose {
            x: t.x,
            y: t.y,
            z: t.z,
            rx,
            ry,
            rz,
        })
    }
}

/// Entry `(row, col)` of a glam (column-major) matrix.
fn at(r: &DMat3, row: usize, col: usize) -> f64 {
    r.col(col)[row]
}

/// Euler angles `(rx, ry, rz)` with `r = Rz(rz) · Ry(ry) · Rx(rx)`.
///
/// With `a = rx`, `b = ry`, `c = rz`, the last row of `r` is
/// `(-sin b, sin a cos b, cos a cos b)`, which gives `a` and `b`; `c` is then read from
/// `r · Rx(a)ᵀ = Rz(c) · Ry(b)`, whose middle column is `(-sin c, cos c, 0)`. Computing
/// `c` from the chosen `a` keeps the result consistent near gimbal lock.
pub(crate) fn euler_zyx(r: &DMat3) -> (f64, f64, f64) {
    let (r21, r22) = (at(r, 2, 1), at(r, 2, 2));
    let cos_b = r21.hypot(r22);
    let rx = if cos_b <= GIMBAL_EPS { 0.0 } else { r21.atan2(r22) };
    let ry = (-at(r, 2, 0)).atan2(cos_b);
    let (sa, ca) = rx.sin_cos();
    let rz = (sa * at(r, 0, 2) - ca * at(r, 0, 1)).atan2(ca * at(r, 1, 1) - sa * at(r, 1, 2));
    (rx, ry, rz)
}

fn check_rigid(m: &DAffine3, what: &'static str) -> Result<(), PoseError> {
    let fail = |reason: String| Err(PoseError::NotRigid { what, reason });
    if !m.is_finite() {
        return fail("it has a NaN or infinite entry".to_string());
    }
    let r = m.matrix3;
    let gram = r.transpose() * r - DMat3::IDENTITY;
    // Overflow can produce NaN entries; count them as infinitely far from orthonormal.
    let dev = gram
        .to_cols_array()
        .iter()
        .map(|v| if v.is_nan() { f64::INFINITY } else { v.abs() })
        .fold(0.0_f64, f64::max);
    if dev > RIGID_TOL {
        return fail(format!(
            "its 3x3 part is not orthonormal (max |RᵀR - I| = {dev:.3e} > {RIGID_TOL:e}); \
             scale and shear are not allowed"
        ));
    }
    let det = r.determinant();
    if det < 0.0 {
        return fail(format!(
            "its 3x3 part has determinant {det:.6}, a reflection, not a rotation"
        ));
    }
    Ok(())
}

/// The box of admissible poses `X_min <= X <= X_max`, componentwise (Eq. 24).
///
/// Angles are compared as plain numbers in radians: no wrapping modulo 2π.
/// Build with [`Bounds::try_new`] or [`Bounds::from_degrees`], which validate; the
/// fields are public, so a `Bounds` made by hand or deserialized can be checked with
/// [`Bounds::validate`]. No method panics, even on invalid bounds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bounds {
    /// Lower corner `X_min`.
    pub min: Pose,
    /// Upper corner `X_max`.
    pub max: Pose,
}

impl Bounds {
    /// Bounds from `[x, y, z, rx, ry, rz]` corners, angles in radians.
    ///
    /// Errors with [`PoseError::InvalidBounds`] listing every non-finite value and every
    /// inverted pair (`min > max`), each naming its component.
    pub fn try_new(min: [f64; 6], max: [f64; 6]) -> Result<Bounds, PoseError> {
        check_bounds(&min, &max, false)?;
        Ok(Bounds {
            min: Pose::from_array(min),
            max: Pose::from_array(max),
        })
    }

    /// Like [`Bounds::try_new`], but the three angle components of `min` and `max`
    /// are given in degrees (error messages quote them in degrees too), and must lie
    /// within ±180° ([`MAX_ANGLE_DEGREES`]).
    pub fn from_degrees(min: [f64; 6], max: [f64; 6]) -> Result<Bounds, PoseError> {
        check_bounds(&min, &max, true)?;
        let radians = |a: [f64; 6]| {
            let mut out = a;
            for v in &mut out[3..] {
                *v = v.to_radians();
            }
            Pose::from_array(out)
        };
        Ok(Bounds {
            min: radians(min),
            max: radians(max),
        })
    }

    /// Checks these bounds as [`Bounds::try_new`] does.
    pub fn validate(&self) -> Result<(), PoseError> {
        check_bounds(&self.min.to_array(), &self.max.to_array(), false)
    }

    /// `true` when every component of `pose` lies in its interval widened by
    /// `tol_len` (x, y, z) or `tol_ang` (rx, ry, rz; radians). Negative or NaN
    /// tolerances count as zero; a NaN pose component is never contained.
    #[must_use]
    pub fn contains(&self, pose: &Pose, tol_len: f64, tol_ang: f64) -> bool {
        let (tol_len, tol_ang) = (tol_len.max(0.0), tol_ang.max(0.0));
        let (lo, hi, v) = (self.min.to_array(), self.max.to_array(), pose.to_array());
        Component::ALL.iter().all(|c| {
            let i = c.index();
            let tol = if c.is_angle() { tol_ang } else { tol_len };
            v[i] >= lo[i] - tol && v[i] <= hi[i] + tol
        })
    }

    /// The nearest pose inside the bounds: each component clamped to `[min, max]`.
    /// Poses inside are returned unchanged; a NaN component becomes `min`.
    #[must_use]
    pub fn clamp(&self, pose: &Pose) -> Pose {
        let (lo, hi, mut v) = (self.min.to_array(), self.max.to_array(), pose.to_array());
        for i in 0..6 {
            // `f64::max` ignores NaN and, unlike `f64::clamp`, this never panics.
            v[i] = v[i].max(lo[i]).min(hi[i]);
        }
        Pose::from_array(v)
    }

    /// The middle of the box, `(min + max) / 2` componentwise.
    #[must_use]
    pub fn center(&self) -> Pose {
        let (lo, hi) = (self.min.to_array(), self.max.to_array());
        Pose::from_array(std::array::from_fn(|i| 0.5 * lo[i] + 0.5 * hi[i]))
    }

    /// The two halves of the box cut across component `k` (`0..6`, as
    /// [`Pose::to_array`] orders them) at its middle: upper first.
    #[must_use]
    pub(crate) fn halves(&self, k: usize) -> Vec<Bounds> {
        let (lo, hi) = (self.min.to_array(), self.max.to_array());
        let mid = 0.5 * (lo[k] + hi[k]);
        let (mut upper_lo, mut lower_hi) = (lo, hi);
        upper_lo[k] = mid;
        lower_hi[k] = mid;
        [(upper_lo, hi), (lo, lower_hi)]
            .into_iter()
            .filter_map(|(l, h)| Bounds::try_new(l, h).ok())
            .collect()
    }

    /// The widths `max - min` of the six intervals (angles in radians).
    #[must_use]
    pub fn width(&self) -> [f64; 6] {
        let (lo, hi) = (self.min.to_array(), self.max.to_array());
        std::array::from_fn(|i| hi[i] - lo[i])
    }

    /// `true` when `component` is fixed (`min == max`), i.e. it does not vary.
    #[must_use]
    pub fn is_fixed(&self, component: Component) -> bool {
        self.min.get(component) == self.max.get(component)
    }
}

fn check_bounds(min: &[f64; 6], max: &[f64; 6], degrees: bool) -> Result<(), PoseError> {
    let mut problems = Vec::new();
    for c in Component::ALL {
        let (lo, hi) = (min[c.index()], max[c.index()]);
        let unit = if degrees && c.is_angle() { "°" } else { "" };
        for (which, v) in [("min", lo), ("max", hi)] {
            if !v.is_finite() {
                problems.push(format!("{which} bound on {c} is {v}; bounds must be finite"));
            }
        }
        if lo > hi {
            problems.push(format!(
                "bound on {c} is inverted: min {lo}{unit} > max {hi}{unit}; swap them"
            ));
        }
        if degrees && c.is_angle() {
            for (which, v) in [("min", lo), ("max", hi)] {
                if v.is_finite() && !angle_in_range(v, true) {
                    problems.push(format!(
                        "{which} bound on {c} is {v}°, outside ±180° (angles are degrees and are not wrapped; \
                         for a free turn give -180:180)"
                    ));
                }
            }
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(PoseError::InvalidBounds { problems })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    const EPS: f64 = 1e-12;

    fn close(a: DVec3, b: DVec3) -> bool {
        a.abs_diff_eq(b, EPS)
    }

    #[test]
    fn parse_accepts_spaces_and_degrees() {
        let p = Pose::parse(" 1 ,2,  -3.5e1 , 90,-45, 180 ", true).unwrap();
        assert_eq!((p.x, p.y, p.z), (1.0, 2.0, -35.0));
        crate::assert_near!(p.rx, FRAC_PI_2, EPS);
        crate::assert_near!(p.ry, -FRAC_PI_2 / 2.0, EPS);
        crate::assert_near!(p.rz, std::f64::consts::PI, EPS);
        let r = Pose::parse("1,2,3,0.5,0.25,-1", false).unwrap();
        assert_eq!(r.to_array(), [1.0, 2.0, 3.0, 0.5, 0.25, -1.0]);
    }

    #[test]
    fn parse_wrong_count() {
        for (text, got) in [("1,2,3,4,5", 5), ("1,2,3,4,5,6,7", 7), ("", 0), ("   ", 0), ("1", 1)] {
            let err = Pose::parse(text, false).unwrap_err();
            assert_eq!(err, PoseError::WrongCount { got });
            assert_eq!(
                err.to_string(),
                format!("expected 6 comma-separated values x,y,z,rx,ry,rz, got {got}")
            );
        }
    }

    #[test]
    fn parse_not_a_number() {
        let err = Pose::parse("1,2,3,abc,5,6", false).unwrap_err();
        assert_eq!(err.to_string(), "value 4 (rx) is 'abc', not a number");
        let err = Pose::parse("1 2,2,3,4,5,6", false).unwrap_err();
        assert_eq!(err.to_string(), "value 1 (x) is '1 2', not a number");
        let err = Pose::parse("1,2,3,4,5,6deg", true).unwrap_err();
        assert_eq!(err.to_string(), "value 6 (rz) is '6deg', not a number");
    }

    #[test]
    fn parse_empty_value() {
        let err = Pose::parse("1,,3,4,5,6", false).unwrap_err();
        assert_eq!(
            err,
            PoseError::EmptyValue {
                position: 2,
                component: Component::Y
            }
        );
        assert_eq!(err.to_string(), "value 2 (y) is empty, expected a number");
    }

    #[test]
    fn angles_outside_half_turn_are_refused() {
        for text in ["0,0,0,180,-180,0", "0,0,0,0,0,-180"] {
            assert!(Pose::parse_checked(text, true).is_ok(), "{text}");
        }
        let err = Pose::parse_checked("0,0,0,0,180.5,0", true).unwrap_err();
        assert!(matches!(
            err,
            PoseError::AngleOutOfRange {
                position: 5,
                component: Component::Ry,
                ..
            }
        ));
        assert!(err.to_string().contains("-179.5°"), "{err}");
        assert!(Pose::parse_checked("0,0,0,3.1415927,0,0", false).is_ok());
        let err = Pose::parse_checked("0,0,0,0,0,18", false).unwrap_err();
        assert!(err.to_string().contains("18 rad"), "{err}");
        // Lengths have no range.
        assert!(Pose::parse_checked("1e6,-1e6,0,0,0,0", true).is_ok());
        let err = Bounds::from_degrees([0.0, 0.0, 0.0, 0.0, 0.0, -190.0], [0.0, 0.0, 0.0, 0.0, 0.0, 10.0]).unwrap_err();
        assert!(
            err.to_string().contains("min bound on rz is -190°, outside ±180°"),
            "{err}"
        );
        assert!(Bounds::from_degrees([0.0, 0.0, 0.0, -180.0, 0.0, 0.0], [0.0, 0.0, 0.0, 180.0, 0.0, 0.0]).is_ok());
    }

    #[test]
    fn parse_non_finite() {
        let err = Pose::parse("1,2,3,4,NaN,6", false).unwrap_err();
        assert_eq!(err.to_string(), "value 5 (ry) is NaN; every value must be finite");
        let err = Pose::parse("inf,2,3,4,5,6", false).unwrap_err();
        assert_eq!(err.to_string(), "value 1 (x) is inf; every value must be finite");
        let err = Pose::parse("1,2,1e400,4,5,6", false).unwrap_err();
        assert!(matches!(
            err,
            PoseError::NonFinite {
                component: Component::Z,
                ..
            }
        ));
    }

    #[test]
    fn display_round_trips_through_parse() {
        let p = Pose::from_array([0.1, -2.0e-7, 3.0e12, 1.0 / 3.0, -0.7, 3.0]);
        assert_eq!(Pose::parse(&p.to_string(), false).unwrap(), p);
    }

    #[test]
    fn rx_90_sends_y_axis_to_z_axis() {
        let p = Pose::from_array([0.0, 0.0, 0.0, FRAC_PI_2, 0.0, 0.0]);
        let m = p.to_affine(&DAffine3::IDENTITY);
        assert!(close(m.transform_vector3(DVec3::Y), DVec3::Z));
        assert!(close(m.transform_vector3(DVec3::Z), -DVec3::Y));
        assert!(close(m.transform_vector3(DVec3::X), DVec3::X));
    }

    #[test]
    fn ry_90_and_rz_90_elementary() {
        let ry = Pose::from_array([0.0, 0.0, 0.0, 0.0, FRAC_PI_2, 0.0]).rotation();
        assert!(close(ry * DVec3::Z, DVec3::X));
        let rz = Pose::from_array([0.0, 0.0, 0.0, 0.0, 0.0, FRAC_PI_2]).rotation();
        assert!(close(rz * DVec3::X, DVec3::Y));
    }

    /// Row-major 3x3 product, written out by hand.
    fn mul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
            }
        }
        c
    }

    #[test]
    fn combined_rotation_matches_hand_written_product() {
        let (x, y, z, a, b, c) = (0.3, -1.2, 2.5, 0.4, -0.9, 2.1);
        let (sa, ca) = (f64::sin(a), f64::cos(a));
        let (sb, cb) = (f64::sin(b), f64::cos(b));
        let (sc, cc) = (f64::sin(c), f64::cos(c));
        let rx = [[1.0, 0.0, 0.0], [0.0, ca, -sa], [0.0, sa, ca]];
        let ry = [[cb, 0.0, sb], [0.0, 1.0, 0.0], [-sb, 0.0, cb]];
        let rz = [[cc, -sc, 0.0], [sc, cc, 0.0], [0.0, 0.0, 1.0]];
        let r = mul(rz, mul(ry, rx));
        let p = [0.7, -0.2, 1.9];
        let expected: Vec<f64> = (0..3)
            .map(|i| r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2] + [x, y, z][i])
            .collect();

        let pose = Pose::from_array([x, y, z, a, b, c]);
        let got = pose
            .to_affine(&DAffine3::IDENTITY)
            .transform_point3(DVec3::from_array(p));
        assert!(close(got, DVec3::from_slice(&expected)), "{got} vs {expected:?}");
        let m = pose.matrix(&DAffine3::IDENTITY);
        for i in 0..3 {
            for j in 0..3 {
                crate::assert_near!(m[i][j], r[i][j], EPS);
            }
        }
    }

    #[test]
    fn matrix_layout_is_row_major_with_translation_in_last_column() {
        let pose = Pose::from_array([1.0, 2.0, 3.0, 0.0, 0.0, FRAC_PI_2]);
        let g = DAffine3::from_translation(DVec3::new(10.0, 0.0, 0.0));
        let m = pose.matrix(&g);
        let expected = [
            [0.0, -1.0, 0.0, 11.0],
            [1.0, 0.0, 0.0, 2.0],
            [0.0, 0.0, 1.0, 3.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        for i in 0..4 {
            for j in 0..4 {
                crate::assert_near!(m[i][j], expected[i][j], EPS);
            }
        }
        assert_eq!(m[3], [0.0, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn assembled_pose_is_applied_last() {
        let pose = Pose::from_array([1.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let g = DAffine3::from_rotation_z(FRAC_PI_2);
        // G (R p + t) with p = 0: t = x-axis rotated by G = y-axis.
        assert!(close(pose.to_affine(&g).transform_point3(DVec3::ZERO), DVec3::Y));
    }

    #[test]
    fn from_affine_round_trip_and_identity() {
        let g = DAffine3::from_rotation_y(0.3) * DAffine3::from_translation(DVec3::new(1.0, 2.0, 3.0));
        let pose = Pose::from_array([0.5, -0.25, 4.0, 1.0, -0.5, -2.5]);
        let back = Pose::from_affine(&pose.to_affine(&g), &g).unwrap();
        for (a, b) in pose.to_array().iter().zip(back.to_array()) {
            crate::assert_near!(*a, b, 1e-12);
        }
        let id = Pose::from_affine(&DAffine3::IDENTITY, &DAffine3::IDENTITY).unwrap();
        assert_eq!(id, Pose::IDENTITY);
    }

    #[test]
    fn from_affine_gimbal_lock_sets_rx_zero() {
        for ry in [FRAC_PI_2, -FRAC_PI_2] {
            let pose = Pose::from_array([0.0, 0.0, 0.0, 0.7, ry, 0.2]);
            let m = pose.to_affine(&DAffine3::IDENTITY);
            let back = Pose::from_affine(&m, &DAffine3::IDENTITY).unwrap();
            assert_eq!(back.rx, 0.0);
            crate::assert_near!(back.ry, ry, 1e-7);
            assert!(back.to_affine(&DAffine3::IDENTITY).abs_diff_eq(m, 1e-12));
        }
    }

    #[test]
    fn from_affine_rejects_non_rigid() {
        let id = DAffine3::IDENTITY;
        let scaled = DAffine3::from_scale(DVec3::new(1.0, 2.0, 1.0));
        let err = Pose::from_affine(&scaled, &id).unwrap_err();
        assert!(matches!(err, PoseError::NotRigid { what: "transform", .. }), "{err}");
        assert!(err.to_string().contains("not orthonormal"), "{err}");

        let mirror = DAffine3::from_scale(DVec3::new(-1.0, 1.0, 1.0));
        let err = Pose::from_affine(&mirror, &id).unwrap_err();
        assert!(err.to_string().contains("reflection"), "{err}");

        let nan = DAffine3::from_translation(DVec3::new(f64::NAN, 0.0, 0.0));
        let err = Pose::from_affine(&nan, &id).unwrap_err();
        assert!(err.to_string().contains("NaN or infinite"), "{err}");

        let err = Pose::from_affine(&id, &scaled).unwrap_err();
        assert!(
            matches!(
                err,
                PoseError::NotRigid {
                    what: "assembled pose G",
                    ..
                }
            ),
            "{err}"
        );
        let huge = DAffine3::from_scale(DVec3::splat(1e300));
        assert!(Pose::from_affine(&huge, &id).is_err());
    }

    #[test]
    fn bounds_report_every_problem() {
        let err = Bounds::try_new(
            [0.0, f64::NAN, 0.0, 0.3, 0.0, 0.0],
            [1.0, 1.0, -1.0, 0.1, f64::INFINITY, 0.0],
        )
        .unwrap_err();
        let PoseError::InvalidBounds { problems } = &err else {
            panic!("wrong error {err:?}");
        };
        assert_eq!(
            problems,
            &vec![
                "min bound on y is NaN; bounds must be finite".to_string(),
                "bound on z is inverted: min 0 > max -1; swap them".to_string(),
                "bound on rx is inverted: min 0.3 > max 0.1; swap them".to_string(),
                "max bound on ry is inf; bounds must be finite".to_string(),
            ]
        );
        assert!(err.to_string().starts_with("invalid bounds: min bound on y is NaN;"));
    }

    #[test]
    fn bounds_from_degrees() {
        let b = Bounds::from_degrees([-1.0, -1.0, 0.0, -5.0, 0.0, -90.0], [1.0, 1.0, 0.0, 5.0, 0.0, 90.0]).unwrap();
        assert_eq!(b.min.x, -1.0);
        crate::assert_near!(b.max.rz, FRAC_PI_2, EPS);
        crate::assert_near!(b.min.rx, -5.0_f64.to_radians(), EPS);
        let err = Bounds::from_degrees([0.0; 6], [0.0, 0.0, 0.0, 0.0, 0.0, -10.0]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "invalid bounds: bound on rz is inverted: min 0° > max -10°; swap them"
        );
    }

    #[test]
    fn bounds_queries() {
        let b = Bounds::try_new([-1.0, 0.0, 2.0, -0.1, 0.0, 0.0], [1.0, 4.0, 2.0, 0.1, 0.0, 0.5]).unwrap();
        assert_eq!(b.center().to_array(), [0.0, 2.0, 2.0, 0.0, 0.0, 0.25]);
        assert_eq!(b.width(), [2.0, 4.0, 0.0, 0.2, 0.0, 0.5]);
        let fixed: Vec<Component> = Component::ALL.into_iter().filter(|&c| b.is_fixed(c)).collect();
        assert_eq!(fixed, [Component::Z, Component::Ry]);

        assert!(b.contains(&b.center(), 0.0, 0.0));
        assert!(b.contains(&b.min, 0.0, 0.0) && b.contains(&b.max, 0.0, 0.0));
        let outside_len = Pose { x: 1.001, ..b.center() };
        assert!(!b.contains(&outside_len, 0.0, 0.0));
        assert!(b.contains(&outside_len, 0.01, 0.0));
        assert!(!b.contains(&outside_len, 0.0, 0.01));
        let outside_ang = Pose {
            ry: -0.001,
            ..b.center()
        };
        assert!(!b.contains(&outside_ang, 0.01, 0.0));
        assert!(b.contains(&outside_ang, 0.0, 0.01));
        assert!(!b.contains(
            &Pose {
                x: f64::NAN,
                ..b.center()
            },
            1.0,
            1.0
        ));
        assert!(!b.contains(&outside_len, -5.0, f64::NAN));

        let far = Pose::from_array([5.0, -5.0, 0.0, f64::NAN, 1.0, f64::NEG_INFINITY]);
        assert_eq!(b.clamp(&far).to_array(), [1.0, 0.0, 2.0, -0.1, 0.0, 0.0]);
        assert_eq!(b.clamp(&b.center()), b.center());
    }

    #[test]
    fn invalid_bounds_built_by_hand_do_not_panic() {
        let b = Bounds {
            min: Pose::from_array([1.0; 6]),
            max: Pose::from_array([0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0]),
        };
        assert!(b.validate().is_err());
        let _ = (
            b.clamp(&Pose::IDENTITY),
            b.center(),
            b.width(),
            b.contains(&Pose::IDENTITY, 0.0, 0.0),
        );
    }

    #[test]
    fn serde_round_trip() {
        let b = Bounds::try_new([-1.0; 6], [1.0; 6]).unwrap();
        let json = serde_json::to_string(&b).unwrap();
        assert!(json.contains("\"rx\""));
        assert_eq!(serde_json::from_str::<Bounds>(&json).unwrap(), b);
    }
}
