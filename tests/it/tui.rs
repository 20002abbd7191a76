//! Issue 5: the terminal UI. State tests drive the app with key presses and
//! no terminal; snapshots render whole screens on a TestBackend; one test
//! runs the real binary in a pseudo-terminal.

use caymos::analysis::analyse;
use caymos::bundled;
use caymos::tui::app::{App, Motion, View};
use caymos::tui::theme::Theme;
use caymos::tui::view;
use caymos::tui::{handle_key, settle};
use proptest::prelude::*;
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

pub fn app(scene: &str) -> App {
    App::ready(analyse(bundled::load(scene).unwrap(), None).unwrap())
}

/// Press keys, each written as its character or: → ← ↑ ↓ arrows, ⇒ Shift-→,
/// ⏎ Enter, ⎋ Esc, ⇥ Tab, ⇤ Shift-Tab, ⌫ Backspace, ⌦ Delete. The analyses
/// the keys ask for are run after each key, as the solver thread would.
pub fn press(app: &mut App, keys: &str) {
    for c in keys.chars() {
        let (code, mods) = match c {
            '→' => (KeyCode::Right, KeyModifiers::NONE),
            '←' => (KeyCode::Left, KeyModifiers::NONE),
            '↑' => (KeyCode::Up, KeyModifiers::NONE),
            '↓' => (KeyCode::Down, KeyModifiers::NONE),
            '⇒' => (KeyCode::Right, KeyModifiers::SHIFT),
            '⏎' => (KeyCode::Enter, KeyModifiers::NONE),
            '⎋' => (KeyCode::Esc, KeyModifiers::NONE),
            '⇥' => (KeyCode::Tab, KeyModifiers::NONE),
            '⇤' => (KeyCode::BackTab, KeyModifiers::SHIFT),
            '⌫' => (KeyCode::Backspace, KeyModifiers::NONE),
            '⌦' => (KeyCode::Delete, KeyModifiers::NONE),
            c => (KeyCode::Char(c), KeyModifiers::NONE),
        };
        handle_key(app, KeyEvent::new(code, mods));
        settle(app);
    }
}

fn lambda(app: &App) -> f64 {
    app.model().unwrap().cursor.lambda
}

fn ty(app: &App) -> String {
    app.model().unwrap().current().ty.to_string()
}

#[test]
fn starts_on_the_drawn_realization() {
    let a = app("jansen");
    let m = a.model().unwrap();
    assert_eq!(Some(m.cursor.component), m.solved().drawn_component);
    assert_eq!(m.cursor.lambda, m.solved().drawn.lambda);
    assert_eq!(ty(&a), m.solved().drawn.ty.to_string());
    assert!(!a.help && !a.quit);
}

#[test]
fn endpoint_jumps_turn_the_jansen_crank_flipping_one_bit_at_each_end() {
    let mut a = app("jansen");
    let op = (38.0f64 * 38.0 + 7.8 * 7.8).sqrt();
    let t0 = ty(&a);
    press(&mut a, "]");
    assert!((lambda(&a) - (op + 15.0)).abs() < 1e-9);
    assert_eq!(a.model().unwrap().flat_here(), &[0]);
    assert_eq!(ty(&a), t0, "the type changes only after the endpoint");
    press(&mut a, "]");
    assert!((lambda(&a) - (op - 15.0)).abs() < 1e-9);
    let t1 = ty(&a);
    assert_ne!(t1, t0);
    assert_eq!(
        t1.chars().skip(1).collect::<String>(),
        t0.chars().skip(1).collect::<String>(),
        "only the crank bit flips"
    );
    press(&mut a, "]");
    assert_eq!(ty(&a), t0);
    press(&mut a, "[[");
    assert!((lambda(&a) - (op + 15.0)).abs() < 1e-9);
}

#[test]
fn small_steps_move_no_joint_more_than_the_step() {
    let mut a = app("limacon");
    let step = a.model().unwrap().pace.step;
    for _ in 0..200 {
        let before = a.model().unwrap().cursor.positions.clone();
        press(&mut a, "→");
        let after = &a.model().unwrap().cursor.positions;
        let moved = before.iter().zip(after).map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1])).fold(0.0, f64::max);
        assert!(moved <= step * (1.0 + 1e-9) + 1e-9, "{moved} > {step}");
    }
    let l = lambda(&a);
    press(&mut a, "←");
    assert_ne!(lambda(&a), l);
}

