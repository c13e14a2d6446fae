//! `lgsvi montecarlo`: members that depend on (seed, member) alone, whatever the thread
//! count; a row that `lgsvi simulate` given the row's parameters reproduces bit for bit,
//! and `--replay`; failures listed with seed and cause, never dropped; bad input refused
//! naming the flag or key.

mod common;

use common::temp_dir;

/// `lgsvi args`, on `threads` threads where given.
fn lgsvi(args: &[&str], threads: Option<&str>) -> (i32, String, String) {
    let dir = std::env::current_dir().expect("a working directory");
    match threads {
        Some(threads) => common::run_in(&dir, args, &[("RAYON_NUM_THREADS", threads)]),
        None => common::run_in(&dir, args, &[]),
    }
}

const RUN: [&str; 12] = [
    "montecarlo",
    "--members",
    "40",
    "--seed",
    "9",
    "--disperse-omega",
    "0.02",
    "--disperse-inertia",
    "0.01",
    "--disperse-attitude",
    "2",
    "--quiet",
];

/// `(header, rows)` of a members.csv.
fn table(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (header, rows)
}

#[test]
fn members_are_the_same_on_one_thread_or_two_and_simulate_reproduces_a_row() {
    let dir = temp_dir("determinism");
    let mut outputs = Vec::new();
    for threads in ["1", "2"] {
        let out = dir.join(format!("threads-{threads}"));
        let mut args = RUN.to_vec();
        args.extend([
            "--t-end",
            "5",
            "--tol",
            "1e-10",
            "--out",
            out.to_str().unwrap(),
        ]);
        let (code, _, err) = lgsvi(&args, Some(threads));
        assert_eq!(code, 0, "{err}");
        outputs.push(std::fs::read(out.join("members.csv")).unwrap());
    }
    assert_eq!(
        outputs[0], outputs[1],
        "members.csv differs between 1 and 2 threads"
    );
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("threads-2").join("summary.json")).unwrap(),
    )
    .unwrap();
    // Every member takes the nominal's step (one time grid for the envelopes).
    let h = summary["settings"]["h"].as_f64().unwrap().to_string();
    let (header, rows) = table(&dir.join("threads-2").join("members.csv"));
    assert_eq!(rows.len(), 40);
    assert_eq!(&header[..3], ["member", "status", "J_11"]);
    assert_eq!(header.len(), 2 + 9 + 9 + 3 + 1 + 9 + 3);
    let row = &rows[13];
    assert_eq!((row[0].as_str(), row[1].as_str()), ("13", "ok"));
    // simulate with the row's drawn J, R₀, Ω₀ (and the nominal's flags) ends on the row's
    // final state, bit for bit (every float printed to round-trip).
    let j = row[2..11].join(",");
    let r0 = row[11..20].join(",");
    let w0 = row[20..23].join(",");
    let (code, out, err) = lgsvi(
        &[
            "simulate",
            "--inertia-tensor",
            &j,
            "--attitude0",
            &r0,
            "--omega0",
            &w0,
            "--t-end",
            "5",
            "--tol",
            "1e-10",
            "--h",
            &h,
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    let json: serde_json::Value = serde_json::from_str(&out).unwrap();
    let last = |key: &str| -> Vec<f64> {
        json[key]
            .as_array()
            .unwrap()
            .last()
            .unwrap()
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let parse =
        |cells: &[String]| -> Vec<f64> { cells.iter().map(|c| c.parse().unwrap()).collect() };
    assert_eq!(last("R"), parse(&row[24..33]));
    assert_eq!(last("omega"), parse(&row[33..36]));
    // --replay 13 writes that member's whole trajectory, the same last state.
    let mut args = RUN.to_vec();
    args.extend(["--t-end", "5", "--tol", "1e-10", "--replay", "13"]);
    let (code, out, err) = lgsvi(&args, None);
    assert_eq!(code, 0, "{err}");
    let replay: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(replay["R"], json["R"]);
    assert_eq!(replay["omega"], json["omega"]);
    // The summary: every member finished, the rates' statistics over them, and the
    // envelopes: at t = 0 the attitude departure's percentiles are those of the drawn
    // starts (2° per axis), ordered, and the same on one thread or two.
    let envelope = &summary["envelopes"]["channels"]["attitude_departure_deg"];
    let at = |p: &str, k: usize| envelope[p][k].as_f64().unwrap();
    let t = summary["envelopes"]["t"].as_array().unwrap();
    assert!(t.len() >= 2 && t[0] == 0.0);
    for k in 0..t.len() {
        assert!(at("p1", k) <= at("p50", k) && at("p50", k) <= at("p99", k));
    }
    assert!((1.0..8.0).contains(&at("p50", 0)), "{}", at("p50", 0));
    let other: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("threads-1").join("summary.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(other["envelopes"], summary["envelopes"]);
    for figure in ["envelope_attitude.png", "envelope_energy.svg"] {
        assert!(dir.join("threads-2").join(figure).exists(), "{figure}");
    }
    assert_eq!(summary["finished"], 40);
    assert_eq!(summary["failed"], 0);
    assert_eq!(
        summary["final_omega"]["covariance"]
            .as_array()
            .unwrap()
            .len(),
        3
    );
    assert_eq!(
        summary["dispersions"]["inertia"]["distribution"],
        "truncated_normal"
    );
}

/// Members whose steps fail (spins the Cayley chart cannot follow at h = 1) are listed
/// with their seed and cause, their rows marked, the rest written; exit status 3.
#[test]
fn failed_members_are_listed_not_dropped() {
    let dir = temp_dir("failures");
    let out = dir.join("run");
    let (code, _, err) = lgsvi(
        &[
            "montecarlo",
            "--members",
            "20",
            "--disperse-omega",
            "2",
            "--h",
            "1",
            "--chart",
            "cayley",
            "--t-end",
            "4",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains("members failed") && err.contains("summary.json"),
        "{err}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let failed = summary["failed"].as_u64().unwrap();
    assert!(failed > 0 && failed < 20, "{failed}");
    let (_, rows) = table(&out.join("members.csv"));
    assert_eq!(rows.len(), 20);
    let marked = rows.iter().filter(|r| r[1] == "failed").count() as u64;
    assert_eq!(marked, failed);
    for failure in summary["failures"].as_array().unwrap() {
        assert_eq!(failure["seed"], 0);
        assert!(
            failure["error"]
                .as_str()
                .unwrap()
                .contains("cayley chart's reach"),
            "{failure}"
        );
        let member = failure["member"].as_u64().unwrap() as usize;
        assert_eq!(rows[member][1], "failed");
    }
}

#[test]
fn bad_input_is_refused_naming_the_flag_or_key() {
    let dir = temp_dir("bad");
    let taken = dir.join("taken");
    std::fs::create_dir_all(&taken).unwrap();
    std::fs::write(taken.join("members.csv"), "member\n").unwrap();
    let config = dir.join("bad.toml");
    std::fs::write(
        &config,
        "[montecarlo.dispersions]\nomegas = { distribution = \"normal\", sigma = 0.1 }\n",
    )
    .unwrap();
    let out = dir.join("out");
    for (args, needles) in [
        (vec!["--members", "0"], vec!["--members 0", "from 1"]),
        (
            vec!["--disperse-omega", "-1"],
            vec!["--disperse-omega -1", "≥ 0"],
        ),
        (
            vec!["--disperse-inertia", "0.2"],
            vec![
                "--disperse-inertia 0.2",
                "triangle inequality",
                "below 0.260870",
            ],
        ),
        (vec!["--plot", "p"], vec!["--plot"]),
        (
            vec!["--config", config.to_str().unwrap()],
            vec!["[montecarlo.dispersions]", "omegas"],
        ),
    ] {
        let mut full = vec!["montecarlo", "--quiet", "--out", out.to_str().unwrap()];
        full.extend(args.iter().copied());
        let (code, _, err) = lgsvi(&full, None);
        assert_ne!(code, 0, "{args:?}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        for needle in needles {
            assert!(err.contains(needle), "{args:?}: {err}");
        }
    }
    // An output folder that holds another run.
    let (code, _, err) = lgsvi(
        &["montecarlo", "--quiet", "--out", taken.to_str().unwrap()],
        None,
    );
    assert_ne!(code, 0);
    assert!(err.contains("holds another run"), "{err}");
}

#[test]
fn stop_times_per_member_match_simulate_and_are_summarised() {
    let dir = temp_dir("stop");
    let out = dir.join("run");
    // An axisymmetric nominal (J = diag(1, 1, 1.8)), rates dispersed: Ω₁ falls through 0
    // near π/(2 · 0.8 · 1.5) ≈ 1.31 for each member.
    let args = [
        "montecarlo",
        "--inertia",
        "1,1,1.8",
        "--omega0",
        "0.3,0,1.5",
        "--h",
        "0.25",
        "--nodes",
        "12",
        "--t-end",
        "10",
        "--members",
        "30",
        "--seed",
        "4",
        "--disperse-omega",
        "0.05",
        "--stop-when",
        "omega_1<0",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    let (code, _, err) = lgsvi(&args, None);
    assert_eq!(code, 0, "{err}");
    let (header, rows) = table(&out.join("members.csv"));
    assert_eq!(header.last().map(String::as_str), Some("t_stop"));
    let row = &rows[7];
    let t_stop: f64 = row.last().unwrap().parse().unwrap();
    let (code, json, err) = lgsvi(
        &[
            "simulate",
            "--inertia-tensor",
            &row[2..11].join(","),
            "--attitude0",
            &row[11..20].join(","),
            "--omega0",
            &row[20..23].join(","),
            "--h",
            "0.25",
            "--nodes",
            "12",
            "--t-end",
            "10",
            "--stop-when",
            "omega_1<0",
            "--quiet",
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    let json: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(json["description"]["stopped"]["t"].as_f64(), Some(t_stop));
    // The member's row ends at the end of the step holding its stop.
    let t_end: f64 = row[23].parse().unwrap();
    assert!(t_end >= t_stop && t_end - t_stop < 0.25);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let stop = &summary["stop"];
    assert_eq!(stop["members_stopped"], 30);
    let mut times: Vec<f64> = rows
        .iter()
        .map(|r| r.last().unwrap().parse().unwrap())
        .collect();
    times.sort_by(f64::total_cmp);
    // The exact sample median: the ⌈0.5 · 30⌉ = 15th smallest.
    assert_eq!(stop["time_percentiles"]["p50"].as_f64(), Some(times[14]));
    let counts: u64 = stop["histogram"]["counts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_u64().unwrap())
        .sum();
    assert_eq!(counts, 30);
    for ext in ["png", "svg"] {
        assert!(out.join(format!("stop_times.{ext}")).exists());
    }
}

#[test]
fn an_interrupted_run_resumes_to_the_uninterrupted_result() {
    let dir = temp_dir("resume");
    let (whole, cut) = (dir.join("whole"), dir.join("cut"));
    let mut args = RUN.to_vec();
    args.extend(["--t-end", "5"]);
    let with_out = |out: &std::path::Path, extra: &[&str]| {
        let mut a = args.clone();
        a.extend(["--out", out.to_str().unwrap()]);
        a.extend(extra);
        lgsvi(&a.iter().map(|s| &**s).collect::<Vec<_>>(), None)
    };
    let (code, _, err) = with_out(&whole, &[]);
    assert_eq!(code, 0, "{err}");
    // Interrupted after 17 of 40 members, a row half written after them.
    let (code, _, err) = with_out(&cut, &["--interrupt-after", "17"]);
    assert_ne!(code, 0);
    assert!(err.contains("17 of 40"), "{err}");
    assert!(cut.join("checkpoint.json").exists());
    let (_, rows) = table(&cut.join("members.csv"));
    assert_eq!(rows.len(), 17);
    let mut file = std::fs::OpenOptions::new()
        .append(true)
        .open(cut.join("members.csv"))
        .unwrap();
    std::io::Write::write_all(&mut file, b"17,ok,3.3,0.0").unwrap();
    let (code, _, err) = lgsvi(
        &[
            "montecarlo",
            "--resume",
            "--quiet",
            "--out",
            cut.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read(whole.join("members.csv")).unwrap(),
        std::fs::read(cut.join("members.csv")).unwrap(),
        "the resumed members.csv differs from the uninterrupted one"
    );
    let summary = |d: &std::path::Path| -> serde_json::Value {
        let mut v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap())
                .unwrap();
        v.as_object_mut().unwrap().remove("wall_time_s");
        v
    };
    assert_eq!(summary(&whole), summary(&cut));
    assert!(!cut.join("checkpoint.json").exists());
    // A complete run has nothing to resume; other flags beside --resume are refused.
    let (code, _, err) = lgsvi(
        &["montecarlo", "--resume", "--out", cut.to_str().unwrap()],
        None,
    );
    assert_ne!(code, 0);
    assert!(
        err.contains("--resume") && err.contains("no interrupted run"),
        "{err}"
    );
    let (code, _, err) = lgsvi(
        &[
            "montecarlo",
            "--resume",
            "--members",
            "3",
            "--out",
            cut.to_str().unwrap(),
        ],
        None,
    );
    assert_ne!(code, 0);
    assert!(err.contains("only --out"), "{err}");
}

/// A dispersion the config's table sets and the body cannot take names the file and key.
#[test]
fn a_config_dispersion_the_body_cannot_take_names_the_file() {
    let dir = temp_dir("config-mass");
    let config = dir.join("mc.toml");
    std::fs::write(
        &config,
        "[montecarlo]\nmembers = 3\n[montecarlo.dispersions]\nmass = { distribution = \"uniform\", half_width = 0.1 }\n",
    )
    .unwrap();
    let out = dir.join("run");
    let (code, _, err) = lgsvi(
        &[
            "montecarlo",
            "--config",
            config.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ],
        None,
    );
    assert_ne!(code, 0);
    assert!(
        err.contains("mc.toml") && err.contains("[montecarlo.dispersions]") && err.contains("mass"),
        "{err}"
    );
}

/// The cells of `row` under the header's columns named `names`, joined by commas (a
/// flag's value).
fn cells(header: &[String], row: &[String], names: &[String]) -> String {
    names
        .iter()
        .map(|name| {
            let i = header
                .iter()
                .position(|h| h == name)
                .unwrap_or_else(|| panic!("{name}"));
            row[i].clone()
        })
        .collect::<Vec<_>>()
        .join(",")
}

/// Column names `prefix_1..3`, or `prefix_11..33` row-major.
fn columns(prefix: &str, matrix: bool) -> Vec<String> {
    if matrix {
        (1..=3)
            .flat_map(|i| (1..=3).map(move |j| format!("{prefix}_{i}{j}")))
            .collect()
    } else {
        (1..=3).map(|i| format!("{prefix}_{i}")).collect()
    }
}

/// simulate's JSON for `row` of a run: the nominal's flags `nominal`, the row's drawn
/// inertia, start (and `extra` flags from its columns), and the run's step.
fn simulate_row(
    nominal: &[&str],
    header: &[String],
    row: &[String],
    extra: &[(&str, Vec<String>)],
    h: &str,
) -> serde_json::Value {
    let mut args: Vec<String> = ["simulate", "--quiet", "--h", h]
        .iter()
        .chain(nominal)
        .map(|a| a.to_string())
        .collect();
    let mut flags = vec![
        ("--inertia-tensor", columns("J", true)),
        ("--attitude0", columns("R0", true)),
        ("--omega0", columns("omega0", false)),
    ];
    flags.extend(extra.iter().cloned());
    for (flag, names) in flags {
        args.push(flag.to_string());
        args.push(cells(header, row, &names));
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, out, err) = lgsvi(&args, None);
    assert_eq!(code, 0, "{args:?}: {err}");
    serde_json::from_str(&out).unwrap()
}

/// The last entry of a JSON trajectory's series `key`.
fn last_of(json: &serde_json::Value, key: &str) -> Vec<f64> {
    json[key]
        .as_array()
        .and_then(|a| a.last())
        .and_then(|v| v.as_array())
        .unwrap_or_else(|| panic!("{key}"))
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// The cells of `row` under `names`, as numbers.
fn numbers(header: &[String], row: &[String], names: &[String]) -> Vec<f64> {
    cells(header, row, names)
        .split(',')
        .map(|c| c.parse().unwrap())
        .collect()
}

/// Runs `lgsvi montecarlo` in a fresh folder named `name`: `[members, seed]`, the start
/// rates dispersed by 0.01 rad/s and the config's `[montecarlo.dispersions]` lines `spec`,
/// the nominal's flags `nominal`; its output folder, members.csv and summary.
fn run_spec(
    name: &str,
    spec: &str,
    [members, seed]: [&str; 2],
    nominal: &[&str],
) -> (
    std::path::PathBuf,
    Vec<String>,
    Vec<Vec<String>>,
    serde_json::Value,
) {
    let dir = temp_dir(name);
    let out = dir.join("run");
    let config = dir.join("spec.toml");
    std::fs::write(&config, format!("[montecarlo.dispersions]\n{spec}\n")).unwrap();
    let mut args = vec![
        "montecarlo",
        "--members",
        members,
        "--seed",
        seed,
        "--disperse-omega",
        "0.01",
        "--config",
        config.to_str().unwrap(),
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(nominal);
    let (code, _, err) = lgsvi(&args, None);
    assert_eq!(code, 0, "{err}");
    let (header, rows) = table(&out.join("members.csv"));
    let summary =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    (out, header, rows, summary)
}

/// A gyrostat's members: the drawn wheels (inertias, misaligned axes) in their columns,
/// the final wheel rates beside the body's, a row that simulate given its draws
/// reproduces bit for bit, wheel-rate envelopes, and a wheel speed limit as a stop
/// condition.
#[test]
fn gyrostat_members_draw_their_wheels_and_simulate_reproduces_a_row() {
    // Wheel 1's motor spins it up from 1 rad/s: the members cross 1.5 rad/s at
    // different times (their wheel inertias differ).
    let nominal = [
        "--system",
        "gyrostat",
        "--wheel-speeds0",
        "1,2,3",
        "--wheel-torque",
        "0.002,0,0",
        "--t-end",
        "20",
        "--stop-when",
        "wheel_1>1.5",
    ];
    let (out, header, rows, summary) = run_spec(
        "gyrostat",
        "wheel_inertia = { distribution = \"uniform\", half_width = 0.05 }\n\
         wheel_axis = { distribution = \"normal\", sigma = 0.01 }",
        ["12", "5"],
        &nominal,
    );
    for name in ["I_w1", "a_w3_3", "wheel_3", "t_stop"] {
        assert!(header.iter().any(|h| h == name), "{name}: {header:?}");
    }
    let h = summary["settings"]["h"].as_f64().unwrap().to_string();
    let wheels = |what: &str| -> Vec<String> { (1..=3).map(|k| format!("{what}{k}")).collect() };
    let axes: Vec<String> = (1..=3)
        .flat_map(|k| (1..=3).map(move |i| format!("a_w{k}_{i}")))
        .collect();
    let row = &rows[4];
    // The drawn inertias within 5% of the nominal 0.05 and the axes unit vectors near
    // the body axes, all different from the nominal.
    let inertias = numbers(&header, row, &wheels("I_w"));
    assert!(inertias
        .iter()
        .all(|i| (i / 0.05 - 1.0).abs() <= 0.05 && *i != 0.05));
    let a = numbers(&header, row, &axes);
    for k in 0..3 {
        let norm = (a[3 * k].powi(2) + a[3 * k + 1].powi(2) + a[3 * k + 2].powi(2)).sqrt();
        assert!((norm - 1.0).abs() < 1e-15 && (a[3 * k + k] - 1.0).abs() < 1e-2);
    }
    let json = simulate_row(
        &nominal,
        &header,
        row,
        &[("--wheel-inertia", wheels("I_w")), ("--wheel-axes", axes)],
        &h,
    );
    assert_eq!(
        last_of(&json, "omega"),
        numbers(&header, row, &columns("omega", false))
    );
    assert_eq!(
        last_of(&json, "wheel_speeds"),
        numbers(&header, row, &wheels("wheel_"))
    );
    assert_eq!(
        json["description"]["stopped"]["t"].as_f64(),
        Some(numbers(&header, row, &["t_stop".to_string()])[0])
    );
    // Every member's wheel 1 crossed 1.5 rad/s; the stop times differ with the inertias.
    assert_eq!(summary["stop"]["members_stopped"], 12);
    assert!(summary["stop"]["time_min"] != summary["stop"]["time_max"]);
    assert_eq!(
        summary["final_wheel_speeds"]["mean"]
            .as_array()
            .unwrap()
            .len(),
        3
    );
    let channels = &summary["envelopes"]["channels"];
    assert!(channels.get("wheel_3").is_some(), "{channels}");
    for k in 1..=3 {
        assert!(out.join(format!("envelope_wheel_{k}.png")).exists());
    }
}

/// A body in space: the drawn mass and torque in their columns, the final position and
/// velocity beside the rotation, a row that simulate reproduces bit for bit.
#[test]
fn bodies_in_space_draw_mass_and_torque_and_simulate_reproduces_a_row() {
    let nominal = ["--system", "orbiting-body", "--t-end", "5"];
    let (_, header, rows, summary) = run_spec(
        "space",
        "mass = { distribution = \"uniform\", half_width = 0.1 }\n\
         torque = { distribution = \"normal\", sigma = 0.01 }",
        ["8", "2"],
        &nominal,
    );
    let h = summary["settings"]["h"].as_f64().unwrap().to_string();
    let row = &rows[3];
    let mass = numbers(&header, row, &["m".to_string()])[0];
    assert!((mass - 1.0).abs() <= 0.1 && mass != 1.0, "{mass}");
    let json = simulate_row(
        &nominal,
        &header,
        row,
        &[
            ("--mass", vec!["m".into()]),
            ("--torque", columns("tau", false)),
        ],
        &h,
    );
    assert_eq!(
        last_of(&json, "position"),
        numbers(&header, row, &columns("x", false))
    );
    assert_eq!(
        last_of(&json, "velocity"),
        numbers(&header, row, &columns("v", false))
    );
    assert_eq!(
        last_of(&json, "R"),
        numbers(&header, row, &columns("R", true))
    );
    assert_eq!(
        summary["final_x"]["covariance"].as_array().unwrap().len(),
        3
    );
}

/// `--settle-when`: each member's settling time (the last crossing into the condition)
/// in its row, the one simulate reports for the row's draws; summarised.
#[test]
fn settling_times_per_member_match_simulate_and_are_summarised() {
    let dir = temp_dir("settle");
    let out = dir.join("run");
    // A damped body: |Ω| decays about as e^(−0.23 t) through 0.05, near t = 14 to 15
    // for these members, and stays below by t = 25.
    let nominal = [
        "--damping",
        "0.5",
        "--nodes",
        "12",
        "--t-end",
        "25",
        "--settle-when",
        "omega<0.05",
    ];
    let mut args = vec![
        "montecarlo",
        "--members",
        "16",
        "--seed",
        "8",
        "--disperse-omega",
        "0.05",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
        "--inertia",
        "2,2.2,2.5",
        "--omega0",
        "0.3,0.1,1",
        "--h",
        "0.25",
    ];
    args.extend(nominal);
    let (code, _, err) = lgsvi(&args, None);
    assert_eq!(code, 0, "{err}");
    let (header, rows) = table(&out.join("members.csv"));
    assert_eq!(header.last().map(String::as_str), Some("t_settle"));
    let times: Vec<Option<f64>> = rows
        .iter()
        .map(|r| r.last().unwrap().parse().ok())
        .collect();
    let settled: Vec<f64> = times.iter().flatten().copied().collect();
    assert_eq!(settled.len(), 16, "{times:?}");
    let k = times.iter().position(Option::is_some).unwrap();
    let json = simulate_row(&nominal, &header, &rows[k], &[], "0.25");
    assert_eq!(json["description"]["settled"]["t"].as_f64(), times[k]);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let settle = &summary["settle"];
    assert_eq!(settle["condition"], "omega<0.05");
    assert_eq!(settle["members_settled"], settled.len());
    assert_eq!(settle["members_not_settled"], 16 - settled.len());
    let least = settled.iter().copied().fold(f64::INFINITY, f64::min);
    assert_eq!(settle["time_min"].as_f64(), Some(least));
    assert!(out.join("settle_times.png").exists());
}

/// A stop or settling condition on a quantity the system lacks is refused before any
/// member runs, naming its flag (each member used to fail on it, exit status 3).
#[test]
fn a_condition_the_system_lacks_is_refused_before_the_members_run() {
    let dir = temp_dir("lacking-condition");
    for (flag, condition, words) in [
        ("--stop-when", "x_1<0", "body in space"),
        ("--settle-when", "wheel_1<0", "gyrostat"),
    ] {
        let out = dir.join(flag.trim_start_matches('-'));
        let (code, _, err) = lgsvi(
            &[
                "montecarlo",
                "--members",
                "3",
                flag,
                condition,
                "--quiet",
                "--out",
                out.to_str().unwrap(),
            ],
            None,
        );
        assert_eq!(code, 1, "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(flag) && err.contains(words), "{err}");
        assert!(!out.join("members.csv").exists());
    }
}

/// A dispersion the nominal body cannot take: a torque on a gyrostat (its wheels take
/// the motor torques), a mass on a body without one.
#[test]
fn dispersions_the_system_lacks_are_refused_naming_the_key() {
    let dir = temp_dir("lacks");
    for (system, key) in [("gyrostat", "torque"), ("rigid-body", "mass")] {
        let config = dir.join(format!("{key}.toml"));
        std::fs::write(
            &config,
            format!(
                "[montecarlo.dispersions]\n{key} = {{ distribution = \"uniform\", half_width = 0.1 }}\n"
            ),
        )
        .unwrap();
        let out = dir.join(system);
        let (code, _, err) = lgsvi(
            &[
                "montecarlo",
                "--system",
                system,
                "--config",
                config.to_str().unwrap(),
                "--quiet",
                "--out",
                out.to_str().unwrap(),
            ],
            None,
        );
        assert_ne!(code, 0, "{system}");
        assert!(err.contains(key) && err.contains("no "), "{system}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
}

/// `--attitude-gain`: every member runs the nominal PD law (the controller is not
/// dispersed, the plant is), its settling time into the pointing error `error<0.5` is the
/// one simulate reports for the row's draws and the same flags, bit for bit; the envelopes
/// gain the pointing error.
#[test]
fn a_controlled_run_settles_each_member_as_simulate_does() {
    controlled_members_settle_as_simulate_does("controlled", &[]);
}

/// As [`a_controlled_run_settles_each_member_as_simulate_does`], the law sampled every 0.5
/// and held, its torque limited to 0.3 N·m (the first seconds of each slew saturate).
#[test]
fn a_sampled_saturated_controller_settles_each_member_as_simulate_does() {
    let sampled = ["--sample-period", "0.5", "--torque-limit", "0.3"];
    controlled_members_settle_as_simulate_does("sampled", &sampled);
}

fn controlled_members_settle_as_simulate_does(name: &str, law: &[&str]) {
    let dir = temp_dir(name);
    let out = dir.join("run");
    // Turned by 74° from the target at rest (q = (0.8, 0.6, 0, 0)), the body is brought in
    // by K = 1.5, C = 3 within about 12 s for these draws (5° and 0.05 rad/s at the start;
    // within 20 s with the torque limited).
    let mut nominal = vec![
        "--attitude-gain",
        "1.5",
        "--damping",
        "3",
        "--target-quaternion",
        "0.8,0.6,0,0",
        "--nodes",
        "10",
        "--t-end",
        "25",
        "--settle-when",
        "error<0.5",
    ];
    nominal.extend(law);
    let mut args = vec![
        "montecarlo",
        "--members",
        "16",
        "--seed",
        "4",
        "--disperse-omega",
        "0.05",
        "--disperse-inertia",
        "0.02",
        "--disperse-attitude",
        "5",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
        "--inertia",
        "2,3,4",
        "--omega0",
        "0,0,0",
        "--h",
        "0.5",
    ];
    args.extend(&nominal);
    let (code, _, err) = lgsvi(&args, None);
    assert_eq!(code, 0, "{err}");
    let (header, rows) = table(&out.join("members.csv"));
    let times: Vec<f64> = rows
        .iter()
        .map(|r| r.last().unwrap().parse().unwrap())
        .collect();
    assert!(times.iter().all(|t| (5.0..25.0).contains(t)), "{times:?}");
    for k in [0, 11] {
        let json = simulate_row(&nominal, &header, &rows[k], &[], "0.5");
        assert_eq!(json["description"]["settled"]["t"].as_f64(), Some(times[k]));
        assert_eq!(
            last_of(&json, "omega"),
            numbers(&header, &rows[k], &columns("omega", false))
        );
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let error = &summary["envelopes"]["channels"]["error_deg"];
    // At the start the members are 74° ± a few from the target, at the end within 0.5°.
    let p50 = error["p50"].as_array().unwrap();
    let (first, last) = (
        p50[0].as_f64().unwrap(),
        p50.last().unwrap().as_f64().unwrap(),
    );
    assert!(
        (65.0..85.0).contains(&first) && last < 0.5,
        "{first} … {last}"
    );
    assert!(out.join("envelope_error.png").exists());
}

/// The example configs run as their headers say (with fewer members): the pointing
/// config's members all settle into its 0.1° requirement, its disturbance torques drawn.
#[test]
fn the_example_configs_run() {
    let dir = temp_dir("configs");
    for name in ["montecarlo.toml", "pointing.toml", "pointing_sampled.toml"] {
        let config = format!("{}/../configs/{name}", env!("CARGO_MANIFEST_DIR"));
        let out = dir.join(name);
        let (code, _, err) = lgsvi(
            &[
                "montecarlo",
                "--config",
                &config,
                "--members",
                "6",
                "--quiet",
                "--out",
                out.to_str().unwrap(),
            ],
            None,
        );
        assert_eq!(code, 0, "{name}: {err}");
        let (header, rows) = table(&out.join("members.csv"));
        assert_eq!(rows.len(), 6, "{name}");
        assert!(rows.iter().all(|r| r[1] == "ok"), "{name}");
        if name.starts_with("pointing") {
            assert_eq!(header.last().map(String::as_str), Some("t_settle"));
            assert!(header.iter().any(|h| h == "tau_1"), "{header:?}");
            let settled: Vec<f64> = rows
                .iter()
                .map(|r| r.last().unwrap().parse().unwrap())
                .collect();
            assert!(
                settled.iter().all(|t| (5.0..40.0).contains(t)),
                "{settled:?}"
            );
        }
    }
}
