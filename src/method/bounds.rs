//! Numeric parameters described once — name, accepted range, unit, help, whether the basic form
//! shows it — so a method's check, its messages and the specs its forms are built from can never
//! disagree. The kinematic baselines declare theirs as a table of [`NumberParam`]s.

use super::{MethodError, ParamKind, ParamSpec};

/// One numeric parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NumberParam {
    pub name: &'static str,
    pub min: f64,
    pub max: f64,
    /// Empty when the number has no unit.
    pub unit: &'static str,
    pub help: &'static str,
    /// Shown in the basic form (the others under "advanced").
    pub basic: bool,
}

/// The working frame rate most methods resample takes to (their `fps` parameter).
pub const WORKING_FPS: NumberParam = NumberParam {
    name: "fps",
    min: 10.0,
    max: 240.0,
    unit: "Hz",
    help: "Frame rate the method works at; takes are resampled to it.",
    basic: false,
};

/// Parameters that passed their method's check; the method only ever runs on these.
#[derive(Debug, Clone, PartialEq)]
pub struct Valid<P>(P);

impl<P> Valid<P> {
    /// Marks `params` as checked (only a method's `check` should call this).
    pub(crate) fn checked(params: P) -> Self {
        Valid(params)
    }
}

impl<P> std::ops::Deref for Valid<P> {
    type Target = P;
    fn deref(&self) -> &P {
        &self.0
    }
}

/// A value as messages show it: plainly, or in exponent form when huge (`1e300`, not 301 digits).
pub fn shown(v: f64) -> String {
    if v.is_finite() && v.abs() < 1e6 {
        v.to_string()
    } else {
        format!("{v:e}").replace("e0", "")
    }
}

/// `invalid <short> parameter <name> = <value>: expected <expected>`.
pub fn refuse(short: &str, name: &str, value: f64, expected: &str) -> MethodError {
    MethodError::param(name, format!("invalid {short} parameter {name} = {}: expected {expected}", shown(value)))
}

/// Checks the value of every parameter of `table` (read by `value(name)`) against its range.
pub fn check(short: &str, table: &[NumberParam], value: impl Fn(&str) -> f64) -> Result<(), MethodError> {
    for p in table {
        let v = value(p.name);
        if !(v.is_finite() && (p.min..=p.max).contains(&v)) {
            let range = format!("{} to {} {}", p.min, p.max, p.unit);
            return Err(refuse(short, p.name, v, range.trim_end()));
        }
    }
    Ok(())
}

/// The specs of `table`, each with its default `default(name)`.
pub fn specs(table: &[NumberParam], default: impl Fn(&str) -> f64) -> Vec<ParamSpec> {
    table
        .iter()
        .map(|p| ParamSpec {
            name: p.name.into(),
            help: p.help.into(),
            kind: ParamKind::Number { min: p.min, max: p.max },
            default: serde_json::json!(default(p.name)),
            unit: (!p.unit.is_empty()).then(|| p.unit.into()),
            basic: p.basic,
            at_most: None,
        })
        .collect()
}

/// The spec of a switch.
pub fn switch(name: &str, help: &str, default: bool, basic: bool) -> ParamSpec {
    ParamSpec {
        name: name.into(),
        help: help.into(),
        kind: ParamKind::Bool,
        default: serde_json::json!(default),
        unit: None,
        basic,
        at_most: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TABLE: [NumberParam; 2] = [
        NumberParam { name: "a", min: 0.0, max: 1.0, unit: "s", help: "A.", basic: true },
        NumberParam { name: "b", min: 2.0, max: 3.0, unit: "", help: "B.", basic: false },
    ];

    #[test]
    fn ranges_are_checked_and_named() {
        let ok = |n: &str| if n == "a" { 0.5 } else { 2.0 };
        assert!(check("X", &TABLE, ok).is_ok());
        let e = check("X", &TABLE, |n| if n == "a" { 1e300 } else { 2.0 }).unwrap_err().to_string();
        assert_eq!(e, "invalid X parameter a = 1e300: expected 0 to 1 s");
        let e = check("X", &TABLE, |n| if n == "a" { 0.0 } else { f64::NAN }).unwrap_err();
        assert_eq!(e.param_name(), Some("b"), "the refusal carries the parameter's name");
        assert_eq!(e.to_string(), "invalid X parameter b = NaN: expected 2 to 3");
        let specs = specs(&TABLE, ok);
        assert_eq!((specs[0].unit.as_deref(), specs[1].unit.as_deref()), (Some("s"), None));
        assert_eq!(specs[1].default, 2.0);
        assert_eq!(specs[0].kind, ParamKind::Number { min: 0.0, max: 1.0 });
    }
}
