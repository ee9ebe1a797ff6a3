//! The CSV writer: a header row (the names of the run's columns,
//! [`columns::csv_columns`]), then one row per record, every float in its
//! shortest round-trip form, the `command` index as an integer.

use std::io::Write;

use crate::columns::{self, Column};
use crate::record::Record;
use crate::scenario::Scenario;
use crate::sink::Sink;

/// Streams records as CSV rows to any writer.
pub struct CsvSink<W: Write> {
    out: csv::Writer<W>,
    columns: &'static [Column],
    buf: ryu::Buffer,
    int: itoa::Buffer,
}

impl<W: Write> core::fmt::Debug for CsvSink<W> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("CsvSink")
            .field("columns", &self.columns.len())
            .finish_non_exhaustive()
    }
}

impl<W: Write> CsvSink<W> {
    /// Writes the header row of the 74 columns of [`columns::CSV`] (a run
    /// without commands) and returns the sink.
    ///
    /// # Errors
    /// The writer's I/O error.
    pub fn new(writer: W) -> csv::Result<Self> {
        Self::with_columns(writer, &columns::CSV)
    }

    /// Writes the header row of `scenario`'s columns
    /// ([`columns::csv_columns`]: `command` last when it has commands) and
    /// returns the sink.
    ///
    /// # Errors
    /// The writer's I/O error.
    pub fn for_scenario(writer: W, scenario: &Scenario) -> csv::Result<Self> {
        Self::with_columns(writer, crate::no_go::csv_columns_of(scenario))
    }

    /// Writes the header row of `columns` and returns the sink.
    ///
    /// # Errors
    /// The writer's I/O error.
    pub fn with_columns(writer: W, columns: &'static [Column]) -> csv::Result<Self> {
        let mut out = csv::WriterBuilder::new()
            .buffer_capacity(1 << 16)
            .from_writer(writer);
        out.write_record(columns.iter().map(|c| c.name))?;
        Ok(Self {
            out,
            columns,
            buf: ryu::Buffer::new(),
            int: itoa::Buffer::new(),
        })
    }

    /// The columns written, in order.
    pub fn columns(&self) -> &'static [Column] {
        self.columns
    }

    /// Flushes and returns the writer.
    ///
    /// # Errors
    /// The writer's I/O error.
    pub fn finish(self) -> std::io::Result<W> {
        self.out.into_inner().map_err(|e| {
            let kind = e.error().kind();
            std::io::Error::new(kind, e.error().to_string())
        })
    }
}

impl<W: Write> Sink for CsvSink<W> {
    type Error = csv::Error;

    fn push(&mut self, record: &Record) -> csv::Result<()> {
        for column in self.columns {
            let value = column.value(record);
            if column.integer {
                // A command index: a u32, exactly an integer-valued f64.
                #[allow(
                    clippy::cast_possible_truncation,
                    clippy::cast_sign_loss,
                    reason = "the value is a u32 widened to f64"
                )]
                let v = value as u32;
                self.out.write_field(self.int.format(v))?;
            } else {
                // ryu prints the shortest decimal that reads back to the same f64.
                self.out.write_field(self.buf.format(value))?;
            }
        }
        self.out.write_record(None::<&[u8]>)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_read_back_exactly() {
        let mut r = Record {
            t: 0.1 + 0.2,
            ..Record::default()
        };
        r.left.tip_err = 1.234_567_890_123_456_7e-13;
        r.angles_deg[0] = 1.0 / 3.0;
        let mut sink = CsvSink::new(Vec::new()).expect("header");
        sink.push(&r).expect("row");
        let text = String::from_utf8(sink.finish().expect("flush")).expect("utf8");
        let mut lines = text.lines();
        assert_eq!(
            lines.next().map(|h| h.split(',').count()),
            Some(columns::CSV_COUNT)
        );
        let row: Vec<f64> = lines
            .next()
            .expect("a row")
            .split(',')
            .map(|v| v.parse().expect("a float"))
            .collect();
        assert_eq!(row, columns::csv_row(&r).to_vec());
    }

    #[test]
    fn a_run_with_commands_ends_with_the_integer_index() {
        let r = Record {
            command: 2,
            ..Record::default()
        };
        let scenario = Scenario {
            run: crate::scenario::Run::Online(crate::scenario::Online {
                stop_at_s: Some(1.0),
                ..crate::scenario::Online::default()
            }),
            ..Scenario::paper()
        };
        let mut sink = CsvSink::for_scenario(Vec::new(), &scenario).expect("header");
        sink.push(&r).expect("row");
        let text = String::from_utf8(sink.finish().expect("flush")).expect("utf8");
        let mut lines = text.lines();
        assert!(
            lines
                .next()
                .is_some_and(|h| h.ends_with(",endoscope_port_y_mm,endoscope_port_z_mm,command"))
        );
        assert!(lines.next().is_some_and(|row| row.ends_with(",0.0,2")));
        let paper = CsvSink::for_scenario(Vec::new(), &Scenario::paper()).expect("header");
        assert_eq!(paper.columns().len(), 74);
    }
}
