//! The key table: a small, pure map from key presses to actions. The key bar
//! and the help overlay are generated from it, so they never disagree.

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

/// Everything a key can ask for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    StepForward,
    StepBack,
    LargeForward,
    LargeBack,
    NextEndpoint,
    PrevEndpoint,
    PlayPause,
    NextComponent,
    PrevComponent,
    GoTo,
    MarkA,
    MarkB,
    ClearMarks,
    FollowArc1,
    FollowArc2,
    FollowComponent,
    ToggleTraces,
    NextJoint,
    ToggleJointTrace,
    SwitchView,
    RotateLeft,
    RotateRight,
    TiltUp,
    TiltDown,
    NextAxes,
    StepBigger,
    StepSmaller,
    Reset,
    Help,
    Quit,
    ToggleEdit,
    Undo,
    Redo,
    Save,
    SelectNext,
    SelectPrev,
    SelectByName,
    MoveLeft,
    MoveRight,
    MoveUp,
    MoveDown,
    MoveLeftFar,
    MoveRightFar,
    MoveUpFar,
    MoveDownFar,
    Lengthen,
    Shorten,
    LengthenFar,
    ShortenFar,
    SetValue,
    DeleteBar,
    ExitEdit,
    NextInputBar,
    Export,
    ScrollDown,
    ScrollUp,
    NextBase,
    Sweep,
    ToggleSweep,
    NameAxes,
    TakeBranch,
}

impl Action {
    /// Every action, in declaration order (the keymap test checks each has a key).
    pub const ALL: [Action; 61] = [
        Action::StepForward,
        Action::StepBack,
        Action::LargeForward,
        Action::LargeBack,
        Action::NextEndpoint,
        Action::PrevEndpoint,
        Action::PlayPause,
        Action::NextComponent,
        Action::PrevComponent,
        Action::GoTo,
        Action::MarkA,
        Action::MarkB,
        Action::ClearMarks,
        Action::FollowArc1,
        Action::FollowArc2,
        Action::FollowComponent,
        Action::ToggleTraces,
        Action::NextJoint,
        Action::ToggleJointTrace,
        Action::SwitchView,
        Action::RotateLeft,
        Action::RotateRight,
        Action::TiltUp,
        Action::TiltDown,
        Action::NextAxes,
        Action::StepBigger,
        Action::StepSmaller,
        Action::Reset,
        Action::Help,
        Action::Quit,
        Action::ToggleEdit,
        Action::Undo,
        Action::Redo,
        Action::Save,
        Action::SelectNext,
        Action::SelectPrev,
        Action::SelectByName,
        Action::MoveLeft,
        Action::MoveRight,
        Action::MoveUp,
        Action::MoveDown,
        Action::MoveLeftFar,
        Action::MoveRightFar,
        Action::MoveUpFar,
        Action::MoveDownFar,
        Action::Lengthen,
        Action::Shorten,
        Action::LengthenFar,
        Action::ShortenFar,
        Action::SetValue,
        Action::DeleteBar,
        Action::ExitEdit,
        Action::NextInputBar,
        Action::Export,
        Action::ScrollDown,
        Action::ScrollUp,
        Action::NextBase,
        Action::Sweep,
        Action::ToggleSweep,
        Action::NameAxes,
        Action::TakeBranch,
    ];
}

/// A key as written in the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    Char(char),
    Ctrl(char),
    Code(KeyCode),
    /// A key with Shift held (Shift-arrows); a plain `Code` row takes any modifier.
    Shift(KeyCode),
}

impl Key {
    /// How the help and the key bar write the key.
    pub fn name(self) -> String {
        match self {
            Key::Char(' ') => "space".into(),
            Key::Char(c) => c.to_string(),
            Key::Ctrl(c) => format!("Ctrl-{c}"),
            Key::Code(KeyCode::Right) => "→".into(),
            Key::Code(KeyCode::Left) => "←".into(),
            Key::Code(KeyCode::Up) => "↑".into(),
            Key::Code(KeyCode::Down) => "↓".into(),
            Key::Code(KeyCode::PageDown) => "PgDn".into(),
            Key::Code(KeyCode::PageUp) => "PgUp".into(),
            Key::Code(KeyCode::Tab) => "Tab".into(),
            Key::Code(KeyCode::BackTab) => "S-Tab".into(),
            Key::Code(KeyCode::Esc) => "Esc".into(),
            Key::Code(KeyCode::Enter) => "Enter".into(),
            Key::Code(KeyCode::Delete) => "Del".into(),
            Key::Code(code) => code.to_string(),
            Key::Shift(code) => format!("S-{}", Key::Code(code).name()),
        }
    }

