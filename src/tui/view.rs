//! Drawing: the app state in, widgets out. Nothing here changes state.

use ratatui::Frame;
use ratatui::layout::{Alignment, Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Context, Line as Segment2, Points};
use ratatui::widgets::{Block, Clear, Paragraph, Wrap};

use super::app::{App, Model, Motion, PromptKind, Screen, View, unit_frame};
use super::edit::Item;
use super::keymap::{Binding, Mode, bindings};
use super::theme::Theme;
use crate::analysis::Analysis;
use crate::report::{fmt_num, fmt_sig};

/// The smallest terminal the layout works in.
pub const MIN_WIDTH: u16 = 60;
pub const MIN_HEIGHT: u16 = 18;

/// Draw the whole screen from the state; nothing here changes it.
pub fn draw(frame: &mut Frame, app: &App, theme: Theme) {
    let area = frame.area();
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        let text = format!(
            "caymos needs a terminal of at least {MIN_WIDTH}×{MIN_HEIGHT};\nthis one is {}×{}. Enlarge it, or press q to quit.",
            area.width, area.height
        );
        let y = area.height / 2;
        let rect = Rect { x: area.x, y: area.y + y.saturating_sub(1), width: area.width, height: 2.min(area.height) };
        frame.render_widget(Paragraph::new(text).alignment(Alignment::Center).style(theme.warn()), rect);
        return;
    }
    // A file error (with its file:line:col) gets two rows, so it is not cut.
    let status_rows = if app.file_error.is_some() && app.input.is_none() && app.message.is_none() { 2 } else { 1 };
    let [body, status, keys] =
        Layout::vertical([Constraint::Min(8), Constraint::Length(status_rows), Constraint::Length(1)]).areas(area);
    let selected = selected_joints(app);
    match &app.screen {
        Screen::Loading { scene } => {
            let p =
                Paragraph::new(format!("analysing {scene} …")).alignment(Alignment::Center).block(Block::bordered());
            frame.render_widget(p, body);
        }
        Screen::Failed { scene, message } => {
            let p = Paragraph::new(vec![
                Line::styled(format!("{scene}: cannot explore this scene"), theme.warn()),
                Line::raw(""),
                Line::raw(message.clone()),
            ])
            .wrap(Wrap { trim: true })
            .block(Block::bordered().title(Span::styled(" caymos ", theme.title())));
            frame.render_widget(p, body);
        }
        Screen::Empty { analysis, why } => {
            let heads = ["nothing to explore", " no realization ", "· the drawing (no realization) "];
            draw_empty(frame, analysis, heads, why, &selected, body, theme)
        }
        Screen::Outside { analysis, why } => {
            let heads = ["cannot explore: outside the handled class", " outside the class ", "· the drawing "];
            draw_empty(frame, analysis, heads, why, &selected, body, theme)
        }
        Screen::Ready(m) => draw_model(frame, app, m, &selected, body, theme),
    }
    draw_status(frame, app, status, theme);
    draw_keys(frame, app, keys, theme);
    if app.help {
        draw_help(frame, app.mode(), area, theme);
    }
}

/// The joints the drawing highlights: the edit selection's (a joint, or a
/// bar's two ends) when editing, else none (the view then marks the traced joint).
fn selected_joints(app: &App) -> Vec<usize> {
    if !app.editor.on {
        return Vec::new();
    }
    match app.item() {
        Item::Joint(j) => vec![j],
        Item::Bar(i) => app.doc.scene.bars[i].joints.to_vec(),
    }
}

