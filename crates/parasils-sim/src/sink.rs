//! Where a simulation's records go: the [`Sink`] trait, and [`Tee`], which
//! hands each record to several sinks.

use crate::record::Record;

/// Where a simulation's records go, one at a time, in order.
///
/// The writers implement it, so that a run of any length streams through
/// [`Simulation::run`](crate::Simulation::run) without holding the table in
/// memory. A closure `FnMut(&Record) -> Result<(), E>` is a sink too.
pub trait Sink {
    /// The error a sink can fail with.
    type Error;

    /// Takes the next record.
    ///
    /// # Errors
    /// The sink's own (an I/O error, a value it cannot write); the run stops
    /// there.
    fn push(&mut self, record: &Record) -> Result<(), Self::Error>;
}

impl<E, F: FnMut(&Record) -> Result<(), E>> Sink for F {
    type Error = E;

    fn push(&mut self, record: &Record) -> Result<(), E> {
        self(record)
    }
}

/// An error of one of the sinks of a [`Tee`].
pub type BoxError = Box<dyn core::error::Error + Send + Sync + 'static>;

/// A [`Sink`] whose error is boxed, so that sinks of different error types
/// can share a [`Tee`].
trait BoxedSink {
    fn push_boxed(&mut self, record: &Record) -> Result<(), BoxError>;
}

impl<S> BoxedSink for S
where
    S: Sink,
    S::Error: Into<BoxError>,
{
    fn push_boxed(&mut self, record: &Record) -> Result<(), BoxError> {
        self.push(record).map_err(Into::into)
    }
}

/// Several sinks fed the same records, in the order they were added; the
/// first error stops the run.
///
/// ```
/// use parasils_sim::{Scenario, Simulation, Tee};
/// use parasils_sim::summary::Summary;
///
/// let sim = Simulation::new(Scenario { rate_hz: 10.0, ..Scenario::paper() })?;
/// let mut summary = Summary::new(sim.module1_assumed());
/// let mut last_t = 0.0;
/// let mut last = |r: &parasils_sim::Record| {
///     last_t = r.t;
///     Ok::<(), std::convert::Infallible>(())
/// };
/// sim.run(&mut Tee::new().with(&mut summary).with(&mut last))?;
/// assert_eq!(summary.count(), 46);
/// assert_eq!(last_t, 4.5);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Default)]
pub struct Tee<'a> {
    sinks: Vec<&'a mut dyn BoxedSink>,
}

impl core::fmt::Debug for Tee<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Tee")
            .field("sinks", &self.sinks.len())
            .finish()
    }
}

impl<'a> Tee<'a> {
    /// No sink yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds `sink`, fed after those already added.
    #[must_use]
    pub fn with<S>(mut self, sink: &'a mut S) -> Self
    where
        S: Sink,
        S::Error: Into<BoxError>,
    {
        self.sinks.push(sink);
        self
    }

    /// Adds `sink` if it is `Some`.
    #[must_use]
    pub fn with_some<S>(self, sink: Option<&'a mut S>) -> Self
    where
        S: Sink,
        S::Error: Into<BoxError>,
    {
        match sink {
            Some(s) => self.with(s),
            None => self,
        }
    }

    /// The number of sinks.
    pub fn len(&self) -> usize {
        self.sinks.len()
    }

    /// Whether there is no sink.
    pub fn is_empty(&self) -> bool {
        self.sinks.is_empty()
    }
}

impl Sink for Tee<'_> {
    type Error = BoxError;

    fn push(&mut self, record: &Record) -> Result<(), BoxError> {
        for s in &mut self.sinks {
            s.push_boxed(record)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, thiserror::Error)]
    #[error("full")]
    struct Full;

    #[test]
    fn feeds_every_sink_in_order_and_stops_at_the_first_error() {
        let mut seen = Vec::new();
        let mut a = |r: &Record| {
            seen.push(("a", r.index));
            Ok::<(), core::convert::Infallible>(())
        };
        let mut count = 0;
        let mut b = |_: &Record| {
            count += 1;
            if count > 1 { Err(Full) } else { Ok(()) }
        };
        let mut tee = Tee::new().with(&mut a).with(&mut b);
        assert_eq!(tee.len(), 2);
        let r = Record::default();
        tee.push(&r).expect("first");
        let err = tee.push(&Record { index: 1, ..r }).expect_err("second");
        assert_eq!(err.to_string(), "full");
        drop(tee);
        assert_eq!(seen, [("a", 0), ("a", 1)]);
    }
}
