//! One banner when no method can segment the take: each method's refusal would otherwise replace
//! the one before in the banner, leaving only the last (DT-FCN's) in view (issue 27). The methods
//! mostly fail for one shared reason (a skeleton none of them can map), said once; different
//! reasons are each said once with the methods that gave them.

/// The banner's text when every method that ran failed: `failures` are (method's short name, its
/// message), in the page's order.
pub fn no_method_can_read(failures: &[(&str, &str)]) -> String {
    let names = |of: &[&str]| of.join(", ");
    let all: Vec<&str> = failures.iter().map(|f| f.0).collect();
    if let Some(reason) = shared_reason(failures.iter().map(|f| f.1)) {
        return format!("No method can read this skeleton ({}): {reason}", names(&all));
    }
    // the distinct reasons, in order, each with the methods that gave it
    let mut reasons: Vec<(&str, Vec<&str>)> = Vec::new();
    for &(method, message) in failures {
        match reasons.iter_mut().find(|r| r.0 == message) {
            Some(r) => r.1.push(method),
            None => reasons.push((message, vec![method])),
        }
    }
    let each: Vec<String> = reasons.iter().map(|(m, who)| format!("{}: {m}", names(who))).collect();
    format!("No method can read this skeleton. {}", each.join(" · "))
}

/// The reason every message ends with, after a method's own words and `": "` (`"the SSSM
/// features need hands…: cannot map the skeleton…"` and `"cannot map the skeleton…"` share the
/// latter); `None` when they share none.
fn shared_reason<'a>(messages: impl Iterator<Item = &'a str> + Clone) -> Option<&'a str> {
    let shortest = messages.clone().min_by_key(|m| m.len())?;
    // the shortest message, or its tails after each ": ", longest first
    let candidates = std::iter::once(shortest).chain(shortest.match_indices(": ").map(|(i, _)| &shortest[i + 2..]));
    candidates
        .filter(|c| !c.trim().is_empty())
        .find(|c| messages.clone().all(|m| m == *c || m.strip_suffix(*c).is_some_and(|head| head.ends_with(": "))))
}

#[cfg(test)]
mod tests {
    use super::*;

    const MAP: &str = "cannot map the skeleton to the 17 canonical joints: 1 found (Hips as Base), 16 missing";

    #[test]
    fn a_shared_reason_is_said_once_with_every_method() {
        let sssm = format!("the SSSM features need hands, feet, head and hips: {MAP}");
        let failures = [("SSSM", sssm.as_str()), ("Velocity", MAP), ("k-NN", MAP), ("DT-FCN", MAP)];
        let text = no_method_can_read(&failures);
        assert_eq!(text, format!("No method can read this skeleton (SSSM, Velocity, k-NN, DT-FCN): {MAP}"));
        assert_eq!(text.matches("cannot map").count(), 1, "{text}");
    }

    #[test]
    fn different_reasons_are_each_said_with_their_methods() {
        let failures = [("SSSM", "too few frames"), ("Velocity", MAP), ("KCS", MAP), ("DT-FCN", "no model")];
        let text = no_method_can_read(&failures);
        assert_eq!(
            text,
            format!("No method can read this skeleton. SSSM: too few frames · Velocity, KCS: {MAP} · DT-FCN: no model")
        );
        // a tail shared by chance (here "…: x") is not a shared reason unless every message has it
        assert_eq!(shared_reason(["a: x", "b: y"].into_iter()), None);
        assert_eq!(shared_reason(["a: x", "x"].into_iter()), Some("x"));
        assert_eq!(shared_reason(["ax", "x"].into_iter()), None);
    }
}
