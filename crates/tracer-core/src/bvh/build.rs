//! The binary tree the BVH is built as: top-down, with the surface area
//! heuristic over binned centroids; `wide.rs` then collapses it.

use crate::shapes::Shape;
use glam::{UVec3, Vec3A};

/// Bins per axis of the SAH sweep.
const BINS: usize = 16;
/// Largest leaf the SAH may choose; larger nodes are always split.
const MAX_LEAF: usize = 8;
/// Cost of visiting a node, relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;
/// Deeper nodes become leaves, so the traversal stack cannot overflow.
pub(super) const MAX_DEPTH: usize = 60;
/// Nodes with more primitives than this build their children in parallel.
const PARALLEL_BUILD: usize = 4096;
/// How much a triangle's box is widened, relative to its coordinates.
const TRIANGLE_PAD: f32 = 64.0 * f32::EPSILON;

#[derive(Debug, Clone, Copy)]
pub(super) struct Aabb {
    pub(super) min: Vec3A,
    pub(super) max: Vec3A,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        min: Vec3A::INFINITY,
        max: Vec3A::NEG_INFINITY,
    };

    fn grow(&mut self, other: &Aabb) {
        self.min = self.min.min(other.min);
        self.max = self.max.max(other.max);
    }

    fn grow_point(&mut self, p: Vec3A) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    pub(super) fn half_area(&self) -> f32 {
        let d = (self.max - self.min).max(Vec3A::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
}

/// A primitive's box and object index, partitioned in place during the build.
#[derive(Debug, Clone, Copy)]
pub(super) struct BuildPrim {
    bounds: Aabb,
    pub(super) id: u32,
}

impl BuildPrim {
    pub(super) fn new(shape: &Shape, id: u32) -> BuildPrim {
        let bounds = match shape {
            Shape::Triangle(t) => {
                let (a, b, c) = (Vec3A::from(t.v0), Vec3A::from(t.v1), Vec3A::from(t.v2));
                let (min, max) = (a.min(b).min(c), a.max(b).max(c));
                // Moller-Trumbore may round a ray that passes just outside an
                // edge into a hit; the box is widened so such a ray still
                // enters it, in proportion to the coordinates' size.
                let size = min.abs().max(max.abs()).max_element() + (max - min).max_element();
                let pad = Vec3A::splat(size * TRIANGLE_PAD);
                Aabb {
                    min: min - pad,
                    max: max + pad,
                }
            }
            Shape::Sphere(s) => {
                let (c, r) = (Vec3A::from(s.center), Vec3A::splat(s.radius));
                Aabb {
                    min: c - r,
                    max: c + r,
                }
            }
        };
        BuildPrim { bounds, id }
    }

    /// Twice the box centre: only compared, never used as a point.
    fn centroid2(&self) -> Vec3A {
        self.bounds.min + self.bounds.max
    }
}

pub(super) enum BuildNode {
    Leaf {
        bounds: Aabb,
        count: usize,
    },
    Inner {
        bounds: Aabb,
        count: usize,
        left: Box<BuildNode>,
        right: Box<BuildNode>,
    },
}

/// One SAH split candidate: axis, first bin of the right side, cost.
#[derive(Clone, Copy)]
struct Split {
    axis: usize,
    bin: usize,
    cost: f32,
}

/// The boxes of a set of primitives and of their centroids.
#[derive(Debug, Clone, Copy)]
struct Extent {
    bounds: Aabb,
    centroids: Aabb,
}

impl Extent {
    const EMPTY: Extent = Extent {
        bounds: Aabb::EMPTY,
        centroids: Aabb::EMPTY,
    };

    fn grow(&mut self, p: &BuildPrim) {
        self.bounds.grow(&p.bounds);
        self.centroids.grow_point(p.centroid2());
    }

    fn of(items: &[BuildPrim]) -> Extent {
        let mut extent = Extent::EMPTY;
        items.iter().for_each(|p| extent.grow(p));
        extent
    }
}

/// The tree over `items`, which it reorders into leaf order.
pub(super) fn build_tree(items: &mut [BuildPrim]) -> BuildNode {
    let extent = Extent::of(items);
    build_node(items, &extent, 0)
}

fn build_node(items: &mut [BuildPrim], extent: &Extent, depth: usize) -> BuildNode {
    let (bounds, count) = (extent.bounds, items.len());
    if count == 1 || depth >= MAX_DEPTH {
        return BuildNode::Leaf { bounds, count };
    }
    let split = best_split(items, &bounds, &extent.centroids);
    let (mid, left, right) = match split {
        Some(s) if count > MAX_LEAF || s.cost < count as f32 => {
            partition(items, &extent.centroids, s.axis, s.bin)
        }
        // Every centroid in one place: halve by count if too many.
        None if count > MAX_LEAF => {
            let mid = count / 2;
            (mid, Extent::of(&items[..mid]), Extent::of(&items[mid..]))
        }
        _ => return BuildNode::Leaf { bounds, count },
    };
    let (lo, hi) = items.split_at_mut(mid);
    let (left, right) = if count > PARALLEL_BUILD {
        rayon::join(
            || build_node(lo, &left, depth + 1),
            || build_node(hi, &right, depth + 1),
        )
    } else {
        (
            build_node(lo, &left, depth + 1),
            build_node(hi, &right, depth + 1),
        )
    };
    BuildNode::Inner {
        bounds,
        count,
        left: Box::new(left),
        right: Box::new(right),
    }
}

/// Bins for a node of `count` primitives: fewer for small nodes, whose
/// sweep over empty bins would cost more than the binning.
fn bins_for(count: usize) -> usize {
    count.clamp(4, BINS)
}

/// Bins per unit of each axis of the centroid box; 0 on a flat axis.
fn bin_scale(centroids: &Aabb, bins: usize) -> Vec3A {
    let extent = centroids.max - centroids.min;
    let scale = Vec3A::splat(bins as f32) / extent;
    Vec3A::select(extent.cmpgt(Vec3A::ZERO), scale, Vec3A::ZERO)
}

/// The bin of a primitive on each axis.
#[inline(always)]
fn bins_of(p: &BuildPrim, centroids: &Aabb, scale: Vec3A, bins: usize) -> UVec3 {
    ((p.centroid2() - centroids.min) * scale)
        .as_uvec3()
        .min(UVec3::splat(bins as u32 - 1))
}

/// The cheapest binned SAH split over the three axes, with its cost in
/// units of one primitive test; None if the centroids do not spread.
fn best_split(items: &[BuildPrim], bounds: &Aabb, centroids: &Aabb) -> Option<Split> {
    let bins = bins_for(items.len());
    let scale = bin_scale(centroids, bins);
    let mut boxes = [[Aabb::EMPTY; BINS]; 3];
    let mut counts = [[0u32; BINS]; 3];
    for p in items {
        let b = bins_of(p, centroids, scale, bins);
        for axis in 0..3 {
            let bin = b[axis] as usize;
            boxes[axis][bin].grow(&p.bounds);
            counts[axis][bin] += 1;
        }
    }
    let parent_area = bounds.half_area();
    let mut best: Option<Split> = None;
    for axis in 0..3 {
        if scale[axis] == 0.0 {
            continue;
        }
        let (boxes, counts) = (&boxes[axis], &counts[axis]);
        // Right-side area * count for each first-right bin, swept from the end.
        let mut right_cost = [0f32; BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, 0u32);
        for b in (1..bins).rev() {
            acc.grow(&boxes[b]);
            n += counts[b];
            right_cost[b] = acc.half_area() * n as f32;
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0u32);
        for b in 1..bins {
            acc.grow(&boxes[b - 1]);
            n += counts[b - 1];
            if n == 0 || n as usize == items.len() {
                continue;
            }
            let cost = TRAVERSAL_COST + (acc.half_area() * n as f32 + right_cost[b]) / parent_area;
            if best.is_none_or(|s| cost < s.cost) {
                best = Some(Split { axis, bin: b, cost });
            }
        }
    }
    best
}

/// Puts the primitives of bins below `bin` first; returns how many, and
/// the extents of both sides.
fn partition(
    items: &mut [BuildPrim],
    centroids: &Aabb,
    axis: usize,
    bin: usize,
) -> (usize, Extent, Extent) {
    let bins = bins_for(items.len());
    let scale = bin_scale(centroids, bins);
    let (mut left, mut right) = (Extent::EMPTY, Extent::EMPTY);
    let mut mid = 0;
    for i in 0..items.len() {
        if (bins_of(&items[i], centroids, scale, bins)[axis] as usize) < bin {
            left.grow(&items[i]);
            items.swap(i, mid);
            mid += 1;
        } else {
            right.grow(&items[i]);
        }
    }
    (mid, left, right)
}

pub(super) fn prim_count(node: &BuildNode) -> usize {
    match node {
        BuildNode::Leaf { count, .. } => *count,
        BuildNode::Inner { count, .. } => *count,
    }
}
