//! The memory budget.
//!
//! Pelt runs inside Blender, where running out of memory aborts the process and loses the
//! artist's unsaved work. So every allocation that a user's parameters size is preceded by an
//! estimate of the stage's peak ([`check`]); above [`limit`] the stage refuses with
//! [`PeltError::MemoryLimit`], which names the parameters to lower and their values. The limit
//! defaults to half of the physical memory (or of the container's limit, whichever is smaller),
//! and is set by [`set_limit`] (Python `pelt.set_memory_limit`, the add-on's preferences),
//! `PELT_MEMORY_LIMIT` or the command line's `--memory-limit`.
//!
//! Estimates are upper bounds in f64 (they cannot overflow), from the formulas beside each stage;
//! they count what is alive at once, not every temporary, and a stage may use somewhat less.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{PeltError, Result};

/// Environment variable that sets the limit (bytes, or a number with `K`, `M`, `G`, `T`, binary
/// units, e.g. `6G`).
pub const MEMORY_LIMIT_ENV: &str = "PELT_MEMORY_LIMIT";

/// Share of the physical memory the default limit allows.
pub const DEFAULT_SHARE: f64 = 0.5;

/// Smallest limit that can be set: below it even the default bake would be refused.
pub const MIN_LIMIT: u64 = 64 << 20;

/// The limit set by [`set_limit`]; 0 while none is (the environment or the default applies).
static LIMIT: AtomicU64 = AtomicU64::new(0);

/// Bytes of physical memory (the container's limit when smaller), read once.
pub fn physical_memory() -> u64 {
    static TOTAL: OnceLock<u64> = OnceLock::new();
    *TOTAL.get_or_init(|| {
        use sysinfo::{MemoryRefreshKind, RefreshKind, System};
        let system = System::new_with_specifics(
            RefreshKind::nothing().with_memory(MemoryRefreshKind::nothing().with_ram()),
        );
        let total = system.total_memory();
        let container = system.cgroup_limits().map(|c| c.total_memory).filter(|&m| m > 0);
        match (total, container) {
            (0, None) => 8 << 30, // Unknown: assume a modest machine.
            (0, Some(c)) => c,
            (t, Some(c)) => t.min(c),
            (t, None) => t,
        }
    })
}

/// The limit used when none is set: [`DEFAULT_SHARE`] of [`physical_memory`].
pub fn default_limit() -> u64 {
    ((physical_memory() as f64 * DEFAULT_SHARE) as u64).max(MIN_LIMIT)
}

/// The limit in bytes: the one set by [`set_limit`], else `PELT_MEMORY_LIMIT`, else
/// [`default_limit`]. A malformed `PELT_MEMORY_LIMIT` is ignored here (the command line refuses it
/// through [`limit_from_env`]).
pub fn limit() -> u64 {
    match LIMIT.load(Ordering::Relaxed) {
        0 => limit_from_env().ok().flatten().unwrap_or_else(default_limit),
        set => set,
    }
}

/// Sets the limit in bytes for later work; `None` returns to `PELT_MEMORY_LIMIT` or the default.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `memory_limit` below [`MIN_LIMIT`].
pub fn set_limit(bytes: Option<u64>) -> Result<()> {
    match bytes {
        Some(b) if b < MIN_LIMIT => Err(PeltError::parameter(
            "memory_limit",
            format!(
                "must be at least {} (or None for the default), got {}",
                size(MIN_LIMIT as f64),
                size(b as f64)
            ),
        )),
        _ => {
            LIMIT.store(bytes.unwrap_or(0), Ordering::Relaxed);
            Ok(())
        }
    }
}

/// The limit `PELT_MEMORY_LIMIT` asks for, `None` when it is unset or empty.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `PELT_MEMORY_LIMIT` when it is not a size of at least
/// [`MIN_LIMIT`].
pub fn limit_from_env() -> Result<Option<u64>> {
    match std::env::var(MEMORY_LIMIT_ENV) {
        Ok(text) if !text.trim().is_empty() => parse_size(MEMORY_LIMIT_ENV, &text).map(Some),
        _ => Ok(None),
    }
}

