//! `pelt.bake_transfer` and `pelt.sh_project_equirect`: the Python face of [`pelt_core::prt`].

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use super::arrays::{flat, float_ndarray, rows};
use super::detached;
use super::progress::PyProgress;
use crate::errors::{IntoPyErr, py_err};
use pelt_core::error::PeltError;
use pelt_core::progress::ProgressCallback;
use pelt_core::prt::bands::{BandParams, BandReport, bake_transfer_auto};
use pelt_core::prt::pack::{PackedF16, PackedU8, pack_f16, pack_u8};
use pelt_core::prt::sh;
use pelt_core::prt::transfer::{
    Method, Phase, Transfer, TransferParams, TransferVolume, bake_transfer as core_bake,
};

pub(super) fn parse_phase(phase: &str) -> PyResult<Phase> {
    match phase {
        "isotropic" => Ok(Phase::Isotropic),
        "kajiya-kay" | "kajiya_kay" => Ok(Phase::KajiyaKay),
        _ => Err(PeltError::parameter(
            "phase",
            format!("must be \"isotropic\" or \"kajiya-kay\", got {phase:?}"),
        )
        .into_pyerr()),
    }
}

fn parse_method(method: &str) -> PyResult<Method> {
    match method {
        "sweep" => Ok(Method::Sweep),
        "brute" => Ok(Method::Brute),
        _ => Err(PeltError::parameter(
            "method",
            format!("must be \"sweep\" or \"brute\", got {method:?}"),
        )
        .into_pyerr()),
    }
}

/// The band table as a list of dicts.
fn bands_list<'py>(py: Python<'py>, report: Option<&BandReport>) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for row in report.map_or(&[][..], |r| &r.rows[..]) {
        let d = PyDict::new(py);
        d.set_item("order", row.order)?;
        d.set_item("coefficients", row.coefficients)?;
        d.set_item("band_energy", row.band_energy)?;
        d.set_item("error_directional", row.error_directional)?;
        d.set_item("error_environment", row.error_environment)?;
        d.set_item("error", row.error)?;
        d.set_item("bytes_f16", row.bytes_f16)?;
        d.set_item("bytes_u8", row.bytes_u8)?;
        list.append(d)?;
    }
    Ok(list)
}

/// Bakes the transfer of a density volume; see the stub for the arguments and the result.
#[pyfunction]
#[pyo3(signature = (
    density, tangents=None, *, layer_spacing, order=None,
    tolerance=pelt_core::prt::bands::DEFAULT_TOLERANCE, directions=256, phase="isotropic",
    method="sweep", sigma=pelt_core::prt::transfer::DEFAULT_SIGMA, progress=None
))]
#[allow(clippy::too_many_arguments)]
pub(super) fn bake_transfer<'py>(
    py: Python<'py>,
    density: &Bound<'py, PyAny>,
    tangents: Option<&Bound<'py, PyAny>>,
    layer_spacing: f32,
    order: Option<i128>,
    tolerance: f64,
    directions: i128,
    phase: &str,
    method: &str,
    sigma: f32,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let order: Option<usize> = super::ints::unsigned_opt("order", order)?;
    let directions: usize = super::ints::unsigned("directions", directions)?;
    let (density, shape) = float_ndarray(density, "density", "[L, R, R]", |s| s.len() == 3 && s[1] == s[2])?;
    let (layers, resolution) = (shape[0], shape[1]);
    let tangents = tangents
        .map(|t| {
            float_ndarray(t, "tangents", "[L, R, R, 3] matching density", |s| {
                s.len() == 4 && s[..3] == shape[..] && s[3] == 3
            })
        })
        .transpose()?;
    let params = TransferParams {
        order: order.unwrap_or(sh::PAPER_ORDER),
        directions,
        sigma,
        phase: parse_phase(phase)?,
        method: parse_method(method)?,
        ..TransferParams::default()
    };
    let bands = BandParams {
        tolerance,
        ..BandParams::default()
    };
    params.validate().map_err(py_err)?;
    // This call also packs the result: count the packed textures before anything is baked.
    pelt_core::prt::peak::check_transfer_memory(layers, resolution, &params, order.is_none(), true)
        .map_err(py_err)?;
    let density = flat(&density)?;
    let tangents = tangents.as_ref().map(|(t, _)| rows::<f32, 3>(t)).transpose()?;
    let reporter = PyProgress::new(progress.map(|p| p.into_bound(py)));
    let report = |fraction: f64| reporter.report(fraction);
    let callback: Option<ProgressCallback<'_>> = reporter.is_some().then_some(&report);
    let outcome = detached(py, || {
        let volume = TransferVolume {
            layers,
            resolution,
            layer_spacing,
            density,
            tangents,
        };
        let (transfer, report): (Transfer, Option<BandReport>) = match order {
            Some(_) => (core_bake(&volume, &params, callback)?, None),
            None => {
                let (t, r) = bake_transfer_auto(&volume, &params, &bands, callback)?;
                (t, Some(r))
            }
        };
        let f16 = pack_f16(&transfer)?;
        let u8 = pack_u8(&transfer)?;
        let sidecar = serde_json::to_string_pretty(&u8.sidecar)
            .map_err(|e| PeltError::Internal(format!("sidecar: {e}")))?;
        Ok((transfer, report, f16, u8, sidecar))
    });
    let (transfer, report, f16, u8, sidecar) = reporter.finish(outcome)?;
    transfer_dict(py, transfer, report.as_ref(), f16, u8, sidecar)
}

