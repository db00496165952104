//! Objects: their transforms and shapes (dimensions, tessellation limits, mesh files).

use std::path::Path;

use crate::desc::{
    Shape, Transform,
};
use crate::mesh::atrium;

use super::checker::*;

pub(super) fn transform(c: &mut Checker, p: &str, t: &Transform) {
    c.point3(&format!("{p}.translation"), t.translation);
    c.finite3(&format!("{p}.rotation_deg"), t.rotation_deg);
    if c.finite3(&format!("{p}.scale"), t.scale) && t.scale.min_element() <= 0.0 {
        c.push(
            &format!("{p}.scale"),
            format!("must be > 0 on every axis, got {}", t.scale),
        );
    }
}

pub(super) fn shape(c: &mut Checker, p: &str, s: &Shape, base: &Path) {
    if let Some(t) = triangle_estimate(s)
        && t > MAX_TRIANGLES
    {
        c.push(
            p,
            format!("would have about {t} triangles; a procedural shape may have at most {MAX_TRIANGLES}"),
        );
    }
    match s {
        Shape::Plane { .. }
        | Shape::Box { .. }
        | Shape::Sphere { .. }
        | Shape::Cylinder { .. }
        | Shape::Torus { .. } => primitive(c, p, s),
        Shape::Spring { .. }
        | Shape::Pencil { .. }
        | Shape::Fence { .. }
        | Shape::Atrium { .. }
        | Shape::AtriumBanners { .. } => procedural(c, p, s),
        Shape::Obj { .. } | Shape::Gltf { .. } => mesh_file(c, p, s, base),
    }
}

/// A primitive's dimensions and tessellation (the kinds `shape` sends here).
fn primitive(c: &mut Checker, p: &str, s: &Shape) {
    let f = |name: &str| format!("{p}.{name}");
    match s {
        Shape::Plane { size } => {
            c.positive(&f("size[0]"), size[0]);
            c.positive(&f("size[1]"), size[1]);
        }
        Shape::Box { size } if c.finite3(&f("size"), *size) && size.min_element() <= 0.0 => {
            c.push(&f("size"), format!("must be > 0 on every axis, got {size}"));
        }
        Shape::Sphere {
            radius,
            segments,
            rings,
        } => {
            c.positive(&f("radius"), *radius);
            c.count(&f("segments"), *segments, 3, MAX_SEGMENTS);
            c.count(&f("rings"), *rings, 2, MAX_SEGMENTS);
        }
        Shape::Cylinder {
            radius,
            height,
            segments,
        } => {
            c.positive(&f("radius"), *radius);
            c.positive(&f("height"), *height);
            c.count(&f("segments"), *segments, 3, MAX_SEGMENTS);
        }
        Shape::Torus {
            major_radius,
            minor_radius,
            segments,
            sides,
        } => {
            c.positive(&f("major_radius"), *major_radius);
            c.positive(&f("minor_radius"), *minor_radius);
            if minor_radius >= major_radius {
                c.push(
                    &f("minor_radius"),
                    format!("must be less than major_radius ({major_radius}), got {minor_radius}"),
                );
            }
            c.count(&f("segments"), *segments, 3, MAX_SEGMENTS);
            c.count(&f("sides"), *sides, 3, MAX_SEGMENTS);
        }
        _ => {} // the other kinds are checked by `procedural` and `mesh_file`
    }
}

/// A procedural shape's dimensions, counts and detail (the kinds `shape` sends here).
fn procedural(c: &mut Checker, p: &str, s: &Shape) {
    let f = |name: &str| format!("{p}.{name}");
    match s {
        Shape::Spring {
            coil_radius,
            wire_radius,
            turns,
            height,
            segments_per_turn,
            sides,
        } => {
            c.positive(&f("coil_radius"), *coil_radius);
            c.positive(&f("wire_radius"), *wire_radius);
            c.positive(&f("height"), *height);
            if !(turns.is_finite() && *turns > 0.0 && *turns <= 1000.0) {
                c.push(&f("turns"), format!("must be in (0, 1000], got {turns}"));
            }
            if wire_radius >= coil_radius {
                c.push(
                    &f("wire_radius"),
                    format!("must be less than coil_radius ({coil_radius}), got {wire_radius}"),
                );
            }
            c.count(&f("segments_per_turn"), *segments_per_turn, 3, MAX_SEGMENTS);
            c.count(&f("sides"), *sides, 3, MAX_SEGMENTS);
        }
        Shape::Pencil {
            radius,
            length,
            tip_length,
        } => {
            c.positive(&f("radius"), *radius);
            c.positive(&f("length"), *length);
            c.positive(&f("tip_length"), *tip_length);
        }
        Shape::Fence {
            width,
            height,
            posts,
            rails,
            bar,
        } => {
            c.positive(&f("width"), *width);
            c.positive(&f("height"), *height);
            c.positive(&f("bar"), *bar);
            c.count(&f("posts"), *posts, 1, MAX_SEGMENTS);
            c.count(&f("rails"), *rails, 0, MAX_SEGMENTS);
            if bar >= width || bar >= height {
                c.push(
                    &f("bar"),
                    format!("must be smaller than the fence ({width} × {height}), got {bar}"),
                );
            }
        }
        Shape::Atrium { detail } | Shape::AtriumBanners { detail } => {
            atrium_detail(c, &f("detail"), *detail)
        }
        _ => {} // the other kinds are checked by `primitive` and `mesh_file`
    }
}

/// A mesh file's path: it must exist (read later, with its own errors naming the file).
fn mesh_file(c: &mut Checker, p: &str, s: &Shape, base: &Path) {
    let f = |name: &str| format!("{p}.{name}");
    match s {
        Shape::Obj { path } => {
            let full = crate::mesh::obj::resolve_path(base, path);
            if !full.is_file() {
                c.push(
                    &f("path"),
                    format!("OBJ file not found: {}", full.display()),
                );
            }
        }
        Shape::Gltf { path, .. } => {
            let full = crate::mesh::obj::resolve_path(base, path);
            if !full.is_file() {
                c.push(
                    &f("path"),
                    format!("glTF file not found: {}", full.display()),
                );
            }
        }
        _ => {} // the other kinds are checked by `primitive` and `procedural`
    }
}

/// The atrium's `detail`: finite, within the mesh builder's range.
fn atrium_detail(c: &mut Checker, path: &str, detail: f32) {
    if !(detail.is_finite() && (atrium::MIN_DETAIL..=atrium::MAX_DETAIL).contains(&detail)) {
        let (lo, hi) = (atrium::MIN_DETAIL, atrium::MAX_DETAIL);
        c.push(path, format!("must be in [{lo}, {hi}], got {detail}"));
    }
}
