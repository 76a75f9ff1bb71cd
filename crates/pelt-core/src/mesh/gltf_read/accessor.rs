//! Accessor data decoded with every bound checked (glTF 2.0 specification §3.6, "Binary data
//! storage"): the element range inside its buffer view, the view inside its buffer, the stride,
//! and the component types the attribute semantics allow. A malformed file gives a message,
//! never a panic or an out-of-bounds read.

use gltf_json as json;
use json::accessor::{ComponentType, Type};
use json::validation::Checked;

use super::container::Document;

/// How the components may be stored for an attribute.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Components {
    /// `FLOAT` only (positions).
    Float,
    /// `FLOAT`, or normalized `UNSIGNED_BYTE` / `UNSIGNED_SHORT` (colors).
    FloatOrUnorm,
    /// `UNSIGNED_BYTE`, `UNSIGNED_SHORT` or `UNSIGNED_INT`, not normalized (indices).
    Index,
}

/// Bytes of one component.
fn component_bytes(c: ComponentType) -> usize {
    match c {
        ComponentType::I8 | ComponentType::U8 => 1,
        ComponentType::I16 | ComponentType::U16 => 2,
        ComponentType::U32 | ComponentType::F32 => 4,
    }
}

/// One little-endian component as f64 (normalized integers mapped to `[0, 1]`).
fn component(raw: &[u8], c: ComponentType, normalized: bool) -> f64 {
    match c {
        ComponentType::F32 => f64::from(f32::from_le_bytes([raw[0], raw[1], raw[2], raw[3]])),
        ComponentType::U8 if normalized => f64::from(raw[0]) / 255.0,
        ComponentType::U16 if normalized => f64::from(u16::from_le_bytes([raw[0], raw[1]])) / 65535.0,
        ComponentType::U8 => f64::from(raw[0]),
        ComponentType::U16 => f64::from(u16::from_le_bytes([raw[0], raw[1]])),
        ComponentType::U32 => f64::from(u32::from_le_bytes([raw[0], raw[1], raw[2], raw[3]])),
        // Signed types are refused before decoding; read them plainly anyway.
        ComponentType::I8 => f64::from(raw[0] as i8),
        ComponentType::I16 => f64::from(i16::from_le_bytes([raw[0], raw[1]])),
    }
}

/// The elements of accessor `index` as `(dims, values)`: `values` holds `dims` f64 components
/// per element, `dims` the width of the accessor's type, which must be one of `types`. `what`
/// names the attribute in messages.
pub(super) fn read(
    doc: &Document,
    index: json::Index<json::Accessor>,
    what: &str,
    types: &[(Type, usize)],
    components: Components,
) -> Result<(usize, Vec<f64>), String> {
    let accessor = doc
        .root
        .get(index)
        .ok_or_else(|| format!("{what}: accessor {} does not exist", index.value()))?;
    let Checked::Valid(kind) = accessor.type_ else {
        return Err(format!("{what}: accessor {} has an unknown type", index.value()));
    };
    let Some(&(_, dims)) = types.iter().find(|(t, _)| *t == kind) else {
        return Err(format!(
            "{what}: accessor {} has type {kind:?}, expected one of {types:?}",
            index.value()
        ));
    };
    let Checked::Valid(json::accessor::GenericComponentType(ctype)) = accessor.component_type else {
        return Err(format!(
            "{what}: accessor {} has an unknown component type",
            index.value()
        ));
    };
    let allowed = match components {
        Components::Float => ctype == ComponentType::F32,
        Components::FloatOrUnorm => {
            ctype == ComponentType::F32
                || (accessor.normalized && matches!(ctype, ComponentType::U8 | ComponentType::U16))
        }
        Components::Index => {
            !accessor.normalized
                && matches!(ctype, ComponentType::U8 | ComponentType::U16 | ComponentType::U32)
        }
    };
    if !allowed {
        return Err(format!(
            "{what}: accessor {} stores {ctype:?}{}, which this attribute does not allow",
            index.value(),
            if accessor.normalized { " (normalized)" } else { "" }
        ));
    }
    if accessor.sparse.is_some() {
        return Err(format!(
            "{what}: accessor {} is sparse, which Pelt does not read",
            index.value()
        ));
    }
    let count = accessor.count.0 as usize;
    let element = component_bytes(ctype) * dims;
    // Without a buffer view every element would be zero (specification §3.6.2.1): nothing a mesh
    // attribute can use, and refusing it keeps the element count bounded by the buffer's size.
    let Some(view_index) = accessor.buffer_view else {
        return Err(format!("{what}: accessor {} has no buffer view", index.value()));
    };
    let view = doc
        .root
        .get(view_index)
        .ok_or_else(|| format!("{what}: buffer view {} does not exist", view_index.value()))?;
    let buffer = doc
        .buffers
        .get(view.buffer.value())
        .ok_or_else(|| format!("{what}: buffer {} does not exist", view.buffer.value()))?;
    let view_start = view.byte_offset.map_or(0, |o| o.0 as usize);
    let view_len = view.byte_length.0 as usize;
    let data = view_start
        .checked_add(view_len)
        .and_then(|end| buffer.get(view_start..end))
        .ok_or_else(|| format!("{what}: buffer view {} runs past its buffer", view_index.value()))?;
    let stride = view.byte_stride.map_or(element, |s| s.0);
    if stride < element {
        return Err(format!(
            "{what}: buffer view {} has stride {stride}, shorter than one element ({element} bytes)",
            view_index.value()
        ));
    }
    let offset = accessor.byte_offset.map_or(0, |o| o.0 as usize);
    if count > 0 {
        let end = (count - 1)
            .checked_mul(stride)
            .and_then(|n| n.checked_add(offset))
            .and_then(|n| n.checked_add(element));
        if end.is_none_or(|end| end > data.len()) {
            return Err(format!(
                "{what}: accessor {} ({count} elements) runs past its buffer view",
                index.value()
            ));
        }
    }
    let size = component_bytes(ctype);
    let mut values = Vec::with_capacity(dims * count);
    for i in 0..count {
        let at = offset + i * stride;
        for k in 0..dims {
            let raw = &data[at + k * size..at + (k + 1) * size];
            values.push(component(raw, ctype, accessor.normalized));
        }
    }
    Ok((dims, values))
}
