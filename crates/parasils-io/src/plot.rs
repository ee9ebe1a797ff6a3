//! The plot kit (feature `plot`): what every picture of the workspace
//! shares (the simulation's figures, the reach map, a tolerance study's
//! histogram). One embedded font ([`FONT`], DejaVu Sans, registered by
//! [`render_figure`]: no system font is needed), one error type
//! ([`PlotError`]), the image formats ([`ImageFormat`]), SVG or PNG from any
//! [`Figure`], a row of legend entries ([`legend_row`]), a palette
//! ([`PALETTE`]) and a plotting range around values ([`range`]).

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;
/// The PNG encoder's compression levels, as [`render_figure`] takes them.
pub use png::Compression;

/// The font family name the embedded font is registered under (by
/// [`render_figure`]).
pub const FONT: &str = "sans-serif";

/// What can go wrong while plotting.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlotError {
    /// The file name's extension is neither `.svg` nor `.png`.
    #[error("cannot tell the image format of {}: use a .svg or .png extension", path.display())]
    UnknownFormat {
        /// The file name.
        path: PathBuf,
    },
    /// No sample was pushed: there is nothing to plot.
    #[error("no sample to plot")]
    NoSamples,
    /// The embedded font could not be loaded.
    #[error("the embedded font could not be loaded")]
    Font,
    /// Drawing or writing the image failed (for instance, an I/O error).
    #[error("plotting to {}: {message}", path.display())]
    Render {
        /// The file written.
        path: PathBuf,
        /// The drawing library's message.
        message: String,
    },
}

/// An image format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// Scalable vector graphics (text as text).
    Svg,
    /// A bitmap (text rasterised with the embedded font).
    Png,
}

impl ImageFormat {
    /// The format named by a path's extension (`.svg` or `.png`, any case).
    ///
    /// # Errors
    /// [`PlotError::UnknownFormat`] for any other extension, or none.
    pub fn from_path(path: &Path) -> Result<Self, PlotError> {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("svg") => Ok(Self::Svg),
            Some(e) if e.eq_ignore_ascii_case("png") => Ok(Self::Png),
            _ => Err(PlotError::UnknownFormat {
                path: path.to_owned(),
            }),
        }
    }
}

/// A picture drawn with the kit's font (the simulation's figures, the reach
/// map, a tolerance study's histogram): what [`render_figure`] needs of it.
pub trait Figure {
    /// Draws the picture on `root`.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// Renders `figure`, `size` pixels, to `out` as SVG or PNG (encoded with
/// `compression`), its text in the embedded DejaVu Sans.
///
/// # Errors
/// [`PlotError::Font`], [`PlotError::Render`] (I/O included).
pub fn render_figure(
    figure: &impl Figure,
    out: &Path,
    format: ImageFormat,
    size: (u32, u32),
    compression: png::Compression,
) -> Result<(), PlotError> {
    plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular())
        .map_err(|_| PlotError::Font)?;
    plotters::style::register_font(FONT, FontStyle::Bold, dejavu::sans::bold())
        .map_err(|_| PlotError::Font)?;
    let fail = |message: String| PlotError::Render {
        path: out.to_owned(),
        message,
    };
    match format {
        ImageFormat::Svg => {
            let root = SVGBackend::new(out, size).into_drawing_area();
            figure.draw(&root).map_err(fail)?;
            root.present().map_err(|e| fail(e.to_string()))
        }
        ImageFormat::Png => {
            // Drawn in memory and encoded here: plotters would pick the
            // format from `out`'s extension, which a temporary file lacks.
            let (w, h) = size;
            let mut rgb = vec![0u8; 3 * w as usize * h as usize];
            {
                let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
                figure.draw(&root).map_err(fail)?;
                root.present().map_err(|e| fail(e.to_string()))?;
            }
            write_png(out, &rgb, size, compression).map_err(|e| fail(e.to_string()))
        }
    }
}

