//! The paper's figures 5-7 as one image (feature `plot`): platform angles, module 1's
//! actuators and the left module's joints over time.
//!
//! [`PlotSink`] keeps a decimated copy of the run (at most
//! [`MAX_POINTS`] points per series, plus the last sample), so memory stays
//! flat however long the run; [`PlotSink::finish`] renders three stacked
//! panels to SVG or PNG with the workspace's plot kit (`parasils_io::plot`:
//! the embedded font, the legend rows, the palette).

use std::path::Path;

use parasils_io::plot::{FONT, Figure, PALETTE, legend_row, range, render_figure};
pub use parasils_io::plot::{ImageFormat, PlotError};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::record::Record;
use crate::sink::Sink;
use crate::timing::PhasePlane;

/// The most points kept per series (the last sample comes on top).
pub const MAX_POINTS: usize = 2000;

/// The image size, pixels.
const SIZE: (u32, u32) = (1200, 1500);

/// What the figures need of one sample, in display units.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Point {
    /// s.
    t: f64,
    /// `psi`, `theta`, deg.
    angles: [f64; 2],
    /// `q1..q6`, mm.
    q: [f64; 6],
    /// Left `qs1`, `qs2` deg, `qs3` mm.
    left: [f64; 3],
}

impl Point {
    fn of(s: &Record) -> Self {
        Self {
            t: s.t,
            angles: [s.angles_deg[0], s.angles_deg[1]],
            q: s.module1.q,
            left: [
                s.left.q[0].to_degrees(),
                s.left.q[1].to_degrees(),
                s.left.q[2],
            ],
        }
    }
}

/// Collects a decimated copy of a run and plots the paper's three figures.
///
/// Keeps every `k`-th sample, with `k` chosen from the expected count so that
/// at most [`MAX_POINTS`] are kept, plus the last sample. Should more samples
/// come than announced, the kept points are thinned (every other one dropped,
/// `k` doubled) so that memory stays bounded all the same.
#[derive(Debug, Clone)]
pub struct PlotSink {
    stride: usize,
    seen: usize,
    points: Vec<Point>,
    /// The latest sample, when not kept.
    last: Option<Point>,
    module1_assumed: bool,
    /// A calibrated module 1's label ("calibrated (RMS ... mm over N
    /// poses)"), shown instead of the assumed-geometry note.
    module1_note: Option<String>,
    /// In a procedure: where each motion starts (s), its index and type
    /// (1 to 4), marked on every panel. `None` outside procedures.
    motions: Option<Vec<(f64, u32, u8)>>,
    /// The time-optimal law's phase plane, drawn as a fourth panel.
    phase_plane: Option<PhasePlane>,
}

impl PlotSink {
    /// A sink for a run of `total_samples` samples; `module1_assumed` says
    /// whether module 1's geometry is the assumed one (the figure says so).
    pub fn new(total_samples: usize, module1_assumed: bool) -> Self {
        let stride = total_samples.div_ceil(MAX_POINTS).max(1);
        Self {
            stride,
            seen: 0,
            points: Vec::with_capacity(total_samples.min(MAX_POINTS) + 1),
            last: None,
            module1_assumed,
            module1_note: None,
            motions: None,
            phase_plane: None,
        }
    }

    /// The same sink, adding a fourth panel: the phase plane of a
    /// time-optimal law (`s_dot` against `s`, with its velocity and
    /// acceleration limit curves and its phases).
    pub fn with_phase_plane(mut self, plane: PhasePlane) -> Self {
        self.phase_plane = Some(plane);
        self
    }

    /// The same sink, saying that module 1 is calibrated: `label` is its
    /// provenance ("calibrated (RMS ... mm over N poses)").
    pub fn calibrated(mut self, label: String) -> Self {
        self.module1_note = Some(format!("Module 1's geometry is {label}"));
        self
    }

    /// The same sink, marking each motion's span (a dashed line where it
    /// starts, its index and type above): for a procedure's run.
    pub fn marking_motions(mut self) -> Self {
        self.motions = Some(Vec::new());
        self
    }

    /// The number of points that will be plotted per series.
    pub fn len(&self) -> usize {
        self.points.len() + usize::from(self.last.is_some())
    }

    /// Whether no sample was pushed.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Renders the figure to `out`, in the format named by the extension of
    /// `name` (`.svg` or `.png`). `out` and `name` may be the same path; the
    /// caller may also write to a temporary file (`out`) and rename it to
    /// `name` afterwards.
    ///
    /// # Errors
    /// [`PlotError::UnknownFormat`], [`PlotError::NoSamples`],
    /// [`PlotError::Font`], [`PlotError::Render`] (I/O included).
    pub fn finish(self, out: &Path, name: &Path) -> Result<(), PlotError> {
        self.render(out, ImageFormat::from_path(name)?)
    }