/// The transfer result as a dict (see the stub's `TransferResult`); the arrays take the vectors
/// without a copy.
pub(super) fn transfer_dict<'py>(
    py: Python<'py>,
    transfer: Transfer,
    report: Option<&BandReport>,
    f16: PackedF16,
    u8: PackedU8,
    sidecar: String,
) -> PyResult<Bound<'py, PyDict>> {
    let (layers, resolution) = (transfer.layers, transfer.resolution);
    let n = transfer.coeff_count();
    let textures = f16.textures;
    let d = PyDict::new(py);
    d.set_item(
        "coefficients",
        PyArray1::from_vec(py, transfer.coefficients).reshape([layers, resolution, resolution, n])?,
    )?;
    d.set_item("order", transfer.order)?;
    d.set_item("tolerance_met", report.map(|r| r.met))?;
    d.set_item("bands", bands_list(py, report)?)?;
    let packed_shape = [textures, layers, resolution, resolution, 4];
    d.set_item(
        "packed_f16",
        PyArray1::from_vec(py, f16.texels).reshape(packed_shape)?,
    )?;
    d.set_item(
        "packed_u8",
        PyArray1::from_vec(py, u8.texels).reshape(packed_shape)?,
    )?;
    d.set_item("scale", PyArray1::from_slice(py, &u8.sidecar.scale))?;
    d.set_item("bias", PyArray1::from_slice(py, &u8.sidecar.bias))?;
    d.set_item("sidecar", sidecar)?;
    Ok(d)
}

/// Projects an equirectangular `[H, W, 3]` image onto SH; returns `[order², 3]` float32.
#[pyfunction]
pub(super) fn sh_project_equirect<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    order: i128,
) -> PyResult<Bound<'py, PyAny>> {
    let order: usize = super::ints::unsigned("order", order)?;
    let (image, shape) = float_ndarray(image, "image", "[H, W, 3]", |s| s.len() == 3 && s[2] == 3)?;
    let (height, width) = (shape[0], shape[1]);
    let rgb = flat(&image)?;
    let coeffs = detached(py, || sh::project_equirect(order, width, height, rgb))?;
    if let Some(big) = coeffs.iter().flatten().find(|c| c.abs() > f64::from(f32::MAX)) {
        return Err(PeltError::parameter(
            "image",
            format!("projects to a coefficient of {big:e}, beyond float32's range: scale the image down"),
        )
        .into_pyerr());
    }
    let flat: Vec<f32> = coeffs.iter().flat_map(|c| c.map(|v| v as f32)).collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([coeffs.len(), 3])?
        .into_any())
}

/// SH coefficients (`[order²]` float32) of a light of unit power from `direction`, spread over a
/// cone of `half_angle` radians (0: a directional light).
#[pyfunction]
#[pyo3(signature = (direction, order, half_angle=0.0))]
pub(super) fn sh_project_light<'py>(
    py: Python<'py>,
    direction: [f64; 3],
    order: i128,
    half_angle: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let order: usize = super::ints::unsigned("order", order)?;
    let coeffs = sh::project_cap(order, direction, half_angle).map_err(py_err)?;
    let flat: Vec<f32> = coeffs.iter().map(|&c| c as f32).collect();
    Ok(PyArray1::from_vec(py, flat).into_any())
}

/// Rotates SH coefficients `[n²]` or `[n², C]` (`n` in 1..=8) by `rotation` (3×3, maps a
/// direction `d` to `rotation · d`): the coefficients of `g(ω) = f(rotationᵀ ω)`, so a lobe along
/// `d` ends up along `rotation · d`. Exact (Ivanic & Ruedenberg's recurrence, `sh::ShRotation`);
/// float32 out, the input's shape.
#[pyfunction]
pub(super) fn sh_rotate<'py>(
    py: Python<'py>,
    coefficients: &Bound<'py, PyAny>,
    rotation: [[f64; 3]; 3],
) -> PyResult<Bound<'py, PyAny>> {
    let (array, shape) = float_ndarray(coefficients, "coefficients", "[n²] or [n², C]", |s| {
        matches!(s.len(), 1 | 2) && s[0] > 0
    })?;
    let values = flat(&array)?;
    let order = sh::order_of_len(shape[0])
        .map_err(|_| {
            PeltError::parameter(
                "coefficients",
                format!(
                    "must have n² rows for an order n in [1, {}] (1, 4, 9, …, 64), got {}",
                    sh::MAX_ORDER,
                    shape[0]
                ),
            )
        })
        .map_err(py_err)?;
    let turn = sh::ShRotation::new(order, rotation).map_err(py_err)?;
    let columns = shape.get(1).copied().unwrap_or(1);
    let mut out = vec![0.0f32; values.len()];
    for c in 0..columns {
        let column: Vec<f64> = values
            .iter()
            .skip(c)
            .step_by(columns)
            .map(|&v| f64::from(v))
            .collect();
        let turned = turn.apply(&column).map_err(py_err)?;
        for (row, v) in turned.into_iter().enumerate() {
            out[row * columns + c] = v as f32;
        }
    }
    Ok(PyArray1::from_vec(py, out).reshape(shape)?.into_any())
}
