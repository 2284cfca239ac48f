//! The splits the BVH is built from: top-down, with the surface area
//! heuristic over binned centroids. A `Part` is a run of primitives with its
//! split decided; `wide.rs` splits parts until a node has its lanes.

use super::tri4::Tri4;
use crate::geometry::Shape;
use bytemuck::Zeroable;
use glam::{BVec3A, Vec3A, Vec4};

/// Bins per axis of the SAH sweep.
const BINS: usize = 16;
/// Largest leaf the SAH may choose (four blocks of four triangles); larger
/// nodes are always split.
const MAX_LEAF: usize = 16;
/// Cost of visiting a node, relative to one primitive test: an 8-wide node
/// reads two to four cache lines and tests up to eight boxes. (Against 1,
/// in one process: under half the nodes, the bunny 1 % slower, the 1.1M
/// bunny 2 % faster.)
pub(super) const TRAVERSAL_COST: f32 = 2.0;
/// Cost of testing four triangles at once, relative to one.
pub(super) const BLOCK_COST: f32 = 1.5;
/// Deeper nodes become leaves, so the traversal stack cannot overflow.
pub(super) const MAX_DEPTH: usize = 60;
/// Nodes with more primitives than this build their children in parallel.
pub(super) const PARALLEL_BUILD: usize = 4096;
/// How much a primitive's box is widened, relative to its coordinates.
const BOX_PAD: f32 = 64.0 * f32::EPSILON;

#[derive(Debug, Clone, Copy)]
pub(super) struct Aabb {
    pub(super) min: Vec3A,
    pub(super) max: Vec3A,
}

impl Aabb {
    pub(super) const EMPTY: Aabb = Aabb {
        min: Vec3A::INFINITY,
        max: Vec3A::NEG_INFINITY,
    };

    pub(super) fn grow(&mut self, other: &Aabb) {
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

/// A primitive's box and object index, partitioned in place during the
/// build: 32 bytes, the id and the kind in the boxes' unused fourth lanes
/// (the build moves every primitive once per level; at 48 bytes that was
/// a third more memory to move).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct BuildPrim {
    /// The box's minimum, and the object index's bits in `w` (`ID_BITS`).
    lo: Vec4,
    /// The box's maximum, and 1 in `w` for a sphere (spheres and triangles
    /// are tested differently, so never share a leaf).
    hi: Vec4,
}

/// Flipped in an object index's bits before they go in a float lane: the
/// lanes take part in the boxes' arithmetic, and the bits of an index below
/// 2^23 are a denormal float, which the processor takes a slow path for
/// (the build was 5 % slower). With bit 30 flipped, no index below 2^30 is.
const ID_BITS: u32 = 1 << 30;

/// The box from `min` to `max`, widened in proportion to its coordinates'
/// size: a test may round a ray that passes just outside its primitive into
/// a hit (Moller-Trumbore at an edge; the sphere's quadratic for a ray that
/// grazes it, as one along an axis at the height of its top does), and
/// such a ray must still enter the box.
fn widened(min: Vec3A, max: Vec3A) -> Aabb {
    let size = min.abs().max(max.abs()).max_element() + (max - min).max_element();
    let pad = Vec3A::splat(size * BOX_PAD);
    Aabb {
        min: min - pad,
        max: max + pad,
    }
}

impl BuildPrim {
    /// None for a plane: it has no finite box (the BVH tests planes apart).
    pub(super) fn new(shape: &Shape, id: u32) -> Option<BuildPrim> {
        let bounds = match shape {
            Shape::Triangle(t) => {
                let (a, b, c) = (Vec3A::from(t.v0), Vec3A::from(t.v1), Vec3A::from(t.v2));
                widened(a.min(b).min(c), a.max(b).max(c))
            }
            Shape::Sphere(s) => {
                let (min, max) = s.bounds();
                widened(min.into(), max.into())
            }
            // Instances are the primitives of a tree of their own (`instances.rs`).
            Shape::Plane(_) | Shape::Instance(_) => return None,
        };
        let sphere = matches!(shape, Shape::Sphere(_));
        Some(BuildPrim {
            lo: bounds.min.extend(f32::from_bits(id ^ ID_BITS)),
            hi: bounds.max.extend(if sphere { 1.0 } else { 0.0 }),
        })
    }