    /// Renders the figure to `out` in `format`.
    ///
    /// # Errors
    /// As [`PlotSink::finish`], less the format.
    pub fn render(&self, out: &Path, format: ImageFormat) -> Result<(), PlotError> {
        if self.is_empty() {
            return Err(PlotError::NoSamples);
        }
        let size = if self.phase_plane.is_some() {
            (SIZE.0, SIZE.1 + SIZE.1 / 3)
        } else {
            SIZE
        };
        render_figure(
            self,
            out,
            format,
            size,
            parasils_io::plot::Compression::Best,
        )
    }

    /// The kept points, the last one included.
    fn series(&self) -> impl Iterator<Item = &Point> + Clone {
        self.points.iter().chain(self.last.iter())
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(e)?;
        let root = root
            .titled(
                if self.motions.is_some() {
                    "PARA-SILSROB procedure: the platform, module 1 and the left module, motion by motion"
                } else {
                    "PARA-SILSROB endoscope reorientation: the paper's figures 5-7"
                },
                (FONT, 28).into_font().style(FontStyle::Bold),
            )
            .map_err(e)?;
        let panels = root.split_evenly((3 + usize::from(self.phase_plane.is_some()), 1));

        let angles = [
            Series::new("psi (deg)", 0, |p| p.angles[0]),
            Series::new("theta (deg)", 1, |p| p.angles[1]),
        ];
        self.panel(
            &panels[0],
            "(a) Platform orientation (fig. 5)",
            None,
            "angle (deg)",
            &angles,
            None,
        )
        .map_err(e)?;

        let actuators: [Series; 6] = core::array::from_fn(|j| Series {
            label: format!("q{} (mm)", j + 1),
            color: PALETTE[j],
            get: Box::new(move |p| p.q[j]),
        });
        let note = self
            .module1_note
            .as_deref()
            .or(self.module1_assumed.then_some(
                "Module 1's geometry is ASSUMED (the robot's dimensions are unpublished): \
             the method, not the real robot's values",
            ));
        self.panel(
            &panels[1],
            "(b) Module 1 actuators q1..q6 (fig. 6)",
            note,
            "actuator position (mm)",
            &actuators,
            None,
        )
        .map_err(e)?;

        let joints = [
            Series::new("qs1 (deg)", 0, |p| p.left[0]),
            Series::new("qs2 (deg)", 1, |p| p.left[1]),
        ];
        let insertion = Series::new("qs3 (mm, right axis)", 3, |p| p.left[2]);
        self.panel(
            &panels[2],
            "(c) Left instrument module joints (fig. 7)",
            None,
            "qs1, qs2 (deg)",
            &joints,
            Some(("qs3 (mm)", &insertion)),
        )
        .map_err(e)?;
        if let (Some(plane), Some(area)) = (&self.phase_plane, panels.get(3)) {
            phase_plane_panel(plane, area).map_err(e)?;
        }
        Ok(())
    }

    /// One panel: a caption, an optional note, a legend row, then the chart
    /// against `t`, with an optional series on a second y axis.
    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        caption: &str,
        note: Option<&str>,
        y_desc: &str,
        series: &[Series],
        secondary: Option<(&str, &Series)>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let mut area = area.titled(caption, (FONT, 22))?;
        if let Some(note) = note {
            area = area.titled(note, (FONT, 16).into_font().color(&RGBColor(170, 20, 20)))?;
        }
        let area = legend_row(
            &area,
            series
                .iter()
                .chain(secondary.map(|(_, s)| s))
                .map(|s| (s.label.as_str(), s.color)),
        )?;

