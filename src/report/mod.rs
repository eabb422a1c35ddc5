//! Data for the figures and the stability table (`dalembert figures`, `dalembert stability`;
//! [spec/09-report.md](crate::spec::report)). This module only computes: the command line renders the data
//! (`src/cli/render.rs` writes SVG with plotters and CSV; `src/cli/stability.rs` prints the
//! Markdown table or JSON). Long computations report progress through a [`Progress`].

pub mod figures;
pub mod orders;
pub mod stability;

pub use crate::progress::Progress;
use crate::Interval;

/// A figure: one or more panels side by side, and the data as tables (one CSV file each).
#[derive(Clone, Debug)]
pub struct Figure {
    /// File stem: `<name>.svg`, and `<name>.csv` or `<name>_<table>.csv`.
    pub name: String,
    /// What is plotted, in words (shown under the panels).
    pub caption: String,
    /// The charts, left to right.
    pub panels: Vec<Panel>,
    /// The data, one CSV file per table.
    pub tables: Vec<Table>,
}

/// One chart.
#[derive(Clone, Debug)]
pub struct Panel {
    /// The chart's title.
    pub title: String,
    /// Label of the x axis.
    pub x_label: String,
    /// Label of the y axis.
    pub y_label: String,
    /// Logarithmic x axis.
    pub x_log: bool,
    /// Logarithmic y axis.
    pub y_log: bool,
    /// The series drawn in this chart.
    pub series: Vec<Series>,
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A solid line through the points.
    Line,
    /// A dashed line through the points.
    Dashed,
    /// A marker at each point, no line.
    Markers,
    /// A solid line with a marker at each point.
    LineMarkers,
}

/// A named list of points `(x, y)`.
#[derive(Clone, Debug)]
pub struct Series {
    /// The legend's text.
    pub label: String,
    /// How the series is drawn.
    pub style: Style,
    /// The points `(x, y)`, in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Index into the renderer's palette (default: the series' position in its panel).
    pub color: Option<usize>,
    /// Empty, or the lower ends of vertical error bars, one per point, each drawn from the
    /// point (the upper end) down to it.
    pub lower: Vec<f64>,
    /// Empty, or one text per point, written beside it.
    pub labels: Vec<String>,
}

/// Numbers with a header; `name` is empty for a figure's only table.
#[derive(Clone, Debug)]
pub struct Table {
    /// The CSV file is `<figure>_<name>.csv`; empty: `<figure>.csv`.
    pub name: String,
    /// The column names.
    pub header: Vec<String>,
    /// The rows, one number per column.
    pub rows: Vec<Vec<f64>>,
}

impl Series {
    /// A series with the palette's colour for its position and no error bars.
    pub fn new(label: impl Into<String>, style: Style, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: label.into(),
            style,
            points,
            color: None,
            lower: Vec::new(),
            labels: Vec::new(),
        }
    }
    /// The same colour as another series (e.g. two forms of one curve).
    pub fn color(mut self, index: usize) -> Self {
        self.color = Some(index);
        self
    }
    /// Error bars: each point `(x, y)` is the upper end of an interval `[lower[i], y]`.
    pub fn lower(mut self, lower: Vec<f64>) -> Self {
        assert_eq!(lower.len(), self.points.len(), "one lower end per point");
        self.lower = lower;
        self
    }
    /// A text beside each point (e.g. the parameter that the point was computed at).
    pub fn labels(mut self, labels: Vec<String>) -> Self {
        assert_eq!(labels.len(), self.points.len(), "one label per point");
        self.labels = labels;
        self
    }
}

impl Table {
    /// An empty table with these column names.
    pub fn new(name: &str, header: &[&str]) -> Self {
        Table {
            name: name.to_string(),
            header: header.iter().map(|s| s.to_string()).collect(),
            rows: Vec::new(),
        }
    }
}

/// Points of f64 values as thin intervals.
pub(crate) fn points(v: &[f64]) -> Vec<Interval> {
    v.iter().map(|x| Interval::point(*x)).collect()
}

/// The largest width of a list of intervals.
pub(crate) fn max_width<'a>(v: impl IntoIterator<Item = &'a Interval>) -> f64 {
    v.into_iter().fold(0.0, |a, x| a.max(x.wid()))
}
