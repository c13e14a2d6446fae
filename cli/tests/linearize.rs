//! `lgsvi linearize` against central finite differences taken through `lgsvi simulate`
//! (one step from perturbed initial states and torques): the reference knows nothing of
//! the linearisation but the documented coordinates, written out here by hand.

use serde_json::Value;
use std::process::Command;

fn lgsvi(args: &[String]) -> Value {
    let out = Command::new(env!("CARGO_BIN_EXE_lgsvi"))
        .args(args)
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "lgsvi {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON")
}

type M3 = [[f64; 3]; 3];

fn mul(a: &M3, b: &M3) -> M3 {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

fn transpose(a: &M3) -> M3 {
    let mut t = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            t[i][j] = a[j][i];
        }
    }
    t
}

/// `exp(θ̂)` by Rodrigues' formula.
fn exp(theta: [f64; 3]) -> M3 {
    let angle = theta.iter().map(|x| x * x).sum::<f64>().sqrt();
    let k = [
        [0.0, -theta[2], theta[1]],
        [theta[2], 0.0, -theta[0]],
        [-theta[1], theta[0], 0.0],
    ];
    let (a, b) = if angle < 1e-8 {
        (1.0 - angle * angle / 6.0, 0.5 - angle * angle / 24.0)
    } else {
        (angle.sin() / angle, (1.0 - angle.cos()) / (angle * angle))
    };
    let k2 = mul(&k, &k);
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = if i == j { 1.0 } else { 0.0 } + a * k[i][j] + b * k2[i][j];
        }
    }
    r
}

/// The attitude change `θ` with `R = R̄ exp(θ̂)`, to third order (`vee` of the skew part
/// of `R̄ᵀR`, which is `sin|θ|/|θ| θ`): central differences cancel the even orders and
/// the third is ~ε³.
fn attitude_change(r: &M3, reference: &M3) -> [f64; 3] {
    let m = mul(&transpose(reference), r);
    [
        0.5 * (m[2][1] - m[1][2]),
        0.5 * (m[0][2] - m[2][0]),
        0.5 * (m[1][0] - m[0][1]),
    ]
}

fn row_major(r: &M3) -> String {
    (0..9)
        .map(|i| format!("{:e}", r[i / 3][i % 3]))
        .collect::<Vec<_>>()
        .join(",")
}

