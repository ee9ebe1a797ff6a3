//! One instant of a simulation: everything the engine computes at a sample,
//! typed, in the libraries' units (mm, rad, s).
//!
//! The [`columns`](crate::columns) table says how a [`Record`] is written
//! (which value, in which unit, under which name and on which MCAP channel);
//! the sinks read records through it.

use nalgebra::Vector3;
use parasils::kin::ActuatorLimits;
use parasils::supervisor::MarginSet;

use crate::scenario::CommandKind;

/// Module 1 (the parallel robot) at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Module1Record {
    /// The actuators `q1..q6`, mm.
    pub q: [f64; 6],
    /// Their rates, mm/s.
    pub q_dot: [f64; 6],
    /// Their accelerations, mm/s^2.
    pub q_ddot: [f64; 6],
    /// The smallest serial margin `min_j |e_j.u_j| / l_j`.
    pub serial_margin: f64,
    /// The parallel margin (see `docs/model.md`, *Singularities and
    /// thresholds*).
    pub parallel_margin: f64,
}

/// One instrument module at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct InstrumentRecord {
    /// `qs1, qs2` (rad), `qs3` (mm).
    pub q: [f64; 3],
    /// Joint rates (rad/s, rad/s, mm/s).
    pub q_dot: [f64; 3],
    /// Joint accelerations (rad/s^2, rad/s^2, mm/s^2).
    pub q_ddot: [f64; 3],
    /// `cos qs2`, signed: positive in assembly mode A, negative in B.
    pub cos_qs2: f64,
    /// The tip recomputed from the joints by forward kinematics, mm, fixed
    /// frame.
    pub tip: Vector3<f64>,
    /// The distance from that tip to its target, mm.
    pub tip_err: f64,
}

/// The surface gaps between the bodies at one sample (mm, negative when two
/// overlap): each instrument shaft and the endoscope as a capsule
/// ([`parasils::kin::Bodies`], sizes from the robot file's `[bodies]`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ClearanceRecord {
    /// Left shaft to right shaft, mm.
    pub left_right: f64,
    /// Left shaft to endoscope, mm.
    pub left_endoscope: f64,
    /// Right shaft to endoscope, mm.
    pub right_endoscope: f64,
}

impl ClearanceRecord {
    /// All three gaps `gap_mm`.
    pub fn splat(gap_mm: f64) -> Self {
        Self {
            left_right: gap_mm,
            left_endoscope: gap_mm,
            right_endoscope: gap_mm,
        }
    }

    /// The gap of `pair`, mm.
    pub fn get(&self, pair: parasils::kin::ClearancePair) -> f64 {
        use parasils::kin::ClearancePair::{LeftEndoscope, LeftRight, RightEndoscope};
        match pair {
            LeftRight => self.left_right,
            LeftEndoscope => self.left_endoscope,
            RightEndoscope => self.right_endoscope,
        }
    }

    /// Sets the gap of `pair` to `gap_mm`.
    pub fn set(&mut self, pair: parasils::kin::ClearancePair, gap_mm: f64) {
        use parasils::kin::ClearancePair::{LeftEndoscope, LeftRight, RightEndoscope};
        match pair {
            LeftRight => self.left_right = gap_mm,
            LeftEndoscope => self.left_endoscope = gap_mm,
            RightEndoscope => self.right_endoscope = gap_mm,
        }
    }

    /// The smallest of the three gaps, mm.
    pub fn min(&self) -> f64 {
        self.left_right
            .min(self.left_endoscope)
            .min(self.right_endoscope)
    }
}

/// Every actuator's force at one instant holding the run's tip loads and
/// moving its platform's body (zero in a run without forces; see
/// `parasils_kin::statics` and `Scenario::has_forces`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ForceRecord {
    /// Module 1's slider forces `q1..q6`, N, positive pushing each slider
    /// along its guide's direction `u`.
    pub module1: [f64; 6],
    /// The left module's `qs1`, `qs2` torques (N mm) and `qs3` force (N).
    pub left: [f64; 3],
    /// The right module's, the same.
    pub right: [f64; 3],
    /// How far each tip, `[left, right]`, gives way under the tissue's
    /// push (minus its load), mm, with the scenario's actuator stiffnesses
    /// (the robot file's `[stiffness]`, assumed by default).
    pub deflection: [f64; 2],
}

