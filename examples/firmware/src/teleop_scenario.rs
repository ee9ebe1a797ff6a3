//! What the teleoperation phase of the firmware (`f32`, on the MCU) and
//! `build.rs` (`f64`, on the host, for the references) share word for word:
//! the core it drives, the console's synthetic input stream, which cycles
//! are compared and the values of a cycle that are compared.
//!
//! The core is [`Teleop`] at `P0` with the paper's tips, the endoscope at
//! [`DEPTH_MM`], the assumed parameters, watching the clearance of the
//! assumed bodies (thresholds no gap reaches, as in the online phase: the
//! cost is measured, no stop is made on it) and a supervisor whose stop
//! thresholds of `qs3` to its limits are [`QS3_STOP_INSIDE_MM`] inside the
//! start's margins, so that a push of half a second reaches one (the
//! assumed joint limits are over 100 mm away: 7 s of pushing).
//!
//! The stream ([`SEGMENTS`]), at 1 kHz, one input per hand and one for the
//! camera every cycle, every device reporting at the cycle's time; each
//! segment's inputs hold (or ramp linearly) until the next one, its command
//! given at its first cycle:
//!
//! | cycles | what | state |
//! |---|---|---|
//! | 0-99 | idle | DISABLED |
//! | 100-799 | `enable`; the left hand full scale along `u`, the right hand ramping from 0 through the dead zone to full scale down (`-v`) | ENABLED |
//! | 800-1399 | the left hand at full scale on two axes (the speed limit), the right hand left and into the picture | ENABLED |
//! | 1400-2399 | the hands let go (enable held, axes 0): the tips come to rest | ENABLED |
//! | 2400-2699 | the left hand's clutch held, its device pushed full scale down (ignored) | ENABLED |
//! | 2700-3199 | the clutch released, the device still pushed: re-anchored, then moving | ENABLED |
//! | 3200-4399 | the camera turning at rate (`psi` full scale, `theta` half), the right hand moving | ENABLED |
//! | 4400-6399 | follow mode: the view comes to rest, then follows; the left hand moves from 5400 | ENABLED |
//! | 6400-7299 | the camera idle (the view comes to rest); both hands pushing | ENABLED |
//! | 7300-7899 | `pause`, the hands pushing on | PAUSED |
//! | 7900-8199 | `resume`, the hands pushing on | ENABLED |
//! | 8200-9199 | the left hand (the right module's tip: the instruments cross) pushes into the picture, into the stop threshold of the right `qs3`, and is held there | ENABLED |
//! | 9200-9799 | `disable`, the left hand pushing on | DISABLED |

use parasils::kin::nalgebra::Vector3;
use parasils::kin::{
    BodyGeometry, Controller, MarginTracker, PlatformState, Pose, Side, TipTargets,
};
use parasils::supervisor::{ClearanceThresholds, Margin, Margins};
use parasils::teleop::{
    BUTTON_CLUTCH, BUTTON_ENABLE, CameraCommand, CameraInput, Command, HandCommand, HandInput,
    HoldAt, Inputs, OperatingState, Teleop, TeleopCycle, TeleopError, TeleopParams,
};
use parasils::{Real, Supervisor};

/// The endoscope's insertion below `P`, mm (the teleoperation docs' 60 mm).
pub const DEPTH_MM: f64 = 60.0;

/// How far inside the start's margin the stop thresholds of `qs3` to its
/// limits are put, mm.
pub const QS3_STOP_INSIDE_MM: f64 = 10.0;

/// A hand's device over a segment: its translation axes `[tx, ty, tz]` (the
/// rotation axes stay 0), from `from` at the segment's first cycle to `to`
/// at its end (a constant when equal), and its buttons.
#[derive(Clone, Copy)]
pub struct Hand {
    /// The axes at the segment's first cycle, normalised.
    pub from: [f64; 3],
    /// The axes at the segment's end (reached at the next segment's first
    /// cycle), normalised.
    pub to: [f64; 3],
    /// The buttons ([`BUTTON_ENABLE`], [`BUTTON_CLUTCH`]).
    pub buttons: u8,
}

/// The camera's device over a segment.
#[derive(Clone, Copy)]
pub enum Camera {
    /// A rate of the view: `[rx, ry]` (`psi`, `theta`), with the enable
    /// button held when `on`.
    Rate { axes: [f64; 2], on: bool },
    /// Follow the tips.
    Follow,
}

/// One segment of the stream.
#[derive(Clone, Copy)]
pub struct Segment {
    /// Its first cycle.
    pub from: usize,
    /// The command given at its first cycle.
    pub command: Option<Command>,
    /// The left hand, the right hand.
    pub hands: [Hand; 2],
    /// The camera.
    pub camera: Camera,
    /// The state every cycle of the segment ends in.
    pub state: OperatingState,
    /// What it is, for the report.
    pub label: &'static str,
}

