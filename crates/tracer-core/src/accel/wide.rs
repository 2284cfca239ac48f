//! 8-wide nodes: a ray tests eight boxes in two SIMD registers, and the path
//! from root to leaf has a third of the nodes of a binary tree, so a large
//! mesh costs a third of the dependent memory loads. A node's lanes are the
//! parts the SAH's splits give, the largest split first (a binary tree
//! collapsed as it is built, never stored).

use super::build::{leaf_cost, Aabb, BuildPrim, Part, BLOCK_COST, PARALLEL_BUILD, TRAVERSAL_COST};
use glam::Vec4;
use rayon::prelude::*;

/// Marks a leaf lane's `count` as a run of spheres; without it, the count
/// is of triangle blocks.
pub(super) const SPHERE_LEAF: u32 = 1 << 30;

/// Children per node.
pub(super) const WIDTH: usize = 8;
/// Leaves whose box has less than this share of the root box's area are
/// not split within their node (`lanes`): few rays meet them, and the
/// search for the splits doubled the build of the 70k bunny, whose leaves
/// are small, for 8 % less render time. The walls of a room, the floor
/// under a mesh, are near the root.
const WITHIN_NODE_AREA: f32 = 1.0 / 64.0;

/// Halves of a node: four lanes each, one SIMD register per plane.
pub(super) const GROUPS: usize = WIDTH / 4;

/// `count` of an inner lane whose node has more than four lanes.
pub(super) const INNER: u32 = 0;
/// `count` of an inner lane whose node has at most four: only the first
/// half of that node, two of its four cache lines, is read.
pub(super) const INNER_HALF: u32 = u32::MAX - 1;
/// `count` of an unused lane.
const UNUSED: u32 = u32::MAX;

/// The children's boxes, one child per SIMD lane, in two halves of four
/// lanes: 256 bytes, four cache lines. Unused lanes hold an inverted box
/// (min +inf, max -inf), which the sign-ordered slab test never enters.
#[repr(C, align(64))]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct Node {
    pub(super) halves: [Half; GROUPS],
}

/// Four lanes of a node: 128 bytes, two cache lines.
#[repr(C, align(64))]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct Half {
    /// min x, min y, min z, max x, max y, max z of the four children.
    pub(super) planes: [Vec4; 6],
    /// An inner child's node index, or a leaf child's first primitive.
    pub(super) child: [u32; 4],
    /// A leaf child's primitive count; `INNER`, `INNER_HALF` or `UNUSED`.
    pub(super) count: [u32; 4],
}

impl Half {
    const EMPTY: Half = Half {
        planes: [
            Vec4::INFINITY,
            Vec4::INFINITY,
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::NEG_INFINITY,
        ],
        child: [0; 4],
        count: [UNUSED; 4],
    };
}

/// Whether a lane's `count` marks a node, and then how many halves of it
/// hold lanes.
#[inline(always)]
pub(super) fn node_halves(count: u32) -> Option<usize> {
    match count {
        INNER => Some(GROUPS),
        INNER_HALF => Some(1),
        _ => None,
    }
}

/// Whether a lane's `count` marks a leaf.
pub(super) fn is_leaf(count: u32) -> bool {
    count != UNUSED && node_halves(count).is_none()
}

impl Node {
    pub(super) const EMPTY: Node = Node {
        halves: [Half::EMPTY; GROUPS],
    };

    pub(super) fn set_bounds(&mut self, lane: usize, bounds: &Aabb) {
        let half = &mut self.halves[lane / 4];
        for axis in 0..3 {
            half.planes[axis][lane % 4] = bounds.min[axis];
            half.planes[axis + 3][lane % 4] = bounds.max[axis];
        }
    }

    pub(super) fn set(&mut self, lane: usize, child: u32, count: u32) {
        let half = &mut self.halves[lane / 4];
        (half.child[lane % 4], half.count[lane % 4]) = (child, count);
    }

    #[inline(always)]
    pub(super) fn child(&self, lane: usize) -> (u32, u32) {
        let half = &self.halves[lane / 4];
        (half.child[lane % 4], half.count[lane % 4])
    }

    /// The planes of one lane's box, in `Half::planes`' order.
    #[inline(always)]
    pub(super) fn lane_planes(&self, lane: usize) -> [f32; 6] {
        // Spelt out: `map` was left a call in the shadow rays' walk.
        let (planes, k) = (&self.halves[lane / 4].planes, lane % 4);
        [
            planes[0][k],
            planes[1][k],
            planes[2][k],
            planes[3][k],
            planes[4][k],
            planes[5][k],
        ]
    }

