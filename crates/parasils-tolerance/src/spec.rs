//! The tolerance specification: one entry per parameter family, named like
//! the robot file's keys, each a normal (`{ sigma = ... }`) or a uniform
//! (`{ half_width = ... }`) distribution of the deviation from nominal.
//! Families left out are not perturbed.
//!
//! ```toml
//! [module1.guides]
//! point_mm = { sigma = 0.05 }
//! direction_deg = { sigma = 0.02 }      # tilt about a random perpendicular axis
//! link_length_mm = { sigma = 0.02 }
//! encoder_offset_mm = { half_width = 0.01 }
//! [module1.legs]
//! node_mm = { sigma = 0.05 }
//! [instruments]                         # both modules
//! alpha_deg = { sigma = 0.01 }
//! beta_deg = { sigma = 0.01 }
//! rcm_mm = { sigma = 0.05 }
//! ```
//!
//! Every coordinate of every member is perturbed independently: each of the
//! six guide points in x, y and z, each link length, each leg's node, each
//! module's `alpha`, `beta` and port. A guide direction is tilted by an angle
//! drawn from its distribution about an axis perpendicular to it, at a
//! uniformly random azimuth.
//!
//! ```
//! use parasils_tolerance::{Distribution, Family, Spec};
//!
//! let spec = Spec::from_toml("[instruments]\nalpha_deg = { half_width = 0.03 }\n")?;
//! assert_eq!(spec.get(Family::Alpha), Some(Distribution::Uniform { half_width: 0.03 }));
//! assert_eq!(spec.get(Family::Beta), None);
//! // The default specification round-trips through its own text.
//! let default = Spec::default();
//! assert_eq!(Spec::from_toml(&default.to_toml())?, default);
//! # Ok::<(), parasils_tolerance::SpecError>(())
//! ```

use std::path::Path;

use thiserror::Error;
use toml::{Table, Value};

/// A family of geometric parameters perturbed together.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Family {
    /// The six guide points `G_j` of module 1, mm (18 coordinates).
    GuidePoint,
    /// The six guide directions `u_j` of module 1: a tilt, deg.
    GuideDirection,
    /// The six link lengths `l_j`, mm.
    LinkLength,
    /// The six encoder offsets `o_j`, mm.
    EncoderOffset,
    /// The three platform nodes `a_i`, mm (9 coordinates).
    LegNode,
    /// `alpha` of both instrument modules, deg.
    Alpha,
    /// `beta` of both instrument modules, deg.
    Beta,
    /// The ports (RCMs) of both instrument modules in the platform frame, mm
    /// (6 coordinates).
    Rcm,
}

impl Family {
    /// Every family, in the order of the specification's text.
    pub const ALL: [Family; 8] = [
        Family::GuidePoint,
        Family::GuideDirection,
        Family::LinkLength,
        Family::EncoderOffset,
        Family::LegNode,
        Family::Alpha,
        Family::Beta,
        Family::Rcm,
    ];

    /// Its full key: `module1.guides.point_mm`, `instruments.alpha_deg`...
    pub fn key(self) -> &'static str {
        match self {
            Family::GuidePoint => "module1.guides.point_mm",
            Family::GuideDirection => "module1.guides.direction_deg",
            Family::LinkLength => "module1.guides.link_length_mm",
            Family::EncoderOffset => "module1.guides.encoder_offset_mm",
            Family::LegNode => "module1.legs.node_mm",
            Family::Alpha => "instruments.alpha_deg",
            Family::Beta => "instruments.beta_deg",
            Family::Rcm => "instruments.rcm_mm",
        }
    }

    /// The unit of its deviations: `"mm"` or `"deg"`.
    pub fn unit(self) -> &'static str {
        match self {
            Family::GuideDirection | Family::Alpha | Family::Beta => "deg",
            _ => "mm",
        }
    }

    /// The number of independent deviations a sample draws for it.
    pub fn coordinates(self) -> usize {
        match self {
            Family::GuidePoint => 18,
            Family::GuideDirection | Family::LinkLength | Family::EncoderOffset | Family::Rcm => 6,
            Family::LegNode => 9,
            Family::Alpha | Family::Beta => 2,
        }
    }

    /// Its position in [`Family::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    fn from_key(key: &str) -> Option<Self> {
        Family::ALL.into_iter().find(|f| f.key() == key)
    }
}

/// The distribution of one family's deviations, in the family's unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Distribution {
    /// Normal, zero mean, standard deviation `sigma`.
    Normal {
        /// The standard deviation.
        sigma: f64,
    },
    /// Uniform on `[-half_width, half_width]`.
    Uniform {
        /// Half the interval's width.
        half_width: f64,
    },
}

