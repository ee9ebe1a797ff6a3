//! The surgeon's input devices for PARA-SILSROB's teleoperation.
//!
//! The team that built the robot drives it from two 3Dconnexion SpaceMouse
//! devices, one per hand (rate control). This crate turns what such a device
//! sends into the six normalised axes and the buttons the teleoperation
//! core takes:
//!
//! | module | concept |
//! |---|---|
//! | [`error`] | [`DeviceError`]: what went wrong, with which device |
//! | [`report`] | one HID input report, parsed ([`Report`]): both formats |
//! | [`puck`] | the device's state built from its reports ([`Puck`], [`PuckState`]) in the console's frame |
//! | [`recording`] | a recorded input stream, CSV, replayed at the control rate ([`Recording`], [`Player`]), in the teleoperation core's vocabulary (`parasils::teleop::Device`, `Command`) |
//! | [`hid`] | finding and reading the devices over Linux hidraw ([`SpaceMouse`], [`DeviceInfo`]) |
//!
//! # The reports
//! A SpaceMouse is a HID multi-axis controller (usage page 1, usage 8).
//! Its cap's six axes are signed 16-bit little-endian counts, about
//! `+-350` at full deflection ([`FULL_SCALE_COUNTS`]). Older devices send
//! them in two reports, translation (report 1, six bytes) and rotation
//! (report 2, six bytes); newer ones send all six in one report 1 of twelve
//! bytes. Buttons come in report 3, one bit per button. [`Report::parse`]
//! reads both formats; [`Puck::apply`] keeps the latest of each.
//!
//! # Axes
//! The device counts in its own frame: `x` to the right, `y` towards the
//! user, `z` down (pressing the cap); rotations about those axes. The
//! console's frame, the one the teleoperation core reads, is the
//! endoscope's image: `tx` to the right of the picture (the image's `u`),
//! `ty` up the picture (`v`), `tz` into the picture. So pushing the cap
//! away moves a tip deeper into the view, lifting it moves the tip up the
//! picture, and the same for the rotations:
//!
//! | console | device |
//! |---|---|
//! | `tx`, `rx` | `x`, `rx` |
//! | `ty`, `ry` | `-z`, `-rz` |
//! | `tz`, `rz` | `-y`, `-ry` |
//!
//! Each is divided by [`FULL_SCALE_COUNTS`] and clamped to `[-1, 1]`.
//!
//! ```
//! use parasils_device::{Puck, Report};
//!
//! let mut puck = Puck::default();
//! // An older device: translation, then rotation, then the left button.
//! for bytes in [
//!     &[1u8, 0x5e, 0x01, 0x00, 0x00, 0x00, 0x00][..], // x = +350
//!     &[2, 0, 0, 0, 0, 0x9f, 0xff],                    // rz = -97
//!     &[3, 0x01, 0x00],
//! ] {
//!     puck.apply(&Report::parse(bytes)?);
//! }
//! let state = puck.state();
//! assert_eq!(state.axes[0], 1.0); // tx: full scale to the right
//! assert_eq!(state.axes[4], 97.0 / 350.0); // ry = -rz
//! assert_eq!(state.buttons, 0b01); // bit 0: enable
//! # Ok::<(), parasils_device::DeviceError>(())
//! ```

pub mod error;
pub mod hid;
pub mod puck;
pub mod recording;
pub mod report;

pub use error::DeviceError;
pub use hid::{DeviceInfo, SpaceMouse, VENDORS};
pub use puck::{Puck, PuckState};
pub use recording::{DEVICES, Held, InputEvent, Player, Recording};
pub use report::{FULL_SCALE_COUNTS, Report};
