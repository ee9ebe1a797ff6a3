//! The column table's names, units, channels and values.

use super::column::{FLAG, ONE};
use super::*;
use crate::record::Record;

#[test]
fn names_are_unique_and_end_with_their_unit() {
    let mut names: Vec<&str> = ALL.iter().map(|c| c.name).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), ALL.len());
    let suffix = |unit: &str| match unit {
        "s" => "_s",
        "mm" => "_mm",
        "mm/s" => "_mm_s",
        "mm/s^2" => "_mm_s2",
        "deg" => "_deg",
        "deg/s" => "_deg_s",
        "deg/s^2" => "_deg_s2",
        _ => "",
    };
    for c in ALL {
        if c.unit == ONE {
            assert!(
                c.name.contains("margin")
                    || c.name.ends_with("cos_qs2")
                    || c.name.ends_with("_tip_u")
                    || c.name.ends_with("_tip_v"),
                "{}",
                c.name
            );
        } else if c.unit == FLAG {
            assert!(c.name.ends_with("_in_view"), "{}", c.name);
        } else {
            assert!(c.name.ends_with(suffix(c.unit)), "{} in {}", c.name, c.unit);
        }
        let rate = c.unit.ends_with("/s");
        let acc = c.unit.ends_with("/s^2");
        assert_eq!(c.name.contains("_rate_"), rate, "{}", c.name);
        assert_eq!(c.name.contains("_acc_"), acc, "{}", c.name);
    }
}

#[test]
fn the_csv_is_every_column_but_the_recomputed_tips() {
    assert_eq!(CSV_COUNT, 74);
    // The first 65 of the table, the six MCAP-only tips, then the ports.
    assert!(ALL[..65].iter().all(|c| c.csv));
    assert!(ALL[65..71].iter().all(|c| !c.csv));
    assert!(ALL[71..].iter().all(|c| c.csv));
    let names = |c: &[Column]| c.iter().map(|c| c.name).collect::<Vec<_>>();
    assert_eq!(names(&CSV[..65]), names(&ALL[..65]));
    assert_eq!(names(&CSV[65..]), names(&ALL[71..]));
    assert_eq!(CSV_NAMES[0], "t_s");
    assert_eq!(CSV_NAMES[31], "left_qs1_deg");
    assert_eq!(CSV_NAMES[52], "right_tip_err_mm");
    assert_eq!(
        CSV_NAMES[53..57],
        [
            "clearance_left_right_mm",
            "clearance_left_endoscope_mm",
            "clearance_right_endoscope_mm",
            "clearance_min_mm"
        ]
    );
    assert_eq!(
        CSV_NAMES[57..65],
        [
            "left_tip_u",
            "left_tip_v",
            "right_tip_u",
            "right_tip_v",
            "left_tip_in_view",
            "right_tip_in_view",
            "camera_aim_error_deg",
            "camera_roll_deg"
        ]
    );
    assert_eq!(
        CSV_NAMES[65..],
        [
            "left_port_x_mm",
            "left_port_y_mm",
            "left_port_z_mm",
            "right_port_x_mm",
            "right_port_y_mm",
            "right_port_z_mm",
            "endoscope_port_x_mm",
            "endoscope_port_y_mm",
            "endoscope_port_z_mm"
        ]
    );
    assert_eq!(csv_index(&LEFT.q[0]), Some(31));
    assert_eq!(csv_index(&PORTS[4]), Some(69));
    assert_eq!(csv_index(&LEFT.tip[0]), None);
}

#[test]
fn the_command_column_comes_last_and_only_with_commands() {
    assert_eq!(csv_columns(false).len(), 74);
    assert_eq!(csv_columns(true).len(), 75);
    assert_eq!(CSV_WITH_COMMAND_NAMES[..74], CSV_NAMES);
    assert_eq!(CSV_WITH_COMMAND_NAMES[74], "command");
    assert!(csv_columns(true)[74].integer);
    assert!(csv_columns(true)[..74].iter().all(|c| !c.integer));
    assert!(ALL.iter().all(|c| c.name != COMMAND.name));
    assert_eq!(csv_index(&COMMAND), None);
    let r = Record {
        command: 3,
        ..Record::default()
    };
    assert_eq!(COMMAND.value(&r), 3.0);
}

