//! The columns of every run, in one table ([`ALL`]), and the command's.

use super::column::{
    Channel, Column, DEG, DEG_S, DEG_S2, FLAG, INDEX, MM, MM_S, MM_S2, ONE, S, col, mcap_only,
};
use crate::record::Record;

/// Time since the start, s.
pub const T_S: Column = Column {
    name: "t_s",
    unit: S,
    channel: None,
    csv: true,
    integer: false,
    get: |r| r.t,
};
/// `X_P`, mm.
pub const X_MM: Column = col("x_mm", MM, Channel::Platform, |r| r.pose[0]);
/// `Y_P`, mm.
pub const Y_MM: Column = col("y_mm", MM, Channel::Platform, |r| r.pose[1]);
/// `Z_P`, mm.
pub const Z_MM: Column = col("z_mm", MM, Channel::Platform, |r| r.pose[2]);
/// `psi`, deg ([`Record::angles_deg`]).
pub const PSI_DEG: Column = col("psi_deg", DEG, Channel::Platform, |r| r.angles_deg[0]);
/// `theta`, deg ([`Record::angles_deg`]).
pub const THETA_DEG: Column = col("theta_deg", DEG, Channel::Platform, |r| r.angles_deg[1]);
/// `phi`, deg ([`Record::angles_deg`]).
pub const PHI_DEG: Column = col("phi_deg", DEG, Channel::Platform, |r| r.angles_deg[2]);
/// The rate of `psi`, deg/s.
pub const PSI_RATE_DEG_S: Column = col("psi_rate_deg_s", DEG_S, Channel::Platform, |r| {
    r.euler_dot[0].to_degrees()
});
/// The rate of `theta`, deg/s.
pub const THETA_RATE_DEG_S: Column = col("theta_rate_deg_s", DEG_S, Channel::Platform, |r| {
    r.euler_dot[1].to_degrees()
});
/// The acceleration of `psi`, deg/s^2.
pub const PSI_ACC_DEG_S2: Column = col("psi_acc_deg_s2", DEG_S2, Channel::Platform, |r| {
    r.euler_ddot[0].to_degrees()
});
/// The acceleration of `theta`, deg/s^2.
pub const THETA_ACC_DEG_S2: Column = col("theta_acc_deg_s2", DEG_S2, Channel::Platform, |r| {
    r.euler_ddot[1].to_degrees()
});

/// Six columns of module 1, one per actuator, `q1` to `q6`.
macro_rules! per_actuator {
    ($suffix:literal, $unit:expr, $field:ident) => {
        [
            col(concat!("q1", $suffix), $unit, Channel::Module1, |r| {
                r.module1.$field[0]
            }),
            col(concat!("q2", $suffix), $unit, Channel::Module1, |r| {
                r.module1.$field[1]
            }),
            col(concat!("q3", $suffix), $unit, Channel::Module1, |r| {
                r.module1.$field[2]
            }),
            col(concat!("q4", $suffix), $unit, Channel::Module1, |r| {
                r.module1.$field[3]
            }),
            col(concat!("q5", $suffix), $unit, Channel::Module1, |r| {
                r.module1.$field[4]
            }),
            col(concat!("q6", $suffix), $unit, Channel::Module1, |r| {
                r.module1.$field[5]
            }),
        ]
    };
}

/// Module 1's actuators `q1..q6`, mm.
pub const Q_MM: [Column; 6] = per_actuator!("_mm", MM, q);
/// Their rates, mm/s.
pub const Q_RATE_MM_S: [Column; 6] = per_actuator!("_rate_mm_s", MM_S, q_dot);
/// Their accelerations, mm/s^2.
pub const Q_ACC_MM_S2: [Column; 6] = per_actuator!("_acc_mm_s2", MM_S2, q_ddot);
/// Module 1's smallest serial margin.
pub const MODULE1_SERIAL_MARGIN: Column =
    col("module1_serial_margin", ONE, Channel::Margins, |r| {
        r.module1.serial_margin
    });
