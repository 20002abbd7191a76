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
}

impl Action {
    /// Every action, in declaration order (the keymap test checks each has a key).
    pub const ALL: [Action; 30] = [
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
    ];
}

/// A key as written in the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    Char(char),
    Ctrl(char),
    Code(KeyCode),
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
            Key::Code(code) => code.to_string(),
        }
    }

    /// The key press this key stands for.
    pub fn event(self) -> KeyEvent {
        match self {
            Key::Char(c) => KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE),
            Key::Ctrl(c) => KeyEvent::new(KeyCode::Char(c), KeyModifiers::CONTROL),
            Key::Code(code) => KeyEvent::new(code, KeyModifiers::NONE),
        }
    }

    fn matches(self, ev: &KeyEvent) -> bool {
        let ctrl = ev.modifiers.contains(KeyModifiers::CONTROL);
        match self {
            Key::Char(c) => !ctrl && ev.code == KeyCode::Char(c),
            Key::Ctrl(c) => ctrl && ev.code == KeyCode::Char(c),
            Key::Code(code) => ev.code == code,
        }
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

const fn bind(keys: &'static [Key], action: Action, help: &'static str, bar: &'static str) -> Binding {
    Binding { keys, action, help, bar }
}

use Key::{Char, Code, Ctrl};

/// The whole table, in the order the help overlay lists it.
pub const BINDINGS: &[Binding] = &[
    bind(&[Code(KeyCode::Right), Char('l')], Action::StepForward, "step forward (geometric)", "step"),
    bind(&[Code(KeyCode::Left), Char('h')], Action::StepBack, "step back", ""),
    bind(&[Char('L'), Code(KeyCode::PageDown)], Action::LargeForward, "large step forward", ""),
    bind(&[Char('H'), Code(KeyCode::PageUp)], Action::LargeBack, "large step back", ""),
    bind(&[Char(']')], Action::NextEndpoint, "next interval endpoint", "endpoint"),
    bind(&[Char('[')], Action::PrevEndpoint, "previous interval endpoint", ""),
    bind(&[Char(' ')], Action::PlayPause, "play / pause", "play"),
    bind(&[Char('n'), Code(KeyCode::Tab)], Action::NextComponent, "next component", "component"),
    bind(&[Char('p'), Code(KeyCode::BackTab)], Action::PrevComponent, "previous component", ""),
    bind(&[Char('g')], Action::GoTo, "go to λ or TYPE@λ", "go to"),
    bind(&[Char('a')], Action::MarkA, "mark A here", "mark A"),
    bind(&[Char('b')], Action::MarkB, "mark B: paths or closest", "mark B"),
    bind(&[Char('c')], Action::ClearMarks, "clear marks A, B", ""),
    bind(&[Char('1')], Action::FollowArc1, "follow path 1, A to B", ""),
    bind(&[Char('2')], Action::FollowArc2, "follow path 2, A to B", ""),
    bind(&[Code(KeyCode::Esc)], Action::FollowComponent, "whole component; close help", ""),
    bind(&[Char('t')], Action::ToggleTraces, "traces on / off", "traces"),
    bind(&[Char('j')], Action::NextJoint, "select next joint", ""),
    bind(&[Char('J')], Action::ToggleJointTrace, "trace / untrace that joint", ""),
    bind(&[Char('v')], Action::SwitchView, "linkage / Cayley curve", "view"),
    bind(&[Char('r')], Action::RotateLeft, "rotate curve left", ""),
    bind(&[Char('R')], Action::RotateRight, "rotate curve right", ""),
    bind(&[Char('e')], Action::TiltUp, "tilt curve up", ""),
    bind(&[Char('E')], Action::TiltDown, "tilt curve down", ""),
    bind(&[Char('x')], Action::NextAxes, "next curve axes (CCV)", ""),
    bind(&[Char('+'), Char('=')], Action::StepBigger, "double the step", ""),
    bind(&[Char('-')], Action::StepSmaller, "halve the step", ""),
    bind(&[Char('0'), Char('d')], Action::Reset, "reset to drawn", ""),
    bind(&[Char('?')], Action::Help, "this help", "help"),
    bind(&[Char('q'), Ctrl('c')], Action::Quit, "quit", "quit"),
];

/// The action for a key press, if any.
pub fn action_for(ev: &KeyEvent) -> Option<Action> {
    BINDINGS.iter().find(|b| b.keys.iter().any(|k| k.matches(ev))).map(|b| b.action)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(code: KeyCode) -> KeyEvent {
        KeyEvent::new(code, KeyModifiers::NONE)
    }

    #[test]
    fn keys_map_to_their_actions() {
        assert_eq!(action_for(&key(KeyCode::Right)), Some(Action::StepForward));
        assert_eq!(action_for(&key(KeyCode::Char('l'))), Some(Action::StepForward));
        assert_eq!(action_for(&key(KeyCode::Char('L'))), Some(Action::LargeForward));
        assert_eq!(action_for(&key(KeyCode::Char(']'))), Some(Action::NextEndpoint));
        assert_eq!(action_for(&key(KeyCode::Char('q'))), Some(Action::Quit));
        assert_eq!(action_for(&KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL)), Some(Action::Quit));
        assert_eq!(action_for(&key(KeyCode::Char('c'))), Some(Action::ClearMarks));
        assert_eq!(action_for(&key(KeyCode::Char('Z'))), None);
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
        }
    }

    #[test]
    fn every_action_has_a_key_and_one_row() {
        for (i, &a) in Action::ALL.iter().enumerate() {
            assert_eq!(ordinal(a), i, "Action::ALL out of order at {a:?}");
            let rows: Vec<&Binding> = BINDINGS.iter().filter(|b| b.action == a).collect();
            assert_eq!(rows.len(), 1, "{a:?} has {} rows in the key table", rows.len());
            assert!(!rows[0].keys.is_empty(), "{a:?} has no key");
            // And its keys reach it.
            for k in rows[0].keys {
                assert_eq!(action_for(&k.event()), Some(a), "{k:?}");
            }
        }
        assert_eq!(BINDINGS.len(), Action::ALL.len());
    }

    #[test]
    fn no_key_is_bound_twice() {
        // Compared as key presses, so `Char('c')` and `Code(KeyCode::Char('c'))` would collide too.
        for b in BINDINGS {
            for k in b.keys {
                let ev = k.event();
                let matching: Vec<Action> = BINDINGS
                    .iter()
                    .flat_map(|b2| b2.keys.iter().filter(|k2| k2.matches(&ev)).map(|_| b2.action))
                    .collect();
                assert_eq!(matching, vec![b.action], "{} is bound to {matching:?}", k.name());
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
        assert!(BINDINGS.iter().any(|b| b.action == Action::Quit && !b.bar.is_empty()));
        assert!(BINDINGS.iter().any(|b| b.action == Action::Help && !b.bar.is_empty()));
    }
}
