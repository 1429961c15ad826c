//! The web build: `cargo xtask web [--port P] [--release]` builds the viewer for the browser
//! and serves `web/` with the headers that cross-origin isolation needs; the `web` step of
//! `cargo xtask test` builds the bundle, serves it, and runs the browser tests in
//! `tests/browser` (Node's test runner driving Debian's chromium through playwright-core).

use std::env;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Ipv4Addr, TcpListener, TcpStream};
use std::path::{Component, Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use crate::{cargo, run_status, succeeds};

/// The wasm-bindgen CLI version; it must equal the `wasm-bindgen` crate's (pinned with `=`
/// in crates/app/Cargo.toml), or the generated JavaScript does not fit the module.
pub const WASM_BINDGEN_VERSION: &str = "0.2.130";

/// The port `cargo xtask web` serves on unless `--port` says otherwise.
pub const DEFAULT_PORT: u16 = 8080;

/// The compiler flags of the threaded build: atomics and a shared, imported memory, plus the
/// thread-local-storage symbols each worker's instance needs (docs/web.md, "Build flags"), and
/// 128-bit SIMD (`simd128`), which the solver's 8-wide lanes use: without it they fall back
/// to scalar code and a step takes about 3.5 times as long (docs/bench/web.md). Every browser
/// with WebAssembly threads has SIMD. They apply to the wasm target only, so host tools and
/// build scripts build as usual.
const WASM_RUSTFLAGS: &str = "-C target-feature=+atomics,+bulk-memory,+mutable-globals,+simd128 \
     -C link-arg=--shared-memory -C link-arg=--max-memory=1073741824 \
     -C link-arg=--import-memory -C link-arg=--export=__wasm_init_tls \
     -C link-arg=--export=__tls_size -C link-arg=--export=__tls_align \
     -C link-arg=--export=__tls_base";

const TARGET: &str = "wasm32-unknown-unknown";

/// The static files of the page (the rest is wasm-bindgen's output in `web/pkg`).
const PAGE_FILES: &[&str] = &["index.html", "main.js", "style.css"];

pub const USAGE: &str =
    "  web     build the viewer for the browser (WebGPU or WebGL2, threads on Web
          Workers) and serve web/ at http://127.0.0.1:8080/ with the cross-origin
          isolation headers, until stopped (installs the nightly toolchain's rust-src,
          the wasm32 target and wasm-bindgen-cli when missing)
            --port P    serve on port P
            --release   also write a static bundle to target/web-bundle/ (host it
                        anywhere that sends the same headers; docs/web.md)
            --test      instead: the browser tests alone (the `web` step of `test`)";

/// `cargo xtask web [--port P] [--release]`.
pub fn task(root: &Path, args: &[String]) -> Result<(), String> {
    let mut port = DEFAULT_PORT;
    let mut bundle = false;
    let mut rest = args.iter();
    while let Some(arg) = rest.next() {
        match arg.as_str() {
            "--release" => bundle = true,
            "--test" if args.len() == 1 => return browser_tests(root),
            "--port" => {
                let value = rest.next().ok_or("--port needs a value")?;
                port = value
                    .parse()
                    .map_err(|_| format!("--port {value}: not a port number"))?;
            }
            other => return Err(format!("unknown argument `{other}`")),
        }
    }
    build(root)?;
    let served = if bundle {
        let dir = write_bundle(root)?;
        println!(
            "static bundle: {} (serve it with the headers \
             Cross-Origin-Opener-Policy: same-origin and \
             Cross-Origin-Embedder-Policy: require-corp)",
            dir.display()
        );
        dir
    } else {
        root.join("web")
    };
    let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, port))
        .map_err(|e| format!("cannot listen on 127.0.0.1:{port}: {e} (try --port)"))?;
    println!(
        "serving {} at http://127.0.0.1:{port}/ (cross-origin isolated; Ctrl-C stops)",
        served.display()
    );
    println!("  a scene and threads: http://127.0.0.1:{port}/?scene=large_pyramid&threads=2");
    serve(listener, &served, true, &AtomicBool::new(false));
    Ok(())
}

