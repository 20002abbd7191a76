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
use super::sweep::{SweepView, Swept};
use super::theme::Theme;
use crate::analysis::Analysis;
use crate::present;
use crate::report::{fmt_num, fmt_sig};

/// The smallest terminal the layout works in.
pub const MIN_WIDTH: u16 = 60;
pub const MIN_HEIGHT: u16 = 18;

/// Draw the whole screen from the state; nothing here changes it.
pub fn draw(frame: &mut Frame, app: &App, theme: Theme) {
    let area = frame.area();
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        let text = format!(
            "caymos needs a terminal of at least {MIN_WIDTH}×{MIN_HEIGHT}; this one is {}×{}. Enlarge it, or press q to quit.",
            area.width, area.height
        );
        // Wrapped to the width, centred: the minimum size and the quit key always show.
        let rows = wrap_words(&text, usize::from(area.width.max(1)));
        let h = (rows.len() as u16).min(area.height);
        let rect = Rect { x: area.x, y: area.y + (area.height - h) / 2, width: area.width, height: h };
        let lines: Vec<Line> = rows.into_iter().map(Line::raw).collect();
        frame.render_widget(Paragraph::new(lines).alignment(Alignment::Center).style(theme.warn()), rect);
        return;
    }
    // The status line wraps to up to STATUS_ROWS rows, so nothing is cut at 80 columns.
    let status = status_lines(app, usize::from(area.width), theme);
    let status_rows = status.len().clamp(1, STATUS_ROWS) as u16;
    let [body, status_area, keys] =
        Layout::vertical([Constraint::Min(8), Constraint::Length(status_rows), Constraint::Length(1)]).areas(area);
    let selected = selected_joints(app);
    match &app.screen {
        _ if app.sweep.as_ref().is_some_and(|s| s.shown) => {
            draw_sweep(frame, app, app.sweep.as_ref().expect("shown"), body, theme)
        }
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
    frame.render_widget(Paragraph::new(status), status_area);
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
    let (head, ccv) = readout_lines(m, usize::from(side - 2), theme);
    let want = (head.len() + ccv.len() + 2) as u16;
    let cap = (top.height / 2 + 2).max(head.len() as u16 + 3).min(top.height.saturating_sub(3));
    let [readout, comps] = Layout::vertical([Constraint::Length(want.min(cap)), Constraint::Min(3)]).areas(right);
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

/// The first markers of the Cayley curve's types, in the order the types are met.
const TYPE_MARKERS: [&str; 8] = ["●", "○", "◆", "◇", "■", "□", "▲", "△"];

/// The marker of the `k`-th type met: a shape, then the letters a–z, then
/// the type's number from 35 on, so no two types share one.
pub fn type_marker(k: usize) -> String {
    let shapes = TYPE_MARKERS.len();
    match k {
        _ if k < shapes => TYPE_MARKERS[k].to_string(),
        _ if k < shapes + 26 => char::from(b'a' + (k - shapes) as u8).to_string(),
        _ => (k + 1).to_string(),
    }
}

/// Markers placed along each run of one type, at most.
const MARKERS_PER_RUN: usize = 4;

fn draw_curve(frame: &mut Frame, m: &Model, area: Rect, theme: Theme) {
    let curve = &m.picture.curve;
    let l = &m.analysis().linkage;
    let ccv = &m.solved().complexity.ccv;
    let names: Vec<String> =
        m.camera.axes.iter().map(|&a| ccv.get(a).map_or("-".into(), |&p| l.pair_name(p))).collect();
    // The types in the order the curve meets them (its runs' indices).
    let mut types: Vec<String> = Vec::new();
    for t in &m.picture.samples.types {
        let t = t.to_string();
        if !types.contains(&t) {
            types.push(t);
        }
    }
    let drawn = m.solved().drawn.ty.to_string();
    let title = Line::from(vec![
        Span::styled(" Cayley curve ", theme.title()),
        Span::styled(format!("· {} {}", motion_label(m), cut_note(m)), theme.dim()),
        Span::styled(if m.picture.mirror { "(stands for a mirror pair) " } else { "" }, theme.dim()),
    ]);
    let block = Block::bordered().title(title);
    let inner = block.inner(area);
    frame.render_widget(block, area);
    // Below the curve: each axis's name and range, and the legend of types.
    let width = usize::from(inner.width.max(1));
    let r = &curve.range;
    let axes: Vec<String> = (0..3).map(|k| format!("{} {}…{}", names[k], fmt_num(r.lo[k]), fmt_num(r.hi[k]))).collect();
    let mut text = pack(&axes, "  ", width);
    let mut legend: Vec<String> = types
        .iter()
        .enumerate()
        .map(|(k, t)| format!("{} {}", type_marker(k), present::type_label(t, Some(&drawn))))
        .collect();
    legend.push("◎ here".to_string());
    text.extend(pack(&legend, "  ", width));
    let text_rows = (text.len() as u16).min(inner.height / 2);
    let [canvas_area, text_area] = Layout::vertical([Constraint::Min(3), Constraint::Length(text_rows)]).areas(inner);
    if (text.len() as u16) > text_rows && text_rows > 0 {
        let last = usize::from(text_rows) - 1;
        text.truncate(usize::from(text_rows));
        text[last] = format!("{}…", text[last].chars().take(width.saturating_sub(1)).collect::<String>());
    }
    let lines: Vec<Line> = text.into_iter().map(|t| Line::styled(t, theme.dim())).collect();
    frame.render_widget(Paragraph::new(lines), text_area);
    // Each axis drawn from the corner of the lowest values to its highest, named at its end.
    let rot = m.camera.rotation();
    let at = |n: [f64; 3]| {
        let p = rot * nalgebra::Vector3::new(n[0], n[2], n[1]);
        (p.x, p.y)
    };
    let corner = at([-1.0, -1.0, -1.0]);
    let ends = [at([1.0, -1.0, -1.0]), at([-1.0, 1.0, -1.0]), at([-1.0, -1.0, 1.0])];
    let (xb, yb) = equal_bounds([-1.8, -1.8, 1.8, 1.8], canvas_area);
    let canvas = Canvas::default().marker(Marker::Braille).x_bounds(xb).y_bounds(yb).paint(|ctx| {
        for (k, e) in ends.iter().enumerate() {
            ctx.draw(&Segment2::new(corner.0, corner.1, e.0, e.1, theme.non_edge()));
            ctx.print(e.0, e.1, Line::styled(names[k].clone(), theme.dim()));
        }
        ctx.layer();
        for (k, pts) in &curve.runs {
            for w in pts.windows(2) {
                ctx.draw(&Segment2::new(w[0].0, w[0].1, w[1].0, w[1].1, theme.of_type(*k)));
            }
        }
        ctx.layer();
        // Markers tell the types apart without colour.
        for (k, pts) in &curve.runs {
            let stride = pts.len().div_ceil(MARKERS_PER_RUN).max(1);
            let marker = type_marker(*k);
            for p in pts.iter().skip(stride / 2).step_by(stride) {
                ctx.print(p.0, p.1, Line::styled(marker.clone(), Style::default().fg(theme.of_type(*k))));
            }
        }
        ctx.print(curve.here.0, curve.here.1, Line::styled("◎", theme.highlight()));
    });
    frame.render_widget(canvas, canvas_area);
}

/// `items` joined by `sep` into rows of at most `width` characters (an item
/// longer than a row gets a row of its own, wrapped).
fn pack(items: &[String], sep: &str, width: usize) -> Vec<String> {
    let mut rows: Vec<String> = Vec::new();
    let mut row = String::new();
    for it in items {
        let (used, len) = (row.chars().count(), it.chars().count());
        if used > 0 && used + sep.chars().count() + len > width {
            rows.push(std::mem::take(&mut row));
        }
        if !row.is_empty() {
            row.push_str(sep);
        }
        row.push_str(it);
    }
    if !row.is_empty() {
        rows.push(row);
    }
    rows.into_iter().flat_map(|r| wrap_words(&r, width)).collect()
}

/// The readout's fixed head (λ, the type, flat steps, the step) and its
/// Cayley-vector rows, for a panel `width` characters inside.
fn readout_lines(m: &Model, width: usize, theme: Theme) -> (Vec<Line<'static>>, Vec<Line<'static>>) {
    let l = &m.analysis().linkage;
    let here = m.current();
    let flat = m.flat_here();
    let drawn = m.solved().drawn.ty.to_string();
    let mut head = vec![Line::from(vec![Span::raw("λ    "), Span::styled(fmt_sig(here.lambda, 8), theme.highlight())])];
    head.extend(type_rows(&here.ty.to_string(), flat, &drawn, width, theme));
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
    head.extend(wrap_words(&format!("flat {flat_text}"), width).into_iter().map(Line::raw));
    head.push(Line::raw(format!("step {}{}", fmt_num(m.pace.step), if m.pace.playing { "  ▶ playing" } else { "" })));
    head.extend(m.drive_line().map(|d| Line::raw(format!("in   {d}"))));
    let v = &m.cursor.cayley;
    let ccv = m.solved().complexity.ccv.iter().enumerate().map(|(k, &[p, q])| {
        let name = format!("{}–{}", l.names[p], l.names[q]);
        Line::from(vec![Span::styled(format!("{name:<10}"), theme.dim()), Span::raw(fmt_sig(v[k], 6))])
    });
    (head, ccv.collect())
}

/// The type in the readout, every sign readable, the flat steps' signs
/// highlighted: up to [`present::TYPE_PLAIN`] signs on one line; up to
/// [`present::TYPE_GROUPED`] in groups of five, rows starting with their step
/// number; longer as the steps whose sign differs from the drawn type.
fn type_rows(ty: &str, flat: &[usize], drawn: &str, width: usize, theme: Theme) -> Vec<Line<'static>> {
    let signs: Vec<char> = ty.chars().collect();
    let n = signs.len();
    let sign = |k: usize| {
        let style = if flat.contains(&k) { theme.highlight() } else { theme.text() };
        Span::styled(signs[k].to_string(), style)
    };
    if n <= present::TYPE_PLAIN {
        let mut spans = vec![Span::raw("type ")];
        spans.extend((0..n).map(sign));
        return vec![Line::from(spans)];
    }
    if n > present::TYPE_GROUPED {
        let mut text = format!("type {}", present::type_against(ty, drawn));
        if let Some(&k) = flat.first() {
            text.push_str(&format!(" (step {} is {})", k + 1, signs[k]));
        }
        return wrap_words(&text, width).into_iter().map(Line::raw).collect();
    }
    // "type " then the first step's number, right-aligned, then groups of five.
    let num_w = n.to_string().len();
    let per_row = (width.saturating_sub(5 + num_w + 1) + 1) / 6;
    let per_row = per_row.max(1) * 5;
    (0..n)
        .step_by(per_row)
        .enumerate()
        .map(|(r, from)| {
            let mut spans = vec![
                Span::raw(if r == 0 { "type " } else { "     " }),
                Span::styled(format!("{:>num_w$} ", from + 1), theme.dim()),
            ];
            for k in from..(from + per_row).min(n) {
                if k > from && k % 5 == 0 {
                    spans.push(Span::styled("·", theme.dim()));
                }
                spans.push(sign(k));
            }
            Line::from(spans)
        })
        .collect()
}