const fn held(axes: [f64; 3], buttons: u8) -> Hand {
    Hand {
        from: axes,
        to: axes,
        buttons,
    }
}

const IDLE: Hand = held([0.0; 3], 0);
const LET_GO: Hand = held([0.0; 3], BUTTON_ENABLE);
const STILL: Camera = Camera::Rate {
    axes: [0.0; 2],
    on: false,
};
const E: u8 = BUTTON_ENABLE;

/// The stream (see the [module docs](self)).
pub const SEGMENTS: [Segment; 14] = {
    use OperatingState::{Disabled, Enabled, Paused};
    [
        Segment {
            from: 0,
            command: None,
            hands: [IDLE, IDLE],
            camera: STILL,
            state: Disabled,
            label: "idle",
        },
        Segment {
            from: ENABLE,
            command: Some(Command::Enable),
            hands: [
                held([1.0, 0.0, 0.0], E),
                Hand {
                    from: [0.0; 3],
                    to: [0.0, -1.0, 0.0],
                    buttons: E,
                },
            ],
            camera: STILL,
            state: Enabled,
            label: "enable; both hands moving, the right ramping to full scale",
        },
        Segment {
            from: 800,
            command: None,
            hands: [held([1.0, 1.0, 0.0], E), held([-1.0, 0.0, 0.5], E)],
            camera: STILL,
            state: Enabled,
            label: "the left hand full scale on two axes (the speed limit)",
        },
        Segment {
            from: 1400,
            command: None,
            hands: [LET_GO, LET_GO],
            camera: STILL,
            state: Enabled,
            label: "the hands let go: the tips come to rest",
        },
        Segment {
            from: CLUTCH_PRESS,
            command: None,
            hands: [held([0.0, -1.0, 0.0], E | BUTTON_CLUTCH), LET_GO],
            camera: STILL,
            state: Enabled,
            label: "the left clutch held, its device pushed down (ignored)",
        },
        Segment {
            from: CLUTCH_RELEASE,
            command: None,
            hands: [held([0.0, -1.0, 0.0], E), LET_GO],
            camera: STILL,
            state: Enabled,
            label: "the clutch released: re-anchored, then moving",
        },
        Segment {
            from: TURN,
            command: None,
            hands: [LET_GO, held([0.5, 0.0, 0.0], E)],
            camera: Camera::Rate {
                axes: [1.0, -0.5],
                on: true,
            },
            state: Enabled,
            label: "the camera turning at rate, the right hand moving",
        },
        Segment {
            from: 4400,
            command: None,
            hands: [LET_GO, LET_GO],
            camera: Camera::Follow,
            state: Enabled,
            label: "follow mode: the view comes to rest",
        },
        Segment {
            from: 5400,
            command: None,
            hands: [held([-1.0, -0.5, 0.0], E), LET_GO],
            camera: Camera::Follow,
            state: Enabled,
            label: "follow mode: the left hand moves, the view follows",
        },
        Segment {
            from: 6400,
            command: None,
            hands: [held([0.0, 0.0, 0.5], E), held([0.0, 1.0, 0.0], E)],
            camera: STILL,
            state: Enabled,
            label: "the camera idle (the view comes to rest), both hands pushing",
        },
        Segment {
            from: PAUSE,
            command: Some(Command::Pause),
            hands: [held([0.0, 0.0, 0.5], E), held([0.0, 1.0, 0.0], E)],
            camera: STILL,
            state: Paused,
            label: "pause, the hands pushing on",
        },
        Segment {
            from: RESUME,
            command: Some(Command::Resume),
            hands: [held([0.0, 0.0, 1.0], E), held([0.0, 1.0, 0.0], E)],
            camera: STILL,
            state: Enabled,
            label: "resume, the hands pushing on",
        },
        Segment {
            from: PUSH,
            command: None,
            hands: [held([0.0, 0.0, 1.0], E), LET_GO],
            camera: STILL,
            state: Enabled,
            label: "the push into the right qs3's stop threshold, held there",
        },
        Segment {
            from: DISABLE,
            command: Some(Command::Disable),
            hands: [held([0.0, 0.0, 1.0], E), IDLE],
            camera: STILL,
            state: Disabled,
            label: "disable, the left hand pushing on",
        },
    ]
};

