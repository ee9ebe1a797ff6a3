//! The anatomy file: TOML, one `[[region]]` table per forbidden region, in
//! the fixed frame, mm.
//!
//! ```toml
//! [[region]]
//! name = "liver"
//! shape = "mesh"
//! file = "liver.stl"             # STL (binary or ASCII) or OBJ, mm, relative to this file
//! translation_mm = [0, 0, -600]  # optional, added to every vertex
//!
//! [[region]]
//! name = "aorta"
//! shape = "capsule"
//! start_mm = [0, 40, -650]
//! end_mm = [0, -40, -650]
//! radius_mm = 10
//!
//! [[region]]
//! name = "kidney"
//! shape = "sphere"
//! centre_mm = [60, 0, -640]
//! radius_mm = 20
//!
//! [[region]]
//! name = "spine"
//! shape = "box"
//! centre_mm = [0, 0, -700]
//! half_extents_mm = [15, 80, 15]
//! rotation_deg = [0, 0, 30]      # optional, R_X(psi) R_Y(theta) R_Z(phi)
//! ```
//!
//! Every region needs a `name` (unique in the file) and a `shape`; a key
//! the shape does not take is refused, so a misspelt key cannot be ignored.
//! Sizes must be positive and every coordinate a finite number.

use std::path::{Path, PathBuf};

use toml::{Table, Value};

use crate::error::AnatomyError;
use crate::mesh::Mesh;
use crate::region::{Region, Shape};

/// The forbidden regions of one anatomy file.
#[derive(Debug, Clone, PartialEq)]
pub struct Anatomy {
    /// The file they were read from.
    pub file: PathBuf,
    /// The regions, in the file's order.
    pub regions: Vec<Region>,
}

/// The keys each shape takes besides `name` and `shape`.
fn keys_of(kind: &str) -> Option<&'static [&'static str]> {
    Some(match kind {
        "sphere" => &["centre_mm", "radius_mm"],
        "box" => &["centre_mm", "half_extents_mm", "rotation_deg"],
        "capsule" => &["start_mm", "end_mm", "radius_mm"],
        "mesh" => &["file", "translation_mm"],
        _ => return None,
    })
}

/// Reads one region's keys, naming the file and the region in its errors.
struct Reader<'a> {
    file: &'a Path,
    region: String,
    table: &'a Table,
}

impl Reader<'_> {
    fn error(&self, key: &str, problem: impl Into<String>) -> AnatomyError {
        AnatomyError::Key {
            file: self.file.to_path_buf(),
            region: self.region.clone(),
            key: key.to_owned(),
            problem: problem.into(),
        }
    }

    fn number(&self, key: &str, value: &Value) -> Result<f64, AnatomyError> {
        let x = match value {
            Value::Float(x) => *x,
            Value::Integer(i) => *i as f64,
            _ => return Err(self.error(key, "must be a number (mm or deg)")),
        };
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.error(key, format!("{x} is not a finite number")))
        }
    }

    fn vector(&self, key: &str) -> Result<Option<[f64; 3]>, AnatomyError> {
        let Some(value) = self.table.get(key) else {
            return Ok(None);
        };
        let bad = || self.error(key, "must be an array of three numbers");
        let items = value.as_array().filter(|a| a.len() == 3).ok_or_else(bad)?;
        let mut out = [0.0; 3];
        for (o, item) in out.iter_mut().zip(items) {
            *o = self.number(key, item)?;
        }
        Ok(Some(out))
    }

    fn required_vector(&self, key: &str) -> Result<[f64; 3], AnatomyError> {
        self.vector(key)?
            .ok_or_else(|| self.error(key, "is missing (an array of three numbers, mm)"))
    }

    fn positive(&self, key: &str) -> Result<f64, AnatomyError> {
        let value = self
            .table
            .get(key)
            .ok_or_else(|| self.error(key, "is missing (a positive number, mm)"))?;
        let x = self.number(key, value)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.error(key, format!("{x} must be positive")))
        }
    }

    fn text(&self, key: &str) -> Result<&str, AnatomyError> {
        match self.table.get(key) {
            Some(Value::String(s)) if !s.trim().is_empty() => Ok(s),
            Some(_) => Err(self.error(key, "must be a non-empty string")),
            None => Err(self.error(key, "is missing")),
        }
    }
}

