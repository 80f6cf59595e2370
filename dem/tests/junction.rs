//! Junction shear (paper 000 section 4) on a small silica box: the rig's mechanics (the top wall slides
//! at its velocity and carries the normal load), thread-count independence, the outputs' consistency,
//! and the refusals of impossible geometries.

use dem::material::{Material, PairModel, SiMaterial};
use dem::sample::{make_sample, RelaxConfig, Sample, SampleSpec};
use dem::scenario::junction::{
    build, run, JunctionConfig, JunctionResult, JunctionShape, Monolayer,
};
use dem::{DemError, Parallelism, UnitSystem};

/// Paper 000 Table 5 silica in nano units (nm, ns, ag: MPa).
fn silica() -> Material {
    Material::from_si(&SiMaterial::table5(), UnitSystem::NANO)
}

/// A 36 x 30 x 24 nm box of the junction recipe at d0 = 6 nm, and a 1 ns run of a D = 10 nm junction.
fn small() -> (Sample, PairModel, JunctionConfig) {
    let model = PairModel::cohesive(silica());
    let cfg = JunctionConfig {
        lengths: [36.0, 30.0, 24.0],
        diameter: 10.0,
        d0: 6.0,
        duration: 1.0,
        frames: 20,
        force_samples: 200,
        dump_frames: 0,
        ..JunctionConfig::default()
    };
    let d_c = model.material.critical_diameter();
    let spec = SampleSpec::Amorphous {
        d0_over_dc: cfg.d0 / d_c,
        l_over_d0: cfg.lengths[0] / cfg.d0,
        w_over_d0: cfg.lengths[2] / cfg.d0,
        h_over_d0: Some(cfg.lengths[1] / cfg.d0),
        ds_over_d0: cfg.ds_over_d0,
        dl_over_d0: cfg.dl / cfg.d0,
        dl_over_l: None,
        seed: 3,
        insert_fraction: cfg.insert_fraction,
    };
    let sample = make_sample(
        &spec,
        &model,
        &RelaxConfig::default(),
        Parallelism::Sequential,
    )
    .unwrap();
    (sample, model, cfg)
}

fn timeless(r: &JunctionResult) -> String {
    let mut r = r.clone();
    r.wall_seconds = 0.0;
    format!("{r:?}")
}

#[test]
fn the_top_wall_slides_at_its_velocity_carries_the_load_and_threads_do_not_matter() {
    let (sample, model, cfg) = small();
    let r = run(&sample, &model, &cfg, Parallelism::Sequential, None).unwrap();
    // Velocity control: the wall moved v t (to the last step's dt).
    let t = r.steps as f64 * r.dt;
    assert!(
        (r.slide - cfg.velocity * t).abs() < 1e-9 * cfg.velocity * t,
        "slide {}",
        r.slide
    );
    assert!((t - cfg.duration).abs() <= r.dt);
    // Traction control: over the second half the sample pushes back with the applied load (the wall
    // is in mean equilibrium: sum F_y + (-p) A = m dv/dt averages to ~0).
    let late = &r.force[r.force.len() / 2..];
    let mean_fy = late.iter().map(|s| s.force[1]).sum::<f64>() / late.len() as f64;
    let load = cfg.pressure * (r.first.hi[0] - r.first.lo[0]) * (r.first.hi[2] - r.first.lo[2]);
    assert!(
        (mean_fy - load).abs() < 0.1 * load,
        "mean F_y {mean_fy} against the load {load}"
    );
    // The frames the classifier read are the members' unwrapped paths: continuous along x.
    assert_eq!(r.frames.frames.len(), cfg.frames as usize + 1);
    assert_eq!(r.verdict.turn_history.len(), r.frames.frames.len());
    assert_eq!(r.frames.members.len(), r.junction_members);
    for w in r.frames.frames.windows(2) {
        for (a, b) in w[0].iter().zip(&w[1]) {
            assert!((b[0] - a[0]).abs() < 0.25 * (r.first.hi[0] - r.first.lo[0]));
        }
    }
    assert!(r.verdict.detachment.is_some());
    // Bit-identical on two threads.
    let two = run(&sample, &model, &cfg, Parallelism::Threads(2), None).unwrap();
    assert_eq!(timeless(&two), timeless(&r));
}

