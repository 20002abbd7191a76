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

/// A key as written in the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    Char(char),
    Ctrl(char),
    Code(KeyCode),
}

impl Key {
    fn matches(self, ev: &KeyEvent) -> bool {
        let ctrl = ev.modifiers.contains(KeyModifiers::CONTROL);
        match self {
            Key::Char(c) => !ctrl && ev.code == KeyCode::Char(c),
            Key::Ctrl(c) => ctrl && ev.code == KeyCode::Char(c),
            Key::Code(code) => ev.code == code,
        }
    }
}

/// One row of the table: the keys, how the key bar and help show them, the action.
#[derive(Clone, Copy, Debug)]
pub struct Binding {
    pub keys: &'static [Key],
    pub label: &'static str,
    pub action: Action,
    pub help: &'static str,
    /// The word shown in the key bar at the bottom; empty: only in the help overlay.
    pub bar: &'static str,
}

const fn bind(
    keys: &'static [Key],
    label: &'static str,
    action: Action,
    help: &'static str,
    bar: &'static str,
) -> Binding {
    Binding { keys, label, action, help, bar }
}

use Key::{Char, Code, Ctrl};

/// The whole table, in the order the help overlay lists it.
pub const BINDINGS: &[Binding] = &[
    bind(&[Code(KeyCode::Right), Char('l')], "→/l", Action::StepForward, "step forward (geometric)", "step"),
    bind(&[Code(KeyCode::Left), Char('h')], "←/h", Action::StepBack, "step back", ""),
    bind(&[Char('L'), Code(KeyCode::PageDown)], "L/PgDn", Action::LargeForward, "large step forward", ""),
    bind(&[Char('H'), Code(KeyCode::PageUp)], "H/PgUp", Action::LargeBack, "large step back", ""),
    bind(&[Char(']')], "]", Action::NextEndpoint, "next interval endpoint", "endpoint"),
    bind(&[Char('[')], "[", Action::PrevEndpoint, "previous interval endpoint", ""),
    bind(&[Char(' ')], "space", Action::PlayPause, "play / pause", "play"),
    bind(&[Char('n'), Code(KeyCode::Tab)], "n", Action::NextComponent, "next component", "component"),
    bind(&[Char('p'), Code(KeyCode::BackTab)], "p", Action::PrevComponent, "previous component", ""),
    bind(&[Char('g')], "g", Action::GoTo, "go to λ or TYPE@λ", "go to"),
    bind(&[Char('a')], "a", Action::MarkA, "mark A here", "mark A"),
    bind(&[Char('b')], "b", Action::MarkB, "mark B: paths or closest", "mark B"),
    bind(&[Char('c')], "c", Action::ClearMarks, "clear marks A, B", ""),
    bind(&[Char('1')], "1", Action::FollowArc1, "follow path 1, A to B", ""),
    bind(&[Char('2')], "2", Action::FollowArc2, "follow path 2, A to B", ""),
    bind(&[Code(KeyCode::Esc)], "Esc", Action::FollowComponent, "whole component; close help", ""),
    bind(&[Char('t')], "t", Action::ToggleTraces, "traces on / off", "traces"),
    bind(&[Char('j')], "j", Action::NextJoint, "select next joint", ""),
    bind(&[Char('J')], "J", Action::ToggleJointTrace, "trace / untrace that joint", ""),
    bind(&[Char('v')], "v", Action::SwitchView, "linkage / Cayley curve", "view"),
    bind(&[Char('r')], "r", Action::RotateLeft, "rotate curve left", ""),
    bind(&[Char('R')], "R", Action::RotateRight, "rotate curve right", ""),
    bind(&[Char('e')], "e", Action::TiltUp, "tilt curve up", ""),
    bind(&[Char('E')], "E", Action::TiltDown, "tilt curve down", ""),
    bind(&[Char('x')], "x", Action::NextAxes, "next curve axes (CCV)", ""),
    bind(&[Char('+'), Char('=')], "+", Action::StepBigger, "double the step", ""),
    bind(&[Char('-')], "-", Action::StepSmaller, "halve the step", ""),
    bind(&[Char('0'), Char('d')], "0/d", Action::Reset, "reset to drawn", ""),
    bind(&[Char('?')], "?", Action::Help, "this help", "help"),
    bind(&[Char('q'), Ctrl('c')], "q", Action::Quit, "quit (also Ctrl-C)", "quit"),
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

    #[test]
    fn no_key_is_bound_twice_and_every_action_has_a_key() {
        let mut seen = Vec::new();
        for b in BINDINGS {
            for k in b.keys {
                assert!(!seen.contains(k), "{k:?} bound twice");
                seen.push(*k);
            }
            assert!(!b.help.is_empty() && !b.label.is_empty());
        }
        assert!(BINDINGS.iter().any(|b| b.action == Action::Quit && !b.bar.is_empty()));
        assert!(BINDINGS.iter().any(|b| b.action == Action::Help && !b.bar.is_empty()));
    }
}
