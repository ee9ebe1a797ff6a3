//! The planned moves: home, look at a point, look at the tips, move to a
//! pose. Each is one time-optimal profile ([`OnlineMulti`], the eight
//! coordinates synchronised: both tips' `x, y, z` at the tip's limits
//! divided by `sqrt 3`, `psi` and `theta` at the view's) from the current
//! setpoint and its velocity to its goal; the core is busy (CRTK's
//! `is_busy`) while it runs, the hands are ignored, and every cycle of it
//! passes the same checks as a hand's (a move that would cross a limit is
//! held there and ends). A move is accepted in ENABLED only.
//!
//! | goal | the view's `[psi, theta]` | the tips |
//! |---|---|---|
//! | [`Goal::Home`] | the home pose's | the home tips |
//! | [`Goal::LookAt`] | [`Camera::look_at`] of the point from the current angles (`P`, `phi` held) | held where they are (fixed frame) |
//! | [`Goal::LookAtTips`] | the same, of the tips' midpoint | held |
//! | [`Goal::Pose`] | as given | as given |
//!
//! The tips are held in the fixed frame while the view turns, as the
//! paper's reorientation holds them: each module's joints move so that
//! its tip stays where the surgeon left it.
//!
//! [`Camera::look_at`]: crate::kin::Camera::look_at

use crate::kin::nalgebra::Vector3;
use crate::kin::{CameraError, Real};
use crate::traj::{Limits, OnlineMulti, State, Synchronization};

use super::core::{Busy, Teleop};
use super::input::Command;
use super::state::OperatingState;

/// The goal of a planned move: home, look at a point or the tips, move to
/// a pose (see [`Teleop::start_move`](crate::teleop::Teleop::start_move)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Goal<T> {
    /// The home pose: its view and tips.
    Home,
    /// Aim the view axis through the point (mm, fixed frame), the tips
    /// held.
    LookAt(Vector3<T>),
    /// Aim the view axis through the tips' midpoint, the tips held.
    LookAtTips,
    /// The view at `angles` (`[psi, theta]`, rad) and the tips at `tips`
    /// (`[left module, right module]`, mm, fixed frame).
    Pose {
        /// `[psi, theta]`, rad.
        angles: [T; 2],
        /// The tips, mm, fixed frame.
        tips: [Vector3<T>; 2],
    },
}

impl<T> Goal<T> {
    /// The command's name: `home`, `look_at`, `look_at_tips`, `move_to`.
    pub const fn name(&self) -> &'static str {
        match self {
            Goal::Home => "home",
            Goal::LookAt(_) => "look_at",
            Goal::LookAtTips => "look_at_tips",
            Goal::Pose { .. } => "move_to",
        }
    }
}