/// The multiple of `sigma` at which a normal deviation is checked for
/// reach when a study starts ([`Study::new`](crate::Study::new)): a single
/// coordinate lies beyond it with probability 2e-9.
pub const NORMAL_EXTREME_SIGMAS: f64 = 6.0;

impl Distribution {
    /// The standard deviation: `sigma`, or `half_width / sqrt(3)`.
    pub fn std_dev(self) -> f64 {
        match self {
            Distribution::Normal { sigma } => sigma,
            Distribution::Uniform { half_width } => half_width / 3f64.sqrt(),
        }
    }

    /// The largest deviation a study checks for reach when it starts:
    /// [`NORMAL_EXTREME_SIGMAS`] sigma, or the half width.
    pub fn extreme(self) -> f64 {
        match self {
            Distribution::Normal { sigma } => NORMAL_EXTREME_SIGMAS * sigma,
            Distribution::Uniform { half_width } => half_width,
        }
    }

    /// The same distribution with its width multiplied by `k`.
    pub fn scaled(self, k: f64) -> Self {
        match self {
            Distribution::Normal { sigma } => Distribution::Normal { sigma: sigma * k },
            Distribution::Uniform { half_width } => Distribution::Uniform {
                half_width: half_width * k,
            },
        }
    }

    /// The deviation of the standard variates `normal` (N(0, 1)) and
    /// `unit` (uniform in `[0, 1)`): only the one this distribution uses is
    /// read.
    pub(crate) fn deviation(self, normal: f64, unit: f64) -> f64 {
        match self {
            Distribution::Normal { sigma } => sigma * normal,
            Distribution::Uniform { half_width } => half_width * (2.0 * unit - 1.0),
        }
    }

    fn text(self) -> String {
        match self {
            Distribution::Normal { sigma } => format!("{{ sigma = {sigma:?} }}"),
            Distribution::Uniform { half_width } => format!("{{ half_width = {half_width:?} }}"),
        }
    }
}

/// What is wrong with a specification.
#[derive(Debug, Error, PartialEq)]
pub enum SpecError {
    /// Not TOML (or JSON) at all; the parser's message has the line.
    #[error("{origin}: {message}")]
    Syntax {
        /// The file, or `"specification"`.
        origin: String,
        /// The parser's message.
        message: String,
    },
    /// A key the specification does not know.
    #[error("{origin}: unknown key `{key}` (known: {known})")]
    UnknownKey {
        /// The file, or `"specification"`.
        origin: String,
        /// The full dotted key.
        key: String,
        /// The keys allowed there.
        known: String,
    },
    /// An entry that is not `{ sigma = x }` or `{ half_width = x }`.
    #[error("{origin}: `{key}` must be {{ sigma = ... }} or {{ half_width = ... }}: {why}")]
    Entry {
        /// The file, or `"specification"`.
        origin: String,
        /// The family's key.
        key: String,
        /// What is wrong.
        why: String,
    },
    /// A negative or non-finite width.
    #[error("{origin}: `{key}` must be finite and >= 0, got {value}")]
    Width {
        /// The file, or `"specification"`.
        origin: String,
        /// `family.sigma` or `family.half_width`.
        key: String,
        /// The value given.
        value: f64,
    },
    /// The file could not be read.
    #[error("cannot read the tolerance specification {path}: {message}")]
    Read {
        /// The path.
        path: String,
        /// The I/O error.
        message: String,
    },
}

/// A tolerance specification: at most one distribution per [`Family`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spec {
    entries: [Option<Distribution>; 8],
}

impl Default for Spec {
    /// The default tolerances: guide points 0.05 mm, directions 0.02 deg,
    /// link lengths 0.02 mm, nodes 0.05 mm, the modules' `alpha` and `beta`
    /// 0.01 deg and ports 0.05 mm (normal, one sigma), encoder offsets
    /// uniform within +-0.01 mm: the figures of a careful machining and
    /// assembly, to be replaced by the shop's own.
    fn default() -> Self {
        let n = |sigma| Some(Distribution::Normal { sigma });
        Self {
            entries: [
                n(0.05),
                n(0.02),
                n(0.02),
                Some(Distribution::Uniform { half_width: 0.01 }),
                n(0.05),
                n(0.01),
                n(0.01),
                n(0.05),
            ],
        }
    }
}

impl Spec {
    /// Nothing perturbed.
    pub fn none() -> Self {
        Self { entries: [None; 8] }
    }

