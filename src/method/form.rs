//! A method's parameters as the text of a form (the page's generic method panel): one text per
//! [`ParamSpec`], read back into the JSON the method checks. Only the *reading* is done here (a
//! field that is not a number of the right kind is named); the values themselves are checked
//! by the method, whose message names the parameter and the accepted range.

use super::{MethodError, ParamKind, ParamSpec};

/// The text a form field shows for `value` (a parameter's JSON value).
pub fn field_text(value: &serde_json::Value) -> String {
    match value {
        serde_json::Value::String(s) => s.clone(),
        serde_json::Value::Array(items) => items.iter().map(field_text).collect::<Vec<_>>().join(","),
        other => other.to_string(),
    }
}

/// The form text of a parameter's default: empty for `null` (the method decides), and a number
/// that is exactly an `f32` (a default written `x as f64`) in the `f32`'s shortest form — `0.8`,
/// not `0.800000011920929`.
pub fn default_text(value: &serde_json::Value) -> String {
    if value.is_null() {
        return String::new();
    }
    if let Some(x) = value.as_f64().filter(|_| value.is_f64()) {
        let short = x as f32;
        if short as f64 == x && x.fract() != 0.0 && short.to_string().len() < x.to_string().len() {
            return short.to_string();
        }
    }
    field_text(value)
}

/// The parameters of a method's form as the page reads them: [`params_from_form`] of the fields
/// that hold something. An empty number field is the method's default — the parameter is left
/// out of the JSON (every field is optional there) — and any empty field whose default is `null`
/// is `null` (the method decides: a labeller's threshold is then its model's own).
pub fn params_from_fields(
    short: &str,
    specs: &[ParamSpec],
    texts: &[String],
) -> Result<serde_json::Value, MethodError> {
    if specs.len() != texts.len() {
        return params_from_form(short, specs, texts);
    }
    let unset: Vec<bool> = specs
        .iter()
        .zip(texts)
        .map(|(s, t)| {
            t.trim().is_empty()
                && (s.default.is_null() || matches!(s.kind, ParamKind::Number { .. } | ParamKind::Integer { .. }))
        })
        .collect();
    let set_specs: Vec<ParamSpec> = specs.iter().zip(&unset).filter(|(_, u)| !**u).map(|(s, _)| s.clone()).collect();
    let set: Vec<String> = texts.iter().zip(&unset).filter(|(_, u)| !**u).map(|(t, _)| t.clone()).collect();
    let mut params = params_from_form(short, &set_specs, &set)?;
    if let Some(object) = params.as_object_mut() {
        for (spec, _) in specs.iter().zip(&unset).filter(|(s, u)| **u && s.default.is_null()) {
            object.insert(spec.name.clone(), serde_json::Value::Null);
        }
    }
    Ok(params)
}

/// The parameters of a form whose fields hold `texts` (one per spec, in order), as a JSON
/// object; `short` names the method in messages, and a refusal carries the field's parameter.
pub fn params_from_form(short: &str, specs: &[ParamSpec], texts: &[String]) -> Result<serde_json::Value, MethodError> {
    if specs.len() != texts.len() {
        return Err(MethodError::params(format!(
            "{short}: the form has {} fields for {} parameters",
            texts.len(),
            specs.len()
        )));
    }
    let mut params = serde_json::Map::new();
    for (spec, text) in specs.iter().zip(texts) {
        let t = text.trim();
        let bad = |expected: &str| {
            MethodError::param(
                &spec.name,
                format!("invalid {short} parameter {} = {t:?}: expected {expected}", spec.name),
            )
        };
        let value = match &spec.kind {
            ParamKind::Number { .. } => {
                let v: f64 = t.parse().ok().filter(|v: &f64| v.is_finite()).ok_or_else(|| bad("a number"))?;
                serde_json::json!(v)
            }
            ParamKind::Integer { .. } => serde_json::json!(t.parse::<i64>().map_err(|_| bad("a whole number"))?),
            ParamKind::Bool => serde_json::json!(t.parse::<bool>().map_err(|_| bad("true or false"))?),
            ParamKind::Choice { .. } => serde_json::json!(t),
            ParamKind::Flags { .. } => serde_json::json!(t
                .split(|c: char| c == ',' || c.is_whitespace())
                .filter(|s| !s.is_empty())
                .collect::<Vec<_>>()),
            ParamKind::IntegerList { .. } => {
                let items: Result<Vec<i64>, _> = t
                    .split(|c: char| c == ',' || c.is_whitespace())
                    .filter(|s| !s.is_empty())
                    .map(str::parse)
                    .collect();
                serde_json::json!(items.map_err(|_| bad("whole numbers separated by commas"))?)
            }
        };
        params.insert(spec.name.clone(), value);
    }
    Ok(serde_json::Value::Object(params))
}

