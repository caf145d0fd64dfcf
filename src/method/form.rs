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

#[cfg(test)]
mod tests {
    use super::*;

    fn texts_of(specs: &[ParamSpec]) -> Vec<String> {
        specs.iter().map(|s| field_text(&s.default)).collect()
    }

    #[test]
    fn the_defaults_read_back_as_the_defaults_for_every_method() {
        for m in crate::methods::registry() {
            let specs = m.param_specs();
            let params = params_from_form(&m.info().short, &specs, &texts_of(&specs)).unwrap();
            let checked = m.check_json(&params).unwrap();
            assert_eq!(checked.echo(), &m.defaults(), "{}", m.info().name);
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