    /// A primitive of box `min`..`max`, built as a triangle is (never
    /// split from its neighbours by kind): an instance of the instance tree.
    pub(super) fn boxed(min: glam::Vec3, max: glam::Vec3, id: u32) -> BuildPrim {
        BuildPrim {
            lo: min.extend(f32::from_bits(id ^ ID_BITS)),
            hi: max.extend(0.0),
        }
    }

    pub(super) fn id(&self) -> u32 {
        self.lo.w.to_bits() ^ ID_BITS
    }

    pub(super) fn sphere(&self) -> bool {
        self.hi.w != 0.0
    }

    #[inline(always)]
    fn bounds(&self) -> Aabb {
        Aabb {
            min: Vec3A::from_vec4(self.lo),
            max: Vec3A::from_vec4(self.hi),
        }
    }

    /// Twice the box centre: only compared, never used as a point.
    #[inline(always)]
    fn centroid2(&self) -> Vec3A {
        Vec3A::from_vec4(self.lo) + Vec3A::from_vec4(self.hi)
    }
}

/// The build's primitives, six to a triangle block's bytes, in the vector
/// the blocks will be packed into: the blocks are then written over the
/// pages the primitives touched, where a page's first touch is a fault of
/// the kernel's (18 ms for the 1.1M bunny's 53 MB of blocks).
pub(super) struct PrimStore {
    blocks: Vec<Tri4>,
    six: [BuildPrim; 6],
    count: usize,
}

impl PrimStore {
    /// Room for the primitives of `objects` objects and, reserved but not
    /// touched, for a third of a block per object: as many as most trees'
    /// leaves need.
    pub(super) fn with_capacity(objects: usize) -> PrimStore {
        PrimStore {
            blocks: Vec::with_capacity(objects / 3 + 1),
            six: [BuildPrim::zeroed(); 6],
            count: 0,
        }
    }

    pub(super) fn extend(&mut self, p: Option<BuildPrim>) {
        let Some(p) = p else { return };
        self.six[self.count % 6] = p;
        self.count += 1;
        if self.count.is_multiple_of(6) {
            self.blocks.push(bytemuck::cast(self.six));
        }
    }

    /// The blocks, and how many primitives their bytes begin with.
    pub(super) fn finish(mut self) -> (Vec<Tri4>, usize) {
        if !self.count.is_multiple_of(6) {
            self.blocks.push(bytemuck::cast(self.six));
        }
        (self.blocks, self.count)
    }
}

/// One SAH split candidate: axis, first bin of the right side, cost, and
/// the boxes of the two sides (the union of their bins' boxes).
#[derive(Debug, Clone, Copy)]
struct Split {
    axis: usize,
    bin: usize,
    cost: f32,
    sides: [Aabb; 2],
}

/// The boxes of a set of primitives and of their centroids.
#[derive(Debug, Clone, Copy)]
pub(super) struct Extent {
    pub(super) bounds: Aabb,
    pub(super) centroids: Aabb,
    spheres: usize,
}

impl Extent {
    const EMPTY: Extent = Extent {
        bounds: Aabb::EMPTY,
        centroids: Aabb::EMPTY,
        spheres: 0,
    };

    fn grow(&mut self, p: &BuildPrim) {
        self.bounds.grow(&p.bounds());
        self.centroids.grow_point(p.centroid2());
        self.spheres += p.sphere() as usize;
    }

    pub(super) fn of(items: &[BuildPrim]) -> Extent {
        let mut extent = Extent::EMPTY;
        items.iter().for_each(|p| extent.grow(p));
        extent
    }
}

/// How the SAH divides a part: not at all, at a bin boundary, (when every
/// centroid is in one place) in two halves by count, or (a leaf that would
/// mix them) spheres from triangles.
#[derive(Debug, Clone, Copy)]
enum Cut {
    Leaf,
    Bins(Split),
    Halve,
    Kind,
}

/// A run of primitives, `items[start..end]` of the node being built, with
/// its boxes, its depth in the binary tree of splits, and its cut decided.
#[derive(Debug, Clone, Copy)]
pub(super) struct Part {
    pub(super) start: usize,
    pub(super) end: usize,
    pub(super) extent: Extent,
    depth: usize,
    cut: Cut,
}

impl Part {
    /// All of `items`: the root.
    pub(super) fn root(items: &[BuildPrim]) -> Part {
        Part::new(items, 0, items.len(), Extent::of(items), 0)
    }

