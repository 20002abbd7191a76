//! Issue 13: the TUI's angle drive, closest pair from marks, and export.

use caymos::tui::app::App;
use caymos::tui::export::export;

use crate::tui::{app, press};

/// The input bar's angle here, degrees.
fn angle(a: &App) -> f64 {
    a.model().unwrap().input_angle().expect("an input bar").1
}

/// An angle difference in degrees, brought into (−180, 180].
fn wrap_deg(d: f64) -> f64 {
    let d = d.rem_euclid(360.0);
    if d > 180.0 { d - 360.0 } else { d }
}

#[test]
fn stepping_the_crank_by_10_degrees_turns_it_once_round_and_back() {
    let mut a = app("fourbar-crank-rocker");
    press(&mut a, "i");
    let (name, start) = a.model().unwrap().input_angle().unwrap();
    assert_eq!(name, "A–B", "{:?}", a.message);
    assert!((start - 70.0).abs() < 1e-6, "the drawn crank is at 70°: {start}");
    let (l0, t0) = (a.model().unwrap().cursor.lambda, a.model().unwrap().current().ty.to_string());
    let mut sign = 0.0;
    let mut lambdas = Vec::new();
    for k in 0..36 {
        let before = angle(&a);
        press(&mut a, "→");
        let d = wrap_deg(angle(&a) - before);
        if sign == 0.0 {
            sign = d.signum();
        }
        assert!((d - sign * 10.0).abs() < 1e-9, "step {k}: turned {d}° ({:?})", a.message);
        lambdas.push(a.model().unwrap().cursor.lambda);
    }
    assert!(wrap_deg(angle(&a) - start).abs() < 1e-9, "back at {}° after a turn, not {start}°", angle(&a));
    let m = a.model().unwrap();
    assert!((m.cursor.lambda - l0).abs() < 1e-9 && m.current().ty.to_string() == t0, "the same realization");
    // λ moved (and turned back at the interval ends): the drive is not a λ walk.
    assert!(lambdas.windows(2).any(|w| w[1] > w[0]) && lambdas.windows(2).any(|w| w[1] < w[0]));
    // Back by one step, then the step doubles and halves.
    press(&mut a, "←");
    assert!((wrap_deg(angle(&a) - start) + sign * 10.0).abs() < 1e-9);
    press(&mut a, "+");
    assert_eq!(a.model().unwrap().drive.step, 20.0);
    press(&mut a, "--");
    assert_eq!(a.model().unwrap().drive.step, 5.0);
}

#[test]
fn go_to_an_angle_and_play_by_degrees() {
    let mut a = app("fourbar-crank-rocker");
    press(&mut a, "g90°⏎");
    assert!(a.message.as_deref().unwrap_or("").contains("input bar"), "{:?}", a.message);
    press(&mut a, "ig90°⏎");
    assert!((angle(&a) - 90.0).abs() < 1e-9, "{} {:?}", angle(&a), a.message);
    press(&mut a, "g-135deg⏎");
    assert!((angle(&a) + 135.0).abs() < 1e-9, "{}", angle(&a));
    // The readout line says the bar and its angle.
    assert!(a.model().unwrap().drive_line().unwrap().starts_with("A–B -135"));
    // Play advances by the angle step per frame.
    press(&mut a, " ");
    let before = angle(&a);
    a.tick();
    assert!((wrap_deg(angle(&a) - before).abs() - 10.0).abs() < 1e-9);
    // The rocker C–D never reaches 90° from the ground line D–A in this mechanism? It rocks: a miss is said.
    press(&mut a, " i");
    let (name, _) = a.model().unwrap().input_angle().unwrap();
    assert_eq!(name, "D–C");
    press(&mut a, "g0°⏎");
    assert!(a.message.as_deref().unwrap_or("").contains("cannot reach"), "{:?}", a.message);
    // i past the last bar: no input bar, geometric steps again.
    press(&mut a, "i");
    assert!(a.model().unwrap().drive.input.is_none());
}

#[test]
fn one_and_two_visit_the_closest_pair_of_marks_in_different_components() {
    let mut a = app("jansen");
    press(&mut a, "a");
    let k0 = a.model().unwrap().cursor.component;
    press(&mut a, "nb");
    let c = a.model().unwrap().marks.path.as_ref().unwrap().closest_pair.clone().expect("a closest pair");
    assert!(a.message.as_deref().unwrap().contains("Cayley distance"), "{:?}", a.message);
    press(&mut a, "1");
    let m = a.model().unwrap();
    assert_eq!(m.current().ty.to_string(), c.a.ty);
    assert_eq!(m.cursor.lambda, c.a.lambda);
    assert_eq!(m.cursor.component, k0);
    let msg = a.message.clone().unwrap();
    assert!(msg.contains("realization 1 of 2") && msg.contains("Cayley distance"), "{msg}");
    assert!(msg.contains(if c.certified { "· certified" } else { "not certified" }), "{msg}");
    press(&mut a, "2");
    let m = a.model().unwrap();
    assert_eq!((m.current().ty.to_string(), m.cursor.lambda), (c.b.ty.clone(), c.b.lambda));
    assert_ne!(m.cursor.component, k0);
    // The two realizations are the certified distance apart in the Cayley vector.
    let va = {
        press(&mut a, "1");
        a.model().unwrap().cursor.cayley.clone()
    };
    press(&mut a, "2");
    let vb = a.model().unwrap().cursor.cayley.clone();
    let d = va.iter().zip(&vb).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt();
    assert!((d - c.distance).abs() <= 1e-9 * c.distance.max(1.0), "{d} vs {}", c.distance);
}

#[test]
fn export_writes_the_trace_and_the_drawing_named_after_the_scene_never_over_a_file() {
    let dir = crate::helpers::scratch("tui-export");
    let mut a = app("fourbar-crank-rocker");
    press(&mut a, "i");
    let m = a.model().unwrap();
    let e = export(m, "fourbar-crank-rocker", &dir).unwrap();
    assert_eq!(e.csv, dir.join("fourbar-crank-rocker-trace.csv"));
    assert_eq!(e.svg, dir.join("fourbar-crank-rocker.svg"));
    let csv = std::fs::read_to_string(&e.csv).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.starts_with("index,lambda,type,jump,") && header.ends_with(",A-B.angle"), "{header}");
    assert_eq!(csv.lines().count(), e.rows + 1);
    assert!(std::fs::read_to_string(&e.svg).unwrap().starts_with("<svg") || e.svg.exists());
    // A second export: new names, the first files kept.
    let again = export(m, "fourbar-crank-rocker", &dir).unwrap();
    assert_eq!(again.csv, dir.join("fourbar-crank-rocker-trace-1.csv"));
    assert_eq!(again.svg, dir.join("fourbar-crank-rocker-1.svg"));
    assert_eq!(std::fs::read_to_string(&e.csv).unwrap(), csv);
    // The key writes into the app's directory and says where.
    a.save_dir = dir.clone();
    press(&mut a, "o");
    let msg = a.message.clone().unwrap();
    assert!(msg.contains("fourbar-crank-rocker-trace-2.csv") && msg.contains("fourbar-crank-rocker-2.svg"), "{msg}");
    std::fs::remove_dir_all(&dir).ok();
}
