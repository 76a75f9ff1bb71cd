//! The exception tree `pelt.PeltError` > `InvalidMeshError`, `InvalidParameterError` (>
//! `MemoryLimitError`),
//! `BakeCancelled`, `RenderError`, and the one mapping from [`PeltError`] onto it.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

use pelt_core::error::PeltError as CoreError;

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

/// The Python exception for a core error: `.map_err(py_err)` or `.into_pyerr()` (a function and a
/// trait, as the orphan rule forbids `From<CoreError> for PyErr` outside the core's crate).
pub(crate) fn py_err(error: CoreError) -> PyErr {
    error.into_pyerr()
}

/// `CoreError` into its Python exception.
pub(crate) trait IntoPyErr {
    fn into_pyerr(self) -> PyErr;
}

impl IntoPyErr for CoreError {
    fn into_pyerr(self) -> PyErr {
        let message = self.to_string();
        match self {
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