    /// The box of one lane.
    fn lane_box(&self, lane: usize) -> Aabb {
        let p = self.halves[lane / 4].planes.map(|plane| plane[lane % 4]);
        Aabb {
            min: glam::Vec3A::new(p[0], p[1], p[2]),
            max: glam::Vec3A::new(p[3], p[4], p[5]),
        }
    }

    /// The box of one lane, for tests.
    #[cfg(test)]
    pub(super) fn bounds(&self, lane: usize) -> ([f32; 3], [f32; 3]) {
        let b = self.lane_box(lane);
        (b.min.to_array(), b.max.to_array())
    }
}

/// Builds the nodes over `items`, reordering them into leaf order: the
/// root first, each node before its subtrees. The nodes are the same
/// whatever the size of the rayon pool.
pub(super) fn build(items: &mut [BuildPrim]) -> Vec<Node> {
    // A reservation, not a bound: leaves hold up to `MAX_LEAF` primitives,
    // so a quarter of the primitive count is more nodes than most trees need.
    let mut nodes = Vec::with_capacity(items.len() / 4 + 1);
    let root = Part::root(items);
    let root_area = root.extent.bounds.half_area();
    write(items, 0, root, &mut nodes, Fork::Root, root_area);
    nodes
}

/// Whether `write` may build a node's subtrees in parallel: only the
/// root's, each into a vector the calling thread allocated. Memory a worker
/// thread allocates and frees stays in its glibc arena, which the rest of
/// the process cannot reuse: nested forks held 17 MB that way at 1.1M
/// triangles on two threads.
#[derive(Clone, Copy, PartialEq)]
enum Fork {
    Root,
    Below,
}

/// Writes the node of `part`, which covers all of `items` (the first being
/// primitive `base`), then the subtrees of its lanes; returns its index and
/// the `count` its parent's lane marks it with.
fn write(
    items: &mut [BuildPrim],
    base: usize,
    part: Part,
    nodes: &mut Vec<Node>,
    fork: Fork,
    root_area: f32,
) -> (u32, u32) {
    let (lanes, len) = lanes(items, part, root_area);
    let lanes = &lanes[..len];
    let index = nodes.len();
    nodes.push(Node::EMPTY);
    let mut node = Node::EMPTY;
    for (lane, p) in lanes.iter().enumerate() {
        node.set_bounds(lane, &p.extent.bounds);
        if p.is_leaf() {
            node.set(lane, (base + p.start) as u32, p.len() as u32);
        }
    }
    // On one thread the subtrees are written in place: built apart, they
    // were copied after, their nodes' pages first touched twice (2-3 % of
    // the 1.1M bunny's build where a page's first touch is dear).
    let parallel = fork == Fork::Root && rayon::current_num_threads() > 1;
    if parallel && items.len() > PARALLEL_BUILD {
        write_subtrees_in_parallel(items, base, lanes, &mut node, nodes, root_area);
    } else {
        for (lane, p) in lanes.iter().enumerate().filter(|(_, p)| !p.is_leaf()) {
            let run = &mut items[p.start..p.end];
            let (child, count) = write(
                run,
                base + p.start,
                p.rebased(),
                nodes,
                Fork::Below,
                root_area,
            );
            node.set(lane, child, count);
        }
    }
    nodes[index] = node;
    let count = if len > 4 { INNER } else { INNER_HALF };
    (index as u32, count)
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
    root_area: f32,
) {
    let mut runs = Vec::with_capacity(lanes.len());
    let mut rest = items;
    for p in lanes {
        let (run, tail) = rest.split_at_mut(p.len());
        // Allocated here, not by the thread that fills it (see `Fork`).
        let subtree = Vec::with_capacity(if p.is_leaf() { 0 } else { run.len() / 4 + 1 });
        runs.push((run, p, subtree));
        rest = tail;
    }
    let subtrees: Vec<Option<(Vec<Node>, u32)>> = runs
        .into_par_iter()
        .map(|(run, p, mut subtree)| {
            (!p.is_leaf()).then(|| {
                let (_, count) = write(
                    run,
                    base + p.start,
                    p.rebased(),
                    &mut subtree,
                    Fork::Below,
                    root_area,
                );
                (subtree, count)
            })
        })
        .collect();
    for (lane, subtree) in subtrees.into_iter().enumerate() {
        let Some((mut subtree, count)) = subtree else {
            continue;
        };
        let offset = nodes.len() as u32;
        for half in subtree.iter_mut().flat_map(|n| &mut n.halves) {
            for k in (0..4).filter(|&k| node_halves(half.count[k]).is_some()) {
                half.child[k] += offset;
            }
        }
        node.set(lane, offset, count);
        nodes.append(&mut subtree);
    }
}

