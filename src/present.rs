//! Sentences for people, made from the solver's data. The solver returns
//! enums and structs carrying joints, steps and numbers; this module is the
//! one place that says them in words, for the report, the commands and the
//! terminal UI alike. Steps and components are numbered from 1 here as
//! everywhere a person or a script sees them ([`StepNo`], [`ComponentNo`]).

use std::fmt::Write as _;

pub use caymos_core::numbering::{ComponentNo, ItemNo, StepNo};

use crate::analysis::{NoRealization, Warning};
use crate::cayley_space::{Note, Unresolved};
use crate::complexity::LccFailure;
use crate::decompose::{Outside, Step};
use crate::distance::{Certificate, Outcome};
use crate::linkage::{Constraint, Linkage};
use crate::motion::Missing;
use crate::numfmt::{fmt_num, fmt_sig, fmt_span};
use crate::realize::Event;
use crate::realize::{RealizationType, Unrealizable};

/// λ in sentences: the shortest digits that read back as the same f64
/// (so two floats print apart, and 0.2 prints as 0.2), positional between
/// 1e-4 and 1e9 as the tables are, else scientific (1e-20, 1e300).
pub fn sig(x: f64) -> String {
    shortest(x, 1e9)
}

/// A distance to full precision: the shortest form that reads back exactly,
/// in scientific notation when tiny or huge.
pub fn full(x: f64) -> String {
    shortest(x, 1e15)
}

/// The shortest digits that read back as `x`: positional from 1e-4 up to
/// `below` (and for 0), else scientific.
fn shortest(x: f64, below: f64) -> String {
    if x == 0.0 || (1e-4..below).contains(&x.abs()) { format!("{x}") } else { format!("{x:e}") }
}

/// A type for a text table: up to [`TYPE_PLAIN`] signs as they are, up to
/// [`TYPE_GROUPED`] in groups of five (`-----·-+---·--`), so a differing sign
/// can be found by its position; longer ones keep their ends (see
/// [`type_label`] to show them against a reference instead).
pub fn short_type(ty: &str) -> String {
    let n = ty.chars().count();
    if n <= TYPE_PLAIN {
        return ty.to_string();
    }
    if n <= TYPE_GROUPED {
        let signs: Vec<char> = ty.chars().collect();
        return signs.chunks(5).map(|c| c.iter().collect::<String>()).collect::<Vec<_>>().join("·");
    }
    let head: String = ty.chars().take(16).collect();
    let tail: String = ty.chars().skip(n - 8).collect();
    format!("{head}…{tail} ({n} signs)")
}

/// Types up to this many signs are printed as they are.
pub const TYPE_PLAIN: usize = 10;
/// Types up to this many signs are printed in groups of five; longer ones
/// against a reference type ([`type_label`]).
pub const TYPE_GROUPED: usize = 40;
/// At most this many differing signs are listed by [`type_label`].
const TYPE_DIFFS_SHOWN: usize = 6;

/// A type for people, given the drawn type as `reference`: short types as
/// [`short_type`]; long ones as the steps (numbered from 1) whose sign
/// differs from the reference, with their sign: `drawn` when none does,
/// `drawn, 17+ 165-` otherwise (at most six listed, then `… (+N)`).
pub fn type_label(ty: &str, reference: Option<&str>) -> String {
    let n = ty.chars().count();
    match reference.filter(|r| n > TYPE_GROUPED && r.chars().count() == n) {
        Some(reference) => type_against(ty, reference),
        None => short_type(ty),
    }
}

/// A type as the steps (from 1) whose sign differs from `reference`, with
/// their sign: `drawn` when none does, `drawn, 17+ 165-` otherwise (at most
/// six listed, then `… (+N)`), whatever its length; `reference` must have as many signs.
pub fn type_against(ty: &str, reference: &str) -> String {
    let diffs: Vec<String> = ty
        .chars()
        .zip(reference.chars())
        .enumerate()
        .filter(|(_, (a, b))| a != b)
        .map(|(k, (a, _))| format!("{}{a}", k + 1))
        .collect();
    if diffs.is_empty() {
        return "drawn".to_string();
    }
    let shown = diffs[..diffs.len().min(TYPE_DIFFS_SHOWN)].join(" ");
    match diffs.len().checked_sub(TYPE_DIFFS_SHOWN).filter(|&m| m > 0) {
        Some(more) => format!("drawn, {shown} … (+{more})"),
        None => format!("drawn, {shown}"),
    }
}