/// A scene with nothing to explore (no realization, or outside the class):
/// the drawing, why (`heads`: the headline, the panel's title, the drawing's), and
/// every bar's length (stated ones marked).
fn draw_empty(
    frame: &mut Frame,
    a: &Analysis,
    heads: [&str; 3],
    why: &str,
    selected: &[usize],
    area: Rect,
    theme: Theme,
) {
    let side = if area.width >= 120 { 52 } else { 36 };
    let [main, right] = Layout::horizontal([Constraint::Min(20), Constraint::Length(side)]).areas(area);
    let l = &a.linkage;
    // Drawn in units of the drawing's extent about its centre, so any scale draws.
    let unit = unit_frame(bounds_of(&l.drawn));
    let pos: Vec<[f64; 2]> = l.drawn.iter().map(|&p| unit(p)).collect();
    let (xb, yb) = equal_bounds(bounds_of(&pos), main);
    let title = Line::from(vec![
        Span::styled(format!(" {} ", a.scene.name), theme.title()),
        Span::styled(heads[2].to_string(), theme.dim()),
    ]);
    let canvas = braille(title, xb, yb, |ctx| {
        draw_bars(ctx, l, &pos, theme.bar());
        ctx.layer();
        let tick = (xb[1] - xb[0]) * 0.015;
        for (j, p) in pos.iter().enumerate() {
            let style = if selected.contains(&j) { theme.highlight() } else { Style::default().fg(theme.joint()) };
            ctx.print(p[0] + tick * 0.5, p[1], Line::styled(l.names[j].clone(), style));
        }
    });
    frame.render_widget(canvas, main);
    let mut lines = vec![
        Line::styled(heads[0].to_string(), theme.warn()),
        Line::raw(""),
        Line::raw(why.to_string()),
        Line::raw(""),
        Line::styled("bar lengths (stated / drawn)", theme.dim()),
    ];
    // As many bars as fit under the (wrapped) explanation; the rest counted.
    let inner = usize::from(right.width.saturating_sub(2)).max(1);
    let why_rows = why.chars().count().div_ceil(inner) + 1;
    let room = usize::from(right.height.saturating_sub(2)).saturating_sub(4 + why_rows);
    let n = l.bars.len();
    let shown = if n <= room { n } else { room.saturating_sub(1) };
    for (bar, sb) in l.bars.iter().zip(&a.scene.bars).take(shown) {
        let drawn = bar.length - bar.sketch_error;
        let text = match sb.length {
            Some(stated) => format!("{}  {} / {}", l.pair_name(bar.joints), fmt_num(stated), fmt_num(drawn)),
            None => format!("{}  {} (drawn)", l.pair_name(bar.joints), fmt_num(drawn)),
        };
        lines.push(Line::raw(text));
    }
    if shown < n {
        lines.push(Line::styled(format!("… and {} more bars (caymos report lists them)", n - shown), theme.dim()));
    }
    let p = Paragraph::new(lines)
        .wrap(Wrap { trim: true })
        .block(Block::bordered().title(Span::styled(heads[1].to_string(), theme.title())));
    frame.render_widget(p, right);
}

/// [min x, min y, max x, max y] of the finite points.
fn bounds_of(points: &[[f64; 2]]) -> [f64; 4] {
    let mut b = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
    for p in points.iter().filter(|p| p[0].is_finite() && p[1].is_finite()) {
        b = [b[0].min(p[0]), b[1].min(p[1]), b[2].max(p[0]), b[3].max(p[1])];
    }
    b
}

/// The bars and body outlines of a linkage at `pos` (canvas coordinates).
fn draw_bars(ctx: &mut Context, l: &crate::linkage::Linkage, pos: &[[f64; 2]], color: ratatui::style::Color) {
    for bar in &l.bars {
        let (p, q) = (pos[bar.joints[0]], pos[bar.joints[1]]);
        ctx.draw(&Segment2::new(p[0], p[1], q[0], q[1], color));
    }
    for body in &l.bodies {
        for (i, &a) in body.iter().enumerate() {
            let b = body[(i + 1) % body.len()];
            ctx.draw(&Segment2::new(pos[a][0], pos[a][1], pos[b][0], pos[b][1], color));
        }
    }
}

