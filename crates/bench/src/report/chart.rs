//! One SVG per case: ms per step across, error up, one panel per plotted metric; each engine's
//! points (labelled with their setting; filled when the run passes the case, hollow when it
//! fails) and its Pareto front (the points no cheaper point beats) as a line; the pass bound as
//! a dashed line. A panel's front leaves out runs that fail the case on another metric, so
//! that, say, a column that fell over does not make the front for overlap. Axes turn
//! logarithmic when the values span more than a factor of 20, and then start at a power of
//! ten; zeros are drawn on the bottom edge.

use std::path::Path;

use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;

/// One point of a panel.
pub struct ChartPoint {
    /// ms per step.
    pub ms: f64,
    /// The panel's metric (non-finite values are left out).
    pub error: f64,
    /// Short setting label.
    pub label: String,
    /// The run passes the case.
    pub pass: bool,
    /// The run may be on the front: it meets every bound but this panel's own.
    pub on_front: bool,
}

/// One engine's points in a panel.
pub struct EngineSeries {
    /// "tumble", "Box2D", "Rapier".
    pub name: String,
    /// Its points.
    pub points: Vec<ChartPoint>,
}

/// One panel: one metric against ms per step.
pub struct Panel {
    /// Y axis label.
    pub y_label: String,
    /// The pass bound, drawn dashed.
    pub bound: Option<f64>,
    /// Per engine.
    pub series: Vec<EngineSeries>,
}

/// Colours (Okabe–Ito): tumble black, Box2D orange, Rapier blue.
const COLOURS: [RGBColor; 3] = [
    RGBColor(0, 0, 0),
    RGBColor(213, 94, 0),
    RGBColor(0, 114, 178),
];

/// The points of `points` that no cheaper (or equally cheap) point beats, in ms order.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut sorted: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut front: Vec<(f64, f64)> = Vec::new();
    for p in sorted {
        if front.last().is_none_or(|last| p.1 < last.1) {
            front.push(p);
        }
    }
    front
}

/// Writes the chart of a case.
pub fn write(path: &Path, title: &str, panels: &[Panel]) -> Result<()> {
    let width = 120 + 780 * panels.len().max(1) as u32;
    let root = SVGBackend::new(path, (width, 580)).into_drawing_area();
    draw(&root, title, panels).map_err(|e| anyhow!("cannot draw {}: {e}", path.display()))?;
    root.present()
        .map_err(|e| anyhow!("cannot write {}: {e}", path.display()))?;
    Ok(())
}

type DrawResult = Result<(), Box<dyn std::error::Error + Send + Sync>>;

fn draw(root: &DrawingArea<SVGBackend<'_>, Shift>, title: &str, panels: &[Panel]) -> DrawResult {
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 22))?;
    let areas = root.split_evenly((1, panels.len().max(1)));
    for (area, panel) in areas.iter().zip(panels) {
        draw_panel(area, panel)?;
    }
    Ok(())
}

/// Finite x, and y values; the y floor for a log axis (zeros are drawn there).
fn ranges(panel: &Panel) -> ((f64, f64), (f64, f64), f64) {
    let mut x = (f64::MAX, f64::MIN);
    let mut y = (f64::MAX, f64::MIN);
    let mut y_pos = f64::MAX;
    for s in &panel.series {
        for p in &s.points {
            let (px, py) = (p.ms, p.error);
            if !(px.is_finite() && py.is_finite()) {
                continue;
            }
            x = (x.0.min(px), x.1.max(px));
            y = (y.0.min(py), y.1.max(py));
            if py > 0.0 {
                y_pos = y_pos.min(py);
            }
        }
    }
    if let Some(b) = panel.bound {
        y = (y.0.min(b), y.1.max(b));
        y_pos = y_pos.min(b);
    }
    if x.0 > x.1 {
        x = (0.001, 1.0);
    }
    if y.0 > y.1 {
        y = (0.0, 1.0);
    }
    if y_pos == f64::MAX {
        y_pos = 1e-6;
    }
    (x, y, y_pos)
}