    /// The distribution of `family`, `None` when it is not perturbed.
    pub fn get(&self, family: Family) -> Option<Distribution> {
        self.entries[family.index()]
    }

    /// This specification with `family` perturbed by `distribution` (or not
    /// at all with `None`).
    #[must_use]
    pub fn with(mut self, family: Family, distribution: Option<Distribution>) -> Self {
        self.entries[family.index()] = distribution;
        self
    }

    /// Every width multiplied by `k` (`k >= 0`).
    #[must_use]
    pub fn scaled(&self, k: f64) -> Self {
        Self {
            entries: self.entries.map(|e| e.map(|d| d.scaled(k))),
        }
    }

    /// The families perturbed, with their distributions.
    pub fn iter(&self) -> impl Iterator<Item = (Family, Distribution)> + '_ {
        Family::ALL
            .into_iter()
            .filter_map(|f| self.get(f).map(|d| (f, d)))
    }

    /// Reads a specification file (TOML).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, SpecError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| SpecError::Read {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::parse(&text, &path.display().to_string())
    }

    /// A specification from TOML text.
    pub fn from_toml(text: &str) -> Result<Self, SpecError> {
        Self::parse(text, "specification")
    }

    fn parse(text: &str, origin: &str) -> Result<Self, SpecError> {
        let table: Table = text
            .parse()
            .map_err(|e: toml::de::Error| SpecError::Syntax {
                origin: origin.to_string(),
                message: e.to_string().trim_end().to_string(),
            })?;
        Self::from_table(&table, origin)
    }

    /// A specification from JSON text of the same structure (what the
    /// Python bindings send for a dict).
    pub fn from_json(text: &str) -> Result<Self, SpecError> {
        let origin = "specification";
        let table: Table = serde_json::from_str(text).map_err(|e| SpecError::Syntax {
            origin: origin.to_string(),
            message: e.to_string(),
        })?;
        Self::from_table(&table, origin)
    }

    fn from_table(table: &Table, origin: &str) -> Result<Self, SpecError> {
        let mut spec = Self::none();
        let unknown = |key: String, known: &[&str]| SpecError::UnknownKey {
            origin: origin.to_string(),
            key,
            known: known.join(", "),
        };
        let sub = |value: &Value, key: &str| -> Result<Table, SpecError> {
            value.as_table().cloned().ok_or_else(|| SpecError::Entry {
                origin: origin.to_string(),
                key: key.to_string(),
                why: "a table is expected here".to_string(),
            })
        };
        for (top, value) in table {
            match top.as_str() {
                "module1" => {
                    for (group, value) in &sub(value, "module1")? {
                        let prefix = format!("module1.{group}");
                        if !matches!(group.as_str(), "guides" | "legs") {
                            return Err(unknown(prefix, &["module1.guides", "module1.legs"]));
                        }
                        spec.read_group(&sub(value, &prefix)?, &prefix, origin)?;
                    }
                }
                "instruments" => {
                    spec.read_group(&sub(value, "instruments")?, "instruments", origin)?;
                }
                _ => return Err(unknown(top.clone(), &["module1", "instruments"])),
            }
        }
        Ok(spec)
    }

    fn read_group(&mut self, table: &Table, prefix: &str, origin: &str) -> Result<(), SpecError> {
        for (name, value) in table {
            let key = format!("{prefix}.{name}");
            let Some(family) = Family::from_key(&key) else {
                let known: Vec<&str> = Family::ALL
                    .iter()
                    .map(|f| f.key())
                    .filter(|k| k.starts_with(&format!("{prefix}.")))
                    .collect();
                return Err(SpecError::UnknownKey {
                    origin: origin.to_string(),
                    key,
                    known: known.join(", "),
                });
            };
            self.entries[family.index()] = Some(read_entry(value, &key, origin)?);
        }
        Ok(())
    }

    /// The specification as TOML, which [`Spec::from_toml`] reads back to
    /// the same value (what `parasils tolerance --print-spec` prints).
    pub fn to_toml(&self) -> String {
        let mut out = String::from(
            "# Tolerances: one entry per parameter family, { sigma = ... } (normal, one\n\
             # standard deviation) or { half_width = ... } (uniform), in the unit the key\n\
             # names. Every coordinate of every member is perturbed independently; a\n\
             # family left out is not perturbed.\n",
        );
        let mut group = "";
        for (family, distribution) in self.iter() {
            let key = family.key();
            let (table, name) = key.rsplit_once('.').unwrap_or(("", key));
            if table != group {
                out.push_str(&format!("\n[{table}]\n"));
                group = table;
            }
            let comment = match family {
                Family::GuideDirection => "  # tilt about a random perpendicular axis",
                Family::Alpha if table == "instruments" => "  # both modules",
                _ => "",
            };
            out.push_str(&format!("{name} = {}{comment}\n", distribution.text()));
        }
        out
    }
}

