//! A scratch interrupted (Ctrl-C) continues from its progress file to the same numbers, to the last
//! bit, as an uninterrupted one, and a finished scratch removes its file. One test in this binary:
//! the interrupt flag is process-wide.

use std::time::Duration;

use dem::io::progress::ProgressFile;
use dem::scenario::plastic::{run_scratch_load, ScratchConfig};
use dem::DemError;

#[test]
fn an_interrupted_scratch_resumes_bit_identically() {
    let cfg: ScratchConfig = toml::from_str(
        "[indent]\nspeed = 0.02\nloads = [3000.0]\n[slide]\nspeed = 0.2\nduration = 0.02\n",
    )
    .unwrap();
    let whole = run_scratch_load(&cfg, 3000.0, None).unwrap();

    let dir = std::env::temp_dir().join(format!("cgdem_scratch_resume_{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let file = ProgressFile {
        path: dir.join("progress.json"),
        every: Duration::ZERO,
    };
    // Interrupt once the second periodic save exists: the run then stops wherever it has reached,
    // in the indentation or in the slide.
    let watched = file.path.clone();
    let watcher = std::thread::spawn(move || {
        let mut seen = None;
        loop {
            let m = std::fs::metadata(&watched).and_then(|m| m.modified()).ok();
            if let (Some(a), Some(b)) = (seen, m) {
                if a != b {
                    break;
                }
            }
            if seen.is_none() {
                seen = m;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        dem::interrupt::request();
    });
    let cut = run_scratch_load(&cfg, 3000.0, Some(&file));
    watcher.join().unwrap();
    dem::interrupt::clear();
    let step = match cut {
        Err(DemError::Interrupted { step }) => step,
        other => panic!("expected an interrupt, got {other:?}"),
    };
    assert!(
        step > 0 && step < whole.steps,
        "cut at step {step} of {}",
        whole.steps
    );
    assert!(file.path.exists(), "the interrupt saved the progress");
    let resumed = run_scratch_load(&cfg, 3000.0, Some(&file)).unwrap();
    println!(
        "cut at step {step} of {}: wear/d {:e} / {:e}",
        whole.steps, whole.wear_per_distance, resumed.wear_per_distance
    );
    assert_eq!(
        serde_json::to_string(&resumed).unwrap(),
        serde_json::to_string(&whole).unwrap(),
        "resumed run differs"
    );
    assert!(
        !file.path.exists(),
        "a finished scratch removes its progress file"
    );
    std::fs::remove_dir_all(&dir).ok();
}
