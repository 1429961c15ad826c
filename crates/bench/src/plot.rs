//! SVG line charts with plotters. The SVG backend writes `<text>` elements and leaves the
//! glyphs to whatever shows the file; plotters' built-in font code only estimates label sizes
//! for the layout, so no font file is read or shipped.

use std::path::Path;

use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;

/// One line of a chart: its legend label and its points, in x order.
pub struct Series {
    /// Legend label.
    pub label: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// Drawn thicker (the total, as against its parts).
    pub bold: bool,
}

/// What a chart shows.
pub struct Chart<'a> {
    /// Title above the plot.
    pub title: &'a str,
    /// X axis label.
    pub x_label: &'a str,
    /// Y axis label.
    pub y_label: &'a str,
    /// Lines.
    pub series: &'a [Series],
}

const SIZE: (u32, u32) = (900, 560);

/// Colours that stay apart on a white page (Okabe–Ito, then greys).
const COLOURS: [RGBColor; 9] = [
    RGBColor(0, 0, 0),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 158, 115),
    RGBColor(213, 94, 0),
    RGBColor(0, 114, 178),
    RGBColor(204, 121, 167),
    RGBColor(170, 170, 0),
    RGBColor(120, 120, 120),
];

fn bounds(series: &[Series]) -> ((f64, f64), (f64, f64)) {
    let points = series.iter().flat_map(|s| s.points.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in points.filter(|(x, y)| x.is_finite() && y.is_finite()) {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if x0 > x1 {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    ((x0, x1), (y0, y1))
}

/// A chart with linear axes; y starts at 0.
pub fn linear(path: &Path, chart: &Chart<'_>) -> Result<()> {
    let ((x0, x1), (_, y1)) = bounds(chart.series);
    let (x0, x1) = if x1 > x0 {
        (x0, x1)
    } else {
        (x0 - 0.5, x1 + 0.5)
    };
    let y1 = if y1 > 0.0 { y1 * 1.08 } else { 1.0 };
    draw(path, chart, x0..x1, 0.0..y1, |x| {
        if x.fract() == 0.0 {
            format!("{x:.0}")
        } else {
            String::new()
        }
    })
}

/// A chart with logarithmic axes.
pub fn log_log(path: &Path, chart: &Chart<'_>) -> Result<()> {
    let ((x0, x1), (y0, y1)) = bounds(chart.series);
    let x0 = x0.max(1e-9);
    let y0 = y0.max(1e-6);
    let (x0, x1) = (x0 / 1.15, x1.max(x0) * 1.15);
    let (y0, y1) = (y0 / 1.5, y1.max(y0) * 1.5);
    draw(
        path,
        chart,
        (x0..x1).log_scale(),
        (y0..y1).log_scale(),
        |x| format!("{x:.0}"),
    )
}

fn draw<X, Y>(
    path: &Path,
    chart: &Chart<'_>,
    x_range: X,
    y_range: Y,
    x_format: impl Fn(&f64) -> String,
) -> Result<()>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    draw_on(&root, chart, x_range, y_range, x_format)
        .map_err(|e| anyhow!("cannot draw {}: {e}", path.display()))?;
    root.present()
        .map_err(|e| anyhow!("cannot write {}: {e}", path.display()))?;
    Ok(())
}

fn draw_on<X, Y>(
    root: &DrawingArea<SVGBackend<'_>, Shift>,
    chart: &Chart<'_>,
    x_range: X,
    y_range: Y,
    x_format: impl Fn(&f64) -> String,
) -> Result<(), Box<dyn std::error::Error + Send + Sync>>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    root.fill(&WHITE)?;
    let mut ctx = ChartBuilder::on(root)
        .caption(chart.title, ("sans-serif", 22))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(x_range, y_range)?;
    ctx.configure_mesh()
        .x_desc(chart.x_label)
        .y_desc(chart.y_label)
        .x_label_formatter(&x_format)
        .y_label_formatter(&|y| format_value(*y))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    for (i, series) in chart.series.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let width = if series.bold { 3 } else { 2 };
        let style = colour.stroke_width(width);
        let points: Vec<(f64, f64)> = series
            .points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect();
        ctx.draw_series(LineSeries::new(points.clone(), style))?
            .label(series.label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        ctx.draw_series(
            points
                .into_iter()
                .map(move |p| Circle::new(p, 3, colour.filled())),
        )?;
    }
    ctx.configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font(("sans-serif", 14))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(180, 180, 180))
        .draw()?;
    Ok(())
}

/// A tick label: three significant digits, no trailing noise.
fn format_value(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if a >= 100.0 {
        format!("{v:.0}")
    } else if a >= 10.0 {
        format!("{v:.1}")
    } else if a >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
}
