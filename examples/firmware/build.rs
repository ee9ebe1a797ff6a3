//! Computes the references the firmware checks itself against: the command
//! stream of `src/scenario.rs` run through the very same
//! [`OnlineController`](parasils::OnlineController) on the host in `f64`
//! (the library built here with `std`), written to `$OUT_DIR/reference.rs`;
//! and the console's input stream of `src/teleop_scenario.rs` run through
//! the very same [`Teleop`](parasils::teleop::Teleop), written to
//! `$OUT_DIR/teleop_reference.rs`.
//! The build script is rerun whenever `parasils`, `parasils-kin` or
//! `parasils-traj` change, so the references are always those of the code
//! being embedded.

use std::fmt::Write as _;
use std::path::PathBuf;

use parasils::traj::Synchronization;

#[path = "src/scenario.rs"]
#[allow(dead_code)]
mod scenario;

#[path = "src/teleop_scenario.rs"]
#[allow(dead_code)]
mod teleop_scenario;

use scenario::{FIELD_COUNT, MAX_CYCLES};

/// A compared cycle this close to a switch of the profile (s) could see its
/// acceleration on the other side of the switch in `f32`.
const SWITCH_CLEARANCE_S: f64 = 1e-5;

fn sync_code(s: Option<Synchronization>) -> u8 {
    match s {
        None => 0,
        Some(Synchronization::Phase) => 1,
        Some(Synchronization::Time) => 2,
        Some(Synchronization::None) => 3,
    }
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=src/scenario.rs");
    println!("cargo:rerun-if-changed=src/teleop_scenario.rs");
    println!("cargo:rerun-if-changed=memory.x");

    // memory.x where the linker (cortex-m-rt's link.x) finds it.
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("OUT_DIR is set by cargo"));
    std::fs::copy("memory.x", out.join("memory.x")).expect("copy memory.x");
    println!("cargo:rustc-link-search={}", out.display());

    let mut online = scenario::online::<f64>().expect("valid controller");
    let loads = scenario::loads::<f64>();
    let orders = scenario::orders::<f64>();
    let last_command = orders.iter().map(|o| o.0).max().unwrap_or(0);
    let mut next = orders.iter().peekable();
    let mut syncs = Vec::new();
    let mut goals = Vec::new();
    let mut cycles = Vec::new();
    let mut worst_drift = 0.0f64;
    for k in 0..MAX_CYCLES {
        let t = scenario::time::<f64>(k);
        if let Some(&&(at, goal)) = next.peek()
            && at == k
        {
            let sync = scenario::give(&mut online, t, goal)
                .unwrap_or_else(|e| panic!("f64 command at cycle {k} failed: {e}"));
            syncs.push(sync_code(sync));
            goals.push(online.goal());
            next.next();
        }
        let s = online
            .tick(t)
            .unwrap_or_else(|e| panic!("f64 cycle {k} failed: {e}"));
        assert!(
            s.warnings.is_empty() && s.stop.is_empty(),
            "cycle {k}: the supervisor warned or stopped ({:?}, {:?})",
            s.warnings,
            s.stop
        );
        let c = online.controller();
        for (m, q, target) in [
            (&c.left, &s.step.left.q, &online.tips().left),
            (&c.right, &s.step.right.q, &online.tips().right),
        ] {
            let tip = m.fk(&s.state.pose, q).expect("finite joints");
            worst_drift = worst_drift.max((tip - target).norm());
        }
        // The acceleration of a compared cycle must not sit on a switch. (The
        // last cycle, compared too, rests after its motion's end.)
        let local = t - online.motion_start();
        if scenario::compared(k, 0) && local > 0.0 {
            for axis in online.motion().axes() {
                for switch in axis.switches().into_iter().chain([axis.duration()]) {
                    assert!(
                        (local - switch).abs() > SWITCH_CLEARANCE_S,
                        "cycle {k} is {:e} s from a switch of its profile",
                        (local - switch).abs()
                    );
                }
            }
        }
        let forces = scenario::forces(c, &s.step, &loads)
            .unwrap_or_else(|e| panic!("f64 forces at cycle {k} failed: {e}"));
        cycles.push((s, forces));
        if k >= last_command && online.is_at_rest(t) {
            break;
        }
    }
    let count = cycles.len();
    assert!(count < MAX_CYCLES, "the run did not come to rest");
    assert_eq!(syncs.len(), orders.len(), "every command given");
    // The references' own error: 1e-9 mm in f64 (see `docs/model.md`,
    // *Check values*).
    assert!(worst_drift < 1e-9, "f64 tip drift {worst_drift} mm");

    let mut peak = [0.0f64; FIELD_COUNT];
    let mut references = Vec::new();
    for (k, (s, forces)) in cycles.iter().enumerate() {
        assert_eq!(scenario::values(s, forces).count(), FIELD_COUNT, "fields");
        let v = scenario::fields(s, forces);
        for (p, x) in peak.iter_mut().zip(&v) {
            *p = p.max(x.abs());
        }
        if scenario::compared(k, count) {
            references.push((k, v));
        }
    }

    let mut src = String::new();
    let _ = writeln!(
        src,
        "// Generated by build.rs from parasils in f64 on the host.\n\
         /// The cycles of the run, the last one at rest on the last goal.\n\
         pub const CYCLES: usize = {count};\n\
         /// Per command, the synchronisation used (0 for the stop, 1 phase, 2 time, 3 none).\n\
         pub const SYNCS: [u8; {}] = {syncs:?};\n\
         /// Per command, the goal `[psi, theta]` it planned to, rad (f64).\n\
         pub const GOALS: [[f64; 2]; {}] = {goals:?};\n\
         /// Per field, its largest magnitude over the run (f64).\n\
         pub const PEAK: [f64; {FIELD_COUNT}] = {:?};\n\
         /// `(cycle, fields)` of the compared cycles (f64).\n\
         pub static REFERENCES: [(usize, [f64; {FIELD_COUNT}]); {}] = [",
        syncs.len(),
        goals.len(),
        peak,
        references.len()
    );
    for (k, v) in &references {
        let _ = writeln!(src, "    ({k}, {v:?}),");
    }
    src.push_str("];\n");
    std::fs::write(out.join("reference.rs"), src).expect("write reference.rs");
    teleop_references(&out);
}

