//! One HID input report of a SpaceMouse, parsed.

use crate::error::DeviceError;

/// The counts of a full deflection of the cap, on every axis: about 350 on
/// the SpaceNavigator, SpaceMouse Compact, Wireless and Pro. Larger counts
/// are clamped when normalised.
pub const FULL_SCALE_COUNTS: f64 = 350.0;

/// One report, in the device's own frame and counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Report {
    /// Report 1 of an older device: `x`, `y`, `z` counts.
    Translation([i16; 3]),
    /// Report 2 of an older device: `rx`, `ry`, `rz` counts.
    Rotation([i16; 3]),
    /// Report 1 of a newer device: all six axes.
    Motion([i16; 6]),
    /// Report 3: one bit per button (bit 0 the first button).
    Buttons(u32),
    /// Another report (LEDs, battery, ...): carries nothing for the axes.
    Other(u8),
}

impl Report {
    /// Parses one report as read from hidraw: the identifier, then the
    /// payload. Report 1 of six payload bytes is a translation, of twelve
    /// or more a full motion; report 3 holds up to four bytes of buttons.
    ///
    /// # Errors
    /// [`DeviceError::EmptyReport`], or [`DeviceError::ShortReport`] when
    /// the payload is shorter than the identifier needs.
    pub fn parse(bytes: &[u8]) -> Result<Self, DeviceError> {
        let (&id, payload) = bytes.split_first().ok_or(DeviceError::EmptyReport)?;
        let short = |expected: usize| DeviceError::ShortReport {
            id,
            len: bytes.len(),
            expected,
        };
        match id {
            1 if payload.len() >= 12 => Ok(Self::Motion(counts(payload))),
            1 => Ok(Self::Translation(counts(payload.get(..6).ok_or(short(7))?))),
            2 => Ok(Self::Rotation(counts(payload.get(..6).ok_or(short(7))?))),
            3 => {
                let first = payload.first().ok_or(short(2))?;
                let mut bits = u32::from(*first);
                for (k, byte) in payload.iter().enumerate().take(4).skip(1) {
                    bits |= u32::from(*byte) << (8 * k);
                }
                Ok(Self::Buttons(bits))
            }
            other => Ok(Self::Other(other)),
        }
    }
}

/// `N` little-endian signed 16-bit counts from the front of `payload` (the
/// caller has checked it holds `2 N` bytes).
fn counts<const N: usize>(payload: &[u8]) -> [i16; N] {
    let mut out = [0i16; N];
    for (value, pair) in out.iter_mut().zip(payload.chunks_exact(2)) {
        *value = i16::from_le_bytes([pair[0], pair[1]]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reports as a SpaceNavigator sends them (captured on the wire): a
    /// translation at rest, a rotation of -30 counts about the second axis,
    /// the first button, both buttons.
    #[test]
    fn recorded_older_reports() -> Result<(), DeviceError> {
        assert_eq!(
            Report::parse(&[0x01, 0, 0, 0, 0, 0, 0])?,
            Report::Translation([0, 0, 0])
        );
        assert_eq!(
            Report::parse(&[0x02, 0x00, 0x00, 0xe2, 0xff, 0x00, 0x00])?,
            Report::Rotation([0, -30, 0])
        );
        assert_eq!(Report::parse(&[0x03, 0x01, 0x00])?, Report::Buttons(1));
        assert_eq!(Report::parse(&[0x03, 0x03, 0x00])?, Report::Buttons(3));
        Ok(())
    }

    #[test]
    fn newer_single_report_carries_six_axes() -> Result<(), DeviceError> {
        // x = 350, y = -350, z = 1, rx = -1, ry = 256, rz = -32768
        let bytes = [
            0x01, 0x5e, 0x01, 0xa2, 0xfe, 0x01, 0x00, 0xff, 0xff, 0x00, 0x01, 0x00, 0x80,
        ];
        assert_eq!(
            Report::parse(&bytes)?,
            Report::Motion([350, -350, 1, -1, 256, i16::MIN])
        );
        Ok(())
    }

    #[test]
    fn short_and_empty_reports_are_errors() {
        assert!(matches!(Report::parse(&[]), Err(DeviceError::EmptyReport)));
        assert!(matches!(
            Report::parse(&[0x02, 0, 0, 0]),
            Err(DeviceError::ShortReport {
                id: 2,
                len: 4,
                expected: 7
            })
        ));
        assert!(matches!(
            Report::parse(&[0x03]),
            Err(DeviceError::ShortReport { id: 3, .. })
        ));
        // A report of another kind (the battery level) is not an error.
        assert!(matches!(
            Report::parse(&[0x17, 100]),
            Ok(Report::Other(0x17))
        ));
    }

    /// Every 16-bit count round-trips through its two bytes.
    #[test]
    fn every_count_round_trips() -> Result<(), DeviceError> {
        for value in i16::MIN..=i16::MAX {
            let [lo, hi] = value.to_le_bytes();
            let report = Report::parse(&[0x02, lo, hi, hi, lo, 0, 0])?;
            let swapped = i16::from_le_bytes([hi, lo]);
            assert_eq!(report, Report::Rotation([value, swapped, 0]));
        }
        Ok(())
    }
}