/// Where cargo puts build output: `$CARGO_TARGET_DIR`, else `target/`.
pub(crate) fn target_dir(root: &Path) -> PathBuf {
    env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|d| if d.is_absolute() { d } else { root.join(d) })
        .unwrap_or_else(|| root.join("target"))
}

/// `cargo +nightly SUBCOMMAND -Z build-std=panic_abort,std --target wasm32-unknown-unknown
/// --release -p tumble` with the threaded build's flags.
fn nightly_wasm(root: &Path, subcommand: &str) -> Command {
    let mut cargo = Command::new("cargo");
    cargo
        .arg("+nightly")
        .args([
            subcommand,
            "-Z",
            "build-std=panic_abort,std",
            "--target",
            TARGET,
        ])
        .args(["--release", "-p", "tumble", "-j2"])
        .current_dir(root)
        // xtask runs under the stable toolchain: let `+nightly` choose the compiler.
        .env_remove("RUSTUP_TOOLCHAIN")
        .env_remove("RUSTC")
        .env_remove("RUSTDOC")
        .env(
            "CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUSTFLAGS",
            WASM_RUSTFLAGS,
        );
    cargo
}

/// Clippy on the web build (its `cfg(target_arch = "wasm32")` code is invisible to the
/// native clippy step), warnings denied.
pub fn clippy(root: &Path) -> Result<(), String> {
    ensure_nightly()?;
    let listed = Command::new("rustup")
        .args(["component", "list", "--toolchain", "nightly", "--installed"])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default();
    if !listed.lines().any(|l| l.starts_with("clippy")) {
        println!("nightly's clippy is missing; installing it");
        run_status(
            Command::new("rustup").args(["component", "add", "clippy", "--toolchain", "nightly"]),
            "rustup component add clippy --toolchain nightly",
        )?;
    }
    run_status(
        nightly_wasm(root, "clippy").args(["--", "-D", "warnings"]),
        "cargo +nightly clippy --target wasm32-unknown-unknown -p tumble -- -D warnings",
    )
}

/// Builds the viewer for the browser (threaded, release) and runs wasm-bindgen into
/// `web/pkg`, installing what is missing first.
pub fn build(root: &Path) -> Result<(), String> {
    ensure_nightly()?;
    let wasm_bindgen = ensure_wasm_bindgen()?;
    run_status(
        nightly_wasm(root, "build").args(["--bin", "tumble"]),
        "cargo +nightly build -Z build-std=panic_abort,std --target wasm32-unknown-unknown \
         --release -p tumble",
    )?;
    let wasm = target_dir(root).join(TARGET).join("release/tumble.wasm");
    let pkg = root.join("web/pkg");
    let _ = std::fs::remove_dir_all(&pkg);
    run_status(
        Command::new(&wasm_bindgen)
            .args(["--target", "web", "--out-name", "tumble", "--out-dir"])
            .arg(&pkg)
            .arg(&wasm),
        "wasm-bindgen --target web --out-dir web/pkg",
    )
}

/// Copies the page and `web/pkg` into `target/web-bundle/` (emptied first), with a
/// `_headers` file for hosts that read one (Netlify, Cloudflare Pages). Returns the folder.
pub fn write_bundle(root: &Path) -> Result<PathBuf, String> {
    let dir = target_dir(root).join("web-bundle");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    for file in PAGE_FILES {
        std::fs::copy(root.join("web").join(file), dir.join(file))
            .map_err(|e| format!("cannot copy web/{file}: {e}"))?;
    }
    copy_dir(&root.join("web/pkg"), &dir.join("pkg"))?;
    std::fs::write(
        dir.join("_headers"),
        "/*\n  Cross-Origin-Opener-Policy: same-origin\n  \
         Cross-Origin-Embedder-Policy: require-corp\n",
    )
    .map_err(|e| format!("cannot write the bundle's _headers: {e}"))?;
    Ok(dir)
}

