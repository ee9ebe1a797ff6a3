//! A reach map as a picture (feature `plot`): the margin as a banded heat
//! map on the feasible cells, a colour per limiting constraint outside, the
//! boundary, the start marked, axes in degrees and a legend.

use std::path::Path;

use parasils_io::Shortest;
use parasils_io::plot::{FONT, Figure, ImageFormat, PlotError, render_figure};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::check::Constraint;
use crate::map::ReachMap;

/// The image size, pixels.
const SIZE: (u32, u32) = (1250, 950);

/// The margin bands: a feasible cell's margin falls in `[BANDS[k],
/// BANDS[k + 1])`, drawn in `HEAT[k]` (near a limit warm, far from every
/// limit deep green).
const BANDS: [f64; 8] = [0.0, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3, f64::INFINITY];
const HEAT: [RGBColor; 7] = [
    RGBColor(253, 174, 97),
    RGBColor(254, 224, 139),
    RGBColor(230, 245, 152),
    RGBColor(171, 221, 164),
    RGBColor(102, 194, 165),
    RGBColor(50, 136, 189),
    RGBColor(37, 88, 160),
];

/// The colours of the infeasible cells, one per constraint met (in the
/// order of [`Constraint::all`]), muted so that they do not read as margin.
const OUTSIDE: [RGBColor; 12] = [
    RGBColor(150, 150, 150),
    RGBColor(190, 150, 200),
    RGBColor(165, 120, 90),
    RGBColor(220, 150, 190),
    RGBColor(120, 100, 150),
    RGBColor(200, 120, 120),
    RGBColor(105, 105, 105),
    RGBColor(210, 180, 140),
    RGBColor(170, 80, 120),
    RGBColor(225, 200, 220),
    RGBColor(140, 110, 100),
    RGBColor(90, 60, 90),
];

/// The band of a feasible margin.
fn band(margin: f64) -> usize {
    BANDS
        .windows(2)
        .position(|w| margin < w[1])
        .unwrap_or(HEAT.len() - 1)
}

/// Halfway to white: a feasible cell that cannot be reached from the start.
fn faded(c: RGBColor) -> RGBColor {
    let f = |v: u8| ((u16::from(v) + 255) / 2) as u8;
    RGBColor(f(c.0), f(c.1), f(c.2))
}

/// Renders `map` to `out` in `format`.
///
/// # Errors
/// [`PlotError::Font`], [`PlotError::Render`] (I/O included).
pub fn render(map: &ReachMap, out: &Path, format: ImageFormat) -> Result<(), PlotError> {
    render_figure(
        &Map(map),
        out,
        format,
        SIZE,
        parasils_io::plot::Compression::Fast,
    )
}

/// The map as a [`Figure`].
struct Map<'a>(&'a ReachMap);

impl Figure for Map<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        draw(self.0, root)
    }
}

fn draw<DB: DrawingBackend>(map: &ReachMap, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (main, legend) = root.split_horizontally(SIZE.0 - 300);
    let title = "Reach map: camera orientations with both tips held";
    let main = main
        .titled(title, (FONT, 24).into_font().style(FontStyle::Bold))
        .map_err(e)?;
    let step = map.options.step_deg;
    let half = 0.5 * step;
    let (cols, rows) = (map.psi.count, map.theta.count);
    let x = map.psi.value_deg(0) - half..map.psi.value_deg(cols - 1) + half;
    let y = map.theta.value_deg(0) - half..map.theta.value_deg(rows - 1) + half;
    let mut chart = ChartBuilder::on(&main)
        .margin(15)
        .x_label_area_size(55)
        .y_label_area_size(70)
        .build_cartesian_2d(x, y)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("dpsi, deg from the start (rotation about X)")
        .y_desc("dtheta, deg from the start (rotation about Y')")
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 18))
        .draw()
        .map_err(|e| e.to_string())?;
    // The constraints met outside, with their colours.
    let mut met: Vec<Constraint> = Vec::new();
    for c in &map.cells {
        if !c.feasible && !met.contains(&c.limiting) {
            met.push(c.limiting);
        }
    }
    met.sort_by_key(|c| c.index());
    let outside = |c: Constraint| {
        let k = met.iter().position(|m| *m == c).unwrap_or(0);
        OUTSIDE[k % OUTSIDE.len()]
    };
    let colour = |i: usize| {
        let c = &map.cells[i];
        if c.feasible {
            let h = HEAT[band(c.margin)];
            if c.reachable { h } else { faded(h) }
        } else {
            outside(c.limiting)
        }
    };
    // Each row as runs of one colour.
    let mut rects = Vec::new();
    for r in 0..rows {
        let yv = map.theta.value_deg(r);
        let mut c0 = 0;
        while c0 < cols {
            let col = colour(map.index(c0, r));
            let mut c1 = c0 + 1;
            while c1 < cols && colour(map.index(c1, r)) == col {
                c1 += 1;
            }
            rects.push(Rectangle::new(
                [
                    (map.psi.value_deg(c0) - half, yv - half),
                    (map.psi.value_deg(c1 - 1) + half, yv + half),
                ],
                col.filled(),
            ));
            c0 = c1;
        }
    }
    chart.draw_series(rects).map_err(|e| e.to_string())?;
    // The straight-line region's edge, dashed: cells with line = 1 next to
    // cells without.
    if map.options.line {
        let line = |c: usize, r: usize| map.cell(c, r).is_some_and(|c| c.line == Some(true));
        let mut edges = Vec::new();
        for r in 0..rows {
            for c in 0..cols {
                let (xv, yv) = (map.psi.value_deg(c), map.theta.value_deg(r));
                if c + 1 < cols && line(c, r) != line(c + 1, r) {
                    edges.push(vec![(xv + half, yv - half), (xv + half, yv + half)]);
                }
                if r + 1 < rows && line(c, r) != line(c, r + 1) {
                    edges.push(vec![(xv - half, yv + half), (xv + half, yv + half)]);
                }
            }
        }
        let style = ShapeStyle::from(&RGBColor(60, 60, 60)).stroke_width(1);
        for e in edges {
            chart
                .draw_series(core::iter::once(PathElement::new(e, style)))
                .map_err(|e| e.to_string())?;
        }
    }
    // The refined boundary.
    let boundary = ShapeStyle::from(&BLACK).stroke_width(3);
    for p in &map.boundary.polylines {
        let mut pts: Vec<(f64, f64)> = p
            .points
            .iter()
            .filter_map(|&i| map.boundary.points.get(i))
            .map(|b| {
                let [u, v] = b.deg();
                (u, v)
            })
            .collect();
        if p.closed
            && let Some(&first) = pts.first()
        {
            pts.push(first);
        }
        chart
            .draw_series(core::iter::once(PathElement::new(pts, boundary)))
            .map_err(|e| e.to_string())?;
    }
    // The start.
    chart
        .draw_series([
            Circle::new((0.0, 0.0), 9, WHITE.filled()),
            Circle::new((0.0, 0.0), 9, BLACK.stroke_width(3)),
            Circle::new((0.0, 0.0), 3, BLACK.filled()),
        ])
        .map_err(|e| e.to_string())?;
    chart
        .draw_series(core::iter::once(
            EmptyElement::at((0.0, 0.0))
                + Text::new(
                    "start",
                    (13, -22),
                    (FONT, 18).into_font().style(FontStyle::Bold),
                ),
        ))
        .map_err(|e| e.to_string())?;
    draw_legend(map, &legend, &met).map_err(e)
}