#[test]
fn channels_hold_the_documented_fields() {
    let count = |ch: Channel| ALL.iter().filter(|c| c.channel == Some(ch)).count();
    assert_eq!(Channel::ALL.map(count), [10, 18, 9, 9, 17, 8, 8]);
    assert_eq!(PORTS[4].channel, Some(Channel::Tips));
    assert!(PORTS.iter().all(|c| c.csv));
    assert_eq!(CAMERA_ROLL_DEG.channel, Some(Channel::Camera));
    assert_eq!(T_S.channel, None);
    assert_eq!(LEFT.q_acc[2].channel, Some(Channel::Left));
    assert_eq!(LEFT.tip_err.channel, Some(Channel::Tips));
    assert_eq!(RIGHT.cos_qs2.channel, Some(Channel::Margins));
    assert_eq!(MODULE1_PARALLEL_MARGIN.channel, Some(Channel::Margins));
    assert_eq!(Q_ACC_MM_S2[5].channel, Some(Channel::Module1));
    assert_eq!(PSI_DEG.channel, Some(Channel::Platform));
}

#[test]
fn the_force_columns_come_last_and_only_with_loads() {
    use crate::scenario::{Online, Run, Scenario, Turn};
    let loaded = Scenario {
        tip_load_right_n: Some([0.0, 0.0, 1.0]),
        ..Scenario::paper()
    };
    let n = CSV_COUNT;
    assert_eq!(csv_columns_of(&Scenario::paper()).len(), n);
    let cols = csv_columns_of(&loaded);
    assert_eq!(cols.len(), n + 14);
    assert_eq!(cols[n].name, "q1_force_n");
    assert_eq!(cols[n + 11].name, "right_qs3_force_n");
    assert_eq!(cols[n + 13].name, "right_tip_deflection_mm");
    let with_command = Scenario {
        run: Run::Online(Online {
            turn: Turn::paper(),
            retargets: Vec::new(),
            stop_at_s: Some(1.0),
        }),
        ..loaded.clone()
    };
    let cols = csv_columns_of(&with_command);
    assert_eq!((cols[n].name, cols[n + 1].name), ("command", "q1_force_n"));
    let mut r = Record::default();
    r.forces.module1[4] = -3.5;
    r.forces.left[2] = 2.0;
    r.forces.right[0] = 40.0;
    assert_eq!(FORCES[4].value(&r), -3.5);
    assert_eq!(FORCES[8].value(&r), 2.0);
    assert_eq!(FORCES[9].value(&r), 40.0);
    let mut names: Vec<&str> = CSV_WITH_PROCEDURE_AND_FORCES
        .iter()
        .map(|c| c.name)
        .collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), CSV_COUNT + 26);
}

#[test]
fn values_are_in_the_columns_units() {
    let mut r = Record {
        angles_deg: [90.0, 0.0, 0.0],
        ..Record::default()
    };
    r.left.q = [core::f64::consts::PI, 0.0, 120.0];
    r.right.tip.z = -600.0;
    r.module1.q_ddot[5] = 7.0;
    assert_eq!(PSI_DEG.value(&r), 90.0);
    assert_eq!(LEFT.q[0].value(&r), 180.0);
    assert_eq!(LEFT.q[2].value(&r), 120.0);
    assert_eq!(RIGHT.tip[2].value(&r), -600.0);
    assert_eq!(Q_ACC_MM_S2[5].value(&r), 7.0);
    r.clearance.left_right = 3.0;
    r.clearance.left_endoscope = -1.5;
    r.clearance.right_endoscope = 2.0;
    assert_eq!(CLEARANCE_LEFT_ENDOSCOPE_MM.value(&r), -1.5);
    assert_eq!(CLEARANCE_MIN_MM.value(&r), -1.5);
    r.camera.tips = [[0.25, -0.5], [1.5, 0.0]];
    r.camera.in_view = [true, false];
    r.camera.aim_error = core::f64::consts::FRAC_PI_4;
    r.camera.roll = -core::f64::consts::FRAC_PI_2;
    assert_eq!((LEFT_TIP_U.value(&r), LEFT_TIP_V.value(&r)), (0.25, -0.5));
    assert_eq!(RIGHT_TIP_U.value(&r), 1.5);
    assert_eq!(
        (LEFT_TIP_IN_VIEW.value(&r), RIGHT_TIP_IN_VIEW.value(&r)),
        (1.0, 0.0)
    );
    assert_eq!(CAMERA_AIM_ERROR_DEG.value(&r), 45.0);
    assert_eq!(CAMERA_ROLL_DEG.value(&r), -90.0);
    r.ports[1] = nalgebra::Vector3::new(10.0, -2.5, -500.0);
    assert_eq!(PORTS[5].value(&r), -500.0);
    let row = csv_row(&r);
    assert_eq!(
        (row[4], row[31], row[33], row[28], row[68], row[70]),
        (90.0, 180.0, 120.0, 7.0, 10.0, -500.0)
    );
}