fn copy_dir(from: &Path, to: &Path) -> Result<(), String> {
    std::fs::create_dir_all(to).map_err(|e| format!("cannot create {}: {e}", to.display()))?;
    let entries =
        std::fs::read_dir(from).map_err(|e| format!("cannot read {}: {e}", from.display()))?;
    for entry in entries {
        let entry = entry.map_err(|e| format!("cannot read {}: {e}", from.display()))?;
        let path = entry.path();
        let dest = to.join(entry.file_name());
        if path.is_dir() {
            copy_dir(&path, &dest)?;
        } else {
            std::fs::copy(&path, &dest)
                .map_err(|e| format!("cannot copy {}: {e}", path.display()))?;
        }
    }
    Ok(())
}

/// What `rustup ARGS` prints on stdout ("" if it cannot run).
fn rustup_listed(args: &[&str]) -> String {
    Command::new("rustup")
        .args(args)
        .stderr(Stdio::null())
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default()
}

/// Makes sure the nightly toolchain is there (for the web build and the fuzzer).
pub fn ensure_nightly_toolchain() -> Result<(), String> {
    if !rustup_listed(&["toolchain", "list"])
        .lines()
        .any(|l| l.starts_with("nightly"))
    {
        println!("the nightly toolchain is missing; installing it");
        run_status(
            Command::new("rustup").args([
                "toolchain",
                "install",
                "nightly",
                "--profile",
                "minimal",
            ]),
            "rustup toolchain install nightly --profile minimal",
        )?;
    }
    Ok(())
}

/// Makes sure the nightly toolchain is there with `rust-src` (for `-Z build-std`) and the
/// wasm32 target.
fn ensure_nightly() -> Result<(), String> {
    ensure_nightly_toolchain()?;
    let listed = rustup_listed;
    if !listed(&["component", "list", "--toolchain", "nightly", "--installed"])
        .lines()
        .any(|l| l.starts_with("rust-src"))
    {
        println!("nightly's rust-src is missing; installing it");
        run_status(
            Command::new("rustup").args(["component", "add", "rust-src", "--toolchain", "nightly"]),
            "rustup component add rust-src --toolchain nightly",
        )?;
    }
    if !listed(&["target", "list", "--toolchain", "nightly", "--installed"])
        .lines()
        .any(|l| l.trim() == TARGET)
    {
        println!("the {TARGET} target is missing; installing it");
        run_status(
            Command::new("rustup").args(["target", "add", TARGET, "--toolchain", "nightly"]),
            "rustup target add wasm32-unknown-unknown --toolchain nightly",
        )?;
    }
    Ok(())
}

/// The wasm-bindgen CLI at [`WASM_BINDGEN_VERSION`]: the one on the PATH or in cargo's bin
/// folder, else installed with `cargo install`.
fn ensure_wasm_bindgen() -> Result<PathBuf, String> {
    let cargo_bin = env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .or_else(|| env::var_os("HOME").map(|h| PathBuf::from(h).join(".cargo")))
        .map(|home| home.join("bin/wasm-bindgen"));
    let candidates: Vec<PathBuf> = [Some(PathBuf::from("wasm-bindgen")), cargo_bin]
        .into_iter()
        .flatten()
        .collect();
    let wanted = format!("wasm-bindgen {WASM_BINDGEN_VERSION}");
    let fits = |path: &Path| {
        Command::new(path)
            .arg("--version")
            .stderr(Stdio::null())
            .output()
            .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == wanted)
    };
    if let Some(found) = candidates.iter().find(|p| fits(p)) {
        return Ok(found.clone());
    }
    println!("wasm-bindgen {WASM_BINDGEN_VERSION} is missing; installing it (about 2 minutes)");
    run_status(
        Command::new(cargo())
            .args(["install", "wasm-bindgen-cli", "--version"])
            .arg(format!("={WASM_BINDGEN_VERSION}"))
            .arg("-j2"),
        &format!("cargo install wasm-bindgen-cli --version ={WASM_BINDGEN_VERSION}"),
    )?;
    candidates
        .iter()
        .find(|p| fits(p))
        .cloned()
        .ok_or_else(|| format!("`{wanted}` is still not found after cargo install"))
}

/// A static file server on a thread, stopped when dropped.
pub struct Server {
    /// The port it listens on.
    pub port: u16,
    stop: Arc<AtomicBool>,
}

