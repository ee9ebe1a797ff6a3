//! The CSV and MCAP writers with arbitrary records, to memory. No call may
//! panic; a value a format cannot hold is a typed error; a file written
//! without error reads back, with every number equal to the record's to the
//! last bit.

use std::io::Cursor;

use nalgebra::Vector3;
use parasils::supervisor::MarginSet;
use parasils_sim::Sink;
use parasils_sim::columns::{self, Column};
use parasils_sim::csv::CsvSink;
use parasils_sim::mcap::{McapError, McapOptions, McapSink};
use parasils_sim::scenario::{CommandKind, Online, Run, Scenario};
use parasils_sim::{InstrumentRecord, Module1Record, Record};

use crate::input::Input;

/// Up to four records from the input: each float arbitrary, or (when the
/// input's flag says so) with every non-finite value replaced by 0, so that
/// whole files are written often; times increasing unless the input says
/// otherwise.
fn records(inp: &mut Input) -> Vec<Record> {
    let n = 1 + usize::from(inp.choose(4));
    let tame = inp.flag();
    let increasing = inp.flag();
    let real = |inp: &mut Input| -> f64 {
        let x: f64 = inp.real();
        if tame && !x.is_finite() { 0.0 } else { x }
    };
    let mut out: Vec<Record> = Vec::with_capacity(n);
    for index in 0..n {
        let mut t = real(inp);
        if increasing {
            let previous = out.last().map_or(0.0, |r: &Record| r.t);
            t = previous + t.abs().min(1e6) + if index == 0 { 0.0 } else { 1e-3 };
        }
        let arr = |inp: &mut Input| -> [f64; 3] { core::array::from_fn(|_| real(inp)) };
        let pose = [
            real(inp),
            real(inp),
            real(inp),
            real(inp),
            real(inp),
            real(inp),
        ];
        let mut record = Record {
            index,
            t,
            pose,
            angles_deg: arr(inp),
            euler_dot: arr(inp),
            euler_ddot: arr(inp),
            ..Record::default()
        };
        let six = |inp: &mut Input| -> [f64; 6] { core::array::from_fn(|_| real(inp)) };
        record.module1 = Module1Record {
            q: six(inp),
            q_dot: six(inp),
            q_ddot: six(inp),
            serial_margin: real(inp),
            parallel_margin: real(inp),
        };
        for side in [&mut record.left, &mut record.right] {
            let arr = |inp: &mut Input| -> [f64; 3] { core::array::from_fn(|_| real(inp)) };
            *side = InstrumentRecord {
                q: arr(inp),
                q_dot: arr(inp),
                q_ddot: arr(inp),
                cos_qs2: real(inp),
                tip: Vector3::from(arr(inp)),
                tip_err: real(inp),
            };
        }
        record.command = u32::from(inp.byte());
        record.kind = match inp.choose(4) {
            0 => CommandKind::Reorient,
            1 => CommandKind::Retarget,
            2 => CommandKind::Stop,
            _ => CommandKind::SupervisorStop,
        };
        record.warnings = MarginSet::from_bits(inp.uint(2) as u16);
        out.push(record);
    }
    out
}

/// Whether `text` reads back as `expected`, to the last bit (NaNs of any
/// payload are equal: CSV has one NaN).
fn same(text: &str, expected: f64) -> bool {
    text.parse::<f64>()
        .is_ok_and(|v| v.to_bits() == expected.to_bits() || (v.is_nan() && expected.is_nan()))
}

thread_local! {
    /// The `csv` crate's parser, built once: building one (its DFA) costs
    /// more than writing and reading a file of four records, so a reader per
    /// input would spend the campaign's time there; `reset` makes it as new.
    static READER: core::cell::RefCell<csv_core::Reader> =
        core::cell::RefCell::new(csv_core::Reader::new());
}

/// The rows of a CSV text, each a list of fields, as the `csv` crate's
/// parser reads them (the parser `csv::Reader` drives, with its defaults).
fn read_rows(bytes: &[u8]) -> Vec<Vec<String>> {
    READER.with_borrow_mut(|reader| {
        reader.reset();
        let mut rows = Vec::new();
        let mut input = bytes;
        // No field nor row is longer than the text: one call reads a record.
        let mut out = vec![0u8; bytes.len() + 1];
        let mut ends = vec![0usize; bytes.len() + 1];
        let (mut n_out, mut n_ends) = (0, 0);
        loop {
            let (result, n_in, o, e) =
                reader.read_record(input, &mut out[n_out..], &mut ends[n_ends..]);
            input = &input[n_in..];
            n_out += o;
            n_ends += e;
            match result {
                // The next call, with no input left, ends the text.
                csv_core::ReadRecordResult::InputEmpty => {}
                csv_core::ReadRecordResult::OutputFull
                | csv_core::ReadRecordResult::OutputEndsFull => {
                    panic!("a CSV record longer than its text")
                }
                csv_core::ReadRecordResult::Record => {
                    let mut start = 0;
                    let row = ends[..n_ends]
                        .iter()
                        .map(|&end| {
                            let field = core::str::from_utf8(&out[start..end])
                                .expect("a UTF-8 field")
                                .to_owned();
                            start = end;
                            field
                        })
                        .collect();
                    rows.push(row);
                    (n_out, n_ends) = (0, 0);
                }
                csv_core::ReadRecordResult::End => return rows,
            }
        }
    })
}