fn triple(v: [f64; 3]) -> String {
    format!("{:e},{:e},{:e}", v[0], v[1], v[2])
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

/// A matrix of the JSON as a list of rows.
fn rows(v: &Value) -> Vec<Vec<f64>> {
    v.as_array().expect("rows").iter().map(numbers).collect()
}

fn last(run: &Value, key: &str) -> Vec<f64> {
    numbers(
        run[key]
            .as_array()
            .expect("states")
            .last()
            .expect("a last state"),
    )
}

/// One system: its flags, whether it moves through space, the nominal state.
struct Case {
    flags: Vec<String>,
    space: bool,
    attitude: M3,
    omega: [f64; 3],
    position: [f64; 3],
    velocity: [f64; 3],
    torque: [f64; 3],
}

impl Case {
    /// The end state of one step from the state perturbed by `s` (world coordinates for
    /// a body in space) and the torque by `u`: `(R, rest)`, `rest` the state's other
    /// entries in the linearisation's order.
    fn step(&self, h: f64, s: &[f64], u: [f64; 3]) -> (M3, Vec<f64>) {
        let attitude = mul(&self.attitude, &exp([s[0], s[1], s[2]]));
        let add = |a: [f64; 3], offset: usize| {
            [a[0] + s[offset], a[1] + s[offset + 1], a[2] + s[offset + 2]]
        };
        let mut args: Vec<String> = vec!["simulate".into(), "--t-end".into(), h.to_string()];
        args.extend(["--h".into(), h.to_string()]);
        args.extend(self.flags.iter().cloned());
        args.extend(["--attitude0".into(), row_major(&attitude)]);
        let torque = [
            self.torque[0] + u[0],
            self.torque[1] + u[1],
            self.torque[2] + u[2],
        ];
        args.extend(["--torque".into(), triple(torque)]);
        if self.space {
            args.extend(["--position0".into(), triple(add(self.position, 3))]);
            args.extend(["--omega0".into(), triple(add(self.omega, 6))]);
            args.extend(["--velocity0".into(), triple(add(self.velocity, 9))]);
        } else {
            args.extend(["--omega0".into(), triple(add(self.omega, 3))]);
        }
        let run = lgsvi(&args);
        let r = last(&run, "R");
        let end = [[r[0], r[1], r[2]], [r[3], r[4], r[5]], [r[6], r[7], r[8]]];
        let mut rest = Vec::new();
        if self.space {
            rest.extend(last(&run, "position"));
        }
        rest.extend(last(&run, "omega"));
        if self.space {
            rest.extend(last(&run, "velocity"));
        }
        (end, rest)
    }

    /// `A` and `B` by central differences (ε = 1e-6 on order-one states: truncation
    /// ~1e-12, rounding of the step's end ~1e-16/1e-6 = 1e-10).
    fn differences(&self, h: f64) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        const EPS: f64 = 1e-6;
        let size = if self.space { 12 } else { 6 };
        let (r0, _) = self.step(h, &vec![0.0; size], [0.0; 3]);
        let mut columns = Vec::new();
        for col in 0..size + 3 {
            let mut sides = Vec::new();
            for sign in [1.0, -1.0] {
                let mut s = vec![0.0; size];
                let mut u = [0.0; 3];
                if col < size {
                    s[col] = sign * EPS;
                } else {
                    u[col - size] = sign * EPS;
                }
                let (r, rest) = self.step(h, &s, u);
                let mut out = attitude_change(&r, &r0).to_vec();
                out.extend(rest);
                sides.push(out);
            }
            columns.push(
                sides[0]
                    .iter()
                    .zip(&sides[1])
                    .map(|(p, m)| (p - m) / (2.0 * EPS))
                    .collect::<Vec<f64>>(),
            );
        }
        let matrix = |cols: &[Vec<f64>]| {
            (0..size)
                .map(|r| cols.iter().map(|c| c[r]).collect())
                .collect::<Vec<Vec<f64>>>()
        };
        (matrix(&columns[..size]), matrix(&columns[size..]))
    }

    /// `lgsvi linearize`'s JSON for the nominal state and torque.
    fn linearize_json(&self, h: f64) -> Value {
        let mut args: Vec<String> = vec!["linearize".into(), "--h".into(), h.to_string()];
        args.extend(self.flags.iter().cloned());
        args.extend(["--attitude0".into(), row_major(&self.attitude)]);
        args.extend(["--torque".into(), triple(self.torque)]);
        args.extend(["--omega0".into(), triple(self.omega)]);
        if self.space {
            args.extend(["--position0".into(), triple(self.position)]);
            args.extend(["--velocity0".into(), triple(self.velocity)]);
        }
        lgsvi(&args)
    }

    fn linearize(&self, h: f64) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let out = self.linearize_json(h);
        (rows(&out["a"]), rows(&out["b"]))
    }
}

/// `max |X − Y| / max(max |Y|, 1)`.
fn relative(x: &[Vec<f64>], y: &[Vec<f64>]) -> f64 {
    let scale = y.iter().flatten().fold(1.0f64, |m, v| m.max(v.abs()));
    x.iter()
        .flatten()
        .zip(y.iter().flatten())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / scale
}

#[test]
fn linearize_matches_differences_through_simulate() {
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<String>>();
    let attitude = exp([0.2, -0.1, 0.3]);
    let so3 = |flags: Vec<String>| Case {
        flags,
        space: false,
        attitude,
        omega: [0.6, 0.1, -0.4],
        position: [0.0; 3],
        velocity: [0.0; 3],
        torque: [0.05, -0.02, 0.03],
    };
    let space = |flags: Vec<String>, position: [f64; 3], velocity: [f64; 3]| Case {
        flags,
        space: true,
        attitude,
        omega: [0.6, 0.1, -0.4],
        position,
        velocity,
        torque: [0.05, -0.02, 0.03],
    };
    let cases = [
        (
            "rigid body, damped",
            so3(s(&["--system", "rigid-body", "--damping", "0.2"])),
        ),
        (
            "heavy top",
            so3(s(&[
                "--system",
                "heavy-top",
                "--gravity-direction",
                "0,0.3,1",
            ])),
        ),
        (
            "heavy top, cayley",
            so3(s(&[
                "--system",
                "heavy-top",
                "--chart",
                "cayley",
                "--nodes",
                "6",
            ])),
        ),
        (
            "body in space",
            space(
                s(&["--system", "se3-body", "--mass", "1.3"]),
                [0.5, -0.2, 1.0],
                [0.1, -0.2, 0.05],
            ),
        ),
        (
            "orbiting body",
            space(
                s(&["--system", "orbiting-body"]),
                [3.0, 0.0, 0.5],
                [0.0, 0.55, 0.05],
            ),
        ),
    ];
    for (name, case) in cases {
        let h = 0.25;
        let (a, b) = case.linearize(h);
        assert_eq!(
            b[0].len(),
            if case.space { 6 } else { 3 },
            "{name}: B's columns"
        );
        // --torque reaches B's torque columns only (a body in space's force columns are
        // checked against differences in the library's tests).
        let b: Vec<Vec<f64>> = b.iter().map(|row| row[..3].to_vec()).collect();
        let (a_fd, b_fd) = case.differences(h);
        let (da, db) = (relative(&a, &a_fd), relative(&b, &b_fd));
        // The goal: 1e-7 relative; the differences' own error is ~1e-10.
        assert!(da < 1e-7 && db < 1e-7, "{name}: A {da:e}, B {db:e}");
        println!("| {name} | {da:.1e} | {db:.1e} |");
    }
}