/// The enable command, cycle.
pub const ENABLE: usize = 100;
/// The clutch's press and release (the first engaged cycle), cycles.
pub const CLUTCH_PRESS: usize = 2400;
/// See [`CLUTCH_PRESS`].
pub const CLUTCH_RELEASE: usize = 2700;
/// The camera's turn, from this cycle.
pub const TURN: usize = 3200;
/// The pause and the resume, cycles.
pub const PAUSE: usize = 7300;
/// See [`PAUSE`].
pub const RESUME: usize = 7900;
/// The push into the limit, from this cycle to [`DISABLE`].
pub const PUSH: usize = 8200;
/// The disable command, cycle.
pub const DISABLE: usize = 9200;
/// The stream's cycles: after the disable, the robot stops and holds.
pub const CYCLES: usize = 9800;
/// The margin the push holds at: the right module's `qs3` to its limits.
pub const HELD_MARGIN: Margin = Margin::RightQs3Limits;

/// The module each hand drives after the enable, `[left hand, right
/// hand]`: the instruments cross at `P0` with the paper's tips.
pub const HANDS: [Side; 2] = [Side::Right, Side::Left];

/// The segment cycle `k` is in, with its index and its end (the next
/// segment's first cycle, or [`CYCLES`]).
pub fn segment(k: usize) -> (usize, &'static Segment, usize) {
    let (i, s) = SEGMENTS
        .iter()
        .enumerate()
        .rev()
        .find(|(_, s)| k >= s.from)
        .unwrap_or((0, &SEGMENTS[0]));
    (i, s, SEGMENTS.get(i + 1).map_or(CYCLES, |s| s.from))
}

/// The time of cycle `k`, s.
pub fn time<T: Real>(k: usize) -> T {
    T::from_index(k) / T::lit(1000.0)
}

/// The console's inputs at cycle `k`, every device reporting at `t`.
pub fn inputs<T: Real>(k: usize) -> Inputs<T> {
    let t = time::<T>(k);
    let (_, s, end) = segment(k);
    let (from, len) = (s.from, end.saturating_sub(s.from).max(1));
    let frac = T::from_index(k.saturating_sub(from)) / T::from_index(len);
    let hand = |h: &Hand| {
        let axis = |a: usize| {
            let (x0, x1) = (
                h.from.get(a).copied().unwrap_or(0.0),
                h.to.get(a).copied().unwrap_or(0.0),
            );
            T::lit(x0) + (T::lit(x1) - T::lit(x0)) * frac
        };
        HandInput {
            command: HandCommand::Rate([
                axis(0),
                axis(1),
                axis(2),
                T::zero(),
                T::zero(),
                T::zero(),
            ]),
            buttons: h.buttons,
            stamp_s: t,
        }
    };
    let camera = match s.camera {
        Camera::Rate { axes, on } => CameraInput {
            command: CameraCommand::Rate([
                T::zero(),
                T::zero(),
                T::zero(),
                T::lit(axes[0]),
                T::lit(axes[1]),
                T::zero(),
            ]),
            buttons: if on { BUTTON_ENABLE } else { 0 },
            stamp_s: t,
        },
        Camera::Follow => CameraInput {
            command: CameraCommand::Follow,
            buttons: 0,
            stamp_s: t,
        },
    };
    Inputs {
        left: hand(&s.hands[0]),
        right: hand(&s.hands[1]),
        camera,
        command: if k == from { s.command } else { None },
    }
}

/// The default supervisor with the stop (and warning) thresholds of both
/// modules' `qs3` to its limits [`QS3_STOP_INSIDE_MM`] inside their values
/// at `P0` with the paper's tips.
///
/// # Errors
/// The kinematics' at `P0` (none with the paper's robot).
pub fn supervisor<T: Real>() -> Result<Supervisor<T>, parasils::Error> {
    let start = Controller::<T>::paper().step(
        &PlatformState::at_rest(Pose::paper_start()),
        &TipTargets::paper(),
        &mut MarginTracker::new(),
    )?;
    let start = Margins::of(&start);
    let mut supervisor = Supervisor::default();
    for m in [Margin::LeftQs3Limits, Margin::RightQs3Limits] {
        supervisor.stop[m] = start[m] - T::lit(QS3_STOP_INSIDE_MM);
        supervisor.warn[m] = supervisor.stop[m];
    }
    Ok(supervisor)
}

/// The core at rest at `P0`, DISABLED (see the [module docs](self)).
///
/// # Errors
/// The core's (none with these parameters).
pub fn teleop<T: Real>() -> Result<Teleop<T>, TeleopError> {
    Teleop::new(
        Controller::paper(),
        Pose::paper_start(),
        TipTargets::paper(),
        T::lit(DEPTH_MM),
        TeleopParams::assumed(),
    )?
    .with_supervisor(supervisor()?)?
    .with_clearance(
        BodyGeometry::assumed(),
        ClearanceThresholds {
            warn: T::lit(-1000.0),
            stop: T::lit(-1000.0),
        },
    )
}