impl Server {
    /// Serves `dir` on a free port of 127.0.0.1; with `isolated`, with the headers of
    /// cross-origin isolation.
    pub fn start(dir: &Path, isolated: bool) -> Result<Server, String> {
        let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, 0))
            .map_err(|e| format!("cannot listen on 127.0.0.1: {e}"))?;
        let port = listener
            .local_addr()
            .map_err(|e| format!("no local address: {e}"))?
            .port();
        let stop = Arc::new(AtomicBool::new(false));
        let dir = dir.to_path_buf();
        let flag = Arc::clone(&stop);
        std::thread::spawn(move || serve(listener, &dir, isolated, &flag));
        Ok(Server { port, stop })
    }

    /// Its address.
    pub fn url(&self) -> String {
        format!("http://127.0.0.1:{}/", self.port)
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        // Wake the accept loop so it sees the flag.
        let _ = TcpStream::connect((Ipv4Addr::LOCALHOST, self.port));
    }
}

/// Serves `dir` until `stop` is set: GET and HEAD of static files, one thread per connection.
pub fn serve(listener: TcpListener, dir: &Path, isolated: bool, stop: &AtomicBool) {
    for stream in listener.incoming() {
        if stop.load(Ordering::SeqCst) {
            break;
        }
        let Ok(stream) = stream else { continue };
        let dir = dir.to_path_buf();
        std::thread::spawn(move || {
            let _ = handle(stream, &dir, isolated);
        });
    }
}

/// Answers the requests of one connection (keep-alive until the client closes it).
fn handle(stream: TcpStream, dir: &Path, isolated: bool) -> std::io::Result<()> {
    stream.set_read_timeout(Some(Duration::from_secs(30)))?;
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut out = stream;
    loop {
        let mut request = String::new();
        if reader.read_line(&mut request)? == 0 {
            return Ok(());
        }
        // Headers: only Content-Length matters (to skip a body) and Connection.
        let mut length = 0usize;
        let mut close = false;
        loop {
            let mut line = String::new();
            if reader.read_line(&mut line)? == 0 {
                return Ok(());
            }
            let line = line.trim_end();
            if line.is_empty() {
                break;
            }
            if let Some((name, value)) = line.split_once(':') {
                let value = value.trim();
                match name.trim().to_ascii_lowercase().as_str() {
                    "content-length" => length = value.parse().unwrap_or(0),
                    "connection" => close = value.eq_ignore_ascii_case("close"),
                    _ => {}
                }
            }
        }
        if length > 0 {
            std::io::copy(&mut (&mut reader).take(length as u64), &mut std::io::sink())?;
        }
        let mut parts = request.split_whitespace();
        let method = parts.next().unwrap_or("");
        let target = parts.next().unwrap_or("/");
        let (status, body, mime) = match method {
            "GET" | "HEAD" => match resolve(dir, target) {
                Some(path) => match std::fs::read(&path) {
                    Ok(bytes) => ("200 OK", bytes, mime_type(&path)),
                    Err(_) => ("404 Not Found", b"not found\n".to_vec(), "text/plain"),
                },
                None => ("404 Not Found", b"not found\n".to_vec(), "text/plain"),
            },
            _ => (
                "405 Method Not Allowed",
                b"only GET and HEAD\n".to_vec(),
                "text/plain",
            ),
        };
        let mut head = format!(
            "HTTP/1.1 {status}\r\nContent-Type: {mime}\r\nContent-Length: {}\r\n\
             Cache-Control: no-cache\r\nX-Content-Type-Options: nosniff\r\n",
            body.len()
        );
        if isolated {
            head.push_str(
                "Cross-Origin-Opener-Policy: same-origin\r\n\
                 Cross-Origin-Embedder-Policy: require-corp\r\n\
                 Cross-Origin-Resource-Policy: same-origin\r\n",
            );
        }
        head.push_str(if close {
            "Connection: close\r\n\r\n"
        } else {
            "Connection: keep-alive\r\n\r\n"
        });
        out.write_all(head.as_bytes())?;
        if method != "HEAD" {
            out.write_all(&body)?;
        }
        out.flush()?;
        if close {
            return Ok(());
        }
    }
}

