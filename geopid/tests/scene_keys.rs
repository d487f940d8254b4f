//! Every key a scene file can hold is documented in the guide's scene
//! chapter: scenes with every optional table present and every variant of
//! the wind, the references and the thrust are serialised to TOML, and each
//! key path found there must appear in `guide/02-scenes.md` — as itself in
//! backticks, or as a word on a line that names its parent path in
//! backticks (the table row of `plan[].position` lists its variants' keys).

use geopid::scenes::builtin;
use geopid::scenes::scene::{
    AttitudeRef, BaroTable, EstimatorKind, EstimatorSpec, GpsTable, GroundSpec, ImuTable,
    MocapTable, MultirotorSpec, PositionRef, Preset, Scene, SegmentSpec, SensorsSpec, SpikeTable,
    ThrustSpec, TriadTable, WindSpec,
};

const CHAPTER: &str = include_str!("../guide/02-scenes.md");

/// A scene with every optional table and key present.
fn populated() -> Scene {
    let mut s = builtin::paper_flip();
    s.format = Some(1);
    s.vehicle.params.insert("any_number".into(), 1.0);
    s.vehicle.model_mass = Some(1.0);
    s.vehicle.multirotor = Some(MultirotorSpec {
        preset: Preset::Hummingbird,
        k_eta: Some(1.0),
        k_m: Some(1.0),
        k_d: Some(1.0),
        k_z: Some(1.0),
        k_h: Some(1.0),
        k_flap: Some(1.0),
        c_dx: Some(1.0),
        c_dy: Some(1.0),
        c_dz: Some(1.0),
        tau_m: Some(1.0),
        rotor_speed_min: Some(1.0),
        rotor_speed_max: Some(2.0),
        aero: Some(true),
        rotor_positions: Some(vec![[0.1, 0.0, 0.0]]),
        rotor_directions: Some(vec![1.0]),
    });
    s.plan[0].until_psi = Some(0.1);
    s.ground = Some(GroundSpec {
        feet: vec![[0.0, 0.0, 0.1]],
        ..GroundSpec::default()
    });
    s.seed = 7;
    s.control.loop_rates = Some("crazyflie".into());
    let triad = TriadTable {
        noise_density: Some(1.0),
        random_walk: Some(1.0),
        turn_on_bias: Some(1.0),
        scale_misalignment: Some([[0.0; 3]; 3]),
        range: Some(1.0),
    };
    let spike = SpikeTable {
        probability: 0.1,
        max: 1.0,
    };
    s.sensors = Some(SensorsSpec {
        preset: "rotorpy".into(),
        noise_scale: 1.0,
        mocap_latency: Some(0.01),
        mocap_rate: Some(100.0),
        imu: Some(ImuTable {
            rate: Some(1.0),
            position: Some([0.0; 3]),
            mounting: Some([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
            accel: Some(triad.clone()),
            gyro: Some(triad),
            attitude_sigma: Some(1.0),
        }),
        mocap: Some(MocapTable {
            position_sigma: Some(1.0),
            velocity_sigma: Some(1.0),
            attitude_sigma: Some(1.0),
            rate_sigma: Some(1.0),
            dropout: Some(0.1),
            velocity_spike: Some(spike.clone()),
            rate_spike: Some(spike),
            ..MocapTable::default()
        }),
        gps: Some(GpsTable {
            rate: Some(1.0),
            delay: Some(1.0),
            horizontal_sigma: Some(1.0),
            vertical_sigma: Some(1.0),
            velocity_sigma: Some(1.0),
        }),
        baro: Some(BaroTable {
            rate: Some(1.0),
            sigma: Some(1.0),
            random_walk: Some(1.0),
            turn_on_bias: Some(1.0),
        }),
    });
    s.estimator = Some(EstimatorSpec {
        kind: EstimatorKind::Mocap,
        gyro_rates: true,
        attitude_error: Some([1.0; 3]),
        attitude_sigma: Some(1.0),
        k_p: Some(1.0),
        k_i: Some(1.0),
        compensate_delay: Some(true),
        q_scale: Some(1.0),
        r_scale: Some(1.0),
    });
    s
}

/// Scenes that each hold one variant of the tagged tables.
fn variants() -> Vec<Scene> {
    let winds = [
        WindSpec::Constant { velocity: [1.0; 3] },
        WindSpec::Sinusoid {
            mean: [0.0; 3],
            amplitude: [1.0; 3],
            frequency: 1.0,
            phase: 0.0,
        },
        WindSpec::Ladder {
            times: vec![1.0],
            velocities: vec![[1.0; 3]],
        },
        WindSpec::Dryden {
            mean: [0.0; 3],
            sigma: [1.0; 3],
            length: [1.0; 3],
            speed: 5.0,
            seed: 1,
            grid: 0.005,
        },
    ];
    let positions = [
        PositionRef::Hold {
            x: [0.0; 3],
            b1d: [1.0, 0.0, 0.0],
        },
        PositionRef::FigureEight {
            center: [0.0; 3],
            a: 1.0,
            b: 1.0,
            omega: 1.0,
        },
        PositionRef::Sinusoids {
            center: [0.0; 3],
            amplitude: [1.0; 3],
            omega: [1.0; 3],
            phase: [0.0; 3],
        },
        PositionRef::Circle {
            center: [0.0; 3],
            radius: 1.0,
            omega: 1.0,
        },
        PositionRef::MinSnap {
            waypoints: vec![[0.0; 3], [1.0, 0.0, 0.0]],
            yaw: Some(vec![0.0, 1.0]),
            times: Some(vec![0.0, 2.0]),
            mean_speed: Some(1.0),
            time_budget: Some(2.0),
            start: 1.0,
        },
        PositionRef::TrajectoryFile {
            path: "trajectory.csv".into(),
            start: 1.0,
        },
    ];
    let attitudes = [
        AttitudeRef::PaperFlip {},
        AttitudeRef::EulerExperiment {
            amplitude: 0.3,
            frequency: 0.5,
        },
        AttitudeRef::Hold { rotation: [0.0; 3] },
    ];
    let mut out = Vec::new();
    for w in winds {
        let mut s = populated();
        s.wind = Some(w);
        out.push(s);
    }
    for (p, a) in positions.into_iter().zip(attitudes.into_iter().cycle()) {
        let mut s = populated();
        s.plan = vec![SegmentSpec {
            attitude: Some(a),
            position: Some(p),
            thrust: ThrustSpec::PdProjection,
            ..s.plan[0].clone()
        }];
        out.push(s);
    }
    out.extend(builtin::all());
    out
}

fn flatten(prefix: &str, v: &toml::Value, out: &mut std::collections::BTreeSet<String>) {
    match v {
        toml::Value::Table(t) => {
            for (k, v) in t {
                let path = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&path, v, out);
            }
        }
        toml::Value::Array(a) if a.iter().any(|x| x.is_table()) => {
            for x in a {
                flatten(&format!("{prefix}[]"), x, out);
            }
        }
        _ => {
            out.insert(prefix.to_string());
        }
    }
}

fn documented(path: &str) -> bool {
    // A registered kind's own numbers take names of its choosing.
    if path.starts_with("vehicle.params.") {
        return CHAPTER.contains("`vehicle.params`");
    }
    if CHAPTER.contains(&format!("`{path}`")) {
        return true;
    }
    let Some((parent, leaf)) = path.rsplit_once('.') else {
        return false;
    };
    let is_word = |line: &str| {
        line.match_indices(leaf).any(|(i, _)| {
            let before = line[..i].chars().next_back();
            let after = line[i + leaf.len()..].chars().next();
            let edge = |c: Option<char>| c.is_none_or(|c| !(c.is_alphanumeric() || c == '_'));
            edge(before) && edge(after)
        })
    };
    CHAPTER.lines().any(|line| {
        (line.contains(&format!("`{parent}.")) || line.contains(&format!("`{parent}`")))
            && is_word(line)
    })
}

#[test]
fn every_key_of_a_serialised_scene_is_in_the_scene_chapter() {
    let mut keys = std::collections::BTreeSet::new();
    for scene in variants() {
        let text = scene.to_toml();
        let value: toml::Value = toml::from_str(&text).expect("to_toml writes TOML");
        flatten("", &value, &mut keys);
    }
    assert!(
        keys.len() > 60,
        "only {} keys found: the scenes are not populated",
        keys.len()
    );
    let missing: Vec<&String> = keys.iter().filter(|k| !documented(k)).collect();
    assert!(
        missing.is_empty(),
        "{} of {} scene keys are not in geopid/guide/02-scenes.md: {missing:?}",
        missing.len(),
        keys.len()
    );
}
