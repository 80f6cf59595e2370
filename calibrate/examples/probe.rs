//! Evaluates a calibration problem at given points (no solver): for measuring the cost and the noise of
//! the residuals. Usage: `probe <config.toml> <dir with sample.json> <x1,x2,...> [<x...> ...]`
//! (x in log multipliers, one point per argument; points run one after another). With PROBE_ELASTIC
//! set, only the elastic test runs and its details (steps, strains) are printed. Used for the noise
//! measurements in docs/calibration.md:
//! `cargo run --release -p calibrate --example probe -- cfg.toml out/dir 0,0,0,0,0 0,0,0.001,0,0`

use calibrate::Problem;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let cfg =
        calibrate::CalibrationConfig::from_toml(&std::fs::read_to_string(&a[1]).unwrap()).unwrap();
    let out = std::path::Path::new(&a[2]);
    std::fs::create_dir_all(out).unwrap();
    let prob = calibrate::run::problem(&cfg, out, dem::Parallelism::Sequential).unwrap();
    println!("names {:?}", prob.residual_names());
    for p in &a[3..] {
        let x: Vec<f64> = p.split(',').map(|v| v.parse().unwrap()).collect();
        let t = std::time::Instant::now();
        let r = prob.residuals(&x);
        println!("x {x:?} r {r:?} {:.1} s", t.elapsed().as_secs_f64());
    }
}
