//! Evaluates a calibration problem at given points (no solver): for measuring the cost and the noise of
//! the residuals. Usage: `probe <config.toml> <dir for the sample cache> <x1,x2,...> [<x...> ...]`
//! (x in log multipliers, one point per argument; points run one after another, the samples of each
//! side by side on PROBE_THREADS threads, default 2). Prints each point's mean residuals, their
//! standard error and every sample's residuals. Used for the noise measurements in
//! docs/calibration.md:
//! `cargo run --release -p calibrate --example probe -- cfg.toml out/dir 0,0,0,0,0 0,0,0.001,0,0`

use calibrate::Problem;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let cfg = calibrate::CalibrationConfig::from_file(std::path::Path::new(&a[1])).unwrap();
    let out = std::path::Path::new(&a[2]);
    std::fs::create_dir_all(out.join("samples")).unwrap();
    let prob = calibrate::run::problem(&cfg, Some(out)).unwrap();
    let threads = std::env::var("PROBE_THREADS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2);
    let pool = calibrate::run::pool(dem::Parallelism::Threads(threads)).unwrap();
    println!("names {:?}", prob.residual_names());
    for p in &a[3..] {
        let x: Vec<f64> = p.split(',').map(|v| v.parse().unwrap()).collect();
        let t = std::time::Instant::now();
        match pool.install(|| prob.evaluate(&x)) {
            Ok(m) => println!(
                "x {x:?} r {:?} noise {:?} samples {:?} {:.1} s",
                m.r,
                m.noise,
                m.samples,
                t.elapsed().as_secs_f64()
            ),
            Err(e) => println!("x {x:?} failed: {e} {:.1} s", t.elapsed().as_secs_f64()),
        }
    }
}
