//! Bounds-checked reading of glTF accessors: float VEC3 attributes (POSITION, NORMAL) and
//! integer index lists. Every byte range is checked against its buffer view and buffer before
//! it is read (in u64, so no overflow), so a lying file is a [`GltfError`] naming
//! `accessors[i]`, never a panic or an out-of-bounds read.

use ::gltf::json::accessor::{ComponentType, Type};
use ::gltf::json::validation::Checked;
use glam::Vec3;

use super::document::{Document, GltfError};

/// The accessor's elements as byte slices, one per element, after every range check.
fn elements<'d>(
    doc: &'d Document,
    index: usize,
    want: &[(Type, ComponentType)],
) -> Result<(ComponentType, Vec<&'d [u8]>), GltfError> {
    let path = format!("accessors[{index}]");
    let a = doc.item(&doc.root.accessors, "accessors", index)?;
    let (Checked::Valid(ty), Checked::Valid(ct)) = (a.type_, a.component_type) else {
        return Err(doc.error(&path, "invalid type or componentType"));
    };
    let ct = ct.0;
    if !want.contains(&(ty, ct)) {
        let allowed: Vec<String> = want.iter().map(|(t, c)| format!("{t:?} {c:?}")).collect();
        return Err(doc.error(
            &path,
            format!("is {ty:?} {ct:?}; allowed here: {}", allowed.join(", ")),
        ));
    }
    if a.sparse.is_some() {
        return Err(doc.error(
            format!("{path}.sparse"),
            "sparse accessors are not supported",
        ));
    }
    if a.normalized {
        return Err(doc.error(
            format!("{path}.normalized"),
            "normalized accessors are not supported here",
        ));
    }
    let view_index = a.buffer_view.ok_or_else(|| {
        doc.error(
            format!("{path}.bufferView"),
            "is absent (an all-zero accessor), which is not supported",
        )
    })?;
    let view_path = format!("bufferViews[{}]", view_index.value());
    let view = doc.item(&doc.root.buffer_views, "bufferViews", view_index.value())?;
    let buffer = doc
        .buffers
        .get(view.buffer.value())
        .ok_or_else(|| doc.error(format!("{view_path}.buffer"), "no such buffer"))?;
    let elem = (ty.multiplicity() * ct.size()) as u64;
    let stride = view.byte_stride.map_or(elem, |s| s.0 as u64);
    if stride < elem {
        return Err(doc.error(
            format!("{view_path}.byteStride"),
            format!("is {stride} bytes, less than an element of {path} ({elem} bytes)"),
        ));
    }
    let count = a.count.0;
    let view_start = view.byte_offset.map_or(0, |o| o.0);
    let view_len = view.byte_length.0;
    let view_end = view_start.checked_add(view_len);
    if view_end.is_none_or(|e| e > buffer.len() as u64) {
        return Err(doc.error(
            &view_path,
            format!(
                "bytes [{view_start}, {view_start} + {view_len}) lie outside its buffer of {} bytes",
                buffer.len()
            ),
        ));
    }
    let offset = a.byte_offset.map_or(0, |o| o.0);
    let needed = count.checked_sub(1).map_or(Some(0), |last| {
        last.checked_mul(stride)
            .and_then(|x| x.checked_add(elem))
            .and_then(|x| x.checked_add(offset))
    });
    match needed {
        Some(n) if n <= view_len => {}
        _ => {
            return Err(doc.error(
                &path,
                format!(
                    "{count} elements of {elem} bytes (stride {stride}) from byteOffset {offset} \
                     do not fit in {view_path}'s {view_len} bytes"
                ),
            ));
        }
    }
    let start = (view_start + offset) as usize;
    let out = (0..count as usize)
        .map(|i| {
            let s = start + i * stride as usize;
            &buffer[s..s + elem as usize]
        })
        .collect();
    Ok((ct, out))
}

/// A float VEC3 accessor (POSITION, NORMAL); every component finite.
pub fn read_vec3(doc: &Document, index: usize) -> Result<Vec<Vec3>, GltfError> {
    let (_, elems) = elements(doc, index, &[(Type::Vec3, ComponentType::F32)])?;
    elems
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let c =
                |k: usize| f32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]]);
            let v = Vec3::new(c(0), c(1), c(2));
            if v.is_finite() {
                Ok(v)
            } else {
                Err(doc.error(
                    format!("accessors[{index}]"),
                    format!("element {i} is not finite: {v}"),
                ))
            }
        })
        .collect()
}

/// An index accessor (SCALAR unsigned byte, short or int), each index < `vertices`.
pub fn read_indices(doc: &Document, index: usize, vertices: usize) -> Result<Vec<u32>, GltfError> {
    let want = [
        (Type::Scalar, ComponentType::U8),
        (Type::Scalar, ComponentType::U16),
        (Type::Scalar, ComponentType::U32),
    ];
    let (ct, elems) = elements(doc, index, &want)?;
    elems
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let v = match ct {
                ComponentType::U8 => b[0] as u32,
                ComponentType::U16 => u16::from_le_bytes([b[0], b[1]]) as u32,
                _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            };
            if (v as usize) < vertices {
                Ok(v)
            } else {
                Err(doc.error(
                    format!("accessors[{index}]"),
                    format!("index {v} at element {i} is out of bounds: the primitive has {vertices} vertices"),
                ))
            }
        })
        .collect()
}