/// "+N more" for a list showing `shown` of `total` rows from `first`, with the scroll keys.
fn more_note(first: usize, shown: usize, total: usize) -> String {
    let (above, below) = (first, total.saturating_sub(first + shown));
    match (above, below) {
        (0, b) => format!("+{b} more · }} scrolls"),
        (a, 0) => format!("+{a} more above · {{ scrolls"),
        (a, b) => format!("+{a} above, +{b} below · {{ }}"),
    }
}

/// The first row of a window of `rows` over `total`, `auto` moved by `scroll`, kept in range.
fn scrolled(auto: usize, scroll: isize, rows: usize, total: usize) -> usize {
    let max = total.saturating_sub(rows) as isize;
    (auto as isize + scroll).clamp(0, max.max(0)) as usize
}

fn draw_readout(frame: &mut Frame, m: &Model, area: Rect, theme: Theme) {
    let (mut lines, ccv) = readout_lines(m, usize::from(area.width.saturating_sub(2)), theme);
    let block = Block::bordered().title(Span::styled(" realization ", theme.title()));
    let rows = usize::from(area.height.saturating_sub(2));
    let block = append_scrolled(&mut lines, ccv, rows, m.scroll, block, theme);
    frame.render_widget(Paragraph::new(lines).block(block), area);
}

