//! What a traversal of the tree keeps: the ray prepared for box tests, the
//! stack of nodes still to visit (one per thread), and the best hit so far.

use super::build::MAX_DEPTH;
use super::tri4::Ray4;
use super::wide::{node_halves, Node, GROUPS, INNER, WIDTH};
use crate::ray::Ray;
use glam::{Vec2, Vec4};
use std::cell::RefCell;
use std::thread::LocalKey;

/// Widens box intervals by a few ulps against the rounding of the slab test
/// (pbrt's `1 + 2 gamma(3)`, with margin). Rays that Moller-Trumbore rounds
/// into a hit just outside an edge are met by the padding of triangle boxes
/// (`build.rs`); neither is a proof for every angle, so the tests compare
/// with brute force.
pub(super) const PAD: f32 = 1.0 + 4.0 * f32::EPSILON;

/// Room on the traversal stack: each level pops one entry and pushes at
/// most `WIDTH`; a split of spheres from triangles may go one below
/// `MAX_DEPTH`.
const STACK: usize = (WIDTH - 1) * (MAX_DEPTH + 1) + 1;

thread_local! {
    /// Each thread's traversal stack, allocated once: zeroing a fresh one
    /// for every ray cost more than a ray that misses the scene.
    static STACKS: RefCell<Vec<Entry>> = const { RefCell::new(Vec::new()) };
    /// The instance tree's: a mesh's own tree is searched (on `STACKS`)
    /// while the instance tree's search is under way.
    static INSTANCE_STACKS: RefCell<Vec<Entry>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with this thread's traversal stack.
#[inline(always)]
pub(super) fn with_stack<R>(f: impl FnOnce(&mut [Entry]) -> R) -> R {
    with_stack_of(&STACKS, f)
}

/// Runs `f` with this thread's stack for the instance tree.
#[inline(always)]
pub(super) fn with_instance_stack<R>(f: impl FnOnce(&mut [Entry]) -> R) -> R {
    with_stack_of(&INSTANCE_STACKS, f)
}

/// Runs `f` with the stack `key`, allocated on its first use.
#[inline(always)]
fn with_stack_of<R>(
    key: &'static LocalKey<RefCell<Vec<Entry>>>,
    f: impl FnOnce(&mut [Entry]) -> R,
) -> R {
    key.with_borrow_mut(|stack| {
        if stack.is_empty() {
            stack.resize(STACK, Entry::ROOT);
        }
        f(stack)
    })
}

/// The best hit so far of a nearest-hit search, and where it is.
#[derive(Clone, Copy)]
pub(super) struct Best {
    pub(super) t: f32,
    pub(super) id: u32,
    pub(super) at: HitAt,
}

#[derive(Clone, Copy)]
pub(super) enum HitAt {
    /// Lane `lane` of triangle block `block`, and the barycentric (u, v) found.
    Triangle {
        block: usize,
        lane: usize,
        uv: Vec2,
    },
    Sphere(usize),
    /// Plane `k` of the list tested beside the tree.
    Plane(usize),
    /// Instance `k` of the instance tree, and where in its mesh's tree.
    Instance {
        k: u32,
        block: u32,
        lane: u32,
        uv: Vec2,
    },
}

impl Best {
    /// No hit yet.
    pub(super) fn none(t_max: f32) -> Best {
        Best {
            t: t_max,
            id: u32::MAX,
            at: HitAt::Sphere(0),
        }
    }

    pub(super) fn found(&self) -> bool {
        self.id != u32::MAX
    }

    /// Whether `t` (within t_min and the limit the test was given) and
    /// `id` make a better hit, as the brute-force loop would take it: once
    /// something is hit, up to and including best_t, an equal distance
    /// winning if its object comes first.
    #[inline(always)]
    pub(super) fn offer(&mut self, t: f32, id: u32, t_max: f32, at: HitAt) {
        if t < self.limit(t_max) && (t < self.t || id < self.id) {
            (self.t, self.id, self.at) = (t, id, at);
        }
    }

    #[inline(always)]
    pub(super) fn limit(&self, t_max: f32) -> f32 {
        if self.id == u32::MAX {
            t_max
        } else {
            next_up(self.t)
        }
    }
}

/// What the traversal precomputes once per ray: origin and inverse
/// direction in every lane, and which plane of each axis the ray meets
/// first (min if it runs toward +, max if toward -).
pub(super) struct RayData {
    pub(super) ray: Ray,
    pub(super) ray4: Ray4,
    origin: [Vec4; 3],
    inv_dir: [Vec4; 3],
    near_plane: [usize; 3],
}

impl RayData {
    pub(super) fn new(ray: &Ray) -> RayData {
        let inv = safe_inverse(ray.dir());
        RayData {
            ray: *ray,
            ray4: Ray4::new(ray),
            origin: ray.origin().to_array().map(Vec4::splat),
            inv_dir: inv.map(Vec4::splat),
            near_plane: [0, 1, 2].map(|axis| if inv[axis] < 0.0 { axis + 3 } else { axis }),
        }
    }
}

/// What a nearest-hit walk asks of its rays: which children of a node
/// they may enter.
pub(super) trait Enter {
    /// Which boxes of the node's first `halves` halves the rays may meet
    /// within (t_min, t_max], padded against rounding, as a bit mask; and
    /// the entry distances (for several rays, the least of them).
    fn enter(&self, node: &Node, halves: usize, t_min: f32, t_max: f32) -> (u32, [Vec4; GROUPS]);
}

/// What a nearest-hit walk asks of its best hits: the farthest distance
/// at which a hit may still count.
pub(super) trait Reach {
    fn reach(&self) -> f32;
}

impl Reach for Best {
    #[inline(always)]
    fn reach(&self) -> f32 {
        self.t
    }
}

impl Enter for RayData {
    #[inline(always)]
    fn enter(&self, node: &Node, halves: usize, t_min: f32, t_max: f32) -> (u32, [Vec4; GROUPS]) {
        slab_test(
            node,
            halves,
            (t_min, t_max),
            &self.near_plane,
            |axis, near, far| {
                let (o, inv) = (self.origin[axis], self.inv_dir[axis]);
                ((near - o) * inv, (far - o) * inv)
            },
        )
    }
}

/// The slab test of the boxes of the node's first `halves` halves, the
/// near plane of each axis being `near_plane`: `slab(axis, near planes,
/// far planes)` gives the distances to them. Returns the boxes entered
/// within (t_min, t_max], padded against rounding, as a bit mask, and the
/// entry distances.
#[inline(always)]
pub(super) fn slab_test(
    node: &Node,
    halves: usize,
    (t_min, t_max): (f32, f32),
    near_plane: &[usize; 3],
    slab: impl Fn(usize, Vec4, Vec4) -> (Vec4, Vec4),
) -> (u32, [Vec4; GROUPS]) {
    let mut mask = 0;
    let mut entries = [Vec4::ZERO; GROUPS];
    for (g, entry) in entries.iter_mut().enumerate().take(halves) {
        let planes = &node.halves[g].planes;
        let mut near = Vec4::splat(t_min);
        let mut far = Vec4::splat(t_max);
        for (axis, &n) in near_plane.iter().enumerate() {
            let (t_near, t_far) = slab(axis, planes[n], planes[(n + 3) % 6]);
            near = near.max(t_near);
            far = far.min(t_far);
        }
        mask |= near.cmple(far * PAD).bitmask() << (4 * g);
        *entry = near;
    }
    (mask, entries)
}

/// 1 / each component of `dir`, for slab tests (`V3::safe_recip`: a
/// zero component is taken as 1e-30 of its sign).
#[inline(always)]
pub(super) fn safe_inverse(dir: glam::Vec3) -> [f32; 3] {
    let inv = crate::simd::V3::<f32>::from(dir).safe_recip();
    [inv.x, inv.y, inv.z]
}

/// A node or leaf waiting on the traversal stack, as its parent's lane
/// refers to it, with the distance at which the ray enters its box.
#[derive(Clone, Copy)]
pub(super) struct Entry {
    pub(super) child: u32,
    pub(super) count: u32,
    pub(super) t: f32,
    /// The node and lane that refer to it, as `node * WIDTH + lane`: where
    /// a packet finds a leaf's box, to test it ray by ray (an entry of 16
    /// bytes, where it was 12; unused for the root and by single rays).
    pub(super) from: u32,
}

impl Entry {
    /// The root, read whole.
    pub(super) const ROOT: Entry = Entry {
        child: 0,
        count: INNER,
        t: 0.0,
        from: 0,
    };
}

/// The nearest-first walk of a tree of `nodes` on `stack`: entries beyond
/// the best hit so far are skipped, leaves handed to `leaf`, and the
/// children the ray enters pushed farthest first. Both trees (the
/// primitives' and the instances') walk this way, with their own leaves,
/// and so do packets of rays (`packet.rs`).
#[inline(always)]
pub(super) fn walk_nearest<B: Reach>(
    nodes: &[Node],
    r: &impl Enter,
    t_min: f32,
    best: &mut B,
    stack: &mut [Entry],
    mut leaf: impl FnMut(Entry, &mut B),
) {
    stack[0] = Entry::ROOT;
    let mut sp = 1;
    while sp > 0 {
        sp -= 1;
        let entry = stack[sp];
        if entry.t > best.reach() * PAD {
            continue;
        }
        let Some(halves) = node_halves(entry.count) else {
            leaf(entry, best);
            continue;
        };
        let node = &nodes[entry.child as usize];
        let (mask, near) = r.enter(node, halves, t_min, best.reach());
        sp = push_nearest_last(stack, sp, (node, entry.child), mask, near);
    }
}

/// The shadow rays' walk of a tree of `nodes` on `stack`, in any order:
/// whether `leaf` finds an occluder in some leaf the ray enters (for a
/// packet, whether it has found one for every ray).
#[inline(always)]
pub(super) fn walk_any(
    nodes: &[Node],
    r: &impl Enter,
    (t_min, t_max): (f32, f32),
    stack: &mut [Entry],
    mut leaf: impl FnMut(Entry) -> bool,
) -> bool {
    stack[0] = Entry::ROOT;
    let mut sp = 1;
    while sp > 0 {
        sp -= 1;
        let entry = stack[sp];
        let Some(halves) = node_halves(entry.count) else {
            if leaf(entry) {
                return true;
            }
            continue;
        };
        let node = &nodes[entry.child as usize];
        let (mask, _) = r.enter(node, halves, t_min, t_max);
        sp = push_entered(stack, sp, (node, entry.child), mask);
    }
    false
}

/// Pushes the children of `node` that the ray enters (`mask`) in lane
/// order: for shadow rays, which any occluder stops (sorting by distance
/// cost more than it saved); returns the new stack size.
#[inline(always)]
pub(super) fn push_entered(
    stack: &mut [Entry],
    mut sp: usize,
    (node, index): (&Node, u32),
    mut mask: u32,
) -> usize {
    while mask != 0 {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let (child, count) = node.child(lane);
        stack[sp] = Entry {
            child,
            count,
            t: 0.0,
            from: index * WIDTH as u32 + lane as u32,
        };
        sp += 1;
    }
    sp
}

/// Pushes the children of `node` that the ray enters (`mask`), farthest
/// first, so the nearest is popped next; returns the new stack size.
#[inline(always)]
pub(super) fn push_nearest_last(
    stack: &mut [Entry],
    mut sp: usize,
    (node, index): (&Node, u32),
    mut mask: u32,
    near: [Vec4; GROUPS],
) -> usize {
    let first = sp;
    while mask != 0 {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let (child, count) = node.child(lane);
        let entry = Entry {
            child,
            count,
            t: near[lane / 4][lane % 4],
            from: index * WIDTH as u32 + lane as u32,
        };
        // Insertion into the pushed run, kept in decreasing distance.
        let mut k = sp;
        while k > first && stack[k - 1].t < entry.t {
            stack[k] = stack[k - 1];
            k -= 1;
        }
        stack[k] = entry;
        sp += 1;
    }
    sp
}

/// The next larger float, for a positive `t` (infinity stays).
pub(super) fn next_up(t: f32) -> f32 {
    if t.is_finite() {
        f32::from_bits(t.to_bits() + 1)
    } else {
        t
    }
}
