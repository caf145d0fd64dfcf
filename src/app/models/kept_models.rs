//! What the page says and does about a training under way and the models kept in the browser,
//! as pure functions (the page's `app::training` and its loader show and apply them): the
//! question asked when another take is opened during a training, and which model a method uses
//! once the user forgets one of theirs.

/// The question asked when a take is opened while a training runs: the method training (its
/// slot) and what the page says.
#[derive(Debug, Clone, PartialEq)]
pub struct SwitchAsk {
    pub index: usize,
    pub question: SwitchQuestion,
}

/// The question shown when another take is opened while a training runs: `short` (the method's
/// short name) trains the model `model` on the take `training_on`; the user opened `next`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SwitchQuestion {
    /// What is under way and what is asked.
    pub text: String,
    /// The two answers: stop the training, or keep it running (bound to its own take).
    pub stop: String,
    pub keep: String,
}

/// The question for opening `next` while `short` trains `model` on `training_on`.
pub fn switch_question(short: &str, model: &str, training_on: &str, next: &str) -> SwitchQuestion {
    SwitchQuestion {
        text: format!("{short} is training `{model}` on {training_on}. Open {next} and:"),
        stop: "Stop the training".to_string(),
        keep: format!("Keep it running (its model is offered for {training_on} when it ends, never applied to {next})"),
    }
}

/// The model a method uses after the user forgot `forgotten` while `chosen` was in use: the same
/// one when another was chosen; else the first shipped model, else the first other choice left
/// (`None`: nothing is left to choose).
pub fn model_after_forget(chosen: &str, forgotten: &str, shipped: &[String], choices: &[String]) -> Option<String> {
    if chosen != forgotten {
        return Some(chosen.to_string());
    }
    shipped.iter().chain(choices).find(|m| *m != forgotten).cloned()
}

/// What the page confirms once `forgotten` is forgotten: `short` is the method's short name,
/// `now` the model it uses now when it changed (it runs again with it).
pub fn forgotten_message(short: &str, forgotten: &str, now: Option<&str>) -> String {
    let gone = format!("Forgot `{forgotten}`: removed from this browser and from the {short} model choice.");
    match now {
        Some(now) => format!("{gone} It was in use: {short} runs with `{now}` again."),
        None => gone,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn the_switch_question_names_the_training_its_take_and_the_take_opened() {
        let q = switch_question("DT-FCN", "mine", "13_29.bvh", "86_01.bvh");
        assert_eq!(q.text, "DT-FCN is training `mine` on 13_29.bvh. Open 86_01.bvh and:");
        assert_eq!(q.stop, "Stop the training");
        assert!(q.keep.contains("offered for 13_29.bvh when it ends"), "{}", q.keep);
        assert!(q.keep.contains("never applied to 86_01.bvh"), "{}", q.keep);
    }

    #[test]
    fn forgetting_the_model_in_use_goes_back_to_a_shipped_one() {
        let shipped = names(&["exercises", "cmu-actions"]);
        let choices = names(&["exercises", "cmu-actions", "mine", "other"]);
        assert_eq!(model_after_forget("mine", "mine", &shipped, &choices).as_deref(), Some("exercises"));
        // another model in use stays
        assert_eq!(model_after_forget("other", "mine", &shipped, &choices).as_deref(), Some("other"));
        // a method without shipped models takes the first choice left
        assert_eq!(model_after_forget("mine", "mine", &[], &names(&["mine", "other"])).as_deref(), Some("other"));
        assert_eq!(model_after_forget("mine", "mine", &[], &names(&["mine"])), None);
    }

    #[test]
    fn forgetting_says_what_was_forgotten_and_what_runs_now() {
        assert_eq!(
            forgotten_message("DT-FCN", "mine", None),
            "Forgot `mine`: removed from this browser and from the DT-FCN model choice."
        );
        assert!(forgotten_message("DT-FCN", "mine", Some("exercises")).ends_with("DT-FCN runs with `exercises` again."));
    }
}
