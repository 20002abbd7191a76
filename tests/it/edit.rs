//! Issue 13: editing a scene in the TUI (select, move, lengths, undo/redo,
//! save keeping comments) and reloading it when its file changes; checked
//! against the four-bar's closed-form Cayley space (THEORY.md §7).

use caymos::scene::load_scene;
use caymos::tui::app::{App, Screen};
use caymos::tui::edit::Item;
use caymos::tui::settle;
use caymos::tui::theme::Theme;

use crate::helpers::scratch;
use crate::tui::{app, press, render, spawn_in_pty, type_and_expect_clean_exit};

/// The four-bar A-B-C-D on the base A–C: every type has the one interval
/// [max(|AB−BC|, |DA−CD|), min(AB+BC, DA+CD)] (THEORY.md §7).
fn four_bar_space(ab: f64, bc: f64, cd: f64, da: f64) -> [f64; 2] {
    [(ab - bc).abs().max((da - cd).abs()), (ab + bc).min(da + cd)]
}

/// The union of the Cayley space on screen.
fn union(a: &App) -> Vec<[f64; 2]> {
    a.model().unwrap_or_else(|| panic!("explorable; message {:?}", a.message)).solved().union.clone()
}

fn assert_space(a: &App, want: [f64; 2]) {
    let u = union(a);
    assert_eq!(u.len(), 1, "{u:?}");
    for k in 0..2 {
        assert!((u[0][k] - want[k]).abs() <= 1e-12 * want[1], "{u:?} vs the closed form {want:?}");
    }
}

/// Replace the selection's value by typing it at the `=` prompt (which starts with the current value).
fn type_value(a: &mut App, value: &str) {
    press(a, &format!("={}{value}⏎", "⌫".repeat(60)));
}

/// The crank-rocker's text with BC = `bc` (the bundled file, comments and all).
fn crank_rocker_with_bc(bc: &str) -> String {
    let text = caymos::bundled::find("fourbar-crank-rocker").unwrap().text;
    assert!(text.contains("[\"B\", \"C\", 4.0]"));
    text.replace("[\"B\", \"C\", 4.0]", &format!("[\"B\", \"C\", {bc}]"))
}

#[test]
fn a_typed_or_nudged_bar_length_changes_the_space_as_the_closed_form_says() {
    let mut a = app("fourbar-crank-rocker");
    assert_space(&a, four_bar_space(1.0, 4.0, 3.0, 3.5));
    press(&mut a, "m/B-C⏎");
    assert_eq!(a.item(), Item::Bar(1), "{:?}", a.message);
    for bc in [4.5, 3.2, 5.9, 4.0] {
        let before = a.model().unwrap().current();
        type_value(&mut a, &bc.to_string());
        let want = four_bar_space(1.0, bc, 3.0, 3.5);
        assert_space(&a, want);
        assert_eq!(a.doc.scene.bars[1].length, Some(bc));
        // The cursor keeps the type, at the nearest λ it still reaches.
        let m = a.model().unwrap();
        let here = m.current();
        assert_eq!(here.ty, before.ty, "BC = {bc}");
        let u = union(&a)[0];
        assert_eq!(here.lambda, before.lambda.clamp(u[0], u[1]), "BC = {bc}");
        if here.lambda != before.lambda {
            let note = a.message.as_deref().unwrap_or("");
            assert!(note.contains("no longer reached") && note.contains(&here.ty.to_string()), "{note}");
        }
    }
    // Nudges: the fine and coarse steps are powers of ten of the drawing (its diagonal is 4.8).
    assert_eq!(a.editor.steps, [0.01, 0.1]);
    press(&mut a, "+");
    assert_space(&a, four_bar_space(1.0, 4.01, 3.0, 3.5));
    press(&mut a, ">--");
    assert_space(&a, four_bar_space(1.0, 4.09, 3.0, 3.5));
    assert!(a.doc.text().contains("[\"B\", \"C\", 4.09]"), "short decimals in the file: {}", a.doc.text());
    // A length that cannot be is refused, and nothing changes.
    let text = a.doc.text();
    type_value(&mut a, "-2");
    assert!(a.message.as_deref().unwrap_or("").contains("positive"), "{:?}", a.message);
    assert_eq!(a.doc.text(), text);
}

