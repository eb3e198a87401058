//! The explorer's server: axum on a tokio runtime of one thread, engine work on the
//! blocking pool (inside the command's rayon pool). Every request must carry the token
//! (`?token=` or the header `x-monoculus-token`), name the address it serves as its
//! Host, and come from no other origin; bodies are bounded.

use std::net::{IpAddr, SocketAddr};
use std::sync::{Arc, Mutex};

use axum::Router;
use axum::body::Bytes;
use axum::extract::{DefaultBodyLimit, Query, Request, State};
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use glam::DVec2;
use serde::Deserialize;
use serde_json::{Value, json};

use super::session::{Refused, Session};
use crate::commands::Failure;

/// The largest request body, bytes: a positions CSV of the most robots the explorer
/// holds fits (about 40 bytes a robot).
pub const MAX_BODY: usize = 64 << 20;

static PAGE: &str = include_str!("../../../assets/explore.html");

/// The page, with the drawing script it shares with the replay page.
fn page_html() -> &'static str {
    static HTML: std::sync::LazyLock<String> = std::sync::LazyLock::new(|| {
        PAGE.replacen(monoculus_plot::VIEW_SLOT, monoculus_plot::VIEW_JS, 1)
    });
    &HTML
}

/// What every request is checked against.
struct Guard {
    token: String,
    /// The Host values of the address served (`127.0.0.1:8000`, and for a loopback
    /// address `localhost:8000`).
    hosts: Vec<String>,
    /// The origins of those (`http://127.0.0.1:8000`).
    origins: Vec<String>,
}

#[derive(Clone)]
struct App {
    session: Arc<Mutex<Session>>,
    pool: Arc<rayon::ThreadPool>,
    guard: Arc<Guard>,
}

/// Serves `session` on `host:port` until the process is stopped (Ctrl-C).
pub fn serve(
    session: Session,
    host: &str,
    port: u16,
    pool: rayon::ThreadPool,
) -> Result<(), Failure> {
    let ip: IpAddr = host.parse().map_err(|_| {
        Failure::Input(format!(
            "--host `{host}`: expected an IP address, e.g. 127.0.0.1"
        ))
    })?;
    if ip.is_unspecified() {
        // The Host check needs the one address the explorer is reached at.
        return Err(Failure::Input(format!(
            "--host {host}: name one address to serve (127.0.0.1, or this machine's address on its network), not all of them"
        )));
    }
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_io()
        .build()?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::bind(SocketAddr::new(ip, port))
            .await
            .map_err(|e| Failure::Input(format!("--host {host} --port {port}: cannot listen: {e}")))?;
        let addr = listener.local_addr()?;
        let shown = match addr {
            SocketAddr::V4(a) => format!("{}:{}", a.ip(), a.port()),
            SocketAddr::V6(a) => format!("[{}]:{}", a.ip(), a.port()),
        };
        let mut hosts = vec![shown.clone()];
        if ip.is_loopback() {
            hosts.push(format!("localhost:{}", addr.port()));
        }
        let guard = Guard {
            token: token()?,
            origins: hosts.iter().map(|h| format!("http://{h}")).collect(),
            hosts,
        };
        let url = format!("http://{shown}/?token={}", guard.token);
        crate::commands::write_stdout(format_args!("monoculus explore: {url}\n"))?;
        eprintln!("Open the address above in a browser; Ctrl-C stops the explorer.");
        if !ip.is_loopback() {
            eprintln!(
                "warning: --host {host} is not a loopback address: other machines can reach the explorer (they still need its token)"
            );
        }
        let app = App {
            session: Arc::new(Mutex::new(session)),
            pool: Arc::new(pool),
            guard: Arc::new(guard),
        };
        let router = routes(app.clone());
        axum::serve(listener, router)
            .await
            .map_err(|e| Failure::Other(e.into()))
    })
}

fn routes(app: App) -> Router {
    Router::new()
        .route("/", get(page))
        .route("/api/setup", get(setup))
        .route("/api/state", get(state))
        .route("/api/settings", post(settings))
        .route("/api/generate", post(generate))
        .route("/api/edit", post(edit))
        .route("/api/positions", post(positions))
        .route("/api/step", post(step))
        .route("/api/reset", post(reset))
        .route("/api/robot", get(robot))
        .route("/api/export/config", get(export_config))
        .route("/api/export/positions.csv", get(export_positions))
        .route("/api/export/replay.html", get(export_replay))
        .layer(DefaultBodyLimit::max(MAX_BODY))
        .layer(middleware::from_fn_with_state(app.clone(), check))
        .with_state(app)
}