#[test]
fn components_go_to_marks_paths_views_help_and_quit() {
    let mut a = app("jansen");
    let k0 = a.model().unwrap().cursor.component;
    press(&mut a, "n");
    assert_eq!(a.model().unwrap().cursor.component, (k0 + 1) % 6);
    press(&mut a, "pp");
    assert_eq!(a.model().unwrap().cursor.component, (k0 + 5) % 6);
    // Go to a realization, then a plain λ in the current motion.
    press(&mut a, "g-+--@30⏎");
    assert_eq!((ty(&a).as_str(), lambda(&a)), ("-+--", 30.0));
    press(&mut a, "g40⏎");
    assert_eq!(lambda(&a), 40.0);
    // A realization that does not exist is a message, not a crash.
    press(&mut a, "g--+-@24⏎");
    assert!(a.message.as_deref().unwrap_or("").contains("not realizable"), "{:?}", a.message);
    press(&mut a, "gnonsense⏎");
    assert!(a.message.is_some());
    // Marks in one component: two paths; follow one, then go back.
    press(&mut a, "0a]]b");
    let m = a.model().unwrap();
    let p = m.marks.path.as_ref().expect("path computed");
    assert!(p.same_component);
    assert!(a.message.as_deref().unwrap().contains("two paths"));
    press(&mut a, "1");
    assert_eq!(a.model().unwrap().cursor.motion, Motion::Path { arc: 0 });
    for _ in 0..400 {
        press(&mut a, "L");
    }
    assert!(a.message.as_deref().unwrap_or("").contains("end of the path"));
    press(&mut a, "⎋");
    assert!(matches!(a.model().unwrap().cursor.motion, Motion::Component(_)));
    // Marks in different components: the closest pair.
    press(&mut a, "ca0nb");
    let m = a.model().unwrap();
    assert!(!m.marks.path.as_ref().unwrap().same_component);
    assert!(a.message.as_deref().unwrap().contains("closest pair"));
    // Views, traces, help, quit.
    press(&mut a, "v");
    assert_eq!(a.model().unwrap().view, View::CayleyCurve);
    press(&mut a, "t");
    assert!(!a.model().unwrap().traces.on);
    press(&mut a, "?");
    assert!(a.help);
    press(&mut a, "⎋");
    assert!(!a.help);
    press(&mut a, " ");
    assert!(a.animating());
    let l = lambda(&a);
    a.tick();
    assert_ne!(lambda(&a), l);
    press(&mut a, "q");
    assert!(a.quit);
}

#[test]
fn a_scene_outside_the_class_is_shown_not_crashed_on() {
    let mut a = app("fig1c");
    assert!(a.model().is_none());
    press(&mut a, "]→ng1⏎abv?⎋");
    let mut t = Terminal::new(TestBackend::new(80, 24)).unwrap();
    t.draw(|f| view::draw(f, &a, Theme { color: false })).unwrap();
    let screen = format!("{}", t.backend());
    assert!(screen.contains("rigid"), "{screen}");
    press(&mut a, "q");
    assert!(a.quit);
}

/// Issue 10 item 1: a four-bar whose stated lengths cannot close.
fn no_realization_scene() -> caymos::scene::Scene {
    caymos::generate::four_bar(1.0, 10.0, 1.0, 1.0)
}

#[test]
fn a_scene_with_no_realization_opens_on_why_and_no_key_crashes_it() {
    let mut a = App::ready(analyse(no_realization_scene(), None).unwrap());
    assert!(a.model().is_none());
    assert!(matches!(a.screen, caymos::tui::app::Screen::Empty { .. }));
    press(&mut a, "]→←LHng1⏎abc12⎋tjJvrx+-0?⎋");
    let t = render(&a, 100, 30, Theme { color: false });
    let screen = format!("{}", t.backend());
    assert!(screen.contains("no realization"), "{screen}");
    // The two steps on the base A–C and the lengths that fail them.
    assert!(screen.contains("at least 9") && screen.contains("at most 2"), "{screen}");
    assert!(screen.contains("A–B  1 / "), "stated lengths listed: {screen}");
    press(&mut a, "q");
    assert!(a.quit);
}

#[test]
fn snapshot_no_realization_80x24() {
    let a = App::ready(analyse(no_realization_scene(), None).unwrap());
    insta::assert_snapshot!("no_realization_80x24", render(&a, 80, 24, Theme { color: false }).backend());
}

/// Issue 10 item 1: extreme coordinates (where an analysis may find no
/// component) open, draw and take keys without a panic, on either screen.
#[test]
fn extreme_scales_open_draw_and_take_keys() {
    for factor in [1e-320, 1e-200, 1e-100, 1e100, 1e130, 1e200, 1e307] {
        let mut scene = bundled::load("fourbar-crank-rocker").unwrap();
        for j in &mut scene.joints {
            j.pos = [j.pos[0] * factor, j.pos[1] * factor];
        }
        for b in &mut scene.bars {
            b.length = b.length.map(|l| l * factor);
        }
        let mut a = App::ready(analyse(scene, None).unwrap());
        for keys in ["", "]]→→LLn", "vrx", "g1⏎", "ab12⎋", "+-0"] {
            press(&mut a, keys);
            let screen = format!("{}", render(&a, 100, 30, Theme { color: true }).backend());
            assert!(screen.contains("realization"), "×{factor:e}: {screen}");
        }
    }
}

/// Issue 10 item 10: the λ readout has significant digits at any scale.
#[test]
fn the_readout_shows_significant_digits_at_tiny_scales() {
    let mut scene = bundled::load("fourbar-non-grashof").unwrap();
    for j in &mut scene.joints {
        j.pos = [j.pos[0] * 1e-20, j.pos[1] * 1e-20];
    }
    for b in &mut scene.bars {
        b.length = b.length.map(|l| l * 1e-20);
    }
    let a = App::ready(analyse(scene, None).unwrap());
    let lambda = a.model().expect("analysed").cursor.lambda;
    let screen = format!("{}", render(&a, 100, 30, Theme { color: false }).backend());
    let shown = caymos::report::fmt_sig(lambda, 8);
    assert!(shown.contains("e-20") && screen.contains(&shown), "{shown}: {screen}");
}

