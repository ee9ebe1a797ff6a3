//! `parasils serve`: the bound address on standard output, the protocol on
//! standard error, a session that ends by itself after `--duration-s`, and
//! one ended by SIGINT whose recording is complete (its summary and every
//! channel read back by the MCAP crate's reader).

mod common;

use core::time::Duration;
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::Path;

use common::process::{Ran, parasils};

/// Every message of the MCAP file at `path`, per topic: (log time, JSON).
fn read_mcap(path: &Path) -> BTreeMap<String, Vec<(u64, serde_json::Value)>> {
    let bytes = std::fs::read(path).expect("the recording");
    // A file cut short has no summary: this is the check that it is whole.
    let summary = mcap::Summary::read(&bytes)
        .expect("readable")
        .expect("a summary section");
    let stats = summary.stats.expect("statistics");
    let mut topics: BTreeMap<String, Vec<(u64, serde_json::Value)>> = BTreeMap::new();
    for m in mcap::MessageStream::new(&bytes).expect("stream") {
        let m = m.expect("a message");
        assert_eq!(m.channel.message_encoding, "json");
        let schema = m.channel.schema.as_ref().expect("a schema");
        assert_eq!(schema.encoding, "jsonschema", "{}", m.channel.topic);
        let value = serde_json::from_slice(&m.data).expect("JSON");
        topics
            .entry(m.channel.topic.clone())
            .or_default()
            .push((m.log_time, value));
    }
    let total: usize = topics.values().map(Vec::len).sum();
    assert_eq!(stats.message_count, total as u64);
    topics
}

/// The `t_s` of each message of `topic`.
fn times(topics: &BTreeMap<String, Vec<(u64, serde_json::Value)>>, topic: &str) -> Vec<f64> {
    topics[topic]
        .iter()
        .map(|(_, v)| v["t_s"].as_f64().expect("t_s"))
        .collect()
}

#[test]
fn a_session_ended_by_sigint_leaves_a_complete_recording() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut child = parasils(&[
        "serve",
        "--port",
        "0",
        "--duration-s",
        "25",
        "-o",
        "session.mcap",
    ])
    .dir(dir.path())
    .spawn();
    let stdout = child.take_stdout();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut line = String::new();
        BufReader::new(stdout).read_line(&mut line).ok();
        tx.send(line).ok();
    });
    let line = rx
        .recv_timeout(Duration::from_secs(60))
        .expect("the address line");
    let address = line
        .trim()
        .strip_prefix("parasils: serving on ws://")
        .unwrap_or_else(|| panic!("{line}"));
    let port: u16 = address
        .rsplit(':')
        .next()
        .and_then(|p| p.parse().ok())
        .expect("a port");
    assert!(address.starts_with("127.0.0.1:") && port != 0, "{address}");
    std::net::TcpStream::connect(address).expect("the server accepts connections");
    std::thread::sleep(Duration::from_millis(1500));
    child.signal("-INT");
    let ran = child.finish();
    let stderr = ran.stderr();
    println!("{stderr}");
    assert!(
        stderr.contains("protocol foxglove.sdk.v1 (the legacy foxglove.websocket.v1 is refused)"),
        "{stderr}"
    );
    assert!(stderr.contains("signal 2: ending the session"), "{stderr}");
    ran.ok();

    let topics = read_mcap(&dir.path().join("session.mcap"));
    for arm in ["left", "right", "platform"] {
        for kind in [
            "measured_js",
            "setpoint_js",
            "measured_cp",
            "setpoint_cp",
            "operating_state",
        ] {
            assert!(
                topics.contains_key(&format!("/{arm}/{kind}")),
                "/{arm}/{kind}"
            );
        }
    }
    for topic in [
        "/platform",
        "/module1",
        "/left",
        "/right",
        "/tips",
        "/margins",
        "/camera",
        "/tf",
        "/scene",
        "/camera/calibration",
        "/camera/annotations",
        "/diagnostics",
    ] {
        assert!(topics.contains_key(topic), "{topic}");
    }
    // 100 Hz publishing: the data channels every 10 ms from 0, all the
    // same times, up to the last cycle run (between the signal and the
    // session's 25 s).
    let platform = times(&topics, "/platform");
    let n = platform.len();
    for (k, t) in platform.iter().enumerate().take(n - 1) {
        assert!((t - k as f64 * 0.01).abs() < 1e-9, "{k}: {t}");
    }
    let last = platform[n - 1];
    assert!(last > 1.0 && last < 25.0, "{last}");
    assert_eq!(times(&topics, "/left/setpoint_js"), platform);
    assert_eq!(times(&topics, "/right/measured_cp"), platform);
    // The last cycle's diagnostics, written as the session ended.
    let diagnostics = &topics["/diagnostics"];
    let (_, final_diag) = diagnostics.last().expect("diagnostics");
    assert_eq!(final_diag["t_s"].as_f64(), Some(last));
    assert_eq!(final_diag["rate_hz"].as_f64(), Some(1000.0));
    let cycles = final_diag["cycles"].as_f64().expect("cycles");
    // Counted before the last cycle: the cycles up to it.
    assert_eq!(cycles, (last * 1000.0).round(), "{final_diag}");
    println!(
        "{n} cycles published over {last} s; {} messages; last diagnostics {final_diag}",
        topics.values().map(Vec::len).sum::<usize>()
    );
}

