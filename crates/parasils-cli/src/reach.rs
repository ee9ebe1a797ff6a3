//! `parasils reach`: the map of the orientations reachable from the start
//! pose with both tips held, as CSV, a picture, or a summary.

use std::io::{BufWriter, Write};

use anyhow::{Context, Result, bail};
use parasils_io::ImageFormat;
use parasils_io::file::{persist, temp_beside};
use parasils_reach::{ReachMap, ReachSummary};

use crate::args::ReachArgs;
use crate::stdout;

/// What `-o` asks for.
enum Target {
    Csv,
    Image(ImageFormat),
}

/// `parasils reach`.
pub fn reach(args: &ReachArgs) -> Result<()> {
    let target = match &args.output {
        None => None,
        Some(path) if path.as_os_str() == "-" => Some(Target::Csv),
        Some(path) => match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("csv") => Some(Target::Csv),
            _ => match ImageFormat::from_path(path) {
                Ok(f) => Some(Target::Image(f)),
                Err(_) => bail!(
                    "cannot tell the output format of {}: use a .csv, .png or .svg extension",
                    path.display()
                ),
            },
        },
    };
    let map = ReachMap::compute(&args.scenario()?, &args.options())?;
    let (Some(path), Some(target)) = (&args.output, target) else {
        let mut out = stdout::stdout();
        out.write_all(ReachSummary::of(&map).text(&map).as_bytes())?;
        out.flush()?;
        return Ok(());
    };
    if path.as_os_str() == "-" {
        let mut out = BufWriter::new(stdout::stdout());
        parasils_reach::csv::write(&map, &mut out)?;
        return Ok(());
    }
    // Written beside the target and renamed on success: a failure leaves
    // nothing behind.
    let tmp = temp_beside(path)?;
    match target {
        Target::Csv => {
            let mut out = BufWriter::new(tmp.as_file());
            parasils_reach::csv::write(&map, &mut out)
                .with_context(|| format!("writing {}", path.display()))?;
        }
        Target::Image(format) => parasils_reach::plot::render(&map, tmp.path(), format)?,
    }
    persist(tmp, path)?;
    Ok(())
}
