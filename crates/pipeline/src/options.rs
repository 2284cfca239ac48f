//! What a render is asked for: a checked display gamma, an AOV.

use crate::Error;

/// One quantity per pixel instead of the shaded colour: the core's list.
pub use tracer_core::aov::Aov;

/// A display gamma, checked: a finite number > 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gamma(f32);

impl Gamma {
    /// The gamma `g`, or [`Error::Gamma`] unless it is finite and > 0.
    pub fn new(g: f32) -> Result<Gamma, Error> {
        if g.is_finite() && g > 0.0 {
            Ok(Gamma(g))
        } else {
            Err(Error::Gamma(g))
        }
    }

    pub fn get(self) -> f32 {
        self.0
    }
}

/// What to render of a loaded scene.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Options {
    /// Overrides the scene's gamma (an AOV's is 1 otherwise).
    pub gamma: Option<Gamma>,
    /// An AOV instead of the shaded colour; 3D scenes only.
    pub aov: Option<Aov>,
}