/// What the endoscope's camera sees at one instant (see `docs/model.md`,
/// *What the camera sees*).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CameraRecord {
    /// Where each commanded tip, `[left, right]`, falls in the image:
    /// `[u, v]`, normalised (`-1` to `1` across the image when in view).
    pub tips: [[f64; 2]; 2],
    /// Whether each tip is ahead of the camera (its `u`, `v` mean nothing
    /// otherwise).
    pub ahead: [bool; 2],
    /// Whether each tip is in view: ahead of the camera, `|u| <= 1` and
    /// `|v| <= 1`.
    pub in_view: [bool; 2],
    /// The angle between the view axis and the direction from the camera
    /// to the run's look-at target, rad.
    pub aim_error: f64,
    /// The image's roll about the view axis since the start, rad
    /// ([`parasils::kin::Camera::roll`]).
    pub roll: f64,
}

/// A teleoperation run's cycle: what each device held, the command given,
/// and what the teleoperation core made of it (see
/// [`parasils::teleop`]). Non-numeric values are small integer codes, as the
/// columns table writes them ([`crate::teleop`] lists the codes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TeleopRecord {
    /// Each device's six normalised axes as held at this cycle,
    /// `[left, right, camera]`, each `[tx, ty, tz, rx, ry, rz]` in the
    /// image frame.
    pub axes: [[f64; 6]; 3],
    /// Each device's buttons as held (bit 0 enable, bit 1 clutch).
    pub buttons: [u8; 3],
    /// The command given at this cycle, if any.
    pub command: Option<parasils::teleop::Command>,
    /// The operating state after this cycle.
    pub state: parasils::teleop::OperatingState,
    /// The limit this cycle holds at, if any.
    pub hold: Option<parasils::teleop::HoldAt>,
    /// The fault the core is in, if any.
    pub fault: Option<parasils::teleop::Fault>,
    /// The module each hand drives, `[left hand, right hand]`.
    pub hands: [parasils::kin::Side; 2],
}

impl Default for TeleopRecord {
    /// Nothing held, no command, DISABLED, each hand on its own side.
    fn default() -> Self {
        Self {
            axes: [[0.0; 6]; 3],
            buttons: [0; 3],
            command: None,
            state: parasils::teleop::OperatingState::Disabled,
            hold: None,
            fault: None,
            hands: [parasils::kin::Side::Left, parasils::kin::Side::Right],
        }
    }
}

/// Everything computed at one instant of a simulation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Record {
    /// The sample's index `k`, from 0.
    pub index: usize,
    /// Time since the start of the motion, `k / rate`, s.
    pub t: f64,
    /// The platform's pose: `[x, y, z]` mm, `[psi, theta, phi]` rad.
    pub pose: [f64; 6],
    /// `[psi, theta, phi]` in degrees as written out: the user's start angle
    /// plus the turn since the start, `start_deg + deg(angle - start_rad)`,
    /// so that the start's own degrees come back unchanged (`-15` stays
    /// `-15` at `t = 0`, and `phi` stays the user's `phi`).
    pub angles_deg: [f64; 3],
    /// The Euler rates `[psi, theta, phi]`, rad/s.
    pub euler_dot: [f64; 3],
    /// The Euler accelerations `[psi, theta, phi]`, rad/s^2.
    pub euler_ddot: [f64; 3],
    /// Module 1.
    pub module1: Module1Record,
    /// The left instrument module.
    pub left: InstrumentRecord,
    /// The right instrument module.
    pub right: InstrumentRecord,
    /// The index of the active command: 0 for the reorientation, one more
    /// at each retarget and at each stop (see
    /// [`Command`](crate::scenario::Command)). Always 0 in a run without
    /// commands.
    pub command: u32,
    /// What the active command is.
    pub kind: CommandKind,
    /// The margins below the online controller's warning thresholds (see
    /// `parasils::supervisor`); always empty in a run without commands,
    /// which has no supervisor.
    pub warnings: MarginSet,
    /// The index of the procedure's motion under way, from 0 (0 in a run
    /// without a procedure).
    pub motion: u32,
    /// Its type, 1 to 4 (the paper's numbering; 4 in a run without a
    /// procedure).
    pub motion_type: u8,
    /// The endoscope's insertion depth, mm (0 at its port, positive
    /// inwards; written in procedures only).
    pub endoscope_depth: f64,
    /// The endoscope's tip, mm, fixed frame (written in procedures only).
    pub endoscope_tip: Vector3<f64>,
    /// The surface gaps between the shafts and the endoscope, mm.
    pub clearance: ClearanceRecord,
    /// The ports, where each shaft crosses the skin, mm, fixed frame: the
    /// left and right modules' RCMs (`P + R rcm`) and the endoscope's
    /// insertion point (`P`), in the order of [`Record::PORTS`].
    pub ports: [Vector3<f64>; 3],
    /// Every actuator's force for the tip loads (written with tip loads
    /// only).
    pub forces: ForceRecord,
    /// What the camera sees.
    pub camera: CameraRecord,
    /// The smallest gap between the in-body part of a shaft or of the
    /// endoscope and a forbidden region, mm (negative inside one; `+inf`
    /// when nothing is inside the patient; written with an anatomy only).
    pub no_go_clearance_mm: f64,
    /// A teleoperation run's cycle (written in such runs only; the default
    /// elsewhere).
    pub teleop: TeleopRecord,
}

