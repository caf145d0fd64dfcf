//! The ASF skeleton file (Acclaim Skeleton File): sections `:version`, `:name`, `:units`,
//! `:documentation`, `:root`, `:bonedata`, `:hierarchy`; other sections are skipped with a warning.

use super::{lines, number, tokens};
use crate::bvh::{BvhError, ParseLimits, Warning};

/// One degree of freedom of a bone, or of the root's AMC values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dof {
    Rx,
    Ry,
    Rz,
    Tx,
    Ty,
    Tz,
}

impl Dof {
    fn parse(text: &str) -> Option<Dof> {
        Some(match text.to_ascii_lowercase().as_str() {
            "rx" => Dof::Rx,
            "ry" => Dof::Ry,
            "rz" => Dof::Rz,
            "tx" => Dof::Tx,
            "ty" => Dof::Ty,
            "tz" => Dof::Tz,
            _ => return None,
        })
    }

    /// 0, 1, 2 for X, Y, Z.
    pub fn axis(self) -> usize {
        match self {
            Dof::Rx | Dof::Tx => 0,
            Dof::Ry | Dof::Ty => 1,
            Dof::Rz | Dof::Tz => 2,
        }
    }

    pub fn is_rotation(self) -> bool {
        matches!(self, Dof::Rx | Dof::Ry | Dof::Rz)
    }
}

/// Euler angles (in the file's angle unit) applied about X, Y, Z axes in `order` (the first
/// letter's rotation applied first).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    pub angles: [f64; 3],
    /// Axis indices in the order the rotations apply, e.g. `[0, 1, 2]` for `XYZ`.
    pub order: [usize; 3],
}

/// One bone of `:bonedata`.
#[derive(Debug, Clone, PartialEq)]
pub struct Bone {
    pub name: String,
    /// Unit direction in the global rest frame.
    pub direction: [f64; 3],
    pub length: f64,
    pub axis: Axis,
    /// The AMC values of this bone, in order (rotations only; empty for a bone that does not move).
    pub dofs: Vec<Dof>,
    /// Line of its `begin`.
    pub line: usize,
}

impl Bone {
    /// The bone's vector, direction × length, in ASF length units.
    pub fn vector(&self) -> [f64; 3] {
        self.direction.map(|d| d * self.length)
    }
}

/// The root: the order of its AMC values, its rest orientation, position.
#[derive(Debug, Clone, PartialEq)]
pub struct Root {
    pub order: Vec<Dof>,
    pub axis: Axis,
    pub position: [f64; 3],
}

/// A parsed ASF file.
#[derive(Debug, Clone, PartialEq)]
pub struct Asf {
    pub name: String,
    /// `:units length` (the CMU files' 0.45: inches per unit × 0.45); lengths are kept as written.
    pub length_unit: f64,
    /// Whether angles (`axis`, `orientation`, and the AMC values unless it says otherwise) are degrees.
    pub degrees: bool,
    pub root: Root,
    pub bones: Vec<Bone>,
    /// Parent of each bone (`None`: the root), from `:hierarchy`.
    pub parents: Vec<Option<usize>>,
    /// The root's children, then each bone's, in `:hierarchy` order.
    pub root_children: Vec<usize>,
    pub children: Vec<Vec<usize>>,
    pub warnings: Vec<Warning>,
}

impl Asf {
    /// Index of the bone called `name` (exact, then ignoring case).
    pub fn bone(&self, name: &str) -> Option<usize> {
        self.bones
            .iter()
            .position(|b| b.name == name)
            .or_else(|| self.bones.iter().position(|b| b.name.eq_ignore_ascii_case(name)))
    }
}

fn err(line: usize, column: usize, message: impl Into<String>) -> BvhError {
    BvhError::new(line, column, message)
}