/// Issue 10 item 8: in a lazy analysis `n` walks the next component.
#[test]
fn next_component_walks_more_components_in_a_lazy_analysis() {
    let mut a = App::ready(analyse(caymos::generate::chain(17), None).unwrap());
    let m = a.model().unwrap();
    assert!(m.solved().lazy);
    assert_eq!(m.n_components(), 1);
    press(&mut a, "n");
    let m = a.model().unwrap();
    assert_eq!(m.n_components(), 2, "{:?}", a.message);
    assert_eq!(m.cursor.component, 1);
    let screen = format!("{}", render(&a, 100, 30, Theme { color: false }).backend());
    assert!(screen.contains("components (2 walked)") && screen.contains("lazy · n walks more"), "{screen}");
}

/// `r`/`R` turn the Cayley curve's camera, `e`/`E` tilt it (up to a limit),
/// `x` takes the next axes; the projected curve is remade in the update.
#[test]
fn camera_keys_turn_tilt_and_change_axes_and_the_curve_follows() {
    use caymos::tui::app::{CAMERA_MAX_PITCH, CAMERA_TURN};
    let mut a = app("jansen");
    press(&mut a, "v");
    let m = a.model().unwrap();
    let (cam, curve) = (m.camera, m.picture.curve.clone());
    assert!(curve.runs.iter().map(|(_, p)| p.len()).sum::<usize>() > 100, "the curve is sampled");
    press(&mut a, "r");
    let m = a.model().unwrap();
    assert!((m.camera.yaw - (cam.yaw - CAMERA_TURN)).abs() < 1e-15);
    assert_eq!(m.camera.pitch, cam.pitch);
    assert_ne!(m.picture.curve.runs, curve.runs, "the curve turned with the camera");
    press(&mut a, "R");
    let m = a.model().unwrap();
    assert!((m.camera.yaw - cam.yaw).abs() < 1e-15);
    assert_eq!(m.picture.curve.runs.len(), curve.runs.len());
    press(&mut a, "e");
    assert!((a.model().unwrap().camera.pitch - (cam.pitch + CAMERA_TURN)).abs() < 1e-15);
    press(&mut a, &"e".repeat(30));
    assert_eq!(a.model().unwrap().camera.pitch, CAMERA_MAX_PITCH, "the tilt stops at the limit");
    press(&mut a, &"E".repeat(60));
    assert_eq!(a.model().unwrap().camera.pitch, -CAMERA_MAX_PITCH);
    // Jansen's complete Cayley vector has more than three entries: x moves on.
    let n = a.model().unwrap().solved().complexity.ccv.len();
    assert!(n > 3, "{n}");
    press(&mut a, "x");
    let axes = a.model().unwrap().camera.axes;
    assert_ne!(axes, cam.axes, "x moves on from the minimal vector's axes");
    assert!(axes.iter().all(|&k| k < n));
    let screen = format!("{}", render(&a, 100, 30, Theme { color: false }).backend());
    let names = &a.model().unwrap().analysis().linkage;
    let ccv = &a.model().unwrap().solved().complexity.ccv;
    for k in axes {
        let name = names.pair_name(ccv[k]);
        assert!(screen.contains(&name), "the axis {name} is named: {screen}");
    }
}

/// Components and paths are numbered from 1 on screen, like `--arc 1|2`.
#[test]
fn components_are_numbered_from_one_on_screen() {
    let mut a = app("jansen");
    let k = a.model().unwrap().cursor.component;
    let screen = |a: &App| format!("{}", render(a, 100, 30, Theme { color: false }).backend());
    assert!(screen(&a).contains(&format!("component {} of 6", k + 1)), "{}", screen(&a));
    // Tab and Shift-Tab are n and p.
    handle_key(&mut a, KeyEvent::new(KeyCode::Tab, KeyModifiers::NONE));
    assert_eq!(a.model().unwrap().cursor.component, (k + 1) % 6);
    assert!(screen(&a).contains(&format!("component {} of 6", (k + 1) % 6 + 1)));
    handle_key(&mut a, KeyEvent::new(KeyCode::BackTab, KeyModifiers::SHIFT));
    assert_eq!(a.model().unwrap().cursor.component, k);
    // Walk to the first component: it is "1", never "0".
    for _ in 0..6 {
        if a.model().unwrap().cursor.component == 0 {
            break;
        }
        press(&mut a, "n");
    }
    let text = screen(&a);
    assert!(text.contains("component 1 of 6") && !text.contains("component 0"), "{text}");
    assert!(text.contains("▸ 1 "), "the list marks component 1: {text}");
    press(&mut a, "0a]]b1");
    assert!(screen(&a).contains("path 1 A→B"));
}

/// `j` selects the next joint, `J` traces or untraces it (and turns traces
/// on), `t` turns all traces off and on; the traces are made in the update.
#[test]
fn joint_and_trace_keys() {
    let mut a = app("jansen");
    let m = a.model().unwrap();
    let n = m.analysis().linkage.n_joints();
    let last = n - 1;
    assert_eq!(m.traces.selected, last);
    let traced: Vec<usize> = m.picture.traces.iter().map(|(j, _)| *j).collect();
    assert_eq!(traced, [last]);
    assert_eq!(m.picture.traces[0].1.len(), m.picture.samples.positions.len());
    press(&mut a, "j");
    assert_eq!(a.model().unwrap().traces.selected, 0, "j wraps to the first joint");
    press(&mut a, "J");
    let m = a.model().unwrap();
    assert!(m.traces.traced[0] && m.traces.on);
    assert_eq!(m.picture.traces.iter().map(|(j, _)| *j).collect::<Vec<_>>(), [0, last]);
    let status = format!("{}", render(&a, 100, 30, Theme { color: false }).backend());
    let names = &m.analysis().linkage.names;
    assert!(status.contains(&format!("traces on [{},{}]", names[0], names[last])), "{status}");
    press(&mut a, "t");
    assert!(!a.model().unwrap().traces.on && a.model().unwrap().picture.traces.is_empty());
    press(&mut a, "t");
    assert_eq!(a.model().unwrap().picture.traces.len(), 2);
    press(&mut a, "J");
    assert!(!a.model().unwrap().traces.traced[0]);
}