        let t_end = self.series().last().map_or(1.0, |p| p.t);
        let t_range = 0.0..if t_end > 0.0 { t_end } else { 1.0 };
        let y = range(
            series
                .iter()
                .flat_map(|s| self.series().map(|p| (s.get)(p))),
        );
        let y_span = y.clone();
        let y2 = secondary.map_or(0.0..1.0, |(_, s)| range(self.series().map(|p| (s.get)(p))));
        let mut builder = ChartBuilder::on(&area);
        builder
            .margin_left(12)
            .margin_right(if secondary.is_some() { 12 } else { 30 })
            .margin_bottom(8)
            .x_label_area_size(42)
            .y_label_area_size(72);
        if secondary.is_some() {
            builder.right_y_label_area_size(72);
        }
        let mut chart = builder
            .build_cartesian_2d(t_range.clone(), y)?
            .set_secondary_coord(t_range, y2);
        chart
            .configure_mesh()
            .x_desc("t (s)")
            .y_desc(y_desc)
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .draw()?;
        for (t, k, kind) in self.motions.iter().flatten() {
            let (lo, hi) = (y_span.start, y_span.end);
            let grey = RGBColor(120, 120, 120);
            if *t > 0.0 {
                let steps = 40;
                let dash = (hi - lo) / f64::from(2 * steps);
                chart.draw_series((0..steps).map(|i| {
                    let y0 = lo + f64::from(2 * i) * dash;
                    PathElement::new([(*t, y0), (*t, y0 + dash)], grey.stroke_width(1))
                }))?;
            }
            let name = match kind {
                1 => "position",
                2 => "insert",
                3 => "manipulate",
                _ => "reorient",
            };
            chart.draw_series(core::iter::once(Text::new(
                format!("{k}: {kind} {name}"),
                (*t, hi),
                (FONT, 13).into_font().color(&grey),
            )))?;
        }
        for s in series {
            chart.draw_series(LineSeries::new(
                self.series().map(|p| (p.t, (s.get)(p))),
                s.color.stroke_width(2),
            ))?;
        }
        if let Some((desc, s)) = secondary {
            chart
                .configure_secondary_axes()
                .y_desc(desc)
                .label_style((FONT, 14))
                .axis_desc_style((FONT, 16))
                .draw()?;
            chart.draw_secondary_series(LineSeries::new(
                self.series().map(|p| (p.t, (s.get)(p))),
                s.color.stroke_width(2),
            ))?;
        }
        Ok(())
    }
}

/// The phase plane of a time-optimal law: `s_dot` against `s` under the
/// velocity and acceleration limit curves and the controllable set's upper
/// end, each phase marked with what limits it.
fn phase_plane_panel<DB: DrawingBackend>(
    plane: &PhasePlane,
    area: &DrawingArea<DB, Shift>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let area = area.titled(
        "(d) Phase plane of the time-optimal law: path speed against path position",
        (FONT, 22),
    )?;
    let top = plane.s_dot.iter().copied().fold(0.0, f64::max).max(1e-9) * 1.8;
    let curves = [
        ("velocity limit curve", PALETTE[1], &plane.velocity_limit, 2),
        (
            "acceleration limit curve (where in the frame)",
            PALETTE[3],
            &plane.acceleration_limit,
            2,
        ),
        (
            "controllable set (stop still possible)",
            RGBColor(150, 150, 150),
            &plane.controllable,
            1,
        ),
        ("the optimal law", PALETTE[0], &plane.s_dot, 3),
    ];
    let area = legend_row(
        &area,
        curves.iter().map(|(label, color, _, _)| (*label, *color)),
    )?;
    let mut chart = ChartBuilder::on(&area)
        .margin_left(12)
        .margin_right(30)
        .margin_bottom(8)
        .x_label_area_size(42)
        .y_label_area_size(72)
        .build_cartesian_2d(0.0..1.0, 0.0..top)?;
    chart
        .configure_mesh()
        .x_desc("s (path position, 0 at the start, 1 at the goal)")
        .y_desc("s_dot (1/s)")
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .draw()?;
    // Each curve in the pieces that lie inside the frame (a limit curve
    // runs off to infinity where no row's limit binds).
    for (_, color, values, width) in &curves {
        let mut piece: Vec<(f64, f64)> = Vec::new();
        for (&s, &v) in plane.s.iter().zip(values.iter()) {
            if v <= top {
                piece.push((s, v));
            } else if !piece.is_empty() {
                chart.draw_series(LineSeries::new(
                    core::mem::take(&mut piece),
                    color.stroke_width(*width),
                ))?;
            }
        }
        chart.draw_series(LineSeries::new(piece, color.stroke_width(*width)))?;
    }
    let grey = RGBColor(90, 90, 90);
    for (k, (from, to, label)) in plane.phases.iter().enumerate() {
        if *from > 0.0 {
            chart.draw_series(core::iter::once(PathElement::new(
                [(*from, 0.0), (*from, top)],
                grey.stroke_width(1),
            )))?;
        }
        let y = top * (0.95 - 0.07 * (k % 3) as f64);
        chart.draw_series(core::iter::once(Text::new(
            format!("{label} to s = {to:.3}"),
            (from.min(0.7) + 0.005, y),
            (FONT, 14).into_font().color(&grey),
        )))?;
    }
    Ok(())
}

/// One curve: its legend label, colour and value.
struct Series {
    label: String,
    color: RGBColor,
    get: Box<dyn Fn(&Point) -> f64>,
}

