//! A file's cameras and lights (`KHR_lights_punctual`), placed by their
//! nodes, as the scene file's `[camera]` and `[[lights]]` would say them.
//! A glTF camera and a spot or directional light look down their node's
//! -Z axis, +Y up.

use super::doc::Document;
use super::{Failure, PlacedCamera};
use crate::key_path::KeyPath;
use crate::model::{Camera, Handedness, Light, Projection};
use glam::{Mat4, Vec3};

/// The width in pixels of the image of a glTF camera; its height follows
/// the camera's aspect ratio (4:3 when the file leaves it to the viewer).
pub const IMAGE_WIDTH: u32 = 800;
const DEFAULT_ASPECT: f32 = 4.0 / 3.0;

/// The cameras `placed` (node, camera, world matrix) in the scene file's terms.
pub(crate) fn cameras(
    doc: &Document,
    placed: &[(usize, usize, Mat4)],
) -> Result<Vec<PlacedCamera>, Failure> {
    placed
        .iter()
        .map(|&(node, index, world)| {
            let c = &doc.cameras[index];
            let at = KeyPath::root().key("cameras").index(index);
            let (eye, forward, up) = frame(world, node)?;
            let mut camera = Camera {
                eye: eye.to_array(),
                look_at: (eye + forward).to_array(),
                up: up.to_array(),
                fov: 50.0,
                width: IMAGE_WIDTH,
                height: IMAGE_WIDTH * 3 / 4,
                handedness: Handedness::Right,
                aperture: 0.0,
                focus_distance: None,
                projection: Projection::Perspective,
                view_width: None,
            };
            match (c.kind.as_str(), &c.perspective, &c.orthographic) {
                ("perspective", Some(p), _) => {
                    let yfov = p.yfov;
                    if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
                        return Err(Failure::at(
                            at.key("perspective").key("yfov"),
                            format!("expected an angle in radians between 0 and pi, found {yfov}"),
                        ));
                    }
                    let aspect = match p.aspect_ratio {
                        Some(a) if a > 0.0 && a.is_finite() => a,
                        Some(a) => {
                            return Err(Failure::at(
                                at.key("perspective").key("aspectRatio"),
                                format!("expected a ratio > 0, found {a}"),
                            ))
                        }
                        None => DEFAULT_ASPECT,
                    };
                    let hfov = 2.0 * (aspect * (yfov / 2.0).tan()).atan();
                    camera.fov = hfov.to_degrees();
                    camera.height = height(aspect);
                }
                ("orthographic", _, Some(o)) => {
                    let ok = |x: f32| x != 0.0 && x.is_finite();
                    if !ok(o.xmag) || !ok(o.ymag) {
                        return Err(Failure::at(
                            at.key("orthographic"),
                            format!(
                                "expected non-zero, finite `xmag` and `ymag`, found {} and {}",
                                o.xmag, o.ymag
                            ),
                        ));
                    }
                    camera.projection = Projection::Orthographic;
                    camera.view_width = Some(2.0 * o.xmag.abs());
                    camera.height = height(o.xmag.abs() / o.ymag.abs());
                }
                (kind @ ("perspective" | "orthographic"), _, _) => {
                    return Err(Failure::at(
                        at.key(kind),
                        format!("expected the `{kind}` table of a camera of type {kind:?}"),
                    ))
                }
                (other, _, _) => {
                    return Err(Failure::at(
                        at.key("type"),
                        format!("expected \"perspective\" or \"orthographic\", found {other:?}"),
                    ))
                }
            }
            let name = c.name.clone().or_else(|| doc.nodes[node].name.clone());
            Ok(PlacedCamera { node, name, camera })
        })
        .collect()
}

/// The image height for an aspect ratio (width / height) at `IMAGE_WIDTH`.
fn height(aspect: f32) -> u32 {
    ((IMAGE_WIDTH as f32 / aspect).round() as u32).clamp(1, 16384)
}

/// A node's position, its -Z (forward) and +Y (up) directions, unit.
fn frame(world: Mat4, node: usize) -> Result<(Vec3, Vec3, Vec3), Failure> {
    let eye = world.transform_point3(Vec3::ZERO);
    let forward = world.transform_vector3(Vec3::NEG_Z).try_normalize();
    let up = world.transform_vector3(Vec3::Y).try_normalize();
    match (forward, up) {
        (Some(f), Some(u)) if f.cross(u).length() > 1e-4 => Ok((eye, f, u)),
        _ => Err(Failure::at(
            KeyPath::root().key("nodes").index(node),
            "the node's transform (with its parents') flattens its axes, so it has no view direction; expected a transform that can be undone",
        )),
    }
}

/// The lights `placed` (node, light, world matrix) in the scene file's terms.
pub(crate) fn lights(
    doc: &Document,
    placed: &[(usize, usize, Mat4)],
) -> Result<Vec<Light>, Failure> {
    let Some(list) = &doc.extensions.lights_punctual else {
        return Ok(Vec::new());
    };
    placed
        .iter()
        .map(|&(node, index, world)| {
            let l = &list.lights[index];
            let at = KeyPath::root()
                .key("extensions")
                .key("KHR_lights_punctual")
                .key("lights")
                .index(index);
            if !l.color.iter().all(|c| (0.0..=1.0).contains(c)) {
                return Err(Failure::at(
                    at.key("color"),
                    format!("expected numbers from 0 to 1, found {:?}", l.color),
                ));
            }
            if !(l.intensity >= 0.0 && l.intensity.is_finite()) {
                return Err(Failure::at(
                    at.key("intensity"),
                    format!("expected a number >= 0, found {}", l.intensity),
                ));
            }
            let (position, forward, _) = frame(world, node)?;
            let mut light = Light {
                position: Some(position.to_array()),
                direction: None,
                cone: None,
                color: l.color.map(|c| c * l.intensity),
                radius: 0.0,
            };
            match (l.kind.as_str(), &l.spot) {
                ("point", _) => {}
                ("directional", _) => {
                    light.position = None;
                    light.direction = Some(forward.to_array());
                }
                ("spot", spot) => {
                    let (inner, outer) = spot
                        .as_ref()
                        .map_or((0.0, std::f32::consts::FRAC_PI_4), |s| {
                            (s.inner_cone_angle, s.outer_cone_angle)
                        });
                    if !(inner >= 0.0 && inner < outer && outer <= std::f32::consts::FRAC_PI_2) {
                        return Err(Failure::at(
                            at.key("spot"),
                            format!(
                                "expected 0 <= innerConeAngle < outerConeAngle <= pi / 2, found {inner} and {outer}"
                            ),
                        ));
                    }
                    light.direction = Some(forward.to_array());
                    light.cone = Some([inner.to_degrees(), outer.to_degrees()]);
                }
                (other, _) => {
                    return Err(Failure::at(
                        at.key("type"),
                        format!("expected \"point\", \"spot\" or \"directional\", found {other:?}"),
                    ))
                }
            }
            Ok(light)
        })
        .collect()
}