impl Anatomy {
    /// Reads the anatomy file `path`, its meshes relative to its folder.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, AnatomyError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| AnatomyError::Read {
            file: path.to_path_buf(),
            message: e.to_string(),
        })?;
        let base = path.parent().unwrap_or(Path::new("."));
        Self::parse(&text, path, base)
    }

    /// The anatomy of `text`, named `file` in errors, its mesh files read
    /// relative to `base`.
    pub fn parse(text: &str, file: &Path, base: &Path) -> Result<Self, AnatomyError> {
        let syntax = |message: String| AnatomyError::Syntax {
            file: file.to_path_buf(),
            message,
        };
        let root: Table = text
            .parse()
            .map_err(|e: toml::de::Error| syntax(e.to_string()))?;
        if let Some(key) = root.keys().find(|k| *k != "region") {
            return Err(syntax(format!(
                "unknown top-level key {key:?}: regions are given as [[region]] tables"
            )));
        }
        let tables = match root.get("region") {
            Some(Value::Array(items)) if !items.is_empty() => items,
            _ => {
                return Err(syntax(
                    "no region: give at least one [[region]] table".into(),
                ));
            }
        };
        let mut regions: Vec<Region> = Vec::with_capacity(tables.len());
        for (i, item) in tables.iter().enumerate() {
            let Some(table) = item.as_table() else {
                return Err(syntax(format!("region #{} is not a table", i + 1)));
            };
            let mut reader = Reader {
                file,
                region: format!("#{}", i + 1),
                table,
            };
            let name = reader.text("name")?.to_owned();
            if regions.iter().any(|r| r.name == name) {
                return Err(reader.error("name", format!("{name:?} is given to two regions")));
            }
            reader.region = name.clone();
            let kind = reader.text("shape")?;
            let Some(keys) = keys_of(kind) else {
                return Err(reader.error(
                    "shape",
                    format!("{kind:?} must be \"sphere\", \"box\", \"capsule\" or \"mesh\""),
                ));
            };
            if let Some(key) = table
                .keys()
                .find(|k| !["name", "shape"].contains(&k.as_str()) && !keys.contains(&k.as_str()))
            {
                return Err(reader.error(
                    key,
                    format!("is not a key of a {kind} (it takes {})", keys.join(", ")),
                ));
            }
            let shape = reader.shape(kind, base)?;
            let region = Region::new(name.clone(), shape).map_err(|problem| {
                let mesh = table
                    .get("file")
                    .and_then(Value::as_str)
                    .map_or_else(PathBuf::new, |f| base.join(f));
                AnatomyError::Mesh {
                    file: file.to_path_buf(),
                    region: name,
                    mesh,
                    problem,
                }
            })?;
            regions.push(region);
        }
        Ok(Self {
            file: file.to_path_buf(),
            regions,
        })
    }

    /// The region named `name`.
    pub fn region(&self, name: &str) -> Option<&Region> {
        self.regions.iter().find(|r| r.name == name)
    }
}

impl Reader<'_> {
    fn shape(&self, kind: &str, base: &Path) -> Result<Shape, AnatomyError> {
        Ok(match kind {
            "sphere" => Shape::Sphere {
                centre_mm: self.required_vector("centre_mm")?,
                radius_mm: self.positive("radius_mm")?,
            },
            "box" => {
                let half_extents_mm = self.required_vector("half_extents_mm")?;
                if let Some(h) = half_extents_mm.iter().find(|h| !(**h > 0.0)) {
                    return Err(self.error("half_extents_mm", format!("{h} must be positive")));
                }
                Shape::Box {
                    centre_mm: self.required_vector("centre_mm")?,
                    half_extents_mm,
                    rotation_deg: self.vector("rotation_deg")?.unwrap_or_default(),
                }
            }
            "capsule" => Shape::Capsule {
                start_mm: self.required_vector("start_mm")?,
                end_mm: self.required_vector("end_mm")?,
                radius_mm: self.positive("radius_mm")?,
            },
            _ => {
                let path = base.join(self.text("file")?);
                let translation_mm = self.vector("translation_mm")?.unwrap_or_default();
                let mesh = Mesh::read(&path)
                    .map_err(|problem| AnatomyError::Mesh {
                        file: self.file.to_path_buf(),
                        region: self.region.clone(),
                        mesh: path.clone(),
                        problem,
                    })?
                    .translated(translation_mm);
                let solid = mesh.is_closed();
                Shape::Mesh {
                    file: path,
                    translation_mm,
                    mesh,
                    solid,
                }
            }
        })
    }
}
