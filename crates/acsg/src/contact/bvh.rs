//! A bounding volume hierarchy over element boxes: the broad phase that makes a part
//! with thousands of faces cost little more than its near elements.

use glam::DAffine3;

use crate::geometry::Aabb;

#[derive(Clone, Debug)]
enum Node {
    Leaf { bounds: Aabb, item: u32 },
    Inner { bounds: Aabb, left: u32, right: u32 },
}

impl Node {
    fn bounds(&self) -> &Aabb {
        match self {
            Node::Leaf { bounds, .. } | Node::Inner { bounds, .. } => bounds,
        }
    }
}

/// A static hierarchy of boxes, built by median splits along the longest axis.
#[derive(Clone, Debug, Default)]
pub(crate) struct Bvh {
    nodes: Vec<Node>,
}

impl Bvh {
    /// Builds the hierarchy over `boxes`; queries report indices into it.
    #[must_use]
    pub(crate) fn new(boxes: &[Aabb]) -> Bvh {
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * boxes.len()),
        };
        let mut items: Vec<u32> = (0..boxes.len() as u32).collect();
        if !items.is_empty() {
            bvh.build(boxes, &mut items);
        }
        bvh
    }

    fn build(&mut self, boxes: &[Aabb], items: &mut [u32]) -> u32 {
        if let [item] = items {
            self.nodes.push(Node::Leaf {
                bounds: boxes[*item as usize],
                item: *item,
            });
            return (self.nodes.len() - 1) as u32;
        }
        let bounds = items
            .iter()
            .skip(1)
            .fold(boxes[items[0] as usize], |b, &i| b.union(&boxes[i as usize]));
        let extent = bounds.max - bounds.min;
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |&a, &b| {
            boxes[a as usize].center()[axis].total_cmp(&boxes[b as usize].center()[axis])
        });
        let slot = self.nodes.len();
        self.nodes.push(Node::Leaf { bounds, item: u32::MAX });
        let (left_items, right_items) = items.split_at_mut(mid);
        let left = self.build(boxes, left_items);
        let right = self.build(boxes, right_items);
        self.nodes[slot] = Node::Inner { bounds, left, right };
        slot as u32
    }

    /// Calls `visit` with every item whose box overlaps `query` (the tests check the
    /// tree's shape through it; the crate itself queries pairs of trees).
    #[cfg(test)]
    pub(crate) fn query(&self, query: &Aabb, mut visit: impl FnMut(u32)) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            if !node.bounds().overlaps(query) {
                continue;
            }
            match node {
                Node::Leaf { item, .. } => visit(*item),
                Node::Inner { left, right, .. } => stack.extend([*left, *right]),
            }
        }
    }
}

impl Bvh {
    /// Calls `visit(i, j)` for every item `i` of this hierarchy and `j` of `other` whose
    /// boxes overlap once `other`'s are mapped by `t` and grown by `margin`. Only pairs
    /// of nearby subtrees are visited, so the cost follows the near pairs.
    pub(crate) fn query_pairs(&self, other: &Bvh, t: &DAffine3, margin: f64, visit: impl FnMut(u32, u32)) {
        self.pairs(
            other,
            |_, node: &Node| node.bounds().transformed(t).inflated(margin),
            visit,
        );
    }

    /// [`Bvh::query_pairs`] for traversals that visit most of `other`: its boxes are
    /// mapped once, up front, rather than at every visit.
    pub(crate) fn query_pairs_dense(&self, other: &Bvh, t: &DAffine3, margin: f64, visit: impl FnMut(u32, u32)) {
        let placed: Vec<Aabb> = other
            .nodes
            .iter()
            .map(|n| n.bounds().transformed(t).inflated(margin))
            .collect();
        self.pairs(other, |j, _| placed[j as usize], visit);
    }

    /// The traversal: `placed(j, node)` is `other`'s node `j` in this hierarchy's frame.
    fn pairs(&self, other: &Bvh, placed_box: impl Fn(u32, &Node) -> Aabb, mut visit: impl FnMut(u32, u32)) {
        if self.nodes.is_empty() || other.nodes.is_empty() {
            return;
        }
        let mut stack = vec![(0u32, 0u32)];
        while let Some((i, j)) = stack.pop() {
            let (a, b) = (&self.nodes[i as usize], &other.nodes[j as usize]);
            let placed = placed_box(j, b);
            if !a.bounds().overlaps(&placed) {
                continue;
            }
            match (a, b) {
                (Node::Leaf { item: x, .. }, Node::Leaf { item: y, .. }) => visit(*x, *y),
                (Node::Leaf { .. }, Node::Inner { left, right, .. }) => stack.extend([(i, *left), (i, *right)]),
                (Node::Inner { left, right, .. }, Node::Leaf { .. }) => stack.extend([(*left, j), (*right, j)]),
                (
                    Node::Inner {
                        bounds: ba,
                        left: la,
                        right: ra,
                    },
                    Node::Inner {
                        left: lb, right: rb, ..
                    },
                ) => {
                    // Split the larger box.
                    let size_a = (ba.max - ba.min).length_squared();
                    let size_b = (placed.max - placed.min).length_squared();
                    if size_a >= size_b {
                        stack.extend([(*la, j), (*ra, j)]);
                    } else {
                        stack.extend([(i, *lb), (i, *rb)]);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn queries_match_brute_force() {
        let mut state = 0x1234_5678_9abc_def0_u64;
        let mut rand = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % 10_000) as f64 / 100.0
        };
        let boxes: Vec<Aabb> = (0..500)
            .map(|_| {
                let p = DVec3::new(rand(), rand(), rand());
                Aabb {
                    min: p,
                    max: p + DVec3::new(rand(), rand(), rand()) * 0.05,
                }
            })
            .collect();
        let bvh = Bvh::new(&boxes);
        for _ in 0..100 {
            let p = DVec3::new(rand(), rand(), rand());
            let q = Aabb {
                min: p,
                max: p + DVec3::splat(rand() * 0.2),
            };
            let mut found = Vec::new();
            bvh.query(&q, |i| found.push(i));
            found.sort_unstable();
            let expected: Vec<u32> = (0..boxes.len() as u32)
                .filter(|&i| boxes[i as usize].overlaps(&q))
                .collect();
            assert_eq!(found, expected);
        }
    }
}