    /// The key press this key stands for.
    pub fn event(self) -> KeyEvent {
        match self {
            Key::Char(c) => KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE),
            Key::Ctrl(c) => KeyEvent::new(KeyCode::Char(c), KeyModifiers::CONTROL),
            Key::Code(code) => KeyEvent::new(code, KeyModifiers::NONE),
            Key::Shift(code) => KeyEvent::new(code, KeyModifiers::SHIFT),
        }
    }

    fn matches(self, ev: &KeyEvent) -> bool {
        let ctrl = ev.modifiers.contains(KeyModifiers::CONTROL);
        match self {
            Key::Char(c) => !ctrl && ev.code == KeyCode::Char(c),
            Key::Ctrl(c) => ctrl && ev.code == KeyCode::Char(c),
            Key::Shift(code) => ev.modifiers.contains(KeyModifiers::SHIFT) && ev.code == code,
            // With Shift held, an arrow is its Shift row's.
            Key::Code(code) => {
                ev.code == code && !(SHIFTED.contains(&code) && ev.modifiers.contains(KeyModifiers::SHIFT))
            }
        }
    }
}

/// Keys with a Shift row of their own (Shift-arrows move a joint farther).
const SHIFTED: [KeyCode; 4] = [KeyCode::Left, KeyCode::Right, KeyCode::Up, KeyCode::Down];

/// What the keys do: explore the motion, or edit the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Explore,
    Edit,
}

/// The modes a row works in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum When {
    Explore,
    Edit,
    Both,
}

impl When {
    pub fn includes(self, mode: Mode) -> bool {
        matches!((self, mode), (When::Both, _) | (When::Explore, Mode::Explore) | (When::Edit, Mode::Edit))
    }
}

/// One row of the table: the keys, the action, how the help and key bar describe it.
#[derive(Clone, Copy, Debug)]
pub struct Binding {
    pub keys: &'static [Key],
    pub action: Action,
    pub help: &'static str,
    /// The word shown in the key bar at the bottom; empty: only in the help overlay.
    pub bar: &'static str,
    /// The modes it works in.
    pub when: When,
}

impl Binding {
    /// Every key of the row, as the help overlay lists them (`n/Tab`).
    pub fn label(&self) -> String {
        self.keys.iter().map(|k| k.name()).collect::<Vec<_>>().join("/")
    }

    /// The first key, as the key bar shows it.
    pub fn short_label(&self) -> String {
        self.keys.first().map(|k| k.name()).unwrap_or_default()
    }
}

/// A row for exploring.
const fn bind(keys: &'static [Key], action: Action, help: &'static str, bar: &'static str) -> Binding {
    Binding { keys, action, help, bar, when: When::Explore }
}

/// A row for both modes.
const fn both(keys: &'static [Key], action: Action, help: &'static str, bar: &'static str) -> Binding {
    Binding { keys, action, help, bar, when: When::Both }
}

/// A row for editing.
const fn edit(keys: &'static [Key], action: Action, help: &'static str, bar: &'static str) -> Binding {
    Binding { keys, action, help, bar, when: When::Edit }
}

use Key::{Char, Code, Ctrl, Shift};