fn read_entry(value: &Value, key: &str, origin: &str) -> Result<Distribution, SpecError> {
    let entry_error = |why: &str| SpecError::Entry {
        origin: origin.to_string(),
        key: key.to_string(),
        why: why.to_string(),
    };
    let Some(table) = value.as_table() else {
        return Err(entry_error("not a table"));
    };
    if table.len() != 1 {
        return Err(entry_error(&format!(
            "exactly one of sigma and half_width is expected, got {} keys",
            table.len()
        )));
    }
    let Some((name, v)) = table.iter().next() else {
        return Err(entry_error("empty"));
    };
    let width = match v {
        Value::Float(x) => *x,
        Value::Integer(i) => *i as f64,
        _ => return Err(entry_error(&format!("`{name}` must be a number"))),
    };
    let full = format!("{key}.{name}");
    if !(width >= 0.0 && width.is_finite()) {
        return Err(SpecError::Width {
            origin: origin.to_string(),
            key: full,
            value: width,
        });
    }
    match name.as_str() {
        "sigma" => Ok(Distribution::Normal { sigma: width }),
        "half_width" => Ok(Distribution::Uniform { half_width: width }),
        _ => Err(SpecError::UnknownKey {
            origin: origin.to_string(),
            key: full,
            known: "sigma, half_width".to_string(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_issue_text_reads_as_the_default() {
        let text = "[module1.guides]\n\
                    point_mm = { sigma = 0.05 }\n\
                    direction_deg = { sigma = 0.02 }\n\
                    link_length_mm = { sigma = 0.02 }\n\
                    encoder_offset_mm = { half_width = 0.01 }\n\
                    [module1.legs]\n\
                    node_mm = { sigma = 0.05 }\n\
                    [instruments]\n\
                    alpha_deg = { sigma = 0.01 }\n\
                    beta_deg = { sigma = 0.01 }\n\
                    rcm_mm = { sigma = 0.05 }\n";
        assert_eq!(Spec::from_toml(text), Ok(Spec::default()));
        let json = r#"{"module1": {"legs": {"node_mm": {"half_width": 2}}}}"#;
        let spec = Spec::from_json(json).expect("valid");
        assert_eq!(
            spec.get(Family::LegNode),
            Some(Distribution::Uniform { half_width: 2.0 })
        );
        assert_eq!(spec.iter().count(), 1);
    }

    #[test]
    fn bad_specifications_say_what_and_where() {
        let err = |text: &str| Spec::from_toml(text).expect_err("invalid").to_string();
        let e = err("[instruments]\ngamma_deg = { sigma = 1.0 }\n");
        assert!(e.contains("unknown key `instruments.gamma_deg`"), "{e}");
        assert!(e.contains("instruments.alpha_deg"), "{e}");
        let e = err("[module1.guides]\npoint_mm = { sigma = -0.1 }\n");
        assert!(
            e.contains("`module1.guides.point_mm.sigma` must be finite and >= 0, got -0.1"),
            "{e}"
        );
        let e = err("[module1.guides]\npoint_mm = { sigma = 0.1, half_width = 0.1 }\n");
        assert!(e.contains("exactly one of sigma and half_width"), "{e}");
        let e = err("[module1.guides]\npoint_mm = { spread = 0.1 }\n");
        assert!(
            e.contains("unknown key `module1.guides.point_mm.spread`"),
            "{e}"
        );
        let e = err("[module2]\n");
        assert!(e.contains("unknown key `module2`"), "{e}");
        let e = err("[module1.guides]\npoint_mm = { sigma = nan }\n");
        assert!(e.contains("got NaN"), "{e}");
        let e = err("[instruments\n");
        assert!(e.contains("line 1"), "{e}");
    }

    #[test]
    fn the_uniform_and_normal_widths() {
        let u = Distribution::Uniform {
            half_width: 3f64.sqrt(),
        };
        assert!((u.std_dev() - 1.0).abs() < 1e-15);
        assert_eq!(u.deviation(7.0, 0.0), -3f64.sqrt());
        assert_eq!(u.deviation(7.0, 0.5), 0.0);
        let n = Distribution::Normal { sigma: 0.5 };
        assert_eq!(n.deviation(2.0, 0.9), 1.0);
        assert_eq!(n.extreme(), 3.0);
    }
}
