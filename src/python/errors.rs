//! The exception tree `pelt.PeltError` > `InvalidMeshError`, `InvalidParameterError` (>
//! `MemoryLimitError`),
//! `BakeCancelled`, `RenderError`, and the one mapping from [`PeltError`] onto it.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

use crate::error::PeltError as CoreError;

create_exception!(
    pelt,
    PeltError,
    PyException,
    "Base class of every error Pelt raises."
);
create_exception!(
    pelt,
    InvalidMeshError,
    PeltError,
    "The mesh or an attribute array is unusable; the message names the element."
);
create_exception!(
    pelt,
    InvalidParameterError,
    PeltError,
    "A parameter is outside its allowed range."
);
create_exception!(
    pelt,
    MemoryLimitError,
    InvalidParameterError,
    "The parameters ask for more memory than the limit (pelt.set_memory_limit) allows; the \
     message names the parameters to lower."
);
create_exception!(pelt, BakeCancelled, PeltError, "A bake was cancelled.");
create_exception!(pelt, RenderError, PeltError, "The GPU renderer failed.");

impl From<CoreError> for PyErr {
    fn from(error: CoreError) -> PyErr {
        let message = error.to_string();
        match error {
            CoreError::InvalidMesh(_) => InvalidMeshError::new_err(message),
            CoreError::InvalidParameter { .. } => InvalidParameterError::new_err(message),
            CoreError::MemoryLimit { .. } => MemoryLimitError::new_err(message),
            CoreError::Cancelled => BakeCancelled::new_err(message),
            CoreError::Render(_) => RenderError::new_err(message),
            CoreError::Io { .. } | CoreError::Internal(_) => PeltError::new_err(message),
        }
    }
}

pub(super) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("PeltError", py.get_type::<PeltError>())?;
    m.add("InvalidMeshError", py.get_type::<InvalidMeshError>())?;
    m.add("InvalidParameterError", py.get_type::<InvalidParameterError>())?;
    m.add("MemoryLimitError", py.get_type::<MemoryLimitError>())?;
    m.add("BakeCancelled", py.get_type::<BakeCancelled>())?;
    m.add("RenderError", py.get_type::<RenderError>())?;
    Ok(())
}