/// The whole table, in the order the help overlay lists it.
pub const BINDINGS: &[Binding] = &[
    bind(&[Code(KeyCode::Right), Char('l')], Action::StepForward, "step forward (geometric)", "step"),
    bind(&[Code(KeyCode::Left), Char('h')], Action::StepBack, "step back", ""),
    bind(&[Char('L'), Code(KeyCode::PageDown)], Action::LargeForward, "large step forward", ""),
    bind(&[Char('H'), Code(KeyCode::PageUp)], Action::LargeBack, "large step back", ""),
    both(&[Char(']')], Action::NextEndpoint, "next interval endpoint", "endpoint"),
    both(&[Char('[')], Action::PrevEndpoint, "previous interval endpoint", ""),
    both(&[Char(' ')], Action::PlayPause, "play / pause", "play"),
    bind(&[Char('n'), Code(KeyCode::Tab)], Action::NextComponent, "next component", "component"),
    bind(&[Char('p'), Code(KeyCode::BackTab)], Action::PrevComponent, "previous component", ""),
    bind(&[Char('g')], Action::GoTo, "go to λ or TYPE@λ", "go to"),
    bind(&[Char('f')], Action::TakeBranch, "branch point: next way on", ""),
    bind(&[Char('a')], Action::MarkA, "mark A here", "mark A"),
    bind(&[Char('b')], Action::MarkB, "mark B: paths or closest", "mark B"),
    bind(&[Char('c')], Action::ClearMarks, "clear marks A, B", ""),
    bind(&[Char('1')], Action::FollowArc1, "follow path 1, A to B", ""),
    bind(&[Char('2')], Action::FollowArc2, "follow path 2, A to B", ""),
    bind(&[Code(KeyCode::Esc)], Action::FollowComponent, "whole component; close help", ""),
    bind(&[Char('t')], Action::ToggleTraces, "traces on / off", "traces"),
    bind(&[Char('j')], Action::NextJoint, "select next joint", ""),
    bind(&[Char('J')], Action::ToggleJointTrace, "trace / untrace that joint", ""),
    both(&[Char('v')], Action::SwitchView, "linkage / Cayley curve", "view"),
    bind(&[Char('r')], Action::RotateLeft, "rotate curve left", ""),
    bind(&[Char('R')], Action::RotateRight, "rotate curve right", ""),
    bind(&[Char('e')], Action::TiltUp, "tilt curve up", ""),
    bind(&[Char('E')], Action::TiltDown, "tilt curve down", ""),
    bind(&[Char('x')], Action::NextAxes, "next curve axes (CCV)", ""),
    bind(&[Char('A')], Action::NameAxes, "curve axes by name", ""),
    bind(&[Char('B')], Action::NextBase, "next valid base non-edge", ""),
    bind(&[Char('+'), Char('=')], Action::StepBigger, "double the step", ""),
    bind(&[Char('-')], Action::StepSmaller, "halve the step", ""),
    bind(&[Char('i')], Action::NextInputBar, "input bar: drive by angle", "angle"),
    both(&[Char('0'), Char('d')], Action::Reset, "reset to drawn", ""),
    both(&[Char('?')], Action::Help, "this help", "help"),
    both(&[Char('q'), Ctrl('c')], Action::Quit, "quit", "quit"),
    both(&[Char('m')], Action::ToggleEdit, "edit mode on / off", "edit"),
    both(&[Char('u')], Action::Undo, "undo an edit", "undo"),
    both(&[Ctrl('r'), Char('U')], Action::Redo, "redo an edit", ""),
    both(&[Char('w'), Ctrl('s')], Action::Save, "save the scene file", "save"),
    bind(&[Char('o')], Action::Export, "export trace CSV + SVG", ""),
    edit(&[Code(KeyCode::Tab)], Action::SelectNext, "select next joint / bar", "select"),
    edit(&[Code(KeyCode::BackTab)], Action::SelectPrev, "select previous joint / bar", ""),
    edit(&[Char('/')], Action::SelectByName, "select by name (C or B-C)", ""),
    edit(&[Code(KeyCode::Left), Char('h')], Action::MoveLeft, "move joint left (fine)", ""),
    edit(&[Code(KeyCode::Right), Char('l')], Action::MoveRight, "move joint right", "move"),
    edit(&[Code(KeyCode::Up), Char('k')], Action::MoveUp, "move joint up", ""),
    edit(&[Code(KeyCode::Down), Char('j')], Action::MoveDown, "move joint down", ""),
    edit(&[Shift(KeyCode::Left), Char('H')], Action::MoveLeftFar, "move joint left (coarse)", ""),
    edit(&[Shift(KeyCode::Right), Char('L')], Action::MoveRightFar, "move joint right (coarse)", ""),
    edit(&[Shift(KeyCode::Up), Char('K')], Action::MoveUpFar, "move joint up (coarse)", ""),
    edit(&[Shift(KeyCode::Down), Char('J')], Action::MoveDownFar, "move joint down (coarse)", ""),
    edit(&[Char('+')], Action::Lengthen, "lengthen bar (fine)", "length"),
    edit(&[Char('-')], Action::Shorten, "shorten bar (fine)", ""),
    edit(&[Char('>')], Action::LengthenFar, "lengthen bar (coarse)", ""),
    edit(&[Char('<')], Action::ShortenFar, "shorten bar (coarse)", ""),
    edit(&[Char('='), Code(KeyCode::Enter)], Action::SetValue, "type x, y or a length", "set"),
    edit(&[Code(KeyCode::Delete), Char('X')], Action::DeleteBar, "delete the bar", ""),
    edit(&[Code(KeyCode::Esc)], Action::ExitEdit, "explore again; close help", ""),
    both(&[Char('s')], Action::Sweep, "sweep selected bar / joint", "sweep"),
    both(&[Char('S')], Action::ToggleSweep, "show / hide the sweep", ""),
    both(&[Char('}')], Action::ScrollDown, "scroll the lists down", ""),
    both(&[Char('{')], Action::ScrollUp, "scroll the lists up", ""),
];

