//! `cgdem report` opened in a real headless browser (Debian's Chromium, installed by
//! `scripts/setup-browser`, which `scripts/test` runs): every figure renders with a non-zero size,
//! the summary table is there with one row per claim, the page logs no error and fetches nothing. The
//! report is built from cheap cases (force laws, two-particle checks, plastic wear) and kept,
//! with the browser's screenshot beside it, in `target/tmp/report-browser/`.
//!
//! How the page is measured: a copy of `report.html` gets a short script at the top of its `<head>`
//! that records errors (`error` events, `console.error`) and, once loaded, writes the figures' sizes,
//! the summary's rows and the resources the page fetched into a `<pre>`; `--dump-dom` prints the page
//! after that script ran. The report itself carries no script.

use std::path::{Path, PathBuf};
use std::process::Command;

const PROBE: &str = r#"<script>
window.__errors = [];
window.addEventListener('error', e => window.__errors.push(String(e.message || e.type)), true);
const __err = console.error;
console.error = (...a) => { window.__errors.push(a.map(String).join(' ')); __err(...a); };
window.addEventListener('load', () => {
  const figs = [...document.querySelectorAll('figure')].map(f => {
    const s = f.querySelector('svg');
    const r = s ? s.getBoundingClientRect() : {width: 0, height: 0};
    return [f.id, r.width, r.height];
  });
  const t = document.getElementById('summary-table');
  const out = document.createElement('pre');
  out.id = 'render-check';
  out.textContent = 'CH' + 'ECK' + JSON.stringify({
    figs,
    rows: t ? t.querySelectorAll('tr').length : 0,
    errors: window.__errors,
    resources: performance.getEntriesByType('resource').map(r => r.name),
  }) + 'CH' + 'ECK';
  document.body.appendChild(out);
});
</script>"#;

fn chromium() -> PathBuf {
    let exe = std::env::var_os("CGDEM_CHROMIUM")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("chromium"));
    match Command::new(&exe).arg("--version").output() {
        Ok(o) if o.status.success() => exe,
        _ => panic!(
            "Chromium not found ({}): run `bash scripts/setup-browser` (scripts/test does)",
            exe.display()
        ),
    }
}

/// Headless Chromium with the flags that work on these machines (no sandbox as root, no network
/// chatter), a fresh profile directory, and `args`.
fn browse(exe: &Path, profile: &Path, args: &[String]) -> std::process::Output {
    let _ = std::fs::remove_dir_all(profile);
    Command::new(exe)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(args)
        .output()
        .expect("cannot start chromium")
}

#[test]
fn the_report_renders_in_a_real_browser_without_errors() {
    let exe = chromium();
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("report-browser");
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args([
            "report",
            "--profile",
            "quick",
            "--only",
            "force-laws,two-particle,wear-impact",
            "--out",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "cgdem report failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let html_path = dir.join("report.html");
    let html = std::fs::read_to_string(&html_path).unwrap();
    let figures = html.matches("<figure").count();
    let claims = std::fs::read_to_string(dir.join("summary.csv"))
        .unwrap()
        .lines()
        .count()
        - 1;
    assert!(
        figures >= 2 && claims > 20,
        "{figures} figures, {claims} claims"
    );

    // The page as a browser lays it out, measured by the probe.
    let probed = dir.join("report-probe.html");
    std::fs::write(
        &probed,
        html.replacen("<head>", &format!("<head>\n{PROBE}"), 1),
    )
    .unwrap();
    let o = browse(
        &exe,
        &dir.join("chromium-profile"),
        &[
            "--virtual-time-budget=10000".into(),
            "--dump-dom".into(),
            format!("file://{}", probed.display()),
        ],
    );
    let dom = String::from_utf8_lossy(&o.stdout);
    let json = dom
        .split("CHECK")
        .nth(1)
        .unwrap_or_else(|| {
            panic!(
                "the probe did not run; stderr:\n{}",
                String::from_utf8_lossy(&o.stderr)
            )
        })
        .replace("&amp;", "&")
        .replace("&lt;", "<")
        .replace("&gt;", ">");
    let check: serde_json::Value = serde_json::from_str(&json).unwrap();
    eprintln!("browser check: {check}");
    let figs = check["figs"].as_array().unwrap();
    assert_eq!(figs.len(), figures, "figures laid out");
    for f in figs {
        let (w, h) = (f[1].as_f64().unwrap(), f[2].as_f64().unwrap());
        assert!(
            w > 100.0 && h > 100.0,
            "figure {} rendered at {w} x {h}",
            f[0]
        );
    }
    assert_eq!(
        check["rows"].as_u64().unwrap() as usize,
        claims + 1,
        "summary rows"
    );
    assert_eq!(
        check["errors"].as_array().unwrap().len(),
        0,
        "page errors: {}",
        check["errors"]
    );
    assert_eq!(
        check["resources"].as_array().unwrap().len(),
        0,
        "fetched: {}",
        check["resources"]
    );

    // The report itself, unmodified: a screenshot kept beside it, and no console message at all
    // (the page has no script, so any would be an error: a blocked fetch, a parse failure).
    let shot = dir.join("screenshot.png");
    let o = browse(
        &exe,
        &dir.join("chromium-profile"),
        &[
            "--window-size=1400,2200".into(),
            format!("--screenshot={}", shot.display()),
            format!("file://{}", html_path.display()),
        ],
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "screenshot failed:\n{stderr}");
    let console: Vec<&str> = stderr.lines().filter(|l| l.contains("CONSOLE")).collect();
    assert!(
        console.is_empty(),
        "the page logged:\n{}",
        console.join("\n")
    );
    let png = std::fs::read(&shot).unwrap();
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 20_000,
        "screenshot of {} bytes",
        png.len()
    );
    eprintln!("report and screenshot kept in {}", dir.display());
}