    /// `items[start..end]`, whose boxes are `extent`, with its cut decided.
    fn new(items: &[BuildPrim], start: usize, end: usize, extent: Extent, depth: usize) -> Part {
        let run = &items[start..end];
        let count = run.len();
        // A split costs at least a node's visit: cheaper leaves are kept
        // without a search (four triangles or fewer).
        let cut = if leaf_cost(count) <= TRAVERSAL_COST || depth >= MAX_DEPTH {
            Cut::Leaf
        } else {
            match best_split(run, &extent.bounds, &extent.centroids) {
                Some(s) if count > MAX_LEAF || s.cost < leaf_cost(count) => Cut::Bins(s),
                None if count > MAX_LEAF => Cut::Halve,
                _ => Cut::Leaf,
            }
        };
        let mixed = extent.spheres > 0 && extent.spheres < count;
        let cut = match cut {
            Cut::Leaf if mixed => Cut::Kind,
            cut => cut,
        };
        Part {
            start,
            end,
            extent,
            depth,
            cut,
        }
    }

    pub(super) fn len(&self) -> usize {
        self.end - self.start
    }

    pub(super) fn is_leaf(&self) -> bool {
        matches!(self.cut, Cut::Leaf)
    }

    /// The same part, its items now the first of a slice of their own.
    pub(super) fn rebased(&self) -> Part {
        Part {
            start: 0,
            end: self.len(),
            ..*self
        }
    }

    /// For a leaf of its node: its least cost (block tests times box area)
    /// as 1, 2, .. `lanes` lanes of the node, each cut by the cheapest
    /// binned split of the part it divides (`least_costs`); None for a
    /// part that is not a leaf or too large to be worth the search.
    ///
    /// The greedy SAH charges a split a node's visit, but a split within
    /// the node being built costs only a box test, which its SIMD lanes
    /// take anyway: the walls of a room, one leaf whose box is the room
    /// (every ray inside it tested every wall), become flat leaves a ray
    /// meets one or two of. A split may pay only with the splits after it
    /// (two walls of four cut off leave two blocks), so the cost looks
    /// ahead over the lanes.
    pub(super) fn costs_within_node(&self, items: &[BuildPrim], lanes: usize) -> Option<Vec<f32>> {
        let eligible = matches!(self.cut, Cut::Leaf)
            && (2..=MAX_LEAF).contains(&self.len())
            && self.depth < MAX_DEPTH;
        eligible.then(|| {
            let mut run = items[self.start..self.end].to_vec();
            least_costs(&mut run, &self.rebased(), lanes)
        })
    }

    /// The same part cut by its cheapest binned split, to be split within
    /// its node (see `costs_within_node`).
    pub(super) fn cut_within_node(&self, items: &[BuildPrim]) -> Option<Part> {
        let run = &items[self.start..self.end];
        let s = best_split(run, &self.extent.bounds, &self.extent.centroids)?;
        Some(Part {
            cut: Cut::Bins(s),
            ..*self
        })
    }