fn draw_legend<DB: DrawingBackend>(
    map: &ReachMap,
    area: &DrawingArea<DB, Shift>,
    met: &[Constraint],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let bold = (FONT, 17).into_font().style(FontStyle::Bold);
    let text = (FONT, 15).into_font();
    let swatch = |y: i32, c: RGBColor| Rectangle::new([(10, y), (38, y + 18)], c.filled());
    let mut y = 50;
    area.draw(&Text::new(
        "feasible: normalised margin",
        (10, y),
        bold.clone(),
    ))?;
    y += 26;
    for k in (0..HEAT.len()).rev() {
        area.draw(&swatch(y, HEAT[k]))?;
        let label = if BANDS[k + 1].is_finite() {
            format!("{} to {}", BANDS[k], BANDS[k + 1])
        } else {
            format!("{} and more", BANDS[k])
        };
        area.draw(&Text::new(label, (48, y + 1), text.clone()))?;
        y += 22;
    }
    area.draw(&swatch(y, faded(HEAT[3])))?;
    area.draw(&Text::new(
        "feasible, not reachable",
        (48, y + 1),
        text.clone(),
    ))?;
    y += 36;
    area.draw(&Text::new("infeasible: limiting", (10, y), bold.clone()))?;
    y += 26;
    for (k, c) in met.iter().enumerate() {
        area.draw(&swatch(y, OUTSIDE[k % OUTSIDE.len()]))?;
        area.draw(&Text::new(map.code(*c), (48, y + 1), text.clone()))?;
        y += 22;
    }
    y += 14;
    area.draw(&PathElement::new(
        vec![(10, y + 9), (38, y + 9)],
        BLACK.stroke_width(3),
    ))?;
    area.draw(&Text::new("boundary (1e-6 rad)", (48, y + 1), text.clone()))?;
    y += 22;
    if map.options.line {
        area.draw(&PathElement::new(
            vec![(10, y + 9), (38, y + 9)],
            RGBColor(60, 60, 60).stroke_width(1),
        ))?;
        area.draw(&Text::new(
            "edge of the straight-line region",
            (48, y + 1),
            text.clone(),
        ))?;
        y += 22;
    }
    area.draw(&Circle::new((24, y + 9), 7, BLACK.stroke_width(3)))?;
    area.draw(&Text::new("start", (48, y + 1), text.clone()))?;
    y += 40;
    let note = format!(
        "start: psi {} deg, theta {} deg",
        Shortest(map.start_deg[0]),
        Shortest(map.start_deg[1])
    );
    area.draw(&Text::new(note, (10, y), text.clone()))?;
    y += 22;
    area.draw(&Text::new(
        format!("grid step {} deg", Shortest(map.options.step_deg)),
        (10, y),
        text,
    ))?;
    y += 30;
    if map.module1_assumed {
        area.draw(&Text::new(
            "module 1: assumed geometry",
            (10, y),
            (FONT, 16).into_font().color(&RGBColor(170, 20, 20)),
        ))?;
        area.draw(&Text::new(
            "(not the real robot's)",
            (10, y + 20),
            (FONT, 16).into_font().color(&RGBColor(170, 20, 20)),
        ))?;
    }
    Ok(())
}
