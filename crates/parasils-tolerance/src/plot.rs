//! A study's report as a picture (feature `plot`): the histogram of both
//! tips' largest deviations with the percentiles marked, and beside it the
//! sensitivity ranking as bars.

use std::path::Path;

use parasils_io::plot::{FONT, Figure, ImageFormat, PlotError, render_figure};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::report::Report;

/// The image size, pixels.
const SIZE: (u32, u32) = (1500, 800);

const LEFT: RGBColor = RGBColor(31, 119, 180);
const RIGHT: RGBColor = RGBColor(214, 39, 40);
const MARK: RGBColor = RGBColor(60, 60, 60);

/// Renders `report` to `out` in `format`; `note` (the robot's provenance,
/// the specification file) is printed under the title.
///
/// # Errors
/// [`PlotError::NoSamples`] when no robot was followed;
/// [`PlotError::Font`], [`PlotError::Render`] (I/O included).
pub fn render(
    report: &Report,
    note: &str,
    out: &Path,
    format: ImageFormat,
) -> Result<(), PlotError> {
    if report.samples == report.failed {
        return Err(PlotError::NoSamples);
    }
    render_figure(
        &Picture { report, note },
        out,
        format,
        SIZE,
        parasils_io::plot::Compression::Fast,
    )
}

struct Picture<'a> {
    report: &'a Report,
    note: &'a str,
}

impl Figure for Picture<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        draw(self.report, self.note, root)
    }
}

fn draw<DB: DrawingBackend>(
    report: &Report,
    note: &str,
    root: &DrawingArea<DB, Shift>,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let title = format!(
        "Tip deviation of {} perturbed robots ({} failed)",
        report.samples, report.failed
    );
    let root = root
        .titled(&title, (FONT, 26).into_font().style(FontStyle::Bold))
        .map_err(e)?;
    let root = root
        .titled(note, (FONT, 16).into_font().color(&MARK))
        .map_err(e)?;
    let (hist, rank) = root.split_horizontally(SIZE.0 - 520);
    let h = &report.histogram;
    let top = h.edges_mm.last().copied().unwrap_or(1.0);
    let width = top / h.left.len().max(1) as f64;
    let peak = h
        .left
        .iter()
        .chain(&h.right)
        .copied()
        .max()
        .unwrap_or(1)
        .max(1);
    let mut chart = ChartBuilder::on(&hist)
        .margin(20)
        .x_label_area_size(55)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..top * 1.12, 0.0..peak as f64 * 1.12)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(
            "largest deviation from the commanded tip over the motion (mm); lines: percentiles \
             of the larger of both",
        )
        .y_desc("robots")
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .light_line_style(WHITE)
        .draw()
        .map_err(e)?;
    for (counts, color, label, shift) in [
        (&h.left, LEFT, "left tip", 0.0),
        (&h.right, RIGHT, "right tip", 0.5),
    ] {
        chart
            .draw_series(counts.iter().enumerate().map(|(k, &c)| {
                let x0 = h.edges_mm[k] + shift * width;
                Rectangle::new(
                    [(x0, 0.0), (x0 + 0.5 * width, c as f64)],
                    color.mix(0.8).filled(),
                )
            }))
            .map_err(e)?
            .label(label)
            .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], color.filled()));
    }
    // The percentiles of the larger of both tips, labelled at staggered
    // heights so that close ones stay readable.
    for (k, (p, v)) in report.tip.percentiles.iter().enumerate() {
        let y = peak as f64 * (1.08 - 0.06 * k as f64);
        chart
            .draw_series(LineSeries::new([(*v, 0.0), (*v, y)], MARK.stroke_width(1)))
            .map_err(e)?;
        chart
            .draw_series([Text::new(
                format!(" p{p} {v:.3} mm"),
                (*v, y),
                (FONT, 14).into_font().color(&MARK),
            )])
            .map_err(e)?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::MiddleRight)
        .label_font((FONT, 16))
        .background_style(WHITE.mix(0.9))
        .border_style(MARK)
        .draw()
        .map_err(e)?;
    draw_ranking(report, &rank)
}

/// The sensitivity ranking: a bar per family, its share of the mean-square
/// tip deviation.
fn draw_ranking<DB: DrawingBackend>(
    report: &Report,
    area: &DrawingArea<DB, Shift>,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let area = area
        .titled(
            "which tolerance to tighten (first order)",
            (FONT, 18).into_font().style(FontStyle::Bold),
        )
        .map_err(e)?;
    let ranking = &report.sensitivity;
    if ranking.is_empty() {
        return Ok(());
    }
    let n = ranking.len();
    let mut chart = ChartBuilder::on(&area)
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(10)
        .build_cartesian_2d(0.0..100.0, 0.0..n as f64)
        .map_err(e)?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .disable_y_axis()
        .x_desc("share of the mean-square tip deviation (%)")
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .light_line_style(WHITE)
        .draw()
        .map_err(e)?;
    for (k, s) in ranking.iter().enumerate() {
        let y = (n - 1 - k) as f64;
        let share = 100.0 * s.share;
        chart
            .draw_series([Rectangle::new(
                [(0.0, y + 0.15), (share, y + 0.85)],
                RGBColor(120, 150, 190).filled(),
            )])
            .map_err(e)?;
        let label = format!("{}  {share:.1}%", s.family.key());
        chart
            .draw_series([Text::new(
                label,
                (1.0, y + 0.62),
                (FONT, 14).into_font().color(&BLACK),
            )])
            .map_err(e)?;
    }
    Ok(())
}
