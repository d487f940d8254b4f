//! Minimum-snap trajectories against RotorPy 3.0.0's `MinSnap` (its QP
//! solved by cvxopt's interior point), run now when `rotorpy` imports,
//! else its stored output: five waypoint sets, with and without yaw, where
//! only equality constraints are active (the golden's largest midpoint
//! speed is below RotorPy's 3 m/s bound). The same segment times, and at
//! 400 times `x_d … x_d⁽⁴⁾`, yaw, yaw rate and yaw acceleration, each
//! within 1e-10 of its largest magnitude along the trajectory; and the
//! largest midpoint velocity component, where RotorPy puts its bound. The problem
//! is linear per axis, so RotorPy's z-up numbers are compared as they are.

use missions::MinSnap;

struct Set {
    name: String,
    v_avg: f64,
    points: Vec<[f64; 3]>,
    yaw: Vec<f64>,
    times: Vec<f64>,
    rows: Vec<Vec<f64>>,
    midspeed: f64,
}

fn parse(text: &str) -> Vec<Set> {
    let nums = |s: &str| -> Vec<f64> { s.split_whitespace().map(|x| x.parse().unwrap()).collect() };
    let mut sets: Vec<Set> = Vec::new();
    for line in text.lines() {
        let (head, rest) = line.split_once(' ').unwrap_or((line, ""));
        match head {
            "set" => {
                let f: Vec<&str> = rest.split_whitespace().collect();
                sets.push(Set {
                    name: f[0].into(),
                    v_avg: f[1].parse().unwrap(),
                    points: vec![],
                    yaw: vec![],
                    times: vec![],
                    rows: vec![],
                    midspeed: 0.0,
                });
            }
            "w" => {
                let v = nums(rest);
                let s = sets.last_mut().unwrap();
                s.points.push([v[0], v[1], v[2]]);
                s.yaw.push(v[3]);
            }
            "times" => sets.last_mut().unwrap().times = nums(rest),
            "midspeed" => sets.last_mut().unwrap().midspeed = rest.trim().parse().unwrap(),
            _ => sets.last_mut().unwrap().rows.push(nums(line)),
        }
    }
    sets
}

#[test]
fn minsnap_matches_rotorpy() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let (text, now) = testkit::rotorpy_golden(&dir, "rotorpy_minsnap");
    println!(
        "reference: RotorPy MinSnap, {}",
        if now { "run now" } else { "stored output" }
    );
    let sets = parse(&text);
    assert_eq!(sets.len(), 5);
    println!("set                 segments  |ΔT|      worst of x … x⁽⁴⁾, ψ, ψ̇, ψ̈ (relative)");
    for s in &sets {
        assert!(
            s.midspeed < 3.0 - 1e-3,
            "{}: RotorPy's speed bound is active",
            s.name
        );
        let traj = MinSnap::through(&s.points)
            .yaw(&s.yaw)
            .mean_speed(s.v_avg)
            .solve()
            .unwrap();
        // RotorPy's bound is on each component at each midpoint, one-sided.
        let mid = traj
            .midpoint_velocities()
            .iter()
            .flatten()
            .fold(f64::NEG_INFINITY, |m, v| m.max(*v));
        assert!(
            (mid - s.midspeed).abs() < 1e-10,
            "{}: midpoint speed {mid} vs {}",
            s.name,
            s.midspeed
        );
        let starts = traj.times();
        let dt = s
            .times
            .iter()
            .enumerate()
            .map(|(i, t)| (t - (starts[i + 1] - starts[i])).abs())
            .fold(0.0, testkit::nan_max);
        // The same formula on the same numbers: differences are rounding.
        assert!(dt < 1e-14, "{}: segment times differ by {dt}", s.name);
        // 8 groups: 5 derivative orders of x (3 axes each) and 3 of yaw.
        let mut scale = [0.0f64; 8];
        let mut worst = [0.0f64; 8];
        for r in &s.rows {
            let f = traj.flat(r[0]);
            for d in 0..5 {
                for a in 0..3 {
                    scale[d] = scale[d].max(r[1 + 3 * d + a].abs());
                    worst[d] = testkit::nan_max(worst[d], (f.x[d][a] - r[1 + 3 * d + a]).abs());
                }
            }
            for d in 0..3 {
                scale[5 + d] = scale[5 + d].max(r[16 + d].abs());
                worst[5 + d] = testkit::nan_max(worst[5 + d], (f.yaw[d] - r[16 + d]).abs());
            }
        }
        // Without yaw RotorPy's yaw is zero to rounding: compared
        // absolutely (rad) there.
        let rel: Vec<f64> = (0..8)
            .map(|k| worst[k] / if scale[k] > 1e-6 { scale[k] } else { 1.0 })
            .collect();
        let max = rel.iter().copied().fold(0.0, testkit::nan_max);
        println!(
            "{:<19} {:>8}  {dt:.1e}   {max:.1e}  [{}]",
            s.name,
            s.times.len(),
            rel.iter()
                .map(|r| format!("{r:.0e}"))
                .collect::<Vec<_>>()
                .join(" ")
        );
        // With no inequality active cvxopt's answer is the KKT solution
        // to rounding (measured at most 9e-13 here), amplified by the
        // monomial basis on pieces up to 5 s long; 1e-10 leaves two orders
        // and still catches any change of constraint or cost (O(1e-2)).
        assert!(max < 1e-10, "{}: {rel:?}", s.name);
    }
}
