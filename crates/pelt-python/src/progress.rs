//! A Python progress callable as a core [`ProgressCallback`](pelt_core::progress::ProgressCallback).
//!
//! The core reports from its worker threads with the GIL released; each report attaches to the
//! interpreter just long enough to call the callable. Returning `False` cancels the stage
//! (`pelt.BakeCancelled`); an exception inside the callable also stops the stage, and is the one
//! raised to the caller, so a bug in a progress bar is not mistaken for a cancel.

use std::sync::Mutex;

use pyo3::prelude::*;

/// Holds the callable and the first exception it raised.
pub(super) struct PyProgress {
    callable: Option<Py<PyAny>>,
    raised: Mutex<Option<PyErr>>,
}

impl PyProgress {
    /// Wraps `callable` (`None`: no reporting).
    pub(super) fn new(callable: Option<Bound<'_, PyAny>>) -> Self {
        PyProgress {
            callable: callable.map(Bound::unbind),
            raised: Mutex::new(None),
        }
    }

    /// Whether a callable was given.
    pub(super) fn is_some(&self) -> bool {
        self.callable.is_some()
    }

    /// Calls the callable with `fraction`; `false` to cancel.
    pub(super) fn report(&self, fraction: f64) -> bool {
        self.call(|py, callable| callable.call1(py, (fraction,)))
    }

    /// Calls the callable with `(stage, fraction)`; `false` to cancel.
    pub(super) fn report_stage(&self, stage: &str, fraction: f64) -> bool {
        self.call(|py, callable| callable.call1(py, (stage, fraction)))
    }

    fn call(&self, invoke: impl FnOnce(Python<'_>, &Py<PyAny>) -> PyResult<Py<PyAny>>) -> bool {
        let Some(callable) = &self.callable else {
            return true;
        };
        Python::attach(|py| match invoke(py, callable) {
            // Only an explicit `False` cancels: a callable returning None keeps going.
            Ok(answer) => !answer.bind(py).is(pyo3::types::PyBool::new(py, false).as_any()),
            Err(error) => {
                let mut raised = self.raised.lock().unwrap_or_else(|e| e.into_inner());
                raised.get_or_insert(error);
                false
            }
        })
    }

    /// The callable's exception, if it raised one, else `result` unchanged.
    pub(super) fn finish<T>(self, result: PyResult<T>) -> PyResult<T> {
        match self.raised.into_inner().unwrap_or_else(|e| e.into_inner()) {
            Some(error) => Err(error),
            None => result,
        }
    }
}