#[test]
fn moving_a_joint_changes_the_drawn_lengths_and_the_space_follows() {
    // A four-bar of drawn lengths: AB = 1, BC = 4, CD = 3, DA = 3.5 as drawn.
    let text = "base = [\"A\", \"C\"]\nbars = [[\"A\", \"B\"], [\"B\", \"C\"], [\"C\", \"D\"], [\"D\", \"A\"]]\n\n\
                [joints]\nA = [0, 0]\nD = [3.5, 0]\nB = [0, 1]\nC = [3.5, 3]\n";
    let scene = caymos::scene::parse_scene(text, "drawn", "drawn").unwrap();
    let mut a = App::ready(caymos::analysis::analyse(scene, None).unwrap());
    let bc = |x: f64, y: f64| (x - 0.0f64).hypot(y - 1.0);
    assert_space(&a, four_bar_space(1.0, bc(3.5, 3.0), 3.0, 3.5));
    // C moves up by the coarse step, then left by two fine ones: CD and BC change.
    press(&mut a, "m/C⏎⇒");
    assert_eq!(a.doc.scene.joints[3].pos, [3.6, 3.0]);
    press(&mut a, "K←←");
    assert_eq!(a.doc.scene.joints[3].pos, [3.58, 3.1]);
    let (x, y) = (3.58, 3.1);
    let cd = (x - 3.5f64).hypot(y);
    assert_space(&a, four_bar_space(1.0, bc(x, y), cd, 3.5));
    // Exact coordinates typed.
    type_value(&mut a, "3.5, 3.25");
    assert_eq!(a.doc.scene.joints[3].pos, [3.5, 3.25]);
    assert_space(&a, four_bar_space(1.0, bc(3.5, 3.25), 3.25, 3.5));
    // A bar selected: arrows say how to move a joint instead.
    press(&mut a, "/A-B⏎→");
    assert!(a.message.as_deref().unwrap().contains("a bar is selected"), "{:?}", a.message);
}

#[test]
fn undo_restores_the_scene_bit_for_bit_and_redo_reapplies() {
    let mut a = app("fourbar-crank-rocker");
    let (scene0, text0) = (a.doc.scene.clone(), a.doc.text());
    let space0 = a.model().unwrap().solved().space.intervals.clone();
    press(&mut a, "m/C⏎→→⇒↑/B-C⏎+>");
    type_value(&mut a, "3.7");
    assert_eq!(a.editor.depth(), (7, 0));
    let (scene1, text1) = (a.doc.scene.clone(), a.doc.text());
    assert_ne!(scene1, scene0);
    press(&mut a, "uuuuuuu");
    assert_eq!(a.doc.scene, scene0, "the scene is bit-identical");
    assert_eq!(a.doc.text(), text0);
    let space = &a.model().unwrap().solved().space.intervals;
    assert_eq!(space.len(), space0.len());
    for (i, j) in space.iter().zip(&space0) {
        assert_eq!(
            (i.ty.clone(), i.lower.lambda.to_bits(), i.upper.lambda.to_bits()),
            (j.ty.clone(), j.lower.lambda.to_bits(), j.upper.lambda.to_bits())
        );
    }
    press(&mut a, "u");
    assert_eq!(a.message.as_deref(), Some("nothing to undo"));
    press(&mut a, "UUUUUUU");
    assert_eq!((a.doc.scene.clone(), a.doc.text()), (scene1, text1));
    assert_space(&a, four_bar_space(1.0, 3.7, 3.0, 3.5));
}