/// `list` after `lines`, in what is left of `rows`: whole when it fits,
/// else a window scrolled by `scroll` (`{` `}`) with the rest counted in the
/// bottom border of `block`, which is returned.
fn append_scrolled<'a>(
    lines: &mut Vec<Line<'a>>,
    list: Vec<Line<'a>>,
    rows: usize,
    scroll: isize,
    block: Block<'a>,
    theme: Theme,
) -> Block<'a> {
    let room = rows.saturating_sub(lines.len());
    if list.len() <= room {
        lines.extend(list);
        return block;
    }
    let first = scrolled(0, scroll, room, list.len());
    let n = list.len();
    lines.extend(list.into_iter().skip(first).take(room));
    block.title_bottom(Span::styled(format!(" {} ", more_note(first, room, n)), theme.dim()))
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
    // Lazily: the count so far in the title, how to walk more in the bottom
    // border (one title would not fit the 80-column layout's panel).
    let mut block = Block::bordered();
    if s.lazy {
        block = block
            .title(Span::styled(format!(" components ({n} walked) "), theme.title()))
            .title_bottom(Span::styled(" lazy · n walks more ", theme.dim()));
    } else {
        block = block.title(Span::styled(format!(" components ({n}) "), theme.title()));
    }
    frame.render_widget(Paragraph::new(lines).block(block), area);
}