fn draw_panel(area: &DrawingArea<SVGBackend<'_>, Shift>, panel: &Panel) -> DrawResult {
    let ((x0, x1), (y0, y1), y_pos) = ranges(panel);
    let x_log = x0 > 0.0 && x1 / x0 > 20.0;
    let y_log = y1 > 0.0 && y1 / y_pos > 20.0;
    // A log axis starts at a power of ten, for plotters labels it from the first one up (just
    // under it: plotters rounds the start's logarithm up).
    let decade = |v: f64| 0.999 * 10f64.powf(v.log10().floor());
    let (xa, xb) = if x_log {
        (decade(x0 / 1.3), x1 * 1.3)
    } else {
        let pad = 0.08 * (x1 - x0).max(0.1 * x1.abs()).max(1e-6);
        ((x0 - pad).max(0.0), x1 + pad)
    };
    let (ya, yb, floor) = if y_log {
        let floor = decade(y_pos / 3.0);
        (floor, y1 * 3.0, floor)
    } else {
        let ya = y0.min(0.0);
        (ya, if y1 > 0.0 { y1 * 1.12 } else { 1.0 }, ya)
    };
    // Where a point falls across the plot, 0 to 1 on each axis.
    let unit = |v: f64, a: f64, b: f64, log: bool| {
        if log {
            (v.max(a).ln() - a.ln()) / (b.ln() - a.ln())
        } else {
            (v - a) / (b - a)
        }
    };
    let points: Vec<(f64, f64)> = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.ms.is_finite() && p.error.is_finite())
        .map(|p| {
            (
                unit(p.ms, xa, xb, x_log),
                unit(p.error.abs().max(floor), ya, yb, y_log),
            )
        })
        .collect();
    let legend = legend_corner(&points);
    let logs = (x_log, y_log);
    match logs {
        (true, true) => body(
            area,
            panel,
            (xa..xb).log_scale(),
            (ya..yb).log_scale(),
            floor,
            legend,
            logs,
        ),
        (false, true) => body(
            area,
            panel,
            xa..xb,
            (ya..yb).log_scale(),
            floor,
            legend,
            logs,
        ),
        (true, false) => body(
            area,
            panel,
            (xa..xb).log_scale(),
            ya..yb,
            floor,
            legend,
            logs,
        ),
        (false, false) => body(area, panel, xa..xb, ya..yb, floor, legend, logs),
    }
}

/// The corner of the plot whose box (the legend's size, about 40% across and 25% up) holds
/// the fewest points, upper right first on a tie.
fn legend_corner(points: &[(f64, f64)]) -> SeriesLabelPosition {
    let corners = [
        (SeriesLabelPosition::UpperRight, (0.6, 1.0), (0.75, 1.0)),
        (SeriesLabelPosition::UpperLeft, (0.0, 0.4), (0.75, 1.0)),
        (SeriesLabelPosition::LowerRight, (0.6, 1.0), (0.0, 0.25)),
        (SeriesLabelPosition::LowerLeft, (0.0, 0.4), (0.0, 0.25)),
    ];
    let count = |(x0, x1): (f64, f64), (y0, y1): (f64, f64)| {
        points
            .iter()
            .filter(|(x, y)| *x >= x0 && *x <= x1 && *y >= y0 && *y <= y1)
            .count()
    };
    let mut best = (usize::MAX, SeriesLabelPosition::UpperRight);
    for (pos, xs, ys) in corners {
        let n = count(xs, ys);
        if n < best.0 {
            best = (n, pos);
        }
    }
    best.1
}

