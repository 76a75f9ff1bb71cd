//! One schema per parameter set: every number's range and unit is stated once, as a [`Range`]
//! constant beside its set, which the set's `validate` checks and
//! [`pipeline::schemas`](crate::pipeline::schemas) exports with the set's defaults (Python
//! `pelt.SCHEMA`, against which the add-on's properties and the module's keyword defaults are
//! tested).
//! A range whose lower end is another field's value (a stretch limit above the stretch tolerance)
//! names that field in `min_field`; `min` is then the lowest that field allows.

use serde::Serialize;

use crate::error::{Num, PeltError, Result, check_range};

/// A number's range: closed, or open at its lower end (`min_open`: a share that must not be 0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Range {
    /// The parameter's name as errors, Python and the add-on spell it (`undercoat.length`,
    /// `fin_size[0]`).
    pub name: &'static str,
    pub min: f64,
    /// The value `min` itself is refused.
    pub min_open: bool,
    pub max: f64,
    /// The field whose value is the real lower end, when it depends on one (checked by the set's
    /// `validate`).
    pub min_field: Option<&'static str>,
    /// What the number counts, in words (`"tile widths"`, `"radians"`, `"share"`).
    pub unit: &'static str,
}

impl Range {
    /// `[min, max]`.
    pub const fn closed(name: &'static str, min: f64, max: f64, unit: &'static str) -> Range {
        Range {
            name,
            min,
            min_open: false,
            max,
            min_field: None,
            unit,
        }
    }

    /// `[value of min_field, max]`; `min` is the lowest `min_field` itself allows.
    pub const fn above_field(
        name: &'static str,
        min_field: &'static Range,
        max: f64,
        unit: &'static str,
    ) -> Range {
        Range {
            name,
            min: min_field.min,
            min_open: false,
            max,
            min_field: Some(min_field.name),
            unit,
        }
    }

    /// `(min, max]`.
    pub const fn open_below(name: &'static str, min: f64, max: f64, unit: &'static str) -> Range {
        Range {
            name,
            min,
            min_open: true,
            max,
            min_field: None,
            unit,
        }
    }

    /// Whether `value` lies in the range (NaN never does).
    pub fn contains(&self, value: f64) -> bool {
        value <= self.max
            && if self.min_open {
                value > self.min
            } else {
                value >= self.min
            }
    }

    /// `value` checked against `[lowest, max]`, `lowest` being the value of `min_field`.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] when `value` is outside.
    pub fn check_above(&self, value: f64, lowest: f64) -> Result<()> {
        check_range(self.name, value, lowest, self.max)
    }

    /// `value`, or an error naming the parameter, its range and the value.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] when `value` is outside.
    pub fn check(&self, value: f64) -> Result<()> {
        if !self.min_open {
            return check_range(self.name, value, self.min, self.max);
        }
        if self.contains(value) {
            return Ok(());
        }
        let range = if self.max == f64::MAX {
            format!("a finite number > {} ({})", Num(self.min), self.unit)
        } else {
            format!("in ({}, {}]", Num(self.min), Num(self.max))
        };
        Err(PeltError::parameter(
            self.name,
            format!("must be {range}, got {}", Num(value)),
        ))
    }

    /// Each of `values` (a color's components), the error naming the first one outside.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] when a component is outside.
    pub fn check_each(&self, values: &[f64]) -> Result<()> {
        for (i, &v) in values.iter().enumerate() {
            if !self.contains(v) {
                return Err(PeltError::parameter(
                    self.name,
                    format!(
                        "component {i} must be in [{}, {}], got {}",
                        Num(self.min),
                        Num(self.max),
                        Num(v)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// A `[min, max]` pair: both inside, and in order.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] when either is outside or they are reversed.
    pub fn check_pair(&self, pair: [f64; 2]) -> Result<()> {
        self.check(pair[0])?;
        self.check(pair[1])?;
        if pair[0] > pair[1] {
            return Err(PeltError::parameter(
                self.name,
                format!(
                    "must be [min, max] with min <= max, got [{}, {}]",
                    pair[0], pair[1]
                ),
            ));
        }
        Ok(())
    }
}

/// One parameter set: its defaults (as serde writes them) and its numbers' ranges.
#[derive(Debug, Clone, Serialize)]
pub struct Schema {
    /// The set, as Python names it (`bake`, `hair`, `volume`, `transfer`, `patches`).
    pub name: &'static str,
    pub defaults: serde_json::Value,
    pub ranges: &'static [Range],
}

impl Schema {
    /// The set `name`: `T::default()` as its defaults, and its `ranges`.
    pub fn new<T: Serialize + Default>(name: &'static str, ranges: &'static [Range]) -> Schema {
        Schema {
            name,
            // Plain data with string keys: serializing it cannot fail.
            defaults: serde_json::to_value(T::default()).unwrap_or_default(),
            ranges,
        }
    }
}