fn draw_intervals(frame: &mut Frame, m: &Model, area: Rect, theme: Theme) {
    let s = m.solved();
    let union = &s.union;
    let (Some(first), Some(last)) = (union.first(), union.last()) else { return };
    let (lo, hi) = (first[0], last[1]);
    let n_steps = s.dec.steps.len();
    let inner = area.width.saturating_sub(2) as usize;
    // Types grouped in fives when they fit a third of the row, else against the drawn type.
    let drawn = s.drawn.ty.to_string();
    let label = |ty: &str| {
        let short = present::short_type(ty);
        if short.chars().count() <= inner / 3 || ty.chars().count() != drawn.chars().count() {
            short
        } else {
            present::type_against(ty, &drawn)
        }
    };
    let comp = &s.components.list[m.cursor.component];
    let labels: Vec<String> = comp.intervals.iter().map(|&i| label(&s.space.intervals[i].ty.to_string())).collect();
    let longest = labels.iter().map(|t| t.chars().count()).max().unwrap_or(0);
    let label_w = longest.max(n_steps.min(5)).clamp(5, (inner / 2).max(5));
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
    let rows = area.height.saturating_sub(3) as usize;
    let total = comp.intervals.len();
    let pos = comp.intervals.iter().position(|&i| i == cur_interval).unwrap_or(0);
    let auto = pos.saturating_sub(rows.saturating_sub(1) / 2).min(total.saturating_sub(rows));
    let start = scrolled(auto, m.scroll, rows, total);
    for (&i, ty) in comp.intervals.iter().zip(&labels).skip(start).take(rows) {
        let iv = &s.space.intervals[i];
        let current = i == cur_interval;
        let mut ty = ty.clone();
        if ty.chars().count() > label_w {
            // Only past half the row (six differing signs listed): said by the ellipsis.
            ty = format!("{}…", ty.chars().take(label_w - 1).collect::<String>());
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
            format!(
                "λ from {} to {} · {} oriented intervals ({total} here) ",
                fmt_num(lo),
                fmt_num(hi),
                s.space.intervals.len()
            ),
            theme.dim(),
        ),
    ]);
    let mut block = Block::bordered().title(title);
    if total > rows {
        block = block.title_bottom(Span::styled(format!(" {} ", more_note(start, rows, total)), theme.dim()));
    }
    frame.render_widget(Paragraph::new(lines).block(block), area);
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