/// Parses a size such as `6G`, `512M` or `1073741824` (binary units) of at least [`MIN_LIMIT`];
/// errors name `what`.
pub fn parse_size(what: &str, text: &str) -> Result<u64> {
    let t = text.trim();
    let (number, unit) = match t.find(|c: char| c.is_ascii_alphabetic()) {
        Some(i) => (&t[..i], t[i..].trim_end_matches(['B', 'b', 'i'])),
        None => (t, ""),
    };
    let scale = match unit.to_ascii_uppercase().as_str() {
        "" => Some(1.0),
        "K" => Some(1024.0),
        "M" => Some(1024.0 * 1024.0),
        "G" => Some(1024.0 * 1024.0 * 1024.0),
        "T" => Some(1024.0 * 1024.0 * 1024.0 * 1024.0),
        _ => None,
    };
    let bytes = number.trim().parse::<f64>().ok().zip(scale).map(|(n, s)| n * s);
    match bytes {
        Some(b) if b.is_finite() && b >= MIN_LIMIT as f64 && b < u64::MAX as f64 => Ok(b as u64),
        _ => Err(PeltError::parameter(
            what,
            format!(
                "must be a size of at least {} such as 6G or 512M, got {text:?}",
                size(MIN_LIMIT as f64)
            ),
        )),
    }
}

/// `bytes` for people: `74.0 GiB`, `512.0 MiB`.
pub fn size(bytes: f64) -> String {
    const UNITS: [&str; 6] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut value = bytes;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{value:.0} B")
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

/// `Ok` when `stage`'s estimated peak `bytes` fits [`limit`]; otherwise
/// [`PeltError::MemoryLimit`] naming the stage and the parameters to `lower` (with their values,
/// e.g. "`resolution` (4096) or `layers` (256)").
pub fn check(stage: &str, bytes: f64, lower: impl FnOnce() -> String) -> Result<()> {
    let limit = limit();
    if bytes.is_finite() && bytes <= limit as f64 {
        return Ok(());
    }
    Err(PeltError::MemoryLimit {
        stage: stage.into(),
        needed: if bytes.is_finite() {
            size(bytes)
        } else {
            "more than any machine has".into()
        },
        limit: size(limit as f64),
        lower: lower(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_in_binary_units_and_bad_ones_are_named() {
        assert_eq!(parse_size("x", "6G").unwrap(), 6 << 30);
        assert_eq!(parse_size("x", " 512 MiB ").unwrap(), 512 << 20);
        assert_eq!(parse_size("x", "1.5g").unwrap(), 3 << 29);
        assert_eq!(parse_size("x", "1073741824").unwrap(), 1 << 30);
        for bad in ["", "lots", "-1G", "1M", "nanG", "6X", "1e30T"] {
            let error = parse_size("PELT_MEMORY_LIMIT", bad).unwrap_err().to_string();
            assert!(
                error.contains("PELT_MEMORY_LIMIT") && error.contains("64.0 MiB"),
                "{bad}: {error}"
            );
        }
        assert_eq!(size(74.0 * (1u64 << 30) as f64), "74.0 GiB");
        assert_eq!(size(100.0), "100 B");
    }

    #[test]
    fn the_check_names_stage_need_limit_and_what_to_lower() {
        assert!(physical_memory() >= MIN_LIMIT);
        assert!(check("bake_volume", 1024.0, String::new).is_ok());
        let error = check("bake_volume", 1e30, || "`layers` (256)".into()).unwrap_err();
        let message = error.to_string();
        assert!(matches!(error, PeltError::MemoryLimit { .. }));
        for part in ["bake_volume", "needs", "`layers` (256)", &size(limit() as f64)] {
            assert!(message.contains(part), "{part}: {message}");
        }
        assert!(check("x", f64::INFINITY, String::new).is_err());
        assert!(check("x", f64::NAN, String::new).is_err());
        assert!(
            set_limit(Some(1))
                .unwrap_err()
                .to_string()
                .contains("memory_limit")
        );
    }
}
