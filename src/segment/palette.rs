//! Colours of segments, shared by the methods' pictures and the page's timeline rows so that a
//! segment has the same colour everywhere.

/// Colours of actions, by the action's cluster (kind of action).
const ACTION_COLOURS: [[u8; 3]; 6] =
    [[0, 160, 70], [150, 60, 200], [0, 150, 170], [200, 40, 140], [120, 150, 0], [90, 90, 220]];

/// The colour of the actions of cluster `cluster`.
pub fn action_colour(cluster: usize) -> [u8; 3] {
    ACTION_COLOURS[cluster % ACTION_COLOURS.len()]
}

/// The CSS colour of primitive cluster `cluster`: a hue per cluster, shared by a mirror pair
/// (taken from the pair's lower id), the pair's higher id lighter.
pub fn cluster_colour(cluster: usize, mirror_of: Option<usize>) -> String {
    let base = mirror_of.map_or(cluster, |m| m.min(cluster));
    let hue = (base as f64 * 137.508) % 360.0;
    let lightness = if mirror_of.is_some_and(|m| m < cluster) { 72 } else { 48 };
    format!("hsl({hue:.0}, 62%, {lightness}%)")
}

/// The CSS colour (`#rrggbb`) of class `i` of a labelling model (DT-FCN, k-NN): hues spread by
/// the golden angle, alternating lightness; a class index has the same colour in every row,
/// take and model file.
pub fn class_colour(i: usize) -> String {
    let h = (i as f64 * 137.508 + 20.0) % 360.0;
    let (s, l) = (0.65, if i % 2 == 0 { 0.45 } else { 0.55 });
    let c = (1.0 - (2.0 * l - 1.0f64).abs()) * s;
    let x = c * (1.0 - ((h / 60.0) % 2.0 - 1.0).abs());
    let m = l - c / 2.0;
    let (r, g, b) = match (h / 60.0) as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let byte = |v: f64| ((v + m) * 255.0).round().clamp(0.0, 255.0) as u8;
    format!("#{:02x}{:02x}{:02x}", byte(r), byte(g), byte(b))
}

/// The colours labels are drawn in (issue 48, "one colour per label"): a categorical palette that stays distinct
/// under the common colour-vision deficiencies — the seven colours of Okabe & Ito (2008) and five of Paul Tol's
/// "muted" scheme that differ from them in lightness — none of them grey (grey and hatching mean "no label").
pub const LABEL_PALETTE: [[u8; 3]; 12] = [
    [0xe6, 0x9f, 0x00], // orange
    [0x56, 0xb4, 0xe9], // sky blue
    [0x00, 0x9e, 0x73], // bluish green
    [0xf0, 0xe4, 0x42], // yellow
    [0x00, 0x72, 0xb2], // blue
    [0xd5, 0x5e, 0x00], // vermillion
    [0xcc, 0x79, 0xa7], // reddish purple
    [0x33, 0x22, 0x88], // indigo
    [0x88, 0x22, 0x55], // wine
    [0x99, 0x99, 0x33], // olive
    [0x11, 0x77, 0x33], // green
    [0xaa, 0x44, 0x99], // purple
];

/// The palette entry a label asks for, from its name alone (FNV-1a of its text, trimmed): the same name asks for
/// the same colour on every row, take and page.
pub fn label_slot(label: &str) -> usize {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in label.trim().as_bytes() {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    (h % LABEL_PALETTE.len() as u64) as usize
}

/// The colour each label is drawn in, kept as labels are met: a label takes the colour its name asks for
/// ([`label_slot`]) unless a label met before has it, then the next colour no label has (so that up to
/// [`LABEL_PALETTE`]'s twelve labels met together are all distinct); once given, a label's colour never changes
/// (the page keeps the assignment in the browser, so it holds across takes and visits).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LabelColours {
    slots: std::collections::BTreeMap<String, usize>,
}

impl LabelColours {
    /// The palette entry of `label`, given now if it has none.
    pub fn slot(&mut self, label: &str) -> usize {
        let label = label.trim();
        if let Some(&slot) = self.slots.get(label) {
            return slot;
        }
        let n = LABEL_PALETTE.len();
        let asked = label_slot(label);
        let used: std::collections::BTreeSet<usize> = self.slots.values().copied().collect();
        let slot = (0..n).map(|k| (asked + k) % n).find(|s| !used.contains(s)).unwrap_or(asked);
        self.slots.insert(label.to_string(), slot);
        slot
    }