impl Series {
    fn new(label: &str, color: usize, get: fn(&Point) -> f64) -> Self {
        Self {
            label: label.to_owned(),
            color: PALETTE[color % PALETTE.len()],
            get: Box::new(get),
        }
    }
}

impl Figure for PlotSink {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        PlotSink::draw(self, root)
    }
}

impl Sink for PlotSink {
    type Error = core::convert::Infallible;

    fn push(&mut self, record: &Record) -> Result<(), Self::Error> {
        let p = Point::of(record);
        if let Some(m) = &mut self.motions
            && m.last().is_none_or(|(_, k, _)| *k != record.motion)
        {
            m.push((record.t, record.motion, record.motion_type));
        }
        if self.seen.is_multiple_of(self.stride) {
            self.points.push(p);
            self.last = None;
            if self.points.len() >= 2 * MAX_POINTS {
                // More samples than announced: thin out, keep memory bounded.
                let mut k = 0;
                self.points.retain(|_| {
                    k += 1;
                    k % 2 == 1
                });
                self.stride *= 2;
            }
        } else {
            self.last = Some(p);
        }
        self.seen += 1;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(t: f64) -> Record {
        let mut s = Record {
            t,
            ..Record::default()
        };
        s.angles_deg[0] = -15.0 + 3.0 * t;
        s.angles_deg[1] = 10.0 + 5.0 * t;
        s.module1.q = [100.0 + t, 110.0 + t, 90.0, 80.0 - t, 120.0, 95.0 + 2.0 * t];
        s.left.q = [(3.0 + t).to_radians(), (-38.0 - t).to_radians(), 147.0 + t];
        s
    }

    fn filled(n: usize, announced: usize) -> PlotSink {
        let mut sink = PlotSink::new(announced, true);
        for k in 0..n {
            sink.push(&sample(k as f64 * 1e-3)).expect("infallible");
        }
        sink
    }

    #[test]
    fn decimates_to_at_most_max_points_plus_the_last() {
        let sink = filled(4501, 4501);
        assert_eq!(sink.stride, 3);
        assert_eq!(sink.points.len(), 1501);
        assert_eq!(sink.series().last().map(|p| p.t), Some(4.5));
        let sink = filled(10_001, 10_001);
        assert!(sink.len() <= MAX_POINTS + 1);
        assert_eq!(sink.series().last().map(|p| p.t), Some(10.0));
        // Announced too few: still bounded.
        let sink = filled(100_000, 10);
        assert!(sink.len() <= 2 * MAX_POINTS + 1, "{}", sink.len());
        assert_eq!(sink.series().last().map(|p| p.t), Some(99.999));
        // Small runs keep everything.
        assert_eq!(filled(7, 7).len(), 7);
    }

    #[test]
    fn renders_an_svg_with_titles_and_units() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("fig.svg");
        filled(4501, 4501).finish(&path, &path).expect("render");
        let svg = std::fs::read_to_string(&path).expect("written");
        for text in [
            "the paper&apos;s figures 5-7",
            "(a) Platform orientation",
            "(b) Module 1 actuators",
            "geometry is ASSUMED",
            "(c) Left instrument module joints",
            "t (s)",
            "angle (deg)",
            "actuator position (mm)",
            "qs3 (mm)",
            "theta (deg)",
            "q6 (mm)",
        ] {
            assert!(svg.contains(text), "missing {text}");
        }
    }

    #[test]
    fn renders_a_png_without_system_fonts() {
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("tmp-without-extension");
        let mut sink = PlotSink::new(100, false);
        for k in 0..100 {
            sink.push(&sample(f64::from(k) * 0.05)).expect("infallible");
        }
        sink.finish(&out, Path::new("fig.png")).expect("render");
        let bytes = std::fs::read(&out).expect("written");
        assert_eq!(&bytes[1..4], b"PNG");
    }

    #[test]
    fn errors_are_typed() {
        fn send_sync<T: Send + Sync + 'static>() {}
        send_sync::<PlotError>();
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("fig.pdf");
        assert!(matches!(
            filled(3, 3).finish(&p, &p),
            Err(PlotError::UnknownFormat { .. })
        ));
        let p = dir.path().join("fig.svg");
        assert!(matches!(
            PlotSink::new(0, true).finish(&p, &p),
            Err(PlotError::NoSamples)
        ));
        let p = dir.path().join("no-such-dir").join("fig.png");
        assert!(matches!(
            filled(3, 3).finish(&p, &p),
            Err(PlotError::Render { .. })
        ));
    }
}
