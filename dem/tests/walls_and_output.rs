//! Rigid walls under prescribed force and traction, the virial stress of a group, and the dump format.

mod common;

use common::*;
use dem::io::dump::write_frame;
use dem::{
    AxisControl, Group, Material, PairModel, Parallelism, RigidMotion, RunConfig, SimBox,
    Simulation, Vec3,
};

#[test]
fn force_controlled_wall_accelerates_as_one_body() {
    // Two spheres far apart in one rigid group, pushed by an external force along z only.
    let mut p = pair_of(1.0, 10.0);
    p.group = vec![1, 1];
    let f = 3.0;
    let motion = RigidMotion {
        axes: [
            AxisControl::Velocity(0.5),
            AxisControl::Force(0.0),
            AxisControl::Force(f),
        ],
        velocity: Vec3::zeros(),
    };
    let groups = vec![Group::free("all"), Group::rigid("wall", motion)];
    let cfg = RunConfig {
        track_energy: true,
        ..RunConfig::default()
    };
    let mut s = Simulation::new(
        p,
        open_box(1e6),
        PairModel::cohesive(Material::table4(0.1)),
        groups,
        cfg,
        Parallelism::Sequential,
    )
    .unwrap();
    let m: f64 = s.particles.mass.iter().sum();
    s.run(1000).unwrap();
    let t = s.time();
    let v = s.particles.vel[1];
    assert!(
        (v.z - f / m * t).abs() < 1e-12 * (f / m * t),
        "v_z {} vs F t / M {}",
        v.z,
        f / m * t
    );
    assert_eq!(v.x, 0.5);
    assert_eq!(s.particles.vel[0], v, "both members move together");
    // Work of the outside force: sum of F v_{n+1} dt = F dt^2 / M * n(n+1)/2.
    let dt = s.dt();
    let n = 1000.0;
    let work = f * f * dt * dt / m * n * (n + 1.0) / 2.0;
    assert!((s.energy().wall_work - work).abs() < 1e-9 * work);
}

#[test]
fn a_ramped_wall_reaches_its_velocity_at_its_acceleration_and_books_the_work() {
    // Two spheres far apart in one rigid group (no pair force), ramped from rest along x to 0.5 in
    // 100 steps and along y to -0.2 in 50: v = a n dt each step until the target, then the target.
    let mut p = pair_of(1.0, 10.0);
    p.group = vec![1, 1];
    let cfg = RunConfig {
        track_energy: true,
        ..RunConfig::default()
    };
    let build = |axes: [AxisControl; 3]| {
        let mut p = p.clone();
        p.group = vec![1, 1];
        let motion = RigidMotion {
            axes,
            velocity: Vec3::zeros(),
        };
        Simulation::new(
            p,
            open_box(1e6),
            PairModel::cohesive(Material::table4(0.1)),
            vec![Group::free("all"), Group::rigid("wall", motion)],
            cfg,
            Parallelism::Sequential,
        )
    };
    let dt = build([AxisControl::Velocity(0.0); 3]).unwrap().dt();
    let (ax, ay) = (0.5 / (100.0 * dt), 0.2 / (50.0 * dt));
    let mut s = build([
        AxisControl::Ramp {
            to: 0.5,
            acceleration: ax,
        },
        AxisControl::Ramp {
            to: -0.2,
            acceleration: ay,
        },
        AxisControl::Velocity(0.0),
    ])
    .unwrap();
    s.run(10).unwrap();
    let v = s.particles.vel[1];
    assert!((v.x - 0.05).abs() < 1e-12, "v_x {} after 10 steps", v.x);
    assert!((v.y + 0.04).abs() < 1e-12, "v_y {} after 10 steps", v.y);
    s.run(100).unwrap();
    let v = s.particles.vel[1];
    assert_eq!((v.x, v.y), (0.5, -0.2), "the ramps stop at their targets");
    assert_eq!(s.particles.vel[0], v, "both members move together");
    // No pair force: the outside work is the body's kinetic energy M (v_x^2 + v_y^2) / 2, up to the
    // first-order booking F v_{n+1} dt (an excess of M a v_target dt / 2 per axis).
    let m: f64 = s.particles.mass.iter().sum();
    let ke = 0.5 * m * (v.x * v.x + v.y * v.y);
    let w = s.energy().wall_work;
    let excess = 0.5 * m * (ax * 0.5 + ay * 0.2) * dt;
    assert!(
        w >= ke && w - ke <= excess * (1.0 + 1e-9),
        "work {w} against {ke} + {excess}"
    );
    // A ramp needs a positive acceleration: a clear error, not a wall that never moves.
    let Err(e) = build([
        AxisControl::Ramp {
            to: 0.5,
            acceleration: 0.0,
        },
        AxisControl::Velocity(0.0),
        AxisControl::Velocity(0.0),
    ]) else {
        panic!("a zero acceleration is refused");
    };
    assert!(e.to_string().contains("acceleration"), "{e}");
}

