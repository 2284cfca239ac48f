//! The binary tree collapsed into 8-wide nodes: a ray tests eight boxes in
//! two SIMD registers, and the path from root to leaf has a third of the
//! nodes, so a large mesh costs a third of the dependent memory loads.

use super::build::{prim_count, Aabb, BuildNode};
use glam::Vec4;

/// Children per node.
pub(super) const WIDTH: usize = 8;
/// SIMD registers of four lanes per plane.
pub(super) const GROUPS: usize = WIDTH / 4;

/// The children's boxes, one child per SIMD lane; 256 bytes, four cache
/// lines. Unused lanes hold an inverted box (min +inf, max -inf), which the
/// sign-ordered slab test never enters.
#[repr(C, align(64))]
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Node {
    /// min x, min y, min z, max x, max y, max z of the children.
    pub(super) planes: [[Vec4; GROUPS]; 6],
    /// An inner child's node index, or a leaf child's first primitive.
    pub(super) child: [u32; WIDTH],
    /// A leaf child's primitive count; 0 for an inner child.
    pub(super) count: [u32; WIDTH],
}

impl Node {
    const EMPTY: Node = Node {
        planes: [
            [Vec4::INFINITY; GROUPS],
            [Vec4::INFINITY; GROUPS],
            [Vec4::INFINITY; GROUPS],
            [Vec4::NEG_INFINITY; GROUPS],
            [Vec4::NEG_INFINITY; GROUPS],
            [Vec4::NEG_INFINITY; GROUPS],
        ],
        child: [0; WIDTH],
        count: [0; WIDTH],
    };

    fn set_bounds(&mut self, lane: usize, bounds: &Aabb) {
        let (g, l) = (lane / 4, lane % 4);
        for axis in 0..3 {
            self.planes[axis][g][l] = bounds.min[axis];
            self.planes[axis + 3][g][l] = bounds.max[axis];
        }
    }

    /// The box of one lane, for tests.
    #[cfg(test)]
    pub(super) fn bounds(&self, lane: usize) -> ([f32; 3], [f32; 3]) {
        let p = self.planes.map(|plane| plane[lane / 4][lane % 4]);
        ([p[0], p[1], p[2]], [p[3], p[4], p[5]])
    }
}

/// Writes the tree into `nodes`, root first, each node before its subtrees;
/// leaves keep the binary tree's primitive order.
pub(super) fn flatten(root: &BuildNode, nodes: &mut Vec<Node>) {
    write(root, 0, nodes);
}

/// Writes `node`'s lanes (and their subtrees) and returns its index; `first`
/// is the index of its first primitive.
fn write(node: &BuildNode, mut first: u32, nodes: &mut Vec<Node>) -> u32 {
    let index = nodes.len();
    nodes.push(Node::EMPTY);
    let mut wide = Node::EMPTY;
    let (children, len) = children(node);
    for (lane, &child) in children[..len].iter().enumerate() {
        let (bounds, count) = match child {
            BuildNode::Leaf { bounds, count } => (bounds, *count as u32),
            BuildNode::Inner { bounds, .. } => (bounds, 0),
        };
        wide.set_bounds(lane, bounds);
        wide.count[lane] = count;
        wide.child[lane] = if count > 0 {
            first
        } else {
            write(child, first, nodes)
        };
        first += prim_count(child) as u32;
    }
    nodes[index] = wide;
    index as u32
}

/// Up to `WIDTH` nodes that together hold `node`'s primitives, in order:
/// its two children, then the largest inner one replaced by its own two,
/// until they are `WIDTH` or all leaves. A leaf root is its own one child.
fn children(node: &BuildNode) -> ([&BuildNode; WIDTH], usize) {
    let mut children = [node; WIDTH];
    let mut len = 1;
    while len < WIDTH {
        let largest = children[..len]
            .iter()
            .enumerate()
            .filter_map(|(k, c)| match c {
                BuildNode::Inner {
                    bounds,
                    left,
                    right,
                    ..
                } => Some((k, bounds.half_area(), left.as_ref(), right.as_ref())),
                BuildNode::Leaf { .. } => None,
            })
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let Some((k, _, left, right)) = largest else {
            break;
        };
        children.copy_within(k + 1..len, k + 2);
        (children[k], children[k + 1]) = (left, right);
        len += 1;
    }
    (children, len)
}
