//! What went wrong with an input device, and with which one.

/// An input device's failure: a report that cannot be read, no device, a
/// device that may not be opened or that stopped answering.
#[derive(Debug, thiserror::Error)]
pub enum DeviceError {
    /// A report shorter than its identifier says.
    #[error("HID report {id}: {len} bytes, expected {expected}")]
    ShortReport {
        /// The report's identifier (its first byte).
        id: u8,
        /// Its length, the identifier included.
        len: usize,
        /// The length its identifier needs.
        expected: usize,
    },
    /// An empty report (no identifier).
    #[error("empty HID report")]
    EmptyReport,
    /// No SpaceMouse among the HID devices.
    #[error(
        "no SpaceMouse found (3Dconnexion vendor 0x046d or 0x256f, multi-axis controller); is it plugged in?"
    )]
    NotFound,
    /// The device exists but this user may not read it.
    #[error(
        "permission denied opening {path}: give this user read access to the hidraw device (a udev rule)"
    )]
    PermissionDenied {
        /// The hidraw device node.
        path: String,
    },
    /// The HID layer failed (enumeration, opening or reading).
    #[error("HID device {path}: {message}")]
    Hid {
        /// The hidraw device node, or `"(enumeration)"`.
        path: String,
        /// The HID layer's message.
        message: String,
    },
    /// A recording file that cannot be read at all (missing, a folder, no
    /// permission, not UTF-8).
    #[error("cannot read {file}: {message}")]
    RecordingFile {
        /// The file.
        file: String,
        /// The operating system's reason.
        message: String,
    },
    /// A recorded input stream that cannot be read as one.
    #[error("{file}: line {line}: {message}")]
    Recording {
        /// The file (or the name given to the text).
        file: String,
        /// The line, 1 for the header.
        line: u64,
        /// What is wrong, naming the column.
        message: String,
    },
}