    /// Divides the part by its cut, reordering its items: the two halves,
    /// each with its own cut decided; None for a leaf.
    pub(super) fn split(&self, items: &mut [BuildPrim]) -> Option<[Part; 2]> {
        let run = &mut items[self.start..self.end];
        let (mid, left, right) = match self.cut {
            Cut::Leaf => return None,
            Cut::Bins(s) => partition(run, &self.extent, &s),
            Cut::Halve => halves(run, run.len() / 2),
            Cut::Kind => {
                let (mid, ..) = partition_by(run, |p| BVec3A::splat(p.sphere()));
                halves(run, mid)
            }
        };
        let mid = self.start + mid;
        let depth = self.depth + 1;
        Some([
            Part::new(items, self.start, mid, left, depth),
            Part::new(items, mid, self.end, right, depth),
        ])
    }
}

/// The least cost (block tests times box area) of `part` of `run` as 1,
/// 2, .. `lanes` leaves, each cut by the cheapest binned split of the part
/// it divides; reorders `run`.
fn least_costs(run: &mut [BuildPrim], part: &Part, lanes: usize) -> Vec<f32> {
    let leaf = part.extent.bounds.half_area() * lane_cost(part);
    let mut costs = vec![leaf; lanes];
    let split = (lanes > 1 && part.len() > 1)
        .then(|| {
            best_split(
                &run[part.start..part.end],
                &part.extent.bounds,
                &part.extent.centroids,
            )
        })
        .flatten();
    let Some(s) = split else {
        return costs;
    };
    let (mid, left, right) = partition(&mut run[part.start..part.end], &part.extent, &s);
    let side = |start, end, extent| Part {
        start,
        end,
        extent,
        depth: part.depth + 1,
        cut: Cut::Leaf,
    };
    let mid = part.start + mid;
    let left = least_costs(run, &side(part.start, mid, left), lanes - 1);
    let right = least_costs(run, &side(mid, part.end, right), lanes - 1);
    for n in 2..=lanes {
        // n lanes: a for the left side, n - a for the right.
        for a in 1..n {
            costs[n - 1] = costs[n - 1].min(left[a - 1] + right[n - a - 1]);
        }
    }
    costs
}

/// The cost of testing a leaf lane's primitives: triangles go four at a
/// time, spheres one by one (each about a block's test). The greedy SAH
/// costs spheres as blocks of four (`leaf_cost`): the lab's trees.
fn lane_cost(part: &Part) -> f32 {
    if part.extent.spheres > 0 {
        part.len() as f32 * BLOCK_COST
    } else {
        leaf_cost(part.len())
    }
}

/// The cost of testing `count` primitives: triangles go four at a time.
pub(super) fn leaf_cost(count: usize) -> f32 {
    count.div_ceil(4) as f32 * BLOCK_COST
}

/// Bins for a node of `count` primitives: fewer for small nodes, whose
/// sweep over the bins would cost more than the binning. One bin per eight
/// primitives: 5 % less build time than one per primitive on the 1.1M
/// bunny, the tree's SAH cost the same within 0.05 %.
fn bins_for(count: usize) -> usize {
    (count / 8).clamp(4, BINS)
}

/// 1.5 * 2^23: floats from 2^23 to 2^24 step by one, so `x + ROUNDER`
/// holds x rounded to a whole number in its low bits (for |x| < 2^22).
const ROUNDER: f32 = 12_582_912.0;

/// The grid a part is binned on, over its centroids' box: the one piece of
/// arithmetic that bins a centroid, which the binning, the partition and
/// `first_of_bin` all go through, so that they cannot disagree.
#[derive(Debug, Clone, Copy)]
struct Grid {
    min: Vec3A,
    /// Bins per unit of each axis; 0 on a flat axis.
    scale: Vec3A,
    /// Within the last bin, kept off its far edge.
    top: Vec3A,
}

impl Grid {
    fn new(centroids: &Aabb, bins: usize) -> Grid {
        let extent = centroids.max - centroids.min;
        let scale = Vec3A::splat(bins as f32) / extent;
        Grid {
            min: centroids.min,
            scale: Vec3A::select(extent.cmpgt(Vec3A::ZERO), scale, Vec3A::ZERO),
            top: Vec3A::splat(bins as f32 - 0.75),
        }
    }

    /// The same grid on axis `axis` alone, in every lane.
    fn along(&self, axis: usize) -> Grid {
        Grid {
            min: Vec3A::splat(self.min[axis]),
            scale: Vec3A::splat(self.scale[axis]),
            top: self.top,
        }
    }

    /// `ROUNDER + k` in each lane, k the bin of that lane of `c`: its
    /// position on the grid, kept within the bins, less a half and rounded.
    /// Rounding by adding `ROUNDER` takes no saturating conversion (`as
    /// u32` needs two compares a lane); a position on a bin boundary may go
    /// to either side, the same in binning and partition.
    #[inline(always)]
    fn rounded(&self, c: Vec3A) -> Vec3A {
        let at = ((c - self.min) * self.scale).max(Vec3A::ZERO).min(self.top);
        at - Vec3A::splat(0.5) + Vec3A::splat(ROUNDER)
    }

