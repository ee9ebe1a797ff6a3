//! The endoscope's view for Foxglove's image panel: a pinhole calibration
//! (`/camera/calibration`, `foxglove.CameraCalibration`) made from the
//! camera's field of view and aspect, and what the image shows
//! (`/camera/annotations`, `foxglove.ImageAnnotations`): both tips and the
//! image's centre, in pixels. There is no picture: the panel draws the
//! annotations on an empty image of the calibration's size, a schematic
//! endoscope view. The 3D scene draws the same camera's frustum
//! ([`frustum`]).
//!
//! The camera's frame (`camera` in `/tf`, child of `platform`) sits at the
//! endoscope's tip with the axes Foxglove's cameras use: `x` along the
//! image's `u` (to its right), `y` along `-v` (down the image), `z` along
//! the view. A point at normalised image coordinates `(u, v)` is at pixel
//! `(cx + u W / 2, cy - v H / 2)`, with `cx = W / 2`, `cy = H / 2`, the
//! pixel's origin at the image's top-left corner; `K` has `fx = (W / 2) /
//! tan(hfov / 2)` and `fy = (H / 2) aspect / tan(hfov / 2)`, so the
//! calibration projects a point where [`Camera::project`] puts it.

use nalgebra::{Matrix3, Vector3};
use parasils::kin::{Camera, PlatformFrame};

use super::error::McapError;
use super::json::Json;
use crate::record::Record;

/// The topic of the `foxglove.CameraCalibration` messages.
pub const CALIBRATION_TOPIC: &str = "/camera/calibration";
/// The topic of the `foxglove.ImageAnnotations` messages.
pub const ANNOTATIONS_TOPIC: &str = "/camera/annotations";
/// The camera's frame in `/tf`.
pub const CAMERA_FRAME: &str = "camera";
/// The schematic image's width, pixels; its height follows from the
/// camera's aspect ratio (720 for 16:9), so that pixels are square.
pub const IMAGE_WIDTH_PX: u32 = 1280;

/// The schematic image: its size and the pinhole's intrinsics, pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraImage {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// The focal lengths `fx`, `fy`, pixels.
    pub focal: [f64; 2],
    /// The principal point `cx`, `cy`, pixels.
    pub centre: [f64; 2],
}

impl CameraImage {
    /// The image of `camera`: [`IMAGE_WIDTH_PX`] wide, its height the width
    /// over the aspect ratio (rounded, at least 1 pixel).
    pub fn of(camera: &Camera<f64>) -> Self {
        let width = IMAGE_WIDTH_PX;
        let h = (f64::from(width) / camera.aspect_ratio).round();
        #[allow(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "clamped to [1, 2^20] first"
        )]
        let height = h.clamp(1.0, f64::from(1u32 << 20)) as u32;
        let tan = (camera.horizontal_fov / 2.0).tan();
        let (w, h) = (f64::from(width), f64::from(height));
        Self {
            width,
            height,
            focal: [w / 2.0 / tan, h / 2.0 * camera.aspect_ratio / tan],
            centre: [w / 2.0, h / 2.0],
        }
    }

    /// The pixel `[x, y]` of normalised image coordinates `[u, v]` (`v` up
    /// the image, pixel `y` down it).
    pub fn pixel(&self, [u, v]: [f64; 2]) -> [f64; 2] {
        [
            self.centre[0] + u * f64::from(self.width) / 2.0,
            self.centre[1] - v * f64::from(self.height) / 2.0,
        ]
    }
}

/// The camera frame's axes in the platform frame, as columns: `u`, `-v`,
/// the view (a proper rotation: `u x v = -view`).
pub(crate) fn frame_axes(camera: &Camera<f64>) -> Matrix3<f64> {
    let a = camera.axes();
    Matrix3::from_columns(&[
        a.column(0).into_owned(),
        -a.column(1).into_owned(),
        a.column(2).into_owned(),
    ])
}

/// The view frustum of `camera` on `frame` at `depth` (mm), `length` mm
/// along the view: a line list (pairs of points, mm, fixed frame), the four
/// edges from the eye to the image's corners, then the rectangle through
/// the corners.
pub(crate) fn frustum(
    camera: &Camera<f64>,
    frame: &PlatformFrame<f64>,
    depth: f64,
    length: f64,
) -> [Vector3<f64>; 16] {
    let eye = Camera::eye(frame, depth);
    let axes = frame.rotation * camera.axes();
    let tan = (camera.horizontal_fov / 2.0).tan();
    let corner = |su: f64, sv: f64| {
        eye + axes * Vector3::new(su * tan, sv * tan / camera.aspect_ratio, 1.0) * length
    };
    let c = [
        corner(-1.0, -1.0),
        corner(1.0, -1.0),
        corner(1.0, 1.0),
        corner(-1.0, 1.0),
    ];
    [
        eye, c[0], eye, c[1], eye, c[2], eye, c[3], c[0], c[1], c[1], c[2], c[2], c[3], c[3], c[0],
    ]
}

