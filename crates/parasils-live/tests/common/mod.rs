//! A small Foxglove WebSocket client for the tests (`foxglove.sdk.v1`,
//! written from the protocol's description): connect, subscribe to every
//! channel, advertise input channels, publish, and collect what arrives.

#![allow(dead_code, reason = "each test binary uses a part of it")]

use core::time::Duration;
use std::collections::HashMap;
use std::time::Instant;

use futures_util::{SinkExt, StreamExt};
use parasils::teleop::TeleopParams;
use parasils_live::{LiveError, LiveOptions, Session, SessionReport};
use parasils_sim::{Scenario, TeleopRun};
use serde_json::{Value, json};
use tokio::net::TcpStream;
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::tungstenite::http::HeaderValue;
use tokio_tungstenite::tungstenite::{Error, Message};
use tokio_tungstenite::{MaybeTlsStream, WebSocketStream};

pub type Ws = WebSocketStream<MaybeTlsStream<TcpStream>>;

/// A session of the paper's robot at `rate_hz`, on a free loopback port.
pub fn session(rate_hz: f64, publish_hz: f64, duration_s: f64) -> Session {
    session_with(rate_hz, publish_hz, duration_s, None)
}

/// The same, with a token to drive.
pub fn session_with(
    rate_hz: f64,
    publish_hz: f64,
    duration_s: f64,
    token: Option<&str>,
) -> Session {
    session_options(
        rate_hz,
        &LiveOptions {
            port: 0,
            publish_hz,
            duration_s: Some(duration_s),
            token: token.map(str::to_owned),
            ..LiveOptions::default()
        },
    )
}

/// A session of the paper's robot at `rate_hz` with `options`.
pub fn session_options(rate_hz: f64, options: &LiveOptions) -> Session {
    start_session(rate_hz, options).expect("session")
}

/// [`Session::start`] for the paper's robot at `rate_hz` with `options`:
/// the session, or why it was refused.
pub fn start_session(rate_hz: f64, options: &LiveOptions) -> Result<Session, LiveError> {
    let scenario = Scenario {
        rate_hz,
        ..Scenario::paper()
    };
    let run = TeleopRun::new(scenario, TeleopParams::assumed()).expect("run");
    Session::start(run, options)
}

/// Runs `client` (given the session's address) on a runtime of its own
/// while `s` runs on another thread, then waits for the session to end;
/// what the client returned and the session's report.
pub fn drive<R>(s: Session, client: impl AsyncFnOnce(&str) -> R) -> (R, SessionReport) {
    let address = s.address().to_string();
    let waiter = std::thread::spawn(move || s.wait());
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    let out = rt.block_on(client(&address));
    let report = waiter.join().expect("join").expect("session");
    (out, report)
}

/// Connects offering `subprotocol`.
pub async fn connect(address: &str, subprotocol: &'static str) -> Result<Ws, Error> {
    let mut request = format!("ws://{address}").into_client_request()?;
    request.headers_mut().insert(
        "sec-websocket-protocol",
        HeaderValue::from_static(subprotocol),
    );
    let (ws, _) = tokio_tungstenite::connect_async(request).await?;
    Ok(ws)
}

/// A connected client: the channels advertised, its subscriptions, what
/// it received.
pub struct Client {
    pub ws: Ws,
    /// Topic of each server channel id.
    pub channels: HashMap<u64, String>,
    /// Topic of each subscription id.
    pub subscriptions: HashMap<u32, String>,
    /// Messages received per topic: (log time ns, payload as JSON).
    pub received: HashMap<String, Vec<(u64, Value)>>,
    /// Status messages received (level, message).
    pub statuses: Vec<(u64, String)>,
    /// Client channel id of each input topic advertised.
    pub inputs: HashMap<String, u32>,
    /// Id of each service the server advertised, by name.
    pub services: HashMap<String, u32>,
    /// Each service call's answer, by call id: the response's payload as
    /// JSON, or the failure's message.
    pub calls: HashMap<u32, Result<Value, String>>,
}

impl Client {
    /// Connects with `foxglove.sdk.v1` and reads until the channels are
    /// advertised.
    pub async fn new(address: &str) -> Client {
        let ws = connect(address, "foxglove.sdk.v1").await.expect("connect");
        let mut c = Client {
            ws,
            channels: HashMap::new(),
            subscriptions: HashMap::new(),
            received: HashMap::new(),
            statuses: Vec::new(),
            inputs: HashMap::new(),
            services: HashMap::new(),
            calls: HashMap::new(),
        };
        let deadline = Instant::now() + Duration::from_secs(5);
        while c.channels.is_empty() && Instant::now() < deadline {
            c.read_one(Duration::from_millis(200)).await;
        }
        assert!(!c.channels.is_empty(), "no channel advertised");
        c
    }

    /// Subscribes to the channels whose topic `keep` accepts.
    pub async fn subscribe(&mut self, keep: impl Fn(&str) -> bool) {
        let mut subs = Vec::new();
        for (id, topic) in &self.channels {
            if keep(topic) {
                let sub = u32::try_from(subs.len()).expect("few") + 1;
                subs.push(json!({"id": sub, "channelId": id}));
                self.subscriptions.insert(sub, topic.clone());
            }
        }
        let text = json!({"op": "subscribe", "subscriptions": subs}).to_string();
        self.ws.send(Message::text(text)).await.expect("subscribe");
    }

