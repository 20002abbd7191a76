//! Issue 13: the sweep in the TUI (`s` sweeps the selected bar or joint, `S`
//! shows or hides it) is `caymos sweep`'s, swept again after every edit, so
//! the transitions move as the closed form says (Grashof: s + l = p + q).

use caymos::sweep::Change;
use caymos::tui::app::{App, PromptKind};
use caymos::tui::sweep::Swept;
use caymos::tui::theme::Theme;

use crate::tui::{app, press, render};

/// The transitions of the sweep on screen, with their changes.
fn transitions(a: &App) -> Vec<(f64, Vec<Change>)> {
    let s = a.sweep.as_ref().expect("a sweep was asked for");
    assert!(!s.pending, "settled");
    let r = s.report.as_ref().unwrap_or_else(|| panic!("a report; error {:?}, message {:?}", s.error, a.message));
    r.transitions.iter().map(|t| (t.value, t.changes.clone())).collect()
}

/// Sweep the selected item over the typed range (the prompt starts filled with a default).
fn sweep(a: &mut App, range: &str) {
    press(a, &format!("s{}{range}⏎", "⌫".repeat(60)));
}

/// The crank-rocker with bar A–B selected for editing.
fn crank_rocker_on_ab() -> App {
    let mut a = app("fourbar-crank-rocker");
    press(&mut a, "m/A-B⏎");
    a
}

#[test]
fn sweeping_the_crank_finds_the_grashof_transition_and_follows_an_edit() {
    let mut a = crank_rocker_on_ab();
    sweep(&mut a, "0.5 3 26");
    let t = transitions(&a);
    // BC = 4, CD = 3, DA = 3.5: AB + BC = CD + DA at AB = 2.5, from 2 components to 1.
    assert_eq!(t.len(), 1, "{t:?}");
    assert!((t[0].0 - 2.5).abs() <= 1e-12, "{t:?}");
    assert!(t[0].1.contains(&Change::Components { from: 2, to: 1 }), "{t:?}");
    assert!(a.sweep.as_ref().unwrap().shown);
    // Lengthen BC to 4.5: the sweep is run again and the transition moves to AB = 2.
    press(&mut a, "/B-C⏎");
    press(&mut a, &format!("={}4.5⏎", "⌫".repeat(30)));
    let t = transitions(&a);
    assert_eq!(t.len(), 1, "{t:?}");
    assert!((t[0].0 - 2.0).abs() <= 1e-12, "{t:?}");
    // Undo: back to 2.5.
    press(&mut a, "u");
    assert!((transitions(&a)[0].0 - 2.5).abs() <= 1e-12);
    // S hides and shows it; the drawing is back in between.
    press(&mut a, "S");
    assert!(!a.sweep.as_ref().unwrap().shown);
    press(&mut a, "S");
    assert!(a.sweep.as_ref().unwrap().shown);
}

#[test]
fn the_default_range_is_all_a_bar_can_span() {
    // (0, Σ other bars]: BC + CD + DA = 10.5 for AB, sampled from 10.5/60.
    let mut a = crank_rocker_on_ab();
    press(&mut a, "s");
    assert_eq!(a.input.as_ref().unwrap().text, "0.175 10.5 60");
    press(&mut a, "⏎");
    let s = a.sweep.as_ref().unwrap();
    assert_eq!((s.from, s.to, s.steps), (0.175, 10.5, 60));
    // The Grashof equalities with BC = 4, CD = 3, DA = 3.5 (AB + BC = CD + DA,
    // AB + DA = BC + CD, AB + CD = BC + DA), and AB = BC + CD + DA, where it stops closing.
    let found: Vec<f64> = transitions(&a).iter().map(|t| t.0).collect();
    assert_eq!(found.len(), 4, "{found:?}");
    for (x, want) in found.iter().zip([2.5, 3.5, 4.5, 10.5]) {
        assert!((x - want).abs() <= 1e-12 * want, "{found:?}");
    }
}

