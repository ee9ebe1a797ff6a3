//! The anatomy as the online controller's forbidden regions: [`Anatomy`]
//! answers [`parasils::ForbiddenRegions`], so that
//! `OnlineController::tick_with(t, &anatomy)` stops the platform ahead of
//! any region as it does ahead of the shafts' pairs.
//!
//! Each in-body capsule the controller gives (from the tip back to the
//! port) is measured against every region with [`Anatomy::gap`], the same
//! gap the simulation reports in `no_go_clearance_mm`; the answer is the
//! smallest, with its region's index in [`Anatomy::regions`]. Nothing is
//! allocated unless a query fails.

use parasils::{ForbiddenRegions, InBodyCapsules, NearestRegion, RegionQueryError};
use parasils_kin::Capsule;

use crate::body::{Body, InBody};
use crate::file::Anatomy;

/// The in-body part `capsule` of `body` (its axis from the tip to the port).
fn in_body(body: Body, capsule: &Capsule<f64>) -> InBody {
    InBody {
        body,
        tip: capsule.axis.start,
        port: capsule.axis.end,
        radius: capsule.radius,
    }
}

impl ForbiddenRegions<f64> for Anatomy {
    fn nearest(
        &self,
        bodies: &InBodyCapsules<f64>,
    ) -> Result<Option<NearestRegion<f64>>, RegionQueryError> {
        let mut best: Option<NearestRegion<f64>> = None;
        for (region, r) in self.regions.iter().enumerate() {
            for (body, capsule) in Body::ALL.into_iter().zip(bodies.all()) {
                let Some(capsule) = capsule else { continue };
                let gap_mm = Anatomy::gap(r, &in_body(body, &capsule))
                    .map_err(|_| RegionQueryError { region })?;
                if best.is_none_or(|b| gap_mm < b.gap_mm) {
                    best = Some(NearestRegion { region, gap_mm });
                }
            }
        }
        Ok(best)
    }

    fn is_empty(&self) -> bool {
        self.regions.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use nalgebra::Vector3;
    use parasils::kin::{BodyGeometry, Controller, Pose, TipTargets};
    use parasils::supervisor::ClearanceThresholds;
    use parasils::traj::Limits;
    use parasils::{
        ClearanceWatch, ForbiddenRegions, InBodyCapsules, MotionKind, OnlineController,
    };
    use parasils_kin::{Capsule, Segment};

    use crate::file::Anatomy;

    type Outcome = Result<(), Box<dyn core::error::Error>>;

    fn anatomy(text: &str) -> Result<Anatomy, crate::AnatomyError> {
        Anatomy::parse(text, Path::new("test.toml"), Path::new("."))
    }

    /// A sphere and a box, measured against capsules: the sphere's gap is
    /// the distance from its centre to the axis minus both radii (by
    /// hand), the box's the distance from the axis to its face.
    #[test]
    fn the_nearest_region_is_the_smallest_gap_with_its_index() -> Outcome {
        let a = anatomy(
            r#"
            [[region]]
            name = "box"
            shape = "box"
            centre_mm = [0.0, 0.0, -100.0]
            half_extents_mm = [10.0, 10.0, 10.0]
            [[region]]
            name = "ball"
            shape = "sphere"
            centre_mm = [50.0, 0.0, -100.0]
            radius_mm = 5.0
            "#,
        )?;
        let capsule = |x: f64, radius: f64| {
            Some(Capsule::new(
                Segment::new(Vector3::new(x, 0.0, -150.0), Vector3::new(x, 0.0, -50.0)),
                radius,
            ))
        };
        let none = InBodyCapsules {
            left: None,
            right: None,
            endoscope: None,
        };
        assert_eq!(a.nearest(&none)?, None);
        // 40 mm along x: 15 mm from the ball's centre, 30 from the box.
        let near_ball = InBodyCapsules {
            endoscope: capsule(35.0, 2.0),
            ..none
        };
        let n = a.nearest(&near_ball)?.ok_or("no gap")?;
        assert_eq!(n.region, 1);
        assert!((n.gap_mm - (15.0 - 5.0 - 2.0)).abs() < 1e-9, "{n:?}");
        // A second body nearer the box wins.
        let both = InBodyCapsules {
            left: capsule(13.0, 1.0),
            ..near_ball
        };
        let n = a.nearest(&both)?.ok_or("no gap")?;
        assert_eq!(n.region, 0);
        assert!((n.gap_mm - (3.0 - 1.0)).abs() < 1e-9, "{n:?}");
        assert!(!ForbiddenRegions::<f64>::is_empty(&a));
        Ok(())
    }

    /// The online controller with a sphere from an anatomy file where the
    /// endoscope's tip would be at 70 % of the paper's turn: stopped with
    /// the gap at or above the stop threshold, the gap it reports the
    /// anatomy's own for the cycle's bodies.
    #[test]
    fn the_online_controller_stops_ahead_of_an_anatomy_sphere() -> Outcome {
        let depth = 40.0;
        let p0 = Pose::<f64>::paper_start();
        let goal = [p0.psi + 15f64.to_radians(), p0.theta + 25f64.to_radians()];
        let at = Pose {
            psi: p0.psi + 0.7 * (goal[0] - p0.psi),
            theta: p0.theta + 0.7 * (goal[1] - p0.theta),
            ..p0
        };
        let centre = at.position() + at.rotation() * Vector3::new(0.0, 0.0, -depth);
        let a = anatomy(&format!(
            "[[region]]\nname = \"organ\"\nshape = \"sphere\"\ncentre_mm = [{}, {}, {}]\nradius_mm = 3.0\n",
            centre.x, centre.y, centre.z
        ))?;
        let mut tips = TipTargets::paper();
        tips.right += Vector3::new(60.0, -40.0, 40.0);
        let watch = ClearanceWatch {
            bodies: BodyGeometry {
                instrument_diameter: 1.0,
                instrument_length: 400.0,
                endoscope_diameter: 4.0,
                endoscope_length: 400.0,
            },
            endoscope_depth: depth,
            thresholds: ClearanceThresholds {
                warn: 2.0,
                stop: 0.5,
            },
        };
        let mut c = OnlineController::new(
            Controller::paper(),
            tips,
            p0,
            [Limits::paper(); 2],
            Default::default(),
        )?
        .with_clearance(watch)?;
        c.command(0.0, goal)?;
        let mut lowest = f64::INFINITY;
        for k in 0..6000u32 {
            let t = f64::from(k) / 1000.0;
            let s = c.tick_with(t, &a)?;
            let n = s.region.ok_or("no region gap")?;
            assert_eq!(n.region, 0);
            assert!(n.gap_mm >= 0.5, "t = {t}: {} mm", n.gap_mm);
            lowest = lowest.min(n.gap_mm);
            if c.is_at_rest(t) {
                break;
            }
        }
        assert_eq!(c.kind(), MotionKind::SupervisorStop);
        assert!(lowest < 2.0, "stopped {lowest} mm away");
        Ok(())
    }
}
