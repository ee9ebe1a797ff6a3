//! A SpaceMouse's state, built from its reports, in the console's frame.

use crate::report::{FULL_SCALE_COUNTS, Report};

/// The device's latest counts and buttons, as its reports set them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Puck {
    /// `x`, `y`, `z`, `rx`, `ry`, `rz` in the device's frame, counts.
    counts: [i16; 6],
    /// One bit per button.
    buttons: u32,
}

/// What the teleoperation core reads of one device at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PuckState {
    /// `tx`, `ty`, `tz`, `rx`, `ry`, `rz` in the console's frame (the
    /// image's `u`, `v` and into the picture), each in `[-1, 1]`.
    pub axes: [f64; 6],
    /// Bit 0: the first button (enable, held for motion); bit 1: the second
    /// (clutch); the others as the device numbers them.
    pub buttons: u32,
}

impl Puck {
    /// Applies one report: a translation or rotation replaces its three
    /// axes, a motion all six, buttons the buttons; other reports change
    /// nothing.
    pub fn apply(&mut self, report: &Report) {
        match *report {
            Report::Translation(t) => self.counts[..3].copy_from_slice(&t),
            Report::Rotation(r) => self.counts[3..].copy_from_slice(&r),
            Report::Motion(m) => self.counts = m,
            Report::Buttons(b) => self.buttons = b,
            Report::Other(_) => {}
        }
    }

    /// The raw counts, device frame.
    pub fn counts(&self) -> [i16; 6] {
        self.counts
    }

    /// The state in the console's frame (see the crate's table of axes),
    /// normalised by [`FULL_SCALE_COUNTS`] and clamped to `[-1, 1]`.
    pub fn state(&self) -> PuckState {
        let [x, y, z, rx, ry, rz] = self.counts.map(|c| f64::from(c) / FULL_SCALE_COUNTS);
        let axes = [x, -z, -y, rx, -rz, -ry].map(|a| a.clamp(-1.0, 1.0));
        PuckState {
            axes,
            buttons: self.buttons,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::DeviceError;

    fn fed(reports: &[&[u8]]) -> Result<Puck, DeviceError> {
        let mut puck = Puck::default();
        for bytes in reports {
            puck.apply(&Report::parse(bytes)?);
        }
        Ok(puck)
    }

    /// Both formats describing the same deflection give the same state.
    #[test]
    fn both_formats_agree() -> Result<(), DeviceError> {
        let [x, y, z, rx, ry, rz] = [120i16, -35, 300, -7, 64, -350].map(i16::to_le_bytes);
        let older = fed(&[
            &[1, x[0], x[1], y[0], y[1], z[0], z[1]],
            &[2, rx[0], rx[1], ry[0], ry[1], rz[0], rz[1]],
        ])?;
        let newer = fed(&[&[
            1, x[0], x[1], y[0], y[1], z[0], z[1], rx[0], rx[1], ry[0], ry[1], rz[0], rz[1],
        ]])?;
        assert_eq!(older, newer);
        assert_eq!(older.counts(), [120, -35, 300, -7, 64, -350]);
        Ok(())
    }

    /// The axis table: pressing the cap (device `+z`) is down the picture,
    /// pulling it towards the user (`+y`) is out of the picture.
    #[test]
    fn console_frame_and_scale() -> Result<(), DeviceError> {
        let state = fed(&[
            &[1, 175, 0, 0x92, 0xfe, 35, 0],     // x = 175, y = -366, z = 35
            &[2, 0xf9, 0xff, 70, 0, 0xa2, 0xfe], // rx = -7, ry = 70, rz = -350
        ])?
        .state();
        assert_eq!(state.axes[0], 0.5); // tx = x / 350
        assert_eq!(state.axes[1], -0.1); // ty = -z / 350
        assert_eq!(state.axes[2], 1.0); // tz = -y / 350 = 1.046, clamped
        assert_eq!(state.axes[3], -7.0 / 350.0); // rx
        assert_eq!(state.axes[4], 1.0); // ry = -rz / 350
        assert_eq!(state.axes[5], -0.2); // rz = -ry / 350
        Ok(())
    }

    #[test]
    fn reports_hold_until_replaced() -> Result<(), DeviceError> {
        let mut puck = fed(&[&[3, 0b10, 0], &[1, 10, 0, 0, 0, 0, 0]])?;
        puck.apply(&Report::parse(&[2, 1, 0, 0, 0, 0, 0])?);
        puck.apply(&Report::parse(&[0x17, 80])?); // battery: nothing
        assert_eq!(puck.counts(), [10, 0, 0, 1, 0, 0]);
        assert_eq!(puck.state().buttons, 0b10);
        puck.apply(&Report::parse(&[3, 0, 0])?);
        assert_eq!(puck.state().buttons, 0);
        Ok(())
    }
}