/// The sweep in place of the drawing: the chart of components over the
/// parameter (with `▲` at its value now), then the transitions, which scroll
/// (`{` `}`) under a note saying how many more there are.
fn draw_sweep(frame: &mut Frame, app: &App, s: &SweepView, area: Rect, theme: Theme) {
    let scene = &app.doc.scene;
    let what = match s.swept {
        Swept::Bar(_) => format!("bar {} length", s.swept.name(scene)),
        Swept::Joint { .. } => format!("joint coordinate {}", s.swept.name(scene)),
    };
    let state = if s.pending { " · updating …" } else { "" };
    let width = usize::from(area.width.saturating_sub(2));
    let rows = usize::from(area.height.saturating_sub(2));
    // The title in full where it fits, else its essentials (long joint names).
    let title = [
        format!(" sweep of {what} · {} samples{state} · S hides ", s.steps),
        format!(" sweep of {}{state} · S hides ", s.swept.name(scene)),
        format!(" sweep{state} "),
    ]
    .into_iter()
    .find(|t| t.chars().count() <= width)
    .unwrap_or_default();
    let mut block = Block::bordered().title(Span::styled(title, theme.title()));
    let (mut lines, list): (Vec<Line>, Vec<Line>) = match (&s.error, &s.report) {
        (Some(e), _) => (vec![Line::styled(e.clone(), theme.warn())], Vec::new()),
        (None, None) => {
            let text = format!("sweeping from {} to {} …", present::full(s.from), present::full(s.to));
            (vec![Line::raw(text)], Vec::new())
        }
        (None, Some(r)) => {
            let mut chart = r.chart(width, app.swept_now());
            let (heading, bars) = if chart.is_empty() {
                (Vec::new(), 0)
            } else {
                // A long heading wraps; the bars fit by construction.
                let bars = chart.iter().skip(1).take_while(|l| l.contains(" |")).count();
                (wrap_words(&chart.remove(0), width), bars)
            };
            // Too tall (many components): the highest rows go, and the note says so;
            // the axis, the transition digits, ▲ and one row of the list stay.
            let room = rows.saturating_sub(heading.len() + usize::from(!r.transitions.is_empty()));
            let hidden = chart.len().saturating_sub(room).min(bars.saturating_sub(1));
            if hidden > 0 {
                chart.drain(..hidden);
                let note = format!(" the {hidden} highest rows of the chart are hidden: enlarge the terminal ");
                block = block.title_bottom(Span::styled(note, theme.warn()));
            }
            let chart = heading
                .into_iter()
                .chain(chart)
                .map(|l| if l.contains('▲') { Line::styled(l, theme.highlight()) } else { Line::raw(l) })
                .collect();
            let list = r
                .transition_lines()
                .iter()
                .flat_map(|l| {
                    let indent = l.len() - l.trim_start().len();
                    let rows = wrap_words(l.trim_start(), width.saturating_sub(indent + 2).max(8));
                    rows.into_iter()
                        .enumerate()
                        .map(move |(k, r)| format!("{}{r}", " ".repeat(if k == 0 { indent } else { indent + 2 })))
                })
                .map(Line::raw)
                .collect();
            (chart, list)
        }
    };
    if lines.len() > rows {
        // Still taller than the panel (a very small terminal): say so rather than cut silently.
        let more = lines.len() - rows;
        lines.truncate(rows);
        let note = format!(" +{more} more rows of the chart: enlarge the terminal ");
        block = block.title_bottom(Span::styled(note, theme.warn()));
    }
    let block = append_scrolled(&mut lines, list, rows, s.scroll, block, theme);
    frame.render_widget(Paragraph::new(lines).block(block), area);
}

/// The most rows the status line takes.
const STATUS_ROWS: usize = 3;