#[test]
fn a_joint_sweeps_x_or_y_and_bad_ranges_say_why() {
    let mut a = app("fourbar-crank-rocker");
    press(&mut a, "m/C⏎s");
    assert!(a.input.as_ref().unwrap().text.starts_with("x "), "{:?}", a.input);
    sweep(&mut a, "y 0 4 12");
    let s = a.sweep.as_ref().unwrap();
    assert_eq!(s.swept, caymos::tui::sweep::Swept::Joint { joint: 2, axis: 1 });
    assert!(s.report.is_some());
    for (typed, why) in
        [("3 1", "must be below"), ("1 two", "not a number"), ("1", "FROM TO"), ("1 2 1", "steps 1: give 2 to")]
    {
        sweep(&mut a, typed);
        let m = a.message.clone().unwrap_or_default();
        assert!(m.contains(why) && !m.contains("--"), "{typed:?}: {m:?} (in words, not flags)");
    }
    // The last good sweep stays.
    assert_eq!(a.sweep.as_ref().unwrap().steps, 12);
}

#[test]
fn exploring_without_a_bar_says_what_to_do_and_a_deleted_bar_is_said_gone() {
    let mut a = app("fourbar-crank-rocker");
    press(&mut a, "s");
    assert!(a.input.is_none());
    assert!(a.message.as_deref().unwrap_or_default().contains("edit mode"), "{:?}", a.message);
    // With an input bar chosen (i), s sweeps it.
    press(&mut a, "i");
    press(&mut a, "s");
    let bar = a.model().unwrap().drive.input.expect("an input bar");
    match a.input.as_ref().map(|p| p.kind) {
        Some(PromptKind::Sweep(Swept::Bar(ends))) => assert_eq!(ends, [bar.pivot, bar.tip]),
        other => panic!("a sweep prompt for the input bar, not {other:?}; {:?}", a.message),
    }
    press(&mut a, "⎋");
    // Delete the swept bar: the sweep says it is gone; undo brings it back.
    let mut a = crank_rocker_on_ab();
    sweep(&mut a, "0.5 3 8");
    press(&mut a, "⌦");
    let s = a.sweep.as_ref().unwrap();
    assert!(s.error.as_deref().unwrap_or_default().contains("gone"), "{:?}", s.error);
    press(&mut a, "u");
    assert!(a.sweep.as_ref().unwrap().error.is_none());
    assert_eq!(transitions(&a).len(), 1);
}

#[test]
fn snapshot_sweep_80x24() {
    let mut a = crank_rocker_on_ab();
    sweep(&mut a, "0.5 3 26");
    insta::assert_snapshot!("sweep_crank_rocker_80x24", render(&a, 80, 24, Theme { color: false }).backend());
}

/// The real binary in a pseudo-terminal: the sweep runs on its own solver
/// thread and shows; an edit while it shows is analysed and swept again.
#[test]
fn a_sweep_in_a_pseudo_terminal() {
    use crate::tui::{spawn_in_pty, type_and_expect_clean_exit};
    use std::io::Write;
    use std::time::{Duration, Instant};

    let (_master, mut child, mut writer, rx) = spawn_in_pty("fourbar-crank-rocker");
    let mut parser = vt100::Parser::new(24, 80, 0);
    let mut wait_for = |writer: &mut Box<dyn Write + Send>, keys: &[u8], want: &str| {
        writer.write_all(keys).unwrap();
        writer.flush().unwrap();
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            while let Ok(bytes) = rx.try_recv() {
                parser.process(&bytes);
            }
            let screen = parser.screen().contents();
            if screen.contains(want) {
                return;
            }
            assert!(Instant::now() < deadline, "timed out waiting for {want:?}; screen:\n{screen}");
            std::thread::sleep(Duration::from_millis(20));
        }
    };
    wait_for(&mut writer, b"", "realization");
    wait_for(&mut writer, b"m/A-B\r", "selected bar A");
    let clear = "\x7f".repeat(30);
    wait_for(&mut writer, format!("s{clear}0.5 3 26\r").as_bytes(), "A–B = 2.5: components 2 → 1");
    // BC = 4.5: the transition moves to AB = 2 (AB + BC = CD + DA).
    wait_for(&mut writer, format!("/B-C\r={clear}4.5\r").as_bytes(), "A–B = 2: components 2 → 1");
    type_and_expect_clean_exit(b"q", &mut *child, &mut *writer, &rx, &mut parser);
}

