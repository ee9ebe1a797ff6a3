//! The forbidden regions among a cell's constraints: the in-body part of
//! each shaft and of the endoscope at the cell's joints measured against
//! each region of the scenario's anatomy (`--anatomy`), as a run's every
//! cycle measures them (`parasils_anatomy::Anatomy::clearance`).

use std::sync::Arc;

use parasils::kin::{Bodies, ControlStep};
use parasils_anatomy::{Anatomy, Body, InBody};
use parasils_sim::Scenario;

/// What a checker measures the bodies against: the scenario's regions and
/// the stop threshold a run fails below, mm.
#[derive(Debug, Clone)]
pub(crate) struct NoGoCheck {
    anatomy: Arc<Anatomy>,
    /// [`SupervisorTable::no_go_stop_mm`](parasils_sim::SupervisorTable::no_go_stop_mm):
    /// the robot file's `clearance_stop_mm`, or its default.
    stop_mm: f64,
}

impl NoGoCheck {
    /// The check of `scenario`'s anatomy; `None` without one.
    pub(crate) fn of(scenario: &Scenario) -> Option<Self> {
        scenario.anatomy.as_ref().map(|anatomy| Self {
            anatomy: Arc::clone(anatomy),
            stop_mm: scenario.supervisor.no_go_stop_mm(),
        })
    }

    /// The regions' names, in the anatomy file's order.
    pub(crate) fn names(&self) -> Vec<String> {
        self.anatomy
            .regions
            .iter()
            .map(|r| r.name.clone())
            .collect()
    }

    /// Each region's normalised margin at `step` (`bodies` its bodies, the
    /// endoscope inserted `depth_mm`), in the file's order: the smallest
    /// gap over the in-body parts, minus the stop threshold, over the
    /// closest body's radius (1 mm for a body of no radius): 0 on the
    /// threshold, negative below it, `+inf` while nothing is inside the
    /// patient. `None` when the anatomy's query fails (a non-finite body).
    pub(crate) fn margins(
        &self,
        bodies: &Bodies<f64>,
        step: &ControlStep<f64>,
        depth_mm: f64,
    ) -> Option<Vec<(usize, f64)>> {
        let inside = InBody::of(bodies, step.left.q.qs3, step.right.q.qs3, depth_mm);
        let gaps = self.anatomy.clearance(&inside).ok()?;
        let radius = |body: Option<Body>| {
            let r = match body {
                Some(Body::Left) => bodies.left.radius,
                Some(Body::Right) => bodies.right.radius,
                Some(Body::Endoscope) => bodies.endoscope.radius,
                None => 1.0,
            };
            if r > 0.0 { r } else { 1.0 }
        };
        Some(
            gaps.regions
                .iter()
                .map(|g| (g.region, (g.gap_mm - self.stop_mm) / radius(g.body)))
                .collect(),
        )
    }
}