/// Every how many cycles a cycle is compared with its `f64` reference; the
/// first cycle of every segment and its last, and the last cycle, too.
pub const REFERENCE_EVERY: usize = 400;

/// Whether cycle `k` is compared with its reference.
pub fn compared(k: usize) -> bool {
    k.is_multiple_of(REFERENCE_EVERY)
        || k + 1 == CYCLES
        || SEGMENTS.iter().any(|s| s.from == k || s.from == k + 1)
}

/// How many values of a cycle are compared, see [`fields`].
pub const FIELD_COUNT: usize = 42;

/// How a field is compared (see `tolerance` in `teleop.rs`).
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// An angle, rad.
    Angle,
    /// A length, mm.
    Length,
    /// A tip's velocity, mm/s.
    TipRate,
    /// A rate of the view, rad/s.
    ViewRate,
    /// A dimensionless margin.
    Margin,
}

/// The names of the values of [`fields`] and their kinds, in order (units:
/// mm, rad, s).
pub const FIELDS: [(&str, Kind); FIELD_COUNT] = {
    use Kind::{Angle as A, Length as L, Margin as M, TipRate as R, ViewRate as W};
    [
        ("m1.q1", L),
        ("m1.q2", L),
        ("m1.q3", L),
        ("m1.q4", L),
        ("m1.q5", L),
        ("m1.q6", L),
        ("left.qs1", A),
        ("left.qs2", A),
        ("left.qs3", L),
        ("right.qs1", A),
        ("right.qs2", A),
        ("right.qs3", L),
        ("left.tip.x", L),
        ("left.tip.y", L),
        ("left.tip.z", L),
        ("right.tip.x", L),
        ("right.tip.y", L),
        ("right.tip.z", L),
        ("left.tip_rate.x", R),
        ("left.tip_rate.y", R),
        ("left.tip_rate.z", R),
        ("right.tip_rate.x", R),
        ("right.tip_rate.y", R),
        ("right.tip_rate.z", R),
        ("psi", A),
        ("theta", A),
        ("psi_dot", W),
        ("theta_dot", W),
        ("left.cos_qs2", M),
        ("left.qs3", L),
        ("left.angle_limits", A),
        ("left.qs3_limits", L),
        ("right.cos_qs2", M),
        ("right.qs3", L),
        ("right.angle_limits", A),
        ("right.qs3_limits", L),
        ("module1.serial", M),
        ("module1.parallel", M),
        ("module1.stroke", L),
        ("clearance.left_right", L),
        ("clearance.left_endoscope", L),
        ("clearance.right_endoscope", L),
    ]
};

/// The values of one cycle that the firmware compares with the host's, in
/// the order of [`FIELDS`]: the twelve setpoints, the tips and their
/// velocities, the view and its rates, the eleven margins, the three gaps
/// (NaN, which matches nothing, when none is watched).
pub fn fields<T: Real>(c: &TeleopCycle<T>) -> [T; FIELD_COUNT] {
    let vector = |v: &Vector3<T>| [v.x, v.y, v.z];
    let gaps = c.clearance.map_or([T::lit(f64::NAN); 3], |g| {
        [
            g.left_right.gap,
            g.left_endoscope.gap,
            g.right_endoscope.gap,
        ]
    });
    let values = c
        .setpoints
        .into_iter()
        .chain(c.tips.iter().flat_map(vector))
        .chain(c.tip_velocity.iter().flat_map(vector))
        .chain(c.angles)
        .chain(c.angle_rates)
        .chain(c.margins.0)
        .chain(gaps);
    let mut v = [T::zero(); FIELD_COUNT];
    for (slot, x) in v.iter_mut().zip(values) {
        *slot = x;
    }
    v
}

/// What a cycle is, exactly, as one number: the state (0 to 3), whether it
/// holds at the right `qs3`'s limits (4), at another limit (8), whether the
/// camera follows (16), whether the hands are assigned as [`HANDS`] (32).
pub fn code<T: Real>(c: &TeleopCycle<T>) -> u8 {
    let state = match c.state {
        OperatingState::Disabled => 0,
        OperatingState::Enabled => 1,
        OperatingState::Paused => 2,
        OperatingState::Fault => 3,
    };
    let hold = match c.hold {
        None => 0,
        Some(HoldAt::Margin(m)) if m == HELD_MARGIN => 4,
        Some(_) => 8,
    };
    state | hold | if c.following { 16 } else { 0 } | if c.hands == HANDS { 32 } else { 0 }
}