/// A coupled parameter the form's texts break: `param` (at `value`) exceeds `limit_param` (at
/// `limit`), which its spec declares it may not ([`ParamSpec::at_most`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Conflict {
    pub param: String,
    pub value: f64,
    pub limit_param: String,
    pub limit: f64,
}

impl Conflict {
    /// The text to put in `param`'s field to resolve it: the limit, as its field would show it.
    pub fn adjusted_text(&self) -> String {
        // `{}` writes 12.0 as "12", as a user types it
        format!("{}", self.limit)
    }
}

/// The couplings of `specs` that the form's `texts` (one per spec) break. Texts that are not
/// numbers are left to [`params_from_form`] to name.
pub fn conflicts(specs: &[ParamSpec], texts: &[String]) -> Vec<Conflict> {
    let number = |name: &str| {
        let at = specs.iter().position(|s| s.name == name)?;
        texts.get(at)?.trim().parse::<f64>().ok().filter(|v| v.is_finite())
    };
    specs
        .iter()
        .filter_map(|s| {
            let limit_param = s.at_most.as_deref()?;
            let (value, limit) = (number(&s.name)?, number(limit_param)?);
            // a limit the dependent parameter may not take itself (a radius of −1) is no value to
            // adjust it to: the limit's own refusal names what is wrong
            let allowed = match &s.kind {
                ParamKind::Number { min, max } => (*min..=*max).contains(&limit),
                ParamKind::Integer { min, max } => limit.fract() == 0.0 && (*min as f64..=*max as f64).contains(&limit),
                _ => false,
            };
            (allowed && value > limit).then(|| Conflict {
                param: s.name.clone(),
                value,
                limit_param: limit_param.to_string(),
                limit,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fields as the page first shows them.
    fn texts_of(specs: &[ParamSpec]) -> Vec<String> {
        specs.iter().map(|s| default_text(&s.default)).collect()
    }

    /// A limit out of the dependent parameter's own range is no adjustment: SSSM's radius −1 is
    /// refused as a radius, never copied into the primitive radius.
    #[test]
    fn a_limit_the_dependent_may_not_take_is_not_offered() {
        let m = crate::methods::find("sssm").unwrap();
        let specs = m.param_specs();
        let mut texts = texts_of(&specs);
        let radius = specs.iter().position(|s| s.name == "radius").unwrap();
        texts[radius] = "12".into();
        assert_eq!(conflicts(&specs, &texts).len(), 1);
        texts[radius] = "-1".into();
        assert!(conflicts(&specs, &texts).is_empty());
    }

    #[test]
    fn the_defaults_read_back_as_the_defaults_for_every_method() {
        for m in crate::methods::registry() {
            let specs = m.param_specs();
            let params = params_from_fields(&m.info().short, &specs, &texts_of(&specs)).unwrap();
            let checked = m.check_json(&params).unwrap();
            let (echo, defaults) = (checked.echo(), m.defaults());
            assert!(crate::method::echoes_defaults(echo, &defaults), "{}: {echo} for {defaults}", m.info().name);
        }
    }

    #[test]
    fn a_refusal_carries_the_parameter_it_is_about() {
        let m = crate::methods::find("sssm").unwrap();
        let specs = m.param_specs();
        // the method's refusals and the form's, as data (the page places them by it)
        for (params, want) in
            [(serde_json::json!({"radius": -1}), "radius"), (serde_json::json!({"horizon_s": 2}), "horizon_s")]
        {
            let e = m.check_json(&params).unwrap_err();
            assert_eq!(e.param_name(), Some(want), "{e}");
        }
        let mut texts = texts_of(&specs);
        let at = specs.iter().position(|s| s.name == "offsets").unwrap();
        texts[at] = "-10,x".into();
        let e = params_from_form("SSSM", &specs, &texts).unwrap_err();
        assert_eq!(e.param_name(), Some("offsets"), "{e}");
        // a form of the wrong shape is no field's fault
        let e = params_from_form("SSSM", &specs, &texts[1..]).unwrap_err();
        assert_eq!(e.param_name(), None, "{e}");
    }

    #[test]
    fn coupled_parameters_are_declared_as_the_checks_enforce_them() {
        // every declared coupling names a number parameter of the same method
        for m in crate::methods::registry() {
            let specs = m.param_specs();
            for s in specs.iter().filter(|s| s.at_most.is_some()) {
                let other = specs.iter().find(|o| Some(&o.name) == s.at_most.as_ref());
                assert!(
                    other.is_some_and(|o| matches!(o.kind, ParamKind::Number { .. } | ParamKind::Integer { .. })),
                    "{}: {} is at most a parameter it does not have",
                    m.info().name,
                    s.name
                );
            }
        }
        // the SSSM's: radius 12 under the default primitive radius 13 is refused by the check,
        // and the form says which field to lower and to what; once lowered, it runs
        let m = crate::methods::find("sssm").unwrap();
        let specs = m.param_specs();
        assert_eq!(specs.iter().find(|s| s.name == "primitive_radius").unwrap().at_most.as_deref(), Some("radius"));
        let mut texts = texts_of(&specs);
        assert!(conflicts(&specs, &texts).is_empty(), "the defaults agree");
        let at = |name: &str| specs.iter().position(|s| s.name == name).unwrap();
        texts[at("radius")] = "12".into();
        let found = conflicts(&specs, &texts);
        assert_eq!(
            found,
            [Conflict { param: "primitive_radius".into(), value: 13.0, limit_param: "radius".into(), limit: 12.0 }]
        );
        let refused = m.check_json(&params_from_form("SSSM", &specs, &texts).unwrap()).unwrap_err();
        assert_eq!(refused.param_name(), Some("primitive_radius"), "{refused}");
        texts[at("primitive_radius")] = found[0].adjusted_text();
        assert_eq!(texts[at("primitive_radius")], "12");
        assert!(conflicts(&specs, &texts).is_empty());
        m.check_json(&params_from_form("SSSM", &specs, &texts).unwrap()).unwrap();
        // equal is allowed; unreadable texts are the reader's to name, not a conflict
        texts[at("primitive_radius")] = "12".into();
        assert!(conflicts(&specs, &texts).is_empty());
        texts[at("radius")] = "abc".into();
        assert!(conflicts(&specs, &texts).is_empty());
        // the declaration travels with the specs (the page reads them as JSON)
        let json = serde_json::to_value(&specs).unwrap();
        assert_eq!(json[at("primitive_radius")]["at_most"], "radius");
        assert!(json[at("radius")].get("at_most").is_none());
        let back: Vec<ParamSpec> = serde_json::from_value(json).unwrap();
        assert_eq!(back, specs);
    }

    #[test]
    fn fields_that_cannot_be_read_are_named() {
        let m = crate::methods::find("sssm").unwrap();
        let specs = m.param_specs();
        let mut texts = texts_of(&specs);
        let at = |name: &str| specs.iter().position(|s| s.name == name).unwrap();
        texts[at("offsets")] = " -10, -5 0,5,10 ".into();
        texts[at("radius")] = "15".into();
        let v = params_from_form("SSSM", &specs, &texts).unwrap();
        assert_eq!(v["offsets"], serde_json::json!([-10, -5, 0, 5, 10]));
        assert_eq!(v["radius"], 15.0);
        texts[at("radius")] = "abc".into();
        let e = params_from_form("SSSM", &specs, &texts).unwrap_err().to_string();
        assert!(e.starts_with("invalid SSSM parameter radius = \"abc\": expected a number"), "{e}");
        texts[at("radius")] = "19".into();
        texts[at("offsets")] = "-10,x".into();
        assert_eq!(params_from_form("SSSM", &specs, &texts).unwrap_err().param_name(), Some("offsets"));
        texts[at("offsets")] = "0".into();
        texts[at("stop_window")] = "2.5".into();
        assert_eq!(params_from_form("SSSM", &specs, &texts).unwrap_err().param_name(), Some("stop_window"));
        // out of range is the method's to refuse, by name
        texts[at("stop_window")] = "5".into();
        texts[at("radius")] = "-1".into();
        let params = params_from_form("SSSM", &specs, &texts).unwrap();
        assert_eq!(m.check_json(&params).unwrap_err().param_name(), Some("radius"));
    }
}
