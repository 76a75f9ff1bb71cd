//! The one error type of Pelt's crates.
//!
//! Every fallible public function returns [`Result`]. The Python layer maps each variant onto one
//! exception class of the tree `pelt.PeltError` > `InvalidMeshError`, `InvalidParameterError`
//! (> `MemoryLimitError`), `BakeCancelled`, `RenderError` (`crates/pelt-python/src/errors.rs`),
//! so the variants here are the categories a user can act on, and the message names the element
//! that is wrong.

use thiserror::Error;

/// Result alias used throughout the crate.
pub type Result<T, E = PeltError> = std::result::Result<T, E>;

/// Everything that can go wrong in Pelt.
#[derive(Debug, Error)]
pub enum PeltError {
    /// The mesh or one of its attribute arrays is unusable; the message names the element.
    #[error("invalid mesh: {0}")]
    InvalidMesh(#[from] MeshError),

    /// A parameter is out of its documented range.
    #[error("invalid parameter `{name}`: {reason}")]
    InvalidParameter {
        /// Parameter name as the user spells it.
        name: String,
        /// What is wrong with it, including the allowed range.
        reason: String,
    },

    /// A stage's parameters ask for more memory than the budget allows (see [`crate::memory`]).
    #[error(
        "`{stage}` needs {needed}, above the memory limit of {limit}: lower {lower}, or raise the \
         limit (pelt.set_memory_limit, PELT_MEMORY_LIMIT, the add-on's preferences)"
    )]
    MemoryLimit {
        /// The stage that would allocate.
        stage: String,
        /// Its estimated peak, for people.
        needed: String,
        /// The limit, for people.
        limit: String,
        /// The parameters that size it, with their values.
        lower: String,
    },

    /// A long operation was cancelled through its cancel flag.
    #[error("cancelled")]
    Cancelled,

    /// The GPU renderer failed (no adapter, device lost, out of memory, shader error).
    #[error("render error: {0}")]
    Render(String),

    /// Reading or writing a file failed.
    #[error("I/O error on {path}: {source}")]
    Io {
        /// The file involved.
        path: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },

    /// A bug in Pelt (for example a caught panic). Please report it.
    #[error("internal error: {0}")]
    Internal(String),
}

impl PeltError {
    /// Shorthand for [`PeltError::InvalidParameter`].
    pub fn parameter(name: impl Into<String>, reason: impl Into<String>) -> Self {
        PeltError::InvalidParameter {
            name: name.into(),
            reason: reason.into(),
        }
    }
}

/// A number as a message shows it: as Rust writes it, but in exponent form when it is huge or
/// tiny (`1e300`, not three hundred digits; `1e-30`, not thirty zeros).
#[derive(Debug, Clone, Copy)]
pub struct Num(pub f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let x = self.0;
        if x.is_finite() && x != 0.0 && !(1e-5..1e16).contains(&x.abs()) {
            write!(f, "{x:e}")
        } else {
            write!(f, "{x}")
        }
    }
}

/// `Ok` when `value` lies in `[lo, hi]`; otherwise [`PeltError::InvalidParameter`] naming `name`
/// and the range (NaN is outside every range). The range check shared by the parameter structs.
pub fn check_range(name: &str, value: f64, lo: f64, hi: f64) -> Result<()> {
    if (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(PeltError::parameter(
            name,
            format!("must be in [{}, {}], got {}", Num(lo), Num(hi), Num(value)),
        ))
    }
}

/// What is wrong with a mesh. Each variant names the array and the row involved.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MeshError {
    /// The mesh has no vertices or no triangles.
    #[error("the mesh has no {0}")]
    Empty(&'static str),

    /// An array does not have the expected shape (raised by bindings that receive untyped arrays).
    #[error("`{array}` must have shape {expected}, got {got}")]
    Shape {
        /// Array name.
        array: &'static str,
        /// Expected shape, e.g. `[N, 3]`.
        expected: String,
        /// Actual shape.
        got: String,
    },

    /// An array has an element type that cannot be converted losslessly.
    #[error("`{array}` has dtype {got}, expected {expected}")]
    DType {
        /// Array name.
        array: &'static str,
        /// Expected element type.
        expected: &'static str,
        /// Actual element type.
        got: String,
    },

    /// A per-vertex attribute has the wrong number of rows.
    #[error("`{array}` has {got} rows but the mesh has {expected} vertices")]
    AttributeLength {
        /// Array name.
        array: &'static str,
        /// Number of vertices.
        expected: usize,
        /// Rows given.
        got: usize,
    },

    /// A per-triangle attribute has the wrong number of rows.
    #[error("`{array}` has {got} rows but the mesh has {expected} triangles")]
    TriangleAttributeLength {
        /// Array name.
        array: &'static str,
        /// Number of triangles.
        expected: usize,
        /// Rows given.
        got: usize,
    },

    /// A NaN or infinity was found.
    #[error("`{array}` row {row} component {component} is {value} (not finite)")]
    NonFinite {
        /// Array name.
        array: &'static str,
        /// Row (vertex) index.
        row: usize,
        /// Column index.
        component: usize,
        /// The offending value.
        value: f32,
    },

    /// A triangle refers to a vertex that does not exist.
    #[error(
        "triangle {triangle} corner {corner} refers to vertex {index}, but the mesh has {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// Triangle index.
        triangle: usize,
        /// Corner (0, 1, 2).
        corner: usize,
        /// The bad index (as given, so negative values from signed arrays survive).
        index: i64,
        /// Number of vertices.
        vertex_count: usize,
    },

    /// A hair length multiplier outside `[0, MAX_LENGTH]`.
    #[error("`length` of vertex {vertex} is {}, outside [0, {max}]", Num(f64::from(*value)))]
    LengthOutOfRange {
        /// Vertex index.
        vertex: usize,
        /// The value.
        value: f32,
        /// The allowed maximum.
        max: f32,
    },

    /// A given vertex normal has zero length, so it has no direction.
    #[error("`normals` row {row} has zero length")]
    ZeroNormal {
        /// Vertex index.
        row: usize,
    },

    /// More vertices than 32-bit indices can address.
    #[error("the mesh has {0} vertices; at most 4294967295 are supported")]
    TooManyVertices(usize),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_and_tiny_numbers_show_in_exponent_form() {
        let shown = |x: f64| Num(x).to_string();
        assert_eq!(shown(1e300), "1e300");
        assert_eq!(shown(-3.4e38), "-3.4e38");
        assert_eq!(shown(1e-30), "1e-30");
        assert_eq!(shown(0.25), "0.25");
        assert_eq!(shown(12345.5), "12345.5");
        assert_eq!(shown(0.0), "0");
        assert_eq!(shown(f64::NAN), "NaN");
        assert_eq!(shown(f64::INFINITY), "inf");
        let error = check_range("curl", 1e300, 0.0, 1.0).unwrap_err().to_string();
        assert!(error.ends_with("must be in [0, 1], got 1e300"), "{error}");
    }
}