/// The teleoperation stream in `f64`: the compared cycles' fields and
/// codes, the first cycle held at a limit and how many are.
fn teleop_references(out: &std::path::Path) {
    use teleop_scenario as ts;
    let mut core = ts::teleop::<f64>().expect("valid teleoperation core");
    let mut first_hold = None;
    let mut holds = 0usize;
    let mut references = Vec::new();
    for k in 0..ts::CYCLES {
        let c = core
            .step(ts::time(k), &ts::inputs(k))
            .unwrap_or_else(|e| panic!("f64 teleoperation cycle {k} failed: {e}"));
        let (_, segment, _) = ts::segment(k);
        assert_eq!(c.state, segment.state, "cycle {k}: the state");
        assert!(c.fault.is_none(), "cycle {k}: {:?}", c.fault);
        if c.hold.is_some() {
            holds += 1;
            first_hold = first_hold.or(Some(k));
        }
        if ts::compared(k) {
            references.push((k, ts::code(&c), ts::fields(&c)));
        }
    }
    let first_hold = first_hold.expect("the push reaches its limit");
    assert!(
        (ts::PUSH..ts::DISABLE).contains(&first_hold),
        "the first hold, at cycle {first_hold}, is in the push"
    );
    let mut src = String::new();
    let _ = writeln!(
        src,
        "// Generated by build.rs from parasils in f64 on the host.\n\
         /// The first cycle that holds at a limit.\n\
         pub const FIRST_HOLD: usize = {first_hold};\n\
         /// How many cycles hold at a limit.\n\
         pub const HOLDS: usize = {holds};\n\
         /// `(cycle, code, fields)` of the compared cycles (f64).\n\
         pub static REFERENCES: [(usize, u8, [f64; {}]); {}] = [",
        ts::FIELD_COUNT,
        references.len()
    );
    for (k, code, v) in &references {
        let _ = writeln!(src, "    ({k}, {code}, {v:?}),");
    }
    src.push_str("];\n");
    std::fs::write(out.join("teleop_reference.rs"), src).expect("write teleop_reference.rs");
}