/// `+`/`=` double the step (up to the drawing's extent), `-` halves it
/// (down to a millionth of it) and both say the new step.
#[test]
fn step_keys_double_and_halve_within_limits() {
    let mut a = app("limacon");
    let pace = a.model().unwrap().pace;
    press(&mut a, "+");
    assert_eq!(a.model().unwrap().pace.step, pace.step * 2.0);
    assert!(a.message.as_deref().unwrap().starts_with("step "));
    press(&mut a, "=");
    assert_eq!(a.model().unwrap().pace.step, pace.step * 4.0);
    press(&mut a, "--");
    assert_eq!(a.model().unwrap().pace.step, pace.step);
    press(&mut a, &"+".repeat(40));
    assert_eq!(a.model().unwrap().pace.step, pace.extent);
    press(&mut a, &"-".repeat(80));
    assert_eq!(a.model().unwrap().pace.step, pace.extent * 1e-6);
}

/// `c` clears both marks and the path; `0` and `d` go back to the drawn
/// realization and stop playing.
#[test]
fn clear_and_reset_keys() {
    let mut a = app("jansen");
    let (drawn, k) = {
        let m = a.model().unwrap();
        (m.cursor.lambda, m.cursor.component)
    };
    press(&mut a, "a]]b");
    assert!(a.model().unwrap().marks.path.is_some());
    press(&mut a, "1c");
    let m = a.model().unwrap();
    assert!(m.marks.slots.iter().all(Option::is_none) && m.marks.path.is_none() && m.marks.arcs.is_none());
    assert_eq!(m.cursor.motion, Motion::Component(k), "c leaves the path for its component");
    assert!(press_and(&mut a, "2").is_some(), "no path to follow without marks");
    for reset in ["0", "d"] {
        press(&mut a, "n]→ ");
        assert!(a.animating());
        press(&mut a, reset);
        let m = a.model().unwrap();
        assert_eq!((m.cursor.lambda, m.cursor.component, a.animating()), (drawn, k, false), "{reset}");
    }
}

/// The message after `keys`.
fn press_and(a: &mut App, keys: &str) -> Option<String> {
    press(a, keys);
    a.message.clone()
}

