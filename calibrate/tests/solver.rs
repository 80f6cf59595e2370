//! The executor and the Levenberg-Marquardt step on analytic least-squares problems with known minima:
//! convergence, finite differences vs analytic Jacobian, failed evaluations, and resume bit for bit.

use std::sync::atomic::{AtomicUsize, Ordering};

use calibrate::{
    CalibrateError, Checkpoint, EvalFailure, Evaluation, Executor, Problem, Settings, Status,
};

/// Fit y = a exp(b t) to exact data from (a, b) = (2, -0.5): x = (ln a, b), minimum residual 0.
struct ExpFit {
    analytic: bool,
    /// Evaluations with x0 > this fail (a "collapsed sample" region).
    fail_above: f64,
    calls: AtomicUsize,
}

impl ExpFit {
    fn new(analytic: bool) -> Self {
        ExpFit {
            analytic,
            fail_above: f64::INFINITY,
            calls: AtomicUsize::new(0),
        }
    }
    fn ts() -> impl Iterator<Item = f64> {
        (0..8).map(|i| 0.5 * i as f64)
    }
}

impl Problem for ExpFit {
    fn dim(&self) -> usize {
        2
    }
    fn residual_names(&self) -> Vec<String> {
        Self::ts().map(|t| format!("t{t}")).collect()
    }
    fn residuals(&self, x: &[f64]) -> Evaluation {
        self.calls.fetch_add(1, Ordering::SeqCst);
        if x[0] > self.fail_above {
            return Err(EvalFailure("collapsed".into()));
        }
        Ok(Self::ts()
            .map(|t| x[0].exp() * (x[1] * t).exp() - 2.0 * (-0.5 * t).exp())
            .collect())
    }
    fn jacobian(&self, x: &[f64]) -> Option<Vec<Vec<f64>>> {
        self.analytic.then(|| {
            Self::ts()
                .map(|t| {
                    let v = x[0].exp() * (x[1] * t).exp();
                    vec![v, t * v]
                })
                .collect()
        })
    }
}

fn settings() -> Settings {
    Settings {
        tolerance: 1e-10,
        max_iterations: 100,
        fd_step: 1e-6,
        min_step: 1e-14,
        ..Settings::default()
    }
}

fn assert_at_minimum(cp: &Checkpoint, tol: f64) {
    assert_eq!(cp.state.status, Status::Converged, "{:?}", cp.state.status);
    assert!((cp.state.x[0] - 2f64.ln()).abs() < tol, "{:?}", cp.state.x);
    assert!((cp.state.x[1] + 0.5).abs() < tol, "{:?}", cp.state.x);
}

#[test]
fn converges_to_the_known_minimum_with_analytic_and_fd_jacobians() {
    for analytic in [true, false] {
        let p = ExpFit::new(analytic);
        let cp = Executor::new(&p, vec![0.0, 0.3], settings(), "exp")
            .run()
            .unwrap();
        assert_at_minimum(&cp, 1e-8);
        // Every accepted step lowered the cost; the start was far off.
        assert!(0.5 * cp.r0.iter().map(|r| r * r).sum::<f64>() > 1.0);
        for rec in cp.history.iter().filter(|r| r.accepted) {
            assert!(rec.cost_trial.unwrap() < rec.cost);
        }
    }
}

#[test]
fn rosenbrock_valley_is_followed_to_its_minimum() {
    struct Rosen;
    impl Problem for Rosen {
        fn dim(&self) -> usize {
            2
        }
        fn residual_names(&self) -> Vec<String> {
            vec!["a".into(), "b".into()]
        }
        fn residuals(&self, x: &[f64]) -> Evaluation {
            Ok(vec![10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]])
        }
    }
    let s = Settings {
        max_step: 10.0,
        ..settings()
    };
    let cp = Executor::new(&Rosen, vec![-1.2, 1.0], s, "rosen")
        .run()
        .unwrap();
    assert_eq!(cp.state.status, Status::Converged);
    assert!((cp.state.x[0] - 1.0).abs() < 1e-9 && (cp.state.x[1] - 1.0).abs() < 1e-9);
}

