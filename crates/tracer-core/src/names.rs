//! What the scene file calls the prepared scene's objects and materials,
//! for `explain`: the tracer numbers the triangles a box, quad or mesh is
//! made of, and materials by first use, where the file has `objects[5]`
//! and `[materials.white]`.

use serde::Serialize;

/// A file object, as the prepared objects it made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Owner {
    /// Its index in the file's `objects`.
    index: usize,
    /// The first object it made, and how many.
    first: usize,
    count: usize,
}

/// The file's names of a prepared scene's objects and materials.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Names {
    /// For each file object that made objects: the first object it made,
    /// and its index in the file's `objects`, in order.
    objects: Vec<(usize, usize)>,
    /// How many objects were made in all.
    made: usize,
    /// Per material index, what the file calls it.
    materials: Vec<String>,
}

impl Names {
    /// Notes that file object `index` made the next `count` objects.
    pub(crate) fn add_objects(&mut self, index: usize, count: usize) {
        if count > 0 {
            self.objects.push((self.made, index));
            self.made += count;
        }
    }

    /// Notes the name of the next material.
    pub(crate) fn add_material(&mut self, name: String) {
        self.materials.push(name);
    }

    /// Object `k` in the file's words: `objects[5]`, or `objects[5]
    /// triangle 3 of 12` for one of the triangles of a box, quad or mesh.
    pub fn object(&self, k: usize) -> String {
        match self.owner(k) {
            Some(Owner {
                index, count: 1, ..
            }) => format!("objects[{index}]"),
            Some(Owner {
                index,
                first,
                count,
            }) => format!("objects[{index}] triangle {} of {count}", k - first + 1),
            None => format!("object {k}"),
        }
    }

    /// Objects `ks` (ascending) in the file's words, the triangles of one
    /// file object together: `objects[0], objects[6] (10 of its 12
    /// triangles)`.
    pub fn objects(&self, ks: &[usize]) -> String {
        let mut groups: Vec<(Option<Owner>, usize)> = Vec::new();
        for &k in ks {
            let owner = self.owner(k);
            match groups.last_mut() {
                Some((Some(last), seen)) if owner == Some(*last) => *seen += 1,
                _ => groups.push((owner, 1)),
            }
        }
        let shown: Vec<String> = groups
            .iter()
            .map(|(owner, seen)| match owner {
                Some(Owner {
                    index, count: 1, ..
                }) => format!("objects[{index}]"),
                Some(Owner { index, count, .. }) if seen == count => {
                    format!("objects[{index}] (all {count} triangles)")
                }
                Some(Owner { index, count, .. }) => {
                    format!("objects[{index}] ({seen} of its {count} triangles)")
                }
                None => "an object".to_string(),
            })
            .collect();
        shown.join(", ")
    }

    /// The file object that made object `k`.
    fn owner(&self, k: usize) -> Option<Owner> {
        let at = self.objects.partition_point(|&(first, _)| first <= k);
        let &(first, index) = self.objects.get(at.checked_sub(1)?)?;
        let end = self.objects.get(at).map_or(self.made, |&(next, _)| next);
        (k < end).then_some(Owner {
            index,
            first,
            count: end - first,
        })
    }

    /// Material `k` in the file's words: `white`, or where it is written.
    pub fn material(&self, k: usize) -> String {
        self.materials
            .get(k)
            .cloned()
            .unwrap_or_else(|| format!("material {k}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_object_of_several_triangles_is_named_with_its_triangle() {
        let mut names = Names::default();
        names.add_objects(0, 1);
        names.add_objects(1, 0);
        names.add_objects(2, 12);
        names.add_objects(3, 1);
        assert_eq!(names.object(0), "objects[0]");
        assert_eq!(names.object(1), "objects[2] triangle 1 of 12");
        assert_eq!(names.object(12), "objects[2] triangle 12 of 12");
        assert_eq!(names.object(13), "objects[3]");
        assert_eq!(names.object(14), "object 14");
        assert_eq!(
            names.objects(&[0, 1, 2, 5, 13]),
            "objects[0], objects[2] (3 of its 12 triangles), objects[3]"
        );
        let all: Vec<usize> = (1..=12).collect();
        assert_eq!(names.objects(&all), "objects[2] (all 12 triangles)");
        names.add_material("`white`".to_string());
        assert_eq!(names.material(0), "`white`");
        assert_eq!(names.material(1), "material 1");
    }
}
