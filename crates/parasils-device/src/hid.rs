//! Finding and reading SpaceMouse devices over Linux hidraw, through the
//! `hidapi` crate's native backend (sysfs and `/dev/hidraw*`, no C library).

use crate::error::DeviceError;
use crate::puck::{Puck, PuckState};
use crate::report::Report;

/// The USB vendors of 3Dconnexion devices: Logitech's (the older ones) and
/// 3Dconnexion's own.
pub const VENDORS: [u16; 2] = [0x046d, 0x256f];

/// HID usage page and usage of a multi-axis controller (Generic Desktop).
const MULTI_AXIS: (u16, u16) = (0x01, 0x08);

/// What is known of one HID device before opening it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DeviceInfo {
    /// The hidraw device node (`/dev/hidrawN`).
    pub path: String,
    /// USB vendor id.
    pub vendor_id: u16,
    /// USB product id.
    pub product_id: u16,
    /// HID usage page of its top-level collection (0 when not reported).
    pub usage_page: u16,
    /// HID usage of its top-level collection (0 when not reported).
    pub usage: u16,
    /// The product's name, when it gives one.
    pub product: String,
}

impl DeviceInfo {
    /// Whether this is a SpaceMouse: a 3Dconnexion vendor and either a
    /// multi-axis controller or, where the system reports no usage, a
    /// product id in 3Dconnexion's `0xc6xx` range.
    pub fn is_space_mouse(&self) -> bool {
        if !VENDORS.contains(&self.vendor_id) {
            return false;
        }
        if (self.usage_page, self.usage) == MULTI_AXIS {
            return true;
        }
        self.usage_page == 0 && self.product_id & 0xff00 == 0xc600
    }
}

/// The SpaceMouse devices among `devices`, in the order given, or
/// [`DeviceError::NotFound`].
///
/// # Errors
/// [`DeviceError::NotFound`] when none is a SpaceMouse.
pub fn space_mice(devices: &[DeviceInfo]) -> Result<Vec<DeviceInfo>, DeviceError> {
    let found: Vec<DeviceInfo> = devices
        .iter()
        .filter(|d| d.is_space_mouse())
        .cloned()
        .collect();
    if found.is_empty() {
        Err(DeviceError::NotFound)
    } else {
        Ok(found)
    }
}

/// The error for a failure of the HID layer at `path`, a denied permission
/// named as such.
fn hid_error(path: &str, error: hidapi::HidError) -> DeviceError {
    let denied = match &error {
        hidapi::HidError::IoError { error } => error.kind() == std::io::ErrorKind::PermissionDenied,
        hidapi::HidError::HidApiError { message } => message.contains("Permission denied"),
        _ => false,
    };
    if denied {
        DeviceError::PermissionDenied {
            path: path.to_owned(),
        }
    } else {
        DeviceError::Hid {
            path: path.to_owned(),
            message: error.to_string(),
        }
    }
}

/// One open SpaceMouse and the state its reports have built.
#[derive(Debug)]
pub struct SpaceMouse {
    info: DeviceInfo,
    device: hidapi::HidDevice,
    puck: Puck,
}

impl SpaceMouse {
    /// Every HID device this system lists.
    ///
    /// # Errors
    /// [`DeviceError::Hid`] when the enumeration fails.
    pub fn list() -> Result<Vec<DeviceInfo>, DeviceError> {
        let api = hidapi::HidApi::new().map_err(|e| hid_error("(enumeration)", e))?;
        Ok(api
            .device_list()
            .map(|d| DeviceInfo {
                path: d.path().to_string_lossy().into_owned(),
                vendor_id: d.vendor_id(),
                product_id: d.product_id(),
                usage_page: d.usage_page(),
                usage: d.usage(),
                product: d.product_string().unwrap_or_default().to_owned(),
            })
            .collect())
    }

    /// Opens the first `count` SpaceMouse devices found (two for both
    /// hands, a third for the camera), in the system's order.
    ///
    /// # Errors
    /// [`DeviceError::NotFound`] when fewer than `count` are attached,
    /// [`DeviceError::PermissionDenied`] or [`DeviceError::Hid`] when one
    /// cannot be opened.
    pub fn open_all(count: usize) -> Result<Vec<Self>, DeviceError> {
        let found = space_mice(&Self::list()?)?;
        if found.len() < count {
            return Err(DeviceError::NotFound);
        }
        found.into_iter().take(count).map(Self::open).collect()
    }