impl Record {
    /// The ports of [`Record::ports`], in order.
    pub const PORTS: [parasils::motions::Port; 3] = [
        parasils::motions::Port::Left,
        parasils::motions::Port::Right,
        parasils::motions::Port::Endoscope,
    ];

    /// The twelve actuators' rates and accelerations in the order of
    /// [`parasils::kin::Actuator::ALL`]: `q1..q6` (mm/s), then each
    /// module's `qs1`, `qs2` (rad/s), `qs3` (mm/s).
    pub fn actuator_rates(&self) -> ([f64; 12], [f64; 12]) {
        let pick = |m: [f64; 6], l: [f64; 3], r: [f64; 3]| {
            core::array::from_fn(|k| match k {
                0..6 => m[k],
                6..9 => l[k - 6],
                _ => r[(k - 9).min(2)],
            })
        };
        (
            pick(self.module1.q_dot, self.left.q_dot, self.right.q_dot),
            pick(self.module1.q_ddot, self.left.q_ddot, self.right.q_ddot),
        )
    }

    /// Raises each actuator's peak use of its limits, `usage[0]` the
    /// velocity's and `usage[1]` the acceleration's (fractions, in the order
    /// of [`Actuator::ALL`](parasils::kin::Actuator::ALL)), to this record's.
    pub fn widen_usage(&self, usage: &mut [[f64; 12]; 2], limits: &ActuatorLimits<f64>) {
        let (q_dot, q_ddot) = self.actuator_rates();
        let [uv, ua] = usage;
        for (k, (v, a)) in q_dot.iter().zip(&q_ddot).enumerate() {
            uv[k] = uv[k].max(v.abs() / limits.velocity[k]);
            ua[k] = ua[k].max(a.abs() / limits.acceleration[k]);
        }
    }

    /// The twelve actuators' forces in the order of
    /// [`parasils::kin::Actuator::ALL`]: `q1..q6` (N), then each module's
    /// `qs1`, `qs2` (N mm), `qs3` (N).
    pub fn actuator_forces(&self) -> [f64; 12] {
        let f = &self.forces;
        core::array::from_fn(|k| match k {
            0..6 => f.module1[k],
            6..9 => f.left[k - 6],
            _ => f.right[(k - 9).min(2)],
        })
    }

    /// Raises each actuator's peak use of its force limit (fractions, in the
    /// order of [`Actuator::ALL`](parasils::kin::Actuator::ALL)) to this
    /// record's.
    pub fn widen_force_usage(&self, usage: &mut [f64; 12], limits: &ActuatorLimits<f64>) {
        for ((u, f), limit) in usage
            .iter_mut()
            .zip(self.actuator_forces())
            .zip(&limits.force)
        {
            *u = u.max(f.abs() / limit);
        }
    }

    /// The pose's Euler angles in degrees as [`Record::angles_deg`] writes
    /// them, given the start's angles in degrees and in radians.
    pub fn degrees_from_start(
        angles_rad: [f64; 3],
        start_deg: [f64; 3],
        start_rad: [f64; 3],
    ) -> [f64; 3] {
        core::array::from_fn(|i| start_deg[i] + (angles_rad[i] - start_rad[i]).to_degrees())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_start_angles_come_back_exactly() {
        let start_deg = [-15.0, 10.0, -60.0];
        let start_rad = start_deg.map(f64::to_radians);
        // to_degrees(to_radians(x)) is not x for these.
        assert_ne!(start_rad[0].to_degrees(), -15.0);
        assert_ne!(start_rad[2].to_degrees(), -60.0);
        assert_eq!(
            Record::degrees_from_start(start_rad, start_deg, start_rad),
            start_deg
        );
        let turned = [
            start_rad[0] + 15f64.to_radians(),
            start_rad[1],
            start_rad[2],
        ];
        let d = Record::degrees_from_start(turned, start_deg, start_rad);
        assert!(d[0].abs() < 1e-13, "{}", d[0]);
        assert_eq!(d[1..], start_deg[1..]);
    }
}