/// `lgsvi linearize`'s `"p"` (the step's derivatives in the system's parameters, the
/// inertia tensor's six entries then the mass) against central differences through
/// `lgsvi simulate` with `--inertia-tensor` (an off-diagonal entry moved in both of its
/// places) and `--mass` moved; velocity coordinates (world frame for a body in space),
/// the start state held.
#[test]
fn linearize_parameters_match_differences_through_simulate() {
    const EPS: f64 = 1e-6;
    let tensor = [[0.6, 0.05, -0.03], [0.05, 0.85, 0.02], [-0.03, 0.02, 0.7]];
    let flags = |j: &M3, mass: f64, system: &[&str]| {
        let mut f: Vec<String> = system.iter().map(|x| x.to_string()).collect();
        f.extend(["--inertia-tensor".into(), row_major(j)]);
        f.extend(["--mass".into(), mass.to_string()]);
        f
    };
    // (name, flags, in space, position, velocity)
    type System<'a> = (&'a str, &'a [&'a str], bool, [f64; 3], [f64; 3]);
    let systems: [System; 2] = [
        (
            "heavy top",
            &["--system", "heavy-top", "--gravity-direction", "0,0.3,1"],
            false,
            [0.0; 3],
            [0.0; 3],
        ),
        (
            "orbiting body",
            &["--system", "orbiting-body"],
            true,
            [3.0, 0.0, 0.5],
            [0.0, 0.55, 0.05],
        ),
    ];
    let places = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
    for (name, system, space, position, velocity) in systems {
        let case = |j: &M3, mass: f64| Case {
            flags: flags(j, mass, system),
            space,
            attitude: exp([0.2, -0.1, 0.3]),
            omega: [0.6, 0.1, -0.4],
            position,
            velocity,
            torque: [0.05, -0.02, 0.03],
        };
        let h = 0.25;
        let nominal = case(&tensor, 1.0);
        let out = nominal.linearize_json(h);
        let names: Vec<&str> = out["parameters"]
            .as_array()
            .expect("names")
            .iter()
            .map(|n| n.as_str().expect("a name"))
            .collect();
        // The orbiting body's gravitational parameter comes last (its column is checked
        // against differences in mechanics/tests/parameters.rs).
        let mut expected = vec!["J_xx", "J_yy", "J_zz", "J_xy", "J_xz", "J_yz", "mass"];
        if space {
            expected.push("mu");
        }
        assert_eq!(names, expected, "{name}");
        let p = rows(&out["p"]);
        let size = if space { 12 } else { 6 };
        let zero = vec![0.0; size];
        let (r0, _) = nominal.step(h, &zero, [0.0; 3]);
        let mut columns = Vec::new();
        for k in 0..7 {
            let mut sides = Vec::new();
            for sign in [1.0, -1.0] {
                let (mut j, mut mass) = (tensor, 1.0);
                match places.get(k) {
                    Some(&(a, b)) => {
                        j[a][b] += sign * EPS;
                        if a != b {
                            j[b][a] += sign * EPS;
                        }
                    }
                    None => mass += sign * EPS,
                }
                let (r, rest) = case(&j, mass).step(h, &zero, [0.0; 3]);
                let mut end = attitude_change(&r, &r0).to_vec();
                end.extend(rest);
                sides.push(end);
            }
            columns.push(
                sides[0]
                    .iter()
                    .zip(&sides[1])
                    .map(|(a, b)| (a - b) / (2.0 * EPS))
                    .collect::<Vec<f64>>(),
            );
        }
        let p_fd: Vec<Vec<f64>> = (0..size)
            .map(|r| columns.iter().map(|c| c[r]).collect())
            .collect();
        // The first seven columns (the inertia entries and the mass) against these
        // differences; the orbit's `mu` column is checked in mechanics/tests/parameters.rs.
        let p: Vec<Vec<f64>> = p.iter().map(|row| row[..7].to_vec()).collect();
        let dp = relative(&p, &p_fd);
        // As for A and B: 1e-7 asked, the differences' own error ~1e-10.
        assert!(dp < 1e-7, "{name}: P {dp:e}");
        println!("| {name} | P | {dp:.1e} |");
    }
}