/// A random token of 128 bits, hex.
fn token() -> Result<String, Failure> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes)
        .map_err(|e| Failure::Other(anyhow::anyhow!("no random token: {e}")))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// Equal strings, compared in a time that does not depend on where they differ.
fn same(a: &str, b: &str) -> bool {
    a.len() == b.len()
        && a.bytes()
            .zip(b.bytes())
            .fold(0u8, |acc, (x, y)| acc | (x ^ y))
            == 0
}

fn refuse(status: StatusCode, message: &str) -> Response {
    (status, axum::Json(json!({ "error": message }))).into_response()
}

/// The checks every request passes before it is served: Host (DNS rebinding), Origin
/// (other sites), token; and the headers every response carries.
async fn check(State(app): State<App>, req: Request, next: Next) -> Response {
    let g = &app.guard;
    let headers = req.headers();
    let host = headers.get(header::HOST).and_then(|v| v.to_str().ok());
    if !host.is_some_and(|h| g.hosts.iter().any(|a| a == h)) {
        return refuse(
            StatusCode::FORBIDDEN,
            "refused: the Host header is not the address the explorer serves",
        );
    }
    if let Some(origin) = headers.get(header::ORIGIN) {
        let ok = origin
            .to_str()
            .is_ok_and(|o| g.origins.iter().any(|a| a == o));
        if !ok {
            return refuse(
                StatusCode::FORBIDDEN,
                "refused: a request from another origin",
            );
        }
    }
    let given = headers
        .get("x-monoculus-token")
        .and_then(|v| v.to_str().ok())
        .map(str::to_string)
        .or_else(|| {
            req.uri().query().and_then(|q| {
                q.split('&')
                    .find_map(|kv| kv.strip_prefix("token="))
                    .map(str::to_string)
            })
        });
    if !given.is_some_and(|t| same(&t, &g.token)) {
        return refuse(
            StatusCode::UNAUTHORIZED,
            "refused: a missing or wrong token (use the address the explorer printed)",
        );
    }
    let mut response = next.run(req).await;
    let h = response.headers_mut();
    h.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
    h.insert(
        header::REFERRER_POLICY,
        HeaderValue::from_static("no-referrer"),
    );
    h.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    h.insert(header::X_FRAME_OPTIONS, HeaderValue::from_static("DENY"));
    response
}

/// Runs `f` on the session, off the runtime's thread, inside the engine's pool.
async fn with<T: Send + 'static>(
    app: &App,
    f: impl FnOnce(&mut Session) -> Result<T, Refused> + Send + 'static,
) -> Result<T, Response> {
    let (session, pool) = (app.session.clone(), app.pool.clone());
    let done = tokio::task::spawn_blocking(move || {
        let mut s = session.lock().unwrap_or_else(|p| p.into_inner());
        let s: &mut Session = &mut s;
        pool.install(|| f(s))
    })
    .await;
    match done {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(Refused(message))) => Err(refuse(StatusCode::BAD_REQUEST, &message)),
        Err(e) => Err(refuse(
            StatusCode::INTERNAL_SERVER_ERROR,
            &format!("the request failed: {e}"),
        )),
    }
}

fn json_or(r: Result<Value, Response>) -> Response {
    match r {
        Ok(v) => axum::Json(v).into_response(),
        Err(e) => e,
    }
}

async fn page() -> Response {
    let mut r = (
        [(header::CONTENT_TYPE, "text/html; charset=utf-8")],
        page_html(),
    )
        .into_response();
    r.headers_mut().insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(
            "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; connect-src 'self'; img-src 'self' data:; frame-ancestors 'none'; form-action 'none'; base-uri 'none'",
        ),
    );
    r
}

#[derive(Deserialize)]
struct Since {
    #[serde(default)]
    since: usize,
}

async fn setup(State(app): State<App>) -> Response {
    json_or(with(&app, |s| Ok(s.setup())).await)
}

