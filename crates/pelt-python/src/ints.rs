//! Integer arguments of the Python API. They are taken as any Python int (`i128`) and narrowed
//! here, so a negative or oversized value raises `InvalidParameterError` naming the argument and
//! its range; an unsigned argument type would raise an `OverflowError` that names nothing.

use pyo3::PyResult;

use crate::errors::IntoPyErr;
use pelt_core::error::PeltError;

/// Unsigned integer types an argument narrows to.
pub(super) trait Unsigned: TryFrom<i128> {
    /// The largest value, for the message.
    const MAX: u128;
}

impl Unsigned for u32 {
    const MAX: u128 = u32::MAX as u128;
}

impl Unsigned for u64 {
    const MAX: u128 = u64::MAX as u128;
}

impl Unsigned for usize {
    const MAX: u128 = usize::MAX as u128;
}

/// `value` as `T`, or `InvalidParameterError` naming `name` when it is negative or too large.
pub(super) fn unsigned<T: Unsigned>(name: &str, value: i128) -> PyResult<T> {
    T::try_from(value).map_err(|_| {
        PeltError::parameter(
            name,
            format!("must be an integer in [0, {}], got {value}", T::MAX),
        )
        .into_pyerr()
    })
}

/// [`unsigned`] for an optional argument.
pub(super) fn unsigned_opt<T: Unsigned>(name: &str, value: Option<i128>) -> PyResult<Option<T>> {
    value.map(|v| unsigned(name, v)).transpose()
}

/// [`unsigned`] for a pair (`name[0]`, `name[1]`).
pub(super) fn unsigned_pair<T: Unsigned>(name: &str, value: (i128, i128)) -> PyResult<(T, T)> {
    Ok((
        unsigned(&format!("{name}[0]"), value.0)?,
        unsigned(&format!("{name}[1]"), value.1)?,
    ))
}