/// The CSV target's check: write, read back with the `csv` crate's parser.
pub fn csv(data: &[u8]) {
    let mut inp = Input::new(data);
    let with_command = inp.flag();
    let records = records(&mut inp);
    let cols: &'static [Column] = columns::csv_columns(with_command);
    let mut sink = CsvSink::with_columns(Vec::new(), cols).expect("memory does not fail");
    for r in &records {
        // Every f64 has a CSV form: no error is possible.
        sink.push(r).expect("a CSV row of any numbers");
    }
    let bytes = sink.finish().expect("memory does not fail");
    let rows = read_rows(&bytes);
    let (header, rows) = rows.split_first().expect("a header");
    assert!(
        header
            .iter()
            .map(String::as_str)
            .eq(cols.iter().map(|c| c.name)),
        "the header {header:?}"
    );
    assert_eq!(rows.len(), records.len(), "the row count");
    for (k, (row, r)) in rows.iter().zip(&records).enumerate() {
        assert_eq!(row.len(), cols.len(), "row {k}'s length");
        for (text, c) in row.iter().zip(cols) {
            let v = c.value(r);
            if c.integer {
                // A whole number (the command index, a tip in view): its
                // digits alone.
                assert_eq!(*text, v.to_string(), "{}", c.name);
            } else {
                assert!(same(text, v), "{}: `{text}` for {v:e}", c.name);
            }
        }
    }
}

/// The MCAP target's check: write with options from the input; a file
/// finished without error reads back with the `mcap` crate, each data
/// message equal to its record.
pub fn mcap(data: &[u8]) {
    let mut inp = Input::new(data);
    let mut scenario = Scenario::paper();
    if inp.flag() {
        // A run with commands: the `/motion` topic.
        scenario.run = Run::Online(Online {
            stop_at_s: Some(1.0),
            ..Online::default()
        });
    }
    let options = McapOptions {
        scene_period_s: inp.real(),
        compression_level: u32::from(inp.choose(4)),
        chunk_size: inp.uint(3),
    };
    let records = records(&mut inp);
    let mut sink = match McapSink::with_options(Cursor::new(Vec::new()), &scenario, options) {
        Ok(s) => s,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    for r in &records {
        if let Err(e) = sink.push(r) {
            // The run stops at the first error, and the file is dropped.
            assert!(!e.to_string().is_empty());
            return;
        }
    }
    let bytes = match sink.finish() {
        Ok(w) => w.into_inner(),
        // The last record's visuals are computed when the file is
        // finished: a number they cannot hold is the typed error `finish`
        // documents, naming the topic.
        Err(e @ McapError::NonFinite { topic, .. })
            if topic == parasils_sim::mcap::TF_TOPIC
                || topic == parasils_sim::mcap::SCENE_TOPIC =>
        {
            assert!(!e.to_string().is_empty());
            return;
        }
        Err(e) => panic!("finishing an MCAP of accepted records failed: {e}"),
    };
    let mut seen = [0usize; columns::Channel::ALL.len()];
    for message in mcap::MessageStream::new(&bytes).expect("an MCAP file") {
        let message = message.expect("a readable message");
        let topic = message.channel.topic.as_str();
        let Some(k) = parasils_sim::mcap::SAMPLE_TOPICS
            .iter()
            .position(|t| *t == topic)
        else {
            continue;
        };
        let channel = columns::Channel::ALL[k];
        let seq = usize::try_from(message.sequence).expect("u32 fits usize");
        let r = records.get(seq).expect("one message per record");
        let json: serde_json::Value =
            serde_json::from_slice(&message.data).expect("a JSON message");
        let object = json.as_object().expect("a JSON object");
        let fields = core::iter::once(columns::T_S).chain(
            columns::ALL
                .into_iter()
                .filter(|c| c.channel == Some(channel)),
        );
        let mut n = 0;
        for c in fields {
            let v = object
                .get(c.name)
                .and_then(serde_json::Value::as_f64)
                .unwrap_or_else(|| panic!("{topic}: no number {}", c.name));
            assert_eq!(v.to_bits(), c.value(r).to_bits(), "{topic}: {}", c.name);
            n += 1;
        }
        assert_eq!(object.len(), n, "{topic}: extra fields");
        seen[k] += 1;
    }
    assert!(
        seen.iter().all(|&n| n == records.len()),
        "messages per topic {seen:?} for {} records",
        records.len()
    );
}