/// The file a request target names inside `dir` (`/` is `index.html`); `None` for anything
/// that climbs out of `dir` or is not a file.
fn resolve(dir: &Path, target: &str) -> Option<PathBuf> {
    let path = target.split(['?', '#']).next().unwrap_or("/");
    let path = percent_decode(path)?;
    let mut file = dir.to_path_buf();
    for component in Path::new(path.trim_start_matches('/')).components() {
        match component {
            Component::Normal(part) => file.push(part),
            Component::CurDir => {}
            _ => return None,
        }
    }
    if file.is_dir() {
        file.push("index.html");
    }
    file.is_file().then_some(file)
}

fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = s.get(i + 1..i + 3)?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// The MIME type of a file, by its extension (browsers refuse modules and streaming
/// compilation without the right ones).
pub fn mime_type(path: &Path) -> &'static str {
    match path.extension().and_then(|e| e.to_str()).unwrap_or("") {
        "html" => "text/html; charset=utf-8",
        "js" | "mjs" => "text/javascript; charset=utf-8",
        "wasm" => "application/wasm",
        "css" => "text/css; charset=utf-8",
        "json" | "map" => "application/json",
        "png" => "image/png",
        "svg" => "image/svg+xml",
        "ico" => "image/x-icon",
        "txt" | "md" => "text/plain; charset=utf-8",
        "ts" => "text/plain; charset=utf-8",
        _ => "application/octet-stream",
    }
}

/// The browser tests' folder, its pinned npm package (playwright-core) and its test files.
const BROWSER_TESTS: &str = "tests/browser";

/// The `web` step of `cargo xtask test`: clippy on the web build, then builds the bundle,
/// serves it (cross-origin isolated, and once more without the headers), installs
/// playwright-core with npm, and runs `node --test` on tests/browser, which drives
/// /usr/bin/chromium.
pub fn browser_tests(root: &Path) -> Result<(), String> {
    ensure_node()?;
    clippy(root)?;
    build(root)?;
    let bundle = write_bundle(root)?;
    let tests = root.join(BROWSER_TESTS);
    run_status(
        Command::new("npm")
            .args(["ci", "--no-audit", "--no-fund", "--loglevel=error"])
            .current_dir(&tests),
        "npm ci (tests/browser: playwright-core)",
    )?;
    let native_hash = native_state_hash(
        root,
        &["falling_circles", "--steps", "120", "--threads", "1"],
    )?;
    let platformer_hash = native_state_hash(root, &platformer_run())?;
    let isolated = Server::start(&bundle, true)?;
    let plain = Server::start(&bundle, false)?;
    let out = target_dir(root).join("browser-tests");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    println!(
        "serving the bundle at {} (isolated) and {} (not isolated); screenshots go to {}",
        isolated.url(),
        plain.url(),
        out.display()
    );
    run_status(
        Command::new("node")
            .args(["--test", "--test-reporter=spec", "--test-concurrency=1"])
            .arg("web.test.mjs")
            .current_dir(&tests)
            .env("TUMBLE_URL", isolated.url())
            .env("TUMBLE_URL_NOT_ISOLATED", plain.url())
            .env("TUMBLE_OUT", &out)
            .env("TUMBLE_NATIVE_HASH", native_hash)
            .env("TUMBLE_PLATFORMER_HASH", platformer_hash)
            .env("TUMBLE_PLATFORMER_STEPS", PLATFORMER_STEPS.to_string()),
        "node --test tests/browser/web.test.mjs",
    )
}

/// Steps of the platformer's scripted run (its `--keys demo`) that the viewer, the page and
/// the runner take: the flag is reached before them.
pub const PLATFORMER_STEPS: u64 = 900;

/// The runner's arguments for the platformer's scripted run on one thread.
pub fn platformer_run() -> Vec<String> {
    ["platformer", "--keys", "demo", "--threads", "1", "--steps"]
        .iter()
        .map(|s| s.to_string())
        .chain([PLATFORMER_STEPS.to_string()])
        .collect()
}