/// Writes the `/camera/calibration` message (logged at `ns`) into `out`.
pub fn write_calibration(
    image: &CameraImage,
    ns: u64,
    t: f64,
    out: &mut Vec<u8>,
    ryu: &mut ryu::Buffer,
) -> Result<(), McapError> {
    let ([fx, fy], [cx, cy]) = (image.focal, image.centre);
    let mut j = Json::new(out, ryu);
    j.raw("{\"timestamp\":")
        .time(ns)
        .raw(",\"frame_id\":\"")
        .raw(CAMERA_FRAME)
        .raw("\",\"width\":")
        .int(u64::from(image.width))
        .raw(",\"height\":")
        .int(u64::from(image.height))
        .raw(",\"distortion_model\":\"plumb_bob\",\"D\":[0,0,0,0,0],\"K\":[");
    j.num(fx).raw(",0,").num(cx).raw(",0,").num(fy).raw(",");
    j.num(cy).raw(",0,0,1],\"R\":[1,0,0,0,1,0,0,0,1],\"P\":[");
    j.num(fx).raw(",0,").num(cx).raw(",0,0,").num(fy).raw(",");
    j.num(cy).raw(",0,0,0,1,0]}");
    j.check(CALIBRATION_TOPIC, "K", t)
}

const WHITE: [f64; 4] = [1.0, 1.0, 1.0, 1.0];
const SHADE: [f64; 4] = [0.0, 0.0, 0.0, 0.5];
const LEFT: [f64; 4] = [0.85, 0.2, 0.2, 1.0];
const RIGHT: [f64; 4] = [0.6, 0.2, 0.85, 1.0];

/// `PointsAnnotation` types.
const POINTS: u64 = 1;
const LINE_LIST: u64 = 4;

impl Json<'_> {
    fn point2(&mut self, [x, y]: [f64; 2]) -> &mut Self {
        self.raw("{\"x\":").num(x).raw(",\"y\":").num(y).raw("}")
    }

    fn points(
        &mut self,
        ns: u64,
        kind: u64,
        points: &[[f64; 2]],
        color: [f64; 4],
        thickness: f64,
    ) -> &mut Self {
        self.raw("{\"timestamp\":")
            .time(ns)
            .raw(",\"type\":")
            .int(kind)
            .raw(",\"points\":[");
        for (k, p) in points.iter().enumerate() {
            if k > 0 {
                self.raw(",");
            }
            self.point2(*p);
        }
        self.raw("],\"outline_color\":")
            .color(color)
            .raw(",\"outline_colors\":[],\"fill_color\":")
            .color(color)
            .raw(",\"thickness\":")
            .num(thickness)
            .raw("}")
    }

    fn text(&mut self, ns: u64, at: [f64; 2], text: &str, color: [f64; 4]) -> &mut Self {
        self.raw("{\"timestamp\":")
            .time(ns)
            .raw(",\"position\":")
            .point2(at)
            .raw(",\"text\":\"")
            .raw(text)
            .raw("\",\"font_size\":18,\"text_color\":")
            .color(color)
            .raw(",\"background_color\":")
            .color(SHADE)
            .raw("}")
    }
}

/// Writes the `/camera/annotations` message of `record` (logged at `ns`)
/// into `out`: a cross at the image's centre, and each tip ahead of the
/// camera as a point with its label (a tip behind the camera is left out;
/// one outside the image is drawn where the image's plane has it).
pub fn write_annotations(
    image: &CameraImage,
    record: &Record,
    ns: u64,
    out: &mut Vec<u8>,
    ryu: &mut ryu::Buffer,
) -> Result<(), McapError> {
    let [cx, cy] = image.centre;
    let arm = f64::from(image.height) / 40.0;
    let cross = [
        [cx - arm, cy],
        [cx + arm, cy],
        [cx, cy - arm],
        [cx, cy + arm],
    ];
    let cam = &record.camera;
    let tips: Vec<([f64; 2], &str, [f64; 4])> = [(0, "left", LEFT), (1, "right", RIGHT)]
        .into_iter()
        .filter(|(k, _, _)| cam.ahead[*k])
        .map(|(k, name, color)| (image.pixel(cam.tips[k]), name, color))
        .collect();
    let mut j = Json::new(out, ryu);
    j.raw("{\"circles\":[],\"points\":[");
    j.points(ns, LINE_LIST, &cross, WHITE, 2.0);
    j.raw(",");
    j.points(ns, POINTS, &[image.centre], WHITE, 6.0);
    for (p, _, color) in &tips {
        j.raw(",");
        j.points(ns, POINTS, &[*p], *color, 14.0);
    }
    j.raw("],\"texts\":[");
    for (k, (p, name, color)) in tips.iter().enumerate() {
        if k > 0 {
            j.raw(",");
        }
        j.text(ns, [p[0] + 10.0, p[1] - 10.0], name, *color);
    }
    j.raw("]}");
    j.check(ANNOTATIONS_TOPIC, "points", record.t)
}
