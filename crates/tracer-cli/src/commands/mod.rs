//! One module per command; each reads its resolved arguments from `args`.

pub mod calib_chart;
pub mod check;
pub mod compare;
pub mod completions;
pub mod convert;
pub mod explain;
pub mod explain_draw;
pub mod gamma_fit;
pub mod merge;
pub mod new;
pub mod pack;
pub mod passes;
pub mod render;
pub mod schema;
pub mod watch;
