//! The exported schema against the sets' own `validate`: every range's ends are accepted and the
//! values just past them refused with the range's name, and every number of a set has a range.

use serde_json::Value;

use super::{BakeKeywords, schemas};
use crate::error::{PeltError, Result};
use crate::field::FieldParams;
use crate::hair::HairParams;
use crate::lapped::PatchParams;
use crate::pipeline::BakeParams;
use crate::prt::TransferParams;
use crate::volume::VolumeParams;

/// Numbers that take any value: a seed; a direction (any finite nonzero vector).
const UNBOUNDED: [&str; 2] = ["seed", "down"];

/// Deserializes `value` as the set `schema` names and validates it.
fn validate(schema: &str, value: Value) -> Result<()> {
    match schema {
        "hair" => serde_json::from_value::<HairParams>(value).unwrap().validate(),
        "volume" => serde_json::from_value::<VolumeParams>(value).unwrap().validate(),
        "transfer" => serde_json::from_value::<TransferParams>(value)
            .unwrap()
            .validate(),
        "patches" => serde_json::from_value::<PatchParams>(value).unwrap().validate(),
        "field" => serde_json::from_value::<FieldParams>(value).unwrap().validate(),
        "bake" => serde_json::from_value::<BakeKeywords>(value)
            .unwrap()
            .apply(BakeParams::default())
            .validate_ranges(),
        other => panic!("no set {other}"),
    }
}

/// The field `name` (`a.b`, `a[i]`) of `root`.
fn field<'a>(root: &'a mut Value, name: &str) -> &'a mut Value {
    name.split('.').fold(root, |v, part| match part.split_once('[') {
        Some((key, index)) => &mut v[key][index.trim_end_matches(']').parse::<usize>().unwrap()],
        None => &mut v[part],
    })
}

/// `defaults` with `name` set to `x` (each element of an array: a pair, a color).
fn with(defaults: &Value, name: &str, x: f64) -> Value {
    let mut value = defaults.clone();
    let target = field(&mut value, name);
    let integer = |v: &Value| v.is_u64() || v.is_i64();
    let number = |old: &Value| {
        if integer(old) {
            Value::from(x as i64)
        } else {
            Value::from(x)
        }
    };
    match target {
        Value::Array(items) => items.iter_mut().for_each(|v| *v = number(v)),
        v => *v = number(v),
    }
    value
}

fn refused_as(result: Result<()>) -> String {
    match result {
        Err(PeltError::InvalidParameter { name, .. }) => name,
        other => panic!("expected a refusal, got {other:?}"),
    }
}

#[test]
fn every_range_is_the_one_validate_checks() {
    for schema in schemas() {
        let defaults = &schema.defaults;
        validate(schema.name, defaults.clone()).unwrap();
        for range in schema.ranges {
            let integer = {
                let mut copy = defaults.clone();
                let f = field(&mut copy, range.name).clone();
                f.is_u64() || f.as_array().is_some_and(|a| a[0].is_u64())
            };
            let step = if integer {
                1.0
            } else {
                (range.max - range.min).abs().max(1.0) * 1e-4
            };
            // A dependent range starts at its field's value (the defaults' here).
            let min = match range.min_field {
                Some(other) => field(&mut defaults.clone(), other).as_f64().unwrap(),
                None => range.min,
            };
            let lowest = if range.min_open { min + step } else { min };
            for inside in [lowest, range.max] {
                let mut value = with(defaults, range.name, inside);
                // The transfer spaces its layers within narrower bounds than the fur depth's own
                // (checked before any stage runs, naming `fur_depth`): the depth's range is the
                // bake's without a transfer.
                if (schema.name, range.name) == ("bake", "fur_depth") {
                    value["transfer"] = Value::Bool(false);
                }
                // Ranges that start at this field's value move up with it.
                for dependent in schema.ranges.iter().filter(|r| r.min_field == Some(range.name)) {
                    value = with(&value, dependent.name, dependent.max);
                }
                let result = validate(schema.name, value);
                assert!(
                    result.is_ok(),
                    "{}.{} = {inside}: {result:?}",
                    schema.name,
                    range.name
                );
            }
            let below = if range.min_open { min } else { min - step };
            // An unsigned field cannot hold a value below 0 at all, nor JSON a value past f64::MAX.
            let mut outside = vec![range.max + step];
            outside.retain(|x| x.is_finite());
            if !(integer && below < 0.0) {
                outside.push(below);
            }
            for x in outside {
                let name = refused_as(validate(schema.name, with(defaults, range.name, x)));
                assert_eq!(name, range.name, "{}.{} = {x}", schema.name, range.name);
            }
        }
    }
}

/// The numeric leaves of `value` under `prefix`, as the schema names them (an array of numbers
/// is one leaf, or one per element where the schema names them `x[i]`).
fn numbers(value: &Value, prefix: &str, out: &mut Vec<String>) {
    match value {
        Value::Number(_) => out.push(prefix.to_string()),
        Value::Array(items) if items.iter().all(Value::is_number) => out.push(prefix.to_string()),
        Value::Object(map) => {
            for (key, v) in map {
                let name = if prefix.is_empty() {
                    key.clone()
                } else {
                    format!("{prefix}.{key}")
                };
                numbers(v, &name, out);
            }
        }
        _ => {}
    }
}

#[test]
fn every_number_of_a_set_has_a_range() {
    for schema in schemas() {
        let mut leaves = Vec::new();
        numbers(&schema.defaults, "", &mut leaves);
        for leaf in leaves {
            let named = schema
                .ranges
                .iter()
                .any(|r| r.name == leaf || r.name.starts_with(&format!("{leaf}[")));
            assert!(
                named || UNBOUNDED.contains(&leaf.as_str()),
                "{}.{leaf} has no range in the schema",
                schema.name
            );
        }
    }
}
