//! Integrators: what colour a ray brings back. The lab's Whitted-style
//! `rayTrace` (`whitted.rs`, and its four-lane form for small plain scenes,
//! `lanes.rs`), and path tracing beside it (`path/`: the estimator and its
//! helpers, and sixteen paths at a time in small matte scenes,
//! `path/matte_lanes/`).

pub(crate) mod lanes;
pub mod path;
pub mod record;
pub mod whitted;

/// How many rays of each kind a render traced.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RayStats {
    /// Rays that look for the nearest hit: primary and reflected.
    pub nearest: u64,
    /// Shadow rays: any hit between a point and a light.
    pub shadow: u64,
    /// Path samples whose value was not finite (NaN or infinite): left out
    /// of their pixel's mean.
    pub dropped: u64,
    /// Whitted samples whose ray tree reached `whitted::MAX_TREE_RAYS`:
    /// the rays past it were not traced.
    pub cut_trees: u64,
}

impl RayStats {
    pub fn total(&self) -> u64 {
        self.nearest + self.shadow
    }
}

impl std::ops::Add for RayStats {
    type Output = RayStats;
    fn add(self, o: RayStats) -> RayStats {
        RayStats {
            nearest: self.nearest + o.nearest,
            shadow: self.shadow + o.shadow,
            dropped: self.dropped + o.dropped,
            cut_trees: self.cut_trees + o.cut_trees,
        }
    }
}
