//! The candidate motion of a cycle, before the limits: the hands' and the
//! camera's velocities through the mapping (dead zone, scale, image frame
//! to fixed frame, tremor filter, speed and acceleration limits), the home
//! move's, and the controlled stop's.

use crate::follow::{Follow, FollowParams};
use crate::kin::nalgebra::{Matrix3, Vector3};
use crate::kin::{ControlStep, Real, Side, step_rates};
use crate::traj::OnlineMulti;

use super::core::{Teleop, Velocities};
use super::filter::dead_zone;
use super::input::{BUTTON_ENABLE, CameraCommand, HandCommand, HandInput, Inputs};

/// The share of each actuator's acceleration limit a controlled stop plans
/// to use (see [`Teleop::stop_time`]).
const BRAKE_SHARE: f64 = 0.9;

/// `v` moved towards `target` by at most `step` (norm).
fn approach<T: Real>(v: &Vector3<T>, target: &Vector3<T>, step: T) -> Vector3<T> {
    let d = target - v;
    let n = d.norm();
    if n > step {
        v + d * (step / n)
    } else {
        *target
    }
}

/// `x` moved towards `target` by at most `step`.
fn approach1<T: Real>(x: T, target: T, step: T) -> T {
    let d = target - x;
    if d > step {
        x + step
    } else if d < -step {
        x - step
    } else {
        target
    }
}

impl<T: Real> Teleop<T> {
    /// The image frame's axes in the fixed frame, as columns (`u`, `v`, the
    /// view), at the current setpoint.
    pub(super) fn image_axes(&self) -> Matrix3<T> {
        self.step.frame.rotation * self.camera.axes()
    }

    /// One hand's desired tip velocity in the image frame, mm/s (0 while it
    /// is not engaged and at the first engaged cycle: releasing the clutch
    /// re-anchors and moves nothing).
    fn hand_desired(&mut self, h: usize, input: &HandInput<T>, dt: T) -> Vector3<T> {
        let engaged = input.engaged();
        let was = self.engaged[h];
        self.engaged[h] = engaged;
        let p = &self.params;
        match input.command {
            HandCommand::Rate(axes) => {
                self.master[h] = None;
                if engaged && was {
                    Vector3::new(axes[0], axes[1], axes[2])
                        .map(|x| dead_zone(x, p.dead_zone) * p.rate_scale_mm_s)
                } else {
                    Vector3::zeros()
                }
            }
            HandCommand::Position(m) => {
                let before = self.master[h];
                self.master[h] = engaged.then_some(m);
                match before {
                    Some(b) if engaged && was && dt > T::zero() => {
                        (m - b) * (p.position_scale / dt)
                    }
                    _ => Vector3::zeros(),
                }
            }
        }
    }

    /// The velocities the hands and the camera ask for at this cycle, each
    /// within the speed and acceleration limits.
    pub(super) fn input_velocity(&mut self, t: T, dt: T, inputs: &Inputs<T>) -> Velocities<T> {
        let axes = self.image_axes();
        let mut out = Velocities::zero();
        let a_step = self.params.tip_accel_mm_s2 * dt;
        for (h, input) in [inputs.left, inputs.right].iter().enumerate() {
            let desired = axes * self.hand_desired(h, input, dt);
            let f = &mut self.filters[h];
            let mut v = Vector3::from(f.update(dt, desired.into()));
            if desired == Vector3::zeros() && v.norm() < self.params.rest_mm_s {
                f.reset();
                v = Vector3::zeros();
            }
            let speed = v.norm();
            if speed > self.params.tip_speed_mm_s {
                v *= self.params.tip_speed_mm_s / speed;
            }
            let m = match self.hands[h] {
                Side::Left => 0,
                Side::Right => 1,
            };
            out.tips[m] = approach(&self.velocity.tips[m], &v, a_step);
        }
        out.angles = self.camera_velocity(t, dt, inputs);
        out
    }

