//! The terminal UI: `ratatui` over `crossterm`. Event → action → update
//! (which also makes everything the screen shows) → draw from `&App` (which
//! only reads); the solver runs on a background thread so input stays
//! responsive (the first analysis, every edit's and reload's, and sweeps), and its
//! analysis is moved into the app, never copied. The scene's file is polled
//! every [`WATCH`]. The terminal is restored on quit, on Ctrl-C and on a
//! panic (the hook installed by `ratatui::init`).

pub mod app;
pub mod document;
pub mod edit;
pub mod export;
pub mod keymap;
pub mod sweep;
pub mod theme;
pub mod view;

use std::sync::mpsc;
use std::time::{Duration, Instant};

use ratatui::crossterm::event::{self, Event, KeyCode, KeyEventKind};

use crate::scene::Scene;
use app::{App, Done, Job};
use keymap::Action;
use theme::Theme;

/// How often an animation advances.
const FRAME: Duration = Duration::from_millis(40);

/// How often the scene's file is checked for changes (its time and length).
pub const WATCH: Duration = Duration::from_millis(250);

/// Run the UI on a scene until the user quits.
pub fn run(scene: Scene, base: Option<[usize; 2]>) -> std::io::Result<()> {
    let mut app = App::new(scene, base);
    let (done_tx, done) = mpsc::channel::<Done>();
    // Analyses and sweeps on threads of their own, so a long sweep never holds up an edit's analysis.
    let solver = Solver { analyses: solver_thread(done_tx.clone()), sweeps: solver_thread(done_tx), done };
    let theme = Theme::from_env();
    let mut terminal = ratatui::init();
    let result = event_loop(&mut terminal, &mut app, solver, theme);
    ratatui::restore();
    result
}

/// The channels to the solver threads, and back.
struct Solver {
    analyses: mpsc::Sender<Job>,
    sweeps: mpsc::Sender<Job>,
    done: mpsc::Receiver<Done>,
}

/// A thread that runs the latest job sent to it, skipping older ones, and sends back what it made.
fn solver_thread(done: mpsc::Sender<Done>) -> mpsc::Sender<Job> {
    let (jobs, job_rx) = mpsc::channel::<Job>();
    std::thread::spawn(move || {
        while let Ok(mut job) = job_rx.recv() {
            while let Ok(newer) = job_rx.try_recv() {
                job = newer;
            }
            if done.send(job.run()).is_err() {
                break;
            }
        }
    });
    jobs
}

fn event_loop(
    terminal: &mut ratatui::DefaultTerminal,
    app: &mut App,
    solver: Solver,
    theme: Theme,
) -> std::io::Result<()> {
    let mut dirty = true;
    let mut watched = Instant::now();
    while !app.quit {
        while let Some(job) = app.take_job() {
            let _ = if job.is_sweep() { solver.sweeps.send(job) } else { solver.analyses.send(job) };
        }
        while let Ok(done) = solver.done.try_recv() {
            app.finish(done);
            dirty = true;
        }
        if watched.elapsed() >= WATCH {
            watched = Instant::now();
            dirty |= app.check_file();
        }
        if dirty {
            terminal.draw(|f| view::draw(f, app, theme))?;
            dirty = false;
        }
        let waiting = matches!(app.screen, app::Screen::Loading { .. });
        let timeout = if app.animating() {
            FRAME
        } else if waiting || app.busy() {
            Duration::from_millis(20)
        } else {
            WATCH
        };
        if event::poll(timeout)? {
            match event::read()? {
                Event::Key(key) if key.kind == KeyEventKind::Press => {
                    handle_key(app, key);
                    dirty = true;
                }
                Event::Resize(_, _) => dirty = true,
                _ => {}
            }
        } else if app.animating() {
            app.tick();
            dirty = true;
        } else if waiting {
            dirty = true; // the loading screen shows the elapsed time
        }
    }
    Ok(())
}

/// Run the analyses asked for here and now (what the solver thread does),
/// for tests and scripts driving an [`App`] without a terminal.
pub fn settle(app: &mut App) {
    while let Some(job) = app.take_job() {
        app.finish(job.run());
    }
}

/// Route a key: a prompt takes text; otherwise the key table of the mode decides.
pub fn handle_key(app: &mut App, key: event::KeyEvent) {
    if app.input.is_some() {
        match key.code {
            KeyCode::Enter => app.submit_input(),
            KeyCode::Esc => app.cancel_input(),
            KeyCode::Backspace => app.backspace(),
            KeyCode::Char('c') if key.modifiers.contains(event::KeyModifiers::CONTROL) => app.update(Action::Quit),
            KeyCode::Char(c) => app.type_char(c),
            _ => {}
        }
        return;
    }
    if let Some(action) = keymap::action_for(app.mode(), &key) {
        app.update(action);
    }
}