#[test]
fn pressure_wall_on_a_column_reaches_its_traction() {
    // A column of spheres between a frozen floor and a traction-controlled lid settles where the
    // virial stress of the free spheres balances the traction.
    let d = 90.0;
    let (mut p, _) = dem::sample::hcp::hcp_lattice(4, 4, 8, d, 1.0, [true, true, false]).unwrap();
    let zs: Vec<f64> = p.pos.iter().map(|x| x.z).collect();
    let (zmin, zmax) = zs
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &z| (a.min(z), b.max(z)));
    for i in 0..p.len() {
        p.group[i] = if zs[i] < zmin + 1.0 {
            1
        } else if zs[i] > zmax - 1.0 {
            2
        } else {
            0
        };
    }
    let lx = 4.0 * d;
    let ly = 4.0 * d * 3f64.sqrt() / 2.0;
    let bx = SimBox::new(
        Vec3::new(0.0, 0.0, zmin - d),
        Vec3::new(lx, ly, zmax + 4.0 * d),
        [true, true, false],
    )
    .unwrap();
    let mat = Material::table4(0.1);
    let traction = -0.005 * mat.young_modulus;
    let lid = RigidMotion {
        axes: [
            AxisControl::Velocity(0.0),
            AxisControl::Velocity(0.0),
            AxisControl::Traction(traction),
        ],
        velocity: Vec3::zeros(),
    };
    let groups = vec![
        Group::free("all"),
        Group::rigid("floor", RigidMotion::frozen()),
        Group::rigid("lid", lid),
    ];
    let cfg = RunConfig {
        global_damping: 0.2,
        ..RunConfig::default()
    };
    let mut s = Simulation::new(
        p,
        bx,
        PairModel::cohesive(mat),
        groups,
        cfg,
        Parallelism::Sequential,
    )
    .unwrap();
    s.run(6000).unwrap();
    s.request_virial();
    s.step().unwrap();
    // Stress of the free spheres over the volume they span: between the wall layers.
    let free = |i: usize| s.particles.group[i] == 0;
    let z = |g: u32| {
        s.particles
            .pos
            .iter()
            .zip(&s.particles.group)
            .filter(|(_, &k)| k == g)
            .map(|(x, _)| x.z)
            .sum::<f64>()
            / s.particles.group.iter().filter(|&&k| k == g).count() as f64
    };
    let height = z(2) - z(1);
    let n_free = (0..s.particles.len()).filter(|&i| free(i)).count() as f64;
    let layers = n_free / 16.0;
    let volume = lx * ly * height * layers / (layers + 1.0);
    let sigma = s.virial_stress(Some(&free), Some(volume));
    assert!(
        ((sigma[(2, 2)] - traction) / traction).abs() < 0.05,
        "sigma_zz {} vs traction {traction}",
        sigma[(2, 2)]
    );
}

