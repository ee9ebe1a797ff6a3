//! A column and the MCAP channel it is on; the units and the constructors
//! the tables are written with.

use crate::record::Record;

/// A data channel of the MCAP file: one message per sample on each.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Channel {
    /// `/platform`: the pose, the Euler rates and accelerations.
    Platform,
    /// `/module1`: the actuators, their rates and accelerations.
    Module1,
    /// `/left`: the left instrument module's joints, rates, accelerations.
    Left,
    /// `/right`: the right instrument module's.
    Right,
    /// `/tips`: the tips recomputed by forward kinematics and their distances
    /// to the targets, and the ports (fixed frame).
    Tips,
    /// `/margins`: module 1's serial and parallel margins, `cos qs2` of each
    /// instrument module.
    Margins,
    /// `/camera`: what the endoscope's camera sees: where each tip falls in
    /// the image, whether it is in view, the aim error and the image's roll.
    Camera,
}

impl Channel {
    /// Every data channel, in the order of the file's channel ids.
    pub const ALL: [Channel; 7] = [
        Channel::Platform,
        Channel::Module1,
        Channel::Left,
        Channel::Right,
        Channel::Tips,
        Channel::Margins,
        Channel::Camera,
    ];

    /// The MCAP topic.
    pub const fn topic(self) -> &'static str {
        match self {
            Channel::Platform => "/platform",
            Channel::Module1 => "/module1",
            Channel::Left => "/left",
            Channel::Right => "/right",
            Channel::Tips => "/tips",
            Channel::Margins => "/margins",
            Channel::Camera => "/camera",
        }
    }

    /// The name of the channel's JSON schema.
    pub const fn schema_name(self) -> &'static str {
        match self {
            Channel::Platform => "parasils.Platform",
            Channel::Module1 => "parasils.Module1",
            Channel::Left => "parasils.LeftModule",
            Channel::Right => "parasils.RightModule",
            Channel::Tips => "parasils.Tips",
            Channel::Margins => "parasils.Margins",
            Channel::Camera => "parasils.Camera",
        }
    }

    /// The description of the channel's JSON schema.
    pub const fn description(self) -> &'static str {
        match self {
            Channel::Platform => "Platform pose (paper's figure 5: psi, theta), fixed frame",
            Channel::Module1 => "Module 1 actuators q1..q6 (paper's figure 6)",
            Channel::Left => "Left instrument module joints (paper's figure 7)",
            Channel::Right => "Right instrument module joints",
            Channel::Tips => {
                "Instrument tips recomputed by forward kinematics (fixed frame) and their distance to the targets; the ports where the shafts and the endoscope cross the skin (fixed frame)"
            }
            Channel::Margins => {
                "Singularity margins: module 1 serial and parallel, cos qs2 of each instrument module; clearance: the surface gaps between the shafts and the endoscope (mm)"
            }
            Channel::Camera => {
                "What the endoscope's camera sees: each commanded tip's normalised image coordinates (-1 to 1 across the image) and whether it is in view, the angle between the view axis and the look-at target, the image's roll about the view axis since the start"
            }
        }
    }
}

/// One output column.
#[derive(Debug, Clone, Copy)]
pub struct Column {
    /// The name, ending with the unit: `t_s`, `q1_rate_mm_s`.
    pub name: &'static str,
    /// The unit, for people: `"deg/s^2"`, `"1 (dimensionless)"`.
    pub unit: &'static str,
    /// The MCAP channel; `None` for the time, the first field of every
    /// channel, and for [`COMMAND`](crate::columns::COMMAND), which is on `/motion` (see
    /// [`mcap`](crate::mcap)).
    pub channel: Option<Channel>,
    /// Whether the CSV (and the Python table) has the column; `false` for
    /// the MCAP's recomputed tip positions.
    pub csv: bool,
    /// Whether the values are whole numbers, written without a fraction
    /// (`2`, not `2.0`): [`COMMAND`](crate::columns::COMMAND).
    pub integer: bool,
    /// The value in the column's unit.
    pub get: fn(&Record) -> f64,
}

impl Column {
    /// The column's value for `record`, in its unit.
    #[inline]
    pub fn value(&self, record: &Record) -> f64 {
        (self.get)(record)
    }
}

pub(super) const S: &str = "s";
pub(super) const MM: &str = "mm";
pub(super) const MM_S: &str = "mm/s";
pub(super) const MM_S2: &str = "mm/s^2";
pub(super) const DEG: &str = "deg";
pub(super) const DEG_S: &str = "deg/s";
pub(super) const DEG_S2: &str = "deg/s^2";
pub(super) const ONE: &str = "1 (dimensionless)";
pub(super) const INDEX: &str = "index";
/// A yes/no column: 1 or 0.
pub(super) const FLAG: &str = "1 (yes) or 0 (no)";

pub(super) const fn col(
    name: &'static str,
    unit: &'static str,
    channel: Channel,
    get: fn(&Record) -> f64,
) -> Column {
    Column {
        name,
        unit,
        channel: Some(channel),
        csv: true,
        integer: false,
        get,
    }
}

pub(super) const fn mcap_only(
    name: &'static str,
    unit: &'static str,
    channel: Channel,
    get: fn(&Record) -> f64,
) -> Column {
    Column {
        csv: false,
        ..col(name, unit, channel, get)
    }
}