    /// The view's `[psi, theta]` rates: a rate within the camera's limits,
    /// or the follow law's setpoint (the law starts once the view is at
    /// rest).
    fn camera_velocity(&mut self, t: T, dt: T, inputs: &Inputs<T>) -> [T; 2] {
        let lim = self.params.camera;
        let a_step = lim.a_max * dt;
        let now = self.velocity.angles;
        let rest = self.params.rest_mm_s * T::lit(1e-3);
        match inputs.camera.command {
            CameraCommand::Rate(axes) => {
                self.follow = None;
                let on = inputs.camera.buttons & BUTTON_ENABLE != 0;
                let desired = if on {
                    [axes[3], axes[4]].map(|x| dead_zone(x, self.params.dead_zone) * lim.v_max)
                } else {
                    [T::zero(); 2]
                };
                let mut w = self.camera_filter.update(dt, desired);
                if desired == [T::zero(); 2] && w.iter().all(|x| x.abs() < rest) {
                    self.camera_filter.reset();
                    w = [T::zero(); 2];
                }
                [0, 1].map(|i| approach1(now[i], w[i].max(-lim.v_max).min(lim.v_max), a_step))
            }
            CameraCommand::Follow => {
                self.camera_filter.reset();
                if self.follow.is_none() {
                    if now != [T::zero(); 2] {
                        return now.map(|w| approach1(w, T::zero(), a_step));
                    }
                    let params = FollowParams {
                        limits: lim,
                        ..FollowParams::assumed()
                    };
                    self.follow = Follow::new(self.camera, params, self.pose, self.depth).ok();
                }
                let Some(follow) = &mut self.follow else {
                    return [T::zero(); 2];
                };
                match follow.step(t, &self.tips) {
                    Ok(s) if dt > T::zero() => {
                        let angles = [self.pose.psi, self.pose.theta];
                        [0, 1].map(|i| (s.angles[i].position - angles[i]) / dt)
                    }
                    Ok(_) => [T::zero(); 2],
                    Err(_) => {
                        self.follow = None;
                        now.map(|w| approach1(w, T::zero(), a_step))
                    }
                }
            }
        }
    }

    /// The home move's velocities at `t`: the plan's positions reached over
    /// this cycle (its goal exactly at its end).
    pub(super) fn home_velocity(
        &self,
        t: T,
        dt: T,
        plan: &OnlineMulti<T, 8>,
        start: T,
    ) -> Velocities<T> {
        if !(dt > T::zero()) {
            return self.velocity;
        }
        let s = plan.sample(t - start);
        let mut out = Velocities::zero();
        for m in 0..2 {
            for k in 0..3 {
                out.tips[m][k] = (s[3 * m + k].position - self.tips[m][k]) / dt;
            }
        }
        out.angles = [
            (s[6].position - self.pose.psi) / dt,
            (s[7].position - self.pose.theta) / dt,
        ];
        out
    }

    /// The time a controlled stop from the velocities `v` takes, s: the
    /// longest of the tips' `|v| / a_max`, the angles' `|w| / alpha_max`
    /// and the actuators' `|q_dot| / (s q_ddot_max)` at `step` (the cycle
    /// moving at `v`), `s` = [`BRAKE_SHARE`]. A stop scales every velocity
    /// alike, so each actuator's rate falls at about `|q_dot| / T_stop`;
    /// the share leaves the rest of its limit to the terms the scaling
    /// does not cover (the velocities' products, the Jacobian's change).
    pub(super) fn stop_time(&self, v: &Velocities<T>, step: &ControlStep<T>) -> T {
        let a = self.params.tip_accel_mm_s2;
        let alpha = self.params.camera.a_max;
        let tips = v.tips.iter().fold(T::zero(), |m, x| m.max(x.norm() / a));
        let view = v.angles.iter().fold(tips, |m, w| m.max(w.abs() / alpha));
        let (q_dot, _) = step_rates(step);
        let share = T::lit(BRAKE_SHARE);
        q_dot
            .iter()
            .zip(&self.controller.limits.acceleration)
            .fold(view, |m, (qd, a_max)| m.max(qd.abs() / (*a_max * share)))
    }

    /// The time the controlled stop from the current setpoint takes, s:
    /// [`Teleop::stop_time`], or what is left of the stop under way when
    /// that is shorter.
    pub(super) fn brake_time(&self) -> T {
        let t_stop = self.stop_time(&self.velocity, &self.step);
        self.stop_left.map_or(t_stop, |left| t_stop.min(left))
    }

    /// The controlled stop's next cycle: every velocity scaled by the same
    /// factor `1 - dt / T_stop`, so that all reach rest together, each
    /// within its acceleration limit, and the robot's coordinates (both
    /// tips and the two angles) keep to one straight line. A stop under way
    /// keeps its end: `T_stop` is never more than what was left of it at
    /// the cycle before (the point its first cycle was checked to reach).
    pub(super) fn brake(&self, dt: T) -> Velocities<T> {
        let v = &self.velocity;
        let t_stop = self.brake_time();
        if !(t_stop > dt) {
            return Velocities::zero();
        }
        let k = T::one() - dt / t_stop;
        Velocities {
            tips: v.tips.map(|x| x * k),
            angles: v.angles.map(|w| w * k),
        }
    }
}