/// The sentence that says how [`type_label`] writes long types.
pub fn type_label_legend(steps: usize) -> String {
    format!(
        "types of {steps} steps are written as the drawn type and the steps whose sign differs from it (17+: step 17 is +)"
    )
}

/// Joints of a set written out in full (see [`joint_set`]).
const JOINT_SET_SHOWN: usize = 12;

/// `{a,b,c}`: a cluster's joints. A set of more than [`JOINT_SET_SHOWN`]
/// shows its first ones and says how many it holds (`{O,X0,…,X10,… 5001
/// joints}`): a Strandbeest's crank body holds every leg's crank tip, and
/// written out it made every row of the step table thousands of characters
/// wide (434 MB of text for 5000 legs).
pub fn joint_set<S: AsRef<str>>(names: &[S]) -> String {
    let shown: Vec<&str> = names.iter().take(JOINT_SET_SHOWN).map(AsRef::as_ref).collect();
    if names.len() <= JOINT_SET_SHOWN {
        format!("{{{}}}", shown.join(","))
    } else {
        format!("{{{},… {} joints}}", shown.join(","), names.len())
    }
}

/// `v ◁ (u, w)`: vertex `v` placed on `u` and `w` (a step without its number).
pub fn step_shape(vertex: &str, u: &str, w: &str) -> String {
    format!("{vertex} ◁ ({u}, {w})")
}

/// What a sentence needs to name things: the joints' names and, for a
/// recognised scene, its construction steps.
#[derive(Clone, Copy)]
pub struct Names<'a> {
    pub linkage: &'a Linkage,
    pub steps: &'a [Step],
}

impl<'a> Names<'a> {
    pub fn new(linkage: &'a Linkage, steps: &'a [Step]) -> Self {
        Names { linkage, steps }
    }

    fn joint(&self, j: usize) -> &'a str {
        &self.linkage.names[j]
    }

    fn joints(&self, js: &[usize]) -> String {
        js.iter().map(|&j| self.joint(j)).collect::<Vec<_>>().join(", ")
    }

    /// `step 3 (v ◁ (u, w))`: the one place a step is labelled.
    pub fn step(&self, k: usize) -> String {
        match self.steps.get(k) {
            Some(s) => format!(
                "step {} ({})",
                StepNo::of_index(k),
                step_shape(self.joint(s.vertex), self.joint(s.u), self.joint(s.w))
            ),
            None => format!("step {}", StepNo::of_index(k)),
        }
    }

    /// `step 3 (v ◁ (u, w)) folded`.
    pub fn event(&self, e: &Event) -> String {
        format!("{} {}", self.step(e.step), e.kind.name())
    }
}

/// Why a linkage is outside the handled class, naming joints, bars and bodies.
pub fn outside(o: &Outside, linkage: &Linkage) -> String {
    let n = Names::new(linkage, &[]);
    match o {
        Outside::Disconnected { parts } => {
            let list: Vec<String> = parts.iter().map(|p| format!("{{{}}}", n.joints(p))).collect();
            format!("disconnected: {} separate parts: {}", parts.len(), list.join(" "))
        }
        Outside::OverConstrained { redundant, dof } => {
            let what: Vec<String> = redundant.iter().map(|c| constraint(c, linkage)).collect();
            let rest = match dof {
                0 => "the rest is rigid".to_string(),
                1 => "1 degree of freedom remains".to_string(),
                d => format!("{d} degrees of freedom remain"),
            };
            format!("over-constrained: {} redundant ({rest})", what.join(", "))
        }
        Outside::Rigid { tree_decomposable: true } => "rigid: no motion (it is tree-decomposable)".to_string(),
        Outside::Rigid { tree_decomposable: false } => {
            "rigid: no motion, and not tree-decomposable (not buildable by ruler and compass)".to_string()
        }
        Outside::ManyDof { dof } => format!("{dof} degrees of freedom: a 1-dof linkage is needed"),
        Outside::NotTreeDecomposable => {
            "1 degree of freedom but not tree-decomposable: no base non-edge makes it buildable by ruler and compass"
                .to_string()
        }
    }
}

