//! The CSV writer: a header row (the names of [`columns::CSV`]), then one
//! row per record, every float in its shortest round-trip form.

use std::io::Write;

use crate::columns;
use crate::record::Record;
use crate::sink::Sink;

/// Streams records as CSV rows to any writer.
pub struct CsvSink<W: Write> {
    out: csv::Writer<W>,
    buf: ryu::Buffer,
}

impl<W: Write> core::fmt::Debug for CsvSink<W> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("CsvSink").finish_non_exhaustive()
    }
}

impl<W: Write> CsvSink<W> {
    /// Writes the header row and returns the sink.
    ///
    /// # Errors
    /// The writer's I/O error.
    pub fn new(writer: W) -> csv::Result<Self> {
        let mut out = csv::WriterBuilder::new()
            .buffer_capacity(1 << 16)
            .from_writer(writer);
        out.write_record(columns::CSV_NAMES)?;
        Ok(Self {
            out,
            buf: ryu::Buffer::new(),
        })
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
        for column in &columns::CSV {
            // ryu prints the shortest decimal that reads back to the same f64.
            self.out
                .write_field(self.buf.format(column.value(record)))?;
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
}