/// The help overlay is the key table: every row of the mode's keys and help are on it.
#[test]
fn the_help_overlay_lists_every_binding() {
    use caymos::tui::keymap::{Mode, bindings};
    let mut a = app("jansen");
    for (keys, mode) in [("?", Mode::Explore), ("?m?", Mode::Edit)] {
        press(&mut a, keys);
        assert_eq!(a.mode(), mode);
        let screen = format!("{}", render(&a, 160, 48, Theme { color: false }).backend());
        for b in bindings(mode) {
            assert!(screen.contains(&format!(" {} ", b.label())) || screen.contains(&b.label()), "{}", b.label());
            assert!(screen.contains(b.help), "{}: {screen}", b.help);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Nothing a user types crashes the UI, drawing included.
    #[test]
    fn no_key_sequence_panics(keys in proptest::collection::vec(prop::sample::select(
        "→←↑↓⇒LH][{} nNpgabc12iI°B\u{238b}tjJvrReExq+-0d?@.,59⏎mmmmu/=X<>kKU⇥⇤⌫⌦sSfA".chars().collect::<Vec<_>>()), 1..60), scene in prop::sample::select(vec!["jansen", "peaucellier", "stephenson", "fourbar-crank-rocker"])) {
        let mut a = app(scene);
        let mut t = Terminal::new(TestBackend::new(80, 24)).unwrap();
        for c in keys {
            let s = c.to_string();
            press(&mut a, &s);
            a.tick();
            t.draw(|f| view::draw(f, &a, Theme { color: true })).unwrap();
            // Still a whole screen: the key bar (help first) is drawn, or the
            // help over it, saying how to close it.
            let bar = format!("{}", t.backend());
            prop_assert!(a.quit || bar.contains("? help") || (a.help && bar.contains("? closes")), "{bar}");
        }
    }
}

pub fn render(a: &App, w: u16, h: u16, theme: Theme) -> Terminal<TestBackend> {
    let mut t = Terminal::new(TestBackend::new(w, h)).unwrap();
    t.draw(|f| view::draw(f, a, theme)).unwrap();
    t
}

#[test]
fn snapshot_linkage_view_80x24() {
    let a = app("jansen");
    insta::assert_snapshot!("jansen_linkage_80x24", render(&a, 80, 24, Theme { color: true }).backend());
}

#[test]
fn snapshot_linkage_view_large_after_steps() {
    let mut a = app("limacon");
    press(&mut a, "]]LLL");
    insta::assert_snapshot!("limacon_linkage_160x48", render(&a, 160, 48, Theme { color: true }).backend());
}

#[test]
fn snapshot_cayley_curve_view() {
    let mut a = app("limacon");
    press(&mut a, "vrr");
    insta::assert_snapshot!("limacon_curve_80x24", render(&a, 80, 24, Theme { color: true }).backend());
}

#[test]
fn snapshot_help_overlay() {
    let mut a = app("jansen");
    press(&mut a, "?");
    insta::assert_snapshot!("help_80x24", render(&a, 80, 24, Theme { color: true }).backend());
    insta::assert_snapshot!("help_160x48", render(&a, 160, 48, Theme { color: true }).backend());
}

#[test]
fn snapshot_too_small() {
    let a = app("jansen");
    insta::assert_snapshot!("too_small_50x12", render(&a, 50, 12, Theme { color: true }).backend());
}

#[test]
fn monochrome_theme_uses_no_colour_and_keeps_emphasis() {
    let mut a = app("jansen");
    press(&mut a, "]");
    let t = render(&a, 80, 24, Theme { color: false });
    let buf = t.backend().buffer();
    let mut emphasised = 0;
    for cell in buf.content() {
        assert_eq!(cell.fg, ratatui::style::Color::Reset, "colour in the monochrome theme at {:?}", cell.symbol());
        assert_eq!(cell.bg, ratatui::style::Color::Reset);
        if !cell.modifier.is_empty() {
            emphasised += 1;
        }
    }
    assert!(emphasised > 10, "emphasis by modifiers must remain");
    insta::assert_snapshot!("jansen_monochrome_80x24", t.backend());
}

/// The real binary in a pseudo-terminal: a full crank turn, then quit.
#[test]
fn end_to_end_in_a_pseudo_terminal() {
    use std::io::Write;
    use std::time::{Duration, Instant};

    let (_master, mut child, mut writer, rx) = spawn_in_pty("jansen");
    let mut parser = vt100::Parser::new(24, 80, 0);
    // Wait until the screen shows `want` (and, if given, a λ different from `not`).
    let wait_for = |parser: &mut vt100::Parser, pred: &dyn Fn(&str) -> bool| -> String {
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            while let Ok(bytes) = rx.try_recv() {
                parser.process(&bytes);
            }
            let screen = parser.screen().contents();
            if pred(&screen) {
                return screen;
            }
            assert!(Instant::now() < deadline, "timed out; screen:\n{screen}");
            std::thread::sleep(Duration::from_millis(20));
        }
    };
    let readout = |screen: &str| -> (String, String) {
        let field = |key: &str| {
            screen
                .lines()
                .find_map(|l| {
                    l.split('│')
                        .find(|c| c.trim_start().starts_with(key))
                        .map(|c| c.trim()[key.len()..].trim().to_string())
                })
                .unwrap_or_default()
        };
        (field("λ"), field("type"))
    };
    let first = wait_for(&mut parser, &|s| s.contains("realization") && s.contains("type"));
    let (l0, t0) = readout(&first);
    assert!(l0.starts_with("50.02"), "drawn λ: {l0:?}");
    let mut seen = vec![(l0, t0.clone())];
    for _ in 0..4 {
        writer.write_all(b"]").unwrap();
        writer.flush().unwrap();
        let last = seen.last().unwrap().clone();
        let screen = wait_for(&mut parser, &|s| readout(s) != last);
        seen.push(readout(&screen));
    }
    let lambdas: Vec<&str> = seen.iter().map(|(l, _)| l.as_str()).collect();
    assert_eq!(&lambdas[1..], ["53.792267", "23.792267", "53.792267", "23.792267"], "{seen:?}");
    let types: Vec<&str> = seen.iter().map(|(_, t)| t.as_str()).collect();
    assert_eq!(types[1], t0, "the type holds up to the endpoint");
    assert_ne!(types[2], types[1], "and flips after it");
    assert_eq!(types[3], types[1]);
    assert_eq!(types[4], types[2], "a full crank turn changes the type twice");
    type_and_expect_clean_exit(b"q", &mut *child, &mut *writer, &rx, &mut parser);
}

/// Issue 10 item 1: the real binary on a scene with no realization opens,
/// draws why, and quits with exit status 0 (it used to panic, exit 101).
#[test]
fn a_scene_with_no_realization_in_a_pseudo_terminal() {
    use std::time::{Duration, Instant};

    let dir = std::env::temp_dir().join(format!("caymos-tui-empty-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("cannot-close.toml");
    std::fs::write(&file, caymos::generate::to_toml(&no_realization_scene())).unwrap();
    let (_master, mut child, mut writer, rx) = spawn_in_pty(file.to_str().unwrap());
    let mut parser = vt100::Parser::new(24, 80, 0);
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        while let Ok(bytes) = rx.try_recv() {
            parser.process(&bytes);
        }
        let screen = parser.screen().contents();
        if screen.contains("no realization") && screen.contains("at least 9") {
            break;
        }
        assert!(Instant::now() < deadline, "timed out; screen:\n{screen}");
        std::thread::sleep(Duration::from_millis(20));
    }
    // Keys that would walk or mark do nothing here; then quit.
    type_and_expect_clean_exit(b"]ln ab1vq", &mut *child, &mut *writer, &rx, &mut parser);
    std::fs::remove_dir_all(&dir).ok();
}

/// The real binary on `arg` in an 80×24 pseudo-terminal with `NO_COLOR=1`:
/// the master (keep it alive), the child, its input, and its output as chunks.
#[allow(clippy::type_complexity)]
pub fn spawn_in_pty(
    arg: &str,
) -> (
    Box<dyn portable_pty::MasterPty + Send>,
    Box<dyn portable_pty::Child + Send + Sync>,
    Box<dyn std::io::Write + Send>,
    std::sync::mpsc::Receiver<Vec<u8>>,
) {
    use portable_pty::{CommandBuilder, PtySize, native_pty_system};
    use std::io::Read;
    let pair = native_pty_system().openpty(PtySize { rows: 24, cols: 80, pixel_width: 0, pixel_height: 0 }).unwrap();
    let mut cmd = CommandBuilder::new(env!("CARGO_BIN_EXE_caymos"));
    cmd.arg(arg);
    cmd.env("NO_COLOR", "1");
    cmd.env("TERM", "xterm-256color");
    let child = pair.slave.spawn_command(cmd).unwrap();
    drop(pair.slave);
    let mut reader = pair.master.try_clone_reader().unwrap();
    let writer = pair.master.take_writer().unwrap();
    let (tx, rx) = std::sync::mpsc::channel::<Vec<u8>>();
    std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n) = reader.read(&mut buf) {
            if n == 0 || tx.send(buf[..n].to_vec()).is_err() {
                break;
            }
        }
    });
    (pair.master, child, writer, rx)
}