#[test]
fn a_session_ends_by_itself_after_its_duration() {
    let dir = tempfile::tempdir().expect("tempdir");
    let ran = serve_to(dir.path(), "500", "50", "1", "s.mcap");
    let stdout = ran.stdout();
    assert!(
        stdout.starts_with("parasils: serving on ws://127.0.0.1:"),
        "{stdout}"
    );
    ran.ok();
    let topics = read_mcap(&dir.path().join("s.mcap"));
    // 500 Hz for 1 s: cycles 0 to 500, every 10th published.
    let t = times(&topics, "/platform");
    assert_eq!(t.len(), 51);
    assert_eq!(t.last().copied(), Some(1.0));
    assert_eq!(times(&topics, "/right/setpoint_js"), t);
    let states: Vec<&str> = topics["/left/operating_state"]
        .iter()
        .map(|(_, v)| v["state"].as_str().expect("state"))
        .collect();
    assert!(states.iter().all(|s| *s == "DISABLED"), "{states:?}");

    // The `parasils.scenario` metadata, as `simulate`'s file has it for the
    // same robot, and the session's options.
    let served = scenario_metadata(&dir.path().join("s.mcap"));
    parasils(&["simulate", "--rate", "500", "-o", "sim.mcap"])
        .dir(dir.path())
        .run()
        .ok();
    let simulated = scenario_metadata(&dir.path().join("sim.mcap"));
    for key in [
        "geometry",
        "tips_mm",
        "bodies_mm",
        "module1_geometry",
        "scenario_units",
    ] {
        assert_eq!(served.get(key), simulated.get(key), "{key}");
    }
    let json = |m: &BTreeMap<String, String>, k: &str| -> serde_json::Value {
        serde_json::from_str(&m[k]).unwrap_or_else(|e| panic!("{k}: {e}"))
    };
    let scenario = json(&served, "scenario");
    assert_eq!(scenario["rate_hz"], 500.0);
    assert_eq!(scenario["start"], json(&simulated, "scenario")["start"]);
    assert_eq!(served["scene_period_s"], "0.02");
    let options = json(&served, "live_options");
    assert_eq!(options["rate_hz"], 500.0);
    assert_eq!(options["publish_hz"], 50.0);
    assert_eq!(options["duration_s"], 1.0);
    assert_eq!(options["bind"], "127.0.0.1");
    assert_eq!(options["token_required"], false);
}

/// `parasils serve` on a free port at `rate` Hz for `duration_s`,
/// publishing at `publish_hz` and recording to `file` in `dir`, run to its
/// end.
fn serve_to(dir: &Path, rate: &str, publish_hz: &str, duration_s: &str, file: &str) -> Ran {
    parasils(&[
        "serve",
        "--port",
        "0",
        "--rate",
        rate,
        "--publish-hz",
        publish_hz,
        "--duration-s",
        duration_s,
        "-o",
        file,
    ])
    .dir(dir)
    .run()
}

/// The `parasils.scenario` metadata record of the MCAP file at `path`.
fn scenario_metadata(path: &Path) -> BTreeMap<String, String> {
    let bytes = std::fs::read(path).expect("the recording");
    let summary = mcap::Summary::read(&bytes)
        .expect("readable")
        .expect("a summary section");
    let records: Vec<mcap::records::Metadata> = summary
        .metadata_indexes
        .iter()
        .map(|i| mcap::read::metadata(&bytes, i).expect("metadata"))
        .filter(|m| m.name == "parasils.scenario")
        .collect();
    assert_eq!(
        records.len(),
        1,
        "{}: one parasils.scenario record",
        path.display()
    );
    records[0].metadata.clone()
}

/// At 20 kHz half a period is 25 us, less than the default spin margin
/// (100 us): the command spins 25 us before each deadline instead of
/// refusing, and the session runs its 2,001 cycles.
#[test]
fn a_fast_control_rate_runs_with_the_spin_margin_within_half_its_period() {
    let dir = tempfile::tempdir().expect("tempdir");
    serve_to(dir.path(), "20000", "100", "0.1", "fast.mcap").ok();
    let topics = read_mcap(&dir.path().join("fast.mcap"));
    // The last cycle's diagnostics count the 2,000 cycles before it.
    let (_, last) = topics["/diagnostics"].last().expect("diagnostics");
    assert_eq!(last["t_s"].as_f64(), Some(0.1), "{last}");
    assert_eq!(last["cycles"].as_f64(), Some(2000.0), "{last}");
    let served = scenario_metadata(&dir.path().join("fast.mcap"));
    let options: serde_json::Value =
        serde_json::from_str(&served["live_options"]).expect("live_options");
    assert_eq!(options["spin_margin_s"], 25e-6);
}

#[test]
fn a_publishing_rate_above_the_control_rate_is_refused() {
    let text = parasils(&[
        "serve",
        "--port",
        "0",
        "--rate",
        "100",
        "--publish-hz",
        "200",
        "--duration-s",
        "1",
    ])
    .run()
    .error_line();
    assert_eq!(
        text.trim_end(),
        "parasils: error: live: publish_hz = 200 is out of range: at most the control rate"
    );
}