/// `bar A–B` or `body [A, B, C]`.
pub fn constraint(c: &Constraint, linkage: &Linkage) -> String {
    match *c {
        Constraint::Bar(i) => format!("bar {}{}", linkage.pair_name(linkage.bars[i].joints), on_line(linkage, *c)),
        Constraint::Body(i) => {
            format!("body [{}]{}", Names::new(linkage, &[]).joints(&linkage.bodies[i]), on_line(linkage, *c))
        }
    }
}

/// " (line N)" for a declaration read from a file; nothing for one made in code.
fn on_line(linkage: &Linkage, c: Constraint) -> String {
    linkage.line_of(c).map(|line| format!(" (line {line})")).unwrap_or_default()
}

/// Why the four-cycle test fails at a step.
pub fn lcc_failure(f: &LccFailure, n: Names) -> String {
    let s = &n.steps[f.step];
    let (u, w) = (n.joint(s.u), n.joint(s.w));
    let why = if f.opposite.is_empty() {
        format!("no adjacent pair of built clusters in a four-cycle holds {u} and {w}")
    } else {
        let cluster = |js: &[usize]| joint_set(&js.iter().map(|&j| n.joint(j)).collect::<Vec<_>>());
        let pairs: Vec<String> = f.opposite.iter().map(|[a, b]| format!("{} and {}", cluster(a), cluster(b))).collect();
        format!("{u} and {w} lie on clusters that share no joint (opposite in a four-cycle): {}", pairs.join("; "))
    };
    format!("{}: {why}", n.step(f.step))
}

/// Why (λ, type) has no realization.
pub fn unrealizable(why: &Unrealizable, ty: &RealizationType, lambda: f64, n: Names) -> String {
    match *why {
        Unrealizable::Infeasible { step, slack } => format!(
            "type {ty} has no realization at λ = {}: {} cannot close (short by {:.3e})",
            sig(lambda),
            n.step(step),
            -slack
        ),
        Unrealizable::Degenerate { step } => {
            let s = &n.steps[step];
            format!(
                "type {ty} at λ = {}: step {} has {} and {} at the same point, so {} is undetermined",
                sig(lambda),
                StepNo::of_index(step),
                n.joint(s.u),
                n.joint(s.w),
                n.joint(s.vertex)
            )
        }
    }
}

/// A special event of the Cayley-space computation.
pub fn note(note: &Note, n: Names) -> String {
    match note {
        Note::Coincident { lambda, events } => {
            let list: Vec<String> = events.iter().map(|e| n.event(e)).collect();
            format!(
                "non-generic: at λ = {} several steps are flat at once: {}; the motion may branch there",
                sig(*lambda),
                list.join(", ")
            )
        }
        Note::Tangency { lambda, event, inside: false } => format!(
            "tangency: {} is {} only at the isolated point λ = {}",
            n.step(event.step),
            event.kind.name(),
            sig(*lambda)
        ),
        Note::Tangency { lambda, event, inside: true } => format!(
            "tangency: {} touches {} at λ = {} inside an interval without leaving it",
            n.step(event.step),
            event.kind.name(),
            sig(*lambda)
        ),
        Note::Unresolved { lambda, step, why } => {
            let detail = match why {
                Unresolved::GapSign => "the slack's sign on one gap disagrees between its two roots".to_string(),
                Unresolved::Inflections => "the root search could not separate the inflections of d_k".to_string(),
                Unresolved::NearDoubleRoot => {
                    "a near-double root: two endpoints or none, not separable at this precision".to_string()
                }
                Unresolved::WalkBudget { intervals } => format!("the lazy walk stopped after {intervals} intervals"),
            };
            format!("unresolved near λ = {}, {}: {detail}", sig(*lambda), n.step(*step))
        }
        Note::ZeroBase { step } => format!(
            "the base length reaches 0 ({} folded with equal bars): the base joints coincide there",
            n.step(*step)
        ),
        Note::Degenerate { lambda, step } => format!(
            "degenerate: for some types {} has its base joints coincide {}, so its vertex turns freely (an extra degree of freedom); those types are left out there",
            n.step(*step),
            if lambda[0] == lambda[1] {
                format!("at λ = {}", sig(lambda[0]))
            } else {
                format!("for λ in [{}, {}]", sig(lambda[0]), sig(lambda[1]))
            }
        ),
    }
}