#[test]
fn failed_evaluations_are_recorded_and_rejected_not_fatal() {
    // The minimum (ln 2 = 0.69) lies just below the failing region; big first steps overshoot into it.
    let mut p = ExpFit::new(true);
    p.fail_above = 0.75;
    let s = Settings {
        max_step: 2.0,
        ..settings()
    };
    let cp = Executor::new(&p, vec![-2.0, 0.0], s, "exp-fail")
        .run()
        .unwrap();
    assert_at_minimum(&cp, 1e-8);
    let failed: Vec<_> = cp.history.iter().filter(|r| r.failure.is_some()).collect();
    assert!(
        !failed.is_empty(),
        "the test should provoke a failed evaluation"
    );
    assert!(failed.iter().all(|r| !r.accepted && r.r_trial.is_none()));
}

#[test]
fn a_failing_first_guess_is_an_error() {
    let mut p = ExpFit::new(true);
    p.fail_above = -1.0;
    let e = Executor::new(&p, vec![0.0, 0.0], settings(), "x")
        .run()
        .unwrap_err();
    assert!(matches!(e, CalibrateError::StartFailed(_)), "{e}");
}

#[test]
fn a_resumed_run_adds_its_wall_time_to_what_the_checkpoint_recorded() {
    let dir = std::env::temp_dir().join(format!("calibrate-wall-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let p = ExpFit::new(false);
    let s = Settings {
        fd_step: 1e-4,
        ..settings()
    };
    let part = Executor::new(&p, vec![0.0, 0.3], s, "exp")
        .checkpoint_dir(&dir)
        .stop_after(2)
        .run()
        .unwrap();
    assert!(part.state.wall_seconds > 0.0);
    // As if the first process had run for 1000 s before its kill.
    let path = dir.join("checkpoint.json");
    let mut cp: Checkpoint = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    cp.state.wall_seconds = 1000.0;
    std::fs::write(&path, serde_json::to_vec(&cp).unwrap()).unwrap();
    let t = std::time::Instant::now();
    let done = Executor::new(&p, vec![0.0, 0.3], s, "exp")
        .checkpoint_dir(&dir)
        .run()
        .unwrap();
    let own = t.elapsed().as_secs_f64();
    assert!(done.history.len() > 2);
    let resumed = &done.history[2..];
    assert!(resumed.iter().all(|r| r.seconds >= 1000.0), "{resumed:?}");
    assert!(resumed.windows(2).all(|w| w[0].seconds <= w[1].seconds));
    let w = done.state.wall_seconds;
    assert!(
        (1000.0..=1000.0 + own).contains(&w),
        "{w} s after 1000 + {own} s"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_killed_run_resumes_to_the_same_result_bit_for_bit_without_redoing_work() {
    let tmp = std::env::temp_dir().join(format!("calibrate-resume-{}", std::process::id()));
    let (a, b) = (tmp.join("a"), tmp.join("b"));
    let _ = std::fs::remove_dir_all(&tmp);
    let s = Settings {
        fd_step: 1e-4,
        ..settings()
    };
    let whole = ExpFit::new(false);
    let full = Executor::new(&whole, vec![0.0, 0.3], s, "exp")
        .checkpoint_dir(&a)
        .run()
        .unwrap();
    assert_at_minimum(&full, 1e-6);

    let first = ExpFit::new(false);
    let part = Executor::new(&first, vec![0.0, 0.3], s, "exp")
        .checkpoint_dir(&b)
        .stop_after(2)
        .run()
        .unwrap();
    assert_eq!(part.state.status, Status::Running);
    assert_eq!(part.state.iteration, 2);
    let second = ExpFit::new(false);
    let resumed = Executor::new(&second, vec![0.0, 0.3], s, "exp")
        .checkpoint_dir(&b)
        .run()
        .unwrap();
    assert_eq!(
        resumed.clone().without_times(),
        full.clone().without_times()
    );
    for (p, q) in resumed.state.x.iter().zip(&full.state.x) {
        assert_eq!(p.to_bits(), q.to_bits());
    }
    // Nothing done before the "kill" is redone: the two halves evaluate as often as the whole run.
    let (n1, n2, n) = (
        first.calls.load(Ordering::SeqCst),
        second.calls.load(Ordering::SeqCst),
        whole.calls.load(Ordering::SeqCst),
    );
    assert_eq!(n1 + n2, n, "{n1} + {n2} evaluations vs {n}");
    // A rerun of a finished calibration evaluates nothing.
    let third = ExpFit::new(false);
    let again = Executor::new(&third, vec![0.0, 0.3], s, "exp")
        .checkpoint_dir(&b)
        .run()
        .unwrap();
    assert_eq!(third.calls.load(Ordering::SeqCst), 0);
    assert_eq!(again.without_times(), full.clone().without_times());
    // A run stopped by its budget continues when the budget grows, to the same end point.
    let c = tmp.join("c");
    let small = Settings {
        max_iterations: 2,
        ..s
    };
    let stopped = Executor::new(&third, vec![0.0, 0.3], small, "exp")
        .checkpoint_dir(&c)
        .run()
        .unwrap();
    assert_eq!(stopped.state.status, Status::MaxIterations);
    let more = Executor::new(&third, vec![0.0, 0.3], s, "exp")
        .checkpoint_dir(&c)
        .run()
        .unwrap();
    assert_eq!(more.without_times(), full.clone().without_times());
    // Other inputs refuse the checkpoint instead of mixing two calibrations.
    let e = Executor::new(&third, vec![0.1, 0.3], s, "exp")
        .checkpoint_dir(&b)
        .run()
        .unwrap_err();
    assert!(matches!(e, CalibrateError::ForeignCheckpoint { .. }), "{e}");
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn underdetermined_problems_take_minimum_norm_like_steps() {
    // One residual x0 + x1 - 2 in two unknowns: any point on the line is a minimum; from the origin,
    // the damped steps stay on the symmetric (minimum-norm) path x0 = x1 = 1.
    struct Line;
    impl Problem for Line {
        fn dim(&self) -> usize {
            2
        }
        fn residual_names(&self) -> Vec<String> {
            vec!["line".into()]
        }
        fn residuals(&self, x: &[f64]) -> Evaluation {
            Ok(vec![x[0] + x[1] - 2.0])
        }
        fn jacobian(&self, _x: &[f64]) -> Option<Vec<Vec<f64>>> {
            Some(vec![vec![1.0, 1.0]])
        }
    }
    let s = Settings {
        max_step: 10.0,
        ..settings()
    };
    let cp = Executor::new(&Line, vec![0.0, 0.0], s, "line")
        .run()
        .unwrap();
    assert_eq!(cp.state.status, Status::Converged);
    assert!((cp.state.x[0] - 1.0).abs() < 1e-9 && (cp.state.x[1] - 1.0).abs() < 1e-9);
}

/// Noisy responses (issue 5, amorphous samples): a rough problem where a small forward difference
/// is dominated by the noise. Broyden updates and central differences reach the minimum, and a
/// Broyden run killed midway resumes to the same bits.
struct Rough {
    calls: AtomicUsize,
}

impl Problem for Rough {
    fn dim(&self) -> usize {
        2
    }
    fn residual_names(&self) -> Vec<String> {
        vec!["a".into(), "b".into(), "c".into()]
    }
    fn residuals(&self, x: &[f64]) -> Evaluation {
        self.calls.fetch_add(1, Ordering::SeqCst);
        // Deterministic "noise" of amplitude 1e-3 that changes on a scale of 1e-3 in x.
        let n = |v: f64| 1e-3 * (v * 7.0e3).sin();
        Ok(vec![
            x[0].exp() - 1.2 + n(x[0] + x[1]),
            (x[0] + x[1]).exp() - 0.9 + n(x[1]),
            0.3 * (x[1] - x[0]) - 0.3 * (0.9f64.ln() - 2.0 * 1.2f64.ln()) + n(x[0] - x[1]),
        ])
    }
}

#[test]
fn broyden_and_central_differences_reach_the_noise_floor_with_fewer_evaluations() {
    let noisy = Settings {
        tolerance: 5e-3,
        max_iterations: 40,
        fd_step: 0.1,
        ..Settings::default()
    };
    let run = |s: Settings| {
        let p = Rough {
            calls: AtomicUsize::new(0),
        };
        let cp = Executor::new(&p, vec![0.0, 0.0], s, "rough").run().unwrap();
        (cp, p.calls.load(Ordering::SeqCst))
    };
    let (fd, n_fd) = run(noisy);
    let (br, n_br) = run(Settings {
        broyden: true,
        ..noisy
    });
    let (ce, _) = run(Settings {
        central: true,
        ..noisy
    });
    for cp in [&fd, &br, &ce] {
        assert_eq!(
            cp.state.status,
            Status::Converged,
            "{:?}",
            cp.history.last()
        );
    }
    assert!(
        n_br <= n_fd,
        "Broyden {n_br} evaluations vs forward differences {n_fd}"
    );
    assert_eq!(br.state.evaluations, n_br);

    // Killed after one iteration and resumed: the same bits as the uninterrupted Broyden run.
    let tmp = std::env::temp_dir().join(format!("calibrate-broyden-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let s = Settings {
        broyden: true,
        ..noisy
    };
    let p = Rough {
        calls: AtomicUsize::new(0),
    };
    let part = Executor::new(&p, vec![0.0, 0.0], s, "rough")
        .checkpoint_dir(&tmp)
        .stop_after(1)
        .run()
        .unwrap();
    assert_eq!(part.state.status, Status::Running);
    let resumed = Executor::new(&p, vec![0.0, 0.0], s, "rough")
        .checkpoint_dir(&tmp)
        .run()
        .unwrap();
    assert_eq!(resumed.without_times(), br.without_times());
    let _ = std::fs::remove_dir_all(&tmp);
}

fn trust_region(s: Settings) -> Settings {
    Settings {
        method: calibrate::Method::TrustRegion,
        radius: 0.3,
        min_radius: 1e-6,
        max_step: 2.0,
        ..s
    }
}

#[test]
fn the_trust_region_reaches_the_known_minima() {
    // The exponential fit, from a start far off, with and without a failing region beyond the
    // minimum (failed trials shrink the region instead of stopping the run).
    for fail_above in [f64::INFINITY, 0.75] {
        let mut p = ExpFit::new(false);
        p.fail_above = fail_above;
        let cp = Executor::new(&p, vec![-1.0, 0.3], trust_region(settings()), "exp-tr")
            .run()
            .unwrap();
        assert_at_minimum(&cp, 1e-7);
        for rec in cp.history.iter().filter(|r| r.accepted) {
            assert!(rec.cost_trial.unwrap() < rec.cost);
        }
    }
    // The underdetermined line: any point of it is a minimum.
    struct Line;
    impl Problem for Line {
        fn dim(&self) -> usize {
            2
        }
        fn residual_names(&self) -> Vec<String> {
            vec!["line".into()]
        }
        fn residuals(&self, x: &[f64]) -> Evaluation {
            Ok(vec![x[0] + x[1] - 2.0])
        }
    }
    let cp = Executor::new(&Line, vec![0.0, 0.0], trust_region(settings()), "line-tr")
        .run()
        .unwrap();
    assert_eq!(cp.state.status, Status::Converged);
    assert!((cp.state.x[0] + cp.state.x[1] - 2.0).abs() < 1e-9);
}

/// The rough problem of the Broyden test, with its noise *reported* as a sampled problem does: the
/// trust region never differences over less than noise_factor times the noise, reaches the noise
/// floor, and a run stopped after two iterations resumes to the same bits.
struct Sampled {
    noise: f64,
    calls: AtomicUsize,
}

impl Problem for Sampled {
    fn dim(&self) -> usize {
        2
    }
    fn residual_names(&self) -> Vec<String> {
        vec!["a".into(), "b".into(), "c".into()]
    }
    fn residuals(&self, x: &[f64]) -> Evaluation {
        Rough {
            calls: AtomicUsize::new(0),
        }
        .residuals(x)
    }
    fn evaluate(&self, x: &[f64]) -> Result<calibrate::Measured, EvalFailure> {
        self.calls.fetch_add(1, Ordering::SeqCst);
        let r = self.residuals(x)?;
        Ok(calibrate::Measured {
            noise: vec![self.noise; r.len()],
            r,
            samples: Vec::new(),
        })
    }
}

#[test]
fn the_trust_region_honours_the_reported_noise_and_resumes_bit_for_bit() {
    let s = Settings {
        method: calibrate::Method::TrustRegion,
        tolerance: 5e-3,
        max_iterations: 40,
        ..Settings::default()
    };
    let p = Sampled {
        noise: 0.02,
        calls: AtomicUsize::new(0),
    };
    let cp = Executor::new(&p, vec![0.0, 0.0], s, "sampled")
        .run()
        .unwrap();
    assert_eq!(
        cp.state.status,
        Status::Converged,
        "{:?}",
        cp.history.last()
    );
    // Every trust radius used is at least 3 x 0.02 (the recorded radius after each iteration).
    assert!(
        cp.history.iter().all(|r| r.lambda >= 0.06 - 1e-12),
        "{:?}",
        cp.history.iter().map(|r| r.lambda).collect::<Vec<_>>()
    );
    // The finite-difference step of LM obeys the same floor: its first Jacobian points lie 0.06 away.
    let lm = Settings {
        method: calibrate::Method::LevenbergMarquardt,
        max_iterations: 1,
        ..s
    };
    let cpl = Executor::new(&p, vec![0.0, 0.0], lm, "sampled-lm")
        .run()
        .unwrap();
    assert_eq!(cpl.state.evaluations, 1 + 2 + 1);
    let tmp = std::env::temp_dir().join(format!("calibrate-noise-fd-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    Executor::new(&p, vec![0.0, 0.0], lm, "sampled-lm")
        .checkpoint_dir(&tmp)
        .run()
        .unwrap();
    let mut fd_points: Vec<Vec<f64>> = std::fs::read_dir(tmp.join("evals"))
        .unwrap()
        .map(|f| {
            let v: serde_json::Value =
                serde_json::from_slice(&std::fs::read(f.unwrap().path()).unwrap()).unwrap();
            serde_json::from_value(v["x"].clone()).unwrap()
        })
        .collect();
    fd_points.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert!(
        fd_points.contains(&vec![0.06, 0.0]) && fd_points.contains(&vec![0.0, 0.06]),
        "{fd_points:?}"
    );
    let _ = std::fs::remove_dir_all(&tmp);

    let tmp = std::env::temp_dir().join(format!("calibrate-tr-resume-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let part = Executor::new(&p, vec![0.0, 0.0], s, "sampled")
        .checkpoint_dir(&tmp)
        .stop_after(2)
        .run()
        .unwrap();
    assert_eq!(part.state.status, Status::Running);
    let q = Sampled {
        noise: 0.02,
        calls: AtomicUsize::new(0),
    };
    let resumed = Executor::new(&q, vec![0.0, 0.0], s, "sampled")
        .checkpoint_dir(&tmp)
        .run()
        .unwrap();
    assert_eq!(resumed.without_times(), cp.without_times());
    let _ = std::fs::remove_dir_all(&tmp);
}