    /// Opens the device `info` describes, non-blocking.
    ///
    /// # Errors
    /// [`DeviceError::PermissionDenied`] or [`DeviceError::Hid`].
    pub fn open(info: DeviceInfo) -> Result<Self, DeviceError> {
        let path = std::ffi::CString::new(info.path.clone()).map_err(|_| DeviceError::Hid {
            path: info.path.clone(),
            message: "the path holds a NUL byte".into(),
        })?;
        let api = hidapi::HidApi::new().map_err(|e| hid_error("(enumeration)", e))?;
        let device = api.open_path(&path).map_err(|e| hid_error(&info.path, e))?;
        device
            .set_blocking_mode(false)
            .map_err(|e| hid_error(&info.path, e))?;
        Ok(Self {
            info,
            device,
            puck: Puck::default(),
        })
    }

    /// The device's description.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }

    /// Reads every report waiting (never blocks) and returns the state they
    /// leave; a report that cannot be parsed is skipped, as the device's
    /// other reports (LEDs, battery) are.
    ///
    /// # Errors
    /// [`DeviceError::Hid`] when the device stops answering (unplugged).
    pub fn poll(&mut self) -> Result<PuckState, DeviceError> {
        let mut buf = [0u8; 64];
        loop {
            let n = self
                .device
                .read(&mut buf)
                .map_err(|e| hid_error(&self.info.path, e))?;
            if n == 0 {
                return Ok(self.puck.state());
            }
            if let Some(bytes) = buf.get(..n)
                && let Ok(report) = Report::parse(bytes)
            {
                self.puck.apply(&report);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(vendor_id: u16, product_id: u16, usage_page: u16, usage: u16) -> DeviceInfo {
        DeviceInfo {
            path: format!("/dev/hidraw{product_id:x}"),
            vendor_id,
            product_id,
            usage_page,
            usage,
            product: String::new(),
        }
    }

    #[test]
    fn finds_space_mice_by_vendor_and_usage() -> Result<(), DeviceError> {
        let devices = [
            info(0x046d, 0xc077, 0x01, 0x02), // a Logitech mouse
            info(0x256f, 0xc635, 0x01, 0x08), // SpaceMouse Compact
            info(0x1234, 0xc626, 0x01, 0x08), // another vendor's controller
            info(0x046d, 0xc626, 0x00, 0x00), // SpaceNavigator, no usage
            info(0x256f, 0xc652, 0x0c, 0x01), // a receiver's consumer page
        ];
        let found = space_mice(&devices)?;
        let ids: Vec<u16> = found.iter().map(|d| d.product_id).collect();
        assert_eq!(ids, [0xc635, 0xc626]);
        Ok(())
    }

    #[test]
    fn none_found_is_a_clear_error() {
        let devices = [info(0x046d, 0xc077, 0x01, 0x02)];
        let err = space_mice(&devices).err();
        assert!(matches!(err, Some(DeviceError::NotFound)));
        let text = err.map(|e| e.to_string()).unwrap_or_default();
        assert!(text.starts_with("no SpaceMouse found"), "{text}");
    }

    #[test]
    fn denied_permission_is_named() {
        let denied = hidapi::HidError::IoError {
            error: std::io::Error::from(std::io::ErrorKind::PermissionDenied),
        };
        let err = hid_error("/dev/hidraw3", denied);
        assert!(matches!(&err, DeviceError::PermissionDenied { path } if path == "/dev/hidraw3"));
        assert!(err.to_string().contains("udev rule"));
        let other = hid_error(
            "/dev/hidraw3",
            hidapi::HidError::HidApiError {
                message: "No such device".into(),
            },
        );
        assert!(matches!(other, DeviceError::Hid { .. }));
    }

    /// On a machine with no SpaceMouse (every build machine), asking for
    /// one fails with the clear error, not a panic or an empty success.
    #[test]
    fn this_machine_lists_without_panicking() {
        match SpaceMouse::list() {
            Ok(devices) => {
                if space_mice(&devices).is_err() {
                    assert!(matches!(
                        SpaceMouse::open_all(1),
                        Err(DeviceError::NotFound)
                    ));
                }
            }
            Err(e) => assert!(matches!(e, DeviceError::Hid { .. })),
        }
    }
}