/// Type `keys` (ending in a quit), then: the child exits with status 0 within
/// 10 s and has left the alternate screen (the terminal is restored).
pub fn type_and_expect_clean_exit(
    keys: &[u8],
    child: &mut dyn portable_pty::Child,
    writer: &mut dyn std::io::Write,
    rx: &std::sync::mpsc::Receiver<Vec<u8>>,
    parser: &mut vt100::Parser,
) {
    use std::time::{Duration, Instant};
    writer.write_all(keys).unwrap();
    writer.flush().unwrap();
    let deadline = Instant::now() + Duration::from_secs(10);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        assert!(Instant::now() < deadline, "did not exit after {:?}", String::from_utf8_lossy(keys));
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(status.success(), "exit status {status:?}");
    while let Ok(bytes) = rx.recv_timeout(Duration::from_millis(200)) {
        parser.process(&bytes);
    }
    assert!(!parser.screen().alternate_screen(), "terminal left in the alternate screen");
}

/// Issue 13: the screen as text, lines joined.
fn screen(a: &App, w: u16, h: u16) -> String {
    let t = render(a, w, h, Theme { color: false });
    let buf = t.backend().buffer().clone();
    (0..h).map(|y| (0..w).map(|x| buf[(x, y)].symbol().to_string()).collect::<String>()).collect::<Vec<_>>().join("\n")
}

#[test]
fn snapshot_a_25_step_type_is_read_whole_in_groups_of_five() {
    let a = App::ready(analyse(caymos::generate::chain(25), None).unwrap());
    let ty = a.model().unwrap().current().ty.to_string();
    assert_eq!(ty.chars().count(), 25);
    let s = screen(&a, 80, 24);
    // Every sign is on screen: rows of three groups of five, each row led by its first step.
    let signs: Vec<char> = ty.chars().collect();
    let groups: Vec<String> = signs.chunks(5).map(|c| c.iter().collect()).collect();
    assert!(s.contains(&format!(" 1 {}·{}·{}", groups[0], groups[1], groups[2])), "{s}");
    assert!(s.contains(&format!("16 {}·{}", groups[3], groups[4])), "{s}");
    insta::assert_snapshot!("chain25_readout_80x24", render(&a, 80, 24, Theme { color: false }).backend());
}

#[test]
fn snapshot_cayley_curve_has_axes_ranges_and_a_legend_without_colour() {
    let mut a = app("limacon");
    press(&mut a, "v");
    let m = a.model().unwrap();
    let s = screen(&a, 80, 24);
    let l = &m.analysis().linkage;
    let ccv = &m.solved().complexity.ccv;
    for (k, &ax) in m.camera.axes.iter().enumerate() {
        let name = l.pair_name(ccv[ax]);
        let range = format!(
            "{name} {}…{}",
            caymos::report::fmt_num(m.picture.curve.range.lo[k]),
            caymos::report::fmt_num(m.picture.curve.range.hi[k])
        );
        assert!(s.contains(&range), "{range} in {s}");
    }
    // Each type met has its own marker in the legend, and the markers are drawn.
    let mut types: Vec<String> = Vec::new();
    for t in &m.picture.samples.types {
        if !types.contains(&t.to_string()) {
            types.push(t.to_string());
        }
    }
    assert!(types.len() >= 2);
    for (k, t) in types.iter().enumerate() {
        let marker = ["●", "○", "◆", "◇", "■", "□", "▲", "△"][k];
        assert!(s.contains(&format!("{marker} {t}")), "{marker} {t} in {s}");
    }
    // Markers are drawn on the curve too, not only in the legend.
    let on_curve: usize = ["●", "○", "◆", "◇", "■", "□", "▲", "△"].iter().map(|mk| s.matches(mk).count()).sum();
    assert!(on_curve > types.len(), "markers on the curve: {s}");
    insta::assert_snapshot!("limacon_curve_monochrome_80x24", render(&a, 80, 24, Theme { color: false }).backend());
}