/// One warning of the analysis, in words.
pub fn warning(w: &Warning, n: Names) -> String {
    match w {
        Warning::GroundMoves { joints: [a, b] } => format!(
            "the ground joints {a} and {b} are in no rigid part together (no bar, body or rigid cluster holds both): their distance changes in the motion, so the display holds {a} in place and {b} on its drawn direction from {a}"
        ),
        Warning::BarInBody { bar, body, line } => {
            let l = n.linkage;
            let at = line.map(|line| format!(", line {line}")).unwrap_or_default();
            format!(
                "bar {} ({}{at}) joins two joints of body {} [{}], which already holds them at that length: the bar adds nothing and is ignored",
                ItemNo::of_index(*bar),
                l.pair_name(l.bars[*bar].joints),
                ItemNo::of_index(*body),
                n.joints(&l.bodies[*body])
            )
        }
        Warning::FlatInDrawing { step } => {
            format!("{} is flat in the drawing; its orientation is taken as +", n.step(*step))
        }
        Warning::RunsDiffer => {
            "the f64 and double-double runs found different intervals: some events are closer than f64 separates"
                .to_string()
        }
        Warning::WalkUnconfirmed => "the lazy walk's ends were not confirmed in double-double (events closer than f64 \
             separates): the full sweep's component through the drawn realization is given instead"
            .to_string(),
        Warning::SketchRelocated { ty, drawn_lambda, lambda } => format!(
            "the sketch's base length λ = {} is not attainable in its type {ty}; realized at the nearest attainable λ = {}",
            sig(*drawn_lambda),
            sig(*lambda)
        ),
        Warning::DrawnUnrealizable { ty, lambda, why } => unrealizable(why, ty, *lambda, n),
        Warning::BarResidual { residual } => format!("the drawn realization misses a bar length by {residual:.3e}"),
        Warning::EstimatedDecisions { count } => format!(
            "{count} decisions (is a slack zero at an end or inside a gap) rest on a double-double error estimate, not a proof: neither balls nor the exact stage decided them (slacks that touch zero or coincide with another step's, at an end only a root defines)"
        ),
        Warning::MirrorsAtResolution => "every cluster the steps stand on is flat to double-double resolution, some not provably (three or more joints on a line as written): mirror images of realizations are taken to be realizations, and mirror-image components to be at distance 0 (not certified)".to_string(),
        Warning::BranchPoint { lambda, events, ways, through } => {
            let list: Vec<String> =
                events.iter().map(|e| format!("step {} {}", StepNo::of_index(e.step), e.kind.name())).collect();
            let (at, list) = (sig(*lambda), list.join(", "));
            if *ways == 0 && *through > 0 {
                let beyond = if *through == 1 {
                    "the type with that step flipped, listed as another component".to_string()
                } else {
                    format!("{through} types with a step flipped, listed as other components")
                };
                return format!(
                    "a singular place at λ = {at} ({list}, a touch): the motion passes through it into {beyond} of the same connected set"
                );
            }
            if events.is_empty() {
                return format!(
                    "an end at λ = {at} where no step is flat (a degenerate place: a step's base joints coincide there, so its vertex can turn freely, an extra degree of freedom): each listed component ends there; motions through that turn are not followed (a base whose joints never meet follows them; caymos picks one when the scene names no base)"
                );
            }
            let what = if *ways == 0 { "a dead end" } else { "a branch point" };
            format!("{what} at λ = {at} ({list}): {ways} ways on; each listed component follows the lowest flat step's flip there")
        }
        Warning::Note(x) => note(x, n),
    }
}

