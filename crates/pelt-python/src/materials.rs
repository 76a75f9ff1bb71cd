//! The `materials` argument of `pelt.export_gltf` read from Python into
//! [`pelt_core::export::materials`]'s types: per object `None` or
//! `{"slots": [None | {"name", "base_color", "metallic", "roughness"}], "triangle_slot": [T]}`.

use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::arrays::uint_ndarray;
use super::rig::{as_dict, item, per_object, sequence};
use crate::errors::{IntoPyErr, py_err};
use pelt_core::error::PeltError;
use pelt_core::export::OwnMaterial;

/// One object's material slots, owned (the export borrows them).
pub(super) struct OwnedSlots {
    pub slots: Vec<Option<OwnMaterial>>,
    pub triangle_slot: Vec<u32>,
}

/// A float entry of a material dict, `default` when absent.
fn number(dict: &Bound<'_, PyDict>, key: &str, name: &str, default: f32) -> PyResult<f32> {
    match dict.get_item(key)? {
        None => Ok(default),
        Some(value) => value
            .extract()
            .map_err(|_| PeltError::parameter(format!("{name}.{key}"), "must be a number").into_pyerr()),
    }
}

fn material(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<OwnMaterial> {
    let dict = as_dict(obj, name)?;
    let material_name: String = item(dict, "name", name)?
        .extract()
        .map_err(|_| PeltError::parameter(format!("{name}.name"), "must be a string").into_pyerr())?;
    let base_color = match dict.get_item("base_color")? {
        None => [0.8, 0.8, 0.8, 1.0],
        Some(value) => {
            let values: Vec<f32> = value
                .extract()
                .or_else(|_| value.call_method0("tolist")?.extract())
                .map_err(|_| {
                    PeltError::parameter(format!("{name}.base_color"), "must be 4 numbers").into_pyerr()
                })?;
            values
                .try_into()
                .map_err(|v: Vec<f32>| {
                    PeltError::parameter(
                        format!("{name}.base_color"),
                        format!("must be 4 numbers (RGBA), got {}", v.len()),
                    )
                })
                .map_err(py_err)?
        }
    };
    Ok(OwnMaterial {
        name: material_name,
        base_color,
        metallic: number(dict, "metallic", name, 0.0)?,
        roughness: number(dict, "roughness", name, 0.5)?,
    })
}

fn slots(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<OwnedSlots> {
    let dict = as_dict(obj, name)?;
    let mut slots = Vec::new();
    for (s, entry) in sequence(&item(dict, "slots", name)?, &format!("{name}.slots"))?.enumerate() {
        let entry = entry?;
        slots.push(if entry.is_none() {
            None
        } else {
            Some(material(&entry, &format!("{name}.slots[{s}]"))?)
        });
    }
    let (triangle_slot, _) = uint_ndarray(
        &item(dict, "triangle_slot", name)?,
        &format!("{name}.triangle_slot"),
        "[T]",
        |shape| shape.len() == 1,
    )?;
    Ok(OwnedSlots { slots, triangle_slot })
}

/// One set of slots (or `None`) per object: `None`, a dict for a single object, or a sequence.
pub(super) fn object_materials(
    obj: Option<&Bound<'_, PyAny>>,
    objects: usize,
) -> PyResult<Vec<Option<OwnedSlots>>> {
    let is_dict = |o: &Bound<'_, PyAny>| o.cast::<PyDict>().is_ok();
    per_object(
        obj,
        objects,
        "materials",
        "material sets",
        is_dict,
        || None,
        |entry, name| Ok(Some(slots(entry, name)?)),
    )
}