/// Module 1's parallel margin.
pub const MODULE1_PARALLEL_MARGIN: Column =
    col("module1_parallel_margin", ONE, Channel::Margins, |r| {
        r.module1.parallel_margin
    });

/// The columns of one instrument module.
#[derive(Debug, Clone, Copy)]
pub struct InstrumentColumns {
    /// `qs1`, `qs2` (deg), `qs3` (mm).
    pub q: [Column; 3],
    /// Their rates (deg/s, deg/s, mm/s).
    pub q_rate: [Column; 3],
    /// Their accelerations (deg/s^2, deg/s^2, mm/s^2).
    pub q_acc: [Column; 3],
    /// `cos qs2`, signed (positive in assembly mode A).
    pub cos_qs2: Column,
    /// The recomputed tip's distance to its target, mm.
    pub tip_err: Column,
    /// The recomputed tip, mm, fixed frame (MCAP only).
    pub tip: [Column; 3],
}

/// The columns of the instrument module in field `$side` of a record, named
/// `$prefix_...`, on `$channel`.
macro_rules! instrument_columns {
    ($side:ident, $prefix:literal, $channel:expr) => {
        InstrumentColumns {
            q: [
                col(concat!($prefix, "_qs1_deg"), DEG, $channel, |r| {
                    r.$side.q[0].to_degrees()
                }),
                col(concat!($prefix, "_qs2_deg"), DEG, $channel, |r| {
                    r.$side.q[1].to_degrees()
                }),
                col(concat!($prefix, "_qs3_mm"), MM, $channel, |r| r.$side.q[2]),
            ],
            q_rate: [
                col(concat!($prefix, "_qs1_rate_deg_s"), DEG_S, $channel, |r| {
                    r.$side.q_dot[0].to_degrees()
                }),
                col(concat!($prefix, "_qs2_rate_deg_s"), DEG_S, $channel, |r| {
                    r.$side.q_dot[1].to_degrees()
                }),
                col(concat!($prefix, "_qs3_rate_mm_s"), MM_S, $channel, |r| {
                    r.$side.q_dot[2]
                }),
            ],
            q_acc: [
                col(concat!($prefix, "_qs1_acc_deg_s2"), DEG_S2, $channel, |r| {
                    r.$side.q_ddot[0].to_degrees()
                }),
                col(concat!($prefix, "_qs2_acc_deg_s2"), DEG_S2, $channel, |r| {
                    r.$side.q_ddot[1].to_degrees()
                }),
                col(concat!($prefix, "_qs3_acc_mm_s2"), MM_S2, $channel, |r| {
                    r.$side.q_ddot[2]
                }),
            ],
            cos_qs2: col(concat!($prefix, "_cos_qs2"), ONE, Channel::Margins, |r| {
                r.$side.cos_qs2
            }),
            tip_err: col(concat!($prefix, "_tip_err_mm"), MM, Channel::Tips, |r| {
                r.$side.tip_err
            }),
            tip: [
                mcap_only(concat!($prefix, "_tip_x_mm"), MM, Channel::Tips, |r| {
                    r.$side.tip.x
                }),
                mcap_only(concat!($prefix, "_tip_y_mm"), MM, Channel::Tips, |r| {
                    r.$side.tip.y
                }),
                mcap_only(concat!($prefix, "_tip_z_mm"), MM, Channel::Tips, |r| {
                    r.$side.tip.z
                }),
            ],
        }
    };
}

/// The surface gap between the two instrument shafts, mm (the distance
/// between their axes minus both radii; negative when they overlap).
pub const CLEARANCE_LEFT_RIGHT_MM: Column =
    col("clearance_left_right_mm", MM, Channel::Margins, |r| {
        r.clearance.left_right
    });
/// The surface gap between the left shaft and the endoscope, mm.
pub const CLEARANCE_LEFT_ENDOSCOPE_MM: Column =
    col("clearance_left_endoscope_mm", MM, Channel::Margins, |r| {
        r.clearance.left_endoscope
    });
