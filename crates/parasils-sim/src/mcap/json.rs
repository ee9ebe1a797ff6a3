//! JSON written directly as text into reused buffers: numbers in their
//! shortest round-trip form (`ryu`), objects built by hand in a fixed field
//! order, so that a message costs no allocation and the file is the same
//! byte for byte from run to run.

use nalgebra::{UnitQuaternion, Vector3};

use super::error::McapError;

/// The log time of `t` seconds, ns.
///
/// # Errors
/// [`McapError::InvalidTime`] for a negative or non-finite time, or one too
/// large for a `u64` of nanoseconds.
pub fn log_time(t: f64) -> Result<u64, McapError> {
    let ns = (t * 1e9).round();
    // 1.8e19 < u64::MAX = 1.8446e19.
    if ns.is_finite() && (0.0..1.8e19).contains(&ns) {
        // In range, checked just above.
        Ok(ns as u64)
    } else {
        Err(McapError::InvalidTime { t })
    }
}

/// Appends `v` to `out` as a JSON number (shortest round-trip form); `Err(v)`
/// for a value JSON cannot hold (NaN, infinite).
pub fn push_num(out: &mut Vec<u8>, ryu: &mut ryu::Buffer, v: f64) -> Result<(), f64> {
    if v.is_finite() {
        out.extend_from_slice(ryu.format_finite(v).as_bytes());
        Ok(())
    } else {
        Err(v)
    }
}

/// A small JSON text builder for the 3D messages, over a reused buffer.
pub(crate) struct Json<'a> {
    pub(crate) out: &'a mut Vec<u8>,
    pub(crate) ryu: &'a mut ryu::Buffer,
    /// The first non-finite value met, if any (written as `0`).
    pub(crate) bad: Option<f64>,
}

impl<'a> Json<'a> {
    /// A builder appending to `out`.
    pub(crate) fn new(out: &'a mut Vec<u8>, ryu: &'a mut ryu::Buffer) -> Self {
        Self {
            out,
            ryu,
            bad: None,
        }
    }

    pub(crate) fn raw(&mut self, s: &str) -> &mut Self {
        self.out.extend_from_slice(s.as_bytes());
        self
    }

    pub(crate) fn num(&mut self, v: f64) -> &mut Self {
        if let Err(v) = push_num(self.out, self.ryu, v) {
            self.bad.get_or_insert(v);
            self.out.push(b'0');
        }
        self
    }

    pub(crate) fn int(&mut self, v: u64) -> &mut Self {
        self.out
            .extend_from_slice(itoa::Buffer::new().format(v).as_bytes());
        self
    }

    /// `{"x":..,"y":..,"z":..}`.
    pub(crate) fn vec3(&mut self, v: &Vector3<f64>) -> &mut Self {
        self.raw("{\"x\":")
            .num(v.x)
            .raw(",\"y\":")
            .num(v.y)
            .raw(",\"z\":")
            .num(v.z)
            .raw("}")
    }

    /// `{"x":..,"y":..,"z":..,"w":..}`.
    pub(crate) fn quat(&mut self, q: &UnitQuaternion<f64>) -> &mut Self {
        self.raw("{\"x\":")
            .num(q.i)
            .raw(",\"y\":")
            .num(q.j)
            .raw(",\"z\":")
            .num(q.k)
            .raw(",\"w\":")
            .num(q.w)
            .raw("}")
    }

    /// `{"sec":..,"nsec":..}`.
    pub(crate) fn time(&mut self, ns: u64) -> &mut Self {
        self.raw("{\"sec\":")
            .int(ns / 1_000_000_000)
            .raw(",\"nsec\":")
            .int(ns % 1_000_000_000)
            .raw("}")
    }

    /// `{"r":..,"g":..,"b":..,"a":..}`.
    pub(crate) fn color(&mut self, c: [f64; 4]) -> &mut Self {
        self.raw("{\"r\":")
            .num(c[0])
            .raw(",\"g\":")
            .num(c[1])
            .raw(",\"b\":")
            .num(c[2])
            .raw(",\"a\":")
            .num(c[3])
            .raw("}")
    }

    /// A `foxglove.CylinderPrimitive` of `diameter` from `a` to `b` (the
    /// unit of the three): centred between them, its own `z` along `b - a`
    /// (any orientation with that `z`; `a = b` gives a flat disc).
    pub(crate) fn cylinder(
        &mut self,
        a: &Vector3<f64>,
        b: &Vector3<f64>,
        diameter: f64,
        color: [f64; 4],
    ) -> &mut Self {
        let axis = b - a;
        let q = UnitQuaternion::rotation_between(&Vector3::z(), &axis).unwrap_or_else(|| {
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), core::f64::consts::PI)
        });
        self.raw("{\"pose\":{\"position\":")
            .vec3(&((a + b) * 0.5))
            .raw(",\"orientation\":")
            .quat(&q)
            .raw("},\"size\":")
            .vec3(&Vector3::new(diameter, diameter, axis.norm()))
            .raw(",\"bottom_scale\":1,\"top_scale\":1,\"color\":")
            .color(color)
            .raw("}")
    }

    /// The identity pose.
    pub(crate) fn identity_pose(&mut self) -> &mut Self {
        self.raw(
            "{\"position\":{\"x\":0,\"y\":0,\"z\":0},\"orientation\":{\"x\":0,\"y\":0,\"z\":0,\"w\":1}}",
        )
    }

    /// `Err(NonFinite)` naming `topic`, `field` and `t` if a non-finite value
    /// was met.
    pub(crate) fn check(
        &self,
        topic: &'static str,
        field: &'static str,
        t: f64,
    ) -> Result<(), McapError> {
        match self.bad {
            Some(value) => Err(McapError::NonFinite {
                topic,
                field,
                t,
                value,
            }),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_times_and_non_finite_values() {
        let (mut out, mut ryu) = (Vec::new(), ryu::Buffer::new());
        let mut j = Json::new(&mut out, &mut ryu);
        j.vec3(&Vector3::new(0.1, -2.0, 1e-20))
            .raw(",")
            .time(1_500_000_000);
        assert!(j.check("/x", "f", 0.0).is_ok());
        j.num(f64::NAN);
        assert!(matches!(
            j.check("/x", "f", 1.0),
            Err(McapError::NonFinite { topic: "/x", .. })
        ));
        assert_eq!(
            String::from_utf8(out).expect("utf8"),
            "{\"x\":0.1,\"y\":-2.0,\"z\":1e-20},{\"sec\":1,\"nsec\":500000000}0"
        );
        assert_eq!(log_time(4.5).ok(), Some(4_500_000_000));
        assert!(log_time(-1.0).is_err());
        assert!(log_time(f64::INFINITY).is_err());
    }
}
