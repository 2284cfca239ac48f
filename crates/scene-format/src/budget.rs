//! How many triangles the meshes of one scene may make, counted as their
//! files are read and before any triangle is built: a small file of
//! polygons with many corners would otherwise take gigabytes before the
//! pipeline's primitive limit refused it.

/// Most triangles the meshes of a scene may make: the tracer's primitive
/// limit (`tracer_pipeline::MAX_PRIMITIVES`, the same number). A mesh
/// file read once counts once, however many objects name it.
pub const MAX_TRIANGLES: usize = 20_000_000;

/// Most vertices a PLY file may declare: three for each triangle allowed
/// (a file of separate triangles), so a lying header cannot make the
/// reader keep billions of them.
pub const MAX_VERTICES: usize = 3 * MAX_TRIANGLES;

/// Why a mesh file was refused by the budget.
pub const TOO_MANY: &str = "with this file the scene's meshes make more than 20000000 triangles \
     (a face of n corners makes n - 2), the most the tracer builds; counted before any is built";

/// The triangles left to the meshes of one scene.
#[derive(Debug, Clone)]
pub struct Budget {
    left: usize,
}

impl Default for Budget {
    fn default() -> Self {
        Budget {
            left: MAX_TRIANGLES,
        }
    }
}

impl Budget {
    /// A budget of `n` triangles (tests use small ones).
    pub fn of(n: usize) -> Budget {
        Budget { left: n }
    }

    /// Takes `n` triangles, or says why not (the budget is then spent).
    pub fn take(&mut self, n: usize) -> Result<(), &'static str> {
        match self.left.checked_sub(n) {
            Some(left) => {
                self.left = left;
                Ok(())
            }
            None => {
                self.left = 0;
                Err(TOO_MANY)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_budget_gives_what_it_has_and_no_more() {
        let mut budget = Budget::of(5);
        assert!(budget.take(3).is_ok());
        assert!(budget.take(2).is_ok());
        assert_eq!(budget.take(1), Err(TOO_MANY));
        assert!(TOO_MANY.contains(&MAX_TRIANGLES.to_string()));
    }
}
