//! The lab's side exercises, apart from the ray tracer: the 2D canvas
//! (exercise 2), the calibration chart and measuring a display's gamma
//! (exercise 17). They share only the image types with `tracer-core`.

pub mod calib;
pub mod canvas;
pub mod gamma_fit;
#[cfg(not(target_arch = "wasm32"))]
pub mod gamma_plot;
pub mod measurements;