/// The surface gap between the right shaft and the endoscope, mm.
pub const CLEARANCE_RIGHT_ENDOSCOPE_MM: Column =
    col("clearance_right_endoscope_mm", MM, Channel::Margins, |r| {
        r.clearance.right_endoscope
    });
/// The smallest of the three gaps, mm.
pub const CLEARANCE_MIN_MM: Column = col("clearance_min_mm", MM, Channel::Margins, |r| {
    r.clearance.min()
});

/// A column of what the camera sees, on `/camera`.
const fn camera(name: &'static str, unit: &'static str, get: fn(&Record) -> f64) -> Column {
    col(name, unit, Channel::Camera, get)
}

/// A yes/no column of what the camera sees: `1.0` or `0.0`, a number like
/// the others (so that every column of every run but the indices is a
/// float).
const fn camera_flag(name: &'static str, get: fn(&Record) -> f64) -> Column {
    camera(name, FLAG, get)
}

/// Where the commanded left tip falls across the image, normalised: `-1`
/// at the image's left edge, `+1` at its right (`Camera::project`).
pub const LEFT_TIP_U: Column = camera("left_tip_u", ONE, |r| r.camera.tips[0][0]);
/// Where the commanded left tip falls up the image, normalised: `-1` to
/// `+1`.
pub const LEFT_TIP_V: Column = camera("left_tip_v", ONE, |r| r.camera.tips[0][1]);
/// The right tip across the image, as [`LEFT_TIP_U`].
pub const RIGHT_TIP_U: Column = camera("right_tip_u", ONE, |r| r.camera.tips[1][0]);
/// The right tip up the image, as [`LEFT_TIP_V`].
pub const RIGHT_TIP_V: Column = camera("right_tip_v", ONE, |r| r.camera.tips[1][1]);
/// Whether the left tip is in view: `1` when ahead of the camera with
/// `|u| <= 1` and `|v| <= 1`, else `0`.
pub const LEFT_TIP_IN_VIEW: Column = camera_flag("left_tip_in_view", |r| {
    f64::from(u8::from(r.camera.in_view[0]))
});
/// Whether the right tip is in view, as [`LEFT_TIP_IN_VIEW`].
pub const RIGHT_TIP_IN_VIEW: Column = camera_flag("right_tip_in_view", |r| {
    f64::from(u8::from(r.camera.in_view[1]))
});
/// The angle between the view axis and the direction from the camera to
/// the look-at target (the run's, or the tips' midpoint for a run given by
/// angles), deg.
pub const CAMERA_AIM_ERROR_DEG: Column = camera("camera_aim_error_deg", DEG, |r| {
    r.camera.aim_error.to_degrees()
});
/// The image's roll about the view axis since the start, deg (right-handed
/// about the view direction; see `docs/model.md`, *What the camera sees*).
pub const CAMERA_ROLL_DEG: Column = camera("camera_roll_deg", DEG, |r| r.camera.roll.to_degrees());

/// The left instrument module's columns.
pub const LEFT: InstrumentColumns = instrument_columns!(left, "left", Channel::Left);
/// The right instrument module's columns.
pub const RIGHT: InstrumentColumns = instrument_columns!(right, "right", Channel::Right);

/// The ports, where each shaft crosses the skin, mm, fixed frame (the last
/// nine of [`CSV`](crate::columns::CSV), and MCAP `/tips`): `left_port_x_mm`, `_y_`, `_z_`,
/// then `right_port_`, then `endoscope_port_` (the modules' RCMs
/// `P + R rcm` and the endoscope's insertion point `P`).
pub const PORTS: [Column; 9] = [
    col("left_port_x_mm", MM, Channel::Tips, |r| r.ports[0].x),
    col("left_port_y_mm", MM, Channel::Tips, |r| r.ports[0].y),
    col("left_port_z_mm", MM, Channel::Tips, |r| r.ports[0].z),
    col("right_port_x_mm", MM, Channel::Tips, |r| r.ports[1].x),
    col("right_port_y_mm", MM, Channel::Tips, |r| r.ports[1].y),
    col("right_port_z_mm", MM, Channel::Tips, |r| r.ports[1].z),
    col("endoscope_port_x_mm", MM, Channel::Tips, |r| r.ports[2].x),
    col("endoscope_port_y_mm", MM, Channel::Tips, |r| r.ports[2].y),
    col("endoscope_port_z_mm", MM, Channel::Tips, |r| r.ports[2].z),
];