/// Up to `WIDTH` parts that together hold `part`'s primitives, in order:
/// its two halves, then the largest one that is not a leaf split in two,
/// until they are `WIDTH` or all leaves; then, while lanes are free, the
/// leaf whose split within the node saves most (`costs_within_node`),
/// of those a fair share of the rays meets (`WITHIN_NODE_AREA` of the
/// root's box). A leaf is its own one lane.
fn lanes(items: &mut [BuildPrim], part: Part, root_area: f32) -> ([Part; WIDTH], usize) {
    let mut lanes = [part; WIDTH];
    // Each leaf lane's costs as 1, 2, .. lanes, worked out once.
    let mut within: [Option<Vec<f32>>; WIDTH] = Default::default();
    let mut len = 1;
    let area = |p: &Part| p.extent.bounds.half_area();
    while len < WIDTH {
        let largest = lanes[..len]
            .iter()
            .enumerate()
            .filter(|(_, p)| !p.is_leaf())
            .max_by(|a, b| area(a.1).total_cmp(&area(b.1)));
        let k = match largest {
            Some((k, _)) => k,
            None => {
                let min_area = root_area * WITHIN_NODE_AREA;
                let Some(k) = most_saving_split(items, &lanes[..len], min_area, &mut within) else {
                    break;
                };
                let Some(cut) = lanes[k].cut_within_node(items) else {
                    break;
                };
                lanes[k] = cut;
                k
            }
        };
        let Some([left, right]) = lanes[k].split(items) else {
            break;
        };
        lanes.copy_within(k + 1..len, k + 2);
        (lanes[k], lanes[k + 1]) = (left, right);
        within[k + 1..=len].rotate_right(1);
        (within[k], within[k + 1]) = (None, None);
        len += 1;
    }
    (lanes, len)
}

/// Which of the leaf lanes `lanes` to split within their node, the
/// `WIDTH - lanes.len()` free lanes shared among them: of those whose box
/// has at least `min_area`, the one whose split saves most, if one saves
/// anything. `within` keeps each lane's costs.
fn most_saving_split(
    items: &[BuildPrim],
    lanes: &[Part],
    min_area: f32,
    within: &mut [Option<Vec<f32>>; WIDTH],
) -> Option<usize> {
    let free = WIDTH - lanes.len();
    let mut best: Option<(usize, f32)> = None;
    for (k, p) in lanes.iter().enumerate() {
        let costs = within[k].get_or_insert_with(|| {
            let large = p.extent.bounds.half_area() >= min_area;
            large
                .then(|| p.costs_within_node(items, free + 1))
                .flatten()
                .unwrap_or_default()
        });
        let saved = match (costs.first(), costs.get(free)) {
            (Some(one), Some(most)) => one - most,
            _ => continue,
        };
        if saved > 0.0 && best.is_none_or(|(_, s)| saved > s) {
            best = Some((k, saved));
        }
    }
    best.map(|(k, _)| k)
}

/// See `Bvh::sah_cost`.
pub(super) fn sah_cost(nodes: &[Node]) -> f64 {
    let Some(root) = nodes.first() else {
        return 0.0;
    };
    let area = |node: &Node, lane: usize| node.lane_box(lane).half_area() as f64;
    let mut root_box = Aabb::EMPTY;
    for lane in used_lanes(root) {
        root_box.grow(&root.lane_box(lane));
    }
    let mut cost = TRAVERSAL_COST as f64 * root_box.half_area() as f64;
    for node in nodes {
        for lane in used_lanes(node) {
            let (_, count) = node.child(lane);
            cost += area(node, lane)
                * match node_halves(count) {
                    Some(_) => TRAVERSAL_COST as f64,
                    None => packed_leaf_cost(count),
                };
        }
    }
    cost / root_box.half_area() as f64
}

/// The build's cost of a leaf lane as `pack_leaves` marked it: a run of
/// spheres, or blocks of four triangles.
fn packed_leaf_cost(count: u32) -> f64 {
    if count & SPHERE_LEAF != 0 {
        leaf_cost((count & !SPHERE_LEAF) as usize) as f64
    } else {
        (count as f32 * BLOCK_COST) as f64
    }
}

fn used_lanes(node: &Node) -> impl Iterator<Item = usize> + '_ {
    (0..WIDTH).filter(move |&k| node.child(k).1 != UNUSED)
}