    /// The CSS colour (`#rrggbb`) of `label`, given now if it has none.
    pub fn css(&mut self, label: &str) -> String {
        let [r, g, b] = LABEL_PALETTE[self.slot(label)];
        format!("#{r:02x}{g:02x}{b:02x}")
    }

    /// How many labels have a colour.
    pub fn len(&self) -> usize {
        self.slots.len()
    }

    /// Whether no label has a colour yet.
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// The assignment as kept (JSON).
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }

    /// An assignment kept; an empty one when it does not read (entries out of the palette dropped).
    pub fn from_json(text: &str) -> LabelColours {
        let mut kept: LabelColours = serde_json::from_str(text).unwrap_or_default();
        kept.slots.retain(|_, s| *s < LABEL_PALETTE.len());
        kept
    }
}

/// The colour of an Effort factor's value `v` (−1 fully indulging … +1 fully condensing): blue
/// through grey to red, as LMA's "Effort of each segment" picture and the page's Effort bars under
/// every row draw it (a value out of range is clamped; not a number is neutral).
pub fn effort_colour(v: f64) -> [u8; 3] {
    let v = if v.is_nan() { 0.0 } else { v };
    let t = ((v + 1.0) / 2.0).clamp(0.0, 1.0);
    [(40.0 + 180.0 * t) as u8, (90.0 + 60.0 * (1.0 - (2.0 * t - 1.0).abs())) as u8, (220.0 - 180.0 * t) as u8]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn effort_runs_from_blue_through_grey_to_red() {
        assert_eq!(effort_colour(-1.0), [40, 90, 220], "indulging: blue");
        assert_eq!(effort_colour(0.0), [130, 150, 130], "neutral: grey-green middle");
        assert_eq!(effort_colour(1.0), [220, 90, 40], "condensing: red");
        assert_eq!(effort_colour(-7.0), effort_colour(-1.0), "clamped");
        assert_eq!(effort_colour(f64::NAN), effort_colour(0.0));
        // redder (and less blue) as the value grows
        let (a, b) = (effort_colour(-0.2), effort_colour(0.4));
        assert!(b[0] > a[0] && b[2] < a[2], "{a:?} {b:?}");
    }

    #[test]
    fn a_label_keeps_its_colour_and_labels_met_together_are_distinct() {
        let mut colours = LabelColours::default();
        let labels = [
            "walk",
            "look_around",
            "stand_and_clap",
            "KneeRaise",
            "UpDown",
            "ToeTouchTwoHands",
            "JumpJack",
            "Twist",
            "Squat",
            "ArmCircle",
            "Jog",
            "wave",
        ];
        let slots: Vec<usize> = labels.iter().map(|l| colours.slot(l)).collect();
        let distinct: std::collections::BTreeSet<usize> = slots.iter().copied().collect();
        assert_eq!(distinct.len(), labels.len(), "twelve labels, twelve colours: {slots:?}");
        assert_eq!(colours.slot(" Twist "), slots[7], "the same label (spaces aside) keeps its colour");
        assert_eq!(colours.css("walk"), colours.css("walk"));
        // kept and read back: the same colours on the next take and visit
        let mut back = LabelColours::from_json(&colours.to_json());
        assert_eq!(labels.iter().map(|l| back.slot(l)).collect::<Vec<_>>(), slots);
        assert!(LabelColours::from_json("not json").is_empty());
        assert!(LabelColours::from_json(r#"{"slots":{"a":99}}"#).is_empty(), "an entry out of the palette is dropped");
        // the first label takes the colour its name asks for
        assert_eq!(LabelColours::default().slot("Twist"), label_slot("Twist"));
    }

    #[test]
    fn the_label_palette_is_not_grey_and_every_colour_differs() {
        for (i, a) in LABEL_PALETTE.iter().enumerate() {
            let spread = a.iter().max().unwrap() - a.iter().min().unwrap();
            assert!(spread >= 60, "{a:?} is too grey: grey means no label");
            for b in &LABEL_PALETTE[i + 1..] {
                let d: i32 = a.iter().zip(b).map(|(x, y)| (*x as i32 - *y as i32).abs()).sum();
                assert!(d >= 80, "{a:?} and {b:?} are too alike");
            }
        }
    }

    #[test]
    fn mirror_pairs_share_a_hue() {
        let (a, b, c) = (cluster_colour(0, Some(2)), cluster_colour(1, None), cluster_colour(2, Some(0)));
        let hue = |s: &str| s.split(',').next().unwrap().to_string();
        assert_eq!(hue(&a), hue(&c));
        assert_ne!(a, c);
        assert_ne!(hue(&a), hue(&b));
        assert_eq!(action_colour(0), action_colour(6));
    }
}
