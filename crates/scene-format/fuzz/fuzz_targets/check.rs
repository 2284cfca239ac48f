//! What every fuzz input must satisfy: loading never panics, and a
//! rejected file gets at least one diagnostic whose span lies inside the
//! text and whose report renders.

use scene_format::{Format, SceneError};
use std::path::Path;

pub fn check(data: &[u8], format: Format) {
    let file = Path::new("fuzz");
    match scene_format::load_bytes(data, format, file) {
        Ok(_) => {}
        Err(e @ SceneError::Invalid { .. }) => {
            let SceneError::Invalid {
                text, diagnostics, ..
            } = &e
            else {
                unreachable!()
            };
            assert!(!diagnostics.is_empty(), "rejected without a reason");
            for d in diagnostics {
                if let Some(span) = &d.span {
                    assert!(span.start <= span.end && span.end <= text.len());
                    assert!(text.is_char_boundary(span.start) && text.is_char_boundary(span.end));
                    assert!(d.location.is_some());
                }
            }
            let _ = e.to_string();
        }
        Err(e) => panic!("unexpected error kind for in-memory bytes: {e}"),
    }
}