/// Why a solved scene has no component, in words.
pub fn no_realization(why: &NoRealization, n: Names, con: &crate::realize::Construction<f64>) -> String {
    let base = format!("{}–{}", n.joint(con.base[0]), n.joint(con.base[1]));
    let with_lengths = |k: usize| {
        let g = &con.steps[k];
        let (v, u, w) = (n.joint(g.vertex), n.joint(g.u), n.joint(g.w));
        format!("{}: |{u}{v}| = {}, |{w}{v}| = {}", n.step(k), fmt_num(g.r1), fmt_num(g.r2))
    };
    match why {
        NoRealization::BaseRangesMiss { lower, lower_step, upper, upper_step } => format!(
            "no realization: the base {base} would have to be at least {} long for {} but at most {} for {}",
            fmt_num(*lower),
            with_lengths(*lower_step),
            fmt_num(*upper),
            with_lengths(*upper_step)
        ),
        NoRealization::NumericFailure { drawn_closes, ty, lambda, scale } => format!(
            "no realization was found, yet {}: the analysis failed numerically (scene scale {}); please report this scene",
            if *drawn_closes {
                format!(
                    "the drawn realization (type {} at λ = {}) closes every step",
                    short_type(&ty.to_string()),
                    fmt_num(*lambda)
                )
            } else {
                "every step stands on the base and their ranges overlap".to_string()
            },
            fmt_num(*scale)
        ),
        NoRealization::LazyDrawnType { ty, lambda } => format!(
            "no realization found: the lazy analysis walks from the drawn realization, and its type {} has none at λ = {} (`--all` analyses every type)",
            short_type(&ty.to_string()),
            fmt_num(*lambda)
        ),
        NoRealization::NoTypeCloses { range, estimated } => {
            let range = range
                .map(|[lo, hi]| {
                    format!(
                        " for any base length in [{}, {}], the range the steps on the base allow",
                        fmt_num(lo),
                        fmt_num(hi)
                    )
                })
                .unwrap_or_default();
            let unproven = if *estimated > 0 {
                format!("; not proven: {estimated} decisions rest on double-double error estimates (see the warnings)")
            } else {
                String::new()
            };
            format!("no realization: no orientation type closes every construction step{range}{unproven}")
        }
    }
}

/// Why a realization could not be located.
pub fn missing(m: &Missing) -> String {
    match m {
        Missing::WrongLength { ty, signs, steps } => {
            format!("type {ty} has {signs} signs; this scene has {steps} steps")
        }
        Missing::NoInterval { ty } => format!("type {ty} has no realization at any λ"),
        Missing::Elsewhere { ty, lambda, spans } => {
            let spans: Vec<String> = spans.iter().map(|&span| fmt_span(span)).collect();
            format!("type {ty} is not realizable at λ = {lambda}; it is at λ in {}", spans.join(" ∪ "))
        }
    }
}

/// How far a minimal complete Cayley vector is proven smallest, in words.
pub fn minimality(m: &crate::minimal_vector::MinimalVector) -> String {
    use crate::minimal_vector::Minimality;
    let mut said = match m.minimality {
        Minimality::Proven => "proven to separate every component's realizations, and proven smallest".to_string(),
        Minimality::SmallestFound => {
            "proven to separate every component's realizations; no smaller set was proven (one may exist)".to_string()
        }
        Minimality::Whole => "no smaller set was proven to separate within the work budget".to_string(),
    };
    if m.unenclosed_component {
        said.push_str(
            " (a component could not be enclosed with proofs: several steps flat at once, or a deep construction)",
        );
    }
    said
}

