//! What a ray can hit: the shapes, the objects of a scene (a shape and its
//! material), and the record of a hit that shading reads.

mod hit;
mod instance;
mod placement;
mod plane;
mod shape;
mod sphere;
mod triangle;

pub use hit::SurfaceHit;
pub use instance::{Instance, SharedMesh};
pub use placement::Placement;
pub use plane::{plane_distance, Plane};
pub use shape::{Object, Shape, UvMap};
pub use sphere::{sphere_roots, Sphere};
pub use triangle::{moller_trumbore, Edges, OriginTerms, Triangle, TriangleHit};