#[test]
fn dump_is_a_lammps_text_frame() {
    let mut p = pair_of(1.5, 0.0);
    p.vel[1] = Vec3::new(0.25, -0.5, 1.0);
    let s = sim(
        p,
        open_box(100.0),
        PairModel::cohesive(Material::table4(0.1)),
        RunConfig::default(),
    );
    let mut buf = Vec::new();
    write_frame(&s, &mut buf).unwrap();
    let text = String::from_utf8(buf).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "ITEM: TIMESTEP");
    assert_eq!(lines[3], "2", "number of atoms");
    assert_eq!(lines[4], "ITEM: BOX BOUNDS ff ff ff");
    assert!(lines[8].starts_with("ITEM: ATOMS id type x y z radius vx vy vz"));
    let row: Vec<f64> = lines[10]
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    assert_eq!(row[0], 2.0, "ids start at 1");
    assert_eq!(row[1], 1.0, "type = group + 1");
    assert!((row[5] - 1.5).abs() < 1e-12, "radius column");
    assert!(
        (row[6] - 0.25).abs() < 1e-12
            && (row[7] + 0.5).abs() < 1e-12
            && (row[8] - 1.0).abs() < 1e-12
    );
}

#[test]
fn a_rig_measures_the_top_walls_travel_across_the_periodic_boundary() {
    // The top wall slides 1.5 box lengths along x: its stored positions are wrapped back into the box at
    // list builds, but the rig's shear offset must grow as v t throughout (it once jumped by -L and a
    // shear test never reached its stop).
    use dem::scenario::rig::{Rig, RigSpec};
    let m = Material::table4(0.0);
    let d0 = 0.6 * m.critical_diameter();
    let sample =
        dem::sample::Sample::hcp(Vec3::new(6.0 * d0, 6.0 * d0, 3.0 * d0), d0, m.density).unwrap();
    let mut rig = Rig::new(
        &sample,
        &PairModel::cohesive(m),
        RigSpec::y_normal(1.5 * d0),
        RunConfig::default(),
        Parallelism::Sequential,
    )
    .unwrap();
    let lx = rig.sim.sim_box.lengths().x;
    let steps = 6000u64;
    let dt = rig.sim.dt();
    let v = 1.5 * lx / (steps as f64 * dt);
    rig.set_top(RigidMotion::with_velocity(Vec3::new(v, 0.0, 0.0)));
    let top = rig.top_ref;
    let x0 = rig.sim.particles.pos[top].x;
    let mut wrapped = false;
    for k in 1..=steps / 100 {
        rig.sim.run(100).unwrap();
        let travel = v * dt * (k * 100) as f64;
        let (shear, _) = rig.wall_offset();
        assert!(
            (shear - travel).abs() < 1e-9 * lx,
            "after {} steps the offset is {shear}, the wall travelled {travel}",
            k * 100
        );
        let stored = rig.sim.particles.pos[top].x;
        assert!(rig.sim.sim_box.lo.x <= stored && stored < rig.sim.sim_box.hi.x + 0.1 * d0);
        wrapped |= (stored - x0 - travel).abs() > 0.5 * lx;
    }
    assert!(
        wrapped,
        "the top wall's stored position never wrapped: the test proves nothing"
    );
    // The dump's image flags give the same continuous position (x + ix L_x).
    let mut buf = Vec::new();
    write_frame(&rig.sim, &mut buf).unwrap();
    let text = String::from_utf8(buf).unwrap();
    let header: Vec<&str> = text.lines().nth(8).unwrap().split_whitespace().collect();
    let col = |name: &str| header.iter().position(|&h| h == name).unwrap() - 2;
    let row: Vec<f64> = text
        .lines()
        .nth(9 + top)
        .unwrap()
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    assert!(row[col("ix")] >= 1.0, "{row:?}");
    let unwrapped = row[col("x")] + row[col("ix")] * lx;
    assert!((unwrapped - rig.sim.unwrapped_position(top).x).abs() < 1e-9 * lx);
}