    /// Advertises `topic` as a JSON input channel.
    pub async fn advertise(&mut self, topic: &str) {
        let id = u32::try_from(self.inputs.len()).expect("few") + 1;
        let text = json!({"op": "advertise", "channels": [{"id": id, "topic": topic, "encoding": "json", "schemaName": "parasils.Input"}]}).to_string();
        self.ws.send(Message::text(text)).await.expect("advertise");
        self.inputs.insert(topic.to_owned(), id);
    }

    /// Publishes `value` on the input channel of `topic`.
    pub async fn publish(&mut self, topic: &str, value: &Value) {
        self.publish_raw(topic, value.to_string().as_bytes()).await;
    }

    /// Publishes raw bytes on the input channel of `topic`.
    pub async fn publish_raw(&mut self, topic: &str, payload: &[u8]) {
        let id = self.inputs[topic];
        let mut data = vec![1u8];
        data.extend_from_slice(&id.to_le_bytes());
        data.extend_from_slice(payload);
        self.ws.send(Message::binary(data)).await.expect("publish");
    }

    /// Calls the service `name` with the JSON `request` as call `call`, and
    /// reads until its answer comes (`None`: none within 2 s).
    pub async fn call(
        &mut self,
        name: &str,
        call: u32,
        request: &Value,
    ) -> Option<Result<Value, String>> {
        let service = self.services[name];
        let mut data = vec![2u8];
        data.extend_from_slice(&service.to_le_bytes());
        data.extend_from_slice(&call.to_le_bytes());
        data.extend_from_slice(&4u32.to_le_bytes());
        data.extend_from_slice(b"json");
        data.extend_from_slice(request.to_string().as_bytes());
        self.ws.send(Message::binary(data)).await.expect("call");
        self.read_until(Duration::from_secs(2), |c| c.calls.contains_key(&call))
            .await;
        self.calls.get(&call).cloned()
    }

    /// Reads one message (or times out); false when the connection closed.
    pub async fn read_one(&mut self, timeout: Duration) -> bool {
        let next = match tokio::time::timeout(timeout, self.ws.next()).await {
            Err(_) => return true,
            Ok(None) | Ok(Some(Err(_))) => return false,
            Ok(Some(Ok(m))) => m,
        };
        match next {
            Message::Text(text) => {
                let v: Value = serde_json::from_str(text.as_str()).expect("json");
                match v["op"].as_str() {
                    Some("advertise") => {
                        for ch in v["channels"].as_array().expect("channels") {
                            let id = ch["id"].as_u64().expect("id");
                            self.channels
                                .insert(id, ch["topic"].as_str().expect("topic").to_owned());
                        }
                    }
                    Some("advertiseServices") => {
                        for sv in v["services"].as_array().expect("services") {
                            let id = u32::try_from(sv["id"].as_u64().expect("id")).expect("u32");
                            let name = sv["name"].as_str().expect("name").to_owned();
                            self.services.insert(name, id);
                        }
                    }
                    Some("serviceCallFailure") => {
                        let call =
                            u32::try_from(v["callId"].as_u64().expect("callId")).expect("u32");
                        let message = v["message"].as_str().unwrap_or_default().to_owned();
                        self.calls.insert(call, Err(message));
                    }
                    Some("status") => self.statuses.push((
                        v["level"].as_u64().unwrap_or(9),
                        v["message"].as_str().unwrap_or_default().to_owned(),
                    )),
                    _ => {}
                }
            }
            Message::Binary(data) if data.first() == Some(&1) && data.len() >= 13 => {
                let sub = u32::from_le_bytes(data[1..5].try_into().expect("4"));
                let ns = u64::from_le_bytes(data[5..13].try_into().expect("8"));
                let value: Value = serde_json::from_slice(&data[13..]).expect("payload json");
                let topic = self.subscriptions[&sub].clone();
                self.received.entry(topic).or_default().push((ns, value));
            }
            Message::Binary(data) if data.first() == Some(&3) && data.len() >= 13 => {
                // Service call response: op, service id, call id, encoding
                // length and encoding, payload.
                let call = u32::from_le_bytes(data[5..9].try_into().expect("4"));
                let n = u32::from_le_bytes(data[9..13].try_into().expect("4")) as usize;
                let value: Value = serde_json::from_slice(&data[13 + n..]).expect("response json");
                self.calls.insert(call, Ok(value));
            }
            Message::Close(_) => return false,
            _ => {}
        }
        true
    }

    /// Reads until `done` holds or `timeout` passes; whether it held.
    pub async fn read_until(&mut self, timeout: Duration, done: impl Fn(&Client) -> bool) -> bool {
        let deadline = Instant::now() + timeout;
        while Instant::now() < deadline {
            if done(self) {
                return true;
            }
            if !self.read_one(Duration::from_millis(50)).await {
                return done(self);
            }
        }
        done(self)
    }

    /// Reads until the server closes the connection (or `timeout`).
    pub async fn read_to_end(&mut self, timeout: Duration) {
        let deadline = Instant::now() + timeout;
        while Instant::now() < deadline && self.read_one(Duration::from_millis(200)).await {}
    }
}