#[test]
fn the_curve_axes_default_to_the_minimal_cayley_vector() {
    let a = app("limacon");
    let m = a.model().unwrap();
    let minimal = m.solved().minimal_vector(caymos::minimal_vector::MinimalOptions::default()).entries;
    let n = m.solved().complexity.ccv.len();
    let axes = caymos::tui::app::default_axes(&minimal, n);
    assert_eq!(m.camera.axes, axes);
    for (k, &e) in minimal.iter().take(3).enumerate() {
        assert_eq!(axes[k], e);
    }
    assert_eq!(caymos::tui::app::default_axes(&[2, 4], 6), [2, 4, 0]);
    assert_eq!(caymos::tui::app::default_axes(&[], 1), [0, 0, 0]);
}

#[test]
fn snapshot_panels_say_how_much_more_and_scroll_on_limacon() {
    let mut a = app("limacon");
    let s = screen(&a, 80, 24);
    assert!(s.contains("more · } scrolls"), "{s}");
    let m = a.model().unwrap();
    let l = &m.analysis().linkage;
    let names: Vec<String> =
        m.solved().complexity.ccv.iter().map(|&p| format!("{}–{}", l.names[p[0]], l.names[p[1]])).collect();
    let last = names.last().unwrap().clone();
    assert!(!s.contains(&format!("│{last} ")), "{last} hidden at first: {s}");
    insta::assert_snapshot!("limacon_more_80x24", render(&a, 80, 24, Theme { color: false }).backend());
    // Scrolling down shows the rest, every entry once on the way; up comes back.
    let mut seen = std::collections::BTreeSet::new();
    for _ in 0..names.len() {
        let s = screen(&a, 80, 24);
        for n in &names {
            if s.contains(&format!("│{n} ")) {
                seen.insert(n.clone());
            }
        }
        press(&mut a, "}");
    }
    assert_eq!(seen.len(), names.len(), "{seen:?}");
    assert!(screen(&a, 80, 24).contains("more above"));
    for _ in 0..names.len() {
        press(&mut a, "{");
    }
    assert_eq!(screen(&a, 80, 24), s);
}

#[test]
fn snapshot_too_small_40x12_shows_the_minimum_and_the_quit_key() {
    let a = app("jansen");
    let s = screen(&a, 40, 12);
    let flat = s.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(flat.contains("at least 60×18;"), "{s}");
    assert!(flat.contains("press q to quit."), "{s}");
    insta::assert_snapshot!("too_small_40x12", render(&a, 40, 12, Theme { color: false }).backend());
}

#[test]
fn long_status_lines_wrap_instead_of_being_cut() {
    let mut a = app("jansen");
    let msg = "different components: closest pair -+--@53.7922671 / ++--@23.7922671 at Cayley distance 1.23456789e-7 (and more words to wrap)";
    a.message = Some(msg.to_string());
    let s = screen(&a, 80, 24);
    let flat = s.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(flat.contains(msg), "{s}");
    assert!(s.contains("? help"), "the key bar stays: {s}");
}

#[test]
fn the_default_traced_joint_moves_farthest() {
    for scene in ["jansen", "limacon", "fourbar-crank-rocker"] {
        let a = app(scene);
        let m = a.model().unwrap();
        let j = m.traces.selected;
        assert!(m.traces.traced[j] && m.traces.traced.iter().filter(|&&t| t).count() == 1);
        assert!(!m.analysis().linkage.ground.contains(&j), "{scene}: traced a ground pivot");
        // Its path over the drawn component spans at least any other joint's.
        let diag = |k: usize| {
            let ps: Vec<[f64; 2]> = m.picture.samples.positions.iter().map(|p| [p[k][0], p[k][1]]).collect();
            let (x0, x1) = ps.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p[0]), b.max(p[0])));
            let (y0, y1) = ps.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p[1]), b.max(p[1])));
            (x1 - x0).hypot(y1 - y0)
        };
        let best = (0..m.traces.traced.len()).map(diag).fold(0.0, f64::max);
        assert!(diag(j) >= best * 0.95, "{scene}: joint {j} spans {} of {best}", diag(j));
    }
}

/// The help overlay at 80×24 shows every key's whole description, in both
/// modes (it used to cut the longer ones without saying so).
#[test]
fn help_at_80x24_shows_every_description_whole() {
    use caymos::tui::keymap::{Mode, bindings};
    for (mode, keys) in [(Mode::Explore, "?"), (Mode::Edit, "m?")] {
        let mut a = app("jansen");
        press(&mut a, keys);
        let s = screen(&a, 80, 24);
        for b in bindings(mode) {
            assert!(s.contains(b.help), "{mode:?}: \"{}\" is cut in the help:\n{s}", b.help);
        }
        assert!(s.contains("Esc or ? closes this help"), "{mode:?}: how to close the help is cut:\n{s}");
    }
}

