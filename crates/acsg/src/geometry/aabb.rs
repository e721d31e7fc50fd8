//! Axis-aligned boxes of 3-D points: a part's bounds, the boxes of a bounding volume
//! hierarchy, the broad phase of the penetration test.

use glam::{DAffine3, DMat3, DVec3};

/// An axis-aligned box: the points `p` with `min <= p <= max` componentwise.
///
/// The box around no points is empty (`min` at +∞, `max` at −∞): it overlaps nothing
/// and its diagonal is 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: DVec3,
    /// Largest corner.
    pub max: DVec3,
}

impl Aabb {
    /// The empty box.
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    };

    /// The box around some points.
    #[must_use]
    pub fn around(points: impl IntoIterator<Item = DVec3>) -> Aabb {
        points.into_iter().fold(Aabb::EMPTY, |b, p| Aabb {
            min: b.min.min(p),
            max: b.max.max(p),
        })
    }

    /// Whether the box holds no point.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Length of the diagonal (0 for an empty box).
    #[must_use]
    pub fn diagonal(&self) -> f64 {
        if self.is_empty() {
            0.0
        } else {
            (self.max - self.min).length()
        }
    }

    /// The centre.
    #[must_use]
    pub fn center(&self) -> DVec3 {
        (self.min + self.max) * 0.5
    }

    /// The smallest box holding both.
    #[must_use]
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// This box grown by `r` on every side.
    #[must_use]
    pub fn inflated(&self, r: f64) -> Aabb {
        Aabb {
            min: self.min - DVec3::splat(r),
            max: self.max + DVec3::splat(r),
        }
    }

    /// Whether the boxes share a point.
    #[must_use]
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// The Euclidean distance between the boxes (0 when they overlap).
    #[must_use]
    pub fn gap(&self, other: &Aabb) -> f64 {
        (self.min - other.max)
            .max(other.min - self.max)
            .max(DVec3::ZERO)
            .length()
    }

    /// The largest gap between the boxes along a coordinate axis: positive when they
    /// are apart (a lower bound of [`Aabb::gap`]), negative when they overlap.
    #[must_use]
    pub fn axis_gap(&self, other: &Aabb) -> f64 {
        (other.min - self.max).max(self.min - other.max).max_element()
    }

    /// The box around this box mapped by an affine transform.
    #[must_use]
    pub fn transformed(&self, t: &DAffine3) -> Aabb {
        let center = t.transform_point3(self.center());
        let m = t.matrix3;
        let abs = DMat3::from_cols(m.x_axis.abs(), m.y_axis.abs(), m.z_axis.abs());
        let half = abs * ((self.max - self.min) * 0.5);
        Aabb {
            min: center - half,
            max: center + half,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_box_around_no_points_is_empty() {
        let empty = Aabb::around([]);
        assert!(empty.is_empty());
        assert_eq!(empty.diagonal(), 0.0);
        let unit = Aabb::around([DVec3::ZERO, DVec3::ONE]);
        assert!(!unit.is_empty() && !empty.overlaps(&unit));
        assert_eq!(unit.diagonal(), 3.0_f64.sqrt());
    }

    #[test]
    fn gaps_between_boxes() {
        let a = Aabb::around([DVec3::ZERO, DVec3::ONE]);
        let b = Aabb::around([DVec3::new(4.0, 5.0, 0.0), DVec3::new(5.0, 6.0, 1.0)]);
        assert_eq!(a.gap(&b), 5.0);
        assert_eq!(a.axis_gap(&b), 4.0);
        assert_eq!(a.axis_gap(&a.inflated(-0.25)), -0.75);
    }
}