/// The status line, word-wrapped to `width` in at most [`STATUS_ROWS`] rows
/// (the last ending in `…` if even that is too short): the prompt, else a
/// message, a file error, the edit hint or the traces and marks.
fn status_lines(app: &App, width: usize, theme: Theme) -> Vec<Line<'static>> {
    let (text, style) = if let Some(input) = &app.input {
        let (label, enter) = match input.kind {
            PromptKind::GoTo => ("go to (λ or TYPE@λ): ".to_string(), "go"),
            PromptKind::Select => ("select (joint C or bar B-C): ".to_string(), "select"),
            PromptKind::Value => (format!("{} = ", app.item_name(app.item())), "set"),
            PromptKind::Sweep(swept) => {
                let what = match swept {
                    Swept::Bar(_) => format!("sweep {} length, FROM TO [STEPS]: ", swept.name(&app.doc.scene)),
                    Swept::Joint { joint, .. } => {
                        // The file may have lost the joint since the prompt opened (a reload).
                        let name = app.doc.scene.joints.get(joint).map_or("?", |j| j.name.as_str());
                        format!("sweep joint {name}, x|y FROM TO [STEPS]: ")
                    }
                };
                (what, "sweep")
            }
            PromptKind::Axes => ("curve axes (three CCV entries, e.g. A-C B-D): ".to_string(), "set"),
        };
        return vec![Line::from(vec![
            Span::styled(label, theme.key()),
            Span::raw(format!("{}▏", input.text)),
            Span::styled(format!("  Enter {enter} · Esc cancel"), theme.dim()),
        ])];
    } else if let Some(msg) = &app.message {
        (msg.clone(), theme.highlight())
    } else if let Some(e) = &app.file_error {
        (e.clone(), theme.warn())
    } else if app.editor.on {
        (
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
        let text = format!(
            "joint {} · traces {} [{}] {}",
            names[t.selected],
            if t.on { "on" } else { "off" },
            traced.join(","),
            marks.join(" · ")
        );
        (text, theme.dim())
    } else {
        (String::new(), theme.text())
    };
    let mut rows = wrap_words(&text, width.max(1));
    if rows.len() > STATUS_ROWS {
        rows.truncate(STATUS_ROWS);
        let last = &mut rows[STATUS_ROWS - 1];
        let keep = width.max(2) - 1;
        *last = format!("{}…", last.chars().take(keep).collect::<String>());
    }
    rows.into_iter().map(|r| Line::styled(r, style)).collect()
}

/// `text` in rows of at most `width` characters, broken at spaces (a word
/// longer than a row is broken inside); at least one row.
pub fn wrap_words(text: &str, width: usize) -> Vec<String> {
    let width = width.max(1);
    let mut rows: Vec<String> = Vec::new();
    let mut row = String::new();
    for word in text.split(' ') {
        let mut word: Vec<char> = word.chars().collect();
        let used = row.chars().count();
        if used > 0 && used + 1 + word.len() > width {
            rows.push(std::mem::take(&mut row));
        }
        if !row.is_empty() {
            row.push(' ');
        }
        while word.len() > width - row.chars().count() && !word.is_empty() {
            let room = width - row.chars().count();
            if room == 0 {
                rows.push(std::mem::take(&mut row));
                continue;
            }
            row.extend(word.drain(..room));
            rows.push(std::mem::take(&mut row));
        }
        row.extend(word);
    }
    if !row.is_empty() || rows.is_empty() {
        rows.push(row);
    }
    rows
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
    let rows_needed = rows.len() as u16 + 2;
    let columns: usize = if rows_needed <= area.height.saturating_sub(2) { 1 } else { 2 };
    let per_column = rows.len().div_ceil(columns);
    let w = if columns == 1 { 64 } else { 118 }.min(area.width.saturating_sub(2));
    // Up to the whole height: it covers the key bar, which it explains.
    let h = (per_column as u16 + 2).min(area.height);
    let rect = Rect { x: area.x + (area.width - w) / 2, y: area.y + (area.height - h) / 2, width: w, height: h };
    let col_w = (w.saturating_sub(2) as usize) / columns;
    // Every key of a row, as the key table has them; the column fits the longest.
    let key_w = rows.iter().map(|b| b.label().chars().count()).max().unwrap_or(0) + 1;
    let cell = |b: &Binding| -> Vec<Span<'static>> {
        let help: String = b.help.chars().take(col_w.saturating_sub(key_w + 2)).collect();
        let pad = col_w.saturating_sub(key_w + 1 + help.chars().count());
        vec![Span::styled(format!(" {:<key_w$}", b.label()), theme.key()), Span::raw(help), Span::raw(" ".repeat(pad))]
    };
    let lines: Vec<Line> = (0..per_column)
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
    let title = if mode == Mode::Edit { " keys while editing (m: explore) " } else { " keys (m: edit) " };
    frame.render_widget(Clear, rect);
    // How to close it sits in the bottom border: every row of the box is a key's.
    let shown = usize::from(h.saturating_sub(2));
    let closing = if per_column > shown {
        format!(" +{} rows more: enlarge the terminal · Esc or ? closes ", per_column - shown)
    } else {
        " Esc or ? closes this help · every key works over SSH ".to_string()
    };
    let block =
        Block::bordered().title(Span::styled(title, theme.title())).title_bottom(Span::styled(closing, theme.dim()));
    frame.render_widget(Paragraph::new(lines).block(block), rect);
}