/// Encodes an RGB buffer as a PNG file.
fn write_png(
    out: &Path,
    rgb: &[u8],
    (w, h): (u32, u32),
    compression: png::Compression,
) -> Result<(), png::EncodingError> {
    let file = std::io::BufWriter::new(std::fs::File::create(out)?);
    let mut encoder = png::Encoder::new(file, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(compression);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(rgb)?;
    writer.finish()
}

/// A row of legend entries (a short line in the colour, the label) along
/// the top of `area`; returns the area below it.
pub fn legend_row<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: impl Iterator<Item = (&'a str, RGBColor)>,
) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    let (strip, below) = area.split_vertically(26);
    let legend_font = TextStyle::from((FONT, 15).into_font());
    let mut x = 90;
    for (label, color) in entries {
        strip.draw(&PathElement::new(
            [(x, 12), (x + 26, 12)],
            color.stroke_width(3),
        ))?;
        strip.draw(&Text::new(label, (x + 32, 4), legend_font.clone()))?;
        let (w, _) = strip.estimate_text_size(label, &legend_font)?;
        x += 32 + i32::try_from(w).unwrap_or(100) + 28;
    }
    Ok(below)
}

/// Distinct colours (Tableau 10).
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// A plotting range around `values`, with a 5 % margin (and a unit one when
/// they are all equal).
pub fn range(values: impl Iterator<Item = f64>) -> core::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return -1.0..1.0;
    }
    let pad = if hi - lo > 1e-9 * hi.abs().max(1.0) {
        0.05 * (hi - lo)
    } else {
        1.0
    };
    (lo - pad)..(hi + pad)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two legend entries over a white background.
    struct Legend;

    impl Figure for Legend {
        fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
            root.fill(&WHITE).map_err(|e| e.to_string())?;
            legend_row(
                root,
                [("psi (deg)", PALETTE[0]), ("theta (deg)", PALETTE[1])].into_iter(),
            )
            .map_err(|e| e.to_string())?;
            Ok(())
        }
    }

    #[test]
    fn svg_and_png_with_the_embedded_font() {
        let dir = tempfile::tempdir().expect("tempdir");
        let svg = dir.path().join("legend.svg");
        render_figure(
            &Legend,
            &svg,
            ImageFormat::Svg,
            (400, 60),
            png::Compression::Fast,
        )
        .expect("svg");
        let text = std::fs::read_to_string(&svg).expect("written");
        assert!(text.contains("psi (deg)") && text.contains("theta (deg)"));
        // No extension: the format is the argument's, not the name's.
        let png = dir.path().join("legend");
        render_figure(
            &Legend,
            &png,
            ImageFormat::Png,
            (400, 60),
            png::Compression::Fast,
        )
        .expect("png");
        let bytes = std::fs::read(&png).expect("written");
        assert_eq!(&bytes[1..4], b"PNG");
        let missing = dir.path().join("no-such-dir").join("a.png");
        assert!(matches!(
            render_figure(
                &Legend,
                &missing,
                ImageFormat::Png,
                (40, 40),
                png::Compression::Fast
            ),
            Err(PlotError::Render { .. })
        ));
    }

    #[test]
    fn formats_from_extensions() {
        assert_eq!(
            ImageFormat::from_path(Path::new("a.SVG")).ok(),
            Some(ImageFormat::Svg)
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("x/a.png")).ok(),
            Some(ImageFormat::Png)
        );
        assert!(matches!(
            ImageFormat::from_path(Path::new("a.pdf")),
            Err(PlotError::UnknownFormat { .. })
        ));
    }

    #[test]
    fn ranges_pad_by_five_percent_or_one() {
        let r = range([0.0, 10.0, f64::NAN].into_iter());
        assert!(
            (r.start + 0.5).abs() < 1e-12 && (r.end - 10.5).abs() < 1e-12,
            "{r:?}"
        );
        assert_eq!(range([3.0, 3.0].into_iter()), 2.0..4.0);
        assert_eq!(range(core::iter::empty()), -1.0..1.0);
    }
}