/// `B` cycles through every valid base non-edge (CayMos let users choose the
/// base): the component count stays (it is the realization space's), the
/// walk starts at the drawn realization, and the cycle comes back.
#[test]
fn next_base_cycles_through_the_valid_bases() {
    let mut a = app("jansen");
    let first = a.model().unwrap().solved().dec.base;
    let n_bases = 1 + a.model().unwrap().solved().dec.other_bases(&a.model().unwrap().analysis().linkage).len();
    let components = a.model().unwrap().n_components();
    let mut seen = vec![first];
    for _ in 1..n_bases {
        press(&mut a, "B");
        let m = a.model().expect("explorable on every valid base");
        let base = m.solved().dec.base;
        assert!(!seen.contains(&base) && !seen.contains(&[base[1], base[0]]), "{base:?} again: {seen:?}");
        seen.push(base);
        assert_eq!(m.n_components(), components, "base {base:?}");
        assert!(a.message.as_deref().unwrap_or("").starts_with("base "), "{:?}", a.message);
    }
    press(&mut a, "B");
    let back = a.model().unwrap().solved().dec.base;
    assert!(back == first || back == [first[1], first[0]], "{back:?} after a full cycle from {first:?}");
}

#[test]
fn curve_axes_are_chosen_by_name() {
    let mut a = app("jansen");
    let names = |a: &App| {
        let m = a.model().unwrap();
        let (l, ccv) = (&m.analysis().linkage, &m.solved().complexity.ccv);
        m.camera.axes.map(|k| l.pair_name(ccv[k]))
    };
    // The prompt starts with the axes now; typed pairs may use - or , and either order.
    press(&mut a, "A");
    assert_eq!(a.input.as_ref().unwrap().text, names(&a).join(" "));
    press(&mut a, &format!("{}K-P Y,O O–W⏎", "⌫".repeat(40)));
    assert_eq!(names(&a), ["P–K", "O–Y", "O–W"], "{:?}", a.message);
    assert_eq!(a.model().unwrap().view, View::CayleyCurve);
    for (typed, why) in [("P-K O-Y", "three entries"), ("P-K O-Y O-F", "O-F is not in"), ("P-K P-K O-W", "different")] {
        press(&mut a, &format!("A{}{typed}⏎", "⌫".repeat(40)));
        assert!(a.message.as_deref().unwrap_or_default().contains(why), "{typed}: {:?}", a.message);
        assert_eq!(names(&a), ["P–K", "O–Y", "O–W"], "unchanged by {typed}");
    }
}

#[test]
fn at_a_branch_point_f_takes_each_way_on() {
    // The crank-rocker with AB = 2.5: AB + BC = CD + DA, so at λ = 6.5 both
    // steps are stretched at once and the four types meet (THEORY.md §6).
    let mut a = app("fourbar-crank-rocker");
    press(&mut a, &format!("m/A-B⏎={}2.5⏎m", "⌫".repeat(30)));
    press(&mut a, "f");
    assert!(a.message.as_deref().unwrap_or_default().contains("not at a branch point"), "{:?}", a.message);
    for _ in 0..4 {
        if lambda(&a) == 6.5 {
            break;
        }
        press(&mut a, "]");
    }
    assert_eq!(lambda(&a), 6.5);
    assert!(a.message.as_deref().unwrap_or_default().contains("ways meet here"), "{:?}", a.message);
    let ways = a.model().unwrap().branch_here();
    assert_eq!(ways.len(), 4, "the four sign types meet: {ways:?}");
    let start = a.model().unwrap().cursor.positions.clone();
    let mut components = std::collections::BTreeSet::new();
    let mut types = std::collections::BTreeSet::new();
    for _ in 0..ways.len() {
        press(&mut a, "f");
        let m = a.model().unwrap();
        let note = a.message.clone().unwrap_or_default();
        assert!(note.contains("steps 1, 2 flat") && note.contains(&format!("of {}", ways.len())), "{note}");
        assert_eq!(lambda(&a), 6.5);
        assert_eq!(m.flat_here(), &[0, 1]);
        // One realization, whichever way: both steps flat, so every sign gives it.
        for (p, q) in m.cursor.positions.iter().zip(&start) {
            assert!((p.x - q.x).abs() <= 1e-12 && (p.y - q.y).abs() <= 1e-12, "{p:?} vs {q:?}");
        }
        components.insert(m.cursor.component);
        types.insert(ty(&a));
    }
    assert_eq!(types.into_iter().collect::<Vec<_>>(), ["++", "+-", "-+", "--"], "every way visited once");
    assert_eq!(components.len(), 2, "the ways lead into both listed components");
    // And the motion goes on along the way taken.
    let k = a.model().unwrap().cursor.component;
    press(&mut a, "←");
    assert_eq!(a.model().unwrap().cursor.component, k);
    assert!(lambda(&a) < 6.5);
}

#[test]
fn go_to_errors_give_spans_in_the_digits_that_matter() {
    let mut a = app("jansen");
    let t = ty(&a);
    press(&mut a, &format!("g{t}@1⏎"));
    let m = a.message.clone().unwrap_or_default();
    assert!(m.contains("is not realizable at λ = 1; it is at λ in ["), "{m}");
    // Every number in it has at most six significant digits (the ends are far apart).
    for word in m.split(|c: char| !(c.is_ascii_digit() || c == '.')).filter(|w| w.contains('.')) {
        assert!(word.replace('.', "").trim_start_matches('0').len() <= 6, "{word} in {m}");
    }
}

#[test]
fn every_type_on_the_curve_has_its_own_marker() {
    let markers: Vec<String> = (0..200).map(view::type_marker).collect();
    let distinct: std::collections::HashSet<&String> = markers.iter().collect();
    assert_eq!(distinct.len(), markers.len(), "{markers:?}");
    assert_eq!(markers[0], "●");
    assert_eq!(markers[8], "a");
    assert_eq!(markers[34], "35");
}