async fn state(State(app): State<App>, Query(q): Query<Since>) -> Response {
    json_or(with(&app, move |s| Ok(s.state(q.since))).await)
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Settings {
    settings: String,
    #[serde(default)]
    generate: bool,
}

/// A JSON body, or the refusal that names what is wrong with it.
fn body<T: serde::de::DeserializeOwned>(bytes: &Bytes) -> Result<T, Response> {
    serde_json::from_slice(bytes)
        .map_err(|e| refuse(StatusCode::BAD_REQUEST, &format!("the request: {e}")))
}

async fn settings(State(app): State<App>, bytes: Bytes) -> Response {
    let req: Settings = match body(&bytes) {
        Ok(r) => r,
        Err(e) => return e,
    };
    json_or(
        with(&app, move |s| {
            s.set_settings(&req.settings, req.generate)?;
            Ok(json!({ "setup": s.setup(), "state": s.state(0) }))
        })
        .await,
    )
}

async fn generate(State(app): State<App>) -> Response {
    json_or(
        with(&app, |s| {
            s.generate()?;
            Ok(s.state(0))
        })
        .await,
    )
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Edit {
    op: String,
    robot: Option<usize>,
    x: Option<f64>,
    y: Option<f64>,
}

async fn edit(State(app): State<App>, bytes: Bytes) -> Response {
    let e: Edit = match body(&bytes) {
        Ok(r) => r,
        Err(e) => return e,
    };
    let at = e.x.zip(e.y).map(|(x, y)| DVec2::new(x, y));
    json_or(
        with(&app, move |s| {
            s.edit(&e.op, e.robot, at)?;
            Ok(s.state(0))
        })
        .await,
    )
}

#[derive(Deserialize)]
struct Named {
    #[serde(default)]
    name: Option<String>,
}

async fn positions(State(app): State<App>, Query(q): Query<Named>, bytes: Bytes) -> Response {
    let text = match String::from_utf8(bytes.to_vec()) {
        Ok(t) => t,
        Err(_) => return refuse(StatusCode::BAD_REQUEST, "the positions CSV is not UTF-8"),
    };
    let name = q.name.unwrap_or_else(|| "positions CSV".into());
    json_or(
        with(&app, move |s| {
            s.load_positions(&text, &name)?;
            Ok(s.state(0))
        })
        .await,
    )
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Step {
    /// Rounds (epochs) to step; none: to the end of the run.
    count: Option<u64>,
    #[serde(default)]
    since: usize,
}

async fn step(State(app): State<App>, bytes: Bytes) -> Response {
    let req: Step = match body(&bytes) {
        Ok(r) => r,
        Err(e) => return e,
    };
    json_or(
        with(&app, move |s| {
            s.step(req.count);
            Ok(s.state(req.since))
        })
        .await,
    )
}

async fn reset(State(app): State<App>) -> Response {
    json_or(
        with(&app, |s| {
            s.restart()?;
            Ok(s.state(0))
        })
        .await,
    )
}

#[derive(Deserialize)]
struct Which {
    i: usize,
}

async fn robot(State(app): State<App>, Query(q): Query<Which>) -> Response {
    json_or(with(&app, move |s| s.robot(q.i)).await)
}

fn download(kind: &'static str, name: &'static str, text: String) -> Response {
    let mut headers = HeaderMap::new();
    headers.insert(header::CONTENT_TYPE, HeaderValue::from_static(kind));
    headers.insert(
        header::CONTENT_DISPOSITION,
        HeaderValue::from_str(&format!("attachment; filename=\"{name}\"")).expect("a plain name"),
    );
    (headers, text).into_response()
}

async fn export_config(State(app): State<App>) -> Response {
    match with(&app, |s| Ok(s.export_config())).await {
        Ok(t) => download("application/toml; charset=utf-8", "explore.toml", t),
        Err(e) => e,
    }
}

async fn export_positions(State(app): State<App>) -> Response {
    match with(&app, |s| Ok(s.export_positions())).await {
        Ok(t) => download("text/csv; charset=utf-8", "positions.csv", t),
        Err(e) => e,
    }
}

async fn export_replay(State(app): State<App>) -> Response {
    match with(&app, |s| s.export_replay()).await {
        Ok(t) => download("text/html; charset=utf-8", "replay.html", t),
        Err(e) => e,
    }
}
