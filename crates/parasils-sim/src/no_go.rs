//! The column a run with an anatomy adds after its others,
//! `no_go_clearance_mm` (CSV and Python only, like the forces; the MCAP
//! scene draws the regions instead), and the CSV's columns of such a run.

use crate::columns::{
    CSV, CSV_COUNT, CSV_WITH_COMMAND, CSV_WITH_COMMAND_AND_FORCES, CSV_WITH_FORCES,
    CSV_WITH_PROCEDURE, CSV_WITH_PROCEDURE_AND_FORCES, Column, csv_columns_of as without, join,
};
use crate::scenario::Scenario;

/// The smallest gap between the in-body part of a shaft or of the endoscope
/// and a forbidden region, mm ([`Record::no_go_clearance_mm`](crate::Record)):
/// negative inside a region, `inf` while nothing is inside the patient.
pub const NO_GO_CLEARANCE_MM: Column = Column {
    name: "no_go_clearance_mm",
    unit: "mm",
    channel: None,
    csv: true,
    integer: false,
    get: |r| r.no_go_clearance_mm,
};

const NO_GO: [Column; 1] = [NO_GO_CLEARANCE_MM];

/// Each CSV layout without an anatomy followed by [`NO_GO_CLEARANCE_MM`].
const WITH_NO_GO: [&[Column]; 6] = [
    &join::<CSV_COUNT, 1, { CSV_COUNT + 1 }>(&CSV, &NO_GO),
    &join::<{ CSV_COUNT + 1 }, 1, { CSV_COUNT + 2 }>(&CSV_WITH_COMMAND, &NO_GO),
    &join::<{ CSV_COUNT + 12 }, 1, { CSV_COUNT + 13 }>(&CSV_WITH_PROCEDURE, &NO_GO),
    &join::<{ CSV_COUNT + 14 }, 1, { CSV_COUNT + 15 }>(&CSV_WITH_FORCES, &NO_GO),
    &join::<{ CSV_COUNT + 15 }, 1, { CSV_COUNT + 16 }>(&CSV_WITH_COMMAND_AND_FORCES, &NO_GO),
    &join::<{ CSV_COUNT + 26 }, 1, { CSV_COUNT + 27 }>(&CSV_WITH_PROCEDURE_AND_FORCES, &NO_GO),
];

/// The CSV's columns of `scenario`'s run: those of
/// [`columns::csv_columns_of`](crate::columns::csv_columns_of), then
/// [`NO_GO_CLEARANCE_MM`] when it has an anatomy.
pub fn csv_columns_of(scenario: &Scenario) -> &'static [Column] {
    let base = without(scenario);
    if scenario.anatomy.is_none() {
        return base;
    }
    WITH_NO_GO
        .iter()
        .copied()
        .find(|w| w.len() == base.len() + 1 && w.iter().zip(base).all(|(a, b)| a.name == b.name))
        .unwrap_or(base)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::columns::csv_columns_of as without;
    use crate::scenario::{Online, Run, Turn};
    use parasils_anatomy::{Anatomy, Region, Shape};
    use std::sync::Arc;

    fn anatomy() -> Arc<Anatomy> {
        let shape = Shape::Sphere {
            centre_mm: [0.0; 3],
            radius_mm: 1.0,
        };
        Arc::new(Anatomy {
            file: "a.toml".into(),
            regions: vec![Region::new("r".into(), shape).expect("region")],
        })
    }

    #[test]
    fn every_layout_gains_the_no_go_column_last_and_only_with_an_anatomy() {
        let online = Run::Online(Online {
            turn: Turn::paper(),
            retargets: vec![],
            stop_at_s: Some(1.0),
        });
        let procedure = Run::procedure(vec![]);
        for run in [Run::turn(Turn::paper()), online, procedure] {
            for load in [None, Some([0.0, 0.0, 1.0])] {
                let plain = Scenario {
                    run: run.clone(),
                    tip_load_left_n: load,
                    ..Scenario::paper()
                };
                let names = |c: &[Column]| c.iter().map(|c| c.name).collect::<Vec<_>>();
                assert_eq!(names(csv_columns_of(&plain)), names(without(&plain)));
                let with = Scenario {
                    anatomy: Some(anatomy()),
                    ..plain.clone()
                };
                let (cols, base) = (csv_columns_of(&with), without(&plain));
                assert_eq!(cols.len(), base.len() + 1, "{run:?} {load:?}");
                assert!(cols.iter().zip(base).all(|(a, b)| a.name == b.name));
                assert_eq!(cols[base.len()].name, "no_go_clearance_mm");
            }
        }
    }
}
