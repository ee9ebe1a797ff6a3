//! What the force tests share: a turn's records and the platform's state
//! read back from one.

use parasils::kin::{PlatformState, Pose, PoseRate};
use parasils_sim::{Record, Scenario, Simulation};

/// The scenario's simulation and every record of its run.
pub fn records(scenario: Scenario) -> (Simulation, Vec<Record>) {
    let sim = Simulation::new(scenario).expect("valid");
    let records = sim.samples().collect::<Result<Vec<_>, _>>().expect("runs");
    (sim, records)
}

/// The platform's state at `r` on a pure turn: the record's pose and Euler
/// rates, the position at rest; the Euler accelerations when
/// `with_acceleration`, else none.
pub fn turn_state(r: &Record, with_acceleration: bool) -> PlatformState<f64> {
    let [psi_dot, theta_dot, phi_dot] = r.euler_dot;
    let [psi_ddot, theta_ddot, phi_ddot] = if with_acceleration {
        r.euler_ddot
    } else {
        [0.0; 3]
    };
    PlatformState {
        pose: Pose::from_array(r.pose),
        velocity: PoseRate::new(0.0, 0.0, 0.0, psi_dot, theta_dot, phi_dot),
        acceleration: PoseRate::new(0.0, 0.0, 0.0, psi_ddot, theta_ddot, phi_ddot),
    }
}