fn body<X, Y>(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    panel: &Panel,
    x_range: X,
    y_range: Y,
    floor: f64,
    legend: SeriesLabelPosition,
    logs: (bool, bool),
) -> DrawResult
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut ctx = ChartBuilder::on(area)
        .margin(14)
        .x_label_area_size(46)
        .y_label_area_size(70)
        .build_cartesian_2d(x_range, y_range)?;
    let (x_log, y_log) = logs;
    ctx.configure_mesh()
        .x_labels(16)
        .y_labels(12)
        .max_light_lines(1)
        .x_desc("ms per step (1 thread)")
        .y_desc(panel.y_label.as_str())
        .x_label_formatter(&|x| tick(*x, x_log))
        .y_label_formatter(&|y| tick(*y, y_log))
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 15))
        .light_line_style(RGBColor(236, 236, 236))
        .draw()?;
    let (xr, _) = (ctx.x_range(), ctx.y_range());
    if let Some(b) = panel.bound {
        let style = RGBColor(0, 158, 115).stroke_width(2);
        ctx.draw_series(DashedLineSeries::new(
            vec![(xr.start, b), (xr.end, b)],
            8,
            5,
            style,
        ))?
        .label(format!("pass bound {}", format_value(b)))
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
    }
    for (k, s) in panel.series.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        let pts: Vec<(f64, f64, &ChartPoint)> = s
            .points
            .iter()
            .filter(|p| p.ms.is_finite() && p.error.is_finite())
            .map(|p| (p.ms, p.error.abs().max(floor), p))
            .collect();
        let front = pareto_front(
            &pts.iter()
                .filter(|(_, _, p)| p.on_front)
                .map(|(x, y, _)| (*x, *y))
                .collect::<Vec<_>>(),
        );
        let line = colour.stroke_width(2);
        ctx.draw_series(LineSeries::new(front, line))?
            .label(format!("{} (Pareto front)", s.name))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], line));
        let font = ("sans-serif", 11).into_font().color(&colour);
        ctx.draw_series(pts.iter().map(|(x, y, p)| {
            let style = if p.pass {
                colour.filled()
            } else {
                colour.stroke_width(1)
            };
            let triangle = vec![(0, -5), (-5, 4), (5, 4), (0, -5)];
            let marker: DynElement<'_, SVGBackend<'_>, (i32, i32)> = match (k, p.pass) {
                (0, _) => Circle::new((0, 0), 4, style).into_dyn(),
                (1, true) => Polygon::new(triangle, style).into_dyn(),
                (1, false) => PathElement::new(triangle, style).into_dyn(),
                _ => Rectangle::new([(-4, -4), (4, 4)], style).into_dyn(),
            };
            EmptyElement::at((*x, *y)) + marker + Text::new(p.label.clone(), (6, -14), font.clone())
        }))?;
    }
    ctx.configure_series_labels()
        .position(legend)
        .label_font(("sans-serif", 13))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(180, 180, 180))
        .draw()?;
    Ok(())
}

/// A tick label; on a log axis only at 1, 2 and 5 times a power of ten, so that the labels
/// of a decade do not run into each other (and a decade's end, 9.999… times the power below,
/// is not labelled twice).
fn tick(v: f64, log: bool) -> String {
    if log && v > 0.0 {
        let mantissa = v / 10f64.powf(v.log10().floor());
        let round = mantissa.round();
        if (mantissa - round).abs() > 0.01 || ![1.0, 2.0, 5.0].contains(&round) {
            return String::new();
        }
    }
    format_value(v)
}

/// A tick label: three significant digits.
fn format_value(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if a >= 100.0 {
        format!("{v:.0}")
    } else if a >= 1.0 {
        let s = format!("{v:.2}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else if a >= 0.001 {
        let digits = (2 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.digits$}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.0e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn front_keeps_what_no_cheaper_point_beats() {
        let pts = [(1.0, 5.0), (2.0, 6.0), (3.0, 1.0), (4.0, 1.0), (0.5, 9.0)];
        assert_eq!(pareto_front(&pts), vec![(0.5, 9.0), (1.0, 5.0), (3.0, 1.0)]);
        assert!(pareto_front(&[(f64::NAN, 1.0)]).is_empty());
    }

    #[test]
    fn tick_labels() {
        assert_eq!(format_value(0.0), "0");
        assert_eq!(format_value(1.5), "1.5");
        assert_eq!(format_value(0.0123), "0.0123");
        assert_eq!(format_value(250.0), "250");
        assert_eq!(tick(0.002, true), "0.002");
        assert_eq!(tick(0.003, true), "");
        assert_eq!(tick(0.003, false), "0.003");
    }
}