pub fn certificate(c: &Certificate) -> String {
    let (lo, hi, req) = (full(c.lower), full(c.upper), c.requested_gap);
    let range = format!("the minimum distance lies in [{lo}, {hi}] (relative gap {:.1e})", c.gap);
    let mut o = match c.outcome {
        Outcome::Mirror => {
            return "distance exactly 0: the components are mirror images (every realization's mirror lies in the \
                    other, with the same Cayley vector)"
                .into();
        }
        Outcome::Shared => {
            return "distance 0: the components meet at a branch point, where they share a realization (the pair \
                    above: the same realization in two types, the steps flat there coinciding to double-double \
                    resolution, a non-generic place; not certified)"
                .into();
        }
        Outcome::GapReached if c.certified => format!(
            "certified to {req:e}: no two realizations, one in each component, are closer than {lo}, and the pair \
             above is at most {hi} apart (interval arithmetic with outward rounding over {} boxes and {} pairs of \
             interval ends, every end verified)",
            c.boxes, c.end_pairs
        ),
        Outcome::GapReached => format!("gap {req:e} reached over the intervals as computed: {range}"),
        Outcome::Resolution if c.upper.is_infinite() => format!(
            "not certified: f64 interval arithmetic cannot enclose these realizations (their construction is too \
             deep for its rounding to stay small); proven: no two realizations are closer than {lo}"
        ),
        Outcome::Resolution if c.lower == 0.0 && c.upper > 0.0 => format!(
            "not certified to {req:e}: the Cayley curves meet or nearly so (the pair above is 0 apart up to \
             rounding); proven: the minimum distance lies in [0, {hi}]"
        ),
        Outcome::Resolution => {
            format!(
                "not certified to {req:e}: f64 interval arithmetic does not resolve the distance that finely here; proven: {range}"
            )
        }
        Outcome::Budget => {
            format!("not certified to {req:e}: the budget of {} boxes ran out; proven: {range}", c.max_boxes)
        }
    };
    if c.unverified_ends > 0 {
        let _ = write!(
            o,
            "; not certified: {} interval ends could not be verified (several steps flat at once, or a tangency), \
             so the bounds hold for the intervals as computed",
            c.unverified_ends
        );
    }
    o
}

/// A branch point passed, and the way taken, in words.
pub fn branch_taken(b: &crate::commands::BranchOut) -> String {
    let steps: Vec<String> = b.steps.iter().map(|k| k.to_string()).collect();
    format!(
        "at λ = {}, a branch point (steps {} flat; {} ways meet: {}), it went on into type {}",
        fmt_sig(b.lambda, 17),
        steps.join(", "),
        b.ways.len(),
        b.ways.join(", "),
        b.took
    )
}

/// Sentences about a walk that did not simply run from start to end.
pub fn walk_notes(w: &crate::motion::WalkSummary, max_samples: usize) -> Vec<String> {
    let mut notes = Vec::new();
    if w.truncated {
        notes.push(format!(
            "stopped at the sample budget ({max_samples} samples) before the end; --max-samples raises it, a larger --step needs fewer"
        ));
    }
    if let Some(l) = w.stopped_at {
        notes.push(format!("no realization could be computed at λ = {}: the walk ends there", fmt_num(l)));
    }
    if !w.jumps.is_empty() {
        // Jumps that print alike (6 digits) are listed once, with their count.
        let mut places: Vec<(String, usize)> = Vec::new();
        for &l in &w.jumps {
            match places.last_mut() {
                Some((text, n)) if *text == fmt_num(l) => *n += 1,
                _ => places.push((fmt_num(l), 1)),
            }
        }
        let shown: Vec<String> =
            places.iter().take(8).map(|(t, n)| if *n > 1 { format!("{t} ({n} times)") } else { t.clone() }).collect();
        let more = if places.len() > 8 { format!(", … ({} places)", places.len()) } else { String::new() };
        notes.push(format!(
            "{} jump{} (joints move farther than the step between adjacent floats of λ: a degenerate pass; no continuous motion joins the two samples) at λ = {}{more}",
            w.jumps.len(),
            if w.jumps.len() == 1 { "" } else { "s" },
            shown.join(", ")
        ));
    }
    for [from, to] in &w.unresolved {
        notes.push(format!(
            "the realization is not resolved in f64 for λ from {} to {} (joints jump at every step there): skipped as one jump",
            fmt_num(*from),
            fmt_num(*to)
        ));
    }
    notes
}

/// Why an analysis within the step limit is lazy: its full sweep's
/// `estimate` is above `budget` (`None` otherwise: asked for, or too many steps).
pub fn lazy_reason(estimate: Option<f64>, budget: f64) -> Option<String> {
    estimate.filter(|&cost| cost > budget).map(|cost| {
        format!(
            "a full sweep is estimated at {} realization steps, above the budget of {}",
            fmt_num(cost),
            fmt_num(budget)
        )
    })
}

