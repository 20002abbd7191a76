//! Colours, or, with `NO_COLOR`, a monochrome theme that keeps emphasis by
//! modifiers (bold, reverse, dim) so nothing depends on colour alone.

use ratatui::style::{Color, Modifier, Style};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Theme {
    pub color: bool,
}

impl Theme {
    /// Monochrome when `NO_COLOR` is set to anything non-empty (no-color.org).
    pub fn from_env() -> Theme {
        Theme { color: std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty()) }
    }

    fn fg(self, c: Color) -> Style {
        if self.color { Style::default().fg(c) } else { Style::default() }
    }

    pub fn text(self) -> Style {
        Style::default()
    }
    pub fn dim(self) -> Style {
        if self.color { self.fg(Color::DarkGray) } else { Style::default().add_modifier(Modifier::DIM) }
    }
    pub fn title(self) -> Style {
        self.fg(Color::Cyan).add_modifier(Modifier::BOLD)
    }
    pub fn highlight(self) -> Style {
        if self.color {
            self.fg(Color::Yellow).add_modifier(Modifier::BOLD)
        } else {
            Style::default().add_modifier(Modifier::REVERSED)
        }
    }
    pub fn key(self) -> Style {
        self.fg(Color::Green).add_modifier(Modifier::BOLD)
    }
    pub fn warn(self) -> Style {
        self.fg(Color::Red).add_modifier(Modifier::BOLD)
    }
    /// Canvas colours: bars, joints, traces, dashed non-edges, the cursor.
    pub fn bar(self) -> Color {
        if self.color { Color::White } else { Color::Reset }
    }
    pub fn joint(self) -> Color {
        if self.color { Color::Yellow } else { Color::Reset }
    }
    pub fn ground(self) -> Color {
        if self.color { Color::Red } else { Color::Reset }
    }
    pub fn non_edge(self) -> Color {
        if self.color { Color::DarkGray } else { Color::Reset }
    }
    pub fn trace(self, k: usize) -> Color {
        const P: [Color; 6] =
            [Color::Cyan, Color::Magenta, Color::Green, Color::LightBlue, Color::LightRed, Color::LightYellow];
        if self.color { P[k % P.len()] } else { Color::Reset }
    }
    /// A colour per realization type (for the Cayley curve).
    pub fn of_type(self, k: usize) -> Color {
        const P: [Color; 8] = [
            Color::Cyan,
            Color::Magenta,
            Color::Green,
            Color::Yellow,
            Color::LightBlue,
            Color::LightRed,
            Color::LightGreen,
            Color::White,
        ];
        if self.color { P[k % P.len()] } else { Color::Reset }
    }
}