#[test]
fn an_edit_that_leaves_the_class_shows_why_with_the_drawing_and_undo_returns() {
    let mut a = app("fourbar-crank-rocker");
    let scene0 = a.doc.scene.clone();
    let space0 = union(&a);
    press(&mut a, "m/C-D⏎X");
    let Screen::Outside { why, .. } = &a.screen else { panic!("outside the class: {:?}", a.message) };
    assert!(why.contains("2 degrees of freedom"), "{why}");
    let screen = format!("{}", render(&a, 80, 24, Theme { color: false }).backend());
    assert!(screen.contains("outside the class") && screen.contains("degrees of freedom"), "{screen}");
    assert!(screen.contains("⠤⠤⠤") && screen.contains(" D "), "the drawing, the ground and the joints: {screen}");
    // Edits still work there, and undo comes back.
    press(&mut a, "/A⏎→u");
    assert!(matches!(a.screen, Screen::Outside { .. }));
    press(&mut a, "u");
    assert_eq!(a.doc.scene, scene0);
    assert_eq!(union(&a), space0);
    // A rigid one: a fifth bar across the base.
    let text =
        crank_rocker_with_bc("4.0").replace("  [\"D\", \"A\", 3.5],", "  [\"D\", \"A\", 3.5],\n  [\"B\", \"D\"],");
    let dir = scratch("edit-rigid");
    std::fs::write(dir.join("r.toml"), &text).unwrap();
    let mut r = App::new(load_scene(&dir.join("r.toml")).unwrap(), None);
    settle(&mut r);
    let Screen::Outside { why, .. } = &r.screen else { panic!("rigid") };
    assert!(why.contains("rigid"), "{why}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn save_keeps_the_comments_and_a_reload_round_trips() {
    let dir = scratch("edit-save");
    let path = dir.join("crank.toml");
    std::fs::write(&path, crank_rocker_with_bc("4.0")).unwrap();
    let mut a = App::new(load_scene(&path).unwrap(), None);
    settle(&mut a);
    press(&mut a, "m/B-C⏎");
    type_value(&mut a, "4.5");
    assert!(a.doc.modified());
    press(&mut a, "w");
    assert!(a.message.as_deref().unwrap().starts_with("saved"), "{:?}", a.message);
    let saved = std::fs::read_to_string(&path).unwrap();
    assert_eq!(saved, crank_rocker_with_bc("4.5"), "only the number changed; comments and layout kept");
    assert!(saved.contains("# AB = 1, BC = 4, CD = 3, DA = 3.5"));
    assert_eq!(load_scene(&path).unwrap(), a.doc.scene, "the file reads back as the scene");
    assert!(!a.doc.modified());
    // Our own save is not a reload.
    assert!(!a.check_file());
    // Someone edits the file: it is reloaded, the realization kept.
    let before = a.model().unwrap().current();
    std::fs::write(&path, crank_rocker_with_bc("3.25")).unwrap();
    assert!(a.check_file());
    settle(&mut a);
    assert!(
        a.message.as_deref().unwrap_or("").contains("reloaded") || a.message.as_deref().unwrap_or("").contains("λ")
    );
    assert_space(&a, four_bar_space(1.0, 3.25, 3.0, 3.5));
    assert_eq!(a.model().unwrap().current().ty, before.ty);
    assert_eq!(a.doc.text(), crank_rocker_with_bc("3.25"));
    // A broken edit: the error with file:line:col, the last analysis stays.
    let broken = crank_rocker_with_bc("3.25").replace("[\"C\", \"D\", 3.0],", "[\"C\", \"D\" 3.0],");
    std::fs::write(&path, &broken).unwrap();
    assert!(a.check_file());
    settle(&mut a);
    let error = a.file_error.clone().expect("the parse error is shown");
    let line = broken.lines().position(|l| l.contains("[\"C\", \"D\" 3.0],")).unwrap() + 1;
    assert!(error.starts_with(&format!("{}:{line}:", path.display())), "{error}");
    assert_space(&a, four_bar_space(1.0, 3.25, 3.0, 3.5));
    let screen = format!("{}", render(&a, 80, 24, Theme { color: false }).backend());
    assert!(screen.contains("crank.toml:"), "{screen}");
    // Fixed: taken, the error gone; undo goes back through the reloads.
    std::fs::write(&path, crank_rocker_with_bc("4.25")).unwrap();
    assert!(a.check_file());
    settle(&mut a);
    assert!(a.file_error.is_none());
    assert_space(&a, four_bar_space(1.0, 4.25, 3.0, 3.5));
    press(&mut a, "u");
    assert_space(&a, four_bar_space(1.0, 3.25, 3.0, 3.5));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_bundled_scene_saves_to_a_new_file_named_after_it() {
    let dir = scratch("edit-bundled");
    let mut a = app("fourbar-crank-rocker");
    a.save_dir = dir.clone();
    assert!(a.doc.path.is_none());
    press(&mut a, "m/B-C⏎+w");
    let path = dir.join("fourbar-crank-rocker.toml");
    assert!(a.message.as_deref().unwrap().contains(&path.display().to_string()), "{:?}", a.message);
    assert_eq!(std::fs::read_to_string(&path).unwrap(), crank_rocker_with_bc("4.01"));
    assert_eq!(a.doc.path.as_deref(), Some(path.as_path()));
    // From now on it is that file: saved there again, and watched.
    press(&mut a, "+w");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), crank_rocker_with_bc("4.02"));
    assert!(!dir.join("fourbar-crank-rocker-2.toml").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn snapshot_edit_mode_80x24() {
    let mut a = app("fourbar-crank-rocker");
    press(&mut a, "m/C⏎→");
    insta::assert_snapshot!("edit_mode_80x24", render(&a, 80, 24, Theme { color: false }).backend());
}

/// The real binary on a scene file: an edit of the file is picked up (the
/// file is polled every 250 ms), a broken edit shows the parse error and the
/// TUI keeps running, a fixed edit recovers.
#[test]
fn the_tui_reloads_its_file_and_survives_a_broken_edit_in_a_pseudo_terminal() {
    use std::io::Write;
    use std::time::{Duration, Instant};

    let dir = scratch("edit-pty");
    let path = dir.join("s.toml");
    std::fs::write(&path, crank_rocker_with_bc("4.0")).unwrap();
    let (_master, mut child, mut writer, rx) = spawn_in_pty(path.to_str().unwrap());
    let mut parser = vt100::Parser::new(24, 80, 0);
    let wait_for = |parser: &mut vt100::Parser, what: &str, pred: &dyn Fn(&str) -> bool| -> String {
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            while let Ok(bytes) = rx.try_recv() {
                parser.process(&bytes);
            }
            let screen = parser.screen().contents();
            if pred(&screen) {
                return screen;
            }
            assert!(Instant::now() < deadline, "timed out waiting for {what}; screen:\n{screen}");
            std::thread::sleep(Duration::from_millis(20));
        }
    };
    wait_for(&mut parser, "the first analysis", &|s| s.contains("λ from 3 to 5"));
    std::fs::write(&path, crank_rocker_with_bc("4.5")).unwrap();
    wait_for(&mut parser, "the reload", &|s| s.contains("λ from 3.5 to 5.5"));
    std::fs::write(&path, crank_rocker_with_bc("4.5").replace("[\"C\", \"D\", 3.0],", "[\"C\", \"D\" 3.0],")).unwrap();
    let screen = wait_for(&mut parser, "the parse error", &|s| s.contains("s.toml:"));
    assert!(screen.contains("TOML syntax error") && screen.contains("λ from 3.5 to 5.5"), "{screen}");
    // Still running: keys work.
    writer.write_all(b"]").unwrap();
    writer.flush().unwrap();
    std::fs::write(&path, crank_rocker_with_bc("3.25")).unwrap();
    let screen = wait_for(&mut parser, "the recovery", &|s| s.contains("λ from 2.25 to 4.25"));
    assert!(!screen.contains("TOML syntax error"), "{screen}");
    type_and_expect_clean_exit(b"q", &mut *child, &mut *writer, &rx, &mut parser);
    std::fs::remove_dir_all(&dir).ok();
}
