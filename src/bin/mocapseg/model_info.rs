//! `mocapseg model-info`: a model file or a shipped model, described by the supervised method that reads it —
//! from what each method declares, never from its name.

use std::path::Path;

/// `mocapseg model-info FILE|NAME [--method M]`: a model file read by the supervised method
/// whose reader takes it (or `method`'s), or a shipped model by name — `exercises` (every method
/// shipping one of that name, or `method`'s), `dtfcn-exercises`, `dtfcn-exercises.model` — from
/// what each supervised method declares.
pub fn model_info(file: &Path, method: Option<&str>) -> Result<(), String> {
    use mocapseg::method::DynMethod;
    use mocapseg::methods::registry;
    let methods: Vec<&dyn DynMethod> = registry()
        .iter()
        .copied()
        .filter(|m| m.supervised().is_some() && method.is_none_or(|name| m.info().name == name))
        .collect();
    if methods.is_empty() {
        let known: Vec<String> =
            registry().iter().filter(|m| m.supervised().is_some()).map(|m| m.info().name).collect();
        return Err(format!(
            "--method {}: not a method with models; those are {}",
            method.unwrap_or(""),
            known.join(", ")
        ));
    }
    let mut details = Vec::new();
    if file.exists() {
        let bytes = std::fs::read(file).map_err(|e| format!("{}: {e}", file.display()))?;
        let shown = file.display().to_string();
        let mut refusals = Vec::new();
        let extension = file.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        for m in &methods {
            let (Some(s), Some(decl)) = (m.supervised(), m.supervision()) else { continue };
            match s.read_model(&shown, &bytes) {
                Ok(loaded) => {
                    details.push(s.model_details(&loaded));
                    break;
                }
                // the refusal of a method whose files have this extension says the most
                Err(e) if extension.as_deref() == Some(decl.model_extension.as_str()) => {
                    refusals.insert(0, e.to_string())
                }
                Err(e) => refusals.push(e.to_string()),
            }
        }
        if details.is_empty() {
            return Err(refusals.first().cloned().unwrap_or_else(|| format!("{shown}: not a model file")));
        }
    } else {
        let name = file.to_string_lossy();
        let mut shipped = Vec::new();
        let store = mocapseg::method::ModelStore::new();
        for m in &methods {
            let (Some(s), Some(decl)) = (m.supervised(), m.supervision()) else { continue };
            let method = m.info().name;
            let stem = name.strip_suffix(&format!(".{}", decl.model_extension)).unwrap_or(&name);
            let own = stem.strip_prefix(&format!("{method}-")).filter(|n| decl.shipped.iter().any(|s| s == n));
            let bare = decl.shipped.iter().any(|s| s == stem).then_some(stem);
            if let Some(n) = own.or(bare) {
                details.push(s.model_details(&s.shipped_model(n, &store).map_err(|e| e.to_string())?));
            }
            shipped.extend(decl.shipped.iter().map(|s| format!("{method}-{s}")));
        }
        if details.is_empty() {
            return Err(format!(
                "{name}: no such file, nor a shipped model (shipped: {}; a bare name, e.g. `exercises`, names every method's)",
                shipped.join(", ")
            ));
        }
    }
    let out = match &details[..] {
        [one] => serde_json::to_string_pretty(one),
        many => serde_json::to_string_pretty(many),
    };
    println!("{}", out.map_err(|e| e.to_string())?);
    Ok(())
}