/// The state hash of a native run (`tumble-bench run ARGS`): `falling_circles` after 120
/// steps on one thread, which the page must get at 1 and 2 threads, and the platformer's
/// scripted run, which the page and the viewer must get.
pub fn native_state_hash(
    root: &Path,
    args: &[impl AsRef<std::ffi::OsStr>],
) -> Result<String, String> {
    let out = Command::new(cargo())
        .args(["run", "--quiet", "-j2", "-p", "tumble-bench", "--"])
        .arg("run")
        .args(args)
        .current_dir(root)
        .output()
        .map_err(|e| format!("cannot run tumble-bench for the native state hash: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "tumble-bench run failed: {}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let json = String::from_utf8_lossy(&out.stdout);
    state_hash_of(&json).ok_or_else(|| format!("no state_hash in tumble-bench's output: {json}"))
}

/// The value of `"state_hash": "<16 hex digits>"` in a runner's JSON.
pub fn state_hash_of(json: &str) -> Option<String> {
    let rest = &json[json.find("\"state_hash\"")? + "\"state_hash\"".len()..];
    let hash: String = rest
        .trim_start_matches([' ', ':', '"'])
        .chars()
        .take_while(char::is_ascii_hexdigit)
        .collect();
    (hash.len() == 16).then_some(hash)
}

/// Node and npm: Debian's when missing (this image has NodeSource's).
fn ensure_node() -> Result<(), String> {
    if succeeds(Command::new("node").arg("--version"))
        && succeeds(Command::new("npm").arg("--version"))
    {
        return Ok(());
    }
    crate::ensure_debian_packages(&["nodejs", "npm"])?;
    if succeeds(Command::new("node").arg("--version")) {
        Ok(())
    } else {
        Err("node is still missing after installing Debian's nodejs".to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolves_files_inside_the_folder_only() {
        let dir = env::temp_dir().join(format!("xtask-web-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("pkg")).unwrap();
        std::fs::write(dir.join("index.html"), "<!doctype html>").unwrap();
        std::fs::write(dir.join("pkg/a b.wasm"), [0u8, 97, 115, 109]).unwrap();
        assert_eq!(resolve(&dir, "/"), Some(dir.join("index.html")));
        assert_eq!(resolve(&dir, "/?scene=x"), Some(dir.join("index.html")));
        assert_eq!(
            resolve(&dir, "/pkg/a%20b.wasm"),
            Some(dir.join("pkg/a b.wasm"))
        );
        assert_eq!(resolve(&dir, "/../etc/passwd"), None);
        assert_eq!(resolve(&dir, "/pkg/../../x"), None);
        assert_eq!(resolve(&dir, "/missing.js"), None);
        assert_eq!(mime_type(Path::new("x.wasm")), "application/wasm");
        assert!(mime_type(Path::new("x.js")).starts_with("text/javascript"));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn reads_the_state_hash_of_the_runners_output() {
        let json = "{\"steps\": 120,\n  \"state_hash\": \"74b329451317af4e\", \"x\": 1}";
        assert_eq!(state_hash_of(json).as_deref(), Some("74b329451317af4e"));
        assert_eq!(state_hash_of("{\"state_hash\": \"12\"}"), None);
        assert_eq!(state_hash_of("{}"), None);
    }

    #[test]
    fn serves_with_the_isolation_headers() {
        let dir = env::temp_dir().join(format!("xtask-serve-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("main.js"), "export {};").unwrap();
        let server = Server::start(&dir, true).unwrap();
        let mut stream = TcpStream::connect((Ipv4Addr::LOCALHOST, server.port)).unwrap();
        stream
            .write_all(b"GET /main.js HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n")
            .unwrap();
        let mut response = String::new();
        stream.read_to_string(&mut response).unwrap();
        assert!(response.starts_with("HTTP/1.1 200 OK"), "{response}");
        assert!(response.contains("Content-Type: text/javascript"));
        assert!(response.contains("Cross-Origin-Opener-Policy: same-origin"));
        assert!(response.contains("Cross-Origin-Embedder-Policy: require-corp"));
        assert!(response.ends_with("export {};"));
        drop(server);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
