//! The names written into exported files and the file names made from them, checked in one
//! place for every export (objects, materials).

use crate::error::{PeltError, Result};

/// Most characters of an object name.
pub const MAX_NAME_CHARS: usize = 64;

/// Checks a name written into the file (an object's, a material's): 1 to [`MAX_NAME_CHARS`]
/// characters, none of them a control character; the error names `field`.
pub(crate) fn validate_name(field: &str, name: &str) -> Result<()> {
    let chars = name.chars().count();
    if !(1..=MAX_NAME_CHARS).contains(&chars) || name.chars().any(char::is_control) {
        return Err(PeltError::parameter(
            field,
            format!("must have 1 to {MAX_NAME_CHARS} characters and no control characters, got {name:?}"),
        ));
    }
    Ok(())
}

/// `name` with every character outside `[A-Za-z0-9_.-]` replaced by `_`; a leading `.` too, so
/// no file is hidden.
pub fn file_stem(name: &str) -> String {
    name.chars()
        .enumerate()
        .map(|(i, c)| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' || (c == '.' && i > 0) {
                c
            } else {
                '_'
            }
        })
        .collect()
}
