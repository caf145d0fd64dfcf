//! A method's parameters as the text of a form (the page's generic method panel): one text per
//! [`ParamSpec`], read back into the JSON the method checks. Only the *reading* is done here (a
//! field that is not a number of the right kind is named); the values themselves are checked
//! by the method, whose message names the parameter and the accepted range.

use super::{ParamKind, ParamSpec};

/// The text a form field shows for `value` (a parameter's JSON value).
pub fn field_text(value: &serde_json::Value) -> String {
    match value {
        serde_json::Value::String(s) => s.clone(),
        serde_json::Value::Array(items) => items.iter().map(field_text).collect::<Vec<_>>().join(","),
        other => other.to_string(),
    }
}

/// The parameters of a form whose fields hold `texts` (one per spec, in order), as a JSON
/// object; `short` names the method in messages.
pub fn params_from_form(short: &str, specs: &[ParamSpec], texts: &[String]) -> Result<serde_json::Value, String> {
    if specs.len() != texts.len() {
        return Err(format!("{short}: the form has {} fields for {} parameters", texts.len(), specs.len()));
    }
    let mut params = serde_json::Map::new();
    for (spec, text) in specs.iter().zip(texts) {
        let t = text.trim();
        let bad = |expected: &str| format!("invalid {short} parameter {} = {t:?}: expected {expected}", spec.name);
        let value = match &spec.kind {
            ParamKind::Number { .. } => {
                let v: f64 = t.parse().ok().filter(|v: &f64| v.is_finite()).ok_or_else(|| bad("a number"))?;
                serde_json::json!(v)
            }
            ParamKind::Integer { .. } => serde_json::json!(t.parse::<i64>().map_err(|_| bad("a whole number"))?),
            ParamKind::Bool => serde_json::json!(t.parse::<bool>().map_err(|_| bad("true or false"))?),
            ParamKind::Choice { .. } => serde_json::json!(t),
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

/// The parameter a refusal is about: the spec whose name `message` names first as a whole word
/// (`radius`, `horizon_s`; not `radius` inside `radius_max`), so the page can show the message at
/// that field. `None` when it names none (the message is about the take, not a field).
pub fn param_named<'a>(specs: &'a [ParamSpec], message: &str) -> Option<&'a str> {
    let word = |c: char| c.is_alphanumeric() || c == '_';
    specs
        .iter()
        .filter_map(|spec| {
            let name = spec.name.as_str();
            message
                .match_indices(name)
                .find(|(at, _)| {
                    let before = message[..*at].chars().next_back();
                    let after = message[at + name.len()..].chars().next();
                    !before.is_some_and(word) && !after.is_some_and(word)
                })
                .map(|(at, _)| (at, name))
        })
        .min_by_key(|(at, _)| *at)
        .map(|(_, name)| name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method;

    fn texts_of(specs: &[ParamSpec]) -> Vec<String> {
        specs.iter().map(|s| field_text(&s.default)).collect()
    }

    #[test]
    fn the_defaults_read_back_as_the_defaults_for_every_method() {
        for m in method::registry() {
            let specs = m.param_specs();
            let params = params_from_form(&m.info().short, &specs, &texts_of(&specs)).unwrap();
            let checked = m.check_json(&params).unwrap();
            assert_eq!(checked.echo(), &m.defaults(), "{}", m.info().name);
        }
    }

    #[test]
    fn a_refusal_is_placed_at_the_parameter_it_names_first_as_a_whole_word() {
        let m = method::find("sssm").unwrap();
        let specs = m.param_specs();
        // what the method and the form really say
        for (params, want) in
            [(serde_json::json!({"radius": -1}), "radius"), (serde_json::json!({"horizon_s": 2}), "horizon_s")]
        {
            let e = m.check_json(&params).unwrap_err().to_string();
            assert_eq!(param_named(&specs, &e), Some(want), "{e}");
        }
        let mut texts = texts_of(&specs);
        let at = specs.iter().position(|s| s.name == "offsets").unwrap();
        texts[at] = "-10,x".into();
        let e = params_from_form("SSSM", &specs, &texts).unwrap_err();
        assert_eq!(param_named(&specs, &e), Some("offsets"), "{e}");
        // whole words only, the first named wins, none when none is named
        let spec = |name: &str| ParamSpec { name: name.into(), ..specs[0].clone() };
        let two = [spec("radius"), spec("radius_max"), spec("k")];
        assert_eq!(param_named(&two, "radius_max 3 is below radius 5"), Some("radius_max"));
        assert_eq!(param_named(&two, "the take is shorter than k frames"), Some("k"));
        assert_eq!(param_named(&two, "kradius and radiusk"), None);
        assert_eq!(param_named(&two, "SSSM needs 2 s of motion"), None);
    }

    #[test]
    fn fields_that_cannot_be_read_are_named() {
        let m = method::find("sssm").unwrap();
        let specs = m.param_specs();
        let mut texts = texts_of(&specs);
        let at = |name: &str| specs.iter().position(|s| s.name == name).unwrap();
        texts[at("offsets")] = " -10, -5 0,5,10 ".into();
        texts[at("radius")] = "15".into();
        let v = params_from_form("SSSM", &specs, &texts).unwrap();
        assert_eq!(v["offsets"], serde_json::json!([-10, -5, 0, 5, 10]));
        assert_eq!(v["radius"], 15.0);
        texts[at("radius")] = "abc".into();
        let e = params_from_form("SSSM", &specs, &texts).unwrap_err();
        assert!(e.starts_with("invalid SSSM parameter radius = \"abc\": expected a number"), "{e}");
        texts[at("radius")] = "19".into();
        texts[at("offsets")] = "-10,x".into();
        assert!(params_from_form("SSSM", &specs, &texts).unwrap_err().contains("offsets"));
        texts[at("offsets")] = "0".into();
        texts[at("stop_window")] = "2.5".into();
        assert!(params_from_form("SSSM", &specs, &texts).unwrap_err().contains("stop_window"));
        // out of range is the method's to refuse, by name
        texts[at("stop_window")] = "5".into();
        texts[at("radius")] = "-1".into();
        let params = params_from_form("SSSM", &specs, &texts).unwrap();
        assert!(m.check_json(&params).unwrap_err().to_string().contains("radius"));
    }
}