    /// The bin of each lane of `c`.
    #[inline(always)]
    fn bins(&self, c: Vec3A) -> [usize; 3] {
        self.rounded(c)
            .to_array()
            .map(|x| x.to_bits().wrapping_sub(ROUNDER.to_bits()) as usize)
    }
}

/// The cheapest binned SAH split over the three axes, with its cost in
/// units of one primitive test; None if the centroids do not spread.
fn best_split(items: &[BuildPrim], bounds: &Aabb, centroids: &Aabb) -> Option<Split> {
    // Most parts are small: their bins are cleared at the size they use.
    match bins_for(items.len()) {
        // (`bins` is 4 here: a constant to the compiler.)
        bins if bins <= 4 => best_split_in::<4>(items, bounds, centroids, 4),
        bins if bins <= 8 => best_split_in::<8>(items, bounds, centroids, bins),
        bins => best_split_in::<BINS>(items, bounds, centroids, bins),
    }
}

/// Each axis's bins: the boxes of the primitives whose centroids fall in
/// them, and their counts; of one axis alone (`only`), or of all three.
#[derive(Clone, Copy)]
struct Bins<const N: usize> {
    boxes: [[Aabb; N]; 3],
    counts: [[u32; N]; 3],
    only: Option<usize>,
}

/// Parts of at least this many primitives are binned into two sets of bins,
/// even and odd primitives apart: a mesh's neighbours mostly fall in the
/// same bin, and each update of a bin waits for the one before it.
const TWO_SETS: usize = 64;

/// Parts of at least this many primitives are binned on one axis, the one
/// their centroids spread most along, where the cheapest split nearly
/// always lies: 10 % less build time at 1.1M triangles; the tree's SAH
/// cost 2.5 % higher there (1.8 % on the bunny), and the renders as fast
/// within 1 %. Smaller parts, whose bins cost little, take all three.
const ONE_AXIS: usize = 64;

impl<const N: usize> Bins<N> {
    const EMPTY: Self = Bins {
        boxes: [[Aabb::EMPTY; N]; 3],
        counts: [[0; N]; 3],
        only: None,
    };

    /// Bins for a part of `count` primitives whose centroids' grid is
    /// `grid`: of one axis for a large part (`ONE_AXIS`).
    fn for_part(count: usize, grid: &Grid, centroids: &Aabb) -> Self {
        Bins {
            only: (count >= ONE_AXIS).then(|| widest_axis(grid, centroids)),
            ..Self::EMPTY
        }
    }

    /// The axes binned.
    fn axes(&self) -> std::ops::Range<usize> {
        self.only.map_or(0..3, |axis| axis..axis + 1)
    }

    /// Adds `p`, whose bin on each axis is `at` (below `N`).
    #[inline(always)]
    fn add(&mut self, p: &BuildPrim, at: [usize; 3]) {
        if let Some(axis) = self.only {
            let bin = at[axis] & (N - 1);
            self.boxes[axis][bin].grow(&p.bounds());
            self.counts[axis][bin] += 1;
            return;
        }
        for (axis, bin) in at.into_iter().enumerate() {
            // `N` is a power of two: the mask keeps the bin and drops the
            // bounds check.
            let bin = bin & (N - 1);
            self.boxes[axis][bin].grow(&p.bounds());
            self.counts[axis][bin] += 1;
        }
    }

    fn merge(&mut self, other: &Self) {
        for axis in 0..3 {
            for bin in 0..N {
                self.boxes[axis][bin].grow(&other.boxes[axis][bin]);
                self.counts[axis][bin] += other.counts[axis][bin];
            }
        }
    }

