//! Rendering of `crate::report` figures: SVG with plotters (pure Rust, text as SVG
//! `<text>`) and CSV. Drawing only; the data are computed in `src/report/`.

use crate::report::{Figure, Panel, Style, Table};
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

const PANEL: (u32, u32) = (640, 460);
const CAPTION_LINE: u32 = 18;
const CAPTION_CHARS: usize = 110;

fn err(e: impl std::fmt::Display) -> String {
    format!("cannot draw the figure: {e}")
}

/// Write `<dir>/<name>.svg` and one CSV per table; returns the paths written.
pub fn write_figure(fig: &Figure, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut written = vec![];
    let svg = dir.join(format!("{}.svg", fig.name));
    write_svg(fig, &svg)?;
    written.push(svg);
    for t in &fig.tables {
        let stem = if t.name.is_empty() {
            fig.name.clone()
        } else {
            format!("{}_{}", fig.name, t.name)
        };
        let path = dir.join(format!("{stem}.csv"));
        std::fs::write(&path, csv(t))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        written.push(path);
    }
    Ok(written)
}

/// A number for CSV and tables: plain decimals for moderate magnitudes, otherwise scientific notation
/// (both shortest round-trip forms).
pub fn number(x: f64) -> String {
    if x == 0.0 {
        "0".to_string()
    } else if (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

fn csv(t: &Table) -> String {
    let mut out = t.header.join(",");
    out.push('\n');
    for row in &t.rows {
        let cells: Vec<String> = row.iter().map(|x| number(*x)).collect();
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    out
}

/// Words of `text` in lines of at most `width` characters.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = vec![];
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.len() + 1 + word.len() > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    lines.push(line);
    lines
}

fn write_svg(fig: &Figure, path: &Path) -> Result<(), String> {
    let n = fig.panels.len().max(1) as u32;
    let width = PANEL.0 * n;
    let caption = wrap(&fig.caption, CAPTION_CHARS * n as usize);
    let caption_h = CAPTION_LINE * (caption.len() as u32 + 1);
    let root = SVGBackend::new(path, (width, PANEL.1 + caption_h)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let (charts, below) = root.split_vertically(PANEL.1);
    for (area, p) in charts.split_evenly((1, n as usize)).iter().zip(&fig.panels) {
        draw_panel(area, p)?;
    }
    for (i, line) in caption.iter().enumerate() {
        let y = (CAPTION_LINE * (i as u32 + 1)) as i32 - 4;
        below
            .draw(&Text::new(line.as_str(), (12, y), ("sans-serif", 13)))
            .map_err(err)?;
    }
    root.present().map_err(err)
}

/// The range of the finite values (positive ones on a log axis), padded.
fn range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && (!log || *v > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if lo > hi {
        return if log { (0.1, 10.0) } else { (-1.0, 1.0) };
    }
    if log {
        let (a, b) = (lo.log10().floor(), hi.log10().ceil());
        let b = if b <= a { a + 1.0 } else { b };
        (10f64.powf(a), 10f64.powf(b))
    } else {
        let pad = if hi > lo {
            0.05 * (hi - lo)
        } else {
            0.5 * lo.abs().max(1e-300)
        };
        (lo - pad, hi + pad)
    }
}

fn draw_panel(area: &Area, p: &Panel) -> Result<(), String> {
    let all = || p.series.iter().flat_map(|s| s.points.iter());
    let (x0, x1) = range(all().map(|q| q.0), p.x_log);
    // The lower ends of error bars count too.
    let lower = p.series.iter().flat_map(|s| s.lower.iter().copied());
    let (y0, y1) = range(all().map(|q| q.1).chain(lower), p.y_log);
    let frame = Frame {
        x: (x0, x1),
        y: (y0, y1),
    };
    let log = |lo: f64, hi: f64| (lo..hi).log_scale().with_key_points(decades(lo, hi));
    match (p.x_log, p.y_log) {
        (false, false) => chart(area, p, &frame, x0..x1, y0..y1),
        (false, true) => chart(area, p, &frame, x0..x1, log(y0, y1)),
        (true, false) => chart(area, p, &frame, log(x0, x1), y0..y1),
        (true, true) => chart(area, p, &frame, log(x0, x1), log(y0, y1)),
    }
}

/// The labelled ticks of a log axis from `lo` to `hi` (powers of ten, from `range`): every
/// `c`-th power of ten from the lowest, `c` the least with at most ten ticks, as plotters
/// chooses them; given explicitly because plotters leaves out ticks below `f64::EPSILON`
/// (it takes them for its zero point).
fn decades(lo: f64, hi: f64) -> Vec<f64> {
    let a = (lo.log10() - 1e-9).ceil() as i32;
    let b = (hi.log10() + 1e-9).floor() as i32;
    let n = (b - a).max(1);
    let step = (1..).find(|c| n / c <= 10).unwrap_or(n);
    (a..=b)
        .step_by(step as usize)
        .map(|k| 10f64.powi(k))
        .collect()
}

/// The drawn ranges of a panel.
struct Frame {
    x: (f64, f64),
    y: (f64, f64),
}

impl Frame {
    /// A point's position in the frame, in [0, 1]^2 (log axes in decades).
    fn unit(&self, p: &Panel, (a, b): (f64, f64)) -> (f64, f64) {
        let f = |v: f64, (lo, hi): (f64, f64), log: bool| {
            if log {
                (v.log10() - lo.log10()) / (hi.log10() - lo.log10())
            } else {
                (v - lo) / (hi - lo)
            }
        };
        (f(a, self.x, p.x_log), f(b, self.y, p.y_log))
    }

    /// The corner for the legend: the one that covers the fewest points.
    fn legend_corner(&self, p: &Panel) -> SeriesLabelPosition {
        let pts: Vec<(f64, f64)> = p
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .map(|q| self.unit(p, *q))
            .collect();
        let count = |left: bool, upper: bool| {
            pts.iter()
                .filter(|(x, y)| {
                    (if left { *x < 0.45 } else { *x > 0.55 })
                        && (if upper { *y > 0.6 } else { *y < 0.4 })
                })
                .count()
        };
        [
            (count(true, true), SeriesLabelPosition::UpperLeft),
            (count(false, true), SeriesLabelPosition::UpperRight),
            (count(true, false), SeriesLabelPosition::LowerLeft),
            (count(false, false), SeriesLabelPosition::LowerRight),
        ]
        .into_iter()
        .min_by_key(|(n, _)| *n)
        .map(|(_, c)| c)
        .unwrap_or(SeriesLabelPosition::UpperLeft)
    }
}

/// A tick label; on a linear axis spanning `span`, rounding noise around 0 prints as 0.
fn axis_label(v: f64, log: bool, span: f64) -> String {
    if log {
        format!("{v:.0e}")
    } else if v.abs() <= 1e-9 * span {
        "0".to_string()
    } else if v.abs() < 1e-3 || v.abs() >= 1e5 {
        format!("{v:.1e}")
    } else {
        format!("{v:.3}")
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    }
}

fn chart<X, Y>(area: &Area, p: &Panel, frame: &Frame, x: X, y: Y) -> Result<(), String>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut c = ChartBuilder::on(area)
        .caption(&p.title, ("sans-serif", 16))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x, y)
        .map_err(err)?;
    let (xl, yl) = (p.x_log, p.y_log);
    let (sx, sy) = (frame.x.1 - frame.x.0, frame.y.1 - frame.y.0);
    let fx = move |v: &f64| axis_label(*v, xl, sx);
    let fy = move |v: &f64| axis_label(*v, yl, sy);
    c.configure_mesh()
        .x_desc(p.x_label.as_str())
        .y_desc(p.y_label.as_str())
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .light_line_style(WHITE)
        .draw()
        .map_err(err)?;
    for (i, s) in p.series.iter().enumerate() {
        let color = PALETTE[s.color.unwrap_or(i) % PALETTE.len()];
        // Points that a log axis cannot show are left out.
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|(a, b)| {
                a.is_finite() && b.is_finite() && (!xl || *a > 0.0) && (!yl || *b > 0.0)
            })
            .collect();
        let style = ShapeStyle::from(color).stroke_width(2);
        let legend = move |(x, y): (i32, i32)| PathElement::new([(x, y), (x + 18, y)], style);
        let anno = match s.style {
            Style::Line | Style::LineMarkers => c
                .draw_series(LineSeries::new(pts.clone(), style))
                .map_err(err)?,
            Style::Dashed => c
                .draw_series(DashedLineSeries::new(pts.clone(), 8, 5, style))
                .map_err(err)?,
            Style::Markers => c
                .draw_series(pts.iter().map(|q| Circle::new(*q, 4, color.filled())))
                .map_err(err)?,
        };
        if !s.label.is_empty() {
            anno.label(s.label.as_str()).legend(legend);
        }
        if s.style == Style::LineMarkers {
            c.draw_series(pts.iter().map(|q| Circle::new(*q, 2, color.filled())))
                .map_err(err)?;
        }
        // Each shown point's text, above and to the right of it.
        let texts = s.points.iter().zip(&s.labels).filter(|((a, b), _)| {
            a.is_finite() && b.is_finite() && (!xl || *a > 0.0) && (!yl || *b > 0.0)
        });
        c.draw_series(texts.map(|(&q, text)| {
            EmptyElement::at(q) + Text::new(text.clone(), (5, -14), ("sans-serif", 11))
        }))
        .map_err(err)?;
        // Error bars from each shown point down to its lower end (on a log axis, a lower end
        // at or below 0 is drawn at the bottom of the frame).
        let bar = ShapeStyle::from(color).stroke_width(1);
        let bottom = frame.y.0;
        let bars = s.points.iter().zip(&s.lower).filter(|((a, b), lo)| {
            a.is_finite()
                && b.is_finite()
                && lo.is_finite()
                && (!xl || *a > 0.0)
                && (!yl || *b > 0.0)
        });
        c.draw_series(bars.map(|(&(a, b), &lo)| {
            let lo = if yl && lo <= 0.0 { bottom } else { lo.min(b) };
            ErrorBar::new_vertical(a, lo, b, b, bar, 6)
        }))
        .map_err(err)?;
    }
    c.configure_series_labels()
        .position(frame.legend_corner(p))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 12))
        .draw()
        .map_err(err)?;
    Ok(())
}
