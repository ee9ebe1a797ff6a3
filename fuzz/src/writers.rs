//! The CSV and MCAP writers with arbitrary records, to memory. No call may
//! panic; a value a format cannot hold is a typed error; a file written
//! without error reads back, with every number equal to the record's to the
//! last bit.

use std::io::Cursor;

use nalgebra::Vector3;
use parasils::supervisor::MarginSet;
use parasils_sim::columns::{self, Column};
use parasils_sim::csv::CsvSink;
use parasils_sim::mcap::{McapOptions, McapSink};
use parasils_sim::record::{InstrumentRecord, Module1Record, Record};
use parasils_sim::scenario::{CommandKind, Scenario};
use parasils_sim::sink::Sink;

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

/// The CSV target's check: write, read back with the `csv` crate.
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
    let mut reader = csv::ReaderBuilder::new().from_reader(bytes.as_slice());
    let header = reader.headers().expect("a header").clone();
    assert!(
        header.iter().eq(cols.iter().map(|c| c.name)),
        "the header {header:?}"
    );
    let mut rows = 0;
    for (row, r) in reader.records().zip(&records) {
        let row = row.expect("a well-formed row");
        assert_eq!(row.len(), cols.len(), "row {rows}'s length");
        for (text, c) in row.iter().zip(cols) {
            let v = c.value(r);
            if c.integer {
                assert_eq!(text, r.command.to_string(), "{}", c.name);
            } else {
                assert!(same(text, v), "{}: `{text}` for {v:e}", c.name);
            }
        }
        rows += 1;
    }
    assert_eq!(rows, records.len(), "the row count");
}

/// The MCAP target's check: write with options from the input; a file
/// finished without error reads back with the `mcap` crate, each data
/// message equal to its record.
pub fn mcap(data: &[u8]) {
    let mut inp = Input::new(data);
    let mut scenario = Scenario::paper();
    if inp.flag() {
        // A run with commands: the `/motion` topic.
        scenario.stop_at_s = Some(1.0);
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
        Err(e) => panic!("finishing an MCAP of accepted records failed: {e}"),
    };
    let mut seen = [0usize; 6];
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
