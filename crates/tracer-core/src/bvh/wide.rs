//! 8-wide nodes: a ray tests eight boxes in two SIMD registers, and the path
//! from root to leaf has a third of the nodes of a binary tree, so a large
//! mesh costs a third of the dependent memory loads. A node's lanes are the
//! parts the SAH's splits give, the largest split first (a binary tree
//! collapsed as it is built, never stored).

use super::build::{Aabb, BuildPrim, Part, PARALLEL_BUILD};
use glam::Vec4;
use rayon::prelude::*;

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
    /// A leaf child's primitive count; 0 for an inner child, `u32::MAX`
    /// for an unused lane.
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
        // Not 0, which marks an inner lane: the indices of unused lanes
        // are never moved.
        count: [u32::MAX; WIDTH],
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

/// Builds the nodes over `items`, reordering them into leaf order: the
/// root first, each node before its subtrees. The nodes are the same
/// whatever the size of the rayon pool.
pub(super) fn build(items: &mut [BuildPrim]) -> Vec<Node> {
    // About one node per five primitives: leaves hold one to eight.
    let mut nodes = Vec::with_capacity(items.len() / 4 + 1);
    let root = Part::root(items);
    write(items, 0, root, &mut nodes);
    nodes
}

/// Writes the node of `part`, which covers all of `items` (the first being
/// primitive `base`), then the subtrees of its lanes; returns its index.
fn write(items: &mut [BuildPrim], base: usize, part: Part, nodes: &mut Vec<Node>) -> u32 {
    let (lanes, len) = lanes(items, part);
    let lanes = &lanes[..len];
    let index = nodes.len();
    nodes.push(Node::EMPTY);
    let mut node = Node::EMPTY;
    for (lane, p) in lanes.iter().enumerate() {
        node.set_bounds(lane, &p.extent.bounds);
        if p.is_leaf() {
            node.child[lane] = (base + p.start) as u32;
            node.count[lane] = p.len() as u32;
        } else {
            node.count[lane] = 0;
        }
    }
    if items.len() > PARALLEL_BUILD {
        write_subtrees_in_parallel(items, base, lanes, &mut node, nodes);
    } else {
        for (lane, p) in lanes.iter().enumerate().filter(|(_, p)| !p.is_leaf()) {
            let run = &mut items[p.start..p.end];
            node.child[lane] = write(run, base + p.start, p.rebased(), nodes);
        }
    }
    nodes[index] = node;
    index as u32
}

/// The subtrees of `node`'s inner lanes, each built into a vector of its
/// own on the rayon pool, then appended in lane order with their node
/// indices moved: the same nodes `write` gives one after another.
fn write_subtrees_in_parallel(
    items: &mut [BuildPrim],
    base: usize,
    lanes: &[Part],
    node: &mut Node,
    nodes: &mut Vec<Node>,
) {
    let mut runs = Vec::with_capacity(lanes.len());
    let mut rest = items;
    for p in lanes {
        let (run, tail) = rest.split_at_mut(p.len());
        runs.push((run, p));
        rest = tail;
    }
    let subtrees: Vec<Option<Vec<Node>>> = runs
        .into_par_iter()
        .map(|(run, p)| {
            (!p.is_leaf()).then(|| {
                let mut subtree = Vec::with_capacity(run.len() / 4 + 1);
                write(run, base + p.start, p.rebased(), &mut subtree);
                subtree
            })
        })
        .collect();
    for (lane, subtree) in subtrees.into_iter().enumerate() {
        let Some(mut subtree) = subtree else { continue };
        let offset = nodes.len() as u32;
        for n in &mut subtree {
            for k in (0..WIDTH).filter(|&k| n.count[k] == 0) {
                n.child[k] += offset;
            }
        }
        node.child[lane] = offset;
        nodes.append(&mut subtree);
    }
}

/// Up to `WIDTH` parts that together hold `part`'s primitives, in order:
/// its two halves, then the largest one that is not a leaf split in two,
/// until they are `WIDTH` or all leaves. A leaf is its own one lane.
fn lanes(items: &mut [BuildPrim], part: Part) -> ([Part; WIDTH], usize) {
    let mut lanes = [part; WIDTH];
    let mut len = 1;
    while len < WIDTH {
        let largest = lanes[..len]
            .iter()
            .enumerate()
            .filter(|(_, p)| !p.is_leaf())
            .max_by(|a, b| {
                let area = |p: &Part| p.extent.bounds.half_area();
                area(a.1).total_cmp(&area(b.1))
            });
        let Some((k, _)) = largest else { break };
        let Some([left, right]) = lanes[k].split(items) else {
            break;
        };
        lanes.copy_within(k + 1..len, k + 2);
        (lanes[k], lanes[k + 1]) = (left, right);
        len += 1;
    }
    (lanes, len)
}