/// The rows that work in `mode`.
pub fn bindings(mode: Mode) -> impl Iterator<Item = &'static Binding> {
    BINDINGS.iter().filter(move |b| b.when.includes(mode))
}

/// The action for a key press in `mode`, if any.
pub fn action_for(mode: Mode, ev: &KeyEvent) -> Option<Action> {
    bindings(mode).find(|b| b.keys.iter().any(|k| k.matches(ev))).map(|b| b.action)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(code: KeyCode) -> KeyEvent {
        KeyEvent::new(code, KeyModifiers::NONE)
    }

    #[test]
    fn keys_map_to_their_actions() {
        assert_eq!(action_for(Mode::Explore, &key(KeyCode::Right)), Some(Action::StepForward));
        assert_eq!(action_for(Mode::Explore, &key(KeyCode::Char('l'))), Some(Action::StepForward));
        assert_eq!(action_for(Mode::Explore, &key(KeyCode::Char('L'))), Some(Action::LargeForward));
        assert_eq!(action_for(Mode::Explore, &key(KeyCode::Char(']'))), Some(Action::NextEndpoint));
        assert_eq!(action_for(Mode::Explore, &key(KeyCode::Char('q'))), Some(Action::Quit));
        assert_eq!(
            action_for(Mode::Explore, &KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL)),
            Some(Action::Quit)
        );
        // Edit mode: arrows move the joint, Shift-arrows farther; Tab selects; q still quits.
        assert_eq!(action_for(Mode::Edit, &key(KeyCode::Right)), Some(Action::MoveRight));
        assert_eq!(
            action_for(Mode::Edit, &KeyEvent::new(KeyCode::Right, KeyModifiers::SHIFT)),
            Some(Action::MoveRightFar)
        );
        assert_eq!(action_for(Mode::Edit, &key(KeyCode::Tab)), Some(Action::SelectNext));
        assert_eq!(
            action_for(Mode::Edit, &KeyEvent::new(KeyCode::BackTab, KeyModifiers::SHIFT)),
            Some(Action::SelectPrev)
        );
        assert_eq!(action_for(Mode::Edit, &key(KeyCode::Char('q'))), Some(Action::Quit));
        assert_eq!(action_for(Mode::Edit, &key(KeyCode::Char('g'))), None, "go to is for exploring");
        assert_eq!(action_for(Mode::Explore, &key(KeyCode::Char('m'))), Some(Action::ToggleEdit));
        assert_eq!(action_for(Mode::Edit, &key(KeyCode::Char('m'))), Some(Action::ToggleEdit));
        assert_eq!(action_for(Mode::Explore, &key(KeyCode::Char('X'))), None, "no deleting while exploring");
        assert_eq!(action_for(Mode::Explore, &key(KeyCode::Char('c'))), Some(Action::ClearMarks));
        assert_eq!(action_for(Mode::Explore, &key(KeyCode::Char('Z'))), None);
        assert_eq!(action_for(Mode::Explore, &key(KeyCode::Char('i'))), Some(Action::NextInputBar));
        assert_eq!(action_for(Mode::Explore, &key(KeyCode::Char('o'))), Some(Action::Export));
        assert_eq!(action_for(Mode::Edit, &key(KeyCode::Char('o'))), None, "no exporting while editing");
    }

    /// `Action::ALL` is every variant, in order: this match has no wildcard,
    /// so a new action does not compile until it is listed here and in `ALL`.
    fn ordinal(a: Action) -> usize {
        match a {
            Action::StepForward => 0,
            Action::StepBack => 1,
            Action::LargeForward => 2,
            Action::LargeBack => 3,
            Action::NextEndpoint => 4,
            Action::PrevEndpoint => 5,
            Action::PlayPause => 6,
            Action::NextComponent => 7,
            Action::PrevComponent => 8,
            Action::GoTo => 9,
            Action::MarkA => 10,
            Action::MarkB => 11,
            Action::ClearMarks => 12,
            Action::FollowArc1 => 13,
            Action::FollowArc2 => 14,
            Action::FollowComponent => 15,
            Action::ToggleTraces => 16,
            Action::NextJoint => 17,
            Action::ToggleJointTrace => 18,
            Action::SwitchView => 19,
            Action::RotateLeft => 20,
            Action::RotateRight => 21,
            Action::TiltUp => 22,
            Action::TiltDown => 23,
            Action::NextAxes => 24,
            Action::StepBigger => 25,
            Action::StepSmaller => 26,
            Action::Reset => 27,
            Action::Help => 28,
            Action::Quit => 29,
            Action::ToggleEdit => 30,
            Action::Undo => 31,
            Action::Redo => 32,
            Action::Save => 33,
            Action::SelectNext => 34,
            Action::SelectPrev => 35,
            Action::SelectByName => 36,
            Action::MoveLeft => 37,
            Action::MoveRight => 38,
            Action::MoveUp => 39,
            Action::MoveDown => 40,
            Action::MoveLeftFar => 41,
            Action::MoveRightFar => 42,
            Action::MoveUpFar => 43,
            Action::MoveDownFar => 44,
            Action::Lengthen => 45,
            Action::Shorten => 46,
            Action::LengthenFar => 47,
            Action::ShortenFar => 48,
            Action::SetValue => 49,
            Action::DeleteBar => 50,
            Action::ExitEdit => 51,
            Action::NextInputBar => 52,
            Action::Export => 53,
            Action::ScrollDown => 54,
            Action::ScrollUp => 55,
            Action::NextBase => 56,
            Action::Sweep => 57,
            Action::ToggleSweep => 58,
            Action::NameAxes => 59,
            Action::TakeBranch => 60,
        }
    }

    #[test]
    fn every_action_has_a_key_and_one_row() {
        for (i, &a) in Action::ALL.iter().enumerate() {
            assert_eq!(ordinal(a), i, "Action::ALL out of order at {a:?}");
            let rows: Vec<&Binding> = BINDINGS.iter().filter(|b| b.action == a).collect();
            assert_eq!(rows.len(), 1, "{a:?} has {} rows in the key table", rows.len());
            assert!(!rows[0].keys.is_empty(), "{a:?} has no key");
            // And its keys reach it in every mode it works in.
            for mode in [Mode::Explore, Mode::Edit].into_iter().filter(|&m| rows[0].when.includes(m)) {
                for k in rows[0].keys {
                    assert_eq!(action_for(mode, &k.event()), Some(a), "{k:?} in {mode:?}");
                }
            }
        }
        assert_eq!(BINDINGS.len(), Action::ALL.len());
    }

    #[test]
    fn no_key_is_bound_twice() {
        // Compared as key presses, so `Char('c')` and `Code(KeyCode::Char('c'))` would collide too.
        // Within each mode: a key may mean different things in the two modes.
        for mode in [Mode::Explore, Mode::Edit] {
            for b in bindings(mode) {
                for k in b.keys {
                    let ev = k.event();
                    let matching: Vec<Action> = bindings(mode)
                        .flat_map(|b2| b2.keys.iter().filter(|k2| k2.matches(&ev)).map(|_| b2.action))
                        .collect();
                    assert_eq!(matching, vec![b.action], "{} is bound to {matching:?} in {mode:?}", k.name());
                }
            }
        }
    }

    #[test]
    fn every_row_has_a_label_and_help_and_the_bar_has_help_and_quit() {
        for b in BINDINGS {
            assert!(!b.help.is_empty() && !b.label().is_empty(), "{:?}", b.action);
        }
        assert_eq!(BINDINGS.iter().find(|b| b.action == Action::Quit).unwrap().label(), "q/Ctrl-c");
        assert_eq!(BINDINGS.iter().find(|b| b.action == Action::NextComponent).unwrap().label(), "n/Tab");
        for mode in [Mode::Explore, Mode::Edit] {
            for a in [Action::Quit, Action::Help, Action::ToggleEdit] {
                assert!(bindings(mode).any(|b| b.action == a && !b.bar.is_empty()), "{a:?} in the {mode:?} bar");
            }
        }
    }
}