/// Scaling the scene scales the sweep: the Grashof transition of the
/// crank-rocker lands at 2.5 × the factor, at 1e±150 as at 1.
#[test]
fn a_sweep_scales_with_the_scene() {
    for factor in [1e-150, 1e150] {
        let mut scene = caymos::bundled::load("fourbar-crank-rocker").unwrap();
        for j in &mut scene.joints {
            j.pos = j.pos.map(|x| x * factor);
        }
        for b in &mut scene.bars {
            b.length = b.length.map(|l| l * factor);
        }
        // Through the file format, so the lengths are read as written.
        let text = caymos::generate::to_toml(&scene);
        let scene = caymos::scene::parse_scene(&text, "scaled", "scaled.toml").unwrap();
        let mut a = App::ready(caymos::analysis::analyse(scene, None).unwrap());
        press(&mut a, "m/A-B⏎");
        // The default range scales too: (0, Σ other bars] = (0, 10.5 × factor].
        press(&mut a, "s");
        let typed = a.input.as_ref().unwrap().text.clone();
        let words: Vec<f64> = typed.split(' ').map(|w| w.parse().unwrap()).collect();
        assert!((words[1] / (10.5 * factor) - 1.0).abs() <= 1e-5, "{typed}");
        press(&mut a, "⎋");
        sweep(&mut a, &format!("{:e} {:e} 26", 0.5 * factor, 3.0 * factor));
        let t = transitions(&a);
        assert_eq!(t.len(), 1, "×{factor:e}: {t:?}");
        assert!((t[0].0 / (2.5 * factor) - 1.0).abs() <= 1e-12, "×{factor:e}: {t:?}");
        assert!(t[0].1.contains(&Change::Components { from: 2, to: 1 }), "{t:?}");
        let screen = format!("{}", render(&a, 80, 24, Theme { color: false }).backend());
        assert!(screen.contains("components 2 → 1"), "{screen}");
    }
}

/// Only the newest sweep's result is shown: an older one finishing late is dropped.
#[test]
fn a_late_result_of_an_older_sweep_is_dropped() {
    let mut a = crank_rocker_on_ab();
    // Ask for two sweeps without running them (keys only, no settle), then finish them out of order.
    use caymos::tui::handle_key;
    use ratatui::crossterm::event::{KeyCode, KeyEvent};
    handle_key(&mut a, KeyEvent::from(KeyCode::Char('s')));
    handle_key(&mut a, KeyEvent::from(KeyCode::Enter));
    let first = a.take_job().expect("the first sweep");
    handle_key(&mut a, KeyEvent::from(KeyCode::Char('s')));
    a.input.as_mut().unwrap().text = "0.5 3 26".into();
    handle_key(&mut a, KeyEvent::from(KeyCode::Enter));
    let second = a.take_job().expect("the second sweep");
    a.finish(first.run());
    let s = a.sweep.as_ref().unwrap();
    assert!(s.pending && s.report.is_none(), "the first sweep's result is not the second's");
    a.finish(second.run());
    assert_eq!(transitions(&a).len(), 1);
    assert_eq!(a.sweep.as_ref().unwrap().steps, 26);
}

/// The sweep follows what changes its answer: a new base, a new input bar,
/// an edit (only when shown: hidden, it waits until shown again).
#[test]
fn the_sweep_runs_again_on_a_new_base_or_input_bar_and_waits_while_hidden() {
    let mut a = crank_rocker_on_ab();
    sweep(&mut a, "0.5 3 8");
    let id = |a: &App| a.sweep.as_ref().unwrap().id;
    let first = id(&a);
    press(&mut a, "m"); // explore: B and i
    press(&mut a, "B");
    assert!(id(&a) > first, "a new base sweeps again");
    assert_eq!(transitions(&a).len(), 1, "the realization space, so the transition, does not depend on the base");
    let before = id(&a);
    press(&mut a, "i");
    assert!(id(&a) > before, "a new input bar sweeps again");
    let r = a.sweep.as_ref().unwrap().report.as_ref().unwrap();
    assert!(r.input_bar.is_some(), "its full turns are counted");
    // Hidden: an edit marks it stale and asks for nothing; shown, it runs.
    press(&mut a, "S");
    let hidden = id(&a);
    press(&mut a, &format!("m/B-C⏎={}4.5⏎", "⌫".repeat(30)));
    assert_eq!(id(&a), hidden);
    assert!(a.sweep.as_ref().unwrap().stale);
    press(&mut a, "S");
    assert!(id(&a) > hidden);
    assert!((transitions(&a)[0].0 - 2.0).abs() <= 1e-12);
}
