//! The skinning arguments of `pelt.export_gltf` (`transform`, `skin`, `skeletons`) read from
//! Python into [`pelt_core::export::rig`]'s types. Matrices are 4×4 row-major (translation in the last
//! column), as numpy shows Blender's `matrix_world`.

use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::arrays::{flat, float_ndarray, uint_ndarray};
use crate::errors::IntoPyErr;
use pelt_core::error::PeltError;
use pelt_core::export::{Animation, Skeleton, SkeletonNode, Transform};

/// A 4×4 row-major matrix's transform, naming `name` when it has none.
fn transform(rows: &[f32], name: &str) -> PyResult<Transform> {
    let mut m = [[0f32; 4]; 4];
    for (r, row) in m.iter_mut().enumerate() {
        row.copy_from_slice(&rows[4 * r..4 * r + 4]);
    }
    Transform::from_rows(m).ok_or_else(|| {
        PeltError::parameter(
            name,
            format!("must be a finite, invertible affine matrix (last row 0, 0, 0, 1), got {m:?}"),
        )
        .into_pyerr()
    })
}

/// `count` 4×4 matrices (`[count, 4, 4]` or, with `prefix`, `[*prefix, 4, 4]`) as transforms.
fn transforms(obj: &Bound<'_, PyAny>, name: &str, prefix: &[usize]) -> PyResult<Vec<Transform>> {
    let expected = format!("{prefix:?} + [4, 4]");
    let (array, _) = float_ndarray(obj, name, &expected, |shape| {
        shape.len() == prefix.len() + 2 && shape[..prefix.len()] == *prefix && shape[prefix.len()..] == [4, 4]
    })?;
    flat(&array)?
        .chunks_exact(16)
        .enumerate()
        .map(|(i, m)| transform(m, &format!("{name}[{i}]")))
        .collect()
}

/// The items of `obj`, the argument `name`, or an error naming it when it is not a sequence.
pub(super) fn sequence<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<Bound<'py, pyo3::types::PyIterator>> {
    obj.try_iter()
        .map_err(|_| PeltError::parameter(name, "must be a sequence").into_pyerr())
}

/// A required item of a dict argument.
pub(super) fn item<'py>(dict: &Bound<'py, PyDict>, key: &str, name: &str) -> PyResult<Bound<'py, PyAny>> {
    dict.get_item(key)?
        .ok_or_else(|| PeltError::parameter(name, format!("must have a {key:?} entry")).into_pyerr())
}

pub(super) fn as_dict<'a, 'py>(obj: &'a Bound<'py, PyAny>, name: &str) -> PyResult<&'a Bound<'py, PyDict>> {
    obj.cast::<PyDict>()
        .map_err(|_| PeltError::parameter(name, "must be a dict").into_pyerr())
}

/// `{"names": [...], "parents": [N] ints (-1 for a root), "rest": [N, 4, 4], "animations":
/// [{"name", "times": [T], "poses": [T, N, 4, 4]}]}`.
pub(super) fn skeleton(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Skeleton> {
    let dict = as_dict(obj, name)?;
    let names: Vec<String> = item(dict, "names", name)?.extract().map_err(|_| {
        PeltError::parameter(format!("{name}.names"), "must be a sequence of strings").into_pyerr()
    })?;
    let n = names.len();
    let parents: Vec<i128> = item(dict, "parents", name)?.extract().map_err(|_| {
        PeltError::parameter(format!("{name}.parents"), "must be a sequence of integers").into_pyerr()
    })?;
    if parents.len() != n {
        return Err(PeltError::parameter(
            format!("{name}.parents"),
            format!("must hold one entry per name ({n}), got {}", parents.len()),
        )
        .into_pyerr());
    }
    let rest = transforms(&item(dict, "rest", name)?, &format!("{name}.rest"), &[n])?;
    let mut nodes = Vec::with_capacity(n);
    for (j, ((node_name, parent), rest)) in names.into_iter().zip(parents).zip(rest).enumerate() {
        let parent = match parent {
            -1 => None,
            p if (0..n as i128).contains(&p) => Some(p as usize),
            p => {
                return Err(PeltError::parameter(
                    format!("{name}.parents"),
                    format!("entry {j} is {p}; a parent is a node index below {n}, or -1 for a root"),
                )
                .into_pyerr());
            }
        };
        nodes.push(SkeletonNode {
            name: node_name,
            parent,
            rest,
        });
    }
    let animations = match dict.get_item("animations")? {
        Some(list) => animations(&list, &format!("{name}.animations"), Some(n))?,
        None => Vec::new(),
    };
    Ok(Skeleton { nodes, animations })
}

/// A sequence of `{"name", "times": [T], "poses": [T, nodes, 4, 4]}` (`[T, 4, 4]` for an
/// object's own node, `nodes` `None`).
fn animations(list: &Bound<'_, PyAny>, name: &str, nodes: Option<usize>) -> PyResult<Vec<Animation>> {
    let mut animations = Vec::new();
    for (a, entry) in sequence(list, name)?.enumerate() {
        let entry = entry?;
        let at = format!("{name}[{a}]");
        let entry = as_dict(&entry, &at)?;
        let anim_name: String = item(entry, "name", &at)?
            .extract()
            .map_err(|_| PeltError::parameter(format!("{at}.name"), "must be a string").into_pyerr())?;
        let times: Vec<f32> = item(entry, "times", &at)?
            .extract()
            .or_else(|_| item(entry, "times", &at)?.call_method0("tolist")?.extract())
            .map_err(|_| {
                PeltError::parameter(format!("{at}.times"), "must be a sequence of numbers").into_pyerr()
            })?;
        let prefix: Vec<usize> = std::iter::once(times.len()).chain(nodes).collect();
        let poses = transforms(&item(entry, "poses", &at)?, &format!("{at}.poses"), &prefix)?;
        animations.push(Animation {
            name: anim_name,
            times,
            poses,
        });
    }
    Ok(animations)
}

/// One object's own animations (its node's transform over time): `None`, for a single object a
/// dict (one animation) or a list of dicts, or a sequence with one entry (or `None`) per object,
/// each a dict or a list of dicts. Poses are `[T, 4, 4]`.
pub(super) fn object_animations(
    obj: Option<&Bound<'_, PyAny>>,
    objects: usize,
) -> PyResult<Vec<Vec<Animation>>> {
    let dict_or_dicts = |o: &Bound<'_, PyAny>| {
        o.cast::<PyDict>().is_ok()
            || o.try_iter().is_ok_and(|mut items| {
                items
                    .next()
                    .is_some_and(|first| first.is_ok_and(|f| f.cast::<PyDict>().is_ok()))
            })
    };
    per_object(
        obj,
        objects,
        "animations",
        "animation lists",
        |o| objects == 1 && dict_or_dicts(o),
        Vec::new,
        |entry, name| {
            if entry.cast::<PyDict>().is_ok() {
                let list = pyo3::types::PyList::new(entry.py(), [entry])?;
                animations(list.as_any(), name, None)
            } else {
                animations(entry, name, None)
            }
        },
    )
}