fn draw_model(frame: &mut Frame, app: &App, m: &Model, selected: &[usize], area: Rect, theme: Theme) {
    let side = if area.width >= 120 { 38 } else { 30 };
    let max_rows = (area.height / 3).max(4);
    let comp_rows = m.solved().components.list[m.cursor.component].intervals.len() as u16;
    let chart_h = (comp_rows + 3).min(max_rows);
    let [top, chart] = Layout::vertical([Constraint::Min(6), Constraint::Length(chart_h)]).areas(area);
    let [main, right] = Layout::horizontal([Constraint::Min(20), Constraint::Length(side)]).areas(top);
    let ccv_rows = m.solved().complexity.ccv.len() as u16;
    let [readout, comps] =
        Layout::vertical([Constraint::Length((ccv_rows + 6).min(top.height / 2 + 2)), Constraint::Min(3)]).areas(right);
    match m.view {
        View::Linkage => draw_linkage(frame, m, selected, main, theme),
        View::CayleyCurve => draw_curve(frame, m, main, theme),
    }
    draw_readout(frame, m, readout, theme);
    if app.editor.on {
        draw_edit_panel(frame, app, comps, theme);
    } else {
        draw_components(frame, m, comps, theme);
    }
    draw_intervals(frame, m, chart, theme);
}

/// A bordered braille canvas over the given bounds: both main views use it.
fn braille<'a, F: Fn(&mut Context)>(title: Line<'a>, xb: [f64; 2], yb: [f64; 2], paint: F) -> Canvas<'a, F> {
    Canvas::default()
        .block(Block::bordered().title(title))
        .marker(Marker::Braille)
        .x_bounds(xb)
        .y_bounds(yb)
        .paint(paint)
}

/// Canvas bounds with equal scale on both axes (a cell is about twice as tall as wide).
fn equal_bounds(b: [f64; 4], area: Rect) -> ([f64; 2], [f64; 2]) {
    let (w, h) = (f64::from(area.width.saturating_sub(2).max(1)), f64::from(area.height.saturating_sub(2).max(1)));
    let (cx, cy) = ((b[0] + b[2]) / 2.0, (b[1] + b[3]) / 2.0);
    let mut dx = (b[2] - b[0]).max(1e-12) * 1.08;
    let mut dy = (b[3] - b[1]).max(1e-12) * 1.08;
    // Units per cell: horizontally dx / w, vertically dy / h; a cell is 2:1 tall.
    if dy / h < 2.0 * dx / w {
        dy = 2.0 * dx / w * h;
    } else {
        dx = dy / h / 2.0 * w;
    }
    ([cx - dx / 2.0, cx + dx / 2.0], [cy - dy / 2.0, cy + dy / 2.0])
}

fn dashed(ctx: &mut Context, p: [f64; 2], q: [f64; 2], color: ratatui::style::Color) {
    const DASHES: usize = 9;
    for k in 0..DASHES {
        let (t0, t1) = (k as f64 / DASHES as f64, (k as f64 + 0.5) / DASHES as f64);
        let at = |t: f64| [p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t];
        let (a, b) = (at(t0), at(t1));
        ctx.draw(&Segment2::new(a[0], a[1], b[0], b[1], color));
    }
}

/// The motion followed, numbered from 1 like the CLI's `--arc`.
fn motion_label(m: &Model) -> String {
    match m.cursor.motion {
        Motion::Component(k) => format!("component {} of {}", k + 1, m.n_components()),
        Motion::Path { arc } => format!("path {} A→B", arc + 1),
    }
}

/// " · traces cut at the sample budget" when the current motion's samples were cut.
fn cut_note(m: &Model) -> &'static str {
    if m.picture.samples.truncated { "· traces cut at the sample budget " } else { "" }
}