/// Every column, in order: the CSV's columns are those with `csv` set, in
/// this order; each MCAP channel's fields are `t_s` then its columns, in this
/// order.
pub const ALL: [Column; 80] = [
    T_S,
    X_MM,
    Y_MM,
    Z_MM,
    PSI_DEG,
    THETA_DEG,
    PHI_DEG,
    PSI_RATE_DEG_S,
    THETA_RATE_DEG_S,
    PSI_ACC_DEG_S2,
    THETA_ACC_DEG_S2,
    Q_MM[0],
    Q_MM[1],
    Q_MM[2],
    Q_MM[3],
    Q_MM[4],
    Q_MM[5],
    Q_RATE_MM_S[0],
    Q_RATE_MM_S[1],
    Q_RATE_MM_S[2],
    Q_RATE_MM_S[3],
    Q_RATE_MM_S[4],
    Q_RATE_MM_S[5],
    Q_ACC_MM_S2[0],
    Q_ACC_MM_S2[1],
    Q_ACC_MM_S2[2],
    Q_ACC_MM_S2[3],
    Q_ACC_MM_S2[4],
    Q_ACC_MM_S2[5],
    MODULE1_SERIAL_MARGIN,
    MODULE1_PARALLEL_MARGIN,
    LEFT.q[0],
    LEFT.q[1],
    LEFT.q[2],
    LEFT.q_rate[0],
    LEFT.q_rate[1],
    LEFT.q_rate[2],
    LEFT.q_acc[0],
    LEFT.q_acc[1],
    LEFT.q_acc[2],
    LEFT.cos_qs2,
    LEFT.tip_err,
    RIGHT.q[0],
    RIGHT.q[1],
    RIGHT.q[2],
    RIGHT.q_rate[0],
    RIGHT.q_rate[1],
    RIGHT.q_rate[2],
    RIGHT.q_acc[0],
    RIGHT.q_acc[1],
    RIGHT.q_acc[2],
    RIGHT.cos_qs2,
    RIGHT.tip_err,
    CLEARANCE_LEFT_RIGHT_MM,
    CLEARANCE_LEFT_ENDOSCOPE_MM,
    CLEARANCE_RIGHT_ENDOSCOPE_MM,
    CLEARANCE_MIN_MM,
    LEFT_TIP_U,
    LEFT_TIP_V,
    RIGHT_TIP_U,
    RIGHT_TIP_V,
    LEFT_TIP_IN_VIEW,
    RIGHT_TIP_IN_VIEW,
    CAMERA_AIM_ERROR_DEG,
    CAMERA_ROLL_DEG,
    LEFT.tip[0],
    LEFT.tip[1],
    LEFT.tip[2],
    RIGHT.tip[0],
    RIGHT.tip[1],
    RIGHT.tip[2],
    PORTS[0],
    PORTS[1],
    PORTS[2],
    PORTS[3],
    PORTS[4],
    PORTS[5],
    PORTS[6],
    PORTS[7],
    PORTS[8],
];

/// The index of the active command (see
/// [`Command`](crate::scenario::Command)): 0 for the reorientation, one more
/// at each retarget and at each stop. Only runs with commands have it: the
/// last column of [`CSV_WITH_COMMAND`](crate::columns::CSV_WITH_COMMAND), and `/motion` in MCAP.
pub const COMMAND: Column = Column {
    name: "command",
    unit: INDEX,
    channel: None,
    csv: true,
    integer: true,
    get: |r| f64::from(r.command),
};