/// Exactly `N` numbers after the keyword at `toks[0]`.
fn numbers<const N: usize>(line: usize, toks: &[(usize, &str)], what: &str) -> Result<[f64; N], BvhError> {
    let mut out = [0.0; N];
    for (i, v) in out.iter_mut().enumerate() {
        let Some(&(col, text)) = toks.get(i + 1) else {
            let col = toks.last().map_or(1, |(c, t)| c + t.chars().count());
            return Err(err(line, col, format!("expected {N} numbers after `{what}`, found {i}")));
        };
        *v = number(text).ok_or_else(|| err(line, col, format!("expected a number after `{what}`, found `{text}`")))?;
    }
    if let Some(&(col, text)) = toks.get(N + 1) {
        return Err(err(line, col, format!("expected {N} numbers after `{what}`, found more: `{text}`")));
    }
    Ok(out)
}

fn axis_order(line: usize, col: usize, text: &str) -> Result<[usize; 3], BvhError> {
    let letters: Vec<usize> = text
        .chars()
        .map(|c| match c.to_ascii_uppercase() {
            'X' => Some(0),
            'Y' => Some(1),
            'Z' => Some(2),
            _ => None,
        })
        .collect::<Option<Vec<_>>>()
        .unwrap_or_default();
    match letters.as_slice() {
        &[a, b, c] if a != b && b != c && a != c => Ok([a, b, c]),
        _ => {
            Err(err(line, col, format!("expected an axis order such as `XYZ` (each of X, Y, Z once), found `{text}`")))
        }
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Section {
    None,
    Units,
    Documentation,
    Root,
    BoneData,
    Hierarchy,
    Other,
}

/// One `:hierarchy` line: a parent and its children, each child with its column.
struct Link {
    line: usize,
    column: usize,
    parent: String,
    children: Vec<(usize, String)>,
}

/// A bone being read between `begin` and `end`.
#[derive(Default)]
struct Draft {
    line: usize,
    name: Option<String>,
    direction: Option<[f64; 3]>,
    length: Option<f64>,
    axis: Option<Axis>,
    dofs: Vec<Dof>,
}

/// Parses ASF text. `limits` bounds the bones (`max_joints`) and the hierarchy's depth.
pub fn parse_asf(text: &str, limits: &ParseLimits) -> Result<Asf, BvhError> {
    let mut asf = Asf {
        name: String::new(),
        length_unit: 1.0,
        degrees: true,
        root: Root { order: Vec::new(), axis: Axis { angles: [0.0; 3], order: [0, 1, 2] }, position: [0.0; 3] },
        bones: Vec::new(),
        parents: Vec::new(),
        root_children: Vec::new(),
        children: Vec::new(),
        warnings: Vec::new(),
    };
    let mut section = Section::None;
    let mut draft: Option<Draft> = None;
    let mut in_hierarchy_block = false;
    let mut seen_root = false;
    let mut seen_hierarchy = false;
    let mut last_line = 1;
    // parent name → children names with the line and column of each
    let mut links: Vec<Link> = Vec::new();
    for (n, line) in lines(text) {
        last_line = n;
        let toks = tokens(line);
        let Some(&(col, first)) = toks.first() else { continue };
        if let Some(keyword) = first.strip_prefix(':') {
            if let Some(d) = &draft {
                return Err(err(
                    n,
                    col,
                    format!("expected `end` closing the bone that begins on line {}, found `{first}`", d.line),
                ));
            }
            section = section_named(&mut asf, keyword, first, &toks, n, (&mut seen_root, &mut seen_hierarchy));
            continue;
        }
        let key = first.to_ascii_lowercase();
        match section {
            Section::Documentation | Section::Other => {}
            Section::None => {
                return Err(err(n, col, format!("expected a section such as `:root` or `:bonedata`, found `{first}`")))
            }
            Section::Units => units_line(&mut asf, n, col, &key, &toks)?,
            Section::Root => root_line(&mut asf, n, col, first, &key, &toks)?,
            Section::BoneData => {
                if key == "begin" {
                    if let Some(d) = &draft {
                        return Err(err(
                            n,
                            col,
                            format!("expected `end` closing the bone that begins on line {}, found `begin`", d.line),
                        ));
                    }
                    draft = Some(Draft { line: n, ..Draft::default() });
                    continue;
                }
                let Some(d) = draft.as_mut() else {
                    return Err(err(n, col, format!("expected `begin` (a bone) in `:bonedata`, found `{first}`")));
                };
                match key.as_str() {
                    "end" => close_bone(&mut asf, draft.take().expect("a bone is open"), n, col, limits)?,
                    "id" | "bodymass" | "cofmass" => {}
                    "name" => d.name = Some(bone_name(n, col, &toks)?),
                    "direction" => d.direction = Some(numbers::<3>(n, &toks, "direction")?),
                    "length" => {
                        let v = numbers::<1>(n, &toks, "length")?[0];
                        if v < 0.0 {
                            return Err(err(n, toks[1].0, format!("a bone's length must not be negative, found {v}")));
                        }
                        d.length = Some(v);
                    }
                    "axis" => {
                        let angles = numbers::<3>(n, &toks[..toks.len().min(4)], "axis")?;
                        let &(c, t) = toks.get(4).ok_or_else(|| {
                            err(n, col, "expected an axis order such as `XYZ` after the 3 `axis` angles")
                        })?;
                        d.axis = Some(Axis { angles, order: axis_order(n, c, t)? });
                    }
                    "dof" => dof_line(d, n, &toks)?,
                    // limits span several lines: `limits (lo hi)` then `(lo hi)` per further dof
                    k if k == "limits" || k.starts_with('(') => {}
                    _ => asf
                        .warnings
                        .push(Warning { line: n, message: format!("bone keyword `{first}` is not used; skipped") }),
                }
            }
            Section::Hierarchy => match key.as_str() {
                "begin" => in_hierarchy_block = true,
                "end" => in_hierarchy_block = false,
                _ if !in_hierarchy_block => {
                    return Err(err(n, col, format!("expected `begin` in `:hierarchy`, found `{first}`")))
                }
                _ => links.push(Link {
                    line: n,
                    column: col,
                    parent: first.to_string(),
                    children: toks[1..].iter().map(|&(c, t)| (c, t.to_string())).collect(),
                }),
            },
        }
    }
    complete(&asf, draft.as_ref(), seen_root, seen_hierarchy, last_line)?;
    link(&mut asf, &links, last_line, limits)?;
    Ok(asf)
}

/// The section a `:keyword` line opens (`seen` marks `:root` and `:hierarchy`); `:name` names the skeleton, an
/// unknown section is skipped with a warning.
fn section_named(
    asf: &mut Asf,
    keyword: &str,
    first: &str,
    toks: &[(usize, &str)],
    n: usize,
    seen: (&mut bool, &mut bool),
) -> Section {
    match keyword.to_ascii_lowercase().as_str() {
        "version" => Section::None,
        "name" => {
            asf.name = toks[1..].iter().map(|t| t.1).collect::<Vec<_>>().join(" ");
            Section::None
        }
        "units" => Section::Units,
        "documentation" => Section::Documentation,
        "root" => {
            *seen.0 = true;
            Section::Root
        }
        "bonedata" => Section::BoneData,
        "hierarchy" => {
            *seen.1 = true;
            Section::Hierarchy
        }
        _ => {
            asf.warnings.push(Warning { line: n, message: format!("section `{first}` is not used; skipped") });
            Section::Other
        }
    }
}

/// At the end of the file: no bone left open, the sections a skeleton needs all there.
fn complete(
    asf: &Asf,
    open: Option<&Draft>,
    seen_root: bool,
    seen_hierarchy: bool,
    last_line: usize,
) -> Result<(), BvhError> {
    if let Some(d) = open {
        return Err(err(
            last_line,
            1,
            format!("expected `end` closing the bone that begins on line {}, found end of file", d.line),
        ));
    }
    if !seen_root {
        return Err(err(last_line, 1, "the file has no `:root` section (is it an ASF skeleton?)"));
    }
    if !seen_hierarchy {
        return Err(err(last_line, 1, "the file has no `:hierarchy` section"));
    }
    if asf.root.order.is_empty() {
        return Err(err(last_line, 1, "`:root` has no `order` (which values the AMC gives for the root)"));
    }
    Ok(())
}

/// A line of `:units`.
fn units_line(asf: &mut Asf, n: usize, col: usize, key: &str, toks: &[(usize, &str)]) -> Result<(), BvhError> {
    match key {
        "length" => asf.length_unit = numbers::<1>(n, toks, "length")?[0],
        "angle" => {
            asf.degrees = match toks.get(1).map(|t| t.1.to_ascii_lowercase()) {
                Some(u) if u.starts_with("deg") => true,
                Some(u) if u.starts_with("rad") => false,
                _ => {
                    let c = toks.get(1).map_or(col + 5, |t| t.0);
                    return Err(err(n, c, "expected `deg` or `rad` after `angle`"));
                }
            }
        }
        _ => {}
    }
    Ok(())
}

/// A line of `:root`.
fn root_line(
    asf: &mut Asf,
    n: usize,
    col: usize,
    first: &str,
    key: &str,
    toks: &[(usize, &str)],
) -> Result<(), BvhError> {
    match key {
        "order" => {
            asf.root.order = toks[1..]
                .iter()
                .map(|&(c, t)| {
                    Dof::parse(t).ok_or_else(|| {
                        err(n, c, format!("expected TX, TY, TZ, RX, RY or RZ in the root's `order`, found `{t}`"))
                    })
                })
                .collect::<Result<_, _>>()?;
        }
        "axis" => {
            let &(c, t) =
                toks.get(1).ok_or_else(|| err(n, col + 4, "expected an axis order such as `XYZ` after `axis`"))?;
            asf.root.axis.order = axis_order(n, c, t)?;
        }
        "position" => asf.root.position = numbers::<3>(n, toks, "position")?,
        "orientation" => asf.root.axis.angles = numbers::<3>(n, toks, "orientation")?,
        _ => {
            return Err(err(
                n,
                col,
                format!("expected `order`, `axis`, `position` or `orientation` in `:root`, found `{first}`"),
            ))
        }
    }
    Ok(())
}

/// `end` of the bone `d` in `:bonedata`: the bone, complete, joins the skeleton.
fn close_bone(asf: &mut Asf, d: Draft, n: usize, col: usize, limits: &ParseLimits) -> Result<(), BvhError> {
    let name = d.name.ok_or_else(|| err(n, col, format!("the bone that begins on line {} has no `name`", d.line)))?;
    let direction = d.direction.ok_or_else(|| err(n, col, format!("bone `{name}` has no `direction`")))?;
    let length = d.length.ok_or_else(|| err(n, col, format!("bone `{name}` has no `length`")))?;
    if asf.bones.iter().any(|b| b.name == name) {
        return Err(err(d.line, 1, format!("bone `{name}` is defined twice")));
    }
    if asf.bones.len() + 1 >= limits.max_joints {
        return Err(err(d.line, 1, format!("too many bones: the limit is {}", limits.max_joints)));
    }
    let axis = d.axis.unwrap_or(Axis { angles: [0.0; 3], order: [0, 1, 2] });
    asf.bones.push(Bone { name, direction, length, axis, dofs: d.dofs, line: d.line });
    Ok(())
}

/// A bone's `name` line: the name, or why it cannot be one.
fn bone_name(n: usize, col: usize, toks: &[(usize, &str)]) -> Result<String, BvhError> {
    let &(c, t) = toks.get(1).ok_or_else(|| err(n, col + 4, "expected the bone's name after `name`"))?;
    if t.eq_ignore_ascii_case("root") {
        return Err(err(n, c, "a bone cannot be called `root` (the root is not a bone)"));
    }
    if let Some(at) = t.find(['{', '}']) {
        let col = c + t[..at].chars().count();
        return Err(err(
            n,
            col,
            format!(
                "a bone's name cannot contain `{{` or `}}` (it would not survive as a BVH joint name), found `{t}`"
            ),
        ));
    }
    Ok(t.to_string())
}

/// A bone's `dof` line: its rotation channels, in order.
fn dof_line(d: &mut Draft, n: usize, toks: &[(usize, &str)]) -> Result<(), BvhError> {
    for &(c, t) in &toks[1..] {
        match Dof::parse(t) {
            Some(dof) if !dof.is_rotation() => {
                return Err(err(n, c, format!("bone translations (`{t}`) are not supported; only rx, ry, rz")))
            }
            Some(dof) if d.dofs.contains(&dof) => return Err(err(n, c, format!("`{t}` is listed twice"))),
            Some(dof) => d.dofs.push(dof),
            None if t.eq_ignore_ascii_case("l") => {
                return Err(err(n, c, "bone length changes (`l`) are not supported; only rx, ry, rz"))
            }
            None => return Err(err(n, c, format!("expected rx, ry or rz after `dof`, found `{t}`"))),
        }
    }
    Ok(())
}

/// Fills parents and children from the `:hierarchy` lines; every bone once, reachable from the root.
fn link(asf: &mut Asf, links: &[Link], last_line: usize, limits: &ParseLimits) -> Result<(), BvhError> {
    let count = asf.bones.len();
    asf.parents = vec![None; count];
    asf.children = vec![Vec::new(); count];
    let mut placed = vec![false; count];
    for Link { line: n, column: col, parent, children: kids } in links {
        let parent_index = if parent.eq_ignore_ascii_case("root") {
            None
        } else {
            Some(asf.bone(parent).ok_or_else(|| err(*n, *col, format!("no bone `{parent}` in `:bonedata`")))?)
        };
        for (c, kid) in kids {
            let k = asf.bone(kid).ok_or_else(|| err(*n, *c, format!("no bone `{kid}` in `:bonedata`")))?;
            if placed[k] {
                return Err(err(*n, *c, format!("bone `{kid}` has two parents in `:hierarchy`")));
            }
            if Some(k) == parent_index {
                return Err(err(*n, *c, format!("bone `{kid}` cannot be its own parent")));
            }
            placed[k] = true;
            asf.parents[k] = parent_index;
            match parent_index {
                None => asf.root_children.push(k),
                Some(p) => asf.children[p].push(k),
            }
        }
    }
    if let Some(k) = (0..count).find(|&k| !placed[k]) {
        let b = &asf.bones[k];
        return Err(err(b.line, 1, format!("bone `{}` is not in `:hierarchy`", b.name)));
    }
    // reachable from the root without cycles, within the depth limit
    let mut depth = vec![0usize; count];
    let mut stack: Vec<usize> = asf.root_children.clone();
    for &k in &stack {
        depth[k] = 2;
    }
    let mut seen = 0;
    while let Some(k) = stack.pop() {
        seen += 1;
        if depth[k] > limits.max_depth {
            return Err(err(
                asf.bones[k].line,
                1,
                format!("the hierarchy nests too deep: the limit is {} levels", limits.max_depth),
            ));
        }
        for &c in &asf.children[k] {
            depth[c] = depth[k] + 1;
            stack.push(c);
        }
    }
    if seen < count {
        let k = (0..count).find(|&k| depth[k] == 0).expect("an unreached bone");
        return Err(err(
            last_line,
            1,
            format!("bone `{}` is not connected to the root in `:hierarchy` (a cycle?)", asf.bones[k].name),
        ));
    }
    Ok(())
}
