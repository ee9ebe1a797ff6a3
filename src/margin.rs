//! The margins a cycle reports, by name: which distance from a hard limit
//! or a singularity each one is (see [`crate::supervisor`]).

/// One margin the [supervisor](crate::supervisor) watches; the index into
/// [`Margins`](crate::supervisor::Margins) and
/// [`MarginSet`](crate::supervisor::MarginSet).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum Margin {
    /// The left module's `|cos qs2|` (dimensionless; 0 at its singularity).
    LeftCosQs2 = 0,
    /// The left module's `qs3`, mm (0 with the tip at the RCM).
    LeftQs3 = 1,
    /// The left module's `qs1` and `qs2`, the nearer to its limit: distance, rad.
    LeftAngleLimits = 2,
    /// The left module's `qs3` to its nearer limit, mm.
    LeftQs3Limits = 3,
    /// The right module's `|cos qs2|`.
    RightCosQs2 = 4,
    /// The right module's `qs3`, mm.
    RightQs3 = 5,
    /// The right module's `qs1` and `qs2` to their limits, rad.
    RightAngleLimits = 6,
    /// The right module's `qs3` to its limits, mm.
    RightQs3Limits = 7,
    /// Module 1's smallest serial margin (dimensionless).
    Serial = 8,
    /// Module 1's parallel margin (dimensionless).
    Parallel = 9,
    /// Module 1's actuators, the nearest to an end of its stroke: distance, mm.
    Stroke = 10,
}

impl Margin {
    /// How many margins there are.
    pub const COUNT: usize = 11;

    /// Every margin, in index order.
    pub const ALL: [Margin; Margin::COUNT] = [
        Margin::LeftCosQs2,
        Margin::LeftQs3,
        Margin::LeftAngleLimits,
        Margin::LeftQs3Limits,
        Margin::RightCosQs2,
        Margin::RightQs3,
        Margin::RightAngleLimits,
        Margin::RightQs3Limits,
        Margin::Serial,
        Margin::Parallel,
        Margin::Stroke,
    ];

    /// The index into [`Margins`](crate::supervisor::Margins), `0..COUNT`.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The margin's name as reports write it, e.g. `"module1.parallel"`.
    pub const fn name(self) -> &'static str {
        match self {
            Margin::LeftCosQs2 => "left.cos_qs2",
            Margin::LeftQs3 => "left.qs3",
            Margin::LeftAngleLimits => "left.angle_limits",
            Margin::LeftQs3Limits => "left.qs3_limits",
            Margin::RightCosQs2 => "right.cos_qs2",
            Margin::RightQs3 => "right.qs3",
            Margin::RightAngleLimits => "right.angle_limits",
            Margin::RightQs3Limits => "right.qs3_limits",
            Margin::Serial => "module1.serial",
            Margin::Parallel => "module1.parallel",
            Margin::Stroke => "module1.stroke",
        }
    }

    /// The unit of its value: `""` (dimensionless), `"mm"` or `"rad"`.
    pub const fn unit(self) -> &'static str {
        match self {
            Margin::LeftQs3
            | Margin::LeftQs3Limits
            | Margin::RightQs3
            | Margin::RightQs3Limits
            | Margin::Stroke => "mm",
            Margin::LeftAngleLimits | Margin::RightAngleLimits => "rad",
            Margin::LeftCosQs2 | Margin::RightCosQs2 | Margin::Serial | Margin::Parallel => "",
        }
    }
}

impl core::fmt::Display for Margin {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}