fn draw_linkage(frame: &mut Frame, m: &Model, selected: &[usize], area: Rect, theme: Theme) {
    let bounds = m.picture.bounds;
    let unit = unit_frame(bounds);
    let [x0, y0] = unit([bounds[0], bounds[1]]);
    let [x1, y1] = unit([bounds[2], bounds[3]]);
    let (xb, yb) = equal_bounds([x0, y0, x1, y1], area);
    let traces = &m.picture.traces;
    let l = &m.analysis().linkage;
    let pos: Vec<[f64; 2]> = m.cursor.positions.iter().map(|&p| unit(p.into())).collect();
    let ccv = &m.solved().complexity.ccv;
    let title = Line::from(vec![
        Span::styled(format!(" {} ", m.analysis().scene.name), theme.title()),
        Span::styled(format!("· {} {}", motion_label(m), cut_note(m)), theme.dim()),
    ]);
    let canvas = braille(title, xb, yb, |ctx| {
        for (k, (_, t)) in traces.iter().enumerate() {
            ctx.draw(&Points::new(t, theme.trace(k)));
        }
        ctx.layer();
        for &[p, q] in ccv {
            dashed(ctx, pos[p], pos[q], theme.non_edge());
        }
        draw_bars(ctx, l, &pos, theme.bar());
        let tick = (xb[1] - xb[0]) * 0.015;
        for &g in &l.ground {
            let p = pos[g];
            ctx.draw(&Segment2::new(p[0] - tick, p[1] - tick, p[0] + tick, p[1] - tick, theme.ground()));
            ctx.draw(&Segment2::new(p[0] - tick, p[1] - tick, p[0], p[1], theme.ground()));
            ctx.draw(&Segment2::new(p[0] + tick, p[1] - tick, p[0], p[1], theme.ground()));
        }
        ctx.layer();
        let joints: Vec<(f64, f64)> = pos.iter().map(|p| (p[0], p[1])).collect();
        ctx.draw(&Points::new(&joints, theme.joint()));
        for (j, p) in pos.iter().enumerate() {
            let marked = if selected.is_empty() { j == m.traces.selected } else { selected.contains(&j) };
            let style = if marked { theme.highlight() } else { Style::default().fg(theme.joint()) };
            ctx.print(p[0] + tick * 0.5, p[1], Line::styled(l.names[j].clone(), style));
        }
    });
    frame.render_widget(canvas, area);
}

fn draw_curve(frame: &mut Frame, m: &Model, area: Rect, theme: Theme) {
    let curve = &m.picture.curve;
    let l = &m.analysis().linkage;
    let ccv = &m.solved().complexity.ccv;
    let (xb, yb) = equal_bounds([-1.8, -1.8, 1.8, 1.8], area);
    let names: Vec<String> =
        m.camera.axes.iter().map(|&a| ccv.get(a).map_or("-".into(), |&p| l.pair_name(p))).collect();
    let title = Line::from(vec![
        Span::styled(" Cayley curve ", theme.title()),
        Span::styled(format!("{} · {} {}", names.join(" × "), motion_label(m), cut_note(m)), theme.dim()),
        Span::styled(if m.picture.mirror { "(stands for a mirror pair) " } else { "" }, theme.dim()),
    ]);
    let canvas = braille(title, xb, yb, |ctx| {
        for (k, pts) in &curve.runs {
            for w in pts.windows(2) {
                ctx.draw(&Segment2::new(w[0].0, w[0].1, w[1].0, w[1].1, theme.of_type(*k)));
            }
        }
        ctx.layer();
        ctx.print(curve.here.0, curve.here.1, Line::styled("●", theme.highlight()));
    });
    frame.render_widget(canvas, area);
}