#[test]
fn a_top_wall_sinking_further_than_the_guard_allows_stops_the_run_as_a_collapse() {
    let (sample, model, cfg) = small();
    // At the default limit (one junction height) the run goes through: the wall settles under the
    // load and the junction flattens, by less than H.
    let r = run(&sample, &model, &cfg, Parallelism::Sequential, None).unwrap();
    let descent = r.largest_wall_descent();
    assert!(
        descent > 0.0 && descent < cfg.height(),
        "descent {descent}, H {}",
        cfg.height()
    );
    // The default is not written, so the keys of runs made before the guard stay.
    let written = toml::to_string(&cfg).unwrap();
    assert!(!written.contains("max_descent"), "{written}");
    // A limit below what this wall descends stops the run with the reason, before its end.
    let tight = JunctionConfig {
        max_descent_over_height: 0.5 * descent / cfg.height(),
        ..cfg.clone()
    };
    assert!(toml::to_string(&tight)
        .unwrap()
        .contains("max_descent_over_height"));
    match run(&sample, &model, &tight, Parallelism::Sequential, None) {
        Err(DemError::MaterialCollapsed { step, reason }) => {
            assert!(step < r.steps, "stopped at {step} of {}", r.steps);
            assert!(
                reason.contains("descended") && reason.contains("no verdict"),
                "{reason}"
            );
        }
        other => panic!("expected a collapse, got {other:?}"),
    }
}

#[test]
fn the_neighbour_skin_changes_nothing_but_round_off() {
    // A larger skin only adds pairs beyond reach, whose force is exactly zero; what moves is where
    // the rebuilds fall (positions are wrapped there), a round-off effect. Over 1 ns of shear the
    // wall force and the members' paths of skins 0.05 and 0.3 stay within 1e-9 of each other.
    let (sample, model, cfg) = small();
    let thin = run(
        &sample,
        &model,
        &JunctionConfig {
            skin_fraction: 0.05,
            ..cfg.clone()
        },
        Parallelism::Sequential,
        None,
    )
    .unwrap();
    let wide = run(
        &sample,
        &model,
        &JunctionConfig {
            skin_fraction: 0.3,
            ..cfg.clone()
        },
        Parallelism::Sequential,
        None,
    )
    .unwrap();
    assert_eq!(thin.outcome, wide.outcome);
    assert_eq!(thin.force.len(), wide.force.len());
    let scale = thin
        .force
        .iter()
        .map(|s| s.force[1].abs())
        .fold(0.0, f64::max);
    for (a, b) in thin.force.iter().zip(&wide.force) {
        for k in 0..3 {
            assert!(
                (a.force[k] - b.force[k]).abs() <= 1e-9 * scale,
                "force {k}: {} against {}",
                a.force[k],
                b.force[k]
            );
        }
    }
    for (fa, fb) in thin.frames.frames.iter().zip(&wide.frames.frames) {
        for (a, b) in fa.iter().zip(fb) {
            for k in 0..3 {
                assert!(
                    (a[k] - b[k]).abs() <= 1e-9 * cfg.d0,
                    "path {a:?} against {b:?}"
                );
            }
        }
    }
    assert!((thin.verdict.turn - wide.verdict.turn).abs() < 1e-9);
    // ... and the skin did reach the engine: the rebuilds fell on other steps, so the bits differ.
    assert_ne!(timeless(&thin), timeless(&wide));
}

#[test]
fn impossible_geometries_are_refused_with_the_reason() {
    let (sample, model, cfg) = small();
    let refused = |c: JunctionConfig, needle: &str| {
        let e = run(&sample, &model, &c, Parallelism::Sequential, None).unwrap_err();
        assert!(
            matches!(e, DemError::InvalidConfig(_)) && e.to_string().contains(needle),
            "{needle}: {e}"
        );
    };
    // A ridge has to fit the sliding length (36 nm), a column the width (24 nm) too.
    refused(
        JunctionConfig {
            diameter: 40.0,
            ..cfg.clone()
        },
        "does not fit the box",
    );
    refused(
        JunctionConfig {
            diameter: 30.0,
            shape: JunctionShape::Column,
            ..cfg.clone()
        },
        "does not fit the box",
    );
    // A monolayer's junction is the MD junction's strip: the column.
    refused(
        JunctionConfig {
            monolayer: Some(Monolayer::default()),
            ..cfg.clone()
        },
        "set shape = \"column\"",
    );
    refused(
        JunctionConfig {
            wall_thickness_over_d0: 2.0,
            ..cfg.clone()
        },
        "walls would cut the junction",
    );
    refused(
        JunctionConfig {
            diameter: 8.0,
            ..cfg.clone()
        },
        "below 1.5 d0",
    );
    refused(
        JunctionConfig {
            velocity: f64::NAN,
            ..cfg.clone()
        },
        "velocity",
    );
    refused(
        JunctionConfig {
            frames: 1,
            ..cfg.clone()
        },
        "frames",
    );
    // Carving alone: the same checks, and a junction that holds no particle centre is an error too.
    let thin = JunctionConfig {
        height_over_diameter: 0.01,
        ..cfg.clone()
    };
    let e = build(&sample, &thin).unwrap_err();
    assert!(e.to_string().contains("no particle centre"), "{e}");
}
