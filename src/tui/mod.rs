//! The terminal UI: `ratatui` over `crossterm`. Event → action → update
//! (which also makes everything the screen shows) → draw from `&App` (which
//! only reads); the solver runs on a background thread so input stays
//! responsive, and its analysis is moved into the app, never copied.
//! The terminal is restored on quit, on Ctrl-C and on a panic (the hook
//! installed by `ratatui::init`).

pub mod app;
pub mod keymap;
pub mod theme;
pub mod view;

use std::sync::mpsc;
use std::time::Duration;

use ratatui::crossterm::event::{self, Event, KeyCode, KeyEventKind};

use crate::analysis::analyse;
use crate::scene::Scene;
use app::App;
use keymap::Action;
use theme::Theme;

/// How often an animation advances.
const FRAME: Duration = Duration::from_millis(40);

/// Run the UI on a scene until the user quits.
pub fn run(scene: Scene, base: Option<[usize; 2]>) -> std::io::Result<()> {
    let mut app = App::loading(&scene.name);
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let result = analyse(scene, base).map_err(|e| e.to_string());
        let _ = tx.send(result);
    });
    let theme = Theme::from_env();
    let mut terminal = ratatui::init();
    let result = event_loop(&mut terminal, &mut app, &rx, theme);
    ratatui::restore();
    result
}

fn event_loop(
    terminal: &mut ratatui::DefaultTerminal,
    app: &mut App,
    rx: &mpsc::Receiver<Result<crate::analysis::Analysis, String>>,
    theme: Theme,
) -> std::io::Result<()> {
    let mut dirty = true;
    while !app.quit {
        if let Ok(result) = rx.try_recv() {
            app.loaded(result);
            dirty = true;
        }
        if dirty {
            terminal.draw(|f| view::draw(f, app, theme))?;
            dirty = false;
        }
        let waiting = matches!(app.screen, app::Screen::Loading { .. });
        let timeout = if app.animating() {
            FRAME
        } else if waiting {
            Duration::from_millis(50)
        } else {
            Duration::from_secs(3600)
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

/// Route a key: the `g` prompt takes text; otherwise the key table decides.
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
    if let Some(action) = keymap::action_for(&key) {
        app.update(action);
    }
}