fn draw_readout(frame: &mut Frame, m: &Model, area: Rect, theme: Theme) {
    let l = &m.analysis().linkage;
    let here = m.current();
    let flat = m.flat_here();
    let mut ty_spans = vec![Span::raw("type ")];
    for (k, c) in here.ty.to_string().chars().enumerate() {
        let style = if flat.contains(&k) { theme.highlight() } else { theme.text() };
        ty_spans.push(Span::styled(c.to_string(), style));
    }
    let flat_text = if flat.is_empty() {
        "—".to_string()
    } else {
        flat.iter()
            .map(|&k| {
                let s = &m.solved().dec.steps[k];
                format!("step {} ({})", k + 1, l.names[s.vertex])
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut lines = vec![
        Line::from(vec![Span::raw("λ    "), Span::styled(fmt_sig(here.lambda, 8), theme.highlight())]),
        Line::from(ty_spans),
        Line::raw(format!("flat {flat_text}")),
        Line::raw(format!("step {}{}", fmt_num(m.pace.step), if m.pace.playing { "  ▶ playing" } else { "" })),
    ];
    lines.extend(m.drive_line().map(|d| Line::raw(format!("in   {d}"))));
    let v = &m.cursor.cayley;
    for (k, &[p, q]) in m.solved().complexity.ccv.iter().enumerate() {
        let name = format!("{}–{}", l.names[p], l.names[q]);
        lines.push(Line::from(vec![Span::styled(format!("{name:<10}"), theme.dim()), Span::raw(fmt_sig(v[k], 6))]));
    }
    let p = Paragraph::new(lines).block(Block::bordered().title(Span::styled(" realization ", theme.title())));
    frame.render_widget(p, area);
}

fn draw_components(frame: &mut Frame, m: &Model, area: Rect, theme: Theme) {
    let s = m.solved();
    let rows = area.height.saturating_sub(2) as usize;
    let n = s.components.list.len();
    let first = m.cursor.component.saturating_sub(rows.saturating_sub(1) / 2).min(n.saturating_sub(rows));
    let lines: Vec<Line> = s
        .components
        .list
        .iter()
        .enumerate()
        .skip(first)
        .take(rows)
        .map(|(k, c)| {
            let here = k == m.cursor.component;
            let drawn = s.drawn_component == Some(k);
            let text = format!(
                "{}{:>2} {:>2} iv [{}, {}]{}",
                if here { "▸" } else { " " },
                k + 1,
                c.intervals.len(),
                fmt_num(c.lambda_range[0]),
                fmt_num(c.lambda_range[1]),
                if drawn { " *" } else { "" }
            );
            Line::styled(text, if here { theme.highlight() } else { theme.text() })
        })
        .collect();
    let title = if s.lazy {
        Span::styled(format!(" components ({n} walked lazily; n walks more) "), theme.title())
    } else {
        Span::styled(format!(" components ({n}) "), theme.title())
    };
    frame.render_widget(Paragraph::new(lines).block(Block::bordered().title(title)), area);
}

fn draw_intervals(frame: &mut Frame, m: &Model, area: Rect, theme: Theme) {
    let s = m.solved();
    let union = &s.union;
    let (Some(first), Some(last)) = (union.first(), union.last()) else { return };
    let (lo, hi) = (first[0], last[1]);
    let n_steps = s.dec.steps.len();
    let label_w = n_steps.clamp(5, 12);
    let inner = area.width.saturating_sub(2) as usize;
    let width = inner.saturating_sub(label_w + 3).max(4);
    let col = |x: f64| -> usize {
        let t = if hi > lo { (x - lo) / (hi - lo) } else { 0.5 };
        ((t * (width - 1) as f64).round().max(0.0) as usize).min(width - 1)
    };
    let bar = |spans: &[(f64, f64)], cursor: Option<f64>| -> String {
        let mut row = vec![' '; width];
        for &(a, b) in spans {
            let (ca, cb) = (col(a), col(b));
            for c in row.iter_mut().take(cb + 1).skip(ca) {
                *c = '━';
            }
            if a == b {
                row[ca] = '•';
            }
        }
        if let Some(x) = cursor {
            row[col(x)] = '┃';
        }
        row.into_iter().collect()
    };
    let here = m.current();
    let cur_interval = m.cursor.segments[m.cursor.seg].interval;
    let mut lines = vec![Line::from(vec![
        Span::styled(format!("{:<label_w$} ", "union"), theme.dim()),
        Span::raw(bar(&union.iter().map(|u| (u[0], u[1])).collect::<Vec<_>>(), Some(here.lambda))),
    ])];
    let comp = &s.components.list[m.cursor.component];
    let rows = area.height.saturating_sub(3) as usize;
    let pos = comp.intervals.iter().position(|&i| i == cur_interval).unwrap_or(0);
    let start = pos.saturating_sub(rows.saturating_sub(1) / 2).min(comp.intervals.len().saturating_sub(rows));
    for &i in comp.intervals.iter().skip(start).take(rows) {
        let iv = &s.space.intervals[i];
        let current = i == cur_interval;
        let mut ty = iv.ty.to_string();
        if ty.chars().count() > label_w {
            ty = format!(
                "…{}",
                ty.chars().rev().take(label_w - 1).collect::<Vec<_>>().into_iter().rev().collect::<String>()
            );
        }
        let style = if current { theme.highlight() } else { theme.text() };
        lines.push(Line::from(vec![
            Span::styled(format!("{ty:<label_w$} "), style),
            Span::styled(bar(&[(iv.lower.lambda, iv.upper.lambda)], current.then_some(here.lambda)), style),
        ]));
    }
    let title = Line::from(vec![
        Span::styled(" Cayley space ", theme.title()),
        Span::styled(
            format!("λ from {} to {} · {} oriented intervals ", fmt_num(lo), fmt_num(hi), s.space.intervals.len()),
            theme.dim(),
        ),
    ]);
    frame.render_widget(Paragraph::new(lines).block(Block::bordered().title(title)), area);
}

/// The edit panel (in place of the component list while editing): the
/// selection and its value, the steps, undo and redo, the file.
fn draw_edit_panel(frame: &mut Frame, app: &App, area: Rect, theme: Theme) {
    let s = &app.doc.scene;
    let item = app.item();
    let mut lines = vec![Line::styled(app.item_name(item), theme.highlight())];
    match item {
        Item::Joint(j) => {
            let p = s.joints[j].pos;
            lines.push(Line::raw(format!("at ({}, {})", p[0], p[1])));
        }
        Item::Bar(i) => {
            let stated = if s.bars[i].length.is_some() { "stated" } else { "drawn" };
            lines.push(Line::raw(format!("length {} ({stated})", app.bar_length(i))));
        }
    }
    let [fine, coarse] = app.editor.steps;
    let (undo, redo) = app.editor.depth();
    lines.push(Line::styled(format!("steps {} / {} (Shift)", fmt_num(fine), fmt_num(coarse)), theme.dim()));
    lines.push(Line::styled(format!("undo {undo} · redo {redo}"), theme.dim()));
    let file = match &app.doc.path {
        Some(p) => p.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default(),
        None => "no file (w saves to a new one)".to_string(),
    };
    let modified = if app.doc.modified() && app.doc.path.is_some() { " · modified" } else { "" };
    lines.push(Line::styled(format!("{file}{modified}"), theme.dim()));
    let p = Paragraph::new(lines)
        .wrap(Wrap { trim: true })
        .block(Block::bordered().title(Span::styled(" edit ", theme.title())));
    frame.render_widget(p, area);
}

fn draw_status(frame: &mut Frame, app: &App, area: Rect, theme: Theme) {
    let line = if let Some(input) = &app.input {
        let (label, enter) = match input.kind {
            PromptKind::GoTo => ("go to (λ or TYPE@λ): ".to_string(), "go"),
            PromptKind::Select => ("select (joint C or bar B-C): ".to_string(), "select"),
            PromptKind::Value => (format!("{} = ", app.item_name(app.item())), "set"),
        };
        Line::from(vec![
            Span::styled(label, theme.key()),
            Span::raw(format!("{}▏", input.text)),
            Span::styled(format!("  Enter {enter} · Esc cancel"), theme.dim()),
        ])
    } else if let Some(msg) = &app.message {
        Line::styled(msg.clone(), theme.highlight())
    } else if let Some(e) = &app.file_error {
        let p = Paragraph::new(Line::styled(e.clone(), theme.warn())).wrap(Wrap { trim: true });
        frame.render_widget(p, area);
        return;
    } else if app.editor.on {
        Line::styled(
            format!("editing {} · Tab selects · arrows move · +/- length · = types a value", app.item_name(app.item())),
            theme.dim(),
        )
    } else if let Some(m) = app.model() {
        let marks: Vec<String> = m
            .marks
            .slots
            .iter()
            .zip(["A", "B"])
            .filter_map(|(mk, n)| mk.as_ref().map(|mk| format!("{n} {}@{}", mk.at.ty, fmt_num(mk.at.lambda))))
            .collect();
        let names = &m.analysis().linkage.names;
        let t = &m.traces;
        let traced: Vec<&str> = (0..t.traced.len()).filter(|&j| t.traced[j]).map(|j| names[j].as_str()).collect();
        Line::styled(
            format!(
                "joint {} · traces {} [{}] {}",
                names[t.selected],
                if t.on { "on" } else { "off" },
                traced.join(","),
                marks.join(" · ")
            ),
            theme.dim(),
        )
    } else {
        Line::raw("")
    };
    frame.render_widget(Paragraph::new(line), area);
}

fn draw_keys(frame: &mut Frame, app: &App, area: Rect, theme: Theme) {
    use super::keymap::{Action, When};
    let mut spans = Vec::new();
    let mut used = 0usize;
    // Help and quit first, so they show however narrow the terminal; then
    // the edit toggle, then (while editing) the edit keys.
    let editing = app.editor.on;
    let rank = |b: &&Binding| match (b.action, b.when) {
        (Action::Help | Action::Quit, _) => 0,
        (Action::ToggleEdit, _) => 1,
        (_, When::Edit) => 2,
        (Action::Undo | Action::Redo | Action::Save, _) if editing => 3,
        _ => 4,
    };
    // Without a scene to explore only help, quit and the edit keys do anything.
    let edits = |b: &&Binding| {
        b.when == When::Edit || matches!(b.action, Action::ToggleEdit | Action::Undo | Action::Redo | Action::Save)
    };
    let useful = |b: &&Binding| rank(b) == 0 || edits(b) || app.model().is_some();
    let mut bar: Vec<&Binding> = bindings(app.mode()).filter(|b| !b.bar.is_empty()).filter(useful).collect();
    bar.sort_by_key(rank);
    for b in bar {
        let (key, short) = (b.short_label(), b.bar);
        let w = key.chars().count() + short.chars().count() + 3;
        if used + w > area.width as usize {
            break;
        }
        used += w;
        spans.push(Span::styled(format!(" {key}"), theme.key()));
        spans.push(Span::raw(format!(" {short} ")));
    }
    frame.render_widget(Paragraph::new(Line::from(spans)), area);
}

fn draw_help(frame: &mut Frame, mode: Mode, area: Rect, theme: Theme) {
    let rows: Vec<&Binding> = bindings(mode).collect();
    // One column when it fits, else two side by side.
    let rows_needed = rows.len() as u16 + 3;
    let columns: usize = if rows_needed <= area.height.saturating_sub(2) { 1 } else { 2 };
    let per_column = rows.len().div_ceil(columns);
    let w = if columns == 1 { 64 } else { 118 }.min(area.width.saturating_sub(2));
    let h = (per_column as u16 + 3).min(area.height.saturating_sub(2));
    let rect = Rect { x: area.x + (area.width - w) / 2, y: area.y + (area.height - h) / 2, width: w, height: h };
    let col_w = (w.saturating_sub(2) as usize) / columns;
    // Every key of a row, as the key table has them; the column fits the longest.
    let key_w = rows.iter().map(|b| b.label().chars().count()).max().unwrap_or(0) + 1;
    let cell = |b: &Binding| -> Vec<Span<'static>> {
        let help: String = b.help.chars().take(col_w.saturating_sub(key_w + 2)).collect();
        let pad = col_w.saturating_sub(key_w + 1 + help.chars().count());
        vec![Span::styled(format!(" {:<key_w$}", b.label()), theme.key()), Span::raw(help), Span::raw(" ".repeat(pad))]
    };
    let mut lines: Vec<Line> = (0..per_column)
        .map(|r| {
            let mut spans = Vec::new();
            for c in 0..columns {
                if let Some(b) = rows.get(c * per_column + r) {
                    spans.extend(cell(b));
                }
            }
            Line::from(spans)
        })
        .collect();
    lines.push(Line::styled(" Esc or ? closes this help · every key works over SSH, no mouse needed", theme.dim()));
    let title = if mode == Mode::Edit { " keys while editing (m: explore) " } else { " keys (m: edit) " };
    frame.render_widget(Clear, rect);
    frame.render_widget(Paragraph::new(lines).block(Block::bordered().title(Span::styled(title, theme.title()))), rect);
}
