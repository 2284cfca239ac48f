//! Whether a hierarchy read back from a file (a prepared scene kept by
//! `--cache`) can be searched: every index it holds lies within its lists,
//! inner nodes point only forward (no cycle), the tree is no deeper than
//! the traversal stack allows, and every primitive's material exists. A
//! tree built here always passes; one read from a file is checked before
//! any ray walks it.

use super::build::MAX_DEPTH;
use super::wide::SPHERE_LEAF;
use super::wide::{is_leaf, node_halves};
use super::Bvh;

impl Bvh {
    /// Why this tree cannot be searched with `materials` materials, if so.
    pub(crate) fn check(&self, materials: usize) -> Result<(), String> {
        self.check_nodes()?;
        let material = |m: u32, what: &str| {
            if (m as usize) < materials {
                Ok(())
            } else {
                Err(format!("{what} names material {m} of {materials}"))
            }
        };
        for block in &self.tris {
            for (m, used) in block.lane_materials() {
                if used {
                    material(m, "a triangle")?;
                }
            }
        }
        for sphere in &self.spheres {
            material(sphere.material(), "a sphere")?;
        }
        if self.sphere4.len() != self.spheres.len().div_ceil(4) {
            return Err(format!(
                "{} blocks of four spheres for {} spheres",
                self.sphere4.len(),
                self.spheres.len()
            ));
        }
        for plane in &self.planes {
            material(plane.material, "a plane")?;
        }
        let masks = self.masks.iter().flat_map(|m| m.iter().flatten());
        if masks.into_iter().any(|m| !m.is_whole()) {
            return Err("an alpha mask's image of the wrong size".into());
        }
        Ok(())
    }

    /// The nodes' links: forward, within the lists, at most `MAX_DEPTH`
    /// deep below the root.
    fn check_nodes(&self) -> Result<(), String> {
        if self.nodes.is_empty() {
            return Ok(());
        }
        let mut depth = vec![0usize; self.nodes.len()];
        for (i, node) in self.nodes.iter().enumerate() {
            for half in &node.halves {
                for (&child, &count) in half.child.iter().zip(&half.count) {
                    if node_halves(count).is_some() {
                        self.check_inner(i, child as usize, &mut depth)?;
                    } else if is_leaf(count) {
                        self.check_leaf(child, count)?;
                    }
                }
            }
        }
        Ok(())
    }

    fn check_inner(&self, parent: usize, child: usize, depth: &mut [usize]) -> Result<(), String> {
        if child <= parent || child >= self.nodes.len() {
            return Err(format!(
                "node {parent} links to node {child} of {}",
                self.nodes.len()
            ));
        }
        depth[child] = depth[parent] + 1;
        if depth[child] > MAX_DEPTH + 1 {
            return Err(format!("the tree is deeper than {}", MAX_DEPTH + 1));
        }
        Ok(())
    }

    fn check_leaf(&self, first: u32, count: u32) -> Result<(), String> {
        let (n, len, what) = if count & SPHERE_LEAF != 0 {
            (count & !SPHERE_LEAF, self.spheres.len(), "spheres")
        } else {
            (count, self.tris.len(), "triangle blocks")
        };
        if u64::from(first) + u64::from(n) > len as u64 {
            return Err(format!(
                "a leaf holds {what} {first}..{} of {len}",
                u64::from(first) + u64::from(n)
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::wide::Node;
    use super::*;

    /// The first inner lane's link: nodes are plain data, a test can
    /// link them wrongly.
    fn first_inner_lane(nodes: &mut [Node]) -> Option<&mut u32> {
        nodes.iter_mut().find_map(|n| {
            n.halves.iter_mut().find_map(|h| {
                let lane = h.count.iter().position(|&c| node_halves(c).is_some())?;
                Some(&mut h.child[lane])
            })
        })
    }
    use crate::geometry::{Object, Shape, Sphere};
    use glam::Vec3;

    /// A tree of `n` spheres in a row, of material 0.
    fn spheres(n: usize) -> Bvh {
        let objects: Vec<Object> = (0..n)
            .map(|i| {
                let sphere = Sphere::new(Vec3::new(i as f32 * 3.0, 0.0, 0.0), 1.0);
                Object::new(Shape::Sphere(sphere), 0)
            })
            .collect();
        Bvh::build(&objects)
    }

    #[test]
    fn a_built_tree_passes_and_a_wrong_link_or_material_does_not() {
        let bvh = spheres(200);
        assert!(bvh.nodes.len() > 1);
        assert_eq!(bvh.check(1), Ok(()));
        assert!(bvh.check(0).unwrap_err().contains("material 0 of 0"));
        // A link back to the root: a cycle.
        let mut cycle = bvh.clone();
        *first_inner_lane(&mut cycle.nodes).unwrap() = 0;
        assert!(cycle.check(1).unwrap_err().contains("links to node 0"));
        // A leaf past the spheres.
        let mut past = bvh.clone();
        past.spheres.truncate(10);
        assert!(
            past.check(1).unwrap_err().contains("of 10"),
            "{:?}",
            past.check(1)
        );
        // Fewer blocks of four than the spheres fill.
        let mut short = bvh.clone();
        short.sphere4.pop();
        let error = short.check(1).unwrap_err();
        assert!(
            error.contains("49 blocks of four spheres for 200"),
            "{error}"
        );
    }
}