/// Why a planned move was refused; the core is then unchanged.
///
/// # When this happens / how to handle it
/// - [`MoveRefused::State`]: moves start in ENABLED only (CRTK's table):
///   enable or resume first.
/// - [`MoveRefused::NonFinite`]: a goal's number is NaN or infinite: fix
///   the goal.
/// - [`MoveRefused::Camera`]: no turn of the platform aims the view at the
///   point (behind the endoscope's tip, `theta = +-90 deg`): choose
///   another point.
/// - [`MoveRefused::Plan`]: the profile cannot be planned from the current
///   state (a limit the parameters make invalid): not expected with
///   validated parameters.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MoveRefused {
    /// The core is not ENABLED.
    #[error("a planned move is valid in ENABLED only (CRTK's table); the state is {0}")]
    State(OperatingState),
    /// A goal's number is not finite.
    #[error("the goal's {what} = {value} is not finite")]
    NonFinite {
        /// Which number: `angles[0]`, `tips[1].z`, `point.x`...
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// The view cannot be aimed at the point.
    #[error("{0}")]
    Camera(#[from] CameraError),
    /// The profile cannot be planned.
    #[error("the move cannot be planned from the current state")]
    Plan,
}

const TIP_NAMES: [[&str; 3]; 2] = [
    ["tips[0].x", "tips[0].y", "tips[0].z"],
    ["tips[1].x", "tips[1].y", "tips[1].z"],
];

fn check<T: Real>(what: &'static str, v: T) -> Result<(), MoveRefused> {
    if v.finite() {
        Ok(())
    } else {
        Err(MoveRefused::NonFinite {
            what,
            value: v.to_f64(),
        })
    }
}

impl<T: Real> Teleop<T> {
    /// Starts a planned move to `goal` from the current setpoint (the last
    /// cycle's, whose time is the move's start: the next cycle is its first
    /// step); the core is busy until it ends, is held at a limit, or a
    /// command ends it (disable, pause, stop, another move).
    ///
    /// # Errors
    /// [`MoveRefused`]: not ENABLED, a non-finite goal, a point the view
    /// cannot aim at; the core is then unchanged.
    pub fn start_move(&mut self, goal: Goal<T>) -> Result<(), MoveRefused> {
        if self.state != OperatingState::Enabled {
            return Err(MoveRefused::State(self.state));
        }
        let t0 = self.last.unwrap_or(T::zero());
        self.plan_move(t0, goal)
    }

    /// The goal's `[psi, theta]` and tips.
    fn resolve(&self, goal: Goal<T>) -> Result<([T; 2], [Vector3<T>; 2]), MoveRefused> {
        let aim = |point: Vector3<T>| {
            self.camera
                .look_at(&self.pose, self.depth, &point)
                .map_err(MoveRefused::from)
        };
        match goal {
            Goal::Home => Ok(self.home),
            Goal::LookAt(point) => {
                for (k, name) in ["point.x", "point.y", "point.z"].into_iter().enumerate() {
                    check(name, point[k])?;
                }
                Ok((aim(point)?, self.tips))
            }
            Goal::LookAtTips => {
                let mid = (self.tips[0] + self.tips[1]) * T::lit(0.5);
                Ok((aim(mid)?, self.tips))
            }
            Goal::Pose { angles, tips } => {
                check("angles[0]", angles[0])?;
                check("angles[1]", angles[1])?;
                for (tip, names) in tips.iter().zip(TIP_NAMES) {
                    for (k, name) in names.into_iter().enumerate() {
                        check(name, tip[k])?;
                    }
                }
                Ok((angles, tips))
            }
        }
    }

    /// Plans the move a command names (`look_at_tips`; `home` for the
    /// others), starting at `t0` (s), as [`plan_move`](Self::plan_move).
    pub(super) fn plan_command(&mut self, t0: T, command: Command) -> Result<(), MoveRefused> {
        let goal = if command == Command::LookAtTips {
            Goal::LookAtTips
        } else {
            Goal::Home
        };
        self.plan_move(t0, goal)
    }

    /// Plans the move to `goal` from the current state, starting at `t0`
    /// (s), and makes it the one under way; the core is unchanged when it
    /// is refused.
    pub(super) fn plan_move(&mut self, t0: T, goal: Goal<T>) -> Result<(), MoveRefused> {
        let (goal_angles, goal_tips) = self.resolve(goal)?;
        let root3 = T::lit(3.0).sqrt();
        let tip = Limits::new(
            self.params.tip_speed_mm_s / root3,
            self.params.tip_accel_mm_s2 / root3,
        );
        let mut start = [State::rest(T::zero()); 8];
        let mut target = [T::zero(); 8];
        let mut limits = [tip; 8];
        for k in 0..3 {
            for m in 0..2 {
                start[3 * m + k] = State {
                    position: self.tips[m][k],
                    velocity: self.velocity.tips[m][k],
                    acceleration: T::zero(),
                };
                target[3 * m + k] = goal_tips[m][k];
            }
        }
        let angles = [self.pose.psi, self.pose.theta];
        for a in 0..2 {
            start[6 + a] = State {
                position: angles[a],
                velocity: self.velocity.angles[a],
                acceleration: T::zero(),
            };
            target[6 + a] = goal_angles[a];
            limits[6 + a] = self.params.camera;
        }
        let plan = OnlineMulti::new(start, target, limits, Synchronization::Phase)
            .map_err(|_| MoveRefused::Plan)?;
        self.busy = Busy::Move(plan, t0);
        self.follow = None;
        Ok(())
    }
}