/// A gyrostat at rest with one wheel on a principal axis: the step is the exact
/// zero-order hold of `J_b Ω̇_z = −τ`, `I(Ω̇_z + φ̈) = τ` (`J_b = J_zz − I`), so the motor
/// column of `B` is `(θ_z, φ, Ω_z, φ̇) = (−h²/2J_b, h²/2I + h²/2J_b, −h/J_b, h/I + h/J_b)`.
#[test]
fn a_gyrostat_at_rest_linearises_to_the_zero_order_hold() {
    let args: Vec<String> = [
        "linearize",
        "--system",
        "gyrostat",
        "--inertia",
        "10,12,8",
        "--wheel-axes",
        "0,0,1",
        "--wheel-inertia",
        "0.05",
        "--omega0",
        "0,0,0",
        "--h",
        "0.1",
        "--nodes",
        "4",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let out = lgsvi(&args);
    let b: Vec<Vec<f64>> = out["b"].as_array().unwrap().iter().map(numbers).collect();
    let (h, i, jb) = (0.1, 0.05, 8.0 - 0.05);
    let motor = [
        -h * h / (2.0 * jb),
        h * h / (2.0 * i) + h * h / (2.0 * jb),
        -h / jb,
        h / i + h / jb,
    ];
    // State order (θ_x, θ_y, θ_z, φ, Ω_x, Ω_y, Ω_z, φ̇); the motor is input 3.
    for (row, expected) in [(2, motor[0]), (3, motor[1]), (6, motor[2]), (7, motor[3])] {
        assert!(
            (b[row][3] - expected).abs() < 1e-14 * expected.abs().max(1.0),
            "row {row}: {} vs {expected}",
            b[row][3]
        );
    }
    assert!(out["coordinates"]
        .as_str()
        .unwrap()
        .contains("motor torques"));
}

/// `lgsvi simulate --system gyrostat`: the wheels' columns, the spatial angular momentum
/// conserved under motor torques, the energy balance with the motors' work, and the
/// refusals of flags that do not apply.
#[test]
fn gyrostat_runs_conserve_the_total_angular_momentum() {
    let args: Vec<String> = [
        "simulate",
        "--system",
        "gyrostat",
        "--wheel-torque",
        "0.01,0,-0.02",
        "--wheel-speeds0",
        "1,2,3",
        "--h",
        "0.1",
        "--nodes",
        "6",
        "--t-end",
        "5",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let run = lgsvi(&args);
    let pi = run["spatial_momentum"].as_array().unwrap();
    let (first, last) = (numbers(&pi[0]), numbers(pi.last().unwrap()));
    let drift = first
        .iter()
        .zip(&last)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    // 50 steps of rounding on momenta of order one.
    assert!(drift < 1e-14, "Rh drifted by {drift:e}");
    let energy = numbers(&run["energy"]);
    let work = numbers(&run["work"]);
    let balance = (energy.last().unwrap() - energy[0] - work.last().unwrap()).abs();
    assert!(balance < 1e-12, "energy balance {balance:e}");
    assert_eq!(numbers(&run["wheel_speeds"][0]), vec![1.0, 2.0, 3.0]);
    for (flags, word) in [
        (
            vec!["--system", "gyrostat", "--torque", "1,0,0"],
            "--wheel-torque",
        ),
        (vec!["--wheel-axes", "1,0,0"], "gyrostat"),
        (
            vec!["--system", "gyrostat", "--wheel-axes", "1,0"],
            "three numbers per wheel",
        ),
        (
            vec!["--system", "gyrostat", "--wheel-inertia", "0.1,0.1"],
            "one number per wheel",
        ),
        (
            vec!["--system", "gyrostat", "--wheel-inertia", "20,1,1"],
            "not positive definite",
        ),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_lgsvi"))
            .arg("simulate")
            .args(&flags)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && stderr.contains(word),
            "{flags:?}: {stderr}"
        );
        assert_eq!(stderr.lines().count(), 1, "{flags:?}: one line");
    }
}