    /// Adds `items`, binned on `grid` (filled in place: returned, the
    /// bins of a large part were copied, 1.7 KB each time).
    #[inline(always)]
    fn add_all(&mut self, items: &[BuildPrim], grid: &Grid) {
        let at = |p: &BuildPrim| grid.bins(p.centroid2());
        if items.len() < TWO_SETS {
            items.iter().for_each(|p| self.add(p, at(p)));
            return;
        }
        let mut odd = Bins {
            only: self.only,
            ..Self::EMPTY
        };
        let pairs = items.chunks_exact(2);
        pairs.remainder().iter().for_each(|p| self.add(p, at(p)));
        for pair in pairs {
            self.add(&pair[0], at(&pair[0]));
            odd.add(&pair[1], at(&pair[1]));
        }
        self.merge(&odd);
    }
}

/// `best_split` with room for `N` bins, of which it uses `bins`.
#[inline(always)]
fn best_split_in<const N: usize>(
    items: &[BuildPrim],
    bounds: &Aabb,
    centroids: &Aabb,
    bins: usize,
) -> Option<Split> {
    let grid = Grid::new(centroids, bins);
    let mut binned = Bins::<N>::for_part(items.len(), &grid, centroids);
    binned.add_all(items, &grid);
    let Bins { boxes, counts, .. } = &binned;
    let parent_area = bounds.half_area();
    let mut best: Option<Split> = None;
    for axis in binned.axes() {
        if grid.scale[axis] == 0.0 {
            continue;
        }
        let (boxes, counts) = (&boxes[axis], &counts[axis]);
        // Right-side box and area * count for each first-right bin, swept
        // from the end.
        let mut right = [(Aabb::EMPTY, 0f32); N];
        let (mut acc, mut n) = (Aabb::EMPTY, 0u32);
        for b in (1..bins).rev() {
            acc.grow(&boxes[b]);
            n += counts[b];
            right[b] = (acc, acc.half_area() * leaf_cost(n as usize));
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0u32);
        for b in 1..bins {
            acc.grow(&boxes[b - 1]);
            n += counts[b - 1];
            if n == 0 || n as usize == items.len() {
                continue;
            }
            // Each candidate's cost divided as a whole: comparing the sums
            // before the division split ties the division rounds together,
            // and mirror-image scenes built other trees.
            let cost = TRAVERSAL_COST
                + (acc.half_area() * leaf_cost(n as usize) + right[b].1) / parent_area;
            if best.is_none_or(|s| cost < s.cost) {
                let sides = [acc, right[b].0];
                best = Some(Split {
                    axis,
                    bin: b,
                    cost,
                    sides,
                });
            }
        }
    }
    best
}

/// The axis the centroids spread most along, of those `grid` bins them on
/// (the first of equals).
fn widest_axis(grid: &Grid, centroids: &Aabb) -> usize {
    let binned = grid.scale.cmpgt(Vec3A::ZERO);
    let spread = Vec3A::select(binned, centroids.max - centroids.min, Vec3A::splat(-1.0));
    if spread.x >= spread.y && spread.x >= spread.z {
        0
    } else if spread.y >= spread.z {
        1
    } else {
        2
    }
}

/// Puts the primitives of bins below the split's first right bin first;
/// returns how many, and the extents of both sides, whose boxes the
/// binning found (`split.sides`).
fn partition(items: &mut [BuildPrim], extent: &Extent, split: &Split) -> (usize, Extent, Extent) {
    let grid = Grid::new(&extent.centroids, bins_for(items.len())).along(split.axis);
    let (mid, centroids, left_spheres) = if items.len() >= FIND_THRESHOLD {
        let first = first_of_bin(&grid, split.bin);
        match split.axis {
            0 => partition_by(items, before::<0>(first)),
            1 => partition_by(items, before::<1>(first)),
            _ => partition_by(items, before::<2>(first)),
        }
    } else {
        match split.axis {
            0 => partition_by(items, below::<0>(grid, split.bin)),
            1 => partition_by(items, below::<1>(grid, split.bin)),
            _ => partition_by(items, below::<2>(grid, split.bin)),
        }
    };
    let side = |k: usize, spheres| Extent {
        bounds: split.sides[k],
        centroids: centroids[k],
        spheres,
    };
    let left = side(0, left_spheres);
    (mid, left, side(1, extent.spheres - left_spheres))
}

/// Parts of at least this many primitives are partitioned by comparing
/// each centroid with the first one of the right side's bins, found once
/// (a search of 32 steps) instead of binning every centroid again.
const FIND_THRESHOLD: usize = 256;

/// The least coordinate whose bin on `grid` (one axis, `Grid::along`) is
/// `bin` or above, found by bisecting the floats in order. The bin of a
/// coordinate never decreases as the coordinate grows (each step of
/// `Grid::rounded` is monotonic), so a coordinate is in a bin below `bin`
/// exactly when it is below that.
fn first_of_bin(grid: &Grid, bin: usize) -> f32 {
    let bin_at = |c: f32| grid.bins(Vec3A::splat(c))[0];
    // The finite floats as integers in their order (both zeros as 0).
    let order = |x: f32| {
        let magnitude = i64::from(x.to_bits() & 0x7fff_ffff);
        if x.is_sign_negative() {
            -magnitude
        } else {
            magnitude
        }
    };
    let float = |k: i64| {
        let bits = k.unsigned_abs() as u32;
        f32::from_bits(if k < 0 { bits | 0x8000_0000 } else { bits })
    };
    // bin_at(lo) < bin <= bin_at(hi): -MAX is in bin 0, MAX in the last.
    let (mut lo, mut hi) = (order(-f32::MAX), order(f32::MAX));
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if bin_at(float(mid)) >= bin {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    float(hi)
}

/// Whether a primitive's centroid on axis `AXIS` is below `first`, in every
/// lane of the mask (`first_of_bin`). A NaN goes left, as `below` sends it.
#[inline(always)]
fn before<const AXIS: usize>(first: f32) -> impl Fn(&BuildPrim) -> BVec3A {
    let first = Vec3A::splat(first);
    move |p| !Vec3A::splat(p.centroid2()[AXIS]).cmpge(first)
}

/// Whether a primitive's bin on axis `AXIS` of `grid` (that axis alone,
/// `Grid::along`) is below `bin`, in every lane of the mask. The rounded
/// position `ROUNDER + k` is compared as a float with `ROUNDER + bin`:
/// both are whole numbers where floats step by one.
#[inline(always)]
fn below<const AXIS: usize>(grid: Grid, bin: usize) -> impl Fn(&BuildPrim) -> BVec3A {
    let first_right = Vec3A::splat(ROUNDER + bin as f32);
    move |p| {
        grid.rounded(Vec3A::splat(p.centroid2()[AXIS]))
            .cmplt(first_right)
    }
}

/// The extents of `items[..mid]` and `items[mid..]`.
fn halves(items: &[BuildPrim], mid: usize) -> (usize, Extent, Extent) {
    (mid, Extent::of(&items[..mid]), Extent::of(&items[mid..]))
}

/// Puts the primitives for which `left` holds first; returns how many, the
/// boxes of both sides' centroids, and the spheres on the left. Without a
/// branch on the side, as a mesh's primitives come to either side
/// unpredictably: every step swaps (a right one swapped with the first right
/// one keeps the order's invariant), and both sides' boxes are kept in
/// registers, each growing by the centroid or by an empty box. (12 % less
/// build time on the bunny than branching, the same tree.)
#[inline(always)]
fn partition_by(
    items: &mut [BuildPrim],
    left: impl Fn(&BuildPrim) -> BVec3A,
) -> (usize, [Aabb; 2], usize) {
    let [mut lo, mut hi] = [Aabb::EMPTY; 2];
    let mut spheres = 0;
    let mut mid = 0;
    for i in 0..items.len() {
        let p = items[i];
        let on_left = left(&p);
        let c = p.centroid2();
        lo.min = lo.min.min(Vec3A::select(on_left, c, Vec3A::INFINITY));
        lo.max = lo.max.max(Vec3A::select(on_left, c, Vec3A::NEG_INFINITY));
        hi.min = hi.min.min(Vec3A::select(on_left, Vec3A::INFINITY, c));
        hi.max = hi.max.max(Vec3A::select(on_left, Vec3A::NEG_INFINITY, c));
        let is_left = (on_left.bitmask() & 1) as usize;
        spheres += is_left & usize::from(p.sphere());
        items.swap(i, mid);
        mid += is_left;
    }
    (mid, [lo, hi], spheres)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A primitive whose doubled centroid is `c` on every axis.
    fn at(c: f32) -> BuildPrim {
        BuildPrim::boxed(Vec3::splat(c / 2.0), Vec3::splat(c / 2.0), 7)
    }

    /// Coordinates around `first` and spread over the grid, from a
    /// fixed-seed generator.
    fn probes(first: f32, min: f32, extent: f32) -> Vec<f32> {
        let mut near: Vec<f32> = (-64..64)
            .map(|k: i32| f32::from_bits(first.to_bits().wrapping_add_signed(k)))
            .collect();
        let mut state = 0x2545_f491_u32;
        near.extend((0..2000).map(|_| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            min + extent * (1.4 * (state >> 8) as f32 / (1 << 24) as f32 - 0.2)
        }));
        near
    }

    #[test]
    fn a_large_part_binned_on_one_axis_is_split_across_its_gap() {
        // Two rows of small boxes along y with a gap between them, and a
        // narrower spread along x: binned on y alone, the split is the gap.
        let items: Vec<BuildPrim> = (0..200u32)
            .map(|k| {
                let y = k as f32 + if k >= 120 { 500.0 } else { 0.0 };
                let x = (k % 7) as f32 * 20.0;
                BuildPrim::boxed(Vec3::new(x, y, 0.0), Vec3::new(x + 0.5, y + 0.5, 0.5), k)
            })
            .collect();
        let extent = Extent::of(&items);
        assert_eq!(
            widest_axis(&Grid::new(&extent.centroids, 16), &extent.centroids),
            1
        );
        let split = best_split(&items, &extent.bounds, &extent.centroids).expect("a split");
        assert_eq!(split.axis, 1);
        let mut items = items;
        let (mid, ..) = partition(&mut items, &extent, &split);
        assert_eq!(mid, 120);
        assert!(items[..mid].iter().all(|p| p.id() < 120));
    }

    #[test]
    fn the_widest_axis_is_the_first_of_equals_among_those_binned() {
        let widest = |min: Vec3, max: Vec3| {
            let centroids = Aabb {
                min: min.into(),
                max: max.into(),
            };
            widest_axis(&Grid::new(&centroids, 8), &centroids)
        };
        assert_eq!(widest(Vec3::ZERO, Vec3::new(1.0, 3.0, 2.0)), 1);
        assert_eq!(widest(Vec3::ZERO, Vec3::new(2.0, 1.0, 2.0)), 0);
        assert_eq!(widest(Vec3::ZERO, Vec3::new(1.0, 2.0, 2.0)), 1);
        assert_eq!(widest(Vec3::splat(-5.0), Vec3::new(-4.0, -5.0, 0.0)), 2);
        // An infinite spread is not binned (its scale is 0): the finite one is.
        assert_eq!(widest(Vec3::ZERO, Vec3::new(f32::INFINITY, 1.0, 0.0)), 1);
    }

    #[test]
    fn the_first_coordinate_of_a_bin_divides_the_centroids_as_their_bins_do() {
        let grids = [
            (0.0, 1.0),
            (-3.75, 0.001),
            (1.0e6, 3.0e5),
            (-2.0e-3, 7.0e-3),
        ];
        for (min, extent) in grids {
            for bins in [4, 7, 16] {
                let centroids = Aabb {
                    min: Vec3A::splat(min),
                    max: Vec3A::splat(min + extent),
                };
                let grid = Grid::new(&centroids, bins);
                for bin in 1..bins {
                    let first = first_of_bin(&grid.along(0), bin);
                    let is_left = before::<0>(first);
                    for c in probes(first, min, extent) {
                        let binned = grid.bins(at(c).centroid2())[0];
                        assert_eq!(
                            is_left(&at(c)).all(),
                            binned < bin,
                            "grid {min} + {extent}, {bins} bins, bin {bin}, coordinate {c}"
                        );
                        assert_eq!(is_left(&at(c)).any(), is_left(&at(c)).all());
                    }
                }
            }
        }
    }

    #[test]
    fn a_nan_centroid_goes_left_both_ways() {
        let centroids = Aabb {
            min: Vec3A::ZERO,
            max: Vec3A::ONE,
        };
        let grid = Grid::new(&centroids, 16);
        let nan = at(f32::NAN);
        assert_eq!(grid.bins(nan.centroid2())[0], 0);
        assert!(before::<0>(first_of_bin(&grid.along(0), 5))(&nan).all());
        assert!(below::<0>(grid.along(0), 5)(&nan).all());
    }
}
