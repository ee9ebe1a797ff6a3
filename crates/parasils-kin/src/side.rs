//! Which of the two instrument modules.

use core::fmt;

/// Which of the two active instruments.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Side {
    /// Module 2-L, port at `(-10, 0, 0)` mm in the paper.
    Left,
    /// Module 2-R, the mirror image of the left across the platform's `Y'Z'` plane.
    Right,
}

impl Side {
    /// `"left"` or `"right"`.
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }
}

impl fmt::Display for Side {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