/// One object's binding: `{"skeleton": int, "joints": [V, K] ints, "weights": [V, K]}`, as owned
/// arrays (the export borrows them).
pub(super) struct OwnedSkin {
    pub skeleton: usize,
    pub influences: usize,
    pub joints: Vec<u32>,
    pub weights: Vec<f32>,
}

pub(super) fn skin(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<OwnedSkin> {
    let dict = as_dict(obj, name)?;
    let skeleton: usize = item(dict, "skeleton", name)?.extract().map_err(|_| {
        PeltError::parameter(format!("{name}.skeleton"), "must be a non-negative integer").into_pyerr()
    })?;
    let two_d = |shape: &[usize]| shape.len() == 2 && shape[1] >= 1;
    let (joints, shape) = uint_ndarray(
        &item(dict, "joints", name)?,
        &format!("{name}.joints"),
        "[V, K]",
        two_d,
    )?;
    let (weights, wshape) = float_ndarray(
        &item(dict, "weights", name)?,
        &format!("{name}.weights"),
        "[V, K]",
        two_d,
    )?;
    if wshape != shape {
        return Err(PeltError::parameter(
            format!("{name}.weights"),
            format!("must have the joints' shape {shape:?}, got {wshape:?}"),
        )
        .into_pyerr());
    }
    Ok(OwnedSkin {
        skeleton,
        influences: shape[1],
        joints,
        weights: flat(&weights)?.to_vec(),
    })
}

/// One value per object from `obj`, the argument `name` (`what` in messages): `None` gives
/// `default()` for each; a single value (`is_single`) serves a single object; otherwise a sequence
/// with one entry (or `None`) per object. `parse(entry, name)` reads one entry.
pub(super) fn per_object<T>(
    obj: Option<&Bound<'_, PyAny>>,
    objects: usize,
    name: &str,
    what: &str,
    is_single: impl Fn(&Bound<'_, PyAny>) -> bool,
    default: impl Fn() -> T,
    parse: impl Fn(&Bound<'_, PyAny>, &str) -> PyResult<T>,
) -> PyResult<Vec<T>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok((0..objects).map(|_| default()).collect());
    };
    if is_single(obj) {
        if objects != 1 {
            return Err(PeltError::parameter(
                name,
                format!("must be a sequence of one entry (or None) per object for {objects} objects"),
            )
            .into_pyerr());
        }
        return Ok(vec![parse(obj, name)?]);
    }
    let mut out = Vec::with_capacity(objects);
    for (i, entry) in sequence(obj, name)?.enumerate() {
        let entry = entry?;
        out.push(if entry.is_none() {
            default()
        } else {
            parse(&entry, &format!("{name}[{i}]"))?
        });
    }
    if out.len() != objects {
        return Err(
            PeltError::parameter(name, format!("gives {} {what} for {objects} objects", out.len()))
                .into_pyerr(),
        );
    }
    Ok(out)
}

/// One transform per object: `None`, a `[4, 4]` matrix for a single object, or a sequence with
/// one matrix (or `None`) per object.
pub(super) fn object_transforms(obj: Option<&Bound<'_, PyAny>>, objects: usize) -> PyResult<Vec<Transform>> {
    let is_matrix = |o: &Bound<'_, PyAny>| {
        o.py()
            .import("numpy")
            .and_then(|numpy| numpy.call_method1("shape", (o,)))
            .and_then(|s| s.extract::<Vec<usize>>())
            .is_ok_and(|shape| shape == [4, 4])
    };
    per_object(
        obj,
        objects,
        "transform",
        "transforms",
        is_matrix,
        || Transform::IDENTITY,
        |entry, name| {
            let single = entry
                .py()
                .import("numpy")?
                .call_method1("expand_dims", (entry, 0))?;
            Ok(transforms(&single, name, &[1])?[0])
        },
    )
}

/// One binding (or `None`) per object: `None`, a dict for a single object, or a sequence.
pub(super) fn object_skins(
    obj: Option<&Bound<'_, PyAny>>,
    objects: usize,
) -> PyResult<Vec<Option<OwnedSkin>>> {
    let is_dict = |o: &Bound<'_, PyAny>| o.cast::<PyDict>().is_ok();
    per_object(
        obj,
        objects,
        "skin",
        "bindings",
        is_dict,
        || None,
        |entry, name| Ok(Some(skin(entry, name)?)),
    )
}