/// In a lazy analysis, which components are known and how they were found.
pub fn lazy_note(s: &crate::analysis::Solved) -> Option<String> {
    if !s.lazy {
        return None;
    }
    let n = s.components.list.len();
    let why =
        lazy_reason(s.sweep_estimate, crate::tolerance::SWEEP_COST_MAX).map_or(String::new(), |r| format!("; {r}"));
    Some(format!(
        "lazy analysis ({} steps{why}): {n} component{} walked: the drawn realization's{}; `--component K` walks more, `--all` analyses every type (component numbers then follow `report --all`)",
        s.dec.steps.len(),
        if n == 1 { "" } else { "s" },
        if n > 1 {
            format!(" and those through realizations at the drawn λ = {}, in type order", fmt_num(s.drawn.lambda))
        } else {
            String::new()
        }
    ))
}

/// "no component K: …" for the component at index `k`, saying what is known
/// (all components, or what a lazy analysis walked).
pub fn missing_component(s: &crate::analysis::Solved, k: usize) -> String {
    let n = s.components.list.len();
    if s.lazy {
        format!(
            "no component {}: {n} component{} walked lazily (the drawn realization's, then at most {} more per command through realizations at the drawn λ = {}, in type order); `--all` analyses every type",
            ComponentNo::of_index(k),
            if n == 1 { "" } else { "s" },
            crate::tolerance::LAZY_MAX_NEW_COMPONENTS,
            fmt_num(s.drawn.lambda)
        )
    } else {
        format!(
            "no component {}: this scene has {n} component{} (1..{n})",
            ComponentNo::of_index(k),
            if n == 1 { "" } else { "s" },
        )
    }
}

/// Said when an SVG's traces end at [`crate::tolerance::SVG_MAX_POINTS`].
pub fn svg_cut_note(joints: usize) -> String {
    format!(
        "the traces end early: an SVG keeps at most {} points ({joints} joints traced; --joints traces fewer, a larger --step needs fewer)",
        crate::tolerance::SVG_MAX_POINTS
    )
}

/// A sweep sample's class in a word or two.
pub fn sweep_class(k: crate::sweep::ClassKind) -> &'static str {
    use crate::sweep::ClassKind;
    match k {
        ClassKind::Solved => "solved",
        ClassKind::NoRealization => "no realization",
        ClassKind::Outside => "outside",
        ClassKind::Invalid => "invalid",
    }
}

/// Why a sweep sample has no Cayley space, in words (`None` when it has one).
pub fn sweep_reason(class: &crate::sweep::Class, linkage: &Linkage) -> Option<String> {
    use crate::sweep::Class;
    match class {
        Class::Solved => None,
        Class::NoRealization => Some("in the class, but the linkage cannot close: no realization".into()),
        Class::Outside(o) => Some(format!("outside the handled class: {}", outside(o, linkage))),
        Class::Invalid(message) => Some(message.clone()),
    }
}

/// One change of a sweep's structure, e.g. "components 2 → 1".
pub fn sweep_change(c: &crate::sweep::Change) -> String {
    use crate::sweep::Change;
    let counts = |v: &[usize]| v.iter().map(usize::to_string).collect::<Vec<_>>().join(",");
    match c {
        Change::Class { from, to } => format!("class {} → {}", sweep_class(*from), sweep_class(*to)),
        Change::Components { from, to } => format!("components {from} → {to}"),
        Change::ComponentSizes { from, to } => {
            format!("component sizes (intervals) {} → {}", counts(from), counts(to))
        }
        Change::Intervals { from, to } if to > from => format!("interval born: oriented intervals {from} → {to}"),
        Change::Intervals { from, to } => format!("interval dies: oriented intervals {from} → {to}"),
        Change::UnionParts { from, to } => format!("Cayley space pieces {from} → {to}"),
        Change::EventsMeet { events } => {
            let e: Vec<String> =
                events.iter().map(|e| format!("step {} {}", StepNo::of_index(e.step), e.kind.name())).collect();
            format!("events meet ({})", e.join(", "))
        }
        Change::BranchPoints { from, to } => format!("branch points {from} → {to}"),
        Change::FullTurns { from, to } => format!("input bar turns fully in {from} → {to} components"),
        Change::TurnsUndecided => "the input bar's turning is undecided on one side".into(),
    }
}

/// All changes of a transition in one line ("no net change" when none).
pub fn sweep_changes(changes: &[crate::sweep::Change]) -> String {
    if changes.is_empty() {
        return "no net change".into();
    }
    changes.iter().map(sweep_change).collect::<Vec<_>>().join("; ")
}
